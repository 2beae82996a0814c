//! The certified count of the Polynomial solver (cheaper than `P`'s cascade): on each real piece of `g`,
//! `P`'s Bernstein coefficients with a bound on their rounding ([`crate::math::descartes`])
//! bound the number of critical points of the entry and exit; where that bound equals the
//! number of sign changes of their sign functions, the entry and exit follow from one bracketed
//! solve each, and `P`'s cascade is skipped (see the parent modules' docs).

use super::super::direct::PieceBounds;
use super::{Crossings, RaySpace};
use crate::math::bezier::split_half;
use crate::math::descartes::{bernstein_on, max_sign_variations};
use crate::math::roots::{default_tol, halley, halley_pair, horner, itp, opposite, poly_mul, regula_falsi};
use crate::real::{Mask, Real};
use crate::vec::V3;

impl<T: Real> RaySpace<T> {
    /// The absolute-value chain of [`Self::p_poly`]'s coefficients (for [`bernstein_on`];
    /// `crate::math::descartes` states the rule): the same sums of products on the inputs'
    /// magnitudes, every difference made a sum (a cross product's component
    /// `q_y d̂_z − q_z d̂_y` becomes `|q_y||d̂_z| + |q_z||d̂_y|`). The longest path from `q`, `r`,
    /// `d̂` to `P` has fewer than 25 operations.
    #[inline(always)]
    fn p_poly_abs(&self) -> [T; 7] {
        let two = T::cst(2.0);
        let d = self.dn;
        let cross = |a: V3<T>| V3::new(a.y * d.z + a.z * d.y, a.z * d.x + a.x * d.z, a.x * d.y + a.y * d.x);
        let [qa, qb, qc] = self.qn;
        let (wa, wb, wc) = (cross(qa), cross(qb), cross(qc));
        let [ra, rb, rc] = self.rn;
        let w2 = [wc.dot(wc), two * wc.dot(wb), wb.dot(wb) + two * wc.dot(wa), two * wb.dot(wa), wa.dot(wa)];
        let r2 = [rc * rc, two * rc * rb, rb * rb + two * rc * ra, two * rb * ra, ra * ra];
        let g = [r2[0] + w2[0], r2[1] + w2[1], r2[2] + w2[2], r2[3] + w2[3], r2[4] + w2[4]];
        let h1 = [qb.dot(d), two * qa.dot(d)];
        let g1 = [g[1], two * g[2], T::cst(3.0) * g[3], T::cst(4.0) * g[4]];
        let h1s: [T; 3] = poly_mul(&h1, &h1);
        let a: [T; 7] = poly_mul(&h1s, &g);
        let b: [T; 7] = poly_mul(&g1, &g1);
        let mut p = [T::zero(); 7];
        for i in 0..7 {
            p[i] = T::cst(4.0) * a[i] + b[i];
        }
        p
    }

    /// Entry and exit by a **certified count** instead of `P`'s cascade (its costliest part).
    /// On each real piece `[a, b]` of `g` (consecutive roots `z` of `g` with `g > 0` between,
    /// or points proven off the tube past those roots: [`Direct::g_piece_bounds`], the same
    /// count and crossings)
    /// the entry's sign function `F₁ = 2h'√g − g'` (`= 2√g·f'`) and the exit's
    /// `F̄₁ = −2h'√g − g'` (`= 2√g·(−e)'`) are evaluated at the ends from the vectors, and
    /// `P = −F₁·F̄₁` (`4h'²g − g'²`, whose roots there are exactly the critical points of `f`
    /// and `e`) has at most `V` roots in `(a, b)`, `V` the sign variations of its Bernstein
    /// coefficients on `[a, b]` counted with their rounding ([`max_sign_variations`]). A
    /// function whose end values differ in sign has an odd number of roots there, so at least
    /// one; when `V` equals the number `c` of the two that change sign, each of those has
    /// exactly one simple root and the other none. Then:
    /// * `F₁` rising (`− → +`): `f` falls then rises, its minimum is that root — found by ITP on
    ///   `F₁` over `[a, b]` (the same solve as [`Self::polish`]);
    /// * otherwise `f` is monotone or has one maximum: its minimum is at `a` or `b`.
    ///
    /// Where `V > c` the interval is halved (de Casteljau on the coefficients and on their
    /// bounds, [`split_half`]), to depth [`CERTIFY_DEPTH`]; the exit likewise, and the hull over
    /// the pieces. Returns the crossings, the lanes with a real piece and the **certified**
    /// lanes: those where every real piece was covered by intervals with `V = c` and no end
    /// value exactly 0. Other lanes must take the cascade. The count is certain for `P` as
    /// formed from its rounded inputs (`hv`, `gv`); like the cascade, it assumes that those
    /// roots are the critical points of `f`, `e` evaluated from the vectors (the parent
    /// module's one assumption), and checks the signs of `F₁`, `F̄₁` at the ends against it. A
    /// thin tube's `P` cancels (its coefficients lie within their rounding), and so does `P`
    /// near a root of `g` where `g'` is small: there the count cannot be certain. A node whose
    /// count fails is then certified by Taylor bounds from the vectors instead where they prove
    /// `P` monotone on it (at most one simple root) or of one sign (none, with `c = 0`)
    /// ([`Direct::p_monotone`]); halving continues to depth [`CERTIFY_DEPTH`]. In `f32` this
    /// certifies most thin, tapered and pinched tubes whose count alone was swamped
    /// (`certified_count_agrees_with_the_cascade`; `f64`'s count is rarely swamped), and every
    /// hit of the spline bench. The rest take the cascade.
    ///
    /// [`Direct::p_monotone`]: super::super::direct::Direct::p_monotone
    /// [`Direct::g_piece_bounds`]: super::super::direct::Direct::g_piece_bounds
    #[inline(always)]
    pub(in crate::kernel::spline) fn certified(&self, pb: &PieceBounds<T>) -> (Crossings<T>, T::Mask, T::Mask) {
        let z = &pb.z;
        let (zero, one, half, inf) = (T::zero(), T::one(), T::cst(0.5), T::infinity());
        let dg = self.dg;
        let ends = |t: T| self.ends(t);
        let h1 = self.h1();
        let (p, pa) = (self.p_poly(), self.p_poly_abs());
        // Least f and least −e: [value, t] for σ = 1, −1.
        let mut best = [[inf, zero], [inf, zero]];
        let mut any = T::Mask::splat(false);
        let mut cert = T::Mask::splat(true);
        for k in 0..5 {
            let (a, b) = (z[k], z[k + 1]);
            let real = pb.real(a, b, dg.g((a + b) * half).gt(zero));
            if real.none() {
                continue;
            }
            any = any | real;
            let (bc, m) = bernstein_on(&p, &pa, a - self.tv, b - a);
            // Depth-first: at most one pending sibling per level.
            let mut stack = [Node { a, b, bc, m, ea: ends(a), eb: ends(b), depth: 0, act: real }; CERTIFY_DEPTH + 2];
            let mut top = 1;
            while top > 0 {
                top -= 1;
                let nd = stack[top];
                let v = max_sign_variations(&nd.bc, &nd.m);
                let (ci, co) = (opposite(nd.ea[2], nd.eb[2]), opposite(nd.ea[3], nd.eb[3]));
                let c = T::select(ci, one, zero) + T::select(co, one, zero);
                let mut nonzero = T::Mask::splat(true);
                for e in [nd.ea, nd.eb] {
                    nonzero = nonzero & !(e[2].eq(zero) | e[3].eq(zero));
                }
                let mut ok = v.eq(c) & nonzero;
                // Where the count is not certain (its rounding bound swamps P near a root of g
                // with a small g'), P proven monotone on the node certifies it as well: at most
                // one simple root, so each sign function has one exactly where it changes sign
                // (`Direct::p_monotone`).
                let try_mono = nd.act & !ok & nonzero & c.le(one);
                if try_mono.any() {
                    let (mono, definite) = dg.p_monotone(nd.a, nd.b, h1);
                    ok = ok | (try_mono & (mono | (definite & c.eq(zero))));
                }
                let fin = nd.act & ok;
                if fin.any() {
                    let x = self.certified_crossings(&nd, fin);
                    for side in 0..2 {
                        let take = fin & x[side][0].lt(best[side][0]);
                        best[side] =
                            [T::select(take, x[side][0], best[side][0]), T::select(take, x[side][1], best[side][1])];
                    }
                }
                let need = nd.act & !ok;
                if need.none() {
                    continue;
                }
                if nd.depth == CERTIFY_DEPTH {
                    cert = cert & !need;
                    continue;
                }
                let mid = (nd.a + nd.b) * half;
                let em = ends(mid);
                let (bl, br) = (split_half(&nd.bc), split_half(&nd.m));
                let depth = nd.depth + 1;
                stack[top] = Node { a: mid, b: nd.b, bc: bl.1, m: br.1, ea: em, eb: nd.eb, depth, act: need };
                stack[top + 1] = Node { a: nd.a, b: mid, bc: bl.0, m: br.0, ea: nd.ea, eb: em, depth, act: need };
                top += 2;
            }
        }
        let [[si, ui], [so, uo]] = best;
        (Crossings { s_in: si, u_in: ui, s_out: -so, u_out: uo }, any, cert)
    }

    /// The least `f` and least `−e` (`[value, t]` each) over an interval `nd` where
    /// [`Self::certified`] has shown that `F₁` and `F̄₁` each have at most one root, and one
    /// exactly where their end values differ in sign. A rising sign function's root is the
    /// minimum; otherwise the least end value is.
    ///
    /// Where both functions have their root here, the interval is first halved on the signs of
    /// both at its midpoint (one evaluation serves the two) until the roots lie in different
    /// halves, at most [`CERTIFY_DEPTH`] times. On a bracket of one side's root that holds no
    /// root of the other side's function, that root is the only root of `P = −F₁·F̄₁` there,
    /// and `P` changes sign across it; it is found by Newton on `P` formed from the vectors
    /// ([`Direct::p_jet`]: a polynomial, with no square root and no `√g` singularity at a
    /// real piece's ends, so Newton converges quadratically from the start; a step `≤ tol`
    /// puts the root within about `tol`). The entry's and the exit's solves run in lock step
    /// (`math::roots::halley_pair`), each from the regula-falsi point of its side's own sign function on
    /// the bracket (its end values are known; `P`'s are their products, whose regula-falsi point
    /// leans to the end where `|P|` is the smaller), which takes fewer iterations on the spline
    /// bench's f32 hits than `P`'s own regula-falsi point. Where the halving did not separate
    /// the roots (both still in one bracket, where `P` has the same sign at both ends) the
    /// side's root is found by ITP on its own sign function instead.
    ///
    /// Newton on `P` rather than ITP on `F₁`, `F̄₁`: on the spline bench's f32 hits
    /// (`cargo bench --bench spline`) it takes fewer iterations, each without the two square
    /// roots and ITP's division.
    ///
    /// [`Direct::p_jet`]: super::super::direct::Direct::p_jet
    #[inline(always)]
    fn certified_crossings(&self, nd: &Node<T>, fin: T::Mask) -> [[T; 2]; 2] {
        let (zero, one, two, half) = (T::zero(), T::one(), T::cst(2.0), T::cst(0.5));
        let tol = default_tol::<T>();
        let dg = self.dg;
        let h1 = self.h1();
        let rise = [fin & nd.ea[2].lt(zero) & nd.eb[2].gt(zero), fin & nd.ea[3].lt(zero) & nd.eb[3].gt(zero)];
        let has = [opposite(nd.ea[2], nd.eb[2]), opposite(nd.ea[3], nd.eb[3])];
        // Brackets (a, b, [f, −e, F₁, F̄₁] at a, at b) of each side's root.
        let mut br = [(nd.a, nd.b, nd.ea, nd.eb); 2];
        let both = (rise[0] | rise[1]) & has[0] & has[1];
        // Lanes whose two roots are still in one bracket.
        let mut open = both;
        if both.any() {
            // Halve [lo, hi] (holding both roots) on the signs of F₁, F̄₁ at its midpoint until
            // the roots lie in different halves.
            let (mut lo, mut hi, mut elo, mut ehi) = (nd.a, nd.b, nd.ea, nd.eb);
            for _ in 0..CERTIFY_DEPTH {
                if open.none() {
                    break;
                }
                let mid = (lo + hi) * half;
                let em = self.ends(mid);
                // Root of side k in [lo, mid]: F changes sign between lo and mid, or is 0 at mid
                // (then `b = mid` with `F(b) = 0`, which the solve below returns; counted right
                // instead, `F(lo) = 0` would hide every later sign change).
                let left = [opposite(elo[2], em[2]) | em[2].eq(zero), opposite(elo[3], em[3]) | em[3].eq(zero)];
                let apart = open & ((left[0] & !left[1]) | (!left[0] & left[1]));
                for k in 0..2 {
                    let (l, r) = (apart & left[k], apart & !left[k]);
                    let (a, b, ea, eb) = br[k];
                    br[k] = (
                        T::select(l, lo, T::select(r, mid, a)),
                        T::select(l, mid, T::select(r, hi, b)),
                        sel4(l, elo, sel4(r, em, ea)),
                        sel4(l, em, sel4(r, ehi, eb)),
                    );
                }
                open = open & !apart;
                let (go_left, go_right) = (open & left[0], open & !left[0]);
                hi = T::select(go_left, mid, hi);
                ehi = sel4(go_left, em, ehi);
                lo = T::select(go_right, mid, lo);
                elo = sel4(go_right, em, elo);
            }
            // Still together: both brackets are the common interval.
            for b in &mut br {
                *b = (T::select(open, lo, b.0), T::select(open, hi, b.1), sel4(open, elo, b.2), sel4(open, ehi, b.3));
            }
        }
        // Per side: a valid bracket of its sign function, and of P (the other side's function
        // keeps its sign there: P = −F₁F̄₁ changes sign with this side's).
        let mut valid = [T::Mask::splat(false); 2];
        let mut on_p = [T::Mask::splat(false); 2];
        let mut pv = [[zero; 2]; 2];
        for side in 0..2 {
            let r = rise[side];
            if r.none() {
                continue;
            }
            let (_, _, ea, eb) = br[side];
            valid[side] = r & opposite(ea[side + 2], eb[side + 2]);
            pv[side] = [-(ea[2] * ea[3]), -(eb[2] * eb[3])];
            on_p[side] = valid[side] & !open & opposite(pv[side][0], pv[side][1]);
        }
        let mut xs = [zero; 2];
        if on_p[0].any() || on_p[1].any() {
            let f = move |x: T| dg.p_jet(x, h1)[0];
            let df = move |x: T| dg.p_jet(x, h1)[1];
            let d2f = move |x: T| dg.p_jet(x, h1)[2];
            let (a, b) = ([br[0].0, br[1].0], [br[0].1, br[1].1]);
            // Start at the regula-falsi point of the side's own sign function (its values at
            // the ends are known), not of P = −F₁F̄₁, whose end values are products.
            let start = |k: usize| regula_falsi(a[k], b[k], br[k].2[k + 2], br[k].3[k + 2]);
            xs = if on_p[0].any() && on_p[1].any() {
                let br = [a, b, [pv[0][0], pv[1][0]], [pv[0][1], pv[1][1]]];
                halley_pair(f, df, d2f, br, [start(0), start(1)], on_p, tol)
            } else {
                let k = if on_p[0].any() { 0 } else { 1 };
                let x = halley(f, df, d2f, [a[k], b[k], pv[k][0], pv[k][1]], start(k), on_p[k], tol);
                [x, x]
            };
        }
        // Newton on P converges to a root of P: where the other side's root lies within
        // rounding of the bracket's end, P's computed sign there can disagree with the sign
        // functions' and the root found is the other side's (differential check against the
        // cascade, a bent tube in f32: the exit 0.11 early). At this side's root its own sign
        // function vanishes and the other's is `∓2g'`; at the other's root the reverse: kept
        // only where this side's is the smaller in magnitude, else ITP on it below. Nor where
        // it is within 2·tol of a bracket end: there P's root can be one at (or just beyond)
        // that end, where both sign functions vanish — the slow end of a curve (p' = 0: h' and
        // g' vanish there, P has a double root) drew Newton's step onto the end, whose value
        // P ≈ 0 it then took (fuzz campaign 2501, regression-slow-end-double-root-{1,2}: the
        // exit 0.18 of the extent early).
        let mut at = [[zero; 4]; 2];
        for side in 0..2 {
            if on_p[side].any() {
                let x = xs[side];
                at[side] = self.ends(x);
                let (a, b) = (br[side].0, br[side].1);
                let clear = (x - a).gt(two * tol) & (b - x).gt(two * tol);
                on_p[side] = on_p[side] & clear & at[side][side + 2].abs().le(at[side][3 - side].abs());
            }
        }
        // Sides left to ITP on their sign function (roots not separated, P's end signs not
        // opposite through rounding, or Newton on P found the other side's root).
        for (side, sigma) in [(0, one), (1, -one)] {
            let rest = valid[side] & !on_p[side];
            if rest.none() {
                continue;
            }
            let hs1 = [h1[0] * sigma, h1[1] * sigma];
            let fs = move |x: T| {
                let (_, g, g1) = dg.gap_g_g1(x);
                two * horner(&hs1, x) * g.max(zero).sqrt() - g1
            };
            let (a, b, ea, eb) = br[side];
            let x = itp(fs, a, b, ea[side + 2], eb[side + 2], rest, tol);
            xs[side] = T::select(rest, x, xs[side]);
            at[side] = sel4(rest, self.ends(x), at[side]);
        }
        let mut out = [[zero; 2]; 2];
        for side in 0..2 {
            let (va, vb) = (nd.ea[side], nd.eb[side]);
            let left = va.le(vb);
            let (mut vm, mut tm) = (T::select(left, va, vb), T::select(left, nd.a, nd.b));
            let r = rise[side];
            if r.any() {
                let (a, b, ea, eb) = br[side];
                let (za, zb) = (ea[side + 2].eq(zero), eb[side + 2].eq(zero));
                let x = T::select(za, a, T::select(zb, b, xs[side]));
                // `ends` gives +∞ off the tube.
                let vx = T::select(za, ea[side], T::select(zb, eb[side], at[side][side]));
                let better = r & vx.lt(vm);
                vm = T::select(better, vx, vm);
                tm = T::select(better, x, tm);
            }
            out[side] = [vm, tm];
        }
        out
    }

    /// `[f, −e, F₁, F̄₁]` at `t` (entry and minus exit distances, and their sign functions);
    /// `f`, `−e` are `+∞` where `t`'s sphere is surely off the line (gap `< −τ`).
    #[inline(always)]
    fn ends(&self, t: T) -> [T; 4] {
        let two = T::cst(2.0);
        let (gap, g, g1) = self.dg.gap_g_g1(t);
        let sq = g.max(T::zero()).sqrt();
        let hv = horner(&self.h, t);
        let hs = two * (self.h[1] + two * self.h[2] * t) * sq;
        // Not a point of the tube (a run's outside end, or a midpoint near one): no candidate.
        let real = gap.ge(-self.dg.tau);
        let inf = T::infinity();
        [T::select(real, hv - sq, inf), T::select(real, -hv - sq, inf), hs - g1, -hs - g1]
    }
}

/// `[f, −e, F₁, F̄₁]` values chosen per lane.
#[inline(always)]
fn sel4<T: Real>(m: T::Mask, a: [T; 4], b: [T; 4]) -> [T; 4] {
    [T::select(m, a[0], b[0]), T::select(m, a[1], b[1]), T::select(m, a[2], b[2]), T::select(m, a[3], b[3])]
}

/// Halvings of a real piece before [`RaySpace::certified`] gives up (at most `2^depth`
/// intervals, each with a count). 6, not 4, since the Taylor certificate (which tightens as
/// a node shrinks, where the count does not): the last two of the spline bench's uncertified
/// f32 hits needed nodes of width 1/64 next to a root of `g`.
const CERTIFY_DEPTH: usize = 6;

/// An interval of [`RaySpace::certified`]: `P`'s Bernstein coefficients on it and their
/// bounds, `[f, −e, F₁, F̄₁]` at its ends, its depth and the lanes it is for.
#[derive(Clone, Copy)]
struct Node<T: Real> {
    a: T,
    b: T,
    bc: [T; 7],
    m: [T; 7],
    ea: [T; 4],
    eb: [T; 4],
    depth: usize,
    act: T::Mask,
}
