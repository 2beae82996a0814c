//! `g` and its derivatives evaluated from the ray-space **vectors** (see "Conditioning" in the
//! parent module): `g = (r − |w|)(r + |w|)`, `w = q × d̂`, never from `g`'s expanded
//! coefficients, whose rounding (`ε` of terms of size 1 in units of the bounding radius) is
//! `ε·(L/r)²` of the values `≈ (r/L)²` that decide a thin tube's hits.

use crate::math::quadric::quadratic_roots_in;
use crate::math::roots::{
    cascade_level, cascade_level_halley, default_tol, halley, model_start, no_start, opposite, Bracket,
};
use crate::real::{Mask, Real};
use crate::vec::V3;

/// The power-basis vectors `w = wa t² + wb t + wc` (`w = q × d̂`, the centre's offset from the
/// line), the radius `r = ra t² + rb t + rc` (units of the bounding radius), their values at
/// `t = 1` formed from the end itself, and the gap tolerance `τ`.
#[derive(Clone, Copy, Debug)]
pub(super) struct Direct<T: Real> {
    wa: V3<T>,
    wb: V3<T>,
    wc: V3<T>,
    ra: T,
    rb: T,
    rc: T,
    /// `w(1) = c₂ × d̂` and `r(1) = r₂` from the end (exact 0 for a zero-radius end on the line,
    /// fuzz finding regression-tip-on-ray); `t = 0` is exact anyway (`wc`, `rc`).
    w_end: V3<T>,
    r_end: T,
    /// Bound on the rounding of the computed gap `r(t) − |w(t)|` on `[0, 1]` (see the parent
    /// module's "Conditioning"): `16ε·(Σ|r_k| + Σ|w_k|)`.
    pub(super) tau: T,
}

impl<T: Real> Direct<T> {
    /// From the power-basis position `q = qa t² + qb t + qc` (re-centred, in units of the
    /// bounding radius), the radius coefficients, the unit direction and the end `c₂`, `r₂`.
    #[inline(always)]
    pub(super) fn new(q: [V3<T>; 3], r: [T; 3], dhat: V3<T>, end: (V3<T>, T)) -> Self {
        let [wa, wb, wc] = [q[0].cross(dhat), q[1].cross(dhat), q[2].cross(dhat)];
        let [ra, rb, rc] = r;
        let sw = wa.length() + wb.length() + wc.length();
        let sr = ra.abs() + rb.abs() + rc.abs();
        let tau = T::epsilon() * T::cst(16.0) * (sw + sr);
        Self { wa, wb, wc, ra, rb, rc, w_end: end.0.cross(dhat), r_end: end.1, tau }
    }

    /// `w(t)` and `r(t)` (Horner; the end values at `t ≥ 1`).
    #[inline(always)]
    fn wr(&self, t: T) -> (V3<T>, T) {
        let w = (self.wa * t + self.wb) * t + self.wc;
        let r = (self.ra * t + self.rb) * t + self.rc;
        let end = t.ge(T::one());
        (V3::select(end, self.w_end, w), T::select(end, self.r_end, r))
    }

    /// `(r − |w|, g)` at `t`: the signed gap of the line to the sphere `t` and `g = r² − |w|²`
    /// formed as `(r − |w|)(r + |w|)`.
    #[inline(always)]
    pub(super) fn gap_g(&self, t: T) -> (T, T) {
        let (w, r) = self.wr(t);
        let lw = w.length();
        let gap = r - lw;
        (gap, gap * (r + lw))
    }

    /// `g(t)`.
    #[inline(always)]
    pub(super) fn g(&self, t: T) -> T {
        self.gap_g(t).1
    }

    /// `g(t) = r² − |w|²` formed without the square root of `|w|`: as accurate as
    /// [`Self::g`] (both carry the absolute rounding of `w` itself, `~4ε·Σ|w_k|` times `2|w|`,
    /// far above that of either product form) and a square root shorter on each step of the
    /// Halley solves for `g`'s roots ([`Self::g_roots`]).
    #[inline(always)]
    fn g_sq(&self, t: T) -> T {
        let (w, r) = self.wr(t);
        r * r - w.dot(w)
    }

    /// `(w, r, w', r')` at `t`.
    #[inline(always)]
    fn jet(&self, t: T) -> (V3<T>, T, V3<T>, T) {
        let two = T::cst(2.0);
        let (w, r) = self.wr(t);
        (w, r, self.wa * (two * t) + self.wb, two * self.ra * t + self.rb)
    }

    /// `(r − |w|, g, g')` at `t` from one evaluation of the jet.
    #[inline(always)]
    pub(super) fn gap_g_g1(&self, t: T) -> (T, T, T) {
        let (w, r, w1, r1) = self.jet(t);
        let lw = w.length();
        let gap = r - lw;
        (gap, gap * (r + lw), T::cst(2.0) * (r * r1 - w.dot(w1)))
    }

    /// `P = 4h'²g − g'²`, `P'` and `P''` at `t` from the vectors, for `h' = h1[0] + h1[1]·t`
    /// (`h''' = 0`): `P' = 8h'h''g + 4h'²g' − 2g'g''`,
    /// `P'' = 8h''²g + 16h'h''g' + 4h'²g'' − 2g''² − 2g'g'''`. With `g = r² − |w|²` formed
    /// without the square root of `|w|`: both forms carry the absolute rounding of `w` itself
    /// (`~4ε·Σ|w_k|`, times `2|w|`), so this one is as accurate and cheaper. Only the certified
    /// count's root solve uses it (`RaySpace::certified`), where `P` has one simple root in
    /// the bracket.
    #[inline(always)]
    pub(super) fn p_jet(&self, t: T, h1: [T; 2]) -> [T; 3] {
        p_from(self.g_jet(t), h1[0] + h1[1] * t, h1[1])
    }

    /// `[g, g', g'', g''']` at `t` from one evaluation of the jet (`g` without the square root
    /// of `|w|`, as [`Self::g_sq`]).
    #[inline(always)]
    fn g_jet(&self, t: T) -> [T; 4] {
        let two = T::cst(2.0);
        let (w, r, w1, r1) = self.jet(t);
        let g = r * r - w.dot(w);
        let g1 = two * (r * r1 - w.dot(w1));
        let g2 = two * (r1 * r1 + r * (two * self.ra) - w1.dot(w1) - w.dot(self.wa * two));
        [g, g1, g2, self.g3(t)]
    }

    /// Whether `P = 4h'²g − g'²` as [`Self::p_jet`] forms it (from the stored vectors and
    /// `h' = h1[0] + h1[1]·t`) is **strictly monotone** on `[a, b]`, proven by Taylor bounds
    /// about the midpoint `m` (`ρ` = the larger half width): for `t ∈ [a, b]`
    /// `|P'(t)| ≥ |P'(m)| − ρ·max|P''|`, `max|P''| ≤ |P''(m)| + ρ·max|P'''|`, and
    /// `P''' = 24h''²g' + 24h'h''g'' + 4h'²g''' − 6g''g''' − 2g'g''''` (`h''' = 0`) is bounded
    /// by the same chain for `g`'s derivatives (`max|g⁽ᵏ⁾| ≤ |g⁽ᵏ⁾(m)| + ρ·max|g⁽ᵏ⁺¹⁾|`, from
    /// the constant `g''''`) and `max|h'| ≤ |h'(m)| + ρ|h''|`. A monotone `P` has at most one
    /// root in `[a, b]`, and it is simple: the certificate `RaySpace::certified` needs where
    /// its Bernstein count cannot give one. Close to a root of `g` where `g'` is small (a line
    /// nearly tangent to the tube there) `P ≈ −g'²` lies below the rounding bound of its
    /// coefficients on every small interval, while its derivative from the vectors is still
    /// clearly non-zero (the f32 hits of the spline bench that the count left uncertified).
    ///
    /// *Rounding.* Each value at `m` is a formula of at most ~12 roundings on the stored
    /// coefficients: its error is below `32ε` times the same formula on their magnitudes (the
    /// `…a` terms below, every difference made a sum); `P'(m)`, `P''(m)` add the propagation
    /// of those errors and their own, bounded by `64ε` times their magnitude formulas. The
    /// bounds are sums of non-negative terms (each rounding relative `≤ ε`), and the final
    /// comparison takes a further factor `1 + 64ε` on the side that must be exceeded. The
    /// statement is about the `P` of the stored coefficients: the polynomial whose root the
    /// certified path then solves (`p_jet`), and the product of the sign functions evaluated
    /// from the same vectors.
    #[inline(always)]
    pub(super) fn p_monotone(&self, a: T, b: T, h1: [T; 2]) -> (T::Mask, T::Mask) {
        let (two, four, half) = (T::cst(2.0), T::cst(4.0), T::cst(0.5));
        let eps = T::epsilon();
        let m = (a + b) * half;
        let rho = (b - m).max(m - a) * (T::one() + four * eps);
        let [g, g1, g2, g3] = self.g_jet(m);
        let g4 = T::cst(24.0) * self.g3_coeffs().1;
        // The magnitude formulas (m ∈ [0, 1]).
        let av = |v: V3<T>| V3::new(v.x.abs(), v.y.abs(), v.z.abs());
        let (aa, ab, ac) = (av(self.wa), av(self.wb), av(self.wc));
        let (ra, rb, rc) = (self.ra.abs(), self.rb.abs(), self.rc.abs());
        let mm = m.abs();
        let wa = (aa * mm + ab) * mm + ac;
        let w1a = aa * (two * mm) + ab;
        let r_a = (ra * mm + rb) * mm + rc;
        let r1a = two * ra * mm + rb;
        let ga = r_a * r_a + wa.dot(wa);
        let g1a = two * (r_a * r1a + wa.dot(w1a));
        let g2a = two * (r1a * r1a + r_a * (two * ra) + w1a.dot(w1a) + wa.dot(aa * two));
        let g3a = T::cst(12.0) * (ra * rb + aa.dot(ab) + two * mm * (ra * ra + aa.dot(aa)));
        let g4a = T::cst(24.0) * (ra * ra + aa.dot(aa));
        let e = T::cst(32.0) * eps;
        let big4 = g4.abs() + e * g4a;
        let big3 = g3.abs() + e * g3a + big4 * rho;
        let big2 = g2.abs() + e * g2a + big3 * rho;
        let big1 = g1.abs() + e * g1a + big2 * rho;
        let (hp, hpp) = (h1[0] + h1[1] * m, h1[1]);
        let ha = h1[0].abs() + hpp.abs() * mm;
        let h2a = hpp.abs();
        let hmax = ha * (T::one() + four * eps) + h2a * rho;
        let [p0, p1, p2] = p_from([g, g1, g2, g3], hp, hpp);
        // Errors of P'(m), P''(m): each term c·x·y·z contributes c·(Π(|x| + δx) − Π|x|) from its
        // factors' errors and 16ε·c·Π|x| from its own roundings (and the difference's).
        let dh = four * eps * ha;
        let (dg0, dg1, dg2, dg3) = (e * ga, e * g1a, e * g2a, e * g3a);
        let (hu, hpa) = (hp.abs() + dh, hp.abs());
        let (a0, a1, a2, a3) = (g.abs(), g1.abs(), g2.abs(), g3.abs());
        let (u0, u1, u2, u3) = (a0 + dg0, a1 + dg1, a2 + dg2, a3 + dg3);
        let e16 = T::cst(16.0) * eps;
        let term = |c: f64, u: T, a: T| T::cst(c) * ((u - a) + e16 * a);
        let d1 = term(8.0, hu * h2a * u0, hpa * h2a * a0)
            + term(4.0, hu * hu * u1, hpa * hpa * a1)
            + term(2.0, u1 * u2, a1 * a2);
        let d2 = term(8.0, h2a * h2a * u0, h2a * h2a * a0)
            + term(16.0, hu * h2a * u1, hpa * h2a * a1)
            + term(4.0, hu * hu * u2, hpa * hpa * a2)
            + term(2.0, u2 * u2, a2 * a2)
            + term(2.0, u1 * u3, a1 * a3);
        let e2 = T::cst(64.0) * eps;
        let b3 = T::cst(24.0) * h2a * h2a * big1
            + T::cst(24.0) * hmax * h2a * big2
            + four * hmax * hmax * big3
            + T::cst(6.0) * big2 * big3
            + two * big1 * big4;
        let b2 = p2.abs() + d2 + b3 * rho;
        let need = (d1 + b2 * rho) * (T::one() + e2);
        // P of one sign on [a, b]: |P(t) − P(m)| ≤ ρ|P'(m)| + ρ²/2·max|P''|.
        let d0 = term(4.0, hu * hu * u0, hpa * hpa * a0) + term(1.0, u1 * u1, a1 * a1);
        let reach = (d0 + (p1.abs() + d1) * rho + b2 * rho * rho * half) * (T::one() + e2);
        let definite = p0.abs().gt(reach) & reach.is_finite();
        // False for NaN (a NaN bound or value compares false).
        (p1.abs().gt(need) & need.is_finite(), definite)
    }

    /// `g'(t) = 2(r r' − w·w')`.
    #[inline(always)]
    pub(super) fn g1(&self, t: T) -> T {
        let (w, r, w1, r1) = self.jet(t);
        T::cst(2.0) * (r * r1 - w.dot(w1))
    }

    /// `g''(t) = 2(r'² + r r'' − |w'|² − w·w'') = 2(6A t² + 6B t + C)` with `A = ra² − |wa|²`,
    /// `B = ra rb − wa·wb`, `C = rb² + 2ra rc − |wb|² − 2wa·wc`.
    #[inline(always)]
    pub(super) fn g2(&self, t: T) -> T {
        let two = T::cst(2.0);
        let (w, r, w1, r1) = self.jet(t);
        two * (r1 * r1 + r * (two * self.ra) - w1.dot(w1) - w.dot(self.wa * two))
    }

    /// `g'''(t) = 6(r' r'' − w'·w'') = 12((ra rb − wa·wb) + 2t(ra² − |wa|²))`.
    #[inline(always)]
    pub(super) fn g3(&self, t: T) -> T {
        let (c0, c1) = self.g3_coeffs();
        T::cst(12.0) * (c0 + T::cst(2.0) * t * c1)
    }

    #[inline(always)]
    fn g3_coeffs(&self) -> (T, T) {
        (self.ra * self.rb - self.wa.dot(self.wb), self.ra * self.ra - self.wa.dot(self.wa))
    }

    /// The roots of `g'` on `[0, 1]` (with both ends: `g` monotone between consecutive
    /// entries), and in [`Self::g_breakpoints`] those of `g`, by the derivative cascade `g''` (quadratic,
    /// solved in closed form with [`Bracket::Newton`]; else `g'''` → `g''` as a cascade level)
    /// → `g'` → `g`, every level evaluated from the vectors ([`Self::g2`], [`Self::g1`],
    /// [`Self::g`]):
    /// * `roots`: `0 = z₀ ≤ … ≤ z₅ = 1` with `g` of one sign between them (its real intervals
    ///   are unions of pieces);
    /// * `extrema`: `0 = y₀ ≤ … ≤ y₄ = 1` with `g` monotone between them, so every maximum of
    ///   `g` — the deepest point of each real interval — is one of them.
    ///
    /// A real interval's ends alone are not enough candidates: √g = 0 there, and when the ray
    /// crosses a thin tube the entry and exit lie at its interior maximum (differential fuzz
    /// finding, `regression-spline-f32-exit-at-end`: in f32 at L/r ≈ 4,000, with `P`'s roots
    /// lost to rounding, the exit was taken at the end `t = 1` of the real interval and its
    /// polish bracket held no root: 9.2·10⁻⁷ against 0.166).
    #[inline(always)]
    pub(super) fn g_extrema(&self, m: Bracket) -> [T; 5] {
        let (zero, one) = (T::zero(), T::one());
        // g'' is the quadratic 2(6A t² + 6B t + C) (module docs of `g2`): its roots in closed
        // form (no cancellation in the formula, `quadratic_roots_in`) replace a Newton level
        // of the cascade, which would be an iterative solve. Its coefficients are dot products
        // of the vectors, rounded like g'' evaluated from them.
        // With a fixed-step bracket method (Bisection) the cascade from g''''s vertex is
        // kept: the vertex stays a breakpoint, narrowing g''s pieces, and its false-miss rates
        // (tests/splines/approximate_solvers.rs) are those measured.
        let (b, a) = self.g3_coeffs();
        let bp = if m == Bracket::Newton {
            let c = self.rb * self.rb + T::cst(2.0) * self.ra * self.rc
                - self.wb.dot(self.wb)
                - T::cst(2.0) * self.wa.dot(self.wc);
            let six = T::cst(6.0);
            let (x1, x2) = quadratic_roots_in(&[c, six * b, six * a], zero, one);
            let mut bp = [one; 8];
            bp[0] = zero;
            bp[1] = x1;
            bp[2] = x2;
            bp
        } else {
            let den = T::cst(2.0) * a;
            let ok = !den.eq(zero) & den.is_finite();
            let t3 = -b / T::select(ok, den, one);
            let t3 = T::select(ok & t3.gt(zero) & t3.lt(one), t3, one);
            let mut bp = [one; 8];
            bp[0] = zero;
            bp[1] = t3;
            cascade_level(&bp, 3, |t| self.g2(t), |t| self.g3(t), m)
        };
        let ext = if m == Bracket::Newton {
            cascade_level_halley(
                &bp,
                4,
                |t| self.g1(t),
                |t| self.g2(t),
                |t| self.g3(t),
                |a, b, fa, fb| self.g1_root_start(a, b, fa, fb),
            )
        } else {
            cascade_level(&bp, 4, |t| self.g1(t), |t| self.g2(t), m)
        };
        [ext[0], ext[1], ext[2], ext[3], ext[4]]
    }

    /// The roots of `g` on `[0, 1]` from its extrema ([`Self::g_extrema`]): the last level of
    /// [`Self::g_breakpoints`].
    #[inline(always)]
    pub(super) fn g_roots(&self, extrema: [T; 5], m: Bracket) -> [T; 6] {
        self.g_roots_from(extrema, m, no_start)
    }

    /// [`Self::g_roots`], the Halley solves ([`Bracket::Newton`]) started at `start`.
    #[inline(always)]
    fn g_roots_from(&self, extrema: [T; 5], m: Bracket, start: impl Fn(T, T, T, T) -> T + Copy) -> [T; 6] {
        let e = extrema;
        let ext = [e[0], e[1], e[2], e[3], e[4], e[4], e[4], e[4]];
        let bp = if m == Bracket::Newton {
            cascade_level_halley(&ext, 5, |t| self.g_sq(t), |t| self.g1(t), |t| self.g2(t), start)
        } else {
            cascade_level(&ext, 5, |t| self.g(t), |t| self.g1(t), m)
        };
        [bp[0], bp[1], bp[2], bp[3], bp[4], bp[5]]
    }

    /// [`Self::g_roots`] with [`Bracket::Newton`], each Halley solve started at
    /// [`Self::g_root_start`] instead of the regula-falsi point: the Polynomial solver's (its
    /// certified count needs only that the roots bound `g`'s real pieces to the solve's
    /// tolerance). Russig's cascade ([`Solver::Newton`]) keeps the regula-falsi start: its
    /// real intervals' ends decide the signs of its scaled sign functions there, and on fuzz
    /// finding `tiny_ball_like_tube_with_large_direction` (tests/splines/extreme_scales.rs) a root
    /// of `g` at 9e-23 instead of 2.7e-20 — both within the tolerance 9e-16 of the true 2.7e-20
    /// — made its cascade take the end of the real interval for the entry (t = 0 for −R/|d|).
    ///
    /// [`Solver::Newton`]: crate::Solver::Newton
    #[inline(always)]
    pub(super) fn g_roots_started(&self, extrema: [T; 5]) -> [T; 6] {
        self.g_roots_from(extrema, Bracket::Newton, |a, b, fa, fb| self.g_root_start(a, b, fa, fb))
    }

    /// Points that bound `g`'s real pieces **from outside**, for the certified count
    /// (`RaySpace::certified`), in the layout of [`Self::g_roots_started`] (`0 = z₀ ≤ … ≤
    /// z₅ = 1`): in each monotone piece `[a, b]` of `g` (consecutive extrema) whose ends
    /// differ in sign, instead of the root, a point `z` past it on the side where `g < 0`,
    /// proven so: its computed gap is `< −τ` (so the gap of the perturbed data, within `τ` of
    /// it, is negative: the sphere `z` misses the line, see "Conditioning" in the parent module)
    /// and `g'` has, at `z`, the sign of `g(b) − g(a)`. As `g` is monotone on `[a, b]`, all of
    /// `[a, b]` beyond `z` is off the tube and the real part lies on the other side; there
    /// `√max(g, 0) = 0`, so the sign functions are `F₁ = F̄₁ = −g'`, of the sign they have at
    /// the root itself, and `P = 4h'²g − g'² < 0` has no root. A count on the widened piece is
    /// therefore the count on the real piece, and its entry and exit the same.
    ///
    /// `z` is the root of the Taylor model of [`Self::g_root_start`] (the Halley start, third
    /// order about an extremum) pushed an eighth of its distance from the model's end further
    /// towards the `g < 0` end: no Halley iterations (the solves for `g`'s roots were a large
    /// share of an f32 hit's cost). Where a piece's point fails the proof (the model has no root
    /// there, or a poor one — from an end that is not an extremum —, or the push does not
    /// clear `τ`: a tube thinner than about `8τ`) that piece's root is solved as
    /// [`Self::g_roots_started`] solves it (the same start, the same root); on the spline
    /// bench's f32 hits 30 of 232 pieces. Lanes with an end value exactly 0 (where the cascade
    /// moves the bracket end inside) take [`Self::g_roots_started`] for all their pieces.
    #[inline(always)]
    pub(super) fn g_piece_bounds(&self, extrema: [T; 5]) -> PieceBounds<T> {
        let zero = T::zero();
        let e = extrema;
        let mut out = [zero; 6];
        out[0] = e[0];
        out[5] = e[4];
        let mut exact = T::Mask::splat(false);
        let fv = [self.g_sq(e[0]), self.g_sq(e[1]), self.g_sq(e[2]), self.g_sq(e[3]), self.g_sq(e[4])];
        for i in 0..4 {
            let (a, b, fa, fb) = (e[i], e[i + 1], fv[i], fv[i + 1]);
            let zero_end = fa.eq(zero) | fb.eq(zero);
            exact = exact | zero_end;
            let change = opposite(fa, fb);
            // The placeholder of a piece without a root, as `cascade_level_halley` sets it.
            let ph = T::select(fa.eq(zero), a, b);
            out[i + 1] = ph;
            if change.none() {
                continue;
            }
            let x0 = self.g_root_start(a, b, fa, fb);
            let from = T::select(fa.abs().le(fb.abs()), a, b);
            let to_b = fb.lt(zero);
            let push = (x0 - from).abs() * T::cst(0.125);
            let z = x0 + T::select(to_b, push, -push);
            let (gap, _, g1) = self.gap_g_g1(z);
            let sign_ok = T::select(to_b, -g1, g1).gt(zero);
            let ok = change & z.gt(a) & z.lt(b) & gap.lt(-self.tau) & sign_ok;
            out[i + 1] = T::select(ok, z, ph);
            // Where the proof fails, this piece's root (the solve `g_roots_started` makes
            // there, from the same start: the same root).
            let solve = change & !ok & !zero_end;
            if solve.any() {
                let x =
                    halley(|t| self.g_sq(t), |t| self.g1(t), |t| self.g2(t), [a, b, fa, fb], x0, solve, default_tol());
                out[i + 1] = T::select(solve, x, out[i + 1]);
            }
        }
        if exact.any() {
            let ex = self.g_roots_started(extrema);
            for i in 1..5 {
                out[i] = T::select(exact, ex[i], out[i]);
            }
        }
        PieceBounds { z: out, ext: e, g_ext: fv, exact }
    }

    /// A start for the solve of `g'`'s root in `[a, b]` (`g'(a) = fa`, `g'(b) = fb` of opposite
    /// signs; the ends are roots of the quadratic `g''` or the segment's ends): from the end
    /// with the smaller `|g'|` where that is inside `(0, 1)`, a root `e` of `g''`, the root of
    /// the model `g'(e) + ½g'''(e)δ² = 0` (exact to third order: `g''''` is constant), which
    /// needs only `g'''` (linear) besides the known `g'(e)`; NaN elsewhere (the regula-falsi
    /// point). On the spline bench's f32 hits it takes fewer lock-step iterations than the
    /// regula-falsi point, per pair and per single solve. Every
    /// solver's cascade uses it ([`Self::g_extrema`] with [`Bracket::Newton`]).
    #[inline(always)]
    fn g1_root_start(&self, a: T, b: T, fa: T, fb: T) -> T {
        let (zero, one) = (T::zero(), T::one());
        let from_a = fa.abs().le(fb.abs());
        let (e, f) = (T::select(from_a, a, b), T::select(from_a, fa, fb));
        let dir = T::select(from_a, one, -one);
        let r = T::cst(-2.0) * f / self.g3(e);
        let ok = e.gt(zero) & e.lt(one) & r.gt(zero);
        T::select(ok, e + dir * r.max(zero).sqrt(), T::cst(f64::NAN))
    }

    /// A start for the solve of `g`'s root in `[a, b]` (`g(a) = ga`, `g(b) = gb` of opposite
    /// signs): [`model_start`] about the end with the smaller `|g|`. At an extremum (`g' = 0`,
    /// most piece ends) the model is `g + ½g''δ² = 0`, exact to third order: for a thin tube,
    /// whose real part is a narrow cap on `g`'s maximum, the start is within `~|g'''|δ²/(6|g''|)`
    /// of the root (`δ` the root's distance from the end). On the spline bench's f32 hits the
    /// solves for `g`'s roots take fewer iterations from this start than from the regula-falsi
    /// point, per pair and per single solve.
    #[inline(always)]
    fn g_root_start(&self, a: T, b: T, ga: T, gb: T) -> T {
        let from_a = ga.abs().le(gb.abs());
        let e = T::select(from_a, a, b);
        let [_, g1, g2, _] = self.g_jet(e);
        model_start(e, T::select(from_a, T::one(), -T::one()), [T::select(from_a, ga, gb), g1, g2])
    }

    /// [`Self::g_extrema`] and [`Self::g_roots`].
    #[inline(always)]
    pub(super) fn g_breakpoints(&self, m: Bracket) -> GBreaks<T> {
        let extrema = self.g_extrema(m);
        GBreaks { roots: self.g_roots(extrema, m), extrema }
    }
}

/// `[P, P', P'']` of `P = 4h'²g − g'²` from `[g, g', g'', g''']`, `h'` and `h''` (`h''' = 0`):
/// `P' = 8h'h''g + 4h'²g' − 2g'g''`, `P'' = 8h''²g + 16h'h''g' + 4h'²g'' − 2g''² − 2g'g'''`.
#[inline(always)]
fn p_from<T: Real>([g, g1, g2, g3]: [T; 4], hp: T, hpp: T) -> [T; 3] {
    let (two, four) = (T::cst(2.0), T::cst(4.0));
    let hp2 = hp * hp;
    let p = four * hp2 * g - g1 * g1;
    let p1 = T::cst(8.0) * hp * hpp * g + four * hp2 * g1 - two * g1 * g2;
    let p2 =
        T::cst(8.0) * hpp * hpp * g + T::cst(16.0) * hp * hpp * g1 + four * hp2 * g2 - two * g2 * g2 - two * g1 * g3;
    [p, p1, p2]
}

/// [`Direct::g_piece_bounds`]: breakpoints `z` (`0 = z₀ ≤ … ≤ z₅ = 1`) between which `g` is of
/// one sign **or** a real piece lies with a margin off the tube on either side, and what tells
/// the two kinds of piece apart.
#[derive(Clone, Copy, Debug)]
pub(super) struct PieceBounds<T: Real> {
    /// The breakpoints.
    pub(super) z: [T; 6],
    /// `g`'s extrema (the input) and `g` at them (`r² − |w|²`).
    pub(super) ext: [T; 5],
    pub(super) g_ext: [T; 5],
    /// Lanes whose `z` are all `g`'s roots as [`Direct::g_roots_started`] gives them (an end
    /// value exactly 0); elsewhere each `z` is a root or a bound.
    pub(super) exact: T::Mask,
}

impl<T: Real> PieceBounds<T> {
    /// Whether the piece `[a, b]` (consecutive breakpoints) holds a real part, given
    /// `g((a + b)/2) > 0` as `mid_real`. Where `z` are `g`'s roots, `g` has one sign on the
    /// piece and its midpoint decides. Where some are bounds, a widened real piece's midpoint
    /// can lie in a margin off the tube; but each real piece holds an extremum of `g` with
    /// `g > 0` (it begins at a segment end with `g > 0`, or at a root or bound in a monotone
    /// piece `[eᵢ, eᵢ₊₁]` where `g` rises, so `g(eᵢ₊₁) > 0`, and `eᵢ₊₁` lies before the
    /// breakpoint that ends it, which is in a later monotone piece), while a piece off the tube
    /// holds no extremum with `g > 0` (those in it are ends of monotone pieces whose sign
    /// change lies on the tube's side, or of pieces without one, `g < 0` at both ends: an end
    /// value exactly 0 makes the lane `exact`): so an extremum with `g > 0` in `[a, b]`
    /// decides as well.
    #[inline(always)]
    pub(super) fn real(&self, a: T, b: T, mid_real: T::Mask) -> T::Mask {
        let mut real = mid_real;
        for i in 0..5 {
            let (e, g) = (self.ext[i], self.g_ext[i]);
            real = real | (!self.exact & e.ge(a) & e.le(b) & g.gt(T::zero()));
        }
        real & b.gt(a)
    }
}

/// [`Direct::g_breakpoints`]: the roots of `g` and of `g'` on `[0, 1]`, with both ends.
#[derive(Clone, Copy, Debug)]
pub(super) struct GBreaks<T> {
    /// `g` of one sign between consecutive entries.
    pub(super) roots: [T; 6],
    /// `g` monotone between consecutive entries (its maxima are among them).
    pub(super) extrema: [T; 5],
}

#[cfg(test)]
impl<T: crate::real::Scalar> Direct<T> {
    /// The stored coefficients in f64 (exactly): `([wa, wb, wc], [ra, rb, rc])`.
    pub(super) fn coeffs_f64(&self) -> ([V3<f64>; 3], [f64; 3]) {
        ([self.wa.cast(), self.wb.cast(), self.wc.cast()], [self.ra.to_f64(), self.rb.to_f64(), self.rc.to_f64()])
    }
}
