//! Property tests of the link kernels against the independent sphere-sweep oracle
//! (`tests/kernels/common`). Case counts: proptest's default (256 per property) or `PROPTEST_CASES=100000`
//! for the long run described in the README.
//!
//! ## Error analysis behind every tolerance here
//! Let `ε` be the unit roundoff of the kernel's precision, `S = max(L, ra, rb)` the link's size and
//! `D = |o − m|` the distance from the ray origin to the link midpoint `m`.
//! * The stable kernel first moves the origin to the point of the line closest to `m`: one
//!   multiply-add and one subtraction on vectors of size ≤ `D`, i.e. an absolute error ≤ 3ε·D.
//!   Every later quantity (cross products, `e = rm − s·z`, the three coefficients) is formed from
//!   vectors of size ≤ `S + dist(line, m)` ≤ 2S near a hit with ≤ 8 roundings each, so the
//!   coefficients are exact for a geometry moved by ≤ 16ε·S. The citardauq root is backward stable:
//!   the computed root is an exact root of a problem perturbed by a few ε more, so the hit point
//!   lies within ≈ 20ε·S + 3ε·D of the true surface — measured as distance, which stays well
//!   conditioned even for grazing rays (there `t` itself may move by √(ε)·S, but along a tangent
//!   ray the distance to the surface grows only quadratically).
//! * Forming `x = o + t·d` in the test adds 2ε·(|o − m| + |t·d|) ≤ 2ε·(2D + 2S); evaluating the
//!   oracle distance in f64 adds ≈ 8ε₆₄·(D + S).
//!
//! Hence `E = 64·ε·(S + D)` bounds the distance of a reported hit point from the surface with a
//! safety factor of ~2, and a `t` error, converted through the incidence cosine `γ = |n·d̂|`
//! (distance changes by at least `γ·|d|·Δt` along a ray entering a convex solid), is bounded by
//! `(E + E₆₄)/(γ·|d|)`.
//!
//! Normals: on a sphere of radius r, a point displaced by `E` turns the normal by ≤ `E/r`; on the
//! cone the normal is constant along generators and turns by ≤ `E/ρ` around the axis (ρ ≥ r_min),
//! plus ~8ε of rounding: `|Δn| ≤ 4E/r_min + 16ε`. The curve parameter moves by ≤ `E/(L·c²)` per
//! unit of displacement along the axis (u = (z − ra·s)/(L c²)), plus the same across: `2E/(L c²)`.

use crate::common::check::*;
use crate::common::*;
use proptest::prelude::*;
use tubecast::baseline::HanLink;
use tubecast::{Interval, LinkShape, Ray, RoundCone, V3};
use tubecast::{Primitive, WideF32x8, WideF64x4};

fn region() -> impl Strategy<Value = Region> {
    proptest::sample::select(REGIONS.to_vec())
}

/// Ratio of apex distance to link size: where Han's formulation is well conditioned.
fn han_conditioning(l: &RoundCone<f64>) -> f64 {
    let len = (l.b - l.a).length();
    let dr = (l.ra - l.rb).abs();
    if dr == 0.0 || dr >= len {
        return 1.0; // cylinder (no apex) or sphere
    }
    let p2 = len * l.ra.max(l.rb) / dr;
    p2 / len.max(l.ra).max(l.rb)
}

proptest! {
    // Defaults (256 cases, or PROPTEST_CASES); the Han properties reject the ill-conditioned
    // part of the case mix by design, so allow many rejects.
    #![proptest_config(ProptestConfig { max_global_rejects: 1 << 24, ..ProptestConfig::default() })]

    #[test]
    fn stable_f64_matches_oracle(seed in any::<u64>(), region in region()) {
        let c = make_case(seed, region);
        check_against_oracle(&c, c.link.intersect(&c.ray), f64::EPSILON, "stable f64")?;
    }

    #[test]
    fn stable_f32_matches_oracle(seed in any::<u64>(), region in region()) {
        // The f32 problem is the f64 one with inputs rounded to f32; the oracle sees exactly that.
        let c = round_case_f32(&make_case(seed, region));
        let l32: RoundCone<f32> = c.link.cast();
        let r32 = Ray { o: c.ray.o.cast(), d: c.ray.d.cast(), t_min: c.ray.t_min as f32, t_max: f32::INFINITY };
        check_against_oracle(&c, iv64(l32.intersect(&r32)), f32::EPSILON as f64, "stable f32")?;
    }

    #[test]
    fn han_matches_oracle_where_well_conditioned(seed in any::<u64>(), region in region()) {
        // Han's transform works relative to the apex at distance p₂ = L·r₂/|r₂ − r₁|; its rounding
        // errors scale with p₂ instead of S. Where p₂ ≤ 100·S that is at most a factor 100.
        let c = make_case(seed, region);
        let k = han_conditioning(&c.link);
        prop_assume!(k <= 100.0);
        // Near an apex (a zero or tiny radius end) Han's quadric X²+Y²−Z² has a vanishing
        // gradient: distance errors grow like ε·D²/ρ. Not "well conditioned"; see the report.
        prop_assume!(c.link.ra.min(c.link.rb) >= 1e-3 * c.link.ra.max(c.link.rb));
        // The faithful version also forms its quadratic from o − A without re-centring:
        // coefficient errors ε·(D + p₂)², i.e. distance errors ε·(D + p₂)²/r_min.
        let m = (c.link.a + c.link.b) * 0.5;
        let d = (c.ray.o - m).length() + k * c.size;
        let r_min = c.link.ra.max(c.link.rb) * 1e-3 + c.link.ra.min(c.link.rb);
        let eps_eff = f64::EPSILON * (d / c.size) * (d / r_min).max(1.0);
        prop_assume!(eps_eff < 1e-6); // beyond that, the faithful form is not "well conditioned"
        let han = HanLink::new(&c.link).intersect(&c.ray);
        check_against_oracle(&c, han, eps_eff, "Han precomputed f64")?;
        let otf = c.link.intersect_han_on_the_fly(&c.ray);
        prop_assert_eq!(han, otf, "on-the-fly and precomputed Han must be the same arithmetic");
    }

    #[test]
    fn lanes_equal_scalar_bitwise(seeds in proptest::array::uniform8(any::<u64>()), region in region()) {
        // Lane kernels run the same IEEE operations in the same order as the scalar kernels
        // (Rust never contracts a*b+c into an FMA, and `Real::mul_add` is not used by the
        // kernels), so the bound is 0 ulp: every lane must equal the scalar call bit for bit.
        let cases: Vec<Case> = seeds.iter().map(|&s| make_case(s, region)).collect();
        let l8 = RoundCone::<WideF32x8>::from_lanes(|i| cases[i].link.cast());
        let r8 = Ray::<WideF32x8>::from_fn(|i| Ray::new(cases[i].ray.o.cast(), cases[i].ray.d.cast()));
        let (s8, h8) = (l8.intersect(&r8), HanLink::new(&l8).intersect(&r8));
        for (i, c) in cases.iter().enumerate() {
            let l: RoundCone<f32> = c.link.cast();
            let r = r8.lane(i);
            prop_assert_eq!(s8.lane(i), l.intersect(&r), "stable f32x8 lane {}", i);
            prop_assert_eq!(h8.lane(i), HanLink::new(&l).intersect(&r), "Han f32x8 lane {}", i);
        }
        let l4 = RoundCone::<WideF64x4>::from_lanes(|i| cases[i].link);
        let r4 = Ray::<WideF64x4>::from_fn(|i| cases[i].ray);
        let (s4, h4) = (l4.intersect(&r4), HanLink::new(&l4).intersect(&r4));
        for (i, c) in cases.iter().enumerate().take(4) {
            prop_assert_eq!(s4.lane(i), c.link.intersect(&c.ray), "stable f64x4 lane {}", i);
            prop_assert_eq!(h4.lane(i), HanLink::new(&c.link).intersect(&c.ray), "Han f64x4 lane {}", i);
        }
    }

    #[test]
    fn f32_and_f64_agree(seed in any::<u64>(), region in region()) {
        // Same (f32-representable) input in both precisions. Both hit points lie within their
        // E of the surface (above), so along a ray entering with incidence cosine γ their t
        // differ by ≤ (E₃₂ + E₆₄)/(γ|d|); classification may differ only inside the band |gap| ≤ E₃₂.
        let c = round_case_f32(&make_case(seed, region));
        let a = c.link.intersect(&c.ray);
        let l32: RoundCone<f32> = c.link.cast();
        let b = iv64(l32.intersect(&Ray::new(c.ray.o.cast(), c.ray.d.cast())));
        let e = bound(&c, f32::EPSILON as f64) + bound(&c, f64::EPSILON);
        let (gap, _) = line_gap(&c.link, &c.ray);
        if a.hit != b.hit {
            let t_out = if a.hit { a.exit.t } else { b.exit.t };
            let edge_of_range = (t_out - c.ray.t_min).abs() <= e / c.ray.d.length() * 1e6;
            prop_assert!(gap.abs() <= e || edge_of_range, "f32/f64 disagree on hit outside the band: gap {gap:e}, E {e:e}");
        } else if a.hit && gap < -e {
            // (Inside the band |gap| ≤ E₃₂ the f32 chord may shrink to nothing: no t bound.)
            let dl = c.ray.d.length();
            let g_in = a.entry.n.dot(c.ray.d).abs() / dl;
            let g_out = a.exit.n.dot(c.ray.d).abs() / dl;
            let tip = tip_term(&c.link, e) / dl;
            prop_assert!((a.entry.t - b.entry.t).abs() <= e / (g_in * dl) + tip + 1e-12 * a.entry.t.abs(), "t_in {} vs {}", a.entry.t, b.entry.t);
            prop_assert!((a.exit.t - b.exit.t).abs() <= e / (g_out * dl) + tip + 1e-12 * a.exit.t.abs(), "t_out {} vs {}", a.exit.t, b.exit.t);
        }
    }

    #[test]
    fn faithful_and_stable_agree_where_well_conditioned(seed in any::<u64>(), region in region()) {
        let c = make_case(seed, region);
        prop_assume!(han_conditioning(&c.link) <= 100.0);
        prop_assume!(c.link.ra.min(c.link.rb) >= 1e-3 * c.link.ra.max(c.link.rb));
        let m = (c.link.a + c.link.b) * 0.5;
        let d = (c.ray.o - m).length() + 100.0 * c.size;
        let r_min = c.link.ra.max(c.link.rb) * 1e-3 + c.link.ra.min(c.link.rb);
        let e_han = 64.0 * f64::EPSILON * d * (d / r_min).max(1.0);
        prop_assume!(e_han < 1e-6 * c.size);
        let (a, b) = (c.link.intersect(&c.ray), HanLink::new(&c.link).intersect(&c.ray));
        let e = e_han + bound(&c, f64::EPSILON);
        let (gap, _) = line_gap(&c.link, &c.ray);
        if a.hit != b.hit {
            prop_assert!(gap.abs() <= e || a.exit.t.max(b.exit.t).abs() * c.ray.d.length() <= e, "disagree on hit: gap {gap:e} E {e:e}");
        } else if a.hit {
            let dl = c.ray.d.length();
            let g = a.entry.n.dot(c.ray.d).abs() / dl;
            prop_assert!((a.entry.t - b.entry.t).abs() <= e / (g * dl) + 1e-12 * a.entry.t.abs(), "t_in {} vs {}", a.entry.t, b.entry.t);
        }
    }

    #[test]
    fn round_cone_sdf_is_exact(seed in any::<u64>(), region in region(), k in -2.0f64..2.0) {
        // Outside the solid the sweep oracle is the exact Euclidean distance; inside both are
        // the negated distance to the surface. Errors: ≈ 20 roundings on values ≤ |x − a| + S.
        let c = make_case(seed, region);
        let x = c.link.a + (c.ray.o - c.link.a) * (k * k * 0.1);
        let (want, _) = sweep_dist(&c.link, x);
        let got = c.link.sdf(x);
        let tol = 64.0 * f64::EPSILON * ((x - c.link.a).length() + c.size);
        if want >= 0.0 {
            prop_assert!((got - want).abs() <= tol, "sdf {got:e} vs oracle {want:e}");
        } else {
            prop_assert!(got <= tol, "inside point has sdf {got:e}");
        }
    }
}

#[test]
fn constructors_reject_bad_input() {
    use tubecast::GeometryError as E;
    let o = V3::new(0.0, 0.0, 0.0);
    let x = V3::new(1.0, 0.0, 0.0);
    assert!(matches!(RoundCone::new(V3::new(f64::NAN, 0.0, 0.0), 1.0, x, 1.0), Err(E::NonFinite { .. })));
    assert!(matches!(RoundCone::new(o, 1.0, V3::new(0.0, f64::INFINITY, 0.0), 1.0), Err(E::NonFinite { .. })));
    assert!(matches!(RoundCone::new(o, f64::NAN, x, 1.0), Err(E::NonFinite { .. })));
    assert!(matches!(RoundCone::new(o, 1.0, x, f64::INFINITY), Err(E::NonFinite { .. })));
    assert_eq!(RoundCone::new(o, -1.0, x, 1.0), Err(E::NegativeRadius));
    assert_eq!(RoundCone::new(o, 1.0, x, -0.5), Err(E::NegativeRadius));
    assert_eq!(RoundCone::new(o, 0.0, x, 0.0), Err(E::ZeroRadius));
    assert!(matches!(RoundCone::new(o, 1e-300, x, 1.0), Err(E::TooSmall { .. })));
    assert!(matches!(RoundCone::new(o, 1e-150, x, 1e-150), Err(E::TooSmall { .. })));
    assert!(RoundCone::new(o, 1e-140, x, 1e-140).is_ok());
    assert!(matches!(RoundCone::new(o, 1.0, x, 1e-20f32 as f64 * 1e-150), Err(E::TooSmall { .. })));
    assert!(matches!(RoundCone::<f32>::new(o.cast(), 1e-30, x.cast(), 1.0), Err(E::TooSmall { .. })));
    assert!(Ray::new(o, V3::new(1e-160, 0.0, 0.0)).validate().is_err());
    assert!(matches!(RoundCone::new(o, 1e300, x, 1.0), Err(E::NonFinite { .. })));
    // Valid degenerate links: zero length, one sphere inside the other, one zero radius.
    assert_eq!(RoundCone::new(o, 1.0, o, 2.0).unwrap().shape(), LinkShape::Sphere);
    assert_eq!(RoundCone::new(o, 3.0, x, 1.0).unwrap().shape(), LinkShape::Sphere);
    assert_eq!(RoundCone::new(o, 0.0, x, 0.5).unwrap().shape(), LinkShape::Cone);
    assert_eq!(RoundCone::new(o, 0.5, x, 0.5).unwrap().shape(), LinkShape::Cylinder);
    // Rays.
    assert_eq!(Ray::new(o, o).validate(), Err(E::ZeroDirection));
    assert!(Ray::new(V3::new(f64::NAN, 0.0, 0.0), x).validate().is_err());
    assert_eq!(Ray::with_range(o, x, 2.0, 1.0).validate(), Err(E::BadRange));
    assert_eq!(Ray::with_range(o, x, f64::NAN, 1.0).validate(), Err(E::BadRange));
    assert!(Ray::new(o, x).validate().is_ok());
}

#[test]
fn degenerate_links_hit_exactly_where_expected() {
    // Hand-derived expectations (not computed by the kernels):
    // * one sphere inside the other: the larger sphere, radius 2 at the origin; a ray along x
    //   from −10 enters at t = 8 and leaves at t = 12 with normals ∓x̂;
    // * a cone to a point (rb = 0) hit on its axis beyond the tip: misses;
    // * equal radii: a cylinder of radius 0.5; a ray along y through (0.5, ·, 0) enters at
    //   t = 10 − √(0.25) = 9.5.
    let o = V3::new(0.0, 0.0, 0.0);
    let inside = RoundCone::new(o, 2.0, V3::new(0.5, 0.0, 0.0), 1.0).unwrap();
    let r = Ray::new(V3::new(-10.0, 0.0, 0.0), V3::new(1.0, 0.0, 0.0));
    for iv in [inside.intersect(&r), HanLink::new(&inside).intersect(&r)] {
        let iv: Interval<f64> = iv;
        assert!(iv.hit);
        assert!((iv.entry.t - 8.0).abs() < 1e-14 && (iv.exit.t - 12.0).abs() < 1e-14, "{iv:?}");
        assert!((iv.entry.n - V3::new(-1.0, 0.0, 0.0)).length() < 1e-15);
        assert!((iv.exit.n - V3::new(1.0, 0.0, 0.0)).length() < 1e-15);
    }
    let tip = RoundCone::new(o, 1.0, V3::new(4.0, 0.0, 0.0), 0.0).unwrap();
    let past = Ray::new(V3::new(4.5, -5.0, 0.0), V3::new(0.0, 1.0, 0.0));
    assert!(!tip.intersect(&past).hit && !HanLink::new(&tip).intersect(&past).hit);
    let cyl = RoundCone::new(o, 0.5, V3::new(2.0, 0.0, 0.0), 0.5).unwrap();
    let side = Ray::new(V3::new(1.0, -10.0, 0.0), V3::new(0.0, 1.0, 0.0));
    for iv in [cyl.intersect(&side), HanLink::new(&cyl).intersect(&side)] {
        assert!((iv.entry.t - 9.5).abs() < 1e-14 && (iv.exit.t - 10.5).abs() < 1e-14, "{iv:?}");
        assert!((iv.entry.u - 0.5).abs() < 1e-15);
    }
}

#[test]
fn kernels_never_nan_on_valid_extremes() {
    // Valid but extreme input: tiny and huge scales, rays parallel to the axis through the
    // axis, rays through the tip of a zero-radius end, zero-length links, in all precisions.
    let links = [
        RoundCone::new(V3::new(0.0, 0.0, 0.0), 1.0, V3::new(0.0, 0.0, 0.0), 1.0).unwrap(),
        RoundCone::new(V3::new(0.0, 0.0, 0.0), 0.0, V3::new(1.0, 0.0, 0.0), 1.0).unwrap(),
        RoundCone::new(V3::new(0.0, 0.0, 0.0), 1e-30, V3::new(1e-30, 0.0, 0.0), 2e-30).unwrap(),
        RoundCone::new(V3::new(1e15, 1e15, 1e15), 1e-3, V3::new(1e15 + 1.0, 1e15, 1e15), 1e-3).unwrap(),
        RoundCone::new(V3::new(0.0, 0.0, 0.0), 1e10, V3::new(1e12, 0.0, 0.0), 1e11).unwrap(),
    ];
    let dirs = [V3::new(1.0, 0.0, 0.0), V3::new(-1.0, 0.0, 0.0), V3::new(0.0, 1.0, 0.0), V3::new(1.0, 1e-20, 0.0)];
    let origins =
        [V3::new(-5.0, 0.0, 0.0), V3::new(0.0, 0.0, 0.0), V3::new(0.5, 0.0, 0.0), V3::new(1e15 - 5.0, 1e15, 1e15)];
    for l in &links {
        for d in dirs {
            for o in origins {
                let r = Ray::new(o, d);
                for iv in [l.intersect(&r), HanLink::new(l).intersect(&r)] {
                    let iv: Interval<f64> = iv;
                    assert!(no_nan(&iv), "{l:?} {r:?} {iv:?}");
                    assert!(!iv.hit || iv.entry.t <= iv.exit.t);
                }
                let l32: RoundCone<f32> = l.cast();
                let r32 = Ray::new(o.cast::<f32>(), d.cast::<f32>());
                for iv in [l32.intersect(&r32), HanLink::new(&l32).intersect(&r32)] {
                    assert!(no_nan(&iv), "{l32:?} {r32:?} {iv:?}");
                }
            }
        }
    }
}
