//! `tubecast info --splines` and `tubecast render --splines` end to end, and their errors.

use crate::common::bin;
crate::common::tmp_fn!();

fn png_size(bytes: &[u8]) -> (u32, u32) {
    assert_eq!(&bytes[1..4], b"PNG");
    (u32::from_be_bytes(bytes[16..20].try_into().unwrap()), u32::from_be_bytes(bytes[20..24].try_into().unwrap()))
}

#[test]
fn info_counts_splines_and_render_draws_them() {
    let tck = tmp("helix.tck");
    assert!(bin().args(["generate", "helix", "--segments", "20", "-o"]).arg(&tck).status().unwrap().success());
    // Link model: no splines.
    let out = bin().arg("info").arg(&tck).output().unwrap();
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("splines    0\n"), "{text}");
    // Spline model: 2 strands × 20 curved segments (a helix has no straight run), each split
    // into the certified split's pieces — the count of the primitives traced equals the count
    // `spline_fidelity` finds by splitting the segments itself, and is more than Russig's pair
    // (2 per segment, off by ~1 radius here); no link primitive is left.
    let out = bin().arg("info").arg(&tck).arg("--splines").output().unwrap();
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    for l in ["links      40", "cylinders  0", "cones      0", "spheres    0", "splines    40 ("] {
        assert!(text.contains(l), "{l:?} in {text}");
    }
    let num = |after: &str| -> usize {
        let rest = text.split(after).nth(1).unwrap_or_else(|| panic!("{after:?} in {text}"));
        rest.split(' ').next().unwrap().parse().unwrap()
    };
    let traced = num("splines    40 (");
    assert_eq!(traced, num("faithful split, "), "{text}");
    assert!(traced > 80, "{text}");

    let mut pngs = Vec::new();
    for (name, extra) in [
        ("links.png", vec![]),
        ("splines.png", vec!["--splines"]),
        ("glass.png", vec!["--splines", "--opacity", "0.4"]),
    ] {
        let png = tmp(name);
        let st = bin()
            .arg("render")
            .arg(&tck)
            .args(["--width", "32", "--height", "24", "--quiet"])
            .args(&extra)
            .arg("-o")
            .arg(&png)
            .status()
            .unwrap();
        assert!(st.success(), "{extra:?}");
        let bytes = std::fs::read(&png).unwrap();
        assert_eq!(png_size(&bytes), (32, 24));
        pngs.push(bytes);
    }
    // The smooth tube is a different image from the polygonal one, and glass from opaque.
    assert_ne!(pngs[0], pngs[1]);
    assert_ne!(pngs[1], pngs[2]);
}

#[test]
fn huge_spline_scenes_render_and_bad_options_are_errors() {
    // Extents of 1e9 (the kernel works in units of the segment's size): renders, no NaN path.
    let obj = tmp("big.obj");
    std::fs::write(&obj, "v 0 0 0\nv 1e9 0 0\nv 2e9 1e9 0\nl 1 2 3\n").unwrap();
    let png = tmp("big.png");
    let st = bin()
        .arg("render")
        .arg(&obj)
        .args(["--splines", "--width", "8", "--height", "8", "--quiet", "-o"])
        .arg(&png)
        .status()
        .unwrap();
    assert!(st.success());
    assert_eq!(png_size(&std::fs::read(&png).unwrap()), (8, 8));
    let out = bin()
        .arg("render")
        .arg(&obj)
        .args(["--splines", "--opacity", "0", "--force", "-o"])
        .arg(&png)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2), "a value out of range is a usage error");
    let e = String::from_utf8_lossy(&out.stderr);
    assert!(e.starts_with("tubecast: error: ") && e.contains("'0' for '--opacity"), "{e}");
}
