//! The spline oracle: a quadratic Bézier tube is the sphere sweep `⋃_{t∈[0,1]} B(p(t), r(t))`
//! with `p`, `r` quadratic Bézier curves, in `f64`. Unlike a link it is not convex in `t`, so
//! the oracle samples densely and refines by golden section around the best sample: entry
//! `min_t` of the sphere entries, exit `max_t` of the exits, gap `min_t dist(line, p(t)) − r(t)`.
//! A refinement that finds nothing better than its sample keeps the sample, so a sampled oracle
//! is never worse than its samples.

use crate::minimise::golden_min;
use crate::vec::{line_dist, sphere_crossing, Line, Vec3};

/// A quadratic Bézier tube: control points `b` and control radii `r`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Quad {
    /// Control points.
    pub b: [Vec3; 3],
    /// Control radii.
    pub r: [f64; 3],
}

impl Quad {
    /// From plain arrays.
    pub fn new(b: [[f64; 3]; 3], r: [f64; 3]) -> Self {
        Self { b: b.map(Vec3::from), r }
    }
    /// Centre `p(t) = b₀·(1−t)² + b₁·2(1−t)t + b₂·t²` (Bernstein weights, summed left to right).
    pub fn point(&self, t: f64) -> Vec3 {
        let s = 1.0 - t;
        let (w0, w1, w2) = (s * s, 2.0 * s * t, t * t);
        self.b[0] * w0 + self.b[1] * w1 + self.b[2] * w2
    }
    /// Radius `r(t) = r₀·(1−t)·(1−t) + r₁·(2(1−t)t) + r₂·t·t` (multiplied in that order: the
    /// report's committed numbers use it).
    pub fn radius(&self, t: f64) -> f64 {
        let s = 1.0 - t;
        self.r[0] * s * s + self.r[1] * (2.0 * s * t) + self.r[2] * t * t
    }
}

/// Where a line crosses a sampled sweep ([`quad_crossing`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QuadCrossing {
    /// Entry `t` (along the line).
    pub t_in: f64,
    /// Curve parameter at entry.
    pub u_in: f64,
    /// Exit `t`.
    pub t_out: f64,
    /// Curve parameter at exit.
    pub u_out: f64,
    /// The largest half chord `√(disc)/|d|` among the sampled spheres: how robust the hit is.
    pub depth: f64,
}

/// Golden-section refinement of a sampled minimum `v` at sample `k` of `n` over the two sample
/// spacings around it (clipped to `[0, 1]`): `(argmin, min)`, the sample itself unless the
/// refinement is lower.
fn refine(f: &dyn Fn(f64) -> f64, k: usize, n: usize, v: f64) -> (f64, f64) {
    let lo = (k as f64 - 1.0) / n as f64;
    let hi = (k as f64 + 1.0) / n as f64;
    let (u, w) = golden_min(f, lo.max(0.0), hi.min(1.0));
    if w < v {
        (u, w)
    } else {
        (k as f64 / n as f64, v)
    }
}

/// Entry and exit of the line through the sweep, from `n + 1` uniform samples of `t` refined by
/// golden section; `None` if no sampled sphere meets the line.
pub fn quad_crossing(q: &Quad, line: &Line, n: usize) -> Option<QuadCrossing> {
    let sph = |t: f64| {
        let t = t.clamp(0.0, 1.0);
        sphere_crossing(line, q.point(t), q.radius(t))
    };
    let tin = |t: f64| sph(t).map_or(f64::INFINITY, |s| s.0);
    let tout = |t: f64| sph(t).map_or(f64::INFINITY, |s| -s.1);
    let (mut bi, mut bo) = ((0usize, f64::INFINITY), (0usize, f64::INFINITY));
    let mut depth: f64 = -1.0;
    for k in 0..=n {
        if let Some((a, b)) = sph(k as f64 / n as f64) {
            depth = depth.max((b - a) * 0.5);
            if a < bi.1 {
                bi = (k, a);
            }
            if -b < bo.1 {
                bo = (k, -b);
            }
        }
    }
    if !(bi.1.is_finite() && bo.1.is_finite()) {
        return None;
    }
    let (u_in, t_in) = refine(&tin, bi.0, n, bi.1);
    let (u_out, t_out) = refine(&tout, bo.0, n, bo.1);
    Some(QuadCrossing { t_in, u_in, t_out: -t_out, u_out, depth })
}

/// The sweep's signed gap to the line, `min_t dist(line, p(t)) − r(t)`, from `n + 1` samples
/// refined by golden section.
pub fn quad_gap(q: &Quad, line: &Line, n: usize) -> f64 {
    let gapf = |t: f64| line_dist(line, q.point(t)) - q.radius(t);
    let mut best = (0usize, f64::INFINITY);
    for k in 0..=n {
        let g = gapf(k as f64 / n as f64);
        if g < best.1 {
            best = (k, g);
        }
    }
    refine(&gapf, best.0, n, best.1).1
}

/// Fraction of `n + 1` uniformly sampled spheres that the line meets.
pub fn quad_hit_measure(q: &Quad, line: &Line, n: usize) -> f64 {
    let t = |k: usize| k as f64 / n as f64;
    let hits = (0..=n).filter(|&k| sphere_crossing(line, q.point(t(k)), q.radius(t(k))).is_some()).count();
    hits as f64 / (n + 1) as f64
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::link::{line_gap, line_interval, Link};

    #[test]
    fn point_and_radius_are_the_bernstein_forms() {
        let q = Quad::new([[0.0, 0.0, 0.0], [1.0, 2.0, 0.0], [2.0, 0.0, 0.0]], [1.0, 3.0, 2.0]);
        // t = ½: weights ¼, ½, ¼ → p = (1, 1, 0), r = ¼ + 3/2 + ½ = 2.25 (all exact in binary).
        assert_eq!(q.point(0.5), Vec3::new(1.0, 1.0, 0.0));
        assert_eq!(q.radius(0.5), 2.25);
        assert_eq!((q.point(0.0), q.radius(1.0)), (Vec3::default(), 2.0));
    }

    #[test]
    fn a_straight_spline_equals_the_link_oracle() {
        // b₁, r₁ at the midpoints: the same sweep as the link, at the same speed.
        let l = Link { a: Vec3::new(-1.0, 0.2, 0.1), ra: 0.3, b: Vec3::new(2.0, -0.4, 0.5), rb: 0.7 };
        let q = Quad { b: [l.a, l.p_at(0.5), l.b], r: [l.ra, l.r_at(0.5), l.rb] };
        for (o, d) in [([0.3, -4.0, 0.2], [0.1, 1.0, 0.05]), ([-5.0, 0.0, 0.3], [1.0, 0.02, 0.0])] {
            let line = Line { o: Vec3::from(o), d: Vec3::from(d) };
            let want = line_interval(&l, &line).expect("the link oracle hits");
            let got = quad_crossing(&q, &line, 1024).expect("the spline oracle hits");
            // Both refine a smooth extremum by golden section to rounding of the value; the
            // spline's p(t), r(t) differ from the link's by a few ulps of the size (~3):
            // 1e-12 is ~1000 ulps of slack.
            assert!((got.t_in - want.t_in).abs() < 1e-12, "{got:?} vs {want:?}");
            assert!((got.t_out - want.t_out).abs() < 1e-12, "{got:?} vs {want:?}");
            assert!((quad_gap(&q, &line, 1024) - line_gap(&l, &line).0).abs() < 1e-12);
            assert!(quad_hit_measure(&q, &line, 1024) > 0.0);
        }
        let far = Line { o: Vec3::new(0.0, 5.0, 0.0), d: Vec3::new(1.0, 0.0, 0.0) };
        assert!(quad_crossing(&q, &far, 1024).is_none());
        assert_eq!(quad_hit_measure(&q, &far, 1024), 0.0);
    }

    #[test]
    fn a_bent_tube_of_equal_radii_is_crossed_where_the_circle_says() {
        // Axis-aligned line through the apex region of a symmetric arch p(t) = (2t, 4t(1−t), 0)
        // of radius 0.5: the line x = 1 (vertical) crosses the apex p(½) = (1, 1, 0) region;
        // its exit is the top of the apex sphere, y = 1.5 (the highest sweep point: p_y ≤ 1,
        // with equality only at t = ½).
        let q = Quad::new([[0.0, 0.0, 0.0], [1.0, 2.0, 0.0], [2.0, 0.0, 0.0]], [0.5, 0.5, 0.5]);
        let line = Line { o: Vec3::new(1.0, -3.0, 0.0), d: Vec3::new(0.0, 1.0, 0.0) };
        let c = quad_crossing(&q, &line, 1024).expect("hits");
        assert!((c.t_out - 4.5).abs() < 1e-12 && (c.u_out - 0.5).abs() < 1e-6, "{c:?}");
        assert!((c.depth - 0.5).abs() < 1e-12, "{c:?}");
    }
}
