//! Surface colours: by direction, radius, SWC type, data values or one colour.

use super::ColorBy;
use crate::scene::fit::RunIndex;
use crate::scene::{Prim, Scene};
use std::sync::OnceLock;

/// Per-scene colour lookups.
pub(super) struct Palette {
    r_lo: f64,
    r_hi: f64,
    /// Finite range of the scene's data values.
    v_range: Option<(f64, f64)>,
    /// The runs of links fitted spline pieces replace, built on the first such piece coloured
    /// by data.
    runs: OnceLock<RunIndex>,
}

fn colormap(x: f64) -> [f32; 3] {
    // Blue → teal → yellow, piecewise linear in three stops.
    let stops = [[0.15, 0.2, 0.75], [0.1, 0.7, 0.6], [0.98, 0.85, 0.15]];
    let x = x.clamp(0.0, 1.0) * 2.0;
    let i = (x as usize).min(1);
    let f = (x - i as f64) as f32;
    std::array::from_fn(|k| stops[i][k] * (1.0 - f) + stops[i + 1][k] * f)
}

fn type_color(t: i32) -> [f32; 3] {
    match t {
        1 => [0.9, 0.9, 0.9],
        2 => [0.25, 0.45, 0.95],
        3 => [0.9, 0.25, 0.2],
        4 => [0.85, 0.25, 0.85],
        _ => {
            let pal = [[0.3, 0.75, 0.3], [0.95, 0.6, 0.1], [0.4, 0.8, 0.85], [0.6, 0.5, 0.3]];
            pal[t.unsigned_abs() as usize % pal.len()]
        }
    }
}

impl Palette {
    pub(super) fn new(scene: &Scene) -> Self {
        let (mut r_lo, mut r_hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for r in (0..scene.nodes.len()).map(|i| scene.radius(i)) {
            r_lo = r_lo.min(r);
            r_hi = r_hi.max(r);
        }
        Self { r_lo, r_hi, v_range: super::value_range(&scene.values), runs: OnceLock::new() }
    }
    /// Colour of primitive `prim` at its curve parameter `u`, and its coverage in `[0, 1]`:
    /// the scene's coverage where thin tubes were widened ([`super::clamp_thin`]), interpolated
    /// along the link, 1 elsewhere. The renderer treats the coverage as an opacity.
    pub(super) fn color(&self, scene: &Scene, by: ColorBy, prim: &Prim, u: f64) -> ([f32; 3], f32) {
        let c = self.base_color(scene, by, prim, u);
        let l = scene.links.get(prim.link as usize);
        match (scene.coverage.get(l[0] as usize), scene.coverage.get(l[1] as usize)) {
            (Some(&a), Some(&b)) => {
                let t = u.clamp(0.0, 1.0) as f32;
                (c, (a + (b - a) * t).clamp(0.0, 1.0))
            }
            _ => (c, 1.0),
        }
    }

    fn base_color(&self, scene: &Scene, by: ColorBy, prim: &Prim, u: f64) -> [f32; 3] {
        let link = prim.link;
        let l = scene.links.get(link as usize);
        let spline = prim.quad().map(|q| q.cast::<f64>());
        match by {
            ColorBy::Solid(c) => c,
            ColorBy::Direction => {
                // Spline: the curve's tangent at u; link: the link's direction.
                let d = if let Some(q) = spline {
                    q.tangent(u).normalize_or_zero().to_array()
                } else {
                    scene.link_direction(link as usize)
                };
                if d == [0.0; 3] {
                    [0.6, 0.6, 0.6]
                } else {
                    d.map(|v| v.abs() as f32)
                }
            }
            ColorBy::Radius => {
                let r = if let Some(q) = spline {
                    q.radius(u)
                } else {
                    let (a, b) = (scene.radius(l[0] as usize), scene.radius(l[1] as usize));
                    a + (b - a) * u
                };
                let span = self.r_hi - self.r_lo;
                colormap(if span > 0.0 { (r - self.r_lo) / span } else { 0.5 })
            }
            ColorBy::Type => type_color(scene.kind(l[1] as usize)),
            ColorBy::Values(map) => {
                let (Some((lo, hi)), Some(&a), Some(&b)) =
                    (self.v_range, scene.values.get(l[0] as usize), scene.values.get(l[1] as usize))
                else {
                    return [0.5; 3];
                };
                // A fitted spline piece interpolates the data of the whole run it replaces.
                let run = spline.and_then(|_| self.runs.get_or_init(|| RunIndex::new(scene)).value(scene, prim, u));
                let v = run.unwrap_or(a + (b - a) * u.clamp(0.0, 1.0));
                if !v.is_finite() {
                    return [0.5; 3];
                }
                map.linear(if hi > lo { (v - lo) / (hi - lo) } else { 0.5 })
            }
        }
    }
}
