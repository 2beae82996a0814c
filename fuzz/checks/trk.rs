// Invariants of the .trk reader: no panic; on success every point finite.
pub fn check(data: &[u8]) {
    if let Ok((_, lines)) = tubecast_render::io::trk::read(data, "fuzz.trk") {
        assert!(lines.iter().flat_map(|l| &l.points).flatten().all(|v| v.is_finite()));
    }
}
