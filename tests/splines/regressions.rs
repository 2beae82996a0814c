//! Spline kernel regressions found by fuzzing (each replays one committed input of
//! `fuzz/corpus/spline/regression-*` as a unit test) — moved verbatim from
//! `tests/splines/kernel.rs`.

use super::common::*;
use proptest::prelude::*;
use tubecast::Solver;
use tubecast::{Primitive, QuadTube};
use tubecast::{Ray, V3};

/// Fuzz finding (fuzz/corpus/spline/regression-behind-origin): the Russig-cascade solvers
/// dropped a real interval lying wholly behind the ray origin from the hull, so their
/// line interval differed from the polynomial solver's. The hull is now formed from the
/// unclipped pieces; every solver returns the same line interval, with both ends on the
/// surface (SDF within the usual bound, S ≈ 60 here).
#[test]
fn hull_keeps_pieces_behind_the_origin() {
    let a: f64 = -14.393;
    let t = QuadTube::new([V3::new(-1.0, 0.0, -14.552), V3::new(a, a, a), V3::new(a, a, a)], [14.393, -14.393, 14.393])
        .unwrap();
    let ray = Ray::new(V3::new(a, a, a), V3::new(a, a, a));
    let want = t.intersect_with(&ray, Solver::Polynomial);
    assert!(want.hit && want.entry.t < -0.9, "{want:?}");
    for solver in SOLVERS {
        let iv = t.intersect_with(&ray, solver);
        assert!(iv.hit, "{solver:?}");
        for tt in [iv.entry.t, iv.exit.t] {
            assert!(t.sdf(ray.at(tt)).abs() <= bound(f64::EPSILON, 60.0), "{solver:?}: {iv:?}");
        }
        // Bisection{10}: t* off by ≤ 2⁻¹⁰ moves the entry by ≤ ½|f''|δt², < 1e-3 here.
        let tol = if solver == (Solver::Bisection { iters: 10 }) { 1e-3 } else { 1e-9 };
        assert!(
            (iv.entry.t - want.entry.t).abs() <= tol && (iv.exit.t - want.exit.t).abs() <= tol,
            "{solver:?}: {iv:?}"
        );
    }
}

/// Fuzz finding (fuzz/corpus/spline/regression-zero-radius-start): r(0) = 0 with the ray
/// through p(0), so g has a double root at t = 0 and the scaled sign function 2√g·f' is
/// exactly 0 there although f'(0) = −2; the Russig cascade took no sign from it and missed
/// the minimum. The cascade now takes the sign √ε inside the piece. All solvers agree with the
/// oracle (bound as above, S ≈ 6).
#[test]
fn zero_radius_end_on_the_ray() {
    let b = [[0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [1.0, 0.232, 0.0]];
    let r = [0.0, 1.0, 1.0];
    let (o, d) = ([-3.072, 0.0, 0.0], [1.0, 0.0, 0.0]);
    let t = tube(&b, &r);
    let QuadCrossing { t_in: ti, t_out: to, .. } = oracle(&b, &r, o, d, 4000).unwrap();
    for solver in SOLVERS {
        let iv = t.intersect_with(&Ray::new(V3::from(o), V3::from(d)), solver);
        let tol = if solver == (Solver::Bisection { iters: 10 }) { 1e-3 } else { bound(f64::EPSILON, 6.0) };
        assert!(
            iv.hit && (iv.entry.t - ti).abs() <= tol && (iv.exit.t - to).abs() <= tol,
            "{solver:?}: {iv:?} vs {ti} {to}"
        );
    }
}

/// Fuzz finding (fuzz/corpus/spline/regression-thin-long): a 0.001-thin tube 35 long hit near
/// its far end. (1) The SDF's degree-6 polynomial has cancelling coefficients there, so its
/// roots were off by ~1e-3 in t and the "exact" SDF by ~1e-4; it now polishes each root by
/// golden section. (2) The polynomial solver's P roots had the same problem (exit 2e-6 off);
/// it now polishes the chosen t* by Newton on F₁. All solvers' hits are now on the surface to
/// 1e-9 — far inside bound(ε, S) with S ≈ 220 (2.6e-5), which is what this asserts, plus the
/// agreement between the solvers to 1e-8 in t (each within 4 ulps·|f'|-scale of the root).
#[test]
fn thin_long_tube_far_end() {
    let t = QuadTube::<f64>::new(
        [V3::new(20.046, 20.046, 20.046), V3::new(-0.178, -0.001, -0.001), V3::new(-0.001, -0.001, -0.001)],
        [0.001, -0.001, 0.001],
    )
    .unwrap();
    let ray = Ray::new(V3::new(-0.001, -3.073, -0.001), V3::new(-0.001, 2.815, 0.0));
    let want = t.intersect_with(&ray, Solver::Itp);
    for solver in [Solver::Polynomial, Solver::Newton, Solver::Bisection { iters: 40 }] {
        let iv = t.intersect_with(&ray, solver);
        assert!(iv.hit);
        for tt in [iv.entry.t, iv.exit.t] {
            assert!(t.sdf(ray.at(tt)).abs() <= 1e-9, "{solver:?} {iv:?}");
        }
        assert!((iv.entry.t - want.entry.t).abs() <= 1e-8 && (iv.exit.t - want.exit.t).abs() <= 1e-8, "{solver:?}");
    }
}

proptest! {
    #![proptest_config(config(32))]

    /// Scale invariance: positions, radii and the ray origin scaled by 2^k (exact) give ray
    /// parameters scaled by exactly 2^k, bit for bit, for every solver and k from −500 to 500 (squares of the extents stay normal and finite):
    /// the kernel re-centres and works in units of the bounding radius, so every intermediate
    /// is the same number. (Fuzz finding fuzz/corpus/spline/regression-tiny-scale: at 1e-33
    /// the sign functions, products of six coordinates, underflowed and ITP/Newton missed
    /// the minimum.)
    #[test]
    fn exact_scale_invariance((b, r) in tube_strategy(0.02, 0.6), (o, d) in ray_strategy(), k in -500i32..500) {
        let f = 2f64.powi(k);
        let sc = |p: [f64; 3]| [p[0] * f, p[1] * f, p[2] * f];
        let t1 = tube(&b, &r);
        let tk = tube(&[sc(b[0]), sc(b[1]), sc(b[2])], &[r[0] * f, r[1] * f, r[2] * f]);
        let r1 = Ray::new(V3::from(o), V3::from(d));
        let rk = Ray::new(V3::from(sc(o)), V3::from(d));
        for solver in SOLVERS {
            let (a, c) = (t1.intersect_with(&r1, solver), tk.intersect_with(&rk, solver));
            prop_assert_eq!(a.hit, c.hit);
            if a.hit {
                prop_assert_eq!(a.entry.t * f, c.entry.t, "{:?}", solver);
                prop_assert_eq!(a.exit.t * f, c.exit.t, "{:?}", solver);
                prop_assert_eq!(a.entry.n, c.entry.n);
                prop_assert_eq!(a.entry.u, c.entry.u);
            }
        }
    }
}

/// Fuzz finding (fuzz/corpus/spline/regression-thin-long-exit): another 0.001-thin, 30-long
/// tube; P's root for the exit was off by 1.3e-3 in t (the exit 4e-5 inside the tube) and two
/// Newton steps did not recover. The polynomial solver now polishes with ITP on F₁ in the
/// bracket of the neighbouring breakpoints: the exit is on the surface to 1e-9 (vs the bound
/// 3e-5 for S ≈ 270) and agrees with ITP's to 1e-6 in t (t·|d| ≈ 2.4e-3·t: 2e-9 in distance).
#[test]
fn thin_long_tube_exit() {
    let t = QuadTube::<f64>::new(
        [V3::new(24.32, -12.544, -12.337), V3::new(-0.049, -0.001, -0.001), V3::new(-0.001, -0.001, -0.001)],
        [0.001, -0.001, 0.001],
    )
    .unwrap();
    let ray = Ray::new(V3::new(-0.001, -0.001, -0.001), V3::new(-0.001, -0.002, -0.001));
    let iv = t.intersect(&ray);
    let want = t.intersect_with(&ray, Solver::Itp);
    assert!(iv.hit && t.sdf(ray.at(iv.exit.t)).abs() <= 1e-9, "{iv:?}");
    assert!((iv.exit.t - want.exit.t).abs() <= 1e-6);
}

/// Fuzz finding (fuzz/corpus/spline/regression-zero-radius-tip): r = 0 at the end t = 1 and
/// the ray starts exactly there, running along the folded centre line. g(1) = 0 exactly but
/// evaluates to −1e-18, and the polynomial solver's `g ≥ 0` filter dropped the end point (its
/// entry was 0.025 inside the tube). Candidates now count as real within g's evaluation error
/// (16ε·Σ|gᵢ|), so the entry is the tip, t = 0, to rounding (t·|d| ≤ bound(ε, S ≈ 30)).
#[test]
fn zero_radius_tip_on_the_ray() {
    let t = QuadTube::<f64>::new(
        [V3::new(0.042, 0.0, 0.002), V3::new(0.0, -0.001, 7.423), V3::new(0.0, 0.0, 0.0)],
        [0.0, 0.137, 0.0],
    )
    .unwrap();
    let ray = Ray::new(V3::new(0.0, 0.0, 0.0), V3::new(0.0, -0.001, 0.255));
    let iv = t.intersect(&ray);
    assert!(iv.hit && iv.entry.t.abs() * 0.255 <= bound(f64::EPSILON, 30.0), "{iv:?}");
    assert!(t.sdf(ray.at(iv.exit.t)).abs() <= bound(f64::EPSILON, 30.0));
}

/// Fuzz finding (fuzz/corpus/spline/regression-pinched-slow-end): a 0.001-thin, 46-long tube
/// with b₁ = b₂ (the centre line stops: p'(1) = 0) and r(t) = 0.001(1 − 2t)² (pinched to 0 at
/// t = ½); the ray starts at p(1) and the entry is a sphere at t ≈ 0.99653. Near t = 1 both
/// h' and g' vanish, so P = 4h'²g − g'² is ~1e-14 there while its t-power coefficients are
/// ~800 (P ≈ −38(1 − t)⁶ + …): its computed roots were noise, the polish had no sign change
/// to work with, and the entry came out 6.3e-5 inside the tube (bound 4.3e-5). Not the pinch,
/// not the ITP: P is now formed about the vertex of the centre line (t = 1 here), where its
/// coefficients carry no cancellation. The entry is on the surface to 1e-9 (vs the bound
/// √(64ε)·S + 8εS ≈ 4.3e-5 for S ≈ 360) and agrees with ITP's and with dense sampling
/// (2·10⁶ spheres: t·|d| error ≤ |p'|·Δu + … ≈ 1e-9 here, measured 4e-10) to 1e-6 in t
/// (|d| = 1.4e-3: 1.4e-9 in distance).
#[test]
fn pinched_tube_slow_end() {
    let b = [[-0.001, 32.767, 32.767], [-0.001, -0.001, -0.001], [-0.001, -0.001, -0.001]];
    let r = [0.001, -0.001, 0.001];
    let (o, d) = ([-0.001, -0.001, -0.001], [-0.001, -0.001, 0.0]);
    let t = tube(&b, &r);
    let ray = Ray::new(V3::from(o), V3::from(d));
    let iv = t.intersect(&ray);
    assert!(iv.hit, "{iv:?}");
    let s = 4.0 * 32.768 * (3f64.sqrt() + 1.0);
    for tt in [iv.entry.t, iv.exit.t] {
        let e = t.sdf(ray.at(tt));
        assert!(e.abs() <= 1e-9 && e.abs() <= bound(f64::EPSILON, s), "{tt}: sdf {e}, {iv:?}");
    }
    let itp = t.intersect_with(&ray, Solver::Itp);
    assert!((iv.entry.t - itp.entry.t).abs() <= 1e-6 && (iv.exit.t - itp.exit.t).abs() <= 1e-6, "{iv:?} vs {itp:?}");
    let QuadCrossing { t_in: ti, t_out: to, .. } = oracle(&b, &r, o, d, 200_000).unwrap();
    assert!((iv.entry.t - ti).abs() <= 1e-6 && (iv.exit.t - to).abs() <= 1e-6, "{iv:?} vs oracle {ti} {to}");
}

/// Fuzz finding (fuzz/corpus/spline/regression-tiny-sdf-underflow): a tube 5e-304 small (one
/// control radius subnormal). The kernel's hits were right (the kernel works in units of the
/// bounding radius; its result scaled by 2¹⁰⁰⁰ has SDF 4e-19 at S ≈ 1e-3), but the "exact"
/// SDF squared coordinates of 1e-304, which underflow to 0, and reported −r (−2.7e-304) at a
/// surface point. `quadratic_tube` now works in units of a power of two near the extent, so
/// it commutes exactly with scaling by 2^k, and the hits are on the surface within the bound.
#[test]
fn tiny_tube_sdf_does_not_underflow() {
    let e = 5.468341514667298e-304;
    let t =
        QuadTube::<f64>::new([V3::new(e, 1.61856e-319, 0.0), V3::zero(), V3::zero()], [0.0, e, 1.61856e-319]).unwrap();
    let ray = Ray::new(V3::zero(), V3::new(0.0, 0.0, 9.230442488933376e-151));
    let iv = t.intersect(&ray);
    assert!(iv.hit, "{iv:?}");
    let s = 4.0 * e * (3f64.sqrt() + 1.0);
    for tt in [iv.entry.t, iv.exit.t] {
        let sdf = t.sdf(ray.at(tt));
        assert!(sdf.abs() <= bound(f64::EPSILON, s), "{tt}: sdf {sdf:e} vs {:e}", bound(f64::EPSILON, s));
    }
    // Scaling by 2^k (exact) scales the SDF exactly, from 1e-304 up to ~1e0 and for far points.
    let f = 2f64.powi(1000);
    let tf = QuadTube::<f64>::new([t.b[0] * f, t.b[1] * f, t.b[2] * f], [t.r[0] * f, t.r[1] * f, t.r[2] * f]).unwrap();
    for x in [ray.at(iv.entry.t), V3::new(e, e, e), V3::new(-3.0 * e, 0.5 * e, 1e3 * e)] {
        assert_eq!(tf.sdf(x * f), t.sdf(x) * f, "{x:?}");
    }
}

/// Fuzz finding (fuzz/corpus/spline/regression-tip-on-ray): b = [(0,0,−30.336), 0,
/// (−30.336,0,0)], r = 30.464(1 − t)², so r(1) = 0 and the tip p(1) = (−30.336, 0, 0) lies
/// on the ray o = (−10.496, 0, 0), d = (0.512, 0, 0), at
/// t = (−30.336 − (−10.496))/0.512 = −19.84/0.512 = −38.75.
/// It is the first crossing: the sphere at u has |z| = 30.336(1 − u)² ≤ r(u), so it meets the
/// x-axis in x ∈ −30.336u² ± c(1 − u)², c = √(30.464² − 30.336²) = √7.7824 ≈ 2.790; the least
/// x, −30.336u² − c(1 − u)², has derivative −60.672u + 2c(1 − u) < 0 near u = 1 and its
/// only critical point is a maximum (u = c/(30.336 + c) ≈ 0.084), so min x is at u = 1: −30.336 (t = −38.75);
/// the greatest, −30.336u² + c(1 − u)², decreases on [0, 1]: max x = c at u = 0, t = (c + 10.496)/0.512 ≈ 25.95.
/// After 4ab0964 (P about the vertex tv = ½) the end u = 1 (g = 0 exactly there) was dropped
/// and the entry came out at t = 11.15, u = 0.344, 0.047 inside the tube.
#[test]
fn zero_radius_tip_on_the_ray_far_side() {
    let b = [[0.0, 0.0, -30.336], [0.0, 0.0, 0.0], [-30.336, 0.0, 0.0]];
    let r = [30.464, 0.0, 0.0];
    let (o, d) = ([-10.496, 0.0, 0.0], [0.512, 0.0, 0.0]);
    let t = tube(&b, &r);
    let ray = Ray::new(V3::from(o), V3::from(d));
    let c = (30.464f64 * 30.464 - 30.336 * 30.336).sqrt();
    let want_out = (c + 10.496) / 0.512;
    let s = 4.0 * 30.464 * (3f64.sqrt() + 1.0);
    let tol = bound(f64::EPSILON, s) / 0.512;
    for solver in [Solver::Polynomial] {
        let iv = t.intersect_with(&ray, solver);
        assert!(iv.hit, "{solver:?}: {iv:?}");
        assert!((iv.entry.t - -38.75).abs() <= tol, "{solver:?}: entry {} vs -38.75 (tol {tol}): {iv:?}", iv.entry.t);
        assert!((iv.exit.t - want_out).abs() <= tol, "{solver:?}: exit {} vs {want_out}: {iv:?}", iv.exit.t);
        for tt in [iv.entry.t, iv.exit.t] {
            assert!(t.sdf(ray.at(tt)).abs() <= bound(f64::EPSILON, s), "{solver:?} {tt}: {iv:?}");
        }
    }
}

/// CI finding (stop 28, `spline_kernel::bulge_region`, random seed): a bulging segment (radii
/// 1.0–1.7 against a curvature radius below 1). The exit is an interior maximum (u = 0.4525);
/// Russig's cascade (ITP, Newton, bisection) took the end u = 1, an exit 0.055 inside the tube
/// — a counterexample to the claim it rests on (`Solver::Itp`'s docs). Polynomial is exact; the
/// cascade's interval must still lie inside the true one (each value it reports is a sphere's).
#[test]
fn bulge_itp_ci_finding() {
    let b = [
        [0.0, 0.0, -0.6806039668123537],
        [-0.42271596806995143, -0.9811607155883479, 0.6582221758710051],
        [0.26729668302490284, -0.9026323694476711, 0.0],
    ];
    let r = [1.5760971475488506, 0.9638322995064503, 1.7370831633480899];
    let o = [2.687277453413412, 3.9812392210464354, -4.686087897631452];
    let d = [-0.5135450748714411, -0.5688428720408804, 0.7968040960170104];
    let t = tube(&b, &r);
    let ray = Ray::new(V3::from(o), V3::from(d));
    let want = oracle(&b, &r, o, d, 4000).expect("the oracle hits");
    let tol = bound(f64::EPSILON, scale(&b, &r) + 2.0) / norm(d);
    let iv = t.intersect_with(&ray, Solver::Polynomial);
    assert!(
        iv.hit && (iv.entry.t - want.t_in).abs() <= tol && (iv.exit.t - want.t_out).abs() <= tol,
        "{iv:?} vs {want:?}"
    );
    for solver in [Solver::Itp, Solver::Newton, Solver::Bisection { iters: 40 }] {
        let iv = t.intersect_with(&ray, solver);
        assert!(
            iv.hit && iv.entry.t >= want.t_in - tol && iv.exit.t <= want.t_out + tol,
            "{solver:?}: {iv:?} vs {want:?}"
        );
    }
}
