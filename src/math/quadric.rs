//! Quadric roots: the quadratic formula in its stable forms, clipped to a slab, and the
//! ray–sphere chord.

use crate::real::{Mask, Real};
use crate::vec::V3;

/// `q = −(b + sign(b)·√disc)` of the citardauq form: `b` and `sign(b)·√disc` never cancel, and
/// `q = 0` only if `b = 0` and `disc = 0`.
#[inline(always)]
fn citardauq_q<T: Real>(b: T, sq: T) -> T {
    -(b + sq.copysign_of(b))
}

/// The set `{t : F(t) ≤ 0}` of `F(t) = a·t² + 2b·t + c` within `[lo, hi]`, as
/// [`quadric_in_slab`] returns it (a single interval: the callers' solids are convex).
#[derive(Clone, Copy, Debug)]
pub(crate) struct SlabInterval<T: Real> {
    /// Start of the interval.
    pub t0: T,
    /// End of the interval.
    pub t1: T,
    /// Lanes whose start is a root of `F` (a crossing of the curved surface) rather than `lo`
    /// (a cap plane).
    pub root0: T::Mask,
    /// Lanes whose end is a root of `F` rather than `hi`.
    pub root1: T::Mask,
    /// Lanes where the interval is non-empty.
    pub ok: T::Mask,
}

/// `{t : a·t² + 2b·t + c ≤ 0} ∩ [lo, hi]` (known to be a single interval because the caller's
/// solid is convex).
#[inline(always)]
pub(crate) fn quadric_in_slab<T: Real>(a: T, b: T, c: T, lo: T, hi: T) -> SlabInterval<T> {
    quadric_in_slab_disc(a, b, c, b * b - a * c, lo, hi)
}

/// [`quadric_in_slab`] with the discriminant `b² − a·c` supplied by a caller that can form it
/// without cancellation.
#[inline(always)]
pub(crate) fn quadric_in_slab_disc<T: Real>(a: T, b: T, c: T, disc: T, lo: T, hi: T) -> SlabInterval<T> {
    let zero = T::zero();
    let no = T::Mask::splat(false);
    let real = disc.ge(zero);
    let sq = disc.max(zero).sqrt();
    // Citardauq form: no cancellation. q = 0 only if b = 0 and disc = 0.
    let q = citardauq_q(b, sq);
    let q_nz = !q.eq(zero);
    let a_nz = !a.eq(zero);
    let r1 = q / T::select(a_nz, a, T::one());
    let r2 = c / T::select(q_nz, q, T::one());
    // Citardauq keeps the small root accurate when the roots differ greatly in size (b² ≫ |ac|,
    // e.g. a ray nearly parallel to a generator). When they are of comparable size its C/q can
    // be noise over noise: near a tangency q = −(b ± √disc) is tiny and C carries its own
    // rounding, inconsistent with a discriminant the caller formed without cancellation. There
    // −b/a ± √disc/|a| is accurate to ε·|b/a| ≲ 4ε·√|c/a|, i.e. to ε of the roots' size.
    let far_apart = (b * b).gt(T::cst(16.0) * (a * c).abs());
    let mid = -b / T::select(a_nz, a, T::one());
    let half = sq / T::select(a_nz, a, T::one()).abs();
    let r1 = T::select(far_apart, r1, mid - half);
    let r2 = T::select(far_apart, r2, mid + half);
    let (rl, rh) = (r1.min(r2), r1.max(r2));

    // a > 0: inside = [rl, rh] (empty without real roots).
    let pos = a.gt(zero);
    let (p0, p1) = (lo.max(rl), hi.min(rh));
    let (pq0, pq1) = (rl.ge(lo), rh.le(hi));
    let pos_ok = real & q_nz & p0.le(p1);

    // a < 0: inside = (−∞, rl] ∪ [rh, ∞) (the whole line without real roots); only one
    // piece can meet the slab of a convex stump, take the non-empty (longer) one.
    let neg = a.lt(zero);
    let ra = real & q_nz;
    let (a0, a1) = (lo, T::select(ra, hi.min(rl), hi));
    let (b0, b1) = (T::select(ra, lo.max(rh), lo), hi);
    let (ok_a, ok_b) = (a0.le(a1), b0.le(b1));
    let take_a = ok_a & (!ok_b | (a1 - a0).ge(b1 - b0));
    let (n0, n1) = (T::select(take_a, a0, b0), T::select(take_a, a1, b1));
    let nq0 = !take_a & ra & rh.ge(lo);
    let nq1 = take_a & ra & rl.le(hi);
    let neg_ok = ok_a | ok_b;

    // a = 0: 2b·t + c ≤ 0, root −c/(2b).
    let lin = !a_nz;
    let b_pos = b.gt(zero);
    let b_neg = b.lt(zero);
    let root = -c / T::select(b_pos | b_neg, b + b, T::one());
    let l0 = T::select(b_neg, lo.max(root), lo);
    let l1 = T::select(b_pos, hi.min(root), hi);
    let lin_ok = l0.le(l1) & ((b_pos | b_neg) | c.le(zero));
    let lq0 = b_neg & root.ge(lo);
    let lq1 = b_pos & root.le(hi);

    SlabInterval {
        t0: T::select(lin, l0, T::select(neg, n0, p0)),
        t1: T::select(lin, l1, T::select(neg, n1, p1)),
        root0: (lin & lq0) | (neg & nq0) | (pos & pq0),
        root1: (lin & lq1) | (neg & nq1) | (pos & pq1),
        ok: (lin & lin_ok) | (neg & neg_ok) | (pos & pos_ok) | no,
    }
}

/// Slab `{t : lo ≤ z0 + t·zd ≤ hi}` as `[t0, t1]` (empty as `t0 > t1`).
#[inline(always)]
pub(crate) fn slab<T: Real>(z0: T, zd: T, lo: T, hi: T) -> (T, T) {
    let zero = T::zero();
    let inf = T::infinity();
    let par = zd.eq(zero);
    let inv = T::one() / T::select(par, T::one(), zd);
    let ta = (lo - z0) * inv;
    let tb = (hi - z0) * inv;
    let inside = z0.ge(lo) & z0.le(hi);
    let t0 = T::select(par, T::select(inside, -inf, inf), ta.min(tb));
    let t1 = T::select(par, T::select(inside, inf, -inf), ta.max(tb));
    (t0, t1)
}

/// The real roots of `c₀ + c₁x + c₂x²` clamped into `[lo, hi]`, sorted. Missing roots (no
/// real root, or a linear/constant polynomial) are returned as `hi`, which keeps the pair a
/// valid set of breakpoints for [`crate::math::roots::cascade_level`]. Never NaN for finite
/// input.
#[inline(always)]
pub fn quadratic_roots_in<T: Real>(c: &[T; 3], lo: T, hi: T) -> (T, T) {
    let (a, b, cc) = (c[2], c[1], c[0]);
    let zero = T::zero();
    let disc = b * b - T::cst(4.0) * a * cc;
    let has2 = disc.ge(zero) & a.abs().gt(zero);
    // q = −(b + sign(b)·√disc)/2: no cancellation; x₁ = q/a, x₂ = c/q.
    let q = citardauq_q(b, disc.max(zero).sqrt()) * T::cst(0.5);
    let qs = T::select(q.eq(zero), T::one(), q);
    let a_s = T::select(has2, a, T::one());
    let x1 = T::select(has2, q / a_s, hi);
    let x2 = T::select(has2 & q.abs().gt(zero), cc / qs, T::select(has2, x1, hi));
    // Linear case: one root −c/b.
    let lin = a.eq(zero) & b.abs().gt(zero);
    let bl = T::select(lin, b, T::one());
    let x1 = T::select(lin, -cc / bl, x1);
    let x1 = x1.clamp(lo, hi);
    let x2 = x2.clamp(lo, hi);
    (x1.min(x2), x1.max(x2))
}

/// The chord of a ray's line through the ball `|x − c| ≤ r`, in units of length along the
/// unit direction, about the line's point closest to `c` ([`sphere_chord`]).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Chord<T: Real> {
    /// Parameter `τ` (along the unit direction) of the point of the line closest to `c`.
    pub tc: T,
    /// Half chord: the line is inside the ball for `τ ∈ [tc − h, tc + h]`.
    pub h: T,
    /// The perpendicular from `c` to the line (closest point − `c`).
    pub l: V3<T>,
    /// Lanes where the line meets the ball (and `r > 0`).
    pub ok: T::Mask,
}

/// The chord of the line `o + τ·dn` (`dn` unit) through the ball `(c, r)`: closest point to the
/// centre first, then the half chord from the perpendicular, so there is no `|o − c|² − (·)²`
/// cancellation for far origins ("Ray Tracing Gems" ch. 7).
#[inline(always)]
pub(crate) fn sphere_chord<T: Real>(o: V3<T>, dn: V3<T>, c: V3<T>, r: T) -> Chord<T> {
    let f = o - c;
    // τ of the closest point of the line to c.
    let tc = -f.dot(dn);
    // Perpendicular from c to the line (accurate: no |f|² − (f·d)² cancellation).
    let l = f + dn * tc;
    let disc = r * r - l.length2();
    let ok = disc.ge(T::zero()) & r.gt(T::zero());
    let h = disc.max(T::zero()).sqrt();
    Chord { tc, h, l, ok }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quadratic_roots_sorted_and_clamped() {
        // (x − 0.25)(x − 0.75) = x² − x + 0.1875
        let (a, b) = quadratic_roots_in(&[0.1875f64, -1.0, 1.0], 0.0, 1.0);
        assert!((a - 0.25).abs() < 1e-15 && (b - 0.75).abs() < 1e-15);
        let (a, b) = quadratic_roots_in(&[1.0f64, 0.0, 1.0], 0.0, 1.0);
        assert_eq!((a, b), (1.0, 1.0));
        let (a, b) = quadratic_roots_in(&[-0.5f64, 1.0, 0.0], 0.0, 1.0);
        assert_eq!((a, b), (0.5, 1.0));
        let (a, b) = quadratic_roots_in(&[0.0f64, 0.0, 0.0], 0.0, 1.0);
        assert!(a.is_finite() && b.is_finite());
    }

    #[test]
    fn slab_quadric_cases() {
        // t² − 1 ≤ 0 in [−0.5, 2]: [−0.5, 1], start on the cap, end a root.
        let s = quadric_in_slab(1.0f64, 0.0, -1.0, -0.5, 2.0);
        assert!(s.ok && !s.root0 && s.root1);
        assert_eq!((s.t0, s.t1), (-0.5, 1.0));
        // −t² + 1 ≤ 0 (outside [−1, 1]) in [0, 3]: [1, 3], start a root.
        let s = quadric_in_slab(-1.0f64, 0.0, 1.0, 0.0, 3.0);
        assert!(s.ok && s.root0 && !s.root1);
        assert_eq!((s.t0, s.t1), (1.0, 3.0));
        // Linear 2·t − 1 ≤ 0 (a = 0, b = 1) in [0, 4]: [0, 0.5].
        let s = quadric_in_slab(0.0f64, 1.0, -1.0, 0.0, 4.0);
        assert!(s.ok && !s.root0 && s.root1);
        assert_eq!((s.t0, s.t1), (0.0, 0.5));
        // No real root with a > 0: empty.
        assert!(!quadric_in_slab(1.0f64, 0.0, 1.0, -5.0, 5.0).ok);
        // Slab of z = 1 + 2t in [0, 2]: t ∈ [−0.5, 0.5]; parallel inside / outside.
        assert_eq!(slab(1.0f64, 2.0, 0.0, 2.0), (-0.5, 0.5));
        assert_eq!(slab(1.0f64, 0.0, 0.0, 2.0), (f64::NEG_INFINITY, f64::INFINITY));
        assert_eq!(slab(3.0f64, 0.0, 0.0, 2.0), (f64::INFINITY, f64::NEG_INFINITY));
    }

    #[test]
    fn chord_of_unit_sphere() {
        // Line x = τ − 5 along x̂, at distance 0.6 from the origin: closest at τ = 5, half chord 0.8.
        let c = sphere_chord(V3::new(-5.0f64, 0.6, 0.0), V3::new(1.0, 0.0, 0.0), V3::zero(), 1.0);
        assert!(c.ok);
        assert_eq!(c.tc, 5.0);
        assert!((c.h - 0.8).abs() <= 4.0 * f64::EPSILON);
        assert!(!sphere_chord(V3::new(0.0f64, 2.0, 0.0), V3::new(1.0, 0.0, 0.0), V3::zero(), 1.0).ok);
    }
}
