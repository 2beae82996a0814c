//! The a-posteriori bound on how far each triangle strays from the union's surface, from the
//! convexity of every tube's exact SDF `fᵢ` (a round cone is convex, and so is its signed
//! distance, inside and out), with `f = minᵢ fᵢ`:
//!
//! - **out** (`f > 0`): `f(p) ≤ fᵢ(p) ≤ maxⱼ fᵢ(vⱼ)` for any tube `i` and any point `p` of the
//!   triangle `v₀v₁v₂`, so `f ≤ bₜ = minᵢ maxⱼ fᵢ(vⱼ)` on it (≤ 0 when one tube holds all
//!   three corners: the triangle is then inside the union).
//! - **in** (`f < 0`): a convex function lies above its tangent planes, so with `gᵢ` the
//!   (sub)gradient of `fᵢ` at the centroid `c`, `fᵢ(p) ≥ fᵢ(c) + gᵢ·(p − c) ≥ fᵢ(c) +
//!   minⱼ gᵢ·(vⱼ − c)` (linear on the triangle: least at a corner). Tubes with
//!   `fᵢ(c) > R = maxⱼ |vⱼ − c|` are positive on the whole triangle and can only raise `f`.
//!   So `f ≥ −aₜ` with `aₜ = max(0, −minᵢ(...))`; second order in the triangle's size where
//!   its corners are on one tube (the tangent plane at `c` is then close to the triangle's).

use super::field::{gradient, Field};
use super::grid::Raw;
use tubecast::{Primitive, V3};

/// The largest excursions over the mesh: `depth = maxₜ aₜ`, `out = maxₜ max(bₜ, 0)`, and the
/// number of triangles with `bₜ > 0` beyond rounding.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Excursion {
    pub depth: f64,
    pub out: f64,
    pub outside: usize,
}

/// Measures every triangle of `raw`.
pub(super) fn excursion(field: &Field, raw: &Raw) -> Excursion {
    let mut e = Excursion::default();
    let all: Vec<u32> = (0..field.tubes.len() as u32).collect();
    for t in &raw.triangles {
        let p = t.map(|i| raw.positions[i as usize]);
        let c = (p[0] + p[1] + p[2]) * (1.0 / 3.0);
        let r = p.iter().map(|&v| (v - c).length()).fold(0.0, f64::max);
        // `near` holds every tube with fᵢ < reach somewhere in c's cell; a triangle wider
        // than the reach (never expected) is measured against every tube.
        let tubes = match field.near(c) {
            Some(ts) if r < field.reach => ts,
            _ => &all[..],
        };
        let (a, b) = triangle(field, tubes, p, c, r);
        e.depth = e.depth.max(a);
        e.out = e.out.max(b);
        if b > super::crease::ON * field.h {
            e.outside += 1;
        }
    }
    e
}

/// `(aₜ, max(bₜ, 0))` of one triangle against `tubes`.
fn triangle(field: &Field, tubes: &[u32], p: [V3<f64>; 3], c: V3<f64>, r: f64) -> (f64, f64) {
    let mut b = f64::INFINITY;
    let mut lower = 0.0f64;
    for &k in tubes {
        let t = &field.tubes[k as usize];
        let fv = p.map(|v| t.sdf(v));
        b = b.min(fv[0].max(fv[1]).max(fv[2]));
        let fc = t.sdf(c);
        if fc - r > 0.0 {
            continue;
        }
        let g = gradient(t, c);
        let lin = p.iter().map(|&v| g.dot(v - c)).fold(f64::INFINITY, f64::min);
        lower = lower.min(fc + lin);
    }
    // No tube near: every fᵢ ≥ reach at the corners (cannot happen for a contoured triangle).
    let b = if b.is_finite() { b } else { field.reach };
    (-lower, b.max(0.0))
}
