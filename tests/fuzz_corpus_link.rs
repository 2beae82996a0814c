//! Replays the committed fuzz corpus of the `link` target (fuzz/corpus/link) on stable Rust,
//! with the same checks as the fuzz target (fuzz/checks/link.rs).
mod check {
    include!("../fuzz/checks/link.rs");
}

#[test]
fn replay_link_corpus() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("fuzz/corpus/link");
    let mut n = 0;
    for e in std::fs::read_dir(&dir).expect("fuzz/corpus/link exists") {
        let p = e.unwrap().path();
        check::check(&std::fs::read(&p).unwrap());
        n += 1;
    }
    assert!(n >= 10, "corpus has only {n} inputs");
}
