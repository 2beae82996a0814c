//! The dynamic-scene (voxel grid vs BVH) report: a tiny run writes its chart and a table with
//! one opaque and one transparent row per size. (No assertion on the times themselves.)

use tubecast_lab::report::{self, parse_num, table_rows, ReportOptions};

#[test]
fn voxel_report_writes_table_and_chart() {
    let out = std::env::temp_dir().join(format!("tubecast-report-{}-voxel", std::process::id()));
    let files = report::run_voxel(&out, &ReportOptions::quick()).expect("report runs");
    let svg = std::fs::read_to_string(&files.charts[0]).unwrap();
    assert!(svg.contains("<svg") && svg.contains("links"));
    let md = std::fs::read_to_string(&files.markdown).unwrap();
    let rows = table_rows(&md, "links");
    // Quick run: 10³ links only; ceil(1000/84) = 12 fibres of 84 links = 1008 links.
    assert_eq!(rows.len(), 2, "{rows:?}");
    for (r, mode) in rows.iter().zip(["opaque", "transparent"]) {
        assert_eq!((r[0].as_str(), r[1].as_str()), ("1008", mode));
        for c in &r[2..] {
            let v = parse_num(c).unwrap();
            assert!(v.is_finite() && v > 0.0, "{r:?}");
        }
    }
    let _ = std::fs::remove_dir_all(&out);
}
