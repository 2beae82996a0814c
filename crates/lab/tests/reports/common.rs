//! Reading a chart's legend back from the SVG the lab wrote: each legend row is a marker
//! (circle, rect, polygon or closed polyline) followed by the series' label as `<text>`.

#![allow(dead_code)]

use std::collections::HashMap;

/// A marker's shape as it appears in the SVG.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SvgShape {
    /// `<circle>`.
    Circle,
    /// `<rect>`.
    Square,
    /// Three-cornered `<polygon>`/`<polyline>`.
    Triangle,
    /// Four-cornered `<polygon>`/`<polyline>`.
    Diamond,
}

fn attr<'a>(tag: &'a str, name: &str) -> Option<&'a str> {
    tag.split(&format!(" {name}=\"")).nth(1).and_then(|r| r.split('"').next())
}

fn corners(points: &str) -> usize {
    let mut v: Vec<&str> = points.split_whitespace().collect();
    if v.len() > 1 && v.first() == v.last() {
        v.pop();
    }
    v.len()
}

/// The legend of `svg` (a chart `width` pixels wide whose legend occupies the right 230 px):
/// (label, shape of the marker drawn just before it on the same row).
pub fn legend(svg: &str, width: f64) -> Vec<(String, SvgShape)> {
    let x0 = width - 230.0;
    let mut last: Option<(SvgShape, f64)> = None; // shape, centre y
    let mut out = Vec::new();
    for chunk in svg.split('<').skip(1) {
        let tag = chunk.split('>').next().unwrap_or("");
        let num = |n: &str| attr(tag, n).and_then(|v| v.parse::<f64>().ok());
        let shape = if tag.starts_with("circle") {
            num("cx").filter(|x| *x >= x0).map(|_| (SvgShape::Circle, num("cy").unwrap_or(0.0)))
        } else if tag.starts_with("rect") {
            let (x, y, h) = (num("x").unwrap_or(0.0), num("y").unwrap_or(0.0), num("height").unwrap_or(0.0));
            (x >= x0 && h < 20.0).then_some((SvgShape::Square, y + h / 2.0))
        } else if tag.starts_with("polygon") || tag.starts_with("polyline") {
            let pts = attr(tag, "points").unwrap_or("");
            let xy: Vec<(f64, f64)> = pts
                .split_whitespace()
                .filter_map(|p| p.split_once(',').and_then(|(a, b)| Some((a.parse().ok()?, b.parse().ok()?))))
                .collect();
            let cy = xy.iter().map(|p| p.1).sum::<f64>() / xy.len().max(1) as f64;
            match corners(pts) {
                3 if xy.iter().all(|p| p.0 >= x0) => Some((SvgShape::Triangle, cy)),
                4 if xy.iter().all(|p| p.0 >= x0) => Some((SvgShape::Diamond, cy)),
                _ => None,
            }
        } else {
            None
        };
        if shape.is_some() {
            last = shape;
            continue;
        }
        if tag.starts_with("text") && num("x").is_some_and(|x| x >= x0) {
            let body = chunk.split_once('>').map(|(_, b)| b.trim()).unwrap_or("");
            let y = num("y").unwrap_or(f64::NAN);
            if let Some((s, cy)) = last.take() {
                // plotters anchors the label's top 6 px above the marker's centre.
                if (cy - y).abs() < 14.0 {
                    out.push((body.to_string(), s));
                }
            }
        }
    }
    out
}

/// Precision (the label's part after its last `/`) → the set of legend shapes drawn for it.
pub fn shapes_by_precision(legend: &[(String, SvgShape)]) -> HashMap<String, Vec<SvgShape>> {
    let mut m: HashMap<String, Vec<SvgShape>> = HashMap::new();
    for (label, s) in legend {
        if let Some((_, p)) = label.rsplit_once('/') {
            let v = m.entry(p.to_string()).or_default();
            if !v.contains(s) {
                v.push(*s);
            }
        }
    }
    m
}

/// Asserts that in `svg` every precision in `expect` has a legend entry, each precision one
/// shape, and no two precisions the same shape.
pub fn assert_precision_shapes(svg: &str, width: f64, expect: &[&str], what: &str) {
    let leg = legend(svg, width);
    let m = shapes_by_precision(&leg);
    for p in expect {
        let s = m.get(*p).unwrap_or_else(|| panic!("{what}: no legend entry for {p}: {leg:?}"));
        assert_eq!(s.len(), 1, "{what}: {p} drawn with several shapes {s:?}");
    }
    let mut seen: Vec<(SvgShape, &str)> = Vec::new();
    for (p, s) in &m {
        if let Some((_, q)) = seen.iter().find(|(t, _)| *t == s[0]) {
            panic!("{what}: precisions {p} and {q} share the marker shape {:?}", s[0]);
        }
        seen.push((s[0], p));
    }
}
