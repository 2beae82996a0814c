//! Ray space of one ray–segment query (Russig §3.2, Salm §3.2): the polynomials `h` and `g`,
//! the candidates for the entry and exit, and their polish (see the parent module's docs).

use super::direct::Direct;
use super::QuadTube;
use crate::math::bezier::bernstein2;
use crate::math::roots::{cascade_level, default_tol, horner, itp, opposite, poly_breakpoints, poly_mul, Bracket};
use crate::ray::{in_range, Crossing, Interval, Ray};
use crate::real::{Mask, Real, Scalar};
use crate::vec::V3;

mod certified;
mod reject;

use reject::{g_hull_misses, hull_misses};

/// Entry and exit of the sweep in ray space: distances along `d̂` from the re-centred origin
/// (in units of the bounding radius) and the curve parameters where they are attained.
#[derive(Clone, Copy, Debug)]
pub(super) struct Crossings<T> {
    /// Entry distance `min (h − √g)`.
    s_in: T,
    /// Curve parameter of the entry.
    u_in: T,
    /// Exit distance `max (h + √g)`.
    s_out: T,
    /// Curve parameter of the exit.
    u_out: T,
}

/// The best entry and exit among candidate parameters ([`RaySpace::best_of_candidates`]).
struct Candidates<T: Real> {
    /// Least entry and greatest exit seen.
    at: Crossings<T>,
    /// Lanes with at least one real candidate.
    any: T::Mask,
    /// The entry's neighbouring candidates: a bracket for [`RaySpace::polish`].
    in_bracket: [T; 2],
    /// The exit's neighbouring candidates.
    out_bracket: [T; 2],
}

/// Working data of one ray–segment query in ray space.
pub(super) struct RaySpace<T: Real> {
    /// `h` coefficients, ascending powers of `t`.
    h: [T; 3],
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
    pub(super) near: T::Mask,
    /// `h` and `g` re-expanded about `tv` (coefficients of powers of `t − tv`), for `P`.
    hv: [T; 3],
    gv: [T; 5],
    /// Expansion point of `hv`, `gv`: the vertex of the centre line (least `|p'|`), in `[0, 1]`.
    tv: T,
    /// The inputs of `hv`, `gv` with every component made positive, for the bound of their
    /// rounding ([`Self::p_poly_abs`]): the position coefficients about `tv` (`a`, `b`, `c`),
    /// the radius coefficients and the direction.
    qn: [V3<T>; 3],
    rn: [T; 3],
    dn: V3<T>,
    /// `g` and its derivatives from the vectors (the decisions and the values; the expanded
    /// coefficients `gv` only feed `P`'s).
    pub(super) dg: Direct<T>,
}

/// `h` and `g` (ascending powers of the parameter) from the power-basis position
/// `q = qa x² + qb x + qc` and radius `ra x² + rb x + rc` (`q = [qa, qb, qc]`, `r = [ra, rb, rc]`).
#[inline(always)]
fn ray_polys<T: Real>(q: [V3<T>; 3], r: [T; 3], dhat: V3<T>) -> ([T; 3], [T; 5]) {
    let h = ray_h(q, dhat);
    let ([qa, qb, qc], [ra, rb, rc]) = (q, r);
    let two = T::cst(2.0);
    let (wa, wb, wc) = (qa.cross(dhat), qb.cross(dhat), qc.cross(dhat));
    let w2 = [wc.dot(wc), two * wc.dot(wb), wb.dot(wb) + two * wc.dot(wa), two * wb.dot(wa), wa.dot(wa)];
    let r2 = [rc * rc, two * rc * rb, rb * rb + two * rc * ra, two * rb * ra, ra * ra];
    let g = [r2[0] - w2[0], r2[1] - w2[1], r2[2] - w2[2], r2[3] - w2[3], r2[4] - w2[4]];
    (h, g)
}

/// `h = q·d̂` (ascending powers) from the power-basis position `q = [qa, qb, qc]`.
#[inline(always)]
fn ray_h<T: Real>(q: [V3<T>; 3], dhat: V3<T>) -> [T; 3] {
    let [qa, qb, qc] = q;
    [qc.dot(dhat), qb.dot(dhat), qa.dot(dhat)]
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
    /// Set up the query of `ray` against `tube`; `None` when no lane's line can meet the sweep
    /// (the bounding sphere and [`hull_misses`], both exact rejections).
    #[inline(always)]
    pub(super) fn new(tube: &QuadTube<T>, ray: &Ray<T>) -> Option<Self> {
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
        // The bounding radius is a sum of lengths, which square the offsets: below √MIN_POSITIVE
        // (1.5e-154 in f64) the squares underflow, a length came out 0 and `big` collapsed to
        // `rmax` (fuzz finding regression-tiny-extent: offsets 3.5e-168, a = 7.4e-171,
        // big = a, 473 times too small). The ray-space coordinates were then ~473 instead of
        // ≤ 1, and t = tc + s·(big/|d|) multiplied the rounding of big/|d| — subnormal there,
        // |d| = 4e149: an absolute q/2 = 2⁻¹⁰⁷⁵, relative 1.4e-4 — by s: t was 208q off, the
        // hit 4.3e-172 outside the tube (bound 1.4e-172). So tubes whose largest offset or
        // radius w is below 2⁻⁴⁰⁰ (f64; 2⁻³⁸ in f32) are measured `up` a power of two, 2⁶⁰⁰
        // (2⁹⁰): w·up ∈ [2⁻⁴⁷⁴, 2²⁰⁰] ([2⁻⁵⁹, 2⁵²]) for every w down to the least subnormal, so
        // every square is normal and finite. (At or above the threshold an offset whose square
        // underflows, < 2⁻⁵¹¹ (2⁻⁶³), is below 2⁻¹¹¹·w (2⁻²⁵·w): beneath big's own rounding.)
        // Scaling by a power of two is exact and sqrt is
        // correctly rounded, so where the squares did not underflow the result is the same
        // number, and elsewhere `up = 1`: bit for bit unchanged (and still exactly invariant
        // under scaling by 2^k). The coordinates are formed in the same measure, so a tube
        // whose `big` is subnormal (1/big would overflow) works too.
        let w = (b0 - m).max_abs().max((b1 - m).max_abs()).max((b2 - m).max_abs()).max(rmax);
        let (thr, sup) = if T::Elem::EPS.to_f64() < 1e-10 { (-400, 600) } else { (-38, 90) };
        let tiny = w.lt(T::cst(2f64.powi(thr)));
        let up = T::select(tiny, T::cst(2f64.powi(sup)), T::one());
        let down = T::select(tiny, T::cst(2f64.powi(-sup)), T::one());
        let big_up = ((b0 - m) * up).length().max(((b1 - m) * up).length()).max(((b2 - m) * up).length()) + rmax * up;
        let near = (l * up).length2().le(big_up * big_up);
        // Work in units of the bounding radius: g, P and the sign functions are products of up
        // to six coordinates, which would over/underflow for large or tiny tubes. (One
        // rounding per coordinate: a relative change of ε, inside the error model.)
        let ok = big_up.gt(T::zero()) & big_up.is_finite();
        let big_s = T::select(ok, big_up * down, T::one());
        let inv = T::one() / T::select(ok, big_up, T::one());
        let (c0, c1, c2) = (((b0 - m - l) * up) * inv, ((b1 - m - l) * up) * inv, ((b2 - m - l) * up) * inv);
        let qa = c0 - c1 * two + c2;
        let qb = (c1 - c0) * two;
        let qc = c0;
        let [r0, r1, r2] = [(tube.r[0] * up) * inv, (tube.r[1] * up) * inv, (tube.r[2] * up) * inv];
        let near = near & !hull_misses([c0, c1, c2], r0.max(r1).max(r2), dhat);
        if near.none() {
            return None;
        }
        let near = near & !g_hull_misses([c0, c1, c2], [r0, r1, r2], dhat);
        if near.none() {
            return None;
        }
        let (ra, rb, rc) = (r0 - r1 * two + r2, (r1 - r0) * two, r0);
        // `h` in powers of `t` (the values); `g`'s coefficients only about `tv`, for `P`.
        let h = ray_h([qa, qb, qc], dhat);
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
        let [wv0, wv1, wv2] = bernstein2(tv);
        let qcv = c0 * wv0 + c1 * wv1 + c2 * wv2;
        let qbv = ((c1 - c0) * sv + (c2 - c1) * tv) * two;
        let rcv = r0 * wv0 + r1 * wv1 + r2 * wv2;
        let rbv = ((r1 - r0) * sv + (r2 - r1) * tv) * two;
        let (hv, gv) = ray_polys([qa, qbv, qcv], [ra, rbv, rcv], dhat);
        let vabs = |v: V3<T>| V3::new(v.x.abs(), v.y.abs(), v.z.abs());
        let (qn, rn, dn) = ([vabs(qa), vabs(qbv), vabs(qcv)], [ra.abs(), rbv.abs(), rcv.abs()], vabs(dhat));
        // g at t = 1 from the end itself (fuzz finding regression-tip-on-ray: r(1) = 0 with
        // p(1) on the ray, g = c(1 − t)⁴; Σ gᵢ came out −2.2e-16 and the tip — the true
        // entry — was dropped). At t = 0 Horner gives wc, rc exactly.
        let dg = Direct::new([qa, qb, qc], [ra, rb, rc], dhat, (c2, r2));
        // Ray-space distances are in units of `big`: t = tc + s·big/|d|.
        Some(Self { h, qa, qb, qc, dhat, tc, inv_dlen: inv_dlen * big_s, near, hv, gv, tv, qn, rn, dn, dg })
    }

    /// `h' = h1[0] + h1[1]·t`.
    #[inline(always)]
    pub(super) fn h1(&self) -> [T; 2] {
        [self.h[1], T::cst(2.0) * self.h[2]]
    }

    #[inline(always)]
    fn q(&self, t: T) -> V3<T> {
        self.qa * (t * t) + self.qb * t + self.qc
    }

    /// `σh(t) − √max(g(t), 0)`: the entry (σ = 1) or minus the exit (σ = −1).
    #[inline(always)]
    fn val(&self, t: T, sigma: T) -> T {
        sigma * horner(&self.h, t) - self.dg.g(t).max(T::zero()).sqrt()
    }

    /// Entry and exit over `[lo, hi]` by Russig's cascade ([`Self::russig_min`] for `σ = ±1`).
    #[inline(always)]
    pub(super) fn russig(&self, lo: T, hi: T, m: Bracket) -> Crossings<T> {
        let (vi, ui) = self.russig_min(lo, hi, T::one(), m);
        let (vo, uo) = self.russig_min(lo, hi, -T::one(), m);
        Crossings { s_in: vi, u_in: ui, s_out: -vo, u_out: uo }
    }

    /// Minimum of `σh − √g` over the critical points in `[lo, hi]` (Russig's cascade) and the
    /// ends. Returns `(value, t)`.
    #[inline(always)]
    fn russig_min(&self, lo: T, hi: T, sigma: T, m: Bracket) -> (T, T) {
        let two = T::cst(2.0);
        let dg = self.dg;
        let hs = [self.h[0] * sigma, self.h[1] * sigma, self.h[2] * sigma];
        let h1 = [hs[1], two * hs[2]];
        let h2 = two * hs[2];
        let gg = move |t: T| dg.g(t).max(T::zero());
        let f3 = move |t: T| {
            let (gv, d1, d2, d3) = (gg(t), dg.g1(t), dg.g2(t), dg.g3(t));
            -T::cst(4.0) * d3 * gv * gv + T::cst(6.0) * d1 * d2 * gv - T::cst(3.0) * d1 * d1 * d1
        };
        let f2 = move |t: T| {
            let (gv, d1, d2) = (gg(t), dg.g1(t), dg.g2(t));
            T::cst(4.0) * h2 * gv * gv.sqrt() - two * d2 * gv + d1 * d1
        };
        let f1 = move |t: T| two * horner(&h1, t) * gg(t).sqrt() - dg.g1(t);
        let df1 = move |t: T| {
            let sg = gg(t).sqrt();
            two * h2 * sg + horner(&h1, t) * dg.g1(t) / sg - dg.g2(t)
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

    /// Polishes a candidate `t` (value `v`) for a minimum of `σh − √g` — `P`'s roots carry
    /// the cancellation of `4h'²g − g'²`'s coefficients and can be far off or missing for thin,
    /// long tubes: the sign of `F₁ = 2σh'√g − g'` (from the vectors, [`Direct`]) at `t` says on
    /// which side the minimum lies; ITP on `F₁` between `t` and that side's neighbouring
    /// candidate (`left`, `right`), kept where the bracket is valid, the point is real (gap
    /// `≥ −τ`) and it lowers the value. A real interval's ends are candidates, where
    /// `F₁ = −g'` has the sign that makes the bracket valid. Returns `(value, t)`.
    #[inline(always)]
    fn polish(&self, t: T, v: T, sigma: T, left: T, right: T) -> (T, T) {
        let two = T::cst(2.0);
        let dg = self.dg;
        let h1 = [self.h[1] * sigma, two * self.h[2] * sigma];
        let f1 = move |x: T| two * horner(&h1, x) * dg.g(x).max(T::zero()).sqrt() - dg.g1(x);
        let ft = f1(t);
        let go_right = ft.lt(T::zero());
        let (a, b) = (T::select(go_right, t, left), T::select(go_right, right, t));
        let (fa, fb) = (T::select(go_right, ft, f1(left)), T::select(go_right, f1(right), ft));
        let valid = opposite(fa, fb);
        if valid.none() {
            return (v, t);
        }
        // ITP, not Newton from `t`: Newton is cheaper per hit (one or two steps from a
        // root of `P`) but stops on a step ≤ tol, which a thin tube's steep `F₁'` (its
        // `h'g'/√g` term) makes tiny before `F₁` is near zero: in f32 on long thin links the
        // p99 entry error rose from 8.8e-3 to 0.34 radii (docs/report/stability.md,
        // `long-thin`, `as-spline-polynomial/f32`). ITP stops on the bracket.
        let x = itp(f1, a, b, fa, fb, valid, default_tol::<T>());
        let vx = self.val(x, sigma);
        let better = valid & vx.lt(v) & dg.gap_g(x).0.ge(-dg.tau);
        (T::select(better, vx, v), T::select(better, x, t))
    }

    /// All roots of `P` in `[0, 1]` as sorted breakpoints (`buf[0] = 0`, `buf[n−1] = 1`),
    /// isolated in powers of `t − tv` (shifted back). About the vertex `tv` of the centre line
    /// the coefficients carry no cancellation where the curve is slow (`p' ≈ 0`:
    /// regression-pinched-slow-end, where the roots in powers of `t` near the slow end were
    /// noise). The roots in powers of `t` are not added as well: the case they would catch, a
    /// zero-radius tip on the ray (regression-tip-on-ray), is covered by `g(1)` formed from the
    /// end and by `g`'s breakpoints, which are candidates too (both ends always among them), and
    /// a second isolation would cost a large share of a hit.
    #[inline(always)]
    pub(super) fn p_breakpoints(&self) -> ([T; 8], usize) {
        let (lo, hi) = (-self.tv, T::one() - self.tv);
        let (bv, nv) = poly_breakpoints(&self.p_poly(), lo, hi, Bracket::Newton);
        debug_assert!(nv == 8);
        let mut out = [T::one(); 8];
        for i in 0..8 {
            let t = (self.tv + bv[i]).clamp(T::zero(), T::one());
            out[i] = T::select(bv[i].le(lo), T::zero(), T::select(bv[i].ge(hi), T::one(), t));
        }
        (out, 8)
    }

    /// `P = 4h'²g − g'²` (degree 6) in powers of `t − tv`.
    #[inline(always)]
    fn p_poly(&self) -> [T; 7] {
        p_of(&self.hv, &self.gv)
    }

    /// Entry and exit from candidate parameters ([`Self::best_of_candidates`]), each polished
    /// ([`Self::polish`]) between its neighbouring candidates. Also returns the lanes with a
    /// real candidate.
    #[inline(always)]
    pub(super) fn polished_candidates(
        &self,
        c: &[T],
        extra: &[T],
        lo: T,
        hi: T,
        all_real: bool,
    ) -> (Crossings<T>, T::Mask) {
        let best = self.best_of_candidates(c, extra, lo, hi, all_real);
        let (vi, ui) = self.polish(best.at.u_in, best.at.s_in, T::one(), best.in_bracket[0], best.in_bracket[1]);
        let (vo, uo) = self.polish(best.at.u_out, -best.at.s_out, -T::one(), best.out_bracket[0], best.out_bracket[1]);
        (Crossings { s_in: vi, u_in: ui, s_out: -vo, u_out: uo }, best.any)
    }

    /// Entry/exit from candidate parameters `c ∪ extra` (clamped to `[lo, hi]`, at most 32),
    /// keeping only real ones (gap `r − |w| ≥ −τ`, [`Direct`]) unless `all_real`; with each
    /// winner's polish bracket: the nearest candidate (or `lo`, `hi`) on the side that `F₁`'s
    /// sign at the winner points to **whose `F₁` has the other sign**, so that the bracket holds
    /// a root. The nearest candidate alone is not enough: two candidates can lie within
    /// rounding of each other (a root of `P` and the maximum of `g` beside it on a grazing
    /// ray), and a bracket between them holds none.
    #[inline(always)]
    fn best_of_candidates(&self, c: &[T], extra: &[T], lo: T, hi: T, all_real: bool) -> Candidates<T> {
        let (inf, two) = (T::infinity(), T::cst(2.0));
        let h1 = self.h1();
        let (mut bi, mut ti, mut bo, mut to) = (inf, lo, inf, lo);
        let mut any = T::Mask::splat(false);
        // Each candidate's t and its F₁ for the entry (σ = 1) and the exit (σ = −1).
        let mut at = [(lo, T::zero(), T::zero()); 32];
        let mut n = 0;
        for &t in c.iter().chain(extra).take(32) {
            let t = t.clamp(lo, hi);
            let (gap, gv, g1) = self.dg.gap_g_g1(t);
            // Within the gap's rounding τ of 0 counts as real (e.g. r = 0 at an end on the ray).
            let ok = if all_real { T::Mask::splat(true) } else { gap.ge(-self.dg.tau) };
            let hv = horner(&self.h, t);
            let sq = gv.max(T::zero()).sqrt();
            let (vi, vo) = (hv - sq, -hv - sq);
            let bi_ = ok & vi.lt(bi);
            let bo_ = ok & vo.lt(bo);
            bi = T::select(bi_, vi, bi);
            ti = T::select(bi_, t, ti);
            bo = T::select(bo_, vo, bo);
            to = T::select(bo_, t, to);
            any = any | ok;
            let hs = two * horner(&h1, t) * sq;
            at[n] = (t, hs - g1, -hs - g1);
            n += 1;
        }
        // F₁ at each winner (the winner's own entry in `at`); F₁ < 0: the minimum lies right.
        let (mut fi, mut fo) = (T::zero(), T::zero());
        for &(t, f_in, f_out) in &at[..n] {
            fi = T::select(t.eq(ti), f_in, fi);
            fo = T::select(t.eq(to), f_out, fo);
        }
        let (ri, ro) = (fi.lt(T::zero()), fo.lt(T::zero()));
        let mut nb = [lo, hi, lo, hi];
        for &(t, f_in, f_out) in &at[..n] {
            // Right of the winner with F₁ ≥ 0, or left with F₁ ≤ 0: a sign change between.
            let (right_i, left_i) = (ri & f_in.ge(T::zero()), !ri & f_in.le(T::zero()));
            let (right_o, left_o) = (ro & f_out.ge(T::zero()), !ro & f_out.le(T::zero()));
            nb[0] = T::select(left_i & t.lt(ti) & t.gt(nb[0]), t, nb[0]);
            nb[1] = T::select(right_i & t.gt(ti) & t.lt(nb[1]), t, nb[1]);
            nb[2] = T::select(left_o & t.lt(to) & t.gt(nb[2]), t, nb[2]);
            nb[3] = T::select(right_o & t.gt(to) & t.lt(nb[3]), t, nb[3]);
        }
        Candidates {
            at: Crossings { s_in: bi, u_in: ti, s_out: -bo, u_out: to },
            any,
            in_bracket: [nb[0], nb[1]],
            out_bracket: [nb[2], nb[3]],
        }
    }

    /// Assemble the interval from ray-space entry/exit distances and curve parameters.
    #[inline(always)]
    pub(super) fn interval(&self, ray: &Ray<T>, x: Crossings<T>, found: T::Mask, clip: bool) -> Interval<T> {
        let Crossings { s_in, u_in, s_out, u_out } = x;
        let normal = |s: T, u: T, fallback: V3<T>| {
            let v = self.dhat * s - self.q(u);
            let n = v.normalize_or_zero();
            V3::select(n.length2().gt(T::zero()), n, fallback)
        };
        // Where big/|d| is subnormal (a tiny tube, a long d: tests/splines/extreme_scales.rs,
        // a 7e-171 tube with |d| = 4e149) so are these t: multiples of q = 2⁻¹⁰⁷⁴ (f64), which
        // no formula can beat: the hit o + t·d is then up to |d|·q/2 off along the ray, beyond
        // the relative error model. Here tc, big·(1/|d|), s·that and the sum each round by
        // ≤ q/2 absolutely (|s| ≤ 1): |t − t*| ≤ 2q. The ray-space s stays exact (units of big).
        let t_in = self.tc + s_in * self.inv_dlen;
        let t_out = self.tc + s_out * self.inv_dlen;
        let n_in = normal(s_in, u_in, -self.dhat);
        let n_out = normal(s_out, u_out, self.dhat);
        // `clip = false`: hit means only "the line meets it" (for hulls clipped later).
        let range = if clip { in_range(ray, t_in, t_out) } else { t_in.le(t_out) };
        let hit = found & self.near & range;
        Interval::new(Crossing { t: t_in, n: n_in, u: u_in }, Crossing { t: t_out, n: n_out, u: u_out }, hit)
            .masked(hit)
    }
}
