//! Shared helpers of the spline tests: random segments and rays, and an independent
//! dense-sampling oracle of the quadratic sphere sweep (f64).
#![allow(dead_code)]

pub mod thin;

use proptest::prelude::*;
use tubecast::QuadTube;
use tubecast::Solver;
use tubecast::V3;
pub use tubecast_oracle::QuadCrossing;
use tubecast_oracle::{quad_crossing, quad_hit_measure, Line, Quad, Vec3};

/// `p(t)`, `r(t)` of a quadratic Bézier tube, by the independent oracle (`tubecast-oracle`).
pub fn eval(b: &[[f64; 3]; 3], r: &[f64; 3], t: f64) -> ([f64; 3], f64) {
    let q = Quad::new(*b, *r);
    (q.point(t).to_array(), q.radius(t))
}

fn line(o: [f64; 3], d: [f64; 3]) -> Line {
    Line { o: Vec3::from(o), d: Vec3::from(d) }
}

/// The oracle: entry = min over t of the sphere entry, exit = max of the sphere exit, by
/// `n + 1` uniform samples and golden-section refinement around the best sample; `depth` is the
/// largest half chord `√(disc)/|d|` seen: how robust the hit is.
pub fn oracle(b: &[[f64; 3]; 3], r: &[f64; 3], o: [f64; 3], d: [f64; 3], n: usize) -> Option<QuadCrossing> {
    quad_crossing(&Quad::new(*b, *r), &line(o, d), n)
}

/// A random, validated quadratic tube of size ~1 near `centre`, radii in `[rmin, rmax]`.
pub fn tube_strategy(rmin: f64, rmax: f64) -> impl Strategy<Value = ([[f64; 3]; 3], [f64; 3])> {
    let p = || prop::array::uniform3(-1.0f64..1.0);
    (p(), p(), p(), prop::array::uniform3(rmin..rmax)).prop_map(|(a, b, c, r)| ([a, b, c], r))
}

/// A ray aimed at a random point near the segment, from distance ~5.
pub fn ray_strategy() -> impl Strategy<Value = ([f64; 3], [f64; 3])> {
    (prop::array::uniform3(-1.5f64..1.5), prop::array::uniform3(-1.0f64..1.0)).prop_filter_map(
        "direction",
        |(target, dir)| {
            let l = (dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]).sqrt();
            if l < 0.2 {
                return None;
            }
            let o = [target[0] - 5.0 * dir[0] / l, target[1] - 5.0 * dir[1] / l, target[2] - 5.0 * dir[2] / l];
            Some((o, dir))
        },
    )
}

/// Crate tube from arrays.
pub fn tube(b: &[[f64; 3]; 3], r: &[f64; 3]) -> QuadTube<f64> {
    QuadTube::new([V3::from(b[0]), V3::from(b[1]), V3::from(b[2])], *r).expect("valid tube")
}

/// Scale of a tube query: max control-point distance from b₀ plus max radius plus the
/// ray's distance to b₀ — the magnitude the ray-space coordinates can reach.
pub fn scale(b: &[[f64; 3]; 3], r: &[f64; 3]) -> f64 {
    let mut s: f64 = 0.0;
    for p in b {
        for k in 0..3 {
            s = s.max((p[k] - b[0][k]).abs());
        }
    }
    s * 3f64.sqrt() + r.iter().fold(0.0f64, |a, x| a.max(x.abs()))
}

/// Proptest config: `PROPTEST_CASES` (read by proptest itself) overrides `default`; the
/// defaults are small so that `cargo test` stays fast.
pub fn config(default: u32) -> ProptestConfig {
    let cases = std::env::var("PROPTEST_CASES").ok().and_then(|s| s.parse().ok()).unwrap_or(default);
    ProptestConfig {
        cases,
        max_global_rejects: 20 * cases + 1024,
        failure_persistence: None,
        ..ProptestConfig::default()
    }
}

/// Measure (in t) of the set of spheres the ray's line meets, by `n` uniform samples.
pub fn hit_measure(b: &[[f64; 3]; 3], r: &[f64; 3], o: [f64; 3], d: [f64; 3], n: usize) -> f64 {
    quad_hit_measure(&Quad::new(*b, *r), &line(o, d), n)
}

/// The solvers every spline property runs.
pub const SOLVERS: [Solver; 5] =
    [Solver::Polynomial, Solver::Itp, Solver::Newton, Solver::Bisection { iters: 40 }, Solver::Bisection { iters: 10 }];

/// Error bound on the ray-space entry/exit distance for a solver that locates critical points
/// to a few ulps of `t` (Polynomial, ITP, Newton, and bisection with ≥ 40 steps: 2⁻⁴⁰ in t,
/// whose effect at a critical point is ½|f''|·2⁻⁸⁰, negligible):
/// `g`'s coefficients are sums of ≤ 8 products of ray-space coordinates of size ≤ S, so
/// `g(t*)` carries an absolute error ≤ 64ε·S²; `√g` then errs by ≤ √(64ε)·S (worst case, at
/// a tangency) — this bound dominates; `h` errs by ≤ 8εS. In units of the ray parameter,
/// divide by |d| (the strategies use |d| ≥ 0.2 and unit-free targets; we compare `t·|d|`).
pub fn bound(eps: f64, s: f64) -> f64 {
    (64.0 * eps).sqrt() * s + 8.0 * eps * s
}

pub fn norm(v: [f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}
