//! Cubic Hermite → two quadratic Béziers (Russig §3.2): C¹ junction, end conditions,
//! exactness for straight segments, and the model error (reported).

mod common_spline;
use common_spline::*;
use proptest::prelude::*;
use tubecast::HermiteSegment;
use tubecast::Solver;
use tubecast::{Primitive, Ray, RoundCone, V3};

fn v(a: [f64; 3]) -> V3<f64> {
    V3::from(a)
}

fn seg_strategy() -> impl Strategy<Value = HermiteSegment<f64>> {
    let p = || prop::array::uniform3(-1.0f64..1.0);
    (p(), p(), p(), p(), 0.2f64..0.6, -0.3f64..0.3, 0.2f64..0.6, -0.3f64..0.3)
        .prop_map(|(a, ma, b, mb, r0, d0, r1, d1)| HermiteSegment::new(v(a), v(ma), r0, d0, v(b), v(mb), r1, d1))
}

proptest! {
    #![proptest_config(config(256))]

    /// Positions, radii and first derivatives agree at the junction (C¹), to rounding
    /// (a few operations on size-3 numbers: 1e-14); the ends interpolate the nodes and the
    /// end tangents are the node tangents scaled by 2/3 (2(a₂ − a₁) = 2m₀/3).
    #[test]
    fn split_is_c1(s in seg_strategy()) {
        let [a, b] = s.split().unwrap();
        let tol = 1e-14;
        prop_assert!((a.point(1.0) - b.point(0.0)).max_abs() <= tol);
        prop_assert!((a.radius(1.0) - b.radius(0.0)).abs() <= tol);
        prop_assert!((a.tangent(1.0) - b.tangent(0.0)).max_abs() <= tol);
        prop_assert!((a.radius_deriv(1.0) - b.radius_deriv(0.0)).abs() <= tol);
        prop_assert!((a.point(0.0) - s.p0).max_abs() <= tol && (b.point(1.0) - s.p1).max_abs() <= tol);
        prop_assert!((a.tangent(0.0) - s.m0 * (2.0 / 3.0)).max_abs() <= tol);
        prop_assert!((b.tangent(1.0) - s.m1 * (2.0 / 3.0)).max_abs() <= tol);
        prop_assert!((a.radius_deriv(0.0) - s.dr0 * (2.0 / 3.0)).abs() <= tol);
    }

    /// A straight Hermite segment (tangents = chord, radius derivatives = radius change) splits
    /// into the same sweep as the round cone: hulls of the two halves match RoundCone.
    #[test]
    fn straight_split_is_the_link(a in prop::array::uniform3(-1.0f64..1.0), b in prop::array::uniform3(-1.0f64..1.0),
                                  r0 in 0.05f64..0.6, r1 in 0.05f64..0.6, (o, d) in ray_strategy()) {
        let ch = v(b) - v(a);
        let s = HermiteSegment::new(v(a), ch, r0, r1 - r0, v(b), ch, r1, r1 - r0);
        let [p, q] = s.split().unwrap();
        let ray = Ray::new(v(o), v(d));
        let iv = p.intersect_with(&ray, Solver::Polynomial).hull(q.intersect_with(&ray, Solver::Polynomial));
        let link = RoundCone::new(v(a), r0, v(b), r1).unwrap().intersect(&ray);
        if link.hit && link.t_out - link.t_in > 1e-3 {
            // Both are exact to √(64ε)·S (tests/spline_kernel.rs), S ≤ 6.
            let tol = 2.0 * (64.0 * f64::EPSILON).sqrt() * 6.0;
            prop_assert!(iv.hit);
            prop_assert!((iv.t_in - link.t_in).abs() * d_len(d) <= tol && (iv.t_out - link.t_out).abs() * d_len(d) <= tol);
        }
    }
}

fn d_len(d: [f64; 3]) -> f64 {
    (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
}

/// Distance in (position, radius) space from a point of one curve to the other curve
/// (dense samples): the sphere sweeps are at most this far apart (a sphere moved by δp
/// and grown by δr stays within |δp| + |δr|).
fn curve_dist(pt: (V3<f64>, f64), other: &dyn Fn(f64) -> (V3<f64>, f64), n: usize) -> f64 {
    (0..=n)
        .map(|k| {
            let (q, r) = other(k as f64 / n as f64);
            (pt.0 - q).length() + (pt.1 - r).abs()
        })
        .fold(f64::INFINITY, f64::min)
}

/// Reported figure: the (one-sided-both-ways) Hausdorff distance between the cubic Hermite
/// (p, r) curve and the quadratic pair, relative to the chord length. It is zero for the
/// straight segment, and bounded by the diameter of the cubic's Bézier control polygon (both
/// curves lie in its convex hull; the pair's control points are hull points).
#[test]
fn model_error_report() {
    use proptest::strategy::ValueTree;
    use proptest::test_runner::TestRunner;
    let mut runner = TestRunner::deterministic();
    let strat = seg_strategy();
    let mut rel = Vec::new();
    for _ in 0..300 {
        let s = strat.new_tree(&mut runner).unwrap().current();
        let [a, b] = s.split().unwrap();
        let cubic = |t: f64| (s.point(t), s.radius(t));
        let pair = |t: f64| {
            if t < 0.5 {
                (a.point(2.0 * t), a.radius(2.0 * t))
            } else {
                (b.point(2.0 * t - 1.0), b.radius(2.0 * t - 1.0))
            }
        };
        let n = 400;
        let mut h: f64 = 0.0;
        for k in 0..=n {
            let t = k as f64 / n as f64;
            h = h.max(curve_dist(cubic(t), &pair, n)).max(curve_dist(pair(t), &cubic, n));
        }
        let c = [s.p0, s.p0 + s.m0 * (1.0 / 3.0), s.p1 - s.m1 * (1.0 / 3.0), s.p1];
        let cr = [s.r0, s.r0 + s.dr0 / 3.0, s.r1 - s.dr1 / 3.0, s.r1];
        let mut diam: f64 = 0.0;
        for i in 0..4 {
            for j in 0..4 {
                diam = diam.max((c[i] - c[j]).length() + (cr[i] - cr[j]).abs());
            }
        }
        assert!(h <= diam + 1e-12, "model error {h} exceeds the control-polygon diameter {diam}");
        rel.push(h / (s.p1 - s.p0).length().max(1e-9));
    }
    rel.sort_by(f64::total_cmp);
    eprintln!(
        "Hermite vs quadratic pair, distance/chord: median {:.4}, p90 {:.4}, max {:.4}",
        rel[150], rel[270], rel[299]
    );
    // Straight segment: zero model error (same sweep).
    let s = HermiteSegment::new(
        v([0.0; 3]),
        v([1.0, 2.0, 0.0]),
        0.3,
        0.1,
        v([1.0, 2.0, 0.0]),
        v([1.0, 2.0, 0.0]),
        0.4,
        0.1,
    );
    let [a, b] = s.split().unwrap();
    for k in 0..=100 {
        let t = k as f64 / 100.0;
        let pair = |u: f64| {
            if u < 0.5 {
                (a.point(2.0 * u), a.radius(2.0 * u))
            } else {
                (b.point(2.0 * u - 1.0), b.radius(2.0 * u - 1.0))
            }
        };
        assert!(curve_dist((s.point(t), s.radius(t)), &pair, 2000) < 2e-3); // sampling step of the straight pair ≤ 2.3/2000 + 0.1/2000
    }
}

/// Bad input: a Hermite segment whose split has a negative radius is rejected.
#[test]
fn negative_sub_radius_rejected() {
    let s = HermiteSegment::new(
        v([0.0; 3]),
        v([1.0, 0.0, 0.0]),
        0.1,
        -3.0,
        v([1.0, 0.0, 0.0]),
        v([1.0, 0.0, 0.0]),
        0.1,
        3.0,
    );
    assert_eq!(s.split(), Err(tubecast::GeometryError::NegativeRadius));
    let s = HermiteSegment::new(
        v([0.0; 3]),
        v([f64::NAN, 0.0, 0.0]),
        0.1,
        0.0,
        v([1.0, 0.0, 0.0]),
        v([1.0, 0.0, 0.0]),
        0.1,
        0.0,
    );
    assert!(matches!(s.split(), Err(tubecast::GeometryError::NonFinite { .. })));
}
