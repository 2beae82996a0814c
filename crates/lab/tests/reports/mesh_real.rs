//! The real-world-like mesh/choice report: a tiny run writes its files, every scene has its
//! exact row, and every certified error it reports is within the tolerance asked for
//! (ε = k·r, r the scene's largest radius, read from the markdown).

use tubecast_lab::report::{self, parse_num, tables_json, ReportOptions};

#[test]
fn mesh_real_report_keeps_each_representation_within_its_tolerance() {
    let out = std::env::temp_dir().join(format!("tubecast-report-{}-meshreal", std::process::id()));
    let opts = ReportOptions { image: 16, ..ReportOptions::quick() };
    let files = report::run_mesh_real(&out, &opts).expect("report runs");
    assert_eq!(files.charts.len(), 2);
    for c in &files.charts {
        let svg = std::fs::read_to_string(c).unwrap();
        assert!(svg.contains("<svg") && svg.contains("certified error"), "{}", c.display());
    }
    let md = std::fs::read_to_string(&files.markdown).unwrap();
    assert!(files.markdown.with_extension("tables.json").exists(), "tables JSON beside the markdown");
    // One section per scene, each: "largest radius r = X." then its table.
    let radii: Vec<f64> = md
        .lines()
        .filter_map(|l| l.split("largest radius r = ").nth(1))
        .map(|v| parse_num(v.trim_end_matches('.')).unwrap())
        .collect();
    let tables = tables_json(&md);
    let tables = tables.as_array().unwrap();
    assert_eq!((radii.len(), tables.len()), (3, 3), "three scenes");
    for (t, r) in tables.iter().zip(&radii) {
        let cols: Vec<&str> = t["columns"].as_array().unwrap().iter().map(|c| c.as_str().unwrap()).collect();
        let col = |n: &str| cols.iter().position(|c| *c == n).unwrap();
        let (cm, cc, ct) = (col("model"), col("certified error"), col("triangles"));
        let rows = t["rows"].as_array().unwrap();
        let cell = |row: &serde_json::Value, c: usize| row[c].as_str().unwrap().to_string();
        assert_eq!(cell(&rows[0], cm), "exact");
        assert_eq!(parse_num(&cell(&rows[0], cc)), Some(0.0));
        let mut meshes = 0;
        for row in rows {
            let model = cell(row, cm);
            let Some(k) = model.split("ε = ").nth(1).and_then(|v| v.split('·').next()) else { continue };
            let k: f64 = k.parse().unwrap();
            let cert = parse_num(&cell(row, cc)).unwrap();
            assert!(cert >= 0.0 && cert <= k * r, "{model}: certified {cert:e} > ε = {:e}", k * r);
            if model.starts_with("mesh") {
                meshes += 1;
                assert!(parse_num(&cell(row, ct)).unwrap() > 0.0, "{model}: no triangles");
            }
        }
        assert!(meshes >= 1, "a mesh row per scene in the quick run");
    }
    let _ = std::fs::remove_dir_all(&out);
}
