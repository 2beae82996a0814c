//! Quadratic Bézier curves with scalar (lane) coefficients: evaluation and extrema over `[0, 1]`.

use crate::real::Real;

/// The Bernstein weights `((1−t)², 2t(1−t), t²)` of a quadratic Bézier at `t`.
#[inline(always)]
pub(crate) fn bernstein2<T: Real>(t: T) -> [T; 3] {
    let s = T::one() - t;
    [s * s, T::cst(2.0) * s * t, t * t]
}

/// Evaluate the quadratic Bézier `(1−t)²c₀ + 2t(1−t)c₁ + t²c₂`.
#[inline(always)]
pub(crate) fn bezier2<T: Real>(c: [T; 3], t: T) -> T {
    let s = T::one() - t;
    c[0] * s * s + c[1] * (T::cst(2.0) * s * t) + c[2] * t * t
}

/// Minimum of a quadratic Bézier over `t ∈ [0, 1]`: at an end or at the vertex (the root of
/// the linear derivative) when that lies inside and is a minimum.
#[inline(always)]
pub(crate) fn bezier2_min<T: Real>(c: [T; 3]) -> T {
    let den = c[0] - c[1] * T::cst(2.0) + c[2];
    let ok = den.gt(T::zero());
    let ts = (c[0] - c[1]) / T::select(ok, den, T::one());
    let inside = ok & ts.gt(T::zero()) & ts.lt(T::one());
    let ts = T::select(inside, ts, T::zero());
    let v = bezier2(c, ts);
    T::select(inside, v.min(c[0]).min(c[2]), c[0].min(c[2]))
}

/// Maximum of a quadratic Bézier over `[0, 1]`.
#[inline(always)]
pub(crate) fn bezier2_max<T: Real>(c: [T; 3]) -> T {
    -bezier2_min([-c[0], -c[1], -c[2]])
}

/// De Casteljau at ½ of Bernstein coefficients of any degree (`N − 1`): the left and right
/// halves' coefficients. Each value is a chain of at most `N − 1` averages (the rounding the
/// callers' bounds count: `crate::math::descartes`, the spline's `g` hull).
#[inline(always)]
pub(crate) fn split_half<T: Real, const N: usize>(b: &[T; N]) -> ([T; N], [T; N]) {
    let half = T::cst(0.5);
    let (mut l, mut r, mut w) = ([T::zero(); N], [T::zero(); N], *b);
    l[0] = w[0];
    r[N - 1] = w[N - 1];
    for k in 1..N {
        for i in 0..N - k {
            w[i] = (w[i] + w[i + 1]) * half;
        }
        l[k] = w[0];
        r[N - 1 - k] = w[N - 1 - k];
    }
    (l, r)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn extrema_against_dense_sampling() {
        // Exact-in-binary cases: vertex inside (min 0 at t = ½), vertex outside, a maximum.
        assert_eq!(bezier2_min([1.0f64, -1.0, 1.0]), 0.0);
        assert_eq!(bezier2_min([0.0f64, 1.0, 3.0]), 0.0);
        assert_eq!(bezier2_max([0.0f64, 2.0, 0.0]), 1.0);
        // Random curves: the extremum is attained (≤ every sample, within the rounding of
        // one evaluation, ≈ 4ε·max|cᵢ|) and no sample is below it.
        let mut s = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 11) as f64 / (1u64 << 53) as f64 * 4.0 - 2.0
        };
        for _ in 0..200 {
            let c = [next(), next(), next()];
            let (lo, hi) = (bezier2_min(c), bezier2_max(c));
            let tol = 8.0 * f64::EPSILON * 2.0;
            let mut best = f64::INFINITY;
            for k in 0..=1000 {
                let v = bezier2(c, k as f64 / 1000.0);
                assert!(v >= lo - tol && v <= hi + tol, "{c:?}: {v} outside [{lo}, {hi}]");
                best = best.min(v);
            }
            // Sampling at spacing 1e-3 misses the vertex by ≤ 5e-4: |c''|/2·(5e-4)² ≤ 1e-6.
            assert!(best - lo <= 1e-6, "{c:?}: min {lo} not attained (best sample {best})");
        }
    }
}
