//! `tubecast intersect --splines` and the spline fidelity line of `info --splines`.

use crate::common::bin;
crate::common::tmp_fn!();
use tubecast_render::io::npy::{read, write, Array2};

#[test]
fn intersect_traces_the_spline_model_and_info_reports_its_fidelity() {
    let swc = tmp("helix-splines.swc");
    assert!(bin().args(["generate", "helix", "--segments", "20", "-o"]).arg(&swc).status().unwrap().success());
    // The rays of tests/cli_commands.rs: up +z from (4, 0, −20) under node 0 (centre (4, 0, −10),
    // radius 0.425), and one at x = 100, far outside the helix (radius 4 plus tube radius < 0.6).
    let rays = Array2 { rows: 2, cols: 6, data: vec![4.0, 0.0, -20.0, 0.0, 0.0, 1.0, 100.0, 0.0, 0.0, 0.0, 0.0, 1.0] };
    let (rp, hp) = (tmp("rays-splines.npy"), tmp("hits-splines.npy"));
    std::fs::write(&rp, write(&rays)).unwrap();
    let out = bin().arg("intersect").arg(&swc).arg("--splines").arg("--rays").arg(&rp).arg("--out").arg(&hp).output();
    let out = out.unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let h = read(&std::fs::read(&hp).unwrap(), "hits", Some(8)).unwrap();
    assert!(h.data.iter().all(|v| !v.is_nan()));
    let (r0, r1) = (h.row(0), h.row(1));
    // The spline passes through node 0 with its radius, so node 0's sphere is part of the sweep:
    // the entry is no later than that sphere's, 9.575 (f32 storage: 1e-5, as for links).
    assert_eq!(r0[7], 1.0, "{r0:?}");
    assert!(r0[0] <= 9.575 + 1e-5 && r0[1] > r0[0], "{r0:?}");
    assert_eq!(r1[7], 0.0, "{r1:?}");
    // info --splines: the traced faithful split's piece count and certified relative distance
    // to the cubic (≤ its 1e-3 tolerance), and Russig's pair's for comparison.
    let out = bin().arg("info").arg(&swc).arg("--splines").output().unwrap();
    let text = String::from_utf8(out.stdout).unwrap();
    let line = text.lines().find(|l| l.starts_with("fidelity")).unwrap_or_else(|| panic!("{text}"));
    let rel: f64 = line.split("pieces for ≤ ").nth(1).and_then(|x| x.split(' ').next()).unwrap().parse().unwrap();
    assert!(rel <= 1e-3, "{line}");
}
