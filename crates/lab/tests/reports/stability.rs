//! The stability report: per-region numbers read back from the markdown match what the
//! error analysis predicts (`tests/kernels/link/properties.rs`): the stable kernel never misclassifies outside
//! its band and stays within its bound in every region; the faithful (apex-based) kernel loses
//! digits where the apex goes to infinity (near-equal radii: apex distance p₂ = L·r/|Δr| ≈ 10⁷·L,
//! so its coefficient errors grow like ε·p₂² instead of ε·S²).

use crate::common;

use tubecast_lab::report::{self, parse_num, table_rows, ReportOptions};

fn col(md: &str, first: &str, name: &str) -> usize {
    let line = md.lines().find(|l| l.starts_with(&format!("| {first} |"))).expect("table header");
    line.trim().trim_matches('|').split('|').position(|c| c.trim() == name).unwrap_or_else(|| panic!("column {name}"))
}

#[test]
fn stability_report_shows_where_methods_break() {
    let out = std::env::temp_dir().join(format!("tubecast-report-{}-stab", std::process::id()));
    let files = report::run_stability(&out, &ReportOptions::quick()).expect("report runs");
    assert_eq!(files.charts.len(), 4);
    for c in &files.charts {
        let svg = std::fs::read_to_string(c).unwrap();
        assert!(svg.contains("<svg") && svg.contains("<text"), "{}", c.display());
        // The charts show the scalar precisions, each with its own marker shape.
        common::assert_precision_shapes(&svg, 1000.0, &["f32", "f64"], &c.display().to_string());
    }
    let md = std::fs::read_to_string(&files.markdown).unwrap();
    let rows = table_rows(&md, "region");
    let c = |n: &str| col(&md, "region", n);
    let (c_fm, c_fh, c_bound, c_max, c_hit) =
        (c("false miss"), c("false hit"), c("max err/bound"), c("max err (r)"), c("must-hit"));
    let get = |region: &str, m: &str| {
        rows.iter().find(|r| r[0] == region && r[1] == m).unwrap_or_else(|| panic!("{region} {m}")).clone()
    };
    let regions: Vec<String> = rows.iter().map(|r| r[0].clone()).fold(Vec::new(), |mut v, r| {
        if !v.contains(&r) {
            v.push(r)
        }
        v
    });
    assert!(regions.len() >= 10, "{regions:?}");
    for region in &regions {
        for m in ["stable/f64", "stable/f32"] {
            let r = get(region, m);
            assert_eq!(r[c_fm], "0", "{region} {m}: false misses");
            assert_eq!(r[c_fh], "0", "{region} {m}: false hits");
            let b = parse_num(&r[c_bound]).unwrap();
            assert!(b.is_nan() || b <= 1.0, "{region} {m}: err/bound {b}");
            assert!(parse_num(&r[c_hit]).unwrap() > 0.0, "{region} {m}: no robust hits");
        }
    }
    let st = parse_num(&get("near-equal-radii", "stable/f64")[c_max]).unwrap();
    let han = parse_num(&get("near-equal-radii", "faithful-precomputed/f64")[c_max]).unwrap();
    assert!(han > 100.0 * st, "near-equal radii: faithful {han:e} should be far worse than stable {st:e}");
    // On the well-conditioned random set both formulations are accurate to far below a radius.
    let hr = parse_num(&get("random", "faithful-precomputed/f64")[c_max]).unwrap();
    assert!(hr < 1e-6, "faithful on random links: {hr:e}");
    // Spline table exists with every region and the default solver never misses a robust hit.
    let srows = table_rows(&md, "spline region");
    assert!(srows.len() >= 5 * 7, "spline rows {}", srows.len());
    let sc = col(&md, "spline region", "false miss");
    for r in srows.iter().filter(|r| r[1] == "polynomial/f64") {
        assert_eq!(r[sc], "0", "spline {}: polynomial/f64 false misses", r[0]);
    }
    let _ = std::fs::remove_dir_all(&out);
}
