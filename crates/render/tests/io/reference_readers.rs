//! Our TrackVis, MRtrix and TRX readers against the community's reference readers (nibabel,
//! trx-python) on the files under reference/readers/: nibabel's own test files, header
//! variants built as nibabel's tests build them, and TRX files written by trx-python.
//! reference/readers.py (pinned, reference/requirements-readers.txt) wrote what the reference
//! readers read into reference/readers/fixture.json; every file they refuse we refuse with an
//! error naming the file, every file they accept we read to the same streamlines and data.

use serde_json::Value;
use std::path::{Path, PathBuf};
use tubecast_render::io::data::{Field, Tractogram};

/// f32 unit roundoff.
const U: f64 = 1.0 / 16_777_216.0;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../reference")
}

fn fixtures() -> Value {
    let text = std::fs::read_to_string(root().join("readers/fixture.json")).unwrap();
    serde_json::from_str(&text).unwrap()
}

fn floats(v: &Value) -> Vec<f64> {
    v.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect()
}

/// Our reading of `rel` (a path under reference/readers/), by extension.
fn ours(rel: &str) -> Result<Tractogram, tubecast_render::io::IoError> {
    let path = root().join("readers").join(rel);
    let data = std::fs::read(&path).unwrap();
    match rel.rsplit('.').next().unwrap() {
        "trk" => tubecast_render::io::trk::read_data(&data, rel).map(|(_, t)| t),
        "tck" => tubecast_render::io::tck::read(&data, rel).map(|lines| Tractogram { lines, ..Default::default() }),
        "trx" => tubecast_render::io::trx::read(&data, rel),
        other => panic!("no reader for .{other}"),
    }
}

fn check_fields(rel: &str, what: &str, ours: &[Field], reference: &Value) {
    let reference = reference.as_object().unwrap();
    let mut names: Vec<&str> = ours.iter().map(|f| f.name.as_str()).collect();
    names.sort();
    assert_eq!(names, reference.keys().map(|k| k.as_str()).collect::<Vec<_>>(), "{rel}: {what} names");
    for f in ours {
        let r = &reference[&f.name];
        assert_eq!(f.width as u64, r["width"].as_u64().unwrap(), "{rel}: {what} {} width", f.name);
        // Stored values (f16/f32/f64) convert to f64 exactly in both readers.
        assert_eq!(f.values, floats(&r["values"]), "{rel}: {what} {} values", f.name);
    }
}

/// TrackVis points: nibabel applies its affine A (computed in f64, rounded to f32) to the
/// stored f32 voxmm point x in f32 arithmetic (`x·A₃ₓ₃ᵀ + t`); we apply the f64 affine in f64.
/// Per coordinate i, with S = Σⱼ|Aᵢⱼ xⱼ| + |tᵢ|: rounding A to f32 moves the result by ≤ u·S,
/// the f32 dot product of three terms plus the translation by ≤ 4u·S (γ₄, first order), the
/// final rounding to f32 is inside that; our f64 evaluation adds ≤ 4·2⁻⁵³·S. Bound: 6u·S.
fn check_trk_points(rel: &str, t: &Tractogram, rec: &Value) {
    let a = floats(&rec["affine"]);
    let (pts, vox) = (floats(&rec["points"]), floats(&rec["voxmm"]));
    let ours: Vec<f64> = t.lines.iter().flat_map(|l| l.points.iter().flatten().copied()).collect();
    assert_eq!(ours.len(), pts.len(), "{rel}: coordinate count");
    for (k, (&o, &r)) in ours.iter().zip(&pts).enumerate() {
        let (p, i) = (k / 3, k % 3);
        let s: f64 = (0..3).map(|j| (a[4 * i + j] * vox[3 * p + j]).abs()).sum::<f64>() + a[4 * i + 3].abs();
        assert!(
            (o - r).abs() <= 6.0 * U * s,
            "{rel}: point {p} coordinate {i}: ours {o}, nibabel {r}, bound {}",
            6.0 * U * s
        );
    }
    // Affine: nibabel's is our f64 product rounded to f32 (≤ u relative), plus the f64
    // rounding of the products (≤ 1e-12 absolute for these entries of size ≤ 1e3).
    let m = t.affine.expect("a TrackVis reading has its affine");
    for (k, &r) in a.iter().enumerate() {
        let o = m[k / 4][k % 4];
        assert!((o - r).abs() <= U * o.abs() + 1e-12, "{rel}: affine entry {k}: ours {o}, nibabel {r}");
    }
}

#[test]
fn every_file_agrees_with_the_reference_reader() {
    let fx = fixtures();
    let files = fx["files"].as_object().unwrap();
    assert!(files.len() >= 40, "only {} files in the fixture", files.len());
    for (rel, rec) in files {
        let got = ours(rel);
        if !rec["accepted"].as_bool().unwrap() {
            let e = got
                .err()
                .unwrap_or_else(|| panic!("{rel}: the reference refuses it ({}), we accepted it", rec["error"]));
            assert!(e.to_string().starts_with(&format!("{rel}: ")) && e.problem.len() > 10, "{rel}: unclear error {e}");
            continue;
        }
        let t = got.unwrap_or_else(|e| panic!("{rel}: the reference reads it, we refuse it: {e}"));
        let lengths: Vec<u64> = t.lines.iter().map(|l| l.points.len() as u64).collect();
        let want: Vec<u64> = rec["lengths"].as_array().unwrap().iter().map(|v| v.as_u64().unwrap()).collect();
        assert_eq!(lengths, want, "{rel}: streamline lengths");
        if rel.ends_with(".trk") {
            check_trk_points(rel, &t, rec);
        } else {
            // MRtrix and TRX store world coordinates: both readers return the stored values.
            let ours: Vec<f64> = t.lines.iter().flat_map(|l| l.points.iter().flatten().copied()).collect();
            assert_eq!(ours, floats(&rec["points"]), "{rel}: points");
        }
        check_fields(rel, "per-point", &t.per_point, &rec["per_point"]);
        check_fields(rel, "per-streamline", &t.per_line, &rec["per_streamline"]);
        if let Some(groups) = rec["groups"].as_object() {
            let want: Vec<(String, Vec<u64>)> = groups
                .iter()
                .map(|(k, v)| (k.clone(), v.as_array().unwrap().iter().map(|i| i.as_u64().unwrap()).collect()))
                .collect();
            assert_eq!(t.groups, want, "{rel}: groups");
        }
    }
}

#[test]
fn committed_inputs_cover_the_header_variants() {
    // The fixture must hold the variants this suite is about, accepted or refused as nibabel does.
    let fx = fixtures();
    let f = &fx["files"];
    for (rel, accepted) in [
        ("nibabel/complex_big_endian.trk", true),
        ("nibabel/standard.LPS.trk", true),
        ("variants/voxel_order_PSR.trk", true),
        ("variants/voxel_order_empty.trk", true),
        ("variants/vox_to_ras_zero.trk", true),
        ("variants/version_1.trk", true),
        ("variants/version_123.trk", false),
        ("variants/no_datatype.tck", true),
        ("variants/unclosed_streamline.tck", false),
        ("nibabel/no_magic_number.tck", false),
        ("trx/complex_float16_uint64_stored.trx", true),
        ("trx/complex_float64_uint32_deflate.trx", true),
    ] {
        assert_eq!(f[rel]["accepted"].as_bool(), Some(accepted), "{rel}");
    }
}
