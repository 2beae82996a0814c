//! Certified root counting for polynomials of degree ≤ 6: Bernstein coefficients on an
//! interval with a bound on their rounding, and Descartes' rule of signs on them.
//!
//! # Descartes' rule in the Bernstein basis
//! If `p(a + w·x) = Σ bᵢ Bᵢ(x)` (`Bᵢ` the Bernstein polynomials of degree `n` on `[0, 1]`), the
//! number of roots of `p` in `(a, a + w)`, counted with multiplicity, is at most the number
//! `V` of sign variations of `b₀, …, bₙ`, and `V` minus it is even (the rule for
//! `(1 + y)ⁿ p((a + (a + w) y)/(1 + y))`, whose power coefficients are `C(n, i)·bᵢ`).
//!
//! # Rounding
//! [`bernstein_on`] forms `b` by a Taylor shift, a scaling and the basis change, all sums of
//! products. Every computed value of such an expression differs from the exact one by at most
//! `γₖ = kε/(1 − kε)` times the same expression evaluated on absolute values, `k` the number of
//! operations on the longest path (Higham, *Accuracy and Stability of Numerical Algorithms*,
//! §3.1–3.3). The caller passes `cabs`, an upper bound of that absolute-value expression for its
//! coefficients (the chain that formed them), and [`bernstein_on`] continues the chain: the
//! Taylor shift has ≤ 12 operations on a path, the scaling ≤ 7 (the power `wᵏ` and the
//! product), the basis change ≤ 14 (seven products and their sum); each halving by de Casteljau
//! (`crate::math::bezier::split_half`, at most four in the spline kernel) adds six averages. With the caller's chain
//! below 25 operations (the spline's `P`), `k ≤ 25 + 12 + 7 + 14 + 24 = 82 < 100` and
//! `γₖ < 101ε` in either precision (`kε ≤ 1.2e-5`), so a coefficient with `|bᵢ| > 128ε·mᵢ`
//! ([`ROUNDING`]) has the sign of the exact one; halving `m` by the same averages keeps it a
//! bound of the halves' chains.
//! [`max_sign_variations`] counts every other coefficient as either sign.

use crate::real::Real;

/// Multiple of `ε·mᵢ` beyond which a computed Bernstein coefficient's sign is certain (module
/// docs: `γₖ < 101ε` for the ≤ 100 operations on any path).
pub(crate) const ROUNDING: f64 = 128.0;

/// `C(i, j)/C(6, j)` for `j ≤ i ≤ 6`: the power → Bernstein change of basis of degree 6
/// (`bᵢ = Σⱼ C(i, j)/C(6, j)·cⱼ`).
const TO_BERNSTEIN6: [[f64; 7]; 7] = {
    const fn binom(n: usize, k: usize) -> f64 {
        let mut c = 1.0;
        let mut i = 0;
        while i < k {
            c = c * (n - i) as f64 / (i + 1) as f64;
            i += 1;
        }
        c
    }
    let mut m = [[0.0; 7]; 7];
    let mut i = 0;
    while i < 7 {
        let mut j = 0;
        while j <= i {
            m[i][j] = binom(i, j) / binom(6, j);
            j += 1;
        }
        i += 1;
    }
    m
};

/// The Bernstein coefficients `b` of `p(s + w·x)` on `x ∈ [0, 1]` (`p` of degree 6, ascending
/// powers `c`), and `m`, the same operations on `cabs` (an upper bound of the absolute-value
/// chain of `c`, see the module docs), `|s|` and `|w|`: `|b − b_exact| ≤ γ·m`.
#[inline(always)]
pub(crate) fn bernstein_on<T: Real>(c: &[T; 7], cabs: &[T; 7], s: T, w: T) -> ([T; 7], [T; 7]) {
    let (mut c, mut m) = (*c, *cabs);
    let sa = s.abs();
    // Taylor shift p(s + y): repeated synthetic division.
    for i in 0..6 {
        for j in (i..6).rev() {
            c[j] += s * c[j + 1];
            m[j] += sa * m[j + 1];
        }
    }
    // Scale y = w·x.
    let wa = w.abs();
    let (mut wk, mut wka) = (w, wa);
    for k in 1..7 {
        c[k] *= wk;
        m[k] *= wka;
        wk *= w;
        wka *= wa;
    }
    let mut b = [T::zero(); 7];
    let mut bm = [T::zero(); 7];
    for i in 0..7 {
        for j in 0..=i {
            let k = T::cst(TO_BERNSTEIN6[i][j]);
            b[i] += k * c[j];
            bm[i] += k * m[j];
        }
    }
    (b, bm)
}

/// The most sign variations that the exact coefficients can have, given computed `b` within
/// `ROUNDING·ε·m` of them: a coefficient inside that band may have either sign (or be zero,
/// which the rule skips; counting it as either sign never gives fewer variations).
#[inline(always)]
pub(crate) fn max_sign_variations<T: Real>(b: &[T; 7], m: &[T; 7]) -> T {
    let (one, ninf) = (T::one(), -T::infinity());
    let k = T::cst(ROUNDING) * T::epsilon();
    // The most variations of a prefix that ends in a positive (vp) or negative (vn) sign;
    // −∞ where the prefix cannot end so.
    let (mut vp, mut vn) = (ninf, ninf);
    for i in 0..7 {
        let e = k * m[i];
        let pos = b[i].gt(e);
        let neg = b[i].lt(-e);
        let (cp, cn) = (!neg, !pos);
        let (sp, sn) = if i == 0 { (T::zero(), T::zero()) } else { (vp.max(vn + one), vn.max(vp + one)) };
        vp = T::select(cp, sp, ninf);
        vn = T::select(cn, sn, ninf);
    }
    vp.max(vn)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// p = ∏ (x − rᵢ) in ascending powers.
    fn from_roots(r: &[f64]) -> [f64; 7] {
        let mut c = [0.0; 7];
        c[0] = 1.0;
        for &x in r {
            let mut n = [0.0; 7];
            for i in 0..7 {
                n[i] -= x * c[i];
                if i > 0 {
                    n[i] += c[i - 1];
                }
            }
            c = n;
        }
        c
    }

    #[test]
    fn bernstein_coefficients_interpolate_the_ends_and_count_roots() {
        // Six roots; on [0.05, 0.95] all six, on [0.05, 0.2] one, on [0.95, 1.2] none.
        let c = from_roots(&[0.1, 0.25, 0.4, 0.55, 0.7, 0.85]);
        let cabs = c.map(f64::abs);
        let eval = |x: f64| c.iter().rev().fold(0.0, |a, &k| a * x + k);
        for (a, b, roots) in [(0.05, 0.95, 6.0), (0.05, 0.2, 1.0), (0.95, 1.2, 0.0)] {
            let (bc, m) = bernstein_on(&c, &cabs, a, b - a);
            // b₀ = p(a), b₆ = p(b): exact values to rounding (|p| ≤ 1 here).
            assert!((bc[0] - eval(a)).abs() < 1e-15 && (bc[6] - eval(b)).abs() < 1e-14, "{bc:?}");
            let v = max_sign_variations(&bc, &m);
            // Descartes: V ≥ roots with even excess; V == roots for these well-separated roots
            // on intervals short against their spacing or holding them all.
            assert!(v >= roots && (v - roots) % 2.0 == 0.0, "[{a}, {b}]: V = {v}, roots {roots}");
        }
        // A single simple root in [0, 1] for a line: exactly one variation.
        let (bc, m) = bernstein_on(&from_roots(&[0.3]), &from_roots(&[-0.3]), 0.0, 1.0);
        assert_eq!(max_sign_variations(&bc, &m), 1.0);
    }

    #[test]
    fn uncertain_coefficients_count_as_either_sign() {
        // + ? + : at most two variations; + ? − : one; ? alone: none.
        let m = [1.0; 7];
        let z = 0.0;
        assert_eq!(max_sign_variations(&[1.0, 1.0, 1.0, z, 1.0, 1.0, 1.0], &m), 2.0);
        assert_eq!(max_sign_variations(&[1.0, 1.0, 1.0, z, -1.0, -1.0, -1.0], &m), 1.0);
        assert_eq!(max_sign_variations(&[z, z, 1.0, 1.0, 1.0, 1.0, 1.0], &m), 2.0);
        assert_eq!(max_sign_variations(&[1.0, -1.0, 1.0, -1.0, 1.0, -1.0, 1.0], &m), 6.0);
        // Within the band: 1e-14 against m = 1 is below 128ε.
        assert_eq!(max_sign_variations(&[1.0, 1.0, 1e-14, -1e-14, 1.0, 1.0, 1.0], &m), 2.0);
        // A certain sign just outside it.
        assert_eq!(max_sign_variations(&[1.0, 1.0, 1.0, -1e-13, 1.0, 1.0, 1.0], &m), 2.0);
        assert_eq!(max_sign_variations(&[1.0, 1.0, 1.0, 1e-13, 1.0, 1.0, 1.0], &m), 0.0);
    }
}
