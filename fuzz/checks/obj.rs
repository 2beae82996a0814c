// Invariants of the OBJ reader: no panic; on success ≥ 1 polyline, each with ≥ 2 finite
// points and either no radii or one finite non-negative radius per point.
pub fn check(data: &[u8]) {
    if let Ok(lines) = tubecast_render::io::obj::read(data, "fuzz.obj") {
        assert!(!lines.is_empty());
        for l in &lines {
            assert!(l.points.len() >= 2);
            assert!(l.points.iter().flatten().all(|v| v.is_finite()));
            assert!(l.radii.is_empty() || l.radii.len() == l.points.len());
            assert!(l.radii.iter().all(|r| r.is_finite() && *r >= 0.0));
        }
    }
}
