//! Cubic Hermite → two quadratic Béziers (Russig §3.2): C¹ junction, end conditions,
//! exactness for straight segments, and the model error (reported).

use super::common::*;
use proptest::prelude::*;
use tubecast::Solver;
use tubecast::{HermiteEnd, HermiteSegment};
use tubecast::{Primitive, Ray, RoundCone, V3};

fn v(a: [f64; 3]) -> V3<f64> {
    V3::from(a)
}

fn seg_strategy() -> impl Strategy<Value = HermiteSegment<f64>> {
    let p = || prop::array::uniform3(-1.0f64..1.0);
    (p(), p(), p(), p(), 0.2f64..0.6, -0.3f64..0.3, 0.2f64..0.6, -0.3f64..0.3).prop_map(
        |(a, ma, b, mb, r0, d0, r1, d1)| {
            HermiteSegment::from_ends(
                HermiteEnd { p: v(a), tangent: v(ma), r: r0, dr: d0 },
                HermiteEnd { p: v(b), tangent: v(mb), r: r1, dr: d1 },
            )
        },
    )
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
        let s = HermiteSegment::from_ends(
            HermiteEnd { p: v(a), tangent: ch, r: r0, dr: r1 - r0 },
            HermiteEnd { p: v(b), tangent: ch, r: r1, dr: r1 - r0 },
        );
        let [p, q] = s.split().unwrap();
        let ray = Ray::new(v(o), v(d));
        let iv = p.intersect_with(&ray, Solver::Polynomial).hull(q.intersect_with(&ray, Solver::Polynomial));
        let link = RoundCone::new(v(a), r0, v(b), r1).unwrap().intersect(&ray);
        if link.hit && link.exit.t - link.entry.t > 1e-3 {
            // Both are exact to √(64ε)·S (tests/splines/kernel.rs), S ≤ 6.
            let tol = 2.0 * (64.0 * f64::EPSILON).sqrt() * 6.0;
            prop_assert!(iv.hit);
            prop_assert!((iv.entry.t - link.entry.t).abs() * d_len(d) <= tol && (iv.exit.t - link.exit.t).abs() * d_len(d) <= tol);
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
    let s = HermiteSegment::from_ends(
        HermiteEnd { p: v([0.0; 3]), tangent: v([1.0, 2.0, 0.0]), r: 0.3, dr: 0.1 },
        HermiteEnd { p: v([1.0, 2.0, 0.0]), tangent: v([1.0, 2.0, 0.0]), r: 0.4, dr: 0.1 },
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
    let s = HermiteSegment::from_ends(
        HermiteEnd { p: v([0.0; 3]), tangent: v([1.0, 0.0, 0.0]), r: 0.1, dr: -3.0 },
        HermiteEnd { p: v([1.0, 0.0, 0.0]), tangent: v([1.0, 0.0, 0.0]), r: 0.1, dr: 3.0 },
    );
    assert_eq!(s.split(), Err(tubecast::GeometryError::NegativeRadius));
    let s = HermiteSegment::from_ends(
        HermiteEnd { p: v([0.0; 3]), tangent: v([f64::NAN, 0.0, 0.0]), r: 0.1, dr: 0.0 },
        HermiteEnd { p: v([1.0, 0.0, 0.0]), tangent: v([1.0, 0.0, 0.0]), r: 0.1, dr: 0.0 },
    );
    assert!(matches!(s.split(), Err(tubecast::GeometryError::NonFinite { .. })));
}

/// A Catmull–Rom helix (radius `big`, pitch `big` per turn, `n` points per turn): its cubic
/// Hermite segments (uniform Catmull–Rom tangents `(P_{k+1} − P_{k−1})/2`), tube radius `r`.
fn helix_segments(n: usize, big: f64, r: f64) -> Vec<HermiteSegment<f64>> {
    let p = |k: i64| {
        let a = 2.0 * std::f64::consts::PI * k as f64 / n as f64;
        V3::new(big * a.cos(), big * a.sin(), big * k as f64 / n as f64)
    };
    let m = |k: i64| (p(k + 1) - p(k - 1)) * 0.5;
    let node = |k: i64| HermiteEnd { p: p(k), tangent: m(k), r, dr: 0.0 };
    (0..n as i64).map(|k| HermiteSegment::from_ends(node(k), node(k + 1))).collect()
}

/// Entry/exit of the line through the union of `n + 1` sampled spheres of the cubic with radius
/// `r(t) + dr` (an independent f64 sweep of the cubic itself; `None`: no sphere met).
fn cubic_sweep_crossing(s: &HermiteSegment<f64>, o: V3<f64>, d: V3<f64>, dr: f64, n: usize) -> Option<(f64, f64)> {
    let mut best: Option<(f64, f64)> = None;
    for k in 0..=n {
        let t = k as f64 / n as f64;
        let (c, r) = (s.point(t), s.radius(t) + dr);
        let f = o - c;
        let tc = -f.dot(d) / d.length2();
        let q = f + d * tc;
        let h2 = (r * r - q.length2()) / d.length2();
        if r > 0.0 && h2 >= 0.0 {
            let h = h2.sqrt();
            best = Some(best.map_or((tc - h, tc + h), |(a, b)| (a.min(tc - h), b.max(tc + h))));
        }
    }
    best
}

/// Faithful to the cubic: on Catmull–Rom helices with 8, 12, 16 points per turn and
/// tube radii 0.07, 0.01, 0.001 of the helix radius, the adaptive split meets the default
/// tolerance (certified distance ≤ 1e-3 of the local radius), and rays agree with the cubic's
/// own sweep, sampled: the pieces' sweep lies between the cubic's sweeps of `r − D` and
/// `r + D` (D the certified distance), so the union of the pieces' intervals lies between the
/// sampled sweeps' intervals, widened by the sampling slack `S = max|p'|·δ/2` (δ = 1/n: a sphere
/// of the true sweep is within S of a sampled one; |r'| = 0 here) plus rounding (1e-12).
#[test]
fn adaptive_split_is_faithful_to_catmull_rom_helices() {
    let big = 1.0;
    for n in [8, 12, 16] {
        for rr in [0.07, 0.01, 0.001] {
            for (k, s) in helix_segments(n, big, rr).into_iter().enumerate().take(2) {
                let split = s.split_adaptive(1e-3, 12).unwrap();
                assert!(split.relative <= 1e-3, "n {n} r {rr}: relative {}", split.relative);
                assert!(split.distance <= 1e-3 * rr, "n {n} r {rr}: {}", split.distance);
                // The certificate is honest: dense samples of the pieces are within D of the
                // cubic at the corresponding parameter (pieces are equal-parameter halvings).
                let m = split.quads.len();
                let ns = 4000;
                let speed = (0..=100)
                    .map(|j| (s.point((j as f64 + 1e-3) / 100.0) - s.point(j as f64 / 100.0)).length() / 1e-3 * 100.0)
                    .fold(0.0, f64::max);
                let slack = speed / ns as f64 / 2.0 * 1.01 + 1e-12;
                for j in 0..5 {
                    let tgt = s.point(0.1 + 0.2 * j as f64) + V3::new(0.3, -0.2, 0.1) * rr * (j as f64 - 2.0);
                    let d = V3::new(0.3 + 0.1 * j as f64, 1.0, -0.4);
                    let o = tgt - d * 3.0;
                    let ray = Ray::new(o, d);
                    let mut got: Option<(f64, f64)> = None;
                    for q in &split.quads {
                        let iv = q.line_interval_with(&ray, Solver::Polynomial);
                        if iv.hit {
                            got = Some(
                                got.map_or((iv.entry.t, iv.exit.t), |(a, b)| (a.min(iv.entry.t), b.max(iv.exit.t))),
                            );
                        }
                    }
                    let dl = d.length();
                    let outer = cubic_sweep_crossing(&s, o, d, split.distance + slack, ns);
                    let inner = cubic_sweep_crossing(&s, o, d, -split.distance, ns);
                    let tol = 1e-12 / dl;
                    match (got, outer, inner) {
                        (Some(_), None, _) => {
                            panic!("n {n} r {rr} seg {k} ray {j}: pieces hit, outer cubic sweep misses")
                        }
                        (None, _, Some(w)) => {
                            panic!("n {n} r {rr} seg {k} ray {j}: pieces miss, inner sweep hit {w:?}")
                        }
                        (Some((ti, to)), Some((ai, ao)), inner) => {
                            assert!(
                                ti >= ai - tol && to <= ao + tol,
                                "n {n} r {rr} ray {j}: {ti} {to} vs outer {ai} {ao}"
                            );
                            if let Some((bi, bo)) = inner {
                                assert!(
                                    ti <= bi + tol && to >= bo - tol,
                                    "n {n} r {rr} ray {j}: {ti} {to} vs inner {bi} {bo}"
                                );
                            }
                        }
                        _ => {}
                    }
                }
                assert!(m >= 2, "at least one halving on a curved segment");
            }
        }
    }
}

/// The certificate against the cubic, sampled: every sample (p(t), r(t)) of the cubic is within
/// D of the piece covering t at the same local parameter (pieces are dyadic, each a mid-point
/// quadratic of its cubic piece), and Russig's C¹ pair, for comparison, is far outside the
/// default tolerance on the same helix (its junction misses the cubic's midpoint).
#[test]
fn certified_distance_bounds_the_sampled_gap() {
    for n in [8, 12, 16] {
        let s = helix_segments(n, 1.0, 0.07)[0];
        for depth in 0..4 {
            let split = s.split_adaptive(0.0, depth).unwrap();
            let m = split.quads.len();
            assert_eq!(m, 1 << depth);
            let mut worst: f64 = 0.0;
            for k in 0..=2000 {
                let t = k as f64 / 2000.0;
                let i = ((t * m as f64) as usize).min(m - 1);
                let u = t * m as f64 - i as f64;
                let q = &split.quads[i];
                worst = worst.max((q.point(u) - s.point(t)).length() + (q.radius(u) - s.radius(t)).abs());
            }
            // The certificate bounds the equal-parameter gap (rounding: 1e-14 of size ~1).
            assert!(worst <= split.distance + 1e-14, "n {n} depth {depth}: {worst} > {}", split.distance);
            // …and is not vacuous: within 4× of the sampled gap.
            assert!(split.distance <= 4.0 * worst + 1e-14, "n {n} depth {depth}: {} vs {worst}", split.distance);
        }
        let [a, b] = s.split().unwrap();
        let gap = (a.point(1.0) - s.point(0.5)).length();
        assert!(gap > 1e-3 * 0.07, "n {n}: Russig's pair is {gap} off at the junction");
        // The pair's certificate bounds its sampled equal-parameter gap too (halves at t = ½).
        let pd = s.pair_distance();
        for k in 0..=2000 {
            let t = k as f64 / 2000.0;
            let (q, u) = if t < 0.5 { (&a, 2.0 * t) } else { (&b, 2.0 * t - 1.0) };
            let g = (q.point(u) - s.point(t)).length() + (q.radius(u) - s.radius(t)).abs();
            assert!(g <= pd + 1e-14, "n {n}: pair gap {g} > certificate {pd}");
        }
        assert!(pd <= 4.0 * gap, "n {n}: certificate {pd} vs junction gap {gap}");
    }
}
