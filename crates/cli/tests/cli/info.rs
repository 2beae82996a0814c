//! `info` tells what a scientist asks first, in text and completely in `--json`; `generate`
//! says when the format drops the radii.

use crate::common::bin;
use std::path::{Path, PathBuf};
crate::common::tmp_fn!();

fn repo(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..").join(rel)
}

fn json(input: &Path, extra: &[&str]) -> serde_json::Value {
    let o = bin().args(["info", "--json"]).arg(input).args(extra).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    serde_json::from_slice(&o.stdout).unwrap()
}

#[test]
fn info_reports_streamlines_space_fields_and_the_model() {
    // nibabel's complex.trk: 3 streamlines of 1, 2 and 5 points (8 points, 5 joining links and
    // the isolated point's sphere), per-point scalars "colors" (3 columns) and "fa", and
    // per-streamline properties "mean_curvature", "mean_torsion", "mean_colors" (nibabel's
    // test data: fa 0.2 … 0.8 as float32, mean_curvature 1.11 … 3.11).
    let trk = repo("reference/readers/nibabel/complex.trk");
    let j = json(&trk, &[]);
    assert_eq!((j["streamlines"].as_u64(), j["points"].as_u64(), j["links"].as_u64()), (Some(3), Some(8), Some(6)));
    assert_eq!(j["format"], "trk");
    assert_eq!(j["space"]["voxel_size"], serde_json::json!([1.0, 1.0, 1.0]));
    assert_eq!(j["space"]["voxel_order"], "RAS");
    let field = |name: &str| j["fields"].as_array().unwrap().iter().find(|f| f["name"] == name).cloned();
    let fa = field("scalar:fa").expect("scalar:fa listed");
    assert_eq!((fa["per"].as_str(), fa["width"].as_u64()), (Some("point"), Some(1)));
    let r = fa["range"].as_array().unwrap();
    assert_eq!((r[0].as_f64().unwrap() as f32, r[1].as_f64().unwrap() as f32), (0.2, 0.8));
    assert_eq!(field("scalar:colors").unwrap()["width"], 3);
    for p in ["property:mean_curvature", "property:mean_torsion", "property:mean_colors"] {
        assert_eq!(field(p).unwrap_or_else(|| panic!("{p}"))["per"], "streamline");
    }
    // The model render would trace, and its certified error.
    assert_eq!((j["model"]["name"].as_str(), j["model"]["certified_error"].as_f64()), (Some("links"), Some(0.0)));
    let helix = tmp("info-helix.swc");
    assert!(bin().args(["generate", "helix", "--segments", "20", "-o"]).arg(&helix).status().unwrap().success());
    let s = json(&helix, &["--splines"]);
    assert_eq!(s["model"]["name"], "splines");
    let rel = s["model"]["certified_error_radii"].as_f64().unwrap();
    assert!(rel > 0.0 && rel <= 1e-3, "the faithful split's certified distance: {rel}");
    let c = json(&helix, &["--tolerance", "0.05"]);
    assert_eq!(c["model"]["name"], "choice");
    assert!(c["model"]["certified_error"].as_f64().unwrap() <= 0.05);
    let q = json(&helix, &["--model", "quantized"]);
    assert_eq!(q["model"]["name"], "quantized");
    assert!(q["model"]["certified_error"].as_f64().unwrap() > 0.0);
    let m = json(&helix, &["--model", "mesh", "--tolerance", "0.05"]);
    assert!(m["model"]["certified_error"].as_f64().unwrap() <= 0.05, "{}", m["model"]);
    // The table says the same.
    let text = String::from_utf8(bin().arg("info").arg(&trk).output().unwrap().stdout).unwrap();
    for line in
        ["streamlines 3", "voxels     size [1.0,1.0,1.0]", "field      scalar:fa (per point", "model      links"]
    {
        assert!(text.contains(line), "{line:?} in {text}");
    }
}

#[test]
fn generate_keeps_radii_where_the_format_holds_them_and_warns_where_not() {
    for (ext, drops) in [("swc", false), ("obj", false), ("tck", true), ("trk", true)] {
        let out = tmp(&format!("radii.{ext}"));
        let o = bin().args(["generate", "helix", "--segments", "10", "-o"]).arg(&out).output().unwrap();
        assert!(o.status.success());
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(err.contains("tubecast: warning:") && err.contains("radii"), drops, "{ext}: {err}");
        // The helix's radii vary along it (cones); dropped, the default radius makes cylinders.
        let j = json(&out, &[]);
        assert_eq!(j["cones"].as_u64().unwrap() > 0, !drops, "{ext}: {j}");
    }
}
