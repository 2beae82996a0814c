//! The `tubecast` binary end to end: generate → info → intersect → render, and errors.

use crate::common::bin;
crate::common::tmp_fn!();
use tubecast_render::io::npy::{read, write, Array2};

#[test]
fn generate_info_intersect_render() {
    let swc = tmp("helix.swc");
    let st = bin().args(["generate", "helix", "--segments", "20", "-o"]).arg(&swc).status().unwrap();
    assert!(st.success());
    let out = bin().arg("info").arg(&swc).output().unwrap();
    let text = String::from_utf8(out.stdout).unwrap();
    // 2 strands × 20 segments, radius 0.425 + 0.175·sin(πk/5) at node k: equal radii (a
    // cylinder) where k + ½ ≡ 5/2 (mod 5), i.e. k = 2, 7, 12, 17 — 4 per strand.
    for line in ["nodes      42", "links      40", "cylinders  8", "cones      32", "spheres    0"] {
        assert!(text.contains(line), "{line:?} in {text}");
    }

    // Two rays: one up +z from (4, 0, −20), one missing. Strand 0 starts at (4, 0, −10) with
    // radius 0.425 (sin 0 = 0) and rises; that sphere's lowest point z = −10.425 is the lowest
    // point of the whole tube (the next node is at z = −9 with radius < 0.6), so the ray
    // enters there: t_in = 9.575, normal (0, 0, −1), link 0, u = 0.
    let rays = Array2 { rows: 2, cols: 6, data: vec![4.0, 0.0, -20.0, 0.0, 0.0, 1.0, 100.0, 0.0, 0.0, 0.0, 0.0, 1.0] };
    let rp = tmp("rays.npy");
    let hp = tmp("hits.npy");
    std::fs::write(&rp, write(&rays)).unwrap();
    let st = bin().arg("intersect").arg(&swc).arg("--rays").arg(&rp).arg("--out").arg(&hp).status().unwrap();
    assert!(st.success());
    let h = read(&std::fs::read(&hp).unwrap(), "hits", Some(8)).unwrap();
    assert_eq!(h.rows, 2);
    assert!(h.data.iter().all(|v| !v.is_nan()));
    let r0 = h.row(0);
    // f32 primitives relative to the link midpoint (offsets ≤ 1.5): rounding ≲ 1.5·2⁻²⁴·few
    // ≈ 1e-6 in position, head-on so the same in t; 1e-5 bounds it with margin.
    assert!((r0[0] - 9.575).abs() < 1e-5, "{r0:?}");
    assert!((r0[4] + 1.0).abs() < 1e-5 && r0[2].abs() < 1e-5, "normal at entry points down: {r0:?}");
    assert_eq!((r0[5], r0[6], r0[7]), (0.0, 0.0, 1.0), "link 0, u = 0, hit: {r0:?}");
    assert!(r0[1] > r0[0]);
    assert_eq!(h.row(1), &[f64::INFINITY, f64::INFINITY, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0]);

    let png = tmp("h.png");
    let st = bin()
        .arg("render")
        .arg(&swc)
        .args(["--width", "24", "--height", "16", "--quiet", "-o"])
        .arg(&png)
        .status()
        .unwrap();
    assert!(st.success());
    let bytes = std::fs::read(&png).unwrap();
    assert_eq!(&bytes[1..4], b"PNG");
    // IHDR width and height (big endian at offsets 16 and 20).
    assert_eq!(u32::from_be_bytes(bytes[16..20].try_into().unwrap()), 24);
    assert_eq!(u32::from_be_bytes(bytes[20..24].try_into().unwrap()), 16);
}

#[test]
fn errors_exit_nonzero_with_a_message() {
    let bad = tmp("bad.swc");
    std::fs::write(&bad, "1 1 0 0 0 1\n").unwrap();
    // A file that fails the job exits 1; a command line that cannot work as written exits 2.
    let cases: Vec<(Vec<String>, i32)> = vec![
        (vec!["info".into(), bad.display().to_string()], 1),
        (vec!["info".into(), tmp("missing.swc").display().to_string()], 1),
        (vec!["info".into(), tmp("x.xyz").display().to_string()], 1),
        (vec!["generate".into(), "neurons".into(), "-o".into(), tmp("n.tck").display().to_string()], 2),
        (
            vec![
                "generate".into(),
                "bundle".into(),
                "--count".into(),
                "0".into(),
                "-o".into(),
                tmp("b.tck").display().to_string(),
            ],
            2,
        ),
    ];
    for (args, code) in cases {
        let out = bin().args(&args).output().unwrap();
        assert_eq!(out.status.code(), Some(code), "{args:?}");
        let e = String::from_utf8_lossy(&out.stderr);
        assert!(e.starts_with("tubecast: error: "), "{args:?}: {e}");
    }
    let out = bin().args(["info"]).arg(&bad).output().unwrap();
    assert!(String::from_utf8_lossy(&out.stderr).contains("bad.swc: line 1: expected 7 columns"));
    // One link past the generator's cap (2·10⁸ links: 10⁸, whole-brain scale, fits): refused
    // before anything is allocated, naming the cap.
    let big = ["generate", "bundle", "--count", "200000001", "--segments", "1", "-o"];
    let out = bin().args(big).arg(tmp("big.tck")).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("between 1 and 200000000"));
    // Bad rays: a zero direction is rejected with its row.
    let swc = tmp("h2.swc");
    assert!(bin().args(["generate", "helix", "--segments", "4", "-o"]).arg(&swc).status().unwrap().success());
    let rp = tmp("zero.npy");
    std::fs::write(&rp, write(&Array2 { rows: 1, cols: 6, data: vec![0.0; 6] })).unwrap();
    let out = bin().arg("intersect").arg(&swc).arg("--rays").arg(&rp).arg("--out").arg(tmp("o.npy")).output().unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("row 0: ray direction is zero"));
    // Bad render options.
    let out = bin().arg("render").arg(&swc).args(["--opacity", "2", "-o"]).arg(tmp("o.png")).output().unwrap();
    assert_eq!(out.status.code(), Some(2), "a value out of range is a usage error");
    let out = bin().arg("render").arg(&swc).args(["--eye", "1,2", "-o"]).arg(tmp("o.png")).output().unwrap();
    assert_eq!(out.status.code(), Some(2), "clap rejects a malformed vector");
}
