//! `render` refused by `--memory-limit`: the message names the estimate and the options that
//! lower it, for what `render` holds besides `info` (the thin-tube clamp, the list of
//! primitives, a tracer built whole with `--accel bvh2`).

use crate::common::bin;
crate::common::tmp_fn!();
use std::process::Output;

/// The GiB figure of "needs about X GiB".
fn needs_gib(out: &Output) -> f64 {
    let err = String::from_utf8_lossy(&out.stderr);
    let rest = err.split("needs about ").nth(1).unwrap_or_else(|| panic!("no figure in {err}"));
    rest.split_whitespace().next().unwrap().parse().unwrap()
}

#[test]
fn a_refused_render_names_the_figure_and_the_options_that_help() {
    let p = tmp("render_big.tck"); // 5·10⁵ links: 5000 fibres of 100
    let made = bin().args(["generate", "bundle", "--segments", "100", "--count", "5000", "-o"]).arg(&p).output();
    assert!(made.unwrap().status.success());
    let png = tmp("render_big.png");
    let _ = std::fs::remove_file(&png);
    let run = |extra: &[&str]| {
        bin().arg("render").arg(&p).args(["--memory-limit", "40M", "-o"]).arg(&png).args(extra).output().unwrap()
    };
    let out = run(&[]);
    assert!(!out.status.success());
    assert!(!png.exists(), "nothing is rendered");
    let err = String::from_utf8_lossy(&out.stderr).to_string();
    for part in [
        "needs about",
        "GiB",
        "500000 links",
        "0.04 GiB available (--memory-limit)",
        "--subsample",
        "--max-streamlines",
        "--memory-limit",
        "thin-tube clamp",
        "--thin off",
    ] {
        assert!(err.contains(part), "{part:?} missing in {err}");
    }
    // The clamp's 12 B per node (101 nodes per 100 links) is in the figure: 5·10⁵ × 12.12 B
    // = 5.8 MiB = 0.0056 GiB more than with --thin off (printed to 0.01 GiB: at least 0.00).
    let off = run(&["--thin", "off"]);
    assert!(!off.status.success());
    let off_err = String::from_utf8_lossy(&off.stderr);
    assert!(!off_err.contains("--thin off") && !off_err.contains("thin-tube clamp"), "{off_err}");
    assert!(needs_gib(&off) <= needs_gib(&out), "{off_err}\n{err}");
    // render needs more than info on the same file (its clamp, image and list of primitives).
    let info = bin().arg("info").arg(&p).args(["--memory-limit", "40M"]).output().unwrap();
    assert!(!info.status.success());
    assert!(needs_gib(&info) < needs_gib(&out), "info {} against render {}", needs_gib(&info), needs_gib(&out));
    // A binary BVH is built whole (5·10⁵ × about 110 B more: 0.05 GiB): the message says the chunked
    // tree helps, and its figure is larger.
    let bvh2 = run(&["--accel", "bvh2"]);
    assert!(!bvh2.status.success());
    let bvh2_err = String::from_utf8_lossy(&bvh2.stderr);
    assert!(bvh2_err.contains("--accel bvh (built in chunks)") && bvh2_err.contains("built whole"), "{bvh2_err}");
    assert!(needs_gib(&bvh2) > needs_gib(&out) + 0.03, "{bvh2_err}");
    // The way out it names works.
    let part = run(&["--subsample", "0.02", "--width", "64", "--height", "64"]);
    assert!(part.status.success(), "{}", String::from_utf8_lossy(&part.stderr));
    assert!(png.exists());
}
