//! The accuracy report: a tiny seeded run writes its files; the numbers read back from the
//! markdown obey the error analysis of `tests/kernels/link/properties.rs`; seeded runs reproduce them.

use crate::common;

use std::path::PathBuf;
use tubecast_lab::report::{self, parse_num, table_rows, ReportOptions};

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("tubecast-report-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// Column index by header name in the table whose first header is `first`.
fn col(md: &str, first: &str, name: &str) -> usize {
    let line = md.lines().find(|l| l.starts_with(&format!("| {first} |"))).expect("table header");
    line.trim().trim_matches('|').split('|').position(|c| c.trim() == name).unwrap_or_else(|| panic!("column {name}"))
}

fn row<'a>(rows: &'a [Vec<String>], method: &str) -> &'a Vec<String> {
    rows.iter().find(|r| r[0] == method).unwrap_or_else(|| panic!("row {method}"))
}

/// The accuracy columns (everything but the timing) of both tables.
fn accuracy_cells(md: &str) -> Vec<Vec<String>> {
    let ns = col(md, "method", "ns/test");
    table_rows(md, "method")
        .into_iter()
        .map(|mut r| {
            r.remove(ns);
            r
        })
        .collect()
}

#[test]
fn accuracy_report_writes_files_and_sane_numbers() {
    let out = tmp("acc");
    let opts = ReportOptions { time_ms: 1, ..ReportOptions::quick() };
    let files = report::run_accuracy(&out, &opts).expect("report runs");
    assert_eq!(files.charts.len(), 2);
    for c in &files.charts {
        let svg = std::fs::read_to_string(c).expect("chart written");
        assert!(svg.starts_with("<svg") || svg.contains("<svg"), "{} is not SVG", c.display());
        // Labels are SVG text, not rasterised glyphs from a system font.
        assert!(svg.contains("<text"), "{} has no text elements", c.display());
        assert!(svg.contains("ns per ray"), "{} lacks its axis description", c.display());
        // Every precision its own marker shape, in the plot and the legend.
        common::assert_precision_shapes(&svg, 1000.0, &["f32", "f64", "f32x8", "f64x4"], &c.display().to_string());
    }
    let md = std::fs::read_to_string(&files.markdown).expect("markdown written");
    let rows = table_rows(&md, "method");
    // 4 link kernels and 7 solver settings, in 4 precisions each.
    assert_eq!(rows.len(), 4 * 4 + 7 * 4, "rows: {rows:?}");
    let c_bound = col(&md, "method", "max err/bound");
    let c_max = col(&md, "method", "max err (r)");
    let c_fm = col(&md, "method", "false miss");
    let c_fh = col(&md, "method", "false hit");
    let c_hits = col(&md, "method", "must-hit");
    let c_ns = col(&md, "method", "ns/test");
    for m in ["stable/f64", "stable/f32", "stable/f64x4", "stable/f32x8"] {
        let r = row(&rows, m);
        // The stable kernel is within the proven bound of tests/kernels/link/properties.rs on every case.
        let b = parse_num(&r[c_bound]).unwrap();
        assert!(b > 0.0 && b <= 1.0, "{m}: max err/bound {b}");
        assert_eq!(r[c_fm], "0", "{m}: false misses");
        assert_eq!(r[c_fh], "0", "{m}: false hits");
        assert!(parse_num(&r[c_hits]).unwrap() >= 50.0, "{m}: too few robust hits to mean anything");
        assert!(parse_num(&r[c_ns]).unwrap() > 0.0, "{m}: timing missing");
    }
    // f64 is more accurate than f32 by orders of magnitude (ε ratio 2^29 ≈ 5e8; allow 1e6).
    let e64 = parse_num(&row(&rows, "stable/f64")[c_max]).unwrap();
    let e32 = parse_num(&row(&rows, "stable/f32")[c_max]).unwrap();
    assert!(e64 * 1e6 < e32, "f64 {e64:e} vs f32 {e32:e}");
    // Lanes compute the same IEEE operations as scalars: identical accuracy columns.
    let cells = accuracy_cells(&md);
    let find = |m: &str| cells.iter().find(|r| r[0] == m).unwrap()[1..].to_vec();
    for (a, b) in [
        ("stable/f32", "stable/f32x8"),
        ("faithful-precomputed/f64", "faithful-precomputed/f64x4"),
        ("polynomial/f32", "polynomial/f32x8"),
        ("bisection10/f64", "bisection10/f64x4"),
    ] {
        assert_eq!(find(a), find(b), "{a} vs {b}");
    }
    // More bisection steps never make the f64 spline less accurate by more than rounding:
    // 6 steps leave a bracket of 2^-6, 24 steps one of 2^-24 (the p99 error must drop a lot).
    let c_p99 = col(&md, "method", "p99 err (r)");
    let b6 = parse_num(&row(&rows, "bisection6/f64")[c_p99]).unwrap();
    let b24 = parse_num(&row(&rows, "bisection24/f64")[c_p99]).unwrap();
    assert!(b24 * 1e3 < b6, "bisection 24 steps {b24:e} vs 6 steps {b6:e}");
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn seeded_runs_reproduce_accuracy_numbers() {
    let (a, b, c) = (tmp("seed-a"), tmp("seed-b"), tmp("seed-c"));
    let opts = ReportOptions { link_cases: 60, spline_cases: 12, ..ReportOptions::quick() };
    let fa = report::run_accuracy(&a, &opts).unwrap();
    let fb = report::run_accuracy(&b, &opts).unwrap();
    let fc = report::run_accuracy(&c, &ReportOptions { seed: opts.seed + 1, ..opts.clone() }).unwrap();
    let read = |p: &PathBuf| accuracy_cells(&std::fs::read_to_string(p).unwrap());
    assert_eq!(read(&fa.markdown), read(&fb.markdown), "same seed, different numbers");
    assert_ne!(read(&fa.markdown), read(&fc.markdown), "the seed has no effect");
    for d in [a, b, c] {
        let _ = std::fs::remove_dir_all(d);
    }
}

#[test]
fn bad_options_are_errors_not_panics() {
    let out = tmp("bad");
    for o in [
        ReportOptions { link_cases: 0, ..ReportOptions::quick() },
        ReportOptions { image: 0, ..ReportOptions::quick() },
        ReportOptions { threads: 0, ..ReportOptions::quick() },
        ReportOptions { max_segments: 10, ..ReportOptions::quick() },
    ] {
        assert!(matches!(report::run_accuracy(&out, &o), Err(report::ReportError::Options(_))), "{o:?}");
    }
    // A path that cannot be a folder (a file is in the way).
    let file = tmp("file");
    std::fs::write(&file, b"x").unwrap();
    let err = report::run_accuracy(&file.join("sub"), &ReportOptions::quick()).unwrap_err();
    assert!(matches!(err, report::ReportError::Io(_)), "{err}");
    let _ = std::fs::remove_file(&file);
}
