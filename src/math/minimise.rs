//! One-dimensional minimisation.

use crate::real::Scalar;

/// Golden-section search for a minimum of `f` on `[lo, hi]` (one critical point there).
///
/// Stops when the bracket is at most `tol` wide or after `max_iter` steps. Returns `best`
/// lowered by every value of `f` seen in those steps (`best.min(f₁).min(f₂)` after each, in
/// that order), so the result is always a value of `f` or `best`: a minimum can only improve.
#[inline]
pub(crate) fn golden_section_min<T: Scalar>(f: impl Fn(T) -> T, lo: T, hi: T, tol: T, max_iter: u32, best: T) -> T {
    let gr = T::cst(0.618_033_988_749_894_8);
    let (mut lo, mut hi, mut best) = (lo, hi, best);
    let mut x1 = hi - gr * (hi - lo);
    let mut x2 = lo + gr * (hi - lo);
    let (mut f1, mut f2) = (f(x1), f(x2));
    for _ in 0..max_iter {
        if hi - lo <= tol {
            break;
        }
        if f1 < f2 {
            hi = x2;
            x2 = x1;
            f2 = f1;
            x1 = hi - gr * (hi - lo);
            f1 = f(x1);
        } else {
            lo = x1;
            x1 = x2;
            f1 = f2;
            x2 = lo + gr * (hi - lo);
            f2 = f(x2);
        }
        best = best.min(f1).min(f2);
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_parabola_minimum() {
        // f(x) = (x − 0.3)² + 2 on [0, 1]: the bracket shrinks to ≤ 1e-9, so the best value is
        // within (1e-9)² of 2 (plus the rounding of f, ≈ 2ε·2).
        let m = golden_section_min(|x: f64| (x - 0.3) * (x - 0.3) + 2.0, 0.0, 1.0, 1e-9, 100, f64::INFINITY);
        assert!((m - 2.0).abs() <= 1e-15, "{m}");
        // `best` lower than every value of f is returned unchanged.
        assert_eq!(golden_section_min(|x: f64| x * x, -1.0, 1.0, 1e-9, 100, -1.0), -1.0);
        // No step taken (bracket already narrower than tol): `best` unchanged.
        assert_eq!(golden_section_min(|x: f64| x, 0.0, 1e-12, 1e-9, 100, 5.0), 5.0);
    }
}
