//! Files from the field end to end: empty tractograms and morphologies (`info` prints zeros,
//! `render` writes the background with a warning, `intersect` writes misses), and SWC
//! placeholder radii (refused at their line with a `--min-radius` hint; replaced and counted
//! with `--min-radius`).

use crate::common::bin;
crate::common::tmp_fn!();
use tubecast_render::io::npy::{read, write, Array2};

/// nibabel's own test file `name` (committed under `reference/readers/nibabel`, MIT).
fn nibabel_file(name: &str) -> Vec<u8> {
    let p = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../reference/readers/nibabel").join(name);
    std::fs::read(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// The three empty files, named `{prefix}-empty.*` (each test its own, as tests run in parallel).
fn empty_files(prefix: &str) -> Vec<std::path::PathBuf> {
    let files = [
        ("empty.tck", nibabel_file("empty.tck")),
        ("empty.trk", nibabel_file("empty.trk")),
        ("empty.swc", b"# NeuroMorpho header\n# no nodes\n".to_vec()),
    ];
    files
        .into_iter()
        .map(|(n, d)| {
            let p = tmp(&format!("{prefix}-{n}"));
            std::fs::write(&p, d).unwrap();
            p
        })
        .collect()
}

#[test]
fn info_on_an_empty_file_prints_zeros() {
    for f in empty_files("info") {
        for extra in [&[][..], &["--splines"][..]] {
            let out = bin().arg("info").arg(&f).args(extra).output().unwrap();
            assert!(out.status.success(), "{}: {}", f.display(), String::from_utf8_lossy(&out.stderr));
            let text = String::from_utf8(out.stdout).unwrap();
            for l in ["nodes      0\n", "links      0\n", "cylinders  0\n", "cones      0\n", "spheres    0\n"] {
                assert!(text.contains(l), "{l:?} in {text}");
            }
            assert!(text.contains("splines    0"), "{text}");
            assert!(text.contains("bounds     none (empty scene)\n"), "{text}");
            // No NaN or infinity printed (the file name line aside).
            let values = text.lines().skip(1).collect::<Vec<_>>().join("\n").to_lowercase();
            assert!(!values.contains("inf") && !values.contains("nan"), "{text}");
            let err = String::from_utf8(out.stderr).unwrap();
            assert!(err.starts_with("tubecast: warning: ") && err.contains("empty scene"), "{err}");
        }
    }
}

#[test]
fn render_of_an_empty_file_writes_the_background_with_a_warning() {
    for f in empty_files("render") {
        for extra in [&[][..], &["--opacity", "0.5"][..], &["--splines", "--eye", "0,0,5"][..]] {
            let png = tmp("empty.png");
            let _ = std::fs::remove_file(&png);
            let out = bin()
                .arg("render")
                .arg(&f)
                .args(["--width", "5", "--height", "3", "--quiet"])
                .args(extra)
                .arg("-o")
                .arg(&png)
                .output()
                .unwrap();
            assert!(out.status.success(), "{}: {}", f.display(), String::from_utf8_lossy(&out.stderr));
            let err = String::from_utf8(out.stderr).unwrap();
            assert!(err.contains("tubecast: warning: ") && err.contains("background only"), "{err}");
            let dec = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&png).unwrap()));
            let mut reader = dec.read_info().unwrap();
            let mut buf = vec![0; reader.output_buffer_size().unwrap()];
            let info = reader.next_frame(&mut buf).unwrap();
            assert_eq!((info.width, info.height, info.color_type), (5, 3, png::ColorType::Rgb));
            // The default background is white.
            assert!(buf[..info.buffer_size()].iter().all(|&b| b == 255), "{:?}", &buf[..info.buffer_size()]);
        }
    }
}

#[test]
fn intersect_on_an_empty_file_writes_misses() {
    let rays = Array2 { rows: 2, cols: 6, data: vec![0.0, 0.0, -5.0, 0.0, 0.0, 1.0, 1.0, 2.0, 3.0, -1.0, 0.0, 0.0] };
    let rp = tmp("empty-rays.npy");
    std::fs::write(&rp, write(&rays)).unwrap();
    for f in empty_files("intersect") {
        let hp = tmp("empty-hits.npy");
        let _ = std::fs::remove_file(&hp);
        let out = bin().arg("intersect").arg(&f).arg("--rays").arg(&rp).arg("--out").arg(&hp).output().unwrap();
        assert!(out.status.success(), "{}: {}", f.display(), String::from_utf8_lossy(&out.stderr));
        assert!(String::from_utf8_lossy(&out.stderr).contains("every ray misses"));
        let h = read(&std::fs::read(&hp).unwrap(), "hits", Some(8)).unwrap();
        assert_eq!(h.rows, 2);
        for r in 0..2 {
            assert_eq!(h.row(r), &[f64::INFINITY, f64::INFINITY, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0]);
        }
    }
}

#[test]
fn a_malformed_empty_file_is_still_an_error() {
    // A .tck header without the Inf end marker, an OBJ without line elements.
    let tck = tmp("cut.tck");
    std::fs::write(&tck, &nibabel_file("empty.tck")[..67]).unwrap();
    let obj = tmp("mesh.obj");
    std::fs::write(&obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    for (f, what) in [(tck, "without the Inf end marker"), (obj, "no line elements")] {
        let out = bin().arg("info").arg(&f).output().unwrap();
        assert_eq!(out.status.code(), Some(1));
        let err = String::from_utf8(out.stderr).unwrap();
        assert!(err.starts_with("tubecast: error: ") && err.contains(what), "{err}");
    }
}

/// Three nodes, radius 0 everywhere but the soma (a placeholder file), and one negative.
const PLACEHOLDERS: &str = "# radii unknown\n1 1 0 0 0 2 -1\n2 3 1 0 0 0 1\n3 3 2 0 0 0 2\n4 3 0 1 0 -1 1\n";

#[test]
fn placeholder_radii_are_refused_with_a_hint_and_replaced_with_min_radius() {
    let swc = tmp("placeholders.swc");
    std::fs::write(&swc, PLACEHOLDERS).unwrap();
    // Without --min-radius: the negative radius on line 5 is refused, with the hint.
    let out = bin().arg("info").arg(&swc).output().unwrap();
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(err.contains("placeholders.swc: line 5: radius -1 is negative"), "{err}");
    assert!(err.contains("--min-radius"), "{err}");
    // Only zeros: the first link without volume (node 3, line 4, parent 2 on line 3).
    let zeros = tmp("zeros.swc");
    std::fs::write(&zeros, PLACEHOLDERS.replace("-1 1\n", "0 1\n")).unwrap();
    let out = bin().arg("info").arg(&zeros).output().unwrap();
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(err.contains("zeros.swc: line 4: node 3 and its parent 2 (line 3) both have radius 0"), "{err}");
    assert!(err.contains("--min-radius"), "{err}");
    // With --min-radius: 3 of 4 radii replaced (all three ≤ 0), on every command.
    let out = bin().arg("info").arg(&swc).args(["--min-radius", "0.5"]).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("nodes      4\n") && text.contains("links      3\n"), "{text}");
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(err.contains("tubecast: warning: "), "{err}");
    assert!(err.contains("3 of 4 radii were below --min-radius 0.5 (3 of them ≤ 0) and were set to 0.5"), "{err}");
    let png = tmp("placeholders.png");
    let out = bin()
        .arg("render")
        .arg(&swc)
        .args(["--min-radius", "0.5", "--width", "8", "--height", "6", "--quiet", "-o"])
        .arg(&png)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(String::from_utf8_lossy(&out.stderr).contains("3 of 4 radii"));
    // A ray down −z at x = 2.25 meets only node 3's end sphere (centre (2, 0, 0), radius 0
    // raised to 0.5; the soma of radius 2 ends at x = 2): it enters at z = √(0.5² − 0.25²), so
    // t_in = 5 − √0.1875. f32 primitives relative to the link midpoint (offsets ≤ 1): rounding
    // ≲ 1e-6, amplified by r/z ≈ 1.15 off head-on; 1e-5 bounds it with margin.
    let rays = Array2 { rows: 1, cols: 6, data: vec![2.25, 0.0, 5.0, 0.0, 0.0, -1.0] };
    let (rp, hp) = (tmp("ph-rays.npy"), tmp("ph-hits.npy"));
    std::fs::write(&rp, write(&rays)).unwrap();
    let out = bin()
        .arg("intersect")
        .arg(&swc)
        .args(["--min-radius", "0.5", "--rays"])
        .arg(&rp)
        .arg("--out")
        .arg(&hp)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let h = read(&std::fs::read(&hp).unwrap(), "hits", Some(8)).unwrap();
    let r = h.row(0);
    assert_eq!(r[7], 1.0, "{r:?}");
    assert!((r[0] - (5.0 - 0.1875f64.sqrt())).abs() < 1e-5, "{r:?}");
}

/// Every nibabel test tractogram: `info` either succeeds or refuses with a clear error, never
/// panics (exit 101). In particular `multiline_header_field.tck`, whose 253 points all lie at
/// the origin (252 zero-length links in one box), once built an 8-wide BVH deeper than
/// obvhs's traversal stack (a debug-build panic; in release, dropped subtrees).
#[test]
fn info_never_panics_on_nibabel_test_files() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../reference/readers/nibabel");
    let mut n = 0;
    for e in std::fs::read_dir(&dir).unwrap() {
        let p = e.unwrap().path();
        if !matches!(p.extension().and_then(|x| x.to_str()), Some("trk" | "tck")) {
            continue;
        }
        n += 1;
        let out = bin().arg("info").arg(&p).output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.code() != Some(101) && !err.contains("panicked"), "{}: {err}", p.display());
        assert!(out.status.success() || err.starts_with("tubecast: "), "{}: {err}", p.display());
    }
    assert!(n >= 14, "only {n} nibabel files found in {}", dir.display());
}

/// `multiline_header_field.tck` (252 zero-length links at one point): the 8-wide BVH (the
/// default) answers as the binary BVH does, ray for ray, and as the sphere they all are.
#[test]
fn a_tractogram_of_coincident_points_traces_alike_in_both_trees() {
    let f = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../reference/readers/nibabel/multiline_header_field.tck");
    // A fan of rays through the origin's neighbourhood (radius 0.5 given below).
    let rays: Vec<f64> = (0..64)
        .flat_map(|i| {
            let y = -0.8 + 1.6 * (i as f64) / 63.0;
            [-5.0, y, 0.1, 1.0, 0.0, 0.0]
        })
        .collect();
    let rays_path = tmp("coincident-rays.npy");
    std::fs::write(&rays_path, write(&Array2 { rows: 64, cols: 6, data: rays })).unwrap();
    let mut hits = Vec::new();
    for accel in ["bvh", "bvh2"] {
        let out_path = tmp(&format!("coincident-hits-{accel}.npy"));
        let _ = std::fs::remove_file(&out_path);
        let out = bin()
            .arg("intersect")
            .arg(&f)
            .arg("--rays")
            .arg(&rays_path)
            .arg("--out")
            .arg(&out_path)
            .args(["--radius", "0.5", "--accel", accel])
            .output()
            .unwrap();
        assert!(out.status.success(), "{accel}: {}", String::from_utf8_lossy(&out.stderr));
        hits.push(read(&std::fs::read(&out_path).unwrap(), "hits", Some(8)).unwrap());
    }
    // Equal in every column but the link (column 5): the 252 coincident links are the same
    // sphere, so which of them a tree reports first at the shared nearest t is a tie.
    for (i, (a, b)) in hits[0].data.iter().zip(&hits[1].data).enumerate() {
        if i % 8 != 5 {
            assert_eq!(a.to_bits(), b.to_bits(), "ray {}, column {}", i / 8, i % 8);
        }
    }
    // A sphere of radius 0.5 at the origin, the rays in the plane z = 0.1: a ray hits where
    // y² + 0.01 < 0.25, |y| < 0.4899; margins of 0.01 ≫ the f32 rounding of the primitive.
    let t = &hits[0];
    for i in 0..64 {
        let y = -0.8 + 1.6 * (i as f64) / 63.0;
        let hit = t.data[i * t.cols].is_finite();
        if y.abs() < 0.48 {
            assert!(hit, "ray {i} (y = {y}) should hit");
        } else if y.abs() > 0.50 {
            assert!(!hit, "ray {i} (y = {y}) should miss");
        }
    }
}
