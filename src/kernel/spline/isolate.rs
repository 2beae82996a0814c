//! The Polynomial solver's candidates: the roots of `P = 4h'²g − g'²` in `[0, 1]` by
//! **Bernstein-form isolation** (issue 10's cost), replacing the two power-basis derivative
//! cascades (kept as a test oracle in `cascade.rs`).
//!
//! *Form.* The curve is split at `tv`, the vertex of the centre line (least `|p'|`), into the
//! pieces `[0, tv]` and `[tv, 1]`; each piece's control net comes from de Casteljau on the
//! re-centred unit control points, with its **differences formed from the differences**
//! `c₁ − c₀`, `c₂ − c₁` (so a slow end, `b₁ = b₂`, has `h' = 0`, `w' = 0` exactly there, as the
//! old expansion about `tv` had). On a piece, in its own parameter `u ∈ [0, 1]`,
//! `w = Σ Wᵢ Bᵢ²` (`Wᵢ = Cᵢ × d̂`), `r = Σ Rᵢ Bᵢ²`, `h'/2 = Σ eⱼ Bⱼ¹` (`eⱼ = ΔCⱼ·d̂`),
//! `g = r² − |w|²` (degree 4: `(RᵢRⱼ − Wᵢ·Wⱼ)` combined by the product weights),
//! `g'/4 = r·r'/2 − w·w'/2` (degree 3), and `P/16 = (h'/2)²g − (g'/4)²` (degree 6), all by
//! Bernstein products ([`crate::math::bernstein::mul`]) — no power-basis expansion.
//!
//! *Why it finds what the cascades found.* Both methods find the roots of a rounded `P`;
//! neither's candidates are trusted (every decision and value is formed from the vectors,
//! `direct.rs`, and the best candidate is polished on `F₁` from the vectors, see the parent
//! module). Three cases, with `η(t)` the rounding of the computed `P` at `t`:
//! 1. *`|P| > η` on both sides of a simple root, roots farther apart than `2⁻¹⁶` of a piece*
//!    (ordinary tubes, the bench's rays): the computed polynomial has the true sign pattern
//!    there, the halving reaches an interval with `V = 1` around the root (Descartes' rule,
//!    variation diminishing: `V` → the root count as the width → 0) and safeguarded Newton
//!    refines it to `4ε` in `t` — the cascade's tolerance — so the same root is found within
//!    the same `δ` (the root's condition `η/|P'|` plus `4ε`), as a root of a polynomial whose
//!    coefficients carry no more rounding than the power expansions' (each Bernstein
//!    coefficient is a positive-weight average of products of the net's values, rounding
//!    `≲ 10ε` of `Σ` of their sizes; the power coefficients sum signed products of the same
//!    sizes, and the power basis on `[0, 1]` is never better conditioned than the Bernstein
//!    basis — Farouki & Rajan 1987).
//! 2. *Clustered pairs (roots closer than `2⁻¹⁶` of the piece) and multiple roots*: the
//!    cascade returns the pair's roots or their `P'` root between them; here the deepest
//!    interval's midpoint, within `2⁻¹⁷` of each. The pair's critical points of `f` (an entry
//!    minimum next to a maximum of `f`, or a critical point of `f` next to one of `e`) are then
//!    within `2⁻¹⁷` of a candidate, and `f' = (t − t₁)(t − t₂)·k` there gives a value within
//!    `2⁻⁵¹·|k|` of the minimum — below `E` in both precisions — and the polish (ITP on `F₁`
//!    from the vectors between the candidate and its neighbours) then converges to the root of
//!    `F₁` the candidate's sign points to. A slow vertex (`p' ≈ 0`, where `P` is tiny over a
//!    wide range: why the old code had a second expansion about `tv`) is a piece end: its net
//!    there is formed from the local values `q(tv)`, `q'(tv)`, so `P(tv)` and the first
//!    coefficients carry the rounding of the local sizes, as the expansion about `tv` did.
//! 3. *`|P| ≤ η` over a window* (thin tubes: `P ≈ (r/R)²` where the line passes the tube, below
//!    `ε` in `f32` from `L/r ≈ 10³`): the roots of either rounded `P` there are noise. The
//!    answer then rests, unchanged, on `g`'s breakpoints from the vectors (a candidate at `g`'s
//!    maxima and each real interval's ends, passed with these) and the polish; the isolation
//!    only bounds its own work there ([`crate::math::bernstein::MAX_NODES`], and at most
//!    [`CAP`] candidates: the computed `P` has at most 6 roots per piece, so only subdivision
//!    rounding or depth-limit midpoints can exceed it).
//!
//! `isolation_tests.rs` compares the kernel's answers with the old cascades' on every
//! generator region (`tubecast_oracle::thin_case` families × `L/r = 1…10⁵`, each with
//! `2^k` scale variants), in `f32` and `f64`: a different hit or miss fails, and so does an
//! answer that differs and lies outside the band `E` of the exact tube; lanes must equal their
//! scalar calls bit for bit.
//!
//! *Lanes.* The tree depends on the data, so it runs lane by lane on the lane's scalars (the
//! coefficients are formed in lanes by the same IEEE operations as the scalar call, no fused
//! multiply-add); the candidate lists are padded with `1` (already a candidate), so each lane
//! sees its scalar call's list in the same order.

use crate::math::bernstein::{isolate, mul};
use crate::math::bezier::bernstein2;
use crate::math::roots::default_tol;
use crate::real::Real;
use crate::vec::V3;

/// Most candidates (`0`, `tv`, `1` and up to 13 roots of `P`).
pub(super) const CAP: usize = 16;

/// Bernstein coefficients of `P/16 = e²g − k²` on one piece from its control points `p`,
/// their differences `dp`, radii `r` and radius differences `dr` (see the module docs).
#[inline(always)]
fn p_piece<T: Real>(p: [V3<T>; 3], dp: [V3<T>; 2], r: [T; 3], dr: [T; 2], dhat: V3<T>) -> [T; 7] {
    let (two, third) = (T::cst(2.0), T::cst(1.0 / 3.0));
    let w = [p[0].cross(dhat), p[1].cross(dhat), p[2].cross(dhat)];
    let v = [dp[0].cross(dhat), dp[1].cross(dhat)];
    let e = [dp[0].dot(dhat), dp[1].dot(dhat)];
    let s = |i: usize, j: usize| r[i] * r[j] - w[i].dot(w[j]);
    let g = [s(0, 0), s(0, 1), (s(0, 2) + two * s(1, 1)) * third, s(1, 2), s(2, 2)];
    let k = |i: usize, j: usize| r[i] * dr[j] - w[i].dot(v[j]);
    let k = [k(0, 0), (two * k(1, 0) + k(0, 1)) * third, (k(2, 0) + two * k(1, 1)) * third, k(2, 1)];
    let e2 = [e[0] * e[0], e[0] * e[1], e[1] * e[1]];
    let a: [T; 7] = mul(&e2, &g);
    let b: [T; 7] = mul(&k, &k);
    [a[0] - b[0], a[1] - b[1], a[2] - b[2], a[3] - b[3], a[4] - b[4], a[5] - b[5], a[6] - b[6]]
}

/// `P/16` on `[0, tv]` and on `[tv, 1]` from the re-centred unit control points `c` and radii
/// `r` (de Casteljau at `tv`, differences from differences: module docs).
#[inline(always)]
pub(super) fn p_pieces<T: Real>(c: [V3<T>; 3], r: [T; 3], tv: T, dhat: V3<T>) -> ([T; 7], [T; 7]) {
    let s = T::one() - tv;
    let (d0, d1) = (c[1] - c[0], c[2] - c[1]);
    let (e0, e1) = (r[1] - r[0], r[2] - r[1]);
    let [w0, w1, w2] = bernstein2(tv);
    let m = c[0] * w0 + c[1] * w1 + c[2] * w2;
    let rm = r[0] * w0 + r[1] * w1 + r[2] * w2;
    let (dm, em) = (d0 * s + d1 * tv, e0 * s + e1 * tv);
    let left =
        p_piece([c[0], c[0] + d0 * tv, m], [d0 * tv, dm * tv], [r[0], r[0] + e0 * tv, rm], [e0 * tv, em * tv], dhat);
    let right = p_piece([m, m + dm * s, c[2]], [dm * s, d1 * s], [rm, rm + em * s, r[2]], [em * s, e1 * s], dhat);
    (left, right)
}

/// Lane `i` of a coefficient array.
#[inline(always)]
fn lane7<T: Real>(p: &[T; 7], i: usize) -> [T::Elem; 7] {
    [p[0].lane(i), p[1].lane(i), p[2].lane(i), p[3].lane(i), p[4].lane(i), p[5].lane(i), p[6].lane(i)]
}

/// Candidates `0, tv, 1` and `P`'s roots on both pieces ([`isolate`]); returns the list and
/// its length (the longest lane's; shorter lanes padded with `1`).
#[inline(always)]
pub(super) fn p_candidates<T: Real>(left: &[T; 7], right: &[T; 7], tv: T) -> ([T; CAP], usize) {
    assert!(T::LANES <= 8);
    let (zero, one) = (T::Elem::zero(), T::Elem::one());
    let tol = default_tol::<T::Elem>();
    let mut buf = [[one; CAP]; 8];
    let mut nmax = 0;
    for (i, b) in buf.iter_mut().enumerate().take(T::LANES) {
        let tvi = tv.lane(i);
        b[0] = zero;
        b[1] = tvi;
        let mut n = 3;
        if tvi > zero {
            isolate(&lane7(left, i), zero, tvi, tol, b, &mut n);
        }
        if tvi < one {
            isolate(&lane7(right, i), tvi, one, tol, b, &mut n);
        }
        nmax = nmax.max(n);
    }
    let mut out = [T::one(); CAP];
    for (k, o) in out.iter_mut().enumerate().take(nmax) {
        *o = T::from_fn(|i| buf[i][k]);
    }
    (out, nmax)
}
