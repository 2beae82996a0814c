//! The speed report: a tiny run writes its chart and table with one row per scene size.
//! (No assertion on the times themselves: they depend on the machine.)

use tubecast_lab::report::{self, parse_num, table_rows, ReportOptions};

#[test]
fn speed_report_writes_table_and_chart() {
    let out = std::env::temp_dir().join(format!("tubecast-report-{}-speed", std::process::id()));
    let files = report::run_speed(&out, &ReportOptions::quick()).expect("report runs");
    let svg = std::fs::read_to_string(&files.charts[0]).unwrap();
    assert!(svg.contains("<svg") && svg.contains("segments"));
    let md = std::fs::read_to_string(&files.markdown).unwrap();
    let rows = table_rows(&md, "segments");
    assert_eq!(rows.len(), 1, "quick run measures 10^3 segments only: {rows:?}");
    let r = &rows[0];
    // ceil(1000/78) = 13 hairs of 78 links: 1014 links.
    assert_eq!(r[0], "1014");
    for c in &r[1..] {
        let v = parse_num(c).unwrap();
        assert!(v.is_finite() && v > 0.0, "{r:?}");
    }
    let _ = std::fs::remove_dir_all(&out);
}
