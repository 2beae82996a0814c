//! Russig's empirical claims about `f = h − √g` (Russig §3.2, Salm §3.2):
//! (1) `f'` has at most 3 roots per real interval of `g`; (2) when it has 3, the middle one
//! is a maximum of `f`. Searched for counterexamples by proptest with an independent
//! dense-sampling root count.
//!
//! `PROPTEST_CASES` raises the case count (default small so `cargo test` stays fast).

use super::common::*;
use proptest::prelude::*;

/// h, g of a quadratic tube in ray space with unit direction, independent of the crate.
fn hg(b: &[[f64; 3]; 3], r: &[f64; 3], o: [f64; 3], dhat: [f64; 3], t: f64) -> (f64, f64) {
    let (p, rr) = eval(b, r, t);
    let q = [p[0] - o[0], p[1] - o[1], p[2] - o[2]];
    let h = q[0] * dhat[0] + q[1] * dhat[1] + q[2] * dhat[2];
    (h, rr * rr - (q[0] * q[0] + q[1] * q[1] + q[2] * q[2]) + h * h)
}

/// Sign changes of f' (as the sign of F₁ = 2h'√g − g', derivatives by central differences)
/// on each maximal run of samples with g > 0. Returns per real interval the list of
/// (t, is_max) at the sign changes.
pub fn fprime_roots(b: &[[f64; 3]; 3], r: &[f64; 3], o: [f64; 3], d: [f64; 3], n: usize) -> Vec<Vec<(f64, bool)>> {
    let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    let dh = [d[0] / l, d[1] / l, d[2] / l];
    let f = |t: f64| {
        let (h, g) = hg(b, r, o, dh, t);
        (g, h - g.max(0.0).sqrt())
    };
    let mut out = Vec::new();
    let mut cur: Option<Vec<(f64, bool)>> = None;
    let mut prev: Option<(f64, f64)> = None; // (t, f)
    let mut prev_slope = 0.0f64;
    for k in 0..=n {
        let t = k as f64 / n as f64;
        let (g, fv) = f(t);
        if g > 0.0 {
            let c = cur.get_or_insert_with(Vec::new);
            if let Some((tp, fp)) = prev {
                let slope = fv - fp;
                if prev_slope != 0.0 && slope != 0.0 && (slope > 0.0) != (prev_slope > 0.0) {
                    c.push((tp, prev_slope > 0.0)); // + then −: a maximum
                }
                if slope != 0.0 {
                    prev_slope = slope;
                }
            }
            prev = Some((t, fv));
        } else {
            if let Some(c) = cur.take() {
                out.push(c);
            }
            prev = None;
            prev_slope = 0.0;
        }
    }
    if let Some(c) = cur.take() {
        out.push(c);
    }
    out
}

/// Kernel entry/exit vs the oracle on a case where a claim might fail (the kernel must not
/// rely on the claim: [`Solver::Polynomial`] does not; the Russig-cascade solvers do).
fn kernel_still_right(b: &[[f64; 3]; 3], r: &[f64; 3], o: [f64; 3], d: [f64; 3]) -> Result<(), TestCaseError> {
    use tubecast::{Ray, Solver, V3};
    let t = tube(b, r);
    let ray = Ray::new(V3::from(o), V3::from(d));
    if let Some(QuadCrossing { t_in: ti, t_out: to, depth, .. }) = oracle(b, r, o, d, 4000) {
        if depth > 1e-3 {
            let iv = t.intersect_with(&ray, Solver::Polynomial);
            let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            // Same bound as tests/splines/kernel.rs: √(64ε)·S with S ≤ scale + 2.
            let tol = (64.0 * f64::EPSILON).sqrt() * (scale(b, r) + 2.0);
            prop_assert!(iv.hit && (iv.entry.t - ti).abs() * l <= tol && (iv.exit.t - to).abs() * l <= tol);
        }
    }
    Ok(())
}

/// Tally of f' root counts per real interval over the deterministic proptest stream.
fn histogram(cases: usize, cusp: bool) -> ([usize; 8], usize) {
    use proptest::strategy::ValueTree;
    use proptest::test_runner::TestRunner;
    let mut runner = TestRunner::deterministic();
    let mut hist = [0usize; 8];
    let mut bad = 0;
    let strat = (tube_strategy(0.05, 2.0), ray_strategy());
    for _ in 0..cases {
        let ((mut b, r), (o, d)) = strat.new_tree(&mut runner).unwrap().current();
        if cusp {
            b[2] = [b[0][0] + 1e-3 * b[2][0], b[0][1], b[0][2]];
        }
        for iv in fprime_roots(&b, &r, o, d, 20000) {
            hist[iv.len().min(7)] += 1;
            if iv.len() > 3 || (iv.len() == 3 && !iv[1].1) {
                bad += 1;
                eprintln!("COUNTEREXAMPLE b={b:?} r={r:?} o={o:?} d={d:?} roots={iv:?}");
                kernel_still_right(&b, &r, o, d).expect("kernel right on a counterexample");
            }
        }
    }
    (hist, bad)
}

/// Recorded result (deterministic stream, 2000 general + 2000 near-cusp cases, 20000
/// samples per case): no interval with more than 3 roots of f', and every interval with 3
/// has a maximum in the middle. (A 20000-case run found the histogram
/// [0 roots: 6916, 1: 6484, 2: 357, 3: 70, ≥4: 0] and no counterexample.) The search must
/// not be vacuous: intervals with 2 and 3 roots occur. The random search does not reach the
/// counterexample below (found by the fuzzer): a radius shrinking ~600-fold along the segment.
#[test]
fn claims_hold_on_the_search() {
    let (h1, bad1) = histogram(2000, false);
    let (h2, bad2) = histogram(2000, true);
    eprintln!("general {h1:?}, near-cusp {h2:?}");
    assert!(h1[3] + h2[3] > 0, "no interval with three roots: the search is vacuous");
    assert_eq!(bad1 + bad2, 0, "Russig's claims fail on some case (printed above); the kernel was checked on it");
    assert_eq!(h1[4..].iter().sum::<usize>() + h2[4..].iter().sum::<usize>(), 0);
}

proptest! {
    #![proptest_config(config(64))]

    /// Searches for violations of the claims; any found is printed and then must still be
    /// handled: the kernel's entry (default solver) equals the oracle's.
    #[test]
    fn russig_claims((b, r) in tube_strategy(0.05, 2.0), (o, d) in ray_strategy()) {
        let roots = fprime_roots(&b, &r, o, d, 20000);
        for iv in &roots {
            let three_mid_not_max = iv.len() == 3 && !iv[1].1;
            if iv.len() > 3 || three_mid_not_max {
                eprintln!("COUNTEREXAMPLE b={b:?} r={r:?} o={o:?} d={d:?} roots={iv:?}");
                kernel_still_right(&b, &r, o, d)?;
            }
        }
    }
}

/// A counterexample, found by the fuzzer (fuzz/corpus/spline/regression-russig-claim): a
/// segment whose radius shrinks from 30.464 to 0.049 while its centre moves 30 units, hit by a
/// ray through the thin end. The whole of [0, 1] is one real interval (bounded by the segment
/// ends, not by roots of g). f' has three roots there: t ≈ 0.020 (maximum of f), 0.459
/// (**minimum**: the entry), 0.998 (maximum), so the middle one is *not* a maximum; and
/// f''' has two roots (f'''(0) < 0, f'''(1) < 0, a sign change near 0.61), so "the number of
/// roots decreases with every differentiation" fails too and Russig's cascade (which starts
/// from at most one root of f''') never brackets the minimum: the Bisection/Itp/Newton solvers
/// report the entry at the segment end t = 0 (a point 0.014 inside the tube). The default
/// solver (Polynomial) does not rely on the claims and finds the right entry.
#[test]
fn counterexample_at_segment_ends() {
    use tubecast::{Primitive, Ray, Solver, V3};
    let b = [[0.0, 0.0, -30.464], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]];
    let r = [30.464, 0.0, 0.049];
    let (o, d) = ([0.0; 3], [-12.544, 0.0, 0.05]);
    let roots = fprime_roots(&b, &r, o, d, 200000);
    assert_eq!(roots.len(), 1);
    let iv = &roots[0];
    assert_eq!(iv.len(), 3, "{iv:?}");
    assert!(iv[0].1 && !iv[1].1 && iv[2].1, "max, min, max expected: {iv:?}");
    kernel_still_right(&b, &r, o, d).unwrap();
    let t = tube(&b, &r);
    let ray = Ray::new(V3::from(o), V3::from(d));
    let good = t.intersect(&ray);
    // The sampled root is within one sample (5e-6) of the true one; the kernel's u to ~1e-8.
    assert!((good.entry.u - iv[1].0).abs() < 1e-4, "entry at the f minimum: {good:?}");
    for s in [Solver::Itp, Solver::Newton, Solver::Bisection { iters: 40 }] {
        let bad = t.intersect_with(&ray, s);
        eprintln!(
            "Russig cascade {s:?}: entry u = {} (t = {}), polynomial u = {} (t = {})",
            bad.entry.u, bad.entry.t, good.entry.u, good.entry.t
        );
        // Whatever they return is a point of the closed tube: never before the true entry.
        assert!(bad.hit && bad.entry.t >= good.entry.t - 1e-12);
    }
}
