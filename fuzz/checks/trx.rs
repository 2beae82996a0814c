// Invariants of the .trx reader: no panic; on success every point finite, one item of every
// per-vertex / per-streamline field per point / streamline, group indices in range.
pub fn check(data: &[u8]) {
    if let Ok(t) = tubecast_render::io::trx::read(data, "fuzz.trx") {
        assert!(t.lines.iter().flat_map(|l| &l.points).flatten().all(|v| v.is_finite()));
        t.validate("fuzz.trx").expect("field sizes match the streamlines");
        assert!(t.groups.iter().flat_map(|g| &g.1).all(|&i| (i as usize) < t.lines.len()));
    }
}
