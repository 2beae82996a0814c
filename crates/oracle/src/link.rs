//! The link oracle: a link is the sphere sweep `⋃_{u∈[0,1]} B(p(u), r(u))` with `p`, `r`
//! linear, in `f64`.
//!
//! * [`sweep_dist`]`(x)`: `min_u |x − p(u)| − r(u)`. The function of `u` is convex (a norm of an
//!   affine map minus a linear one), so bisection on the sign of its derivative finds the global
//!   minimum. Outside the solid it is the exact Euclidean distance; its zero set is the surface;
//!   its gradient is `(x − p(u*))/|x − p(u*)|` (envelope theorem), the outward normal.
//! * [`line_gap`]`(line)`: `min_u dist(line, p(u)) − r(u)`, also convex in `u`: the signed
//!   distance of the line to the solid (< 0: the line enters it).
//! * [`line_interval`]`(line)`: the line enters the union when it enters one of its spheres, so
//!   `t_in = min_u t_in(u)` and `t_out = max_u t_out(u)` over the `u` where the line meets
//!   `B(p(u), r(u))` — an interval `[u0, u1]` (a sublevel set of the convex `line_gap`
//!   integrand), found by bisection; the min/max over it by dense sampling plus golden-section
//!   refinement.

use crate::minimise::{convex_argmin, golden_min};
use crate::vec::{line_dist, sphere_crossing, Line, Vec3};

/// A link: the sweep of `B(a, ra)` to `B(b, rb)` (radii ≥ 0).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Link {
    /// First centre.
    pub a: Vec3,
    /// First radius.
    pub ra: f64,
    /// Second centre.
    pub b: Vec3,
    /// Second radius.
    pub rb: f64,
}

impl Link {
    /// Centre `p(u) = a + (b − a)·u`.
    pub fn p_at(&self, u: f64) -> Vec3 {
        self.a + (self.b - self.a) * u
    }
    /// Radius `r(u) = ra + (rb − ra)·u`.
    pub fn r_at(&self, u: f64) -> f64 {
        self.ra + (self.rb - self.ra) * u
    }
}

/// `(min_u |x − p(u)| − r(u), argmin u)`: the exact distance outside the link.
pub fn sweep_dist(l: &Link, x: Vec3) -> (f64, f64) {
    // f(u) = |x − p(u)| − r(u); f'(u) = −(x − p(u))·v/|x − p(u)| − (rb − ra).
    let v = l.b - l.a;
    let dr = l.rb - l.ra;
    let u = convex_argmin(|u| {
        let w = x - l.p_at(u);
        let n = w.length();
        if n == 0.0 {
            return 0.0;
        }
        -w.dot(v) / n - dr
    });
    ((x - l.p_at(u)).length() - l.r_at(u), u)
}

/// Outward unit normal of the link's surface at (or near) `x` (NaN at the centre line).
pub fn sweep_normal(l: &Link, x: Vec3) -> Vec3 {
    let (_, u) = sweep_dist(l, x);
    let g = x - l.p_at(u);
    g * (1.0 / g.length())
}

/// `(gap, argmin u)`: the link's signed distance from the line (negative: the line enters the
/// solid), by golden section on the convex `u ↦ dist(line, p(u)) − r(u)`.
pub fn line_gap(l: &Link, line: &Line) -> (f64, f64) {
    let (u, v) = golden_min(|u| line_dist(line, l.p_at(u)) - l.r_at(u), 0.0, 1.0);
    (v, u)
}

/// Where a line crosses a sweep: entry and exit `t` and the curve parameters of the spheres
/// that give them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Crossing {
    /// Entry `t`.
    pub t_in: f64,
    /// Curve parameter at entry.
    pub u_in: f64,
    /// Exit `t`.
    pub t_out: f64,
    /// Curve parameter at exit.
    pub u_out: f64,
}

/// The oracle line interval, if the line meets the link (and both ends are finite).
pub fn line_interval(l: &Link, line: &Line) -> Option<Crossing> {
    let (gap, us) = line_gap(l, line);
    if gap > 0.0 {
        return None;
    }
    // [u0, u1] = {u : line_dist(p(u)) ≤ r(u)} by bisection from the argmin outwards.
    let inside = |u: f64| line_dist(line, l.p_at(u)) - l.r_at(u) <= 0.0;
    let edge = |from: f64, to: f64| {
        if inside(to) {
            return to;
        }
        let (mut a, mut b) = (from, to);
        for _ in 0..100 {
            let m = 0.5 * (a + b);
            if inside(m) {
                a = m
            } else {
                b = m
            }
        }
        a
    };
    let (u0, u1) = (edge(us, 0.0), edge(us, 1.0));
    let ts = |u: f64| {
        let u = u.clamp(u0, u1);
        sphere_crossing(line, l.p_at(u), l.r_at(u))
    };
    let tin = |u: f64| ts(u).map_or(f64::INFINITY, |s| s.0);
    let tout = |u: f64| ts(u).map_or(f64::INFINITY, |s| -s.1);
    let refine = |f: &dyn Fn(f64) -> f64| {
        let n = 64;
        let mut best = (us, f(us));
        for i in 0..=n {
            let u = u0 + (u1 - u0) * i as f64 / n as f64;
            let v = f(u);
            if v < best.1 {
                best = (u, v);
            }
        }
        let w = (u1 - u0) / n as f64;
        let (u, v) = golden_min(f, (best.0 - w).max(u0), (best.0 + w).min(u1));
        if v < best.1 {
            (u, v)
        } else {
            best
        }
    };
    let (u_in, ti) = refine(&tin);
    let (u_out, to) = refine(&tout);
    if !(ti.is_finite() && to.is_finite()) {
        return None;
    }
    Some(Crossing { t_in: ti, u_in, t_out: -to, u_out })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64, tol: f64) -> bool {
        (a - b).abs() <= tol
    }

    /// A cylinder of radius 1 along x from 0 to 4 (with its round caps).
    const CYL: Link = Link { a: Vec3::new(0.0, 0.0, 0.0), ra: 1.0, b: Vec3::new(4.0, 0.0, 0.0), rb: 1.0 };

    #[test]
    fn sweep_dist_of_a_cylinder_is_the_distance_to_its_axis_minus_one() {
        // Beside the body: distance to the axis − 1, at the foot of the perpendicular.
        let (d, u) = sweep_dist(&CYL, Vec3::new(1.0, 3.0, 4.0));
        assert!(close(d, 4.0, 4.0 * f64::EPSILON) && close(u, 0.25, 4.0 * f64::EPSILON), "{d} {u}");
        // Beyond a cap: distance to the end centre − 1.
        let (d, u) = sweep_dist(&CYL, Vec3::new(7.0, 4.0, 0.0));
        assert!(close(d, 4.0, 4.0 * f64::EPSILON) && u == 1.0, "{d} {u}");
        let n = sweep_normal(&CYL, Vec3::new(1.0, 3.0, 4.0));
        assert!(close(n.y, 0.6, 4.0 * f64::EPSILON) && close(n.z, 0.8, 4.0 * f64::EPSILON) && n.x.abs() < 1e-15);
    }

    #[test]
    fn sweep_dist_of_a_cone_matches_the_tangent_cone_formula() {
        // ra = 2 at x = 0, rb = 1 at x = 4: sin θ = (ra − rb)/L = 1/4. A point at radial
        // distance ρ over axial position x on the cone part is at distance
        // (ρ − (ra − x·tanθ))·cos θ … written via the generator: d = ρ·cos θ + x·sin θ − ra,
        // with cos θ = √15/4 (the tangent-plane form of the stump's SDF).
        let l = Link { a: Vec3::default(), ra: 2.0, b: Vec3::new(4.0, 0.0, 0.0), rb: 1.0 };
        let (x, rho) = (2.0, 5.0);
        let (s, c) = (0.25, 15f64.sqrt() / 4.0);
        let want = rho * c + x * s - 2.0;
        let (d, _) = sweep_dist(&l, Vec3::new(x, rho, 0.0));
        assert!(close(d, want, 16.0 * f64::EPSILON), "{d} vs {want}");
    }

    #[test]
    fn line_interval_of_a_cylinder_is_the_closed_form() {
        // Across the body: y = 0.6 at x = 2 meets the unit circle at z = ±0.8.
        let line = Line { o: Vec3::new(2.0, 0.6, -5.0), d: Vec3::new(0.0, 0.0, 2.0) };
        let c = line_interval(&CYL, &line).expect("hits");
        let tol = 1e-12;
        assert!(close(c.t_in, 2.1, tol) && close(c.t_out, 2.9, tol), "{c:?}");
        assert!(close(line_gap(&CYL, &line).0, -0.4, 1e-12));
        // Along the axis: enters the cap at x = −1, leaves at x = 5.
        let line = Line { o: Vec3::new(-3.0, 0.0, 0.0), d: Vec3::new(1.0, 0.0, 0.0) };
        let c = line_interval(&CYL, &line).expect("hits");
        assert!(close(c.t_in, 2.0, tol) && close(c.t_out, 8.0, tol), "{c:?}");
        assert!(c.u_in == 0.0 && c.u_out == 1.0, "{c:?}");
        // A line 1e-9 beyond the surface misses.
        let line = Line { o: Vec3::new(2.0, 1.0 + 1e-9, -5.0), d: Vec3::new(0.0, 0.0, 1.0) };
        assert!(line_interval(&CYL, &line).is_none());
        assert!(close(line_gap(&CYL, &line).0, 1e-9, 1e-15));
    }
}
