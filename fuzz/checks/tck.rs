// Invariants of the .tck reader: no panic; on success every point finite and no streamline
// empty; a successful read round-trips through the writer to the same f32 points.
pub fn check(data: &[u8]) {
    if let Ok(lines) = tubecast_render::io::tck::read(data, "fuzz.tck") {
        for l in &lines {
            assert!(!l.points.is_empty());
            assert!(l.points.iter().flatten().all(|v| v.is_finite()));
        }
        let again = tubecast_render::io::tck::read(&tubecast_render::io::tck::write(&lines, false), "rt.tck").expect("round trip");
        assert_eq!(again, lines);
    }
}
