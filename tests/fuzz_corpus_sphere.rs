//! Replays the committed fuzz corpus of the `sphere` target (fuzz/corpus/sphere) on stable Rust,
//! with the same checks as the fuzz target (fuzz/checks/sphere.rs).
mod check {
    include!("../fuzz/checks/sphere.rs");
}

#[test]
fn replay_sphere_corpus() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("fuzz/corpus/sphere");
    let mut n = 0;
    for e in std::fs::read_dir(&dir).expect("fuzz/corpus/sphere exists") {
        let p = e.unwrap().path();
        check::check(&std::fs::read(&p).unwrap());
        n += 1;
    }
    assert!(n >= 10, "corpus has only {n} inputs");
}
