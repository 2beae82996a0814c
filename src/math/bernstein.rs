//! Polynomials in Bernstein form on `[0, 1]`: products, de Casteljau subdivision and
//! evaluation, and root isolation by the sign-variation count (the spline kernel's `P`,
//! issue 10's cost).
//!
//! A polynomial of degree `n` is `p(x) = Σ bₖ·C(n,k)·xᵏ(1−x)ⁿ⁻ᵏ`. Facts used:
//! * **Products** are exact small formulas: `(a·b)ₖ = Σ_{i+j=k} C(m,i)C(n,j)/C(m+n,k)·aᵢbⱼ`
//!   (positive weights summing to 1 over each `k`), so a coefficient of a product carries a
//!   rounding of a few `ε` of `Σ|aᵢbⱼ|` over its terms — no power-basis expansion, no
//!   cancellation beyond the data's own.
//! * **de Casteljau** at `½` gives the coefficients on both halves by averages (convex
//!   combinations: each new coefficient is within `nε·max|bₖ|` of the exact restriction of
//!   the computed polynomial).
//! * **Descartes' rule for Bernstein form**: the number of roots in the open interval
//!   `(0, 1)`, with multiplicity, is at most the number `V` of sign changes of `b₀ … bₙ`
//!   (zeros skipped) and has its parity. `V = 0`: no root; `V = 1`: exactly one, simple, and
//!   `b₀`, `bₙ` (the end values) differ in sign — a bracket. After enough halvings an interval
//!   with `V ≥ 2` around separated simple roots splits into `V ≤ 1` pieces (the variation
//!   diminishing property: `V` of a sub-interval's coefficients tends to the true root count
//!   as its width → 0, quadratically).
//!
//! [`isolate`] runs that on scalars (a data-dependent tree: lanes run it lane by lane, see the
//! spline kernel), depth- and work-limited; what it does at the limits is documented there.

use crate::real::{Real, Scalar};

/// `C(n, k)` for the small degrees used here.
#[inline(always)]
const fn binom(n: usize, k: usize) -> usize {
    let mut r = 1;
    let mut i = 0;
    while i < k {
        r = r * (n - i) / (i + 1);
        i += 1;
    }
    r
}

/// Bernstein coefficients of the product of two polynomials in Bernstein form (degrees
/// `N − 1` and `M − 1`, `K = N + M − 1`).
#[inline(always)]
pub fn mul<T: Real, const N: usize, const M: usize, const K: usize>(a: &[T; N], b: &[T; M]) -> [T; K] {
    debug_assert!(K + 1 == N + M);
    let (m, n) = (N - 1, M - 1);
    let mut c = [T::zero(); K];
    for i in 0..N {
        for j in 0..M {
            let w = binom(m, i) * binom(n, j);
            let ab = a[i] * b[j];
            c[i + j] += if w == 1 { ab } else { ab * T::cst(w as f64) };
        }
    }
    for (k, ck) in c.iter_mut().enumerate() {
        let w = binom(m + n, k);
        if w != 1 {
            *ck = *ck / T::cst(w as f64);
        }
    }
    c
}

/// The coefficients on `[0, ½]` and `[½, 1]` (de Casteljau at `½`: exact halvings).
#[inline(always)]
pub fn split_half<T: Scalar, const N: usize>(p: &[T; N]) -> ([T; N], [T; N]) {
    let half = T::cst(0.5);
    let (mut l, mut r) = ([T::zero(); N], [T::zero(); N]);
    let mut b = *p;
    for k in 0..N {
        l[k] = b[0];
        r[N - 1 - k] = b[N - 1 - k];
        for i in 0..N - 1 - k {
            b[i] = (b[i] + b[i + 1]) * half;
        }
    }
    (l, r)
}

/// `(p(x), p'(x))` by de Casteljau (the last level's difference gives the derivative).
#[inline(always)]
pub fn eval_d<T: Scalar, const N: usize>(p: &[T; N], x: T) -> (T, T) {
    let s = T::one() - x;
    let mut b = *p;
    for k in 1..N - 1 {
        for i in 0..N - k {
            b[i] = b[i] * s + b[i + 1] * x;
        }
    }
    let v = b[0] * s + b[1] * x;
    (v, (b[1] - b[0]) * T::cst((N - 1) as f64))
}

/// Sign changes of `p` (zeros skipped).
#[inline(always)]
pub fn variations<T: Scalar, const N: usize>(p: &[T; N]) -> u32 {
    let mut v = 0;
    let mut last = T::zero();
    for &c in p {
        if c != T::zero() {
            if (c > T::zero()) != (last > T::zero()) && last != T::zero() {
                v += 1;
            }
            last = c;
        }
    }
    v
}

/// The single root in `(0, 1)` of `p` with `p₀·pₙ < 0`: safeguarded Newton (a Newton step
/// where it falls strictly inside the shrinking bracket, bisection otherwise) from the
/// regula-falsi point, until a step or the bracket is at most `tol`.
#[inline(always)]
pub fn refine<T: Scalar, const N: usize>(p: &[T; N], tol: T) -> T {
    let (zero, one, half) = (T::zero(), T::one(), T::cst(0.5));
    let (p0, pn) = (p[0], p[N - 1]);
    let neg0 = p0 < zero;
    let (mut a, mut b) = (zero, one);
    let mut x = (p0 / (p0 - pn)).clamp(zero, one);
    for _ in 0..super::roots::MAX_ITER {
        let (v, dv) = eval_d(p, x);
        if v == zero {
            return x;
        }
        if (v < zero) == neg0 {
            a = x;
        } else {
            b = x;
        }
        let xn = x - v / dv;
        let xn = if xn > a && xn < b { xn } else { (a + b) * half };
        let step = (xn - x).abs();
        x = xn;
        if step <= tol || b - a <= tol {
            break;
        }
    }
    x
}

/// Deepest halving of [`isolate`]: intervals `2⁻¹⁶` of the piece wide.
pub const MAX_DEPTH: u32 = 16;
/// Most sub-intervals [`isolate`] examines (a bound on its work where rounding makes `P`'s
/// signs noise: see the spline kernel's "Candidates").
pub const MAX_NODES: u32 = 128;

/// Candidates for the roots of `p` (degree 6, Bernstein form on `[a, b]`) in `[a, b]`,
/// appended to `out[*n..]` (at most `out.len()` in all; the rest are dropped): by halving
/// while the sign-variation count is `≥ 2`,
/// * `V = 0`: no root;
/// * `V = 1` with non-zero ends: the root, refined by [`refine`] to `tol` (in `t`);
/// * a zero end coefficient: that end (an exact root of the computed polynomial);
/// * `V ≥ 2` at [`MAX_DEPTH`] or past [`MAX_NODES`]: the interval's midpoint (every root
///   inside is within half the interval of it).
pub fn isolate<T: Scalar>(p: &[T; 7], a: T, b: T, tol: T, out: &mut [T], n: &mut usize) {
    let half = T::cst(0.5);
    let mut push = |t: T, n: &mut usize| {
        if *n < out.len() {
            out[*n] = t;
            *n += 1;
        }
    };
    // Depth-first, left to right: a stack of (coefficients, lo, hi, depth).
    let mut stack = [([T::zero(); 7], a, b, 0u32); MAX_DEPTH as usize + 2];
    stack[0].0 = *p;
    let mut top = 1;
    let mut nodes = 0;
    while top > 0 {
        top -= 1;
        let (c, lo, hi, depth) = stack[top];
        nodes += 1;
        if c[0] == T::zero() {
            push(lo, n);
        }
        if c[6] == T::zero() {
            push(hi, n);
        }
        let v = variations(&c);
        if v == 0 {
            continue;
        }
        let w = hi - lo;
        if v == 1 && c[0] != T::zero() && c[6] != T::zero() {
            let x = refine(&c, tol / w);
            push((lo + x * w).clamp(lo, hi), n);
        } else if depth >= MAX_DEPTH || nodes >= MAX_NODES {
            push((lo + hi) * half, n);
        } else {
            let (l, r) = split_half(&c);
            let mid = (lo + hi) * half;
            stack[top] = (r, mid, hi, depth + 1);
            stack[top + 1] = (l, lo, mid, depth + 1);
            top += 2;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Bernstein coefficients of `∏ (x − rₖ)` (degree 6) by products of linear factors
    /// `x − r = (−r)·B₀ + (1 − r)·B₁`.
    fn from_roots(r: [f64; 6]) -> [f64; 7] {
        let f = |x: f64| [-x, 1.0 - x];
        let q2: [f64; 3] = mul(&f(r[0]), &f(r[1]));
        let q3: [f64; 4] = mul(&q2, &f(r[2]));
        let q4: [f64; 5] = mul(&q3, &f(r[3]));
        let q5: [f64; 6] = mul(&q4, &f(r[4]));
        mul(&q5, &f(r[5]))
    }

    #[test]
    fn products_evaluate_to_products() {
        let a = [0.3, -1.2, 2.0];
        let b = [1.5, 0.25, -0.7, 0.1, 3.0];
        let c: [f64; 7] = mul(&a, &b);
        for k in 0..=10 {
            let x = k as f64 / 10.0;
            let want = eval_d(&a, x).0 * eval_d(&b, x).0;
            // Each side is a few roundings of terms ≤ 3·3: 1e-14 is ~50ε of them.
            assert!((eval_d(&c, x).0 - want).abs() < 1e-14, "x = {x}");
        }
    }

    #[test]
    fn split_halves_agree_with_the_whole() {
        let p = from_roots([0.05, 0.2, 0.21, 0.5, 0.77, 0.9]);
        let (l, r) = split_half(&p);
        for k in 0..=8 {
            let x = k as f64 / 8.0;
            let (vl, vr) = (eval_d(&l, x).0, eval_d(&r, x).0);
            assert!((vl - eval_d(&p, x * 0.5).0).abs() < 1e-15);
            assert!((vr - eval_d(&p, 0.5 + x * 0.5).0).abs() < 1e-15);
        }
    }

    #[test]
    fn isolates_simple_clustered_and_double_roots() {
        let tol = 4.0 * f64::EPSILON;
        // Six simple roots, a pair 10⁻³ apart, a pair 10⁻⁹ apart (below 2⁻¹⁶: one midpoint).
        for (roots, within) in [
            ([1.0, 2.0, 3.0, 4.0, 5.0, 6.0].map(|k: f64| k / 7.0), 1e-13),
            ([0.1, 0.4, 0.401, 0.6, 0.8, 0.95], 1e-12),
            ([0.1, 0.3, 0.3 + 1e-9, 0.6, 0.8, 0.95], 2f64.powi(-17)),
            ([0.2, 0.2, 0.5, 0.5, 0.7, 0.71], 2f64.powi(-17)),
        ] {
            let p = from_roots(roots);
            let mut out = [0.0; 16];
            let mut n = 0;
            isolate(&p, 0.0, 1.0, tol, &mut out, &mut n);
            for r in roots {
                let best = out[..n].iter().map(|x| (x - r).abs()).fold(f64::INFINITY, f64::min);
                // A simple root: Newton to 4ε plus the root's condition (|p'| ≥ 1e-6 here,
                // rounding 1e-17 → 1e-11 at worst, below `within`); a pair or double root
                // closer than the deepest interval: that interval's midpoint (≤ 2⁻¹⁷).
                assert!(best < within, "{roots:?}: root {r} missed, candidates {:?}", &out[..n]);
            }
        }
        // No root: no candidate.
        let p = from_roots([-1.0, -2.0, 1.5, 2.0, 3.0, -0.5]);
        let (mut out, mut n) = ([0.0; 16], 0);
        isolate(&p, 0.0, 1.0, tol, &mut out, &mut n);
        assert_eq!(n, 0, "{:?}", &out[..n]);
    }
}
