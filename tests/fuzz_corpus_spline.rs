//! Replays the committed fuzz corpus of the `spline` target (fuzz/corpus/spline) on stable
//! Rust, with the same checks as the fuzz target (fuzz/checks/spline.rs).
mod check {
    include!("../fuzz/checks/spline.rs");
}

#[test]
fn replay_spline_corpus() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("fuzz/corpus/spline");
    let mut n = 0;
    for e in std::fs::read_dir(&dir).expect("fuzz/corpus/spline exists") {
        let p = e.unwrap().path();
        check::check(&std::fs::read(&p).unwrap());
        n += 1;
    }
    assert!(n >= 10, "corpus has only {n} inputs");
}

/// The check does fire: a hand-made interval with t_in > t_out is rejected by `sane`.
#[test]
#[should_panic(expected = "t_in > t_out")]
fn check_catches_a_bad_interval() {
    let mut iv = tubecast::Interval::<f64>::miss();
    iv.hit = true;
    iv.t_in = 1.0;
    iv.t_out = 0.0;
    iv.n_in = tubecast::V3::new(1.0, 0.0, 0.0);
    iv.n_out = iv.n_in;
    check::sane(&iv);
}
