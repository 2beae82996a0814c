// Replays a committed fuzz corpus through its check on stable Rust; shared by
// tests/kernels/fuzz_corpus.rs and crates/render/tests/io/fuzz_corpus.rs (each `include!`s it).

/// Runs `check` on every file of `corpus/<name>`; an input that panics fails the test with its
/// path (the check's own message is printed above it). At least `min` inputs must be there.
#[allow(dead_code)]
fn replay_corpus(corpus: &std::path::Path, name: &str, check: fn(&[u8]), min: usize) {
    let dir = corpus.join(name);
    let mut n = 0;
    for e in std::fs::read_dir(&dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display())) {
        let p = e.unwrap().path();
        if p.is_file() {
            let data = std::fs::read(&p).unwrap();
            let r = std::panic::catch_unwind(|| check(&data));
            assert!(r.is_ok(), "{} violates the {name} invariants", p.display());
            n += 1;
        }
    }
    assert!(n >= min, "corpus {name} has only {n} inputs");
}
