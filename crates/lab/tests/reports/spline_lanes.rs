//! The spline-lanes report (the spline kernel's cost per call): a quick run writes all twelve timed rows
//! and a floor table that obeys identities derived by hand from its own inputs. (No assertion
//! on the times themselves: speed is measured, not tested.)

use tubecast_lab::report::{self, parse_num, spline_lane_floor, table_rows, ReportOptions};

#[test]
fn spline_lanes_report_rows_and_floor() {
    let out = std::env::temp_dir().join(format!("tubecast-report-{}-spline-lanes", std::process::id()));
    let files = report::run_spline_lanes(&out, &ReportOptions::quick()).expect("report runs");
    let md = std::fs::read_to_string(&files.markdown).unwrap();
    let rows = table_rows(&md, "precision");
    assert_eq!(rows.len(), 12, "{rows:?}");
    for r in &rows {
        for c in &r[2..5] {
            let v = parse_num(c).unwrap();
            assert!(v.is_finite() && v > 0.0, "{r:?}");
        }
    }
    let input = |name: &str| {
        table_rows(&md, "input").into_iter().find(|r| r[0] == name).unwrap_or_else(|| panic!("no {name}"))[1].clone()
    };
    // The bench's documented mixed set: 22 hits in its first 64 rays (`benches/spline.rs`).
    let k: Vec<usize> = input("k_p").split_whitespace().map(|s| s.parse().unwrap()).collect();
    assert_eq!((k.len(), k.iter().sum::<usize>()), (8, 22), "{k:?}");
    let (h, g_l) = (parse_num(&input("H")).unwrap(), parse_num(&input("G_l")).unwrap());
    let floors: Vec<f64> =
        table_rows(&md, "hit path's lane gain G_s").iter().map(|r| parse_num(&r[1]).unwrap()).collect();
    assert_eq!(floors.len(), 4);
    // Every pack holds a hit, so with every lane useful (G_s = 8, cap 1) the sum is the 8 packs:
    // floor = G_l·H·8/64 = G_l·H/8. At G_s = G_l every pack holds ≥ 8/G_l hits when G_l ≥ 4
    // (cap ≤ 2 ≤ k_p): floor = G_l·H/64 · 64/G_l = H.
    // Tolerances: the table prints H, G_l and each floor to two decimals (each within 0.005 of
    // the value used), and floor = c·G_l·H is linear in the product: with printed G_l', H',
    // |G_l'·H' − G_l·H| ≤ 0.005·(G_l' + H') + 0.005² (to first order in the larger printed
    // factors, the second-order term bounding the rest). So a printed floor differs from
    // c·G_l'·H' by at most 0.005 + c·(0.005·(G_l' + H') + 2.5e-5), plus 1e-9 for the parse.
    let prod = |c: f64| 0.005 + c * (0.005 * (g_l + h) + 2.5e-5) + 1e-9;
    assert!((floors[3] - g_l * h / 8.0).abs() <= prod(1.0 / 8.0), "{floors:?} {g_l} {h}");
    // The identity floor = H needs the true G_l ≥ 4: printed ≥ 4.005 makes it so. Then the
    // printed floor and the printed H are each within 0.005 of the same H.
    if g_l >= 4.005 {
        assert!((floors[1] - h).abs() <= 0.01 + 1e-9, "{floors:?} {g_l} {h}");
    }
    // The printed floor of the G_s = 4 row is the library function's: cap 2, Σ min(k_p, 2) = 16
    // for these packs, so c = 16/64.
    assert_eq!(k.iter().map(|&k| k.min(2)).sum::<usize>(), 16);
    assert!((floors[2] - spline_lane_floor(&k, 8, 64, h, g_l, 4.0)).abs() <= prod(16.0 / 64.0));
    let _ = std::fs::remove_dir_all(&out);
}
