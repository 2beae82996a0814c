//! Chart readability: zero and infinity marked, precision series by shape in the legend,
//! long category labels cut, colliding point labels moved apart; markdown tables as JSON.

use crate::common;

use tubecast_lab::report::chart::{precision_shape, write_svg, Chart, Marker, Pt, Series, Shape, XAxis};
use tubecast_lab::report::{tables_json, write_tables_json};

fn pt(x: f64, y: f64, text: Option<&str>) -> Pt {
    Pt { x, y, marker: Marker::Dot, text: text.map(String::from) }
}

#[test]
fn zero_infinity_shapes_labels_and_collisions() {
    let long = "a category label far longer than any axis area allows for";
    let chart = Chart {
        title: "t".into(),
        x_desc: "x".into(),
        y_desc: "y".into(),
        x: XAxis::Categories(vec![long.into(), "b".into()]),
        y_floor: 1e-3,
        series: vec![
            Series {
                label: "stable/f32".into(),
                color: 0,
                points: vec![pt(0.0, 0.0, None), pt(1.0, 1.0, Some("AAA"))],
                line: false,
            },
            Series {
                label: "stable/f64".into(),
                color: 1,
                points: vec![pt(0.0, f64::INFINITY, None), pt(1.0, 1.0, Some("BBB"))],
                line: false,
            },
            Series { label: "stable/f32x8".into(), color: 2, points: vec![pt(1.0, 2.0, None)], line: false },
            Series { label: "stable/f64x4".into(), color: 3, points: vec![pt(1.0, 3.0, None)], line: false },
        ],
        note: None,
    };
    let path = std::env::temp_dir().join(format!("tubecast-chart-{}.svg", std::process::id()));
    write_svg(&path, &chart, (800, 500)).unwrap();
    let svg = std::fs::read_to_string(&path).unwrap();
    // Every <text> element as (y, content): plotters writes the content on its own line.
    let texts: Vec<(f64, String)> = svg
        .split("<text")
        .skip(1)
        .map(|t| {
            let y = t.split("y=\"").nth(1).unwrap().split('"').next().unwrap().parse().unwrap();
            let body = t.split_once('>').unwrap().1.split("</text>").next().unwrap().trim().to_string();
            (y, body)
        })
        .collect();
    let has = |s: &str| texts.iter().any(|(_, b)| b == s);
    // Zero is marked "0", +∞ "∞" (neither dropped).
    assert!(has("0"), "zero not marked");
    assert!(has("∞"), "infinity not marked");
    // Precision shapes: f32 circle, f64 square (rect), f32x8 triangle, f64x4 diamond (polygons),
    // in the legend too, one shape per precision and no shape shared.
    assert_eq!(
        [
            precision_shape("x/f32"),
            precision_shape("x/f64"),
            precision_shape("x/f32x8"),
            precision_shape("x/f64x4"),
            precision_shape("cone")
        ],
        [Some(Shape::Circle), Some(Shape::Square), Some(Shape::Triangle), Some(Shape::Diamond), None]
    );
    assert!(svg.contains("<rect") && svg.contains("<polygon"), "square and triangle markers drawn");
    common::assert_precision_shapes(&svg, 800.0, &["f32", "f64", "f32x8", "f64x4"], "synthetic chart");
    // The long category label is cut with an ellipsis, never written whole.
    assert!(!svg.contains(long) && svg.contains('…'));
    // The two point labels at the same spot are moved apart by at least one text line.
    let y_of = |t: &str| texts.iter().find(|(_, b)| b == t).map(|(y, _)| *y).unwrap();
    assert!((y_of("AAA") - y_of("BBB")).abs() >= 11.0, "labels collide");
    let _ = std::fs::remove_file(&path);
}

#[test]
fn markdown_tables_as_json() {
    let md = "# R\n\n| a | b |\n|---|---|\n| 1 | x |\n| 2 | - |\n\ntext\n\n| c |\n|---|\n| 3 |\n";
    let j = tables_json(md);
    assert_eq!(j.as_array().unwrap().len(), 2);
    assert_eq!(j[0]["columns"], serde_json::json!(["a", "b"]));
    assert_eq!(j[0]["rows"], serde_json::json!([["1", "x"], ["2", "-"]]));
    assert_eq!(j[1]["rows"], serde_json::json!([["3"]]));
}

#[test]
fn committed_reports_get_their_json_without_rerunning() {
    let dir = std::env::temp_dir().join(format!("tubecast-tables-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("r.md"), "# R\n\n| a |\n|---|\n| 1 |\n").unwrap();
    std::fs::write(dir.join("README.md"), "| x |\n|---|\n| y |\n").unwrap();
    std::fs::write(dir.join("plain.md"), "no tables\n").unwrap();
    let files = write_tables_json(&dir).unwrap();
    assert_eq!(files, vec![dir.join("r.tables.json")]);
    let j: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&files[0]).unwrap()).unwrap();
    assert_eq!(j[0]["rows"], serde_json::json!([["1"]]));
    assert!(!dir.join("README.tables.json").exists() && !dir.join("plain.tables.json").exists());
    let _ = std::fs::remove_dir_all(&dir);
}
