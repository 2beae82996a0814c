//! The AO report (`tubecast-lab voxel-ao`) and the grid ablation table of the voxel report:
//! quick runs write their tables, every error is a finite occlusion difference in [0, 1],
//! every time is finite and positive, and the ray estimator's mean error falls from 1 to 64
//! rays: at a point occluded with probability `p` one ray is off by `2p(1 − p)` on average,
//! 64 rays by at most `√(p(1 − p))/8`, less wherever `p(1 − p) > 1/256`; the 1024-ray
//! reference adds at most `0.0156` (one standard error) to both. (No assertion on the times.)

use tubecast_lab::report::{self, parse_num, table_rows, ReportOptions};

#[test]
fn ao_report_writes_errors_against_cost() {
    let out = std::env::temp_dir().join(format!("tubecast-report-{}-voxel-ao", std::process::id()));
    // A 24×24 camera (image/4): enough shaded points for the statistical check below.
    let files =
        report::run_voxel_ao(&out, &ReportOptions { image: 96, ..ReportOptions::quick() }).expect("report runs");
    let svg = std::fs::read_to_string(&files.charts[0]).unwrap();
    assert!(svg.contains("<svg") && svg.contains("ns per shaded point"));
    let md = std::fs::read_to_string(&files.markdown).unwrap();
    assert!(out.join("voxel_ao.tables.json").exists());
    let rows = table_rows(&md, "scene");
    // 2 scenes × (4 ray counts + 3 pyramid resolutions × 4 cone counts + 4 volume-model rows
    // + 2 LoD resolutions × 4 cone counts).
    assert_eq!(rows.len(), 2 * (4 + 12 + 4 + 8), "{rows:?}");
    for r in &rows {
        let num = |k: usize| parse_num(&r[k]).unwrap();
        assert!(num(4).is_finite() && num(4) > 0.0 && num(5).is_finite() && num(5) > 0.0, "{r:?}");
        assert!((0.0..=num(7)).contains(&num(6)) && num(7) <= 1.0 && num(8).abs() <= num(6) + 1e-4, "{r:?}");
    }
    for scene in ["bundle", "furball"] {
        let mean = |n: &str| {
            let r = rows.iter().find(|r| r[0] == scene && r[1] == "rays" && r[2] == n).unwrap();
            parse_num(&r[6]).unwrap()
        };
        assert!(mean("64") < mean("1"), "{scene}: 64 rays not better than 1: {rows:?}");
    }
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn voxel_report_has_the_ablation_table() {
    let out = std::env::temp_dir().join(format!("tubecast-report-{}-voxel-ablation", std::process::id()));
    let files = report::run_voxel(&out, &ReportOptions::quick()).expect("report runs");
    let md = std::fs::read_to_string(&files.markdown).unwrap();
    let rows = table_rows(&md, "scene");
    assert_eq!(rows.len(), 3, "{rows:?}"); // bundle, furball, two bundles apart at 10³ links
    for r in &rows {
        assert!(r[2].parse::<usize>().unwrap() >= 1, "{r:?}");
        for c in &r[3..] {
            let v = parse_num(c).unwrap();
            assert!(v.is_finite() && v > 0.0, "{r:?}");
        }
    }
    let _ = std::fs::remove_dir_all(&out);
}
