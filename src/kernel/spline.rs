//! Ray–spline-tube intersection: the sphere sweep `S(p(t), r(t))`, `t ∈ [0, 1]`, of a
//! **quadratic** Bézier position curve and radius curve ([`QuadTube`]; a cubic Hermite segment
//! is split into two of them by [`crate::kernel::hermite`]).
//!
//! # Ray space (Russig §3.2, Salm §3.2)
//! With `d̂ = d/|d|` and `q(t) = p(t) − o`, the ray enters the sphere `t` at `s = h − √g` and
//! leaves it at `h + √g` (`s` = distance along `d̂`), where
//!
//! * `h(t) = q·d̂` — quadratic,
//! * `g(t) = r² − |q|² + (q·d̂)² = r² − |q × d̂|²` — quartic; formed from the cross products,
//!   so no ray-space basis is built and there is no `|q|² − (q·d̂)²` cancellation.
//!
//! The ray origin is first moved to the point of the line closest to `p(½)` (so far origins
//! lose only what representing the origin loses). The entry of the sweep is `min f`,
//! `f = h − √g`, over `{t : g(t) ≥ 0}`, the exit `max e`, `e = h + √g`. Both extrema are at
//! interior critical points or at the segment ends `t = 0, 1` (where the tube continues into
//! the neighbouring segment: a minimum exactly at a joint is a candidate, never missed).
//!
//! # Solvers ([`Solver`])
//! * Russig's cascade ([`Solver::Bisection`], [`Solver::Itp`], [`Solver::Newton`]): real
//!   intervals of `g` by the cascade `g''` (analytic) → `g'` → `g`; on each real interval the
//!   critical points of `f` by `f'''` → `f''` → `f'` (sign functions scaled by powers of `g`
//!   so they stay finite at the interval ends: `F₁ = 2h'√g − g'`,
//!   `F₂ = 4h''g√g − 2g''g + g'²`, `F₃ = −4g'''g² + 6g'g''g − 3g'³`), and the same for the exit
//!   with `h → −h`. This assumes Russig's empirical claim that `f'''` has at most one root per
//!   real interval (`f'` at most three). `tests/spline_claims.rs` tests it: it holds on random
//!   segments, but **fails** on a real interval bounded by the segment ends (a radius
//!   shrinking 600-fold; f''' has two roots, the middle of f''s three roots is the minimum), where
//!   these solvers report a point inside the tube instead of the entry.
//! * [`Solver::Polynomial`]: the critical points of `f` **and** `e` are exactly the roots of
//!   `P = 4h'²g − g'² = (2h'√g − g')(2h'√g + g')` where `g > 0`; all roots of `P` in `[0, 1]`
//!   by the derivative cascade (the union of the roots of `P` formed in powers of `t` and in
//!   powers of `t − t_v`, `t_v` the vertex of the centre line, where a slow curve makes `P`
//!   tiny), then `f` and `e` at every root with `g ≥ 0` (to rounding; `g(1)` formed from the
//!   end itself, exactly 0 for a zero-radius end on the line) and at `t = 0, 1`.
//!   Needs no real intervals and no claim.
//!
//! The kernel returns the hull `[first entry, last exit]` ([`QuadTube::intersect_with`]). A strongly
//! bent segment can be crossed more than once; [`QuadTube::intersect_pieces`] returns one
//! interval per real interval of `g` (each exact: the part of the sweep over a connected
//! `t`-interval meets the line in one interval), which is what CSG needs.

use super::roots::{cascade_level, default_tol, horner, itp, opposite, poly_breakpoints, poly_mul, Bracket, Solver};
use crate::error::GeometryError;
use crate::kernel::link::RoundCone;
use crate::ray::{in_range, Interval, Ray};
use crate::real::{Mask, Real, Scalar};
use crate::vec::V3;

/// A quadratic sphere-swept segment: Bézier control points `b` and control radii `r`;
/// `p(t) = (1−t)²b₀ + 2t(1−t)b₁ + t²b₂`, likewise `r(t)`.
///
/// Build scalar segments with [`QuadTube::new`] (validated: the interpolated radius must not
/// be negative anywhere on `[0, 1]`); lanes with [`QuadTube::from_lanes`]. [`Primitive`](crate::Primitive)
/// gives the ray queries with the default solver ([`Solver::Polynomial`]), the box and the
/// distance.
///
/// ```
/// use tubecast::{Primitive, QuadTube, Ray, Solver, V3};
/// let tube = QuadTube::new(
///     [V3::new(0.0f64, 0.0, 0.0), V3::new(1.0, 1.0, 0.0), V3::new(2.0, 0.0, 0.0)],
///     [0.2, 0.3, 0.2],
/// )?;
/// let ray = Ray::new(V3::new(1.0, 0.5, -5.0), V3::new(0.0, 0.0, 1.0));
/// let iv = tube.intersect(&ray);
/// assert!(iv.hit && iv.t_in < 5.0 && iv.t_out > 5.0);
/// assert_eq!(tube.intersect_with(&ray, Solver::Itp).hit, true);
/// assert!(tube.sdf(ray.at(iv.t_in)).abs() < 1e-12); // on the surface
/// # Ok::<(), tubecast::GeometryError>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QuadTube<T> {
    /// Control points.
    pub b: [V3<T>; 3],
    /// Control radii (`r₁` may be negative as long as `r(t) ≥ 0` on `[0, 1]`).
    pub r: [T; 3],
}

/// Minimum of the quadratic Bézier `(1−t)²c₀ + 2t(1−t)c₁ + t²c₂` over `t ∈ [0, 1]`.
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

/// Evaluate a quadratic Bézier with scalar (lane) coefficients.
#[inline(always)]
pub(crate) fn bezier2<T: Real>(c: [T; 3], t: T) -> T {
    let s = T::one() - t;
    c[0] * s * s + c[1] * (T::cst(2.0) * s * t) + c[2] * t * t
}

impl<T: Scalar> QuadTube<T> {
    /// A validated segment. Errors: non-finite input ([`GeometryError::NonFinite`]), a radius
    /// curve that is negative somewhere on `[0, 1]` ([`GeometryError::NegativeRadius`]), a
    /// radius that is zero everywhere ([`GeometryError::ZeroRadius`]), or an extent whose
    /// square overflows ([`GeometryError::NonFinite`]).
    pub fn new(b: [V3<T>; 3], r: [T; 3]) -> Result<Self, GeometryError> {
        if b.iter().any(|p| !p.is_finite()) {
            return Err(GeometryError::NonFinite { what: "spline control point" });
        }
        if r.iter().any(|x| !x.is_finite()) {
            return Err(GeometryError::NonFinite { what: "spline control radius" });
        }
        if bezier2_min(r) < T::zero() {
            return Err(GeometryError::NegativeRadius);
        }
        if bezier2_max(r) <= T::zero() {
            return Err(GeometryError::ZeroRadius);
        }
        let mut e = T::zero();
        for i in 0..3 {
            e = e.max((b[i] - b[0]).max_abs()).max(r[i].abs());
        }
        // The kernel works in units of the bounding radius (≤ 4e), which it computes from
        // squared lengths: those must not overflow.
        let e2 = e * e * T::cst(64.0);
        if !e2.is_finite() {
            return Err(GeometryError::NonFinite { what: "spline extent (overflows in the kernel)" });
        }
        Ok(Self { b, r })
    }
    /// The straight segment equal to a link: `b₁`, `r₁` at the midpoints (the same sweep as
    /// the round cone, parametrised at the same speed).
    pub fn from_link(l: &RoundCone<T>) -> Result<Self, GeometryError> {
        let h = T::cst(0.5);
        Self::new([l.a, (l.a + l.b) * h, l.b], [l.ra, (l.ra + l.rb) * h, l.rb])
    }
    /// Minimum of `r(t)` over `[0, 1]`.
    pub fn min_radius(&self) -> T {
        bezier2_min(self.r)
    }
    /// Convert the precision.
    pub fn cast<U: Scalar>(&self) -> QuadTube<U> {
        QuadTube {
            b: [self.b[0].cast(), self.b[1].cast(), self.b[2].cast()],
            r: [U::from_f64(self.r[0].to_f64()), U::from_f64(self.r[1].to_f64()), U::from_f64(self.r[2].to_f64())],
        }
    }
}

/// Working data of one ray–segment query in ray space.
struct RaySpace<T: Real> {
    /// `h` coefficients, ascending powers of `t`.
    h: [T; 3],
    /// `g` coefficients.
    g: [T; 5],
    /// Power-basis position relative to the re-centred origin, in units of the bounding
    /// radius: `q = qa t² + qb t + qc`.
    qa: V3<T>,
    qb: V3<T>,
    qc: V3<T>,
    dhat: V3<T>,
    /// Ray parameter of the re-centred origin.
    tc: T,
    /// Bounding radius / |d|: converts a ray-space distance to a ray parameter step.
    inv_dlen: T,
    /// Lanes whose line comes within the bounding sphere.
    near: T::Mask,
    /// `h` and `g` re-expanded about `tv` (coefficients of powers of `t − tv`), for `P`.
    hv: [T; 3],
    gv: [T; 5],
    /// Expansion point of `hv`, `gv`: the vertex of the centre line (least `|p'|`), in `[0, 1]`.
    tv: T,
    /// `g(1) = r₂² − |c₂ × d̂|²` formed directly from the end (not as `Σ gᵢ`, which carries
    /// the rounding of every coefficient): exactly 0 for a zero-radius end on the line.
    g_end: T,
}

/// `h` and `g` (ascending powers of the parameter) from the power-basis position
/// `q = qa x² + qb x + qc` and radius `ra x² + rb x + rc`.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn ray_polys<T: Real>(qa: V3<T>, qb: V3<T>, qc: V3<T>, ra: T, rb: T, rc: T, dhat: V3<T>) -> ([T; 3], [T; 5]) {
    let two = T::cst(2.0);
    let h = [qc.dot(dhat), qb.dot(dhat), qa.dot(dhat)];
    let (wa, wb, wc) = (qa.cross(dhat), qb.cross(dhat), qc.cross(dhat));
    let w2 = [wc.dot(wc), two * wc.dot(wb), wb.dot(wb) + two * wc.dot(wa), two * wb.dot(wa), wa.dot(wa)];
    let r2 = [rc * rc, two * rc * rb, rb * rb + two * rc * ra, two * rb * ra, ra * ra];
    let g = [r2[0] - w2[0], r2[1] - w2[1], r2[2] - w2[2], r2[3] - w2[3], r2[4] - w2[4]];
    (h, g)
}

/// `P = 4h'²g − g'²` from `h`, `g` in powers of one variable.
#[inline(always)]
fn p_of<T: Real>(h: &[T; 3], g: &[T; 5]) -> [T; 7] {
    let two = T::cst(2.0);
    let h1 = [h[1], two * h[2]];
    let g1 = [g[1], two * g[2], T::cst(3.0) * g[3], T::cst(4.0) * g[4]];
    let h1s: [T; 3] = poly_mul(&h1, &h1);
    let a: [T; 7] = poly_mul(&h1s, g);
    let b: [T; 7] = poly_mul(&g1, &g1);
    let mut p = [T::zero(); 7];
    for i in 0..7 {
        p[i] = T::cst(4.0) * a[i] - b[i];
    }
    p
}

impl<T: Real> RaySpace<T> {
    #[inline(always)]
    fn new(tube: &QuadTube<T>, ray: &Ray<T>) -> Self {
        let two = T::cst(2.0);
        let quarter = T::cst(0.25);
        let [b0, b1, b2] = tube.b;
        let m = (b0 + b1 * two + b2) * quarter; // p(½)
        let d2 = ray.d.length2();
        let dlen = d2.sqrt();
        let inv_dlen = T::one() / dlen;
        let dhat = ray.d * inv_dlen;
        let tc = (m - ray.o).dot(ray.d) / d2;
        // l = o' − m, o' the closest point of the line to m.
        let l = (ray.o - m) + ray.d * tc;
        let rmax = tube.r[0].abs().max(tube.r[1].abs()).max(tube.r[2].abs());
        let big = (b0 - m).length().max((b1 - m).length()).max((b2 - m).length()) + rmax;
        let near = l.length2().le(big * big);
        // Work in units of the bounding radius: g, P and the sign functions are products of up
        // to six coordinates, which would over/underflow for large or tiny tubes. (One
        // rounding per coordinate: a relative change of ε, inside the error model.)
        let big_s = T::select(big.gt(T::zero()) & big.is_finite(), big, T::one());
        let inv = T::one() / big_s;
        let (c0, c1, c2) = ((b0 - m - l) * inv, (b1 - m - l) * inv, (b2 - m - l) * inv);
        let qa = c0 - c1 * two + c2;
        let qb = (c1 - c0) * two;
        let qc = c0;
        let [r0, r1, r2] = [tube.r[0] * inv, tube.r[1] * inv, tube.r[2] * inv];
        let (ra, rb, rc) = (r0 - r1 * two + r2, (r1 - r0) * two, r0);
        let (h, g) = ray_polys(qa, qb, qc, ra, rb, rc, dhat);
        // The same about the vertex tv of the centre line (|p'|² = |qb + 2qa·t|² least), from
        // the control points (de Casteljau: each coefficient to ε of the local sizes). Where
        // the curve is slow (p' ≈ 0, e.g. b₁ = b₂) the ray meets the tube over a wide range
        // of t around tv, and h' ≈ 0 there: P = 4h'²g − g'² is tiny there, far below the
        // rounding of its t-power coefficients (fuzz finding regression-pinched-slow-end:
        // a 46-long tube with p'(1) = 0; P's roots near t = 1 were noise). About tv the
        // coefficients of q, and so of h, g and P, carry no such cancellation.
        let qq = qa.dot(qa);
        let tv0 = -qb.dot(qa) / (two * T::select(qq.gt(T::zero()), qq, T::one()));
        let tv = T::select(qq.gt(T::zero()) & tv0.is_finite(), tv0, T::zero()).clamp(T::zero(), T::one());
        let sv = T::one() - tv;
        let (wv0, wv1, wv2) = (sv * sv, two * sv * tv, tv * tv);
        let qcv = c0 * wv0 + c1 * wv1 + c2 * wv2;
        let qbv = ((c1 - c0) * sv + (c2 - c1) * tv) * two;
        let rcv = r0 * wv0 + r1 * wv1 + r2 * wv2;
        let rbv = ((r1 - r0) * sv + (r2 - r1) * tv) * two;
        let (hv, gv) = ray_polys(qa, qbv, qcv, ra, rbv, rcv, dhat);
        // g at t = 1 from the end itself (fuzz finding regression-tip-on-ray: r(1) = 0 with
        // p(1) on the ray, g = c(1 − t)⁴; Σ gᵢ came out −2.2e-16, below the tolerance 16ε·Σ|gᵢ|,
        // which bounds the evaluation of g's coefficients but not their own rounding, and the
        // tip — the true entry — was dropped). At t = 0 Horner gives g₀ = rc² − |wc|², the
        // same formula.
        let w_end = c2.cross(dhat);
        let g_end = r2 * r2 - w_end.dot(w_end);
        // Ray-space distances are in units of `big`: t = tc + s·big/|d|.
        Self { h, g, qa, qb, qc, dhat, tc, inv_dlen: inv_dlen * big_s, near, hv, gv, tv, g_end }
    }

    #[inline(always)]
    fn q(&self, t: T) -> V3<T> {
        self.qa * (t * t) + self.qb * t + self.qc
    }

    /// `σh(t) − √max(g(t), 0)`: the entry (σ = 1) or minus the exit (σ = −1).
    #[inline(always)]
    fn val(&self, t: T, sigma: T) -> T {
        sigma * horner(&self.h, t) - horner(&self.g, t).max(T::zero()).sqrt()
    }

    /// Minimum of `σh − √g` over the critical points in `[lo, hi]` (Russig's cascade) and the
    /// ends. Returns `(value, t)`.
    #[inline(always)]
    fn russig_min(&self, lo: T, hi: T, sigma: T, m: Bracket) -> (T, T) {
        let two = T::cst(2.0);
        let g = self.g;
        let g1 = [g[1], two * g[2], T::cst(3.0) * g[3], T::cst(4.0) * g[4]];
        let g2 = [two * g[2], T::cst(6.0) * g[3], T::cst(12.0) * g[4]];
        let g3 = [T::cst(6.0) * g[3], T::cst(24.0) * g[4]];
        let hs = [self.h[0] * sigma, self.h[1] * sigma, self.h[2] * sigma];
        let h1 = [hs[1], two * hs[2]];
        let h2 = two * hs[2];
        let gg = move |t: T| horner(&g, t).max(T::zero());
        let f3 = move |t: T| {
            let (gv, d1, d2, d3) = (gg(t), horner(&g1, t), horner(&g2, t), horner(&g3, t));
            -T::cst(4.0) * d3 * gv * gv + T::cst(6.0) * d1 * d2 * gv - T::cst(3.0) * d1 * d1 * d1
        };
        let f2 = move |t: T| {
            let (gv, d1, d2) = (gg(t), horner(&g1, t), horner(&g2, t));
            T::cst(4.0) * h2 * gv * gv.sqrt() - two * d2 * gv + d1 * d1
        };
        let f1 = move |t: T| two * horner(&h1, t) * gg(t).sqrt() - horner(&g1, t);
        let df1 = move |t: T| {
            let sg = gg(t).sqrt();
            two * h2 * sg + horner(&h1, t) * horner(&g1, t) / sg - horner(&g2, t)
        };
        let none = |_: T| T::zero();
        let (m3, m1) = match m {
            Bracket::Newton => (Bracket::Itp, Bracket::Newton),
            other => (other, other),
        };
        let mut bp = [hi; 8];
        bp[0] = lo;
        bp[1] = hi;
        let bp = cascade_level(&bp, 2, f3, none, m3);
        let bp = cascade_level(&bp, 3, f2, none, m3);
        let bp = cascade_level(&bp, 4, f1, df1, m1);
        let mut best = self.val(bp[0], sigma);
        let mut bt = bp[0];
        for &t in bp.iter().take(5).skip(1) {
            let v = self.val(t, sigma);
            let better = v.lt(best);
            best = T::select(better, v, best);
            bt = T::select(better, t, bt);
        }
        (best, bt)
    }

    /// Polishes a critical point of `σh − √g` found as a root of `P` (whose coefficients carry
    /// the cancellation of `4h'²g − g'²`, so its roots can be off for thin, long tubes): ITP on
    /// `F₁ = 2σh'√g − g'` (evaluated from `g` directly) in the bracket `[a, b]` of the
    /// neighbouring breakpoints, kept where it lowers the value. Returns `(value, t)`.
    #[inline(always)]
    fn polish(&self, t: T, v: T, sigma: T, a: T, b: T) -> (T, T) {
        let two = T::cst(2.0);
        let g = self.g;
        let g1 = [g[1], two * g[2], T::cst(3.0) * g[3], T::cst(4.0) * g[4]];
        let h1 = [self.h[1] * sigma, two * self.h[2] * sigma];
        let f1 = move |x: T| two * horner(&h1, x) * horner(&g, x).max(T::zero()).sqrt() - horner(&g1, x);
        let (fa, fb) = (f1(a), f1(b));
        let valid = opposite(fa, fb);
        if valid.none() {
            return (v, t);
        }
        let x = itp(f1, a, b, fa, fb, valid, default_tol::<T>());
        let vx = self.val(x, sigma);
        let better = valid & vx.lt(v) & horner(&g, x).ge(T::zero());
        (T::select(better, vx, v), T::select(better, x, t))
    }

    /// All roots of `P` in `[0, 1]` as sorted breakpoints (`buf[0] = 0`, `buf[n−1] = 1`):
    /// the union of those found in powers of `t` and in powers of `t − tv` (shifted back),
    /// merged by a fixed compare-exchange network (`select` on `<`: every lane bit-equal to
    /// the scalar). Each expansion can be the noisy one: about `tv` for a slow end
    /// (regression-pinched-slow-end), in powers of `t` elsewhere; a spare candidate costs
    /// nothing (every candidate is a point of the sweep), a lost one can lose the entry.
    #[inline(always)]
    fn p_breakpoints(&self) -> ([T; 16], usize) {
        let (lo, hi) = (-self.tv, T::one() - self.tv);
        let (bv, nv) = poly_breakpoints(&self.p_poly(), lo, hi, Bracket::Newton);
        let (bt, nt) = poly_breakpoints(&self.p_poly_t(), T::zero(), T::one(), Bracket::Newton);
        debug_assert!(nv == 8 && nt == 8);
        let mut out = [T::one(); 16];
        // out = bt ascending, then the shifted bv descending: a bitonic sequence.
        out[..8].copy_from_slice(&bt);
        for i in 0..8 {
            let t = (self.tv + bv[i]).clamp(T::zero(), T::one());
            out[15 - i] = T::select(bv[i].le(lo), T::zero(), T::select(bv[i].ge(hi), T::one(), t));
        }
        let mut stride = 8;
        while stride > 0 {
            for i in 0..16 {
                if i & stride == 0 {
                    let (a, b) = (out[i], out[i + stride]);
                    let sw = b.lt(a);
                    out[i] = T::select(sw, b, a);
                    out[i + stride] = T::select(sw, a, b);
                }
            }
            stride /= 2;
        }
        (out, 16)
    }

    /// `P = 4h'²g − g'²` (degree 6) in powers of `t`.
    #[inline(always)]
    fn p_poly_t(&self) -> [T; 7] {
        p_of(&self.h, &self.g)
    }

    /// `P = 4h'²g − g'²` (degree 6) in powers of `t − tv`.
    #[inline(always)]
    fn p_poly(&self) -> [T; 7] {
        p_of(&self.hv, &self.gv)
    }

    /// Entry/exit from candidate parameters (clamped to `[lo, hi]`), keeping only those with
    /// `g ≥ 0` unless `all_real`. Returns `(s_in, t_in*, s_out, t_out*, any)`.
    #[inline(always)]
    fn best_of_candidates(&self, c: &[T], lo: T, hi: T, all_real: bool) -> (T, T, T, T, T::Mask, [T; 4]) {
        let inf = T::infinity();
        let (mut bi, mut ti, mut bo, mut to) = (inf, lo, inf, lo);
        // Neighbouring candidates of the best ones: brackets for `polish`.
        let mut nb = [lo, hi, lo, hi];
        let mut any = T::Mask::splat(false);
        let n = c.len();
        // g within its own rounding of 0 counts as real (e.g. r = 0 at an end on the ray:
        // g = 0 exactly, computed as −1e-18): 16ε·Σ|gᵢ| bounds g's evaluation error on [0, 1].
        let g = self.g;
        let gtol = T::epsilon() * T::cst(16.0) * (g[0].abs() + g[1].abs() + g[2].abs() + g[3].abs() + g[4].abs());
        for (k, &t) in c.iter().enumerate() {
            let t = t.clamp(lo, hi);
            let left = c[k.saturating_sub(1)].clamp(lo, hi);
            let right = c[(k + 1).min(n - 1)].clamp(lo, hi);
            let gv = T::select(t.ge(T::one()), self.g_end, horner(&self.g, t));
            let ok = if all_real { T::Mask::splat(true) } else { gv.ge(-gtol) };
            let hv = horner(&self.h, t);
            let sq = gv.max(T::zero()).sqrt();
            let (vi, vo) = (hv - sq, -hv - sq);
            let bi_ = ok & vi.lt(bi);
            let bo_ = ok & vo.lt(bo);
            bi = T::select(bi_, vi, bi);
            ti = T::select(bi_, t, ti);
            bo = T::select(bo_, vo, bo);
            to = T::select(bo_, t, to);
            nb = [
                T::select(bi_, left, nb[0]),
                T::select(bi_, right, nb[1]),
                T::select(bo_, left, nb[2]),
                T::select(bo_, right, nb[3]),
            ];
            any = any | ok;
        }
        (bi, ti, -bo, to, any, nb)
    }

    /// Assemble the interval from ray-space entry/exit distances and curve parameters.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn interval(&self, ray: &Ray<T>, s_in: T, u_in: T, s_out: T, u_out: T, found: T::Mask, clip: bool) -> Interval<T> {
        let normal = |s: T, u: T, fallback: V3<T>| {
            let v = self.dhat * s - self.q(u);
            let n = v.normalize_or_zero();
            V3::select(n.length2().gt(T::zero()), n, fallback)
        };
        let t_in = self.tc + s_in * self.inv_dlen;
        let t_out = self.tc + s_out * self.inv_dlen;
        let n_in = normal(s_in, u_in, -self.dhat);
        let n_out = normal(s_out, u_out, self.dhat);
        // `clip = false`: hit means only "the line meets it" (for hulls clipped later).
        let range = if clip { in_range(ray, t_in, t_out) } else { t_in.le(t_out) };
        let hit = found & self.near & range;
        Interval { t_in, t_out, n_in, n_out, u_in, u_out, hit }.masked(hit)
    }
}

impl<T: Real> QuadTube<T> {
    /// Lanes from validated scalar segments (one per lane).
    pub fn from_lanes(f: impl Fn(usize) -> QuadTube<T::Elem>) -> Self {
        Self {
            b: [V3::from_fn(|i| f(i).b[0]), V3::from_fn(|i| f(i).b[1]), V3::from_fn(|i| f(i).b[2])],
            r: [T::from_fn(|i| f(i).r[0]), T::from_fn(|i| f(i).r[1]), T::from_fn(|i| f(i).r[2])],
        }
    }
    /// Every lane the same segment.
    pub fn splat(s: QuadTube<T::Elem>) -> Self {
        Self {
            b: [V3::splat(s.b[0]), V3::splat(s.b[1]), V3::splat(s.b[2])],
            r: [T::splat(s.r[0]), T::splat(s.r[1]), T::splat(s.r[2])],
        }
    }
    /// Lane `i` as a scalar segment.
    pub fn lane(&self, i: usize) -> QuadTube<T::Elem> {
        QuadTube {
            b: [self.b[0].lane(i), self.b[1].lane(i), self.b[2].lane(i)],
            r: [self.r[0].lane(i), self.r[1].lane(i), self.r[2].lane(i)],
        }
    }
    /// Centre-line point `p(t)`.
    #[inline(always)]
    pub fn point(&self, t: T) -> V3<T> {
        let s = T::one() - t;
        let (w0, w1, w2) = (s * s, T::cst(2.0) * s * t, t * t);
        self.b[0] * w0 + self.b[1] * w1 + self.b[2] * w2
    }
    /// Radius `r(t)`.
    #[inline(always)]
    pub fn radius(&self, t: T) -> T {
        bezier2(self.r, t)
    }
    /// Tangent `p'(t)`.
    #[inline(always)]
    pub fn tangent(&self, t: T) -> V3<T> {
        let two = T::cst(2.0);
        ((self.b[1] - self.b[0]) * (T::one() - t) + (self.b[2] - self.b[1]) * t) * two
    }
    /// Radius derivative `r'(t)`.
    #[inline(always)]
    pub fn radius_deriv(&self, t: T) -> T {
        T::cst(2.0) * ((self.r[1] - self.r[0]) * (T::one() - t) + (self.r[2] - self.r[1]) * t)
    }

    /// Ray–segment interval (hull: entry `min f`, exit `max e` over the whole segment, the
    /// hull of [`Self::intersect_pieces`]) with a chosen solver; [`crate::Primitive::intersect`] uses
    /// [`Solver::Polynomial`].
    #[inline(always)]
    pub fn intersect_with(&self, ray: &Ray<T>, solver: Solver) -> Interval<T> {
        self.line_interval_with(ray, solver).clip(ray)
    }

    /// The hull's interval on the ray's whole line (`hit`: the line meets the segment) with a
    /// chosen solver; [`Self::intersect_with`] clips it to the ray.
    #[inline(always)]
    pub fn line_interval_with(&self, ray: &Ray<T>, solver: Solver) -> Interval<T> {
        let rs = RaySpace::new(self, ray);
        if rs.near.none() {
            return Interval::miss();
        }
        match solver {
            Solver::Polynomial => {
                let (bp, n) = rs.p_breakpoints();
                let (si, ui, so, uo, any, nb) = rs.best_of_candidates(&bp[..n], T::zero(), T::one(), false);
                let (vi, ui) = rs.polish(ui, si, T::one(), nb[0], nb[1]);
                let (vo, uo) = rs.polish(uo, -so, -T::one(), nb[2], nb[3]);
                rs.interval(ray, vi, ui, -vo, uo, any, false)
            }
            _ => {
                // Hull of the line pieces (a piece behind the origin still belongs to the line
                // interval).
                let pieces = self.pieces_in(&rs, ray, solver, false);
                let mut iv = pieces[0];
                for p in &pieces[1..] {
                    iv = iv.hull(*p);
                }
                iv
            }
        }
    }

    /// One interval per real interval of `g` (at most three non-empty, in slots `0..5`; the
    /// others miss), each exact. Feed them to [`crate::csg::union`] for transparency.
    /// With [`Solver::Polynomial`] the real intervals come from `g`'s cascade with Newton and
    /// the candidates from `P`'s roots.
    #[inline(always)]
    pub fn intersect_pieces(&self, ray: &Ray<T>, solver: Solver) -> [Interval<T>; 5] {
        let rs = RaySpace::new(self, ray);
        if rs.near.none() {
            return [Interval::miss(); 5];
        }
        self.pieces_in(&rs, ray, solver, true)
    }

    #[inline(always)]
    fn pieces_in(&self, rs: &RaySpace<T>, ray: &Ray<T>, solver: Solver, clip: bool) -> [Interval<T>; 5] {
        let half = T::cst(0.5);
        let method = match solver {
            Solver::Bisection { iters } => Bracket::Bisection(iters),
            Solver::Itp => Bracket::Itp,
            Solver::Newton | Solver::Polynomial => Bracket::Newton,
        };
        // Real intervals of g: breakpoints 0 = z₀ ≤ z₁ ≤ … ≤ z₅ = 1, g of one sign on each piece.
        let (z, _) = poly_breakpoints(&rs.g, T::zero(), T::one(), method);
        let mut real = [T::Mask::splat(false); 5];
        for k in 0..5 {
            let mid = (z[k] + z[k + 1]) * half;
            real[k] = horner(&rs.g, mid).gt(T::zero()) & z[k + 1].gt(z[k]);
        }
        // A boundary is a cut (a root of g) where realness changes or g ≤ 0 there.
        let mut cut = [T::Mask::splat(true); 6];
        for j in 1..5 {
            let rj = real[j - 1] & real[j];
            cut[j] = !rj | horner(&rs.g, z[j]).le(T::zero());
        }
        let ppoly = if solver == Solver::Polynomial { Some(rs.p_breakpoints()) } else { None };
        let mut out = [Interval::miss(); 5];
        for k in 0..5 {
            // Process piece k only where it starts a merged real interval.
            let first = real[k] & cut[k];
            if first.none() {
                continue;
            }
            let lo = z[k];
            let mut hi = z[k + 1];
            let mut open = T::Mask::splat(true);
            for j in k + 1..5 {
                open = open & !cut[j];
                hi = T::select(open, z[j + 1], hi);
            }
            let (si, ui, so, uo) = match ppoly {
                Some((bp, n)) => {
                    let (si, ui, so, uo, _, nb) = rs.best_of_candidates(&bp[..n], lo, hi, true);
                    let (vi, ui) = rs.polish(ui, si, T::one(), nb[0], nb[1]);
                    let (vo, uo) = rs.polish(uo, -so, -T::one(), nb[2], nb[3]);
                    (vi, ui, -vo, uo)
                }
                None => {
                    let (vi, ui) = rs.russig_min(lo, hi, T::one(), method);
                    let (vo, uo) = rs.russig_min(lo, hi, -T::one(), method);
                    (vi, ui, -vo, uo)
                }
            };
            out[k] = rs.interval(ray, si, ui, so, uo, first, clip);
        }
        out
    }
}

/// Distance-like function of the sweep: `φ(x) = min_t (|x − p(t)| − r(t))` over `t ∈ [0, 1]`,
/// by exact 1-D minimisation. Outside the tube and on its surface this **is** the exact
/// distance to the sweep (the distance to a union of balls is the least distance to one of
/// them); inside it is `−max_t (r(t) − |x − p(t)|)`, negative, zero on the surface and at most
/// the depth in magnitude.
///
/// The critical points of `|x − p| − r` satisfy `(x − p)·p' = −r'|x − p|`, so they are roots of
/// the degree-6 polynomial `((x − p)·p')² − r'²|x − p|²`; all of them in `[0, 1]` are isolated
/// by the derivative cascade with safeguarded Newton, each is polished by a golden-section
/// search between its neighbours, and `φ` is the least value seen (ends included).
pub fn quadratic_tube<T: Scalar>(x: V3<T>, tube: &QuadTube<T>) -> T {
    let two = T::cst(2.0);
    let [b0, b1, b2] = tube.b;
    // Relative to b₀ (precision), in units of a power of two near the extent (exact scaling;
    // the polynomial below has products of up to six coordinates, and |x − p| squares them,
    // which would underflow for a tube 1e-304 small — fuzz finding
    // regression-tiny-sdf-underflow: the SDF said −r at a surface point — or overflow far out).
    let xr = x - b0;
    let mut e = xr.max_abs();
    for i in 0..3 {
        e = e.max((tube.b[i] - b0).max_abs()).max(tube.r[i].abs());
    }
    let kmax = if T::EPS.to_f64() < 1e-10 { 1000 } else { 120 };
    let k = if e > T::zero() && e.is_finite() { (e.to_f64().log2().floor() as i32).clamp(-kmax, kmax) } else { 0 };
    let (sc, unsc) = (T::from_f64(2f64.powi(-k)), T::from_f64(2f64.powi(k)));
    let (b0, b1, b2) = (V3::zero(), (b1 - b0) * sc, (b2 - b0) * sc);
    let xr = xr * sc;
    let tube = &QuadTube { b: [b0, b1, b2], r: [tube.r[0] * sc, tube.r[1] * sc, tube.r[2] * sc] };
    // p = A t² + B t, D = x − p.
    let a = b0 - b1 * two + b2;
    let b = (b1 - b0) * two;
    let d = [xr, -b, -a];
    let dp = [b, a * two];
    let [r0, r1, r2] = tube.r;
    let rp = [(r1 - r0) * two, (r0 - r1 * two + r2) * two];
    // D·p' (cubic), |D|² (quartic).
    let mut dpp = [T::zero(); 4];
    for i in 0..3 {
        for j in 0..2 {
            dpp[i + j] += d[i].dot(dp[j]);
        }
    }
    let mut dd = [T::zero(); 5];
    for i in 0..3 {
        for j in 0..3 {
            dd[i + j] += d[i].dot(d[j]);
        }
    }
    let s1: [T; 7] = poly_mul(&dpp, &dpp);
    let rp2: [T; 3] = poly_mul(&rp, &rp);
    let s2: [T; 7] = poly_mul(&rp2, &dd);
    let mut q = [T::zero(); 7];
    for i in 0..7 {
        q[i] = s1[i] - s2[i];
    }
    let (bp, n) = poly_breakpoints(&q, T::zero(), T::one(), Bracket::Newton);
    let phi = |t: T| (xr - (a * (t * t) + b * t)).length() - tube.radius(t);
    let mut best = T::infinity();
    for &t in &bp[..n] {
        best = best.min(phi(t));
    }
    // The polynomial's roots can be off where its coefficients cancel (a thin tube far from
    // b₀: |x − p| ≪ |x − b₀|), though φ itself is evaluated to ~ε|x − b₀|. Between the
    // neighbours of a computed root φ has one critical point, so a golden-section search
    // there polishes it (every value it sees is a value of φ: the minimum can only improve).
    let gr = T::cst(0.618_033_988_749_894_8);
    for i in 1..n - 1 {
        let (mut lo, mut hi) = (bp[i - 1], bp[i + 1]);
        let mut x1 = hi - gr * (hi - lo);
        let mut x2 = lo + gr * (hi - lo);
        let (mut f1, mut f2) = (phi(x1), phi(x2));
        for _ in 0..100 {
            if hi - lo <= T::epsilon() * T::cst(4.0) {
                break;
            }
            if f1 < f2 {
                hi = x2;
                x2 = x1;
                f2 = f1;
                x1 = hi - gr * (hi - lo);
                f1 = phi(x1);
            } else {
                lo = x1;
                x1 = x2;
                f1 = f2;
                x2 = lo + gr * (hi - lo);
                f2 = phi(x2);
            }
            best = best.min(f1).min(f2);
        }
    }
    best * unsc
}
