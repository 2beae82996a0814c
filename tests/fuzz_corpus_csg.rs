//! Replays the committed fuzz corpus of the `csg` target (fuzz/corpus/csg) on stable Rust,
//! with the same checks as the fuzz target (fuzz/checks/csg.rs).
mod check {
    include!("../fuzz/checks/csg.rs");
}

#[test]
fn replay_csg_corpus() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("fuzz/corpus/csg");
    let mut n = 0;
    for e in std::fs::read_dir(&dir).expect("fuzz/corpus/csg exists") {
        let p = e.unwrap().path();
        check::check(&std::fs::read(&p).unwrap());
        n += 1;
    }
    assert!(n >= 10, "corpus has only {n} inputs");
}
