// Invariants of the SWC reader (shared by the fuzz target and crates/render/tests/io/fuzz_corpus.rs):
// no panic; on success every value finite, radii ≥ 0, and building a scene either succeeds
// with finite bounds or gives an error (never a panic).
pub fn check(data: &[u8]) {
    if let Ok(nodes) = tubecast_render::io::swc::read(data, "fuzz.swc") {
        for n in &nodes {
            assert!(n.pos.iter().all(|v| v.is_finite()) && n.radius.is_finite() && n.radius >= 0.0);
        }
        if let Ok(s) = tubecast_render::scene::Scene::from_swc(&nodes, "fuzz.swc") {
            let st = s.stats();
            assert!(st.bounds.0.iter().chain(&st.bounds.1).all(|v| v.is_finite()));
        }
    }
}
