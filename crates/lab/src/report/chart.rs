//! SVG charts with plotters' SVG backend. Text is written as SVG `<text>` elements; plotters is
//! built without its `ttf`/`ab_glyph` features, so its "naive" font layout is used and no
//! system font is ever loaded (the viewer's font renders the labels).
//!
//! Log axes are drawn as linear axes over `log10` of the values, labelled `1e<k>`: one code path
//! for every chart. Values at or below the axis floor (zero included) are drawn at the floor
//! and marked `0` (or `≤floor`), `+∞` at the top edge marked `∞`, so neither is silently lost.
//! Category labels are cut to 28 characters and the label area sized to the longest, so
//! they never cross the axis; point labels that would overlap are moved down until they do
//! not. Series whose label names a precision get a shape as well as a colour (f32 circle, f64
//! square, f32x8 lanes triangle, f64x4 lanes diamond), drawn in the plot and in the legend.

use super::ReportError;
use plotters::prelude::*;
use std::path::Path;

/// How a point is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Marker {
    /// Filled circle.
    Dot,
    /// Cross.
    Cross,
    /// Filled triangle.
    Triangle,
}

/// One point.
#[derive(Clone, Debug)]
pub struct Pt {
    /// x (data units; log axes take the log themselves).
    pub x: f64,
    /// y (data units).
    pub y: f64,
    /// Marker.
    pub marker: Marker,
    /// Optional small text next to the point.
    pub text: Option<String>,
}

/// A named, coloured set of points (optionally joined by a line).
#[derive(Clone, Debug)]
pub struct Series {
    /// Legend label.
    pub label: String,
    /// Colour index into the palette.
    pub color: usize,
    /// Points.
    pub points: Vec<Pt>,
    /// Join the points with a line (in the given order).
    pub line: bool,
}

/// An x axis.
#[derive(Clone, Debug)]
pub enum XAxis {
    /// Logarithmic, data in `(0, ∞)`.
    Log,
    /// Categories at x = 0, 1, …, labelled with these names.
    Categories(Vec<String>),
}

/// A chart description.
#[derive(Clone, Debug)]
pub struct Chart {
    /// Caption.
    pub title: String,
    /// x axis description.
    pub x_desc: String,
    /// y axis description.
    pub y_desc: String,
    /// x axis kind.
    pub x: XAxis,
    /// Smallest y shown (values below are drawn at this floor).
    pub y_floor: f64,
    /// Series.
    pub series: Vec<Series>,
    /// A note under the legend (e.g. marker meanings).
    pub note: Option<String>,
}

const PALETTE: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

/// Palette colour `i` (wraps).
pub fn color(i: usize) -> RGBColor {
    PALETTE[i % PALETTE.len()]
}

fn lg(v: f64, floor: f64) -> f64 {
    if v.is_finite() && v > floor {
        v.log10()
    } else if v.is_finite() || v.is_nan() {
        floor.log10()
    } else {
        // +∞: drawn at the floor too would hide it; callers filter infinities.
        floor.log10()
    }
}

/// A precision's marker shape.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Shape {
    /// `f32`.
    Circle,
    /// `f64`.
    Square,
    /// `f32x8` lanes.
    Triangle,
    /// `f64x4` lanes.
    Diamond,
}

/// The marker shape of a series whose label names a precision: `f32` circle, `f64` square,
/// `f32x8` lanes triangle, `f64x4` lanes diamond (any other `lane` label triangle); `None`
/// otherwise. The precision is the label's last `/`-separated part when it has one.
pub fn precision_shape(label: &str) -> Option<Shape> {
    let l = label.to_ascii_lowercase();
    let last = l.rsplit('/').next().unwrap_or(&l);
    let has = |k: &str| last.contains(k);
    if has("x4") {
        Some(Shape::Diamond)
    } else if has("x8") || has("lane") {
        Some(Shape::Triangle)
    } else if has("f64") {
        Some(Shape::Square)
    } else if has("f32") {
        Some(Shape::Circle)
    } else {
        None
    }
}

/// A category label cut to 28 characters (with an ellipsis).
fn short(label: &str) -> String {
    if label.chars().count() > 28 {
        label.chars().take(27).collect::<String>() + "…"
    } else {
        label.to_string()
    }
}

fn err<E: std::fmt::Debug>(path: &Path) -> impl Fn(E) -> ReportError + '_ {
    move |e| ReportError::Chart(format!("{}: {e:?}", path.display()))
}

/// Write `chart` as an SVG of `size` pixels.
pub fn write_svg(path: &Path, chart: &Chart, size: (u32, u32)) -> Result<(), ReportError> {
    let e = err(path);
    let floor = chart.y_floor;
    let pts = chart.series.iter().flat_map(|s| s.points.iter()).filter(|p| p.y.is_finite() && p.x.is_finite());
    let ys: Vec<f64> = pts.clone().map(|p| lg(p.y, floor)).collect();
    let xs: Vec<f64> = match chart.x {
        XAxis::Log => pts.map(|p| lg(p.x, 1e-300)).collect(),
        XAxis::Categories(_) => pts.map(|p| p.x).collect(),
    };
    let (mut y0, mut y1) = ys.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &y| (a.min(y), b.max(y)));
    if !(y0.is_finite() && y1.is_finite()) {
        (y0, y1) = (floor.log10(), floor.log10() + 1.0);
    }
    let (y0, y1) = ((y0 - 0.3).floor(), (y1 + 0.3).ceil().max(y0.floor() + 1.0));
    let (x0, x1) = match &chart.x {
        XAxis::Log => {
            let (a, b) = xs.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| (a.min(x), b.max(x)));
            if a.is_finite() {
                ((a - 0.15).floor().min(a - 0.1), (b + 0.15).ceil().max(b + 0.1))
            } else {
                (0.0, 1.0)
            }
        }
        XAxis::Categories(c) => (-0.6, c.len() as f64 - 0.4),
    };
    let root = SVGBackend::new(path, size).into_drawing_area();
    root.fill(&WHITE).map_err(&e)?;
    let (plot, legend) = root.split_horizontally(size.0.saturating_sub(230));
    let mut cc = ChartBuilder::on(&plot)
        .caption(&chart.title, ("sans-serif", 18))
        .margin(12)
        .x_label_area_size(match &chart.x {
            XAxis::Log => 40,
            // Rotated labels of 12-px text: about 7 px per character, plus the axis title.
            XAxis::Categories(c) => 40 + 7 * c.iter().map(|l| short(l).chars().count()).max().unwrap_or(1) as u32,
        })
        .y_label_area_size(60)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(&e)?;
    let log_label = |v: &f64| {
        if (v - v.round()).abs() < 1e-9 {
            format!("1e{}", v.round() as i64)
        } else {
            String::new()
        }
    };
    let cats = match &chart.x {
        XAxis::Categories(c) => c.iter().map(|l| short(l)).collect(),
        XAxis::Log => Vec::new(),
    };
    let cat_label = |v: &f64| {
        let k = v.round();
        if (v - k).abs() < 1e-6 && k >= 0.0 && (k as usize) < cats.len() {
            cats[k as usize].clone()
        } else {
            String::new()
        }
    };
    {
        let mut mesh = cc.configure_mesh();
        mesh.x_desc(&chart.x_desc).y_desc(&chart.y_desc).y_labels((y1 - y0) as usize + 1).y_label_formatter(&log_label);
        match &chart.x {
            XAxis::Log => {
                mesh.x_labels((x1 - x0) as usize + 1).x_label_formatter(&log_label);
            }
            XAxis::Categories(c) => {
                mesh.x_labels(c.len() * 4 + 1)
                    .x_label_formatter(&cat_label)
                    .x_label_style(("sans-serif", 12).into_font().transform(FontTransform::Rotate90))
                    .disable_x_mesh();
            }
        }
        mesh.draw().map_err(&e)?;
    }
    let xmap = |x: f64| match chart.x {
        XAxis::Log => lg(x, 1e-300),
        XAxis::Categories(_) => x,
    };
    let mut placed: Vec<(i32, i32, i32)> = Vec::new(); // point-label boxes: x, y, width (px)
    for s in &chart.series {
        let c = color(s.color);
        let shape = precision_shape(&s.label);
        let pts: Vec<(f64, f64, &Pt, Option<&str>)> = s
            .points
            .iter()
            .filter(|p| p.x.is_finite() && !p.y.is_nan())
            .map(|p| {
                // +∞ at the top edge, values at or below the floor at the floor: both marked.
                let (y, mark) = if p.y == f64::INFINITY {
                    (y1, Some("∞"))
                } else if p.y <= floor {
                    (lg(p.y, floor), Some(if p.y == 0.0 { "0" } else { "≤floor" }))
                } else {
                    (lg(p.y, floor), None)
                };
                (xmap(p.x), y, p, mark)
            })
            .collect();
        if s.line && pts.len() > 1 {
            cc.draw_series(LineSeries::new(pts.iter().map(|&(x, y, _, _)| (x, y)), c.stroke_width(2))).map_err(&e)?;
        }
        for &(x, y, p, mark) in &pts {
            draw_marker(&mut cc, (x, y), p.marker, shape, c).map_err(&e)?;
            let text = match (mark, &p.text) {
                (Some(m), Some(t)) => Some(format!("{m} {t}")),
                (Some(m), None) => Some(m.to_string()),
                (None, t) => t.clone(),
            };
            if let Some(t) = text {
                // Move the label down (12 px at a time) until it overlaps no label placed before.
                let (px, mut py) = cc.backend_coord(&(x, y));
                let w = 6 * t.chars().count() as i32 + 4;
                for _ in 0..8 {
                    let hit = placed.iter().any(|&(qx, qy, qw)| px < qx + qw && qx < px + w && (py - qy).abs() < 11);
                    if !hit {
                        break;
                    }
                    py += 12;
                }
                placed.push((px, py, w));
                plot.draw(&Text::new(t, (px + 5, py - 5), ("sans-serif", 10).into_font().color(&c))).map_err(&e)?;
            }
        }
    }
    // Legend in its own area (plotters' series legend needs per-series draw handles; this is
    // simpler and never overlaps the data).
    // Rows shrink (to 12 px) when there are many series, so the legend fits beside the plot.
    let n = chart.series.len().max(1) as i32;
    let step = ((size.1 as i32 - 140) / n).clamp(12, 18);
    let mut yy = 30;
    for s in &chart.series {
        let c = color(s.color);
        let m = precision_shape(&s.label).map_or(Mark::Plain(Marker::Dot), Mark::Shape);
        draw_mark(&legend, (12, yy), m, c.filled()).map_err(&e)?;
        legend.draw(&Text::new(s.label.clone(), (24, yy - 6), ("sans-serif", 12).into_font())).map_err(&e)?;
        yy += step;
    }
    if let Some(n) = &chart.note {
        for line in n.lines() {
            yy += 4;
            legend.draw(&Text::new(line.to_string(), (6, yy), ("sans-serif", 11).into_font())).map_err(&e)?;
            yy += 14;
        }
    }
    root.present().map_err(&e)?;
    Ok(())
}

type Cc<'a, 'b> = ChartContext<
    'a,
    SVGBackend<'b>,
    Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
>;

/// What a marker looks like: a precision's shape, or a statistic's marker.
#[derive(Clone, Copy)]
enum Mark {
    Shape(Shape),
    Plain(Marker),
}

/// Draw mark `m` centred at pixel `p` of `area`.
fn draw_mark<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    p: (i32, i32),
    m: Mark,
    style: ShapeStyle,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    match m {
        Mark::Shape(Shape::Square) => area.draw(&Rectangle::new([(p.0 - 4, p.1 - 4), (p.0 + 4, p.1 + 4)], style)),
        Mark::Shape(Shape::Triangle) | Mark::Plain(Marker::Triangle) => area.draw(&TriangleMarker::new(p, 5, style)),
        Mark::Shape(Shape::Diamond) => {
            let d = [(p.0, p.1 - 6), (p.0 + 6, p.1), (p.0, p.1 + 6), (p.0 - 6, p.1)];
            if style.filled {
                area.draw(&Polygon::new(d.to_vec(), style))
            } else {
                area.draw(&PathElement::new(vec![d[0], d[1], d[2], d[3], d[0]], style))
            }
        }
        Mark::Shape(Shape::Circle) | Mark::Plain(Marker::Dot) => area.draw(&Circle::new(p, 4, style)),
        Mark::Plain(Marker::Cross) => area.draw(&Cross::new(p, 4, style)),
    }
}

/// One point's marker: the point's own marker (a statistic: dot, cross, triangle) for series
/// without a precision; for precision series the precision's shape, filled for a dot and
/// hollow for a cross (so both distinctions survive).
fn draw_marker(
    cc: &mut Cc<'_, '_>,
    at: (f64, f64),
    m: Marker,
    shape: Option<Shape>,
    c: RGBColor,
) -> Result<(), DrawingAreaErrorKind<std::io::Error>> {
    let style = if m == Marker::Cross { c.stroke_width(2) } else { c.filled() };
    let (px, py) = cc.backend_coord(&at);
    let area = cc.plotting_area().strip_coord_spec();
    let (ox, oy) = cc.plotting_area().get_base_pixel();
    draw_mark(&area, (px - ox, py - oy), shape.map_or(Mark::Plain(m), Mark::Shape), style)
}
