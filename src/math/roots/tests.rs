//! Unit tests of the cascade and the bracketed solvers.

use super::*;

#[test]
fn sextic_roots_found_by_every_method() {
    // ∏ (x − k/7), k = 1..6: six simple roots in (0, 1).
    let mut c = [1.0f64, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0];
    for k in 1..=6 {
        let r = k as f64 / 7.0;
        let mut nc = [0.0; 7];
        for i in 0..7 {
            nc[i] -= r * c[i];
            if i > 0 {
                nc[i] += c[i - 1];
            }
        }
        c = nc;
    }
    for (m, tol) in [(Bracket::Bisection(40), 1e-11), (Bracket::Itp, 1e-13), (Bracket::Newton, 1e-13)] {
        let (bp, n) = poly_breakpoints(&c, 0.0, 1.0, m);
        assert_eq!(n, 8);
        for k in 1..=6 {
            let r = k as f64 / 7.0;
            let best = bp[..n].iter().map(|x| (x - r).abs()).fold(f64::INFINITY, f64::min);
            // Bisection(40) on a bracket ≤ 1 wide: ≤ 2⁻⁴¹ ≈ 4.5e-13; ITP/Newton: 4 ulps of 1
            // plus the root's condition (|c'(r)| ≈ 1e-3, |c| rounding ≈ 1e-16 → 1e-13).
            assert!(best < tol, "{m:?}: root {r} missed, best {best}");
        }
    }
}

/// `pair_of` returns, bit for bit, what one `halley_or_newton` call per bracket returns, with
/// Newton's and with Halley's steps: on cubics with roots anywhere (near the bracket ends,
/// double, none), valid and invalid brackets, in f32 and f64. (A solve frozen too early or
/// stepped once too often changes the last bits, which this compares exactly.)
#[test]
fn paired_solves_equal_single_solves() {
    fn check<T: crate::real::Scalar>(seed: u64) {
        let mut s = seed;
        let mut next = move || {
            // SplitMix64 → [0, 1).
            s = s.wrapping_add(0x9e37_79b9_7f4a_7c15);
            let mut z = s;
            z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
            ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
        };
        let tol = default_tol::<T>();
        for k in 0..4000 {
            // (x − r₁)(x − r₂)(x − r₃) with roots in [−0.2, 1.2], one of them doubled at times.
            let mut r = [next() * 1.4 - 0.2, next() * 1.4 - 0.2, next() * 1.4 - 0.2];
            if next() < 0.2 {
                r[1] = r[0];
            }
            let c = [-r[0] * r[1] * r[2], r[0] * r[1] + r[0] * r[2] + r[1] * r[2], -(r[0] + r[1] + r[2]), 1.0];
            let c: [T; 4] = c.map(T::from_f64);
            let d = [c[1], c[2] * T::from_f64(2.0), c[3] * T::from_f64(3.0)];
            let e = [d[1], d[2] * T::from_f64(2.0)];
            let f = move |x: T| horner(&c, x);
            let df = move |x: T| horner(&d, x);
            let d2f = move |x: T| horner(&e, x);
            let mut br = || {
                let (a, b) = (next(), next());
                let (a, b) = (T::from_f64(a.min(b)), T::from_f64(a.max(b)));
                [a, b, f(a), f(b)]
            };
            let (p, q) = (br(), br());
            let (vp, vq) = (opposite(p[2], p[3]), opposite(q[2], q[3]));
            let h = k % 2 == 1;
            let single = [
                halley_or_newton(f, df, d2f, h, p, T::cst(f64::NAN), vp, tol),
                halley_or_newton(f, df, d2f, h, q, T::cst(f64::NAN), vq, tol),
            ];
            let br2 = [[p[0], q[0]], [p[1], q[1]], [p[2], q[2]], [p[3], q[3]]];
            let pair = pair_of(f, df, d2f, h, br2, [T::cst(f64::NAN); 2], [vp, vq], tol);
            assert_eq!(single.map(|x| x.to_f64().to_bits()), pair.map(|x| x.to_f64().to_bits()), "halley {h} {r:?}");
        }
    }
    check::<f32>(1);
    check::<f64>(2);
}

/// Halley's step is taken only where it is within [⅔, 2] times Newton's: on `x⁴ − c` over
/// `[0, 1]` with `c = 10⁻¹⁶` the regula-falsi start is `≈ c`, next to the end where `f' = 0`,
/// and there Halley's step is `≈ −2f'/f'' = 2x/3`, below `tol` (f64: 8.9e-16) — an unguarded
/// solve stops at `≈ 1.7·10⁻¹⁶`, 10⁻⁴ from the root `c^¼`. Guarded, it must find the root to
/// the tolerance (Newton's own error bound there: a few `tol`).
#[test]
fn halley_is_not_fooled_by_a_flat_end() {
    let c = 1e-16f64;
    let f = |x: f64| x * x * x * x - c;
    let df = |x: f64| 4.0 * x * x * x;
    let d2f = |x: f64| 12.0 * x * x;
    let tol = default_tol::<f64>();
    let x = halley(f, df, d2f, [0.0, 1.0, f(0.0), f(1.0)], f64::NAN, true, tol);
    assert!((x - 1e-4).abs() <= 4.0 * tol, "{x:e}");
}
