//! The mesh report (Salm's question), tiny run: the exact row, the built 10⁻²·r mesh, and the
//! 10⁻³·r mesh skipped over the quick run's memory limit with its estimate in the notes.

use tubecast_lab::report::{self, parse_num, tables_json, ReportOptions};

#[test]
fn mesh_report_builds_what_fits_and_estimates_the_rest() {
    let out = std::env::temp_dir().join(format!("tubecast-report-{}-mesh", std::process::id()));
    let opts = ReportOptions { image: 16, ..ReportOptions::quick() };
    let files = report::run_mesh(&out, &opts).expect("report runs");
    let md = std::fs::read_to_string(&files.markdown).unwrap();
    let tables = tables_json(&md);
    let t = &tables.as_array().unwrap()[0];
    let cols: Vec<&str> = t["columns"].as_array().unwrap().iter().map(|c| c.as_str().unwrap()).collect();
    let col = |n: &str| cols.iter().position(|c| *c == n).unwrap();
    let rows = t["rows"].as_array().unwrap();
    let cell = |r: usize, c: &str| rows[r][col(c)].as_str().unwrap().to_string();
    assert_eq!(cell(0, "model"), "exact");
    let mesh: Vec<usize> = (0..rows.len()).filter(|&r| cell(r, "model").starts_with("mesh")).collect();
    assert_eq!(mesh.len(), 1, "the 10⁻²·r mesh is built, the 10⁻³·r one is not");
    assert_eq!(cell(mesh[0], "model"), "mesh ε = 0.01·r");
    assert!(parse_num(&cell(mesh[0], "triangles")).unwrap() > 0.0);
    // The note: "… mesh at ε = 0.001·r: not built — estimated T triangles, A GB for the
    // tracer, ≥ B GB peak …". A tracer holds at least three f32 vertices (36 bytes) per
    // triangle, and the peak while building holds the finished tracer.
    let note = md.lines().find(|l| l.contains("ε = 0.001·r: not built")).expect("a skipped note");
    let num = |after: &str| -> f64 {
        let s = note.split(after).nth(1).unwrap().trim_start();
        parse_num(s.split(' ').next().unwrap().trim_end_matches(',')).unwrap()
    };
    let (tris, tracer, peak) = (num("estimated"), num("triangles, "), num("≥"));
    assert!(tris > 0.0 && tracer * 1e9 >= 36.0 * tris, "{note}");
    assert!(peak >= tracer, "{note}");
    assert!(peak * 1e9 > 1.5e8, "skipped only over the quick run's limit: {note}");
    assert_eq!(files.charts.len(), 1);
    let _ = std::fs::remove_dir_all(&out);
}
