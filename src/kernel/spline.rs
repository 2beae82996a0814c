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
//!   real interval (`f'` at most three). `tests/splines/derivative_roots.rs` tests it: it holds on random
//!   segments, but **fails** on a real interval bounded by the segment ends (a radius
//!   shrinking 600-fold; f''' has two roots, the middle of f''s three roots is the minimum), where
//!   these solvers report a point inside the tube instead of the entry.
//! * [`Solver::Polynomial`]: the critical points of `f` **and** `e` are exactly the roots of
//!   `P = 4h'²g − g'² = (2h'√g − g')(2h'√g + g')` where `g > 0`; all roots of `P` in `[0, 1]`
//!   by the derivative cascade (`P` formed in powers of `t − t_v`, `t_v` the vertex of the
//!   centre line, where a slow curve makes `P` tiny), then `f` and `e` at every root with
//!   `g ≥ 0` (to rounding; `g(1)` formed from the end itself, exactly 0 for a zero-radius end
//!   on the line) and at `t = 0, 1`.
//!   Needs no real intervals and no claim.
//!
//!   Where it can, it skips `P`'s cascade, the costliest part of a hit: on each real piece of `g`
//!   (bounded by points proven off the tube just past `g`'s roots, which then need no solve:
//!   `Direct::g_piece_bounds`), the
//!   Bernstein coefficients of `P` with a bound on their rounding count its roots from above
//!   (Descartes' rule, `crate::math::descartes`); when that count equals the number of the
//!   entry's and exit's sign functions that change sign between the piece's ends (halving the
//!   piece up to six times), each has at most one root there, the entry is that root if `F₁`
//!   rises through it and an end otherwise, likewise the exit (`RaySpace::certified`). Rays it
//!   cannot certify — chiefly thin tubes in `f32`, whose `P` is within its rounding — take the
//!   cascade. Where the count's rounding swamps `P` (a thin tube in `f32`, or next to a root of
//!   `g` with a small `g'`), Taylor bounds from the vectors that prove `P` monotone or of one
//!   sign on a node certify it instead (`Direct::p_monotone`). On the spline bench's f32 rays
//!   it certifies all 64 hits (60 with the count alone).
//!
//! # Conditioning
//! In units of the bounding radius `R` (≈ `L/2 + r`) the coefficients of `g` are of size 1
//! while the values that decide a thin tube's hits are `≈ (r/R)²`; `g` formed from its
//! expanded coefficients carries an absolute rounding of `~ε`, i.e. a relative `ε·(R/r)²`:
//! phantom hits 2 radii from an `f32` tube at `L/r = 10³`, entry errors `∝ ε(L/r)²`. So every
//! **decision and value** is formed from the ray-space *vectors* instead (`direct.rs`):
//! `w(t) = q(t) × d̂ = wa t² + wb t + wc` (the centre's offset from the line) and
//! `g = (r − |w|)(r + |w|)`, its derivatives `g' = 2(rr' − w·w')`,
//! `g'' = 2(r'² + rr'' − |w'|² − w·w'')`, `g''' = 6(r'r'' − w'·w'')`; the coefficients of `g` only
//! seed `P`'s roots (candidates, never trusted: see below).
//!
//! *Bound.* With the origin re-centred near `p(½)`, `|cᵢ| ≤ 2`, so `|qa|, |qb| ≤ 8`, `|qc| ≤ 2`
//! and `Σ|w_k| ≤ 18`, `Σ|r_k| ≤ 9`. Forming the control points' offsets, the re-centring and the
//! unit scaling perturbs each coefficient by `≲ 40ε` (a perturbation of the *input*), and Horner
//! on `[0, 1]` adds `≤ 4ε·Σ|coefficients|` to `w(t)`, `r(t)` (plus `2ε|w|` for the norm): the
//! computed gap `r − |w|` is within `τ = 16ε·(Σ|r_k| + Σ|w_k|) ≤ 432ε` of the gap of the
//! perturbed data. A candidate counts as real iff its computed gap is `≥ −τ`, and
//! `(r − |w| + δ₁)(r + |w| + δ₂) = (r + δ)² − |w|²` with `|δ| ≤ |δ₁| + |δ₂|/2` (for `|w| ≤ r`),
//! so a computed `√g` is the exact half chord of a sphere whose radius is off by `≤ 2τ`; `h`
//! errs by `≤ 16ε·Σ|h_k| + 120ε ≤ 408ε` along the line. Converting to the ray parameter
//! (`t = t_c + s·R/|d|`) and re-centring the origin (`l = (o − m) + d t_c`) add `≤ 4ε(R + |o − m|)`.
//! Hence the kernel's interval is, up to a shift `≤ E` along the ray, exactly the interval of a
//! tube whose radius is within `E` of the given one,
//!
//! `E = 1024·ε·R + 8·ε·|o − m|` ([`crate::spline_error_band`], [`QuadTube::error_band`]),
//!
//! **provided** the entry's critical point is among the polished candidates (the one
//! assumption, tested, not proven: below; on the certified path, that the root count of `P`
//! as formed holds for `F₁`, `F̄₁` from the vectors — the same assumption in another form). `E/r ≈ 1024ε·L/(2r)` is linear in `L/r`, like the
//! stable link's; the old formulation's was quadratic. What `E` excludes is exact: a phantom
//! hit needs the tube inflated by `E` to be hit, a false miss the tube deflated by `E` to be
//! missed. `tests/splines/conditioning.rs` asserts both, and the interval between the inflated
//! and deflated tubes' intervals, for every accurate solver in `f32` and `f64` across
//! `L/r = 1 … 10⁵` in eleven families (unit, bulge, cusp, taper to `r ≈ 0`, grazing, far origin,
//! inside, inside beside an end crossed at right angles, pinched `r(½) = 0`, scales `2^±50`,
//! direction ratios `2⁴⁰`) against an independent
//! thin-tube oracle (`tubecast_oracle::quad_crossing_offset`).
//!
//! *Candidates.* Whatever rounding does to `P`'s roots, the roots of `g'` and of `g` (the
//! cascade `g'''` → `g''` → `g'` → `g`, each level from the vectors) are candidates too: `g`'s
//! maxima and its real intervals' ends, so every real interval holds a candidate at its deepest
//! point and no hit deeper than `E` is lost. (The ends alone were not enough: √g = 0 there, and
//! a line that crosses a thin tube at right angles has `h' ≡ 0`, so `P = −g'²` has only double
//! roots, which the cascade can miss — differential finding `regression-spline-f32-exit-at-end`,
//! `tests/splines/straight_link.rs`.) The best candidate is then polished by a bracketed
//! solve of `F₁ = 2σh'√g − g'` towards the side its sign points to, up to the nearest candidate
//! there whose `F₁` has the other sign (at a real interval's ends `F₁ = −g'` has the sign that
//! closes the bracket).
//!
//! *Cost (exact early exits).* A line is rejected before any polynomial is formed when it is
//! farther than the largest control radius from the control triangle (`ray_space::hull_misses`,
//! exact: its proof is there), and the Polynomial solver forms `P` only when one of `g`'s
//! breakpoints is real (they hold `g`'s maxima, so otherwise the line misses the tube deflated
//! by `E`: a miss is right). Before all this a chord-capsule filter (`capsule.rs`, exact, proof
//! there) rejects lines farther than `max rᵢ + ½|b₁ − (b₀+b₂)/2|` (plus a margin over `E`)
//! from the chord `[b₀, b₂]` with a dozen dot products. Lanes take an exit only when every lane does, and mask the same
//! lanes otherwise, so a lane still equals the scalar call; where at most three quarters of the
//! lanes pass the capsule filter, they run the scalar kernel one by one.
//!
//! The kernel returns the hull `[first entry, last exit]` ([`QuadTube::intersect_with`]). A strongly
//! bent segment can be crossed more than once; [`QuadTube::intersect_pieces`] returns one
//! interval per real interval of `g` (each exact: the part of the sweep over a connected
//! `t`-interval meets the line in one interval), which is what CSG needs.

mod capsule;
mod direct;
mod ray_space;
mod sdf;
#[cfg(test)]
mod tests;

pub use sdf::quadratic_tube;

use self::capsule::capsule_misses;
use self::ray_space::RaySpace;
use super::roots::Solver;
use crate::error::GeometryError;
use crate::kernel::link::RoundCone;
use crate::math::bezier::{bernstein2, bezier2, bezier2_max, bezier2_min};
use crate::math::roots::Bracket;
use crate::ray::{Interval, Ray};
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
/// assert!(iv.hit && iv.entry.t < 5.0 && iv.exit.t > 5.0);
/// assert_eq!(tube.intersect_with(&ray, Solver::Itp).hit, true);
/// assert!(tube.sdf(ray.at(iv.entry.t)).abs() < 1e-12); // on the surface
/// # Ok::<(), tubecast::GeometryError>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QuadTube<T> {
    /// Control points.
    pub b: [V3<T>; 3],
    /// Control radii (`r₁` may be negative as long as `r(t) ≥ 0` on `[0, 1]`).
    pub r: [T; 3],
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

impl<T: Real> QuadTube<T> {
    /// Lanes from validated scalar segments (one per lane).
    pub fn from_lanes(f: impl Fn(usize) -> QuadTube<T::Elem>) -> Self {
        Self {
            b: [V3::from_fn(|i| f(i).b[0]), V3::from_fn(|i| f(i).b[1]), V3::from_fn(|i| f(i).b[2])],
            r: [T::from_fn(|i| f(i).r[0]), T::from_fn(|i| f(i).r[1]), T::from_fn(|i| f(i).r[2])],
        }
    }
    /// Every lane the same segment.
    pub fn broadcast(s: QuadTube<T::Elem>) -> Self {
        Self {
            b: [V3::broadcast(s.b[0]), V3::broadcast(s.b[1]), V3::broadcast(s.b[2])],
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
        let [w0, w1, w2] = bernstein2(t);
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
        // The chord-capsule filter (exact: `capsule.rs`); masking its lanes keeps every lane
        // equal to the scalar call.
        let far = capsule_misses(self, ray);
        if far.all() {
            return Interval::miss();
        }
        // At most three quarters of the lanes left: the scalar kernel lane by lane (the same
        // answer bit for bit, by construction). The lane kernel pays each stage's worst lane in
        // every lane, so a pack with one hit costs about what eight hits cost: on one ray
        // against a leaf's eight segments (`spline_leaf_hits` in `benches/spline.rs`) the lane
        // kernel cost about twice what eight scalar calls cost without this, markedly less
        // with it (thresholds ½ and ¾ measured alike).
        if T::LANES > 1 {
            let live = (0..T::LANES).filter(|&i| !far.lane(i)).count();
            if 4 * live <= 3 * T::LANES {
                return Interval::from_lanes(|i| {
                    if far.lane(i) {
                        Interval::miss()
                    } else {
                        // The lane passed the filter: the scalar call's remaining stages (its
                        // `masked(true)` as the scalar `line_interval_with` ends).
                        self.lane(i).line_interval_unfiltered(&ray.lane(i), solver).masked(true)
                    }
                });
            }
        }
        self.line_interval_unfiltered(ray, solver).masked(!far)
    }

    /// [`Self::line_interval_with`] without the capsule filter.
    #[inline(always)]
    fn line_interval_unfiltered(&self, ray: &Ray<T>, solver: Solver) -> Interval<T> {
        let Some(rs) = RaySpace::new(self, ray) else {
            return Interval::miss();
        };
        match solver {
            Solver::Polynomial => self.polynomial_line(&rs, ray, Path::Auto).0,
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

    /// [`Solver::Polynomial`]'s line interval, and the lanes answered by the certified count
    /// (`RaySpace::certified`); `Path::Cascade` forces `P`'s cascade for every lane (tests).
    #[inline(always)]
    fn polynomial_line(&self, rs: &RaySpace<T>, ray: &Ray<T>, path: Path) -> (Interval<T>, T::Mask) {
        // g's breakpoints hold its maxima: a candidate in every real interval, whatever
        // the rounding of P's coefficients does to P's roots. None of them real (gap
        // ≥ −τ): the line misses the tube deflated by the band (see "Conditioning"), a
        // miss is a right answer and P's cascade is skipped.
        let extrema = rs.dg.g_extrema(Bracket::Newton);
        let mut real = T::Mask::splat(false);
        for &t in &extrema {
            real = real | rs.dg.gap_g(t).0.ge(-rs.dg.tau);
        }
        let none = T::Mask::splat(false);
        if (real & rs.near).none() {
            return (Interval::miss(), none);
        }
        // The certified count on g's real pieces first; P's cascade only for lanes it
        // cannot certify (`RaySpace::certified`). A lane with a candidate real within
        // the gap's rounding but no piece with g > 0 (a graze within τ) is not certified.
        let (fast, cert) = if path == Path::Auto {
            // The real pieces bounded from outside (no solves for g's roots,
            // `Direct::g_piece_bounds`): the count and its crossings are the same.
            let (xc, pieces, cert) = rs.certified(&rs.dg.g_piece_bounds(extrema));
            let cert = cert & ((pieces & real) | (!pieces & !real));
            let fast = rs.interval(ray, xc, pieces & real, false);
            if cert.all() {
                return (fast, cert);
            }
            (fast, cert)
        } else {
            (Interval::miss(), none)
        };
        let roots = rs.dg.g_roots_started(extrema);
        // The ends 0 and 1 once (they open and close every breakpoint list).
        let mut z = [T::zero(); 9];
        z[..4].copy_from_slice(&roots[1..5]);
        z[4..].copy_from_slice(&extrema);
        let (bp, n) = rs.p_breakpoints();
        let (x, any) = rs.polished_candidates(&bp[1..n - 1], &z, T::zero(), T::one(), false);
        // `& real`: a lane decides as the scalar call does (which returned above).
        (Interval::select(cert, fast, rs.interval(ray, x, any & real, false)), cert)
    }

    /// One interval per real interval of `g` (at most three non-empty, in slots `0..5`; the
    /// others miss), each exact. Feed them to [`crate::csg::union`] for transparency.
    /// With [`Solver::Polynomial`] the real intervals come from `g`'s cascade with Newton and
    /// the candidates from `P`'s roots.
    #[inline(always)]
    pub fn intersect_pieces(&self, ray: &Ray<T>, solver: Solver) -> [Interval<T>; 5] {
        let Some(rs) = RaySpace::new(self, ray) else {
            return [Interval::miss(); 5];
        };
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
        let gb = rs.dg.g_breakpoints(method);
        let z = gb.roots;
        let mut real = [T::Mask::splat(false); 5];
        for k in 0..5 {
            let mid = (z[k] + z[k + 1]) * half;
            real[k] = rs.dg.g(mid).gt(T::zero()) & z[k + 1].gt(z[k]);
        }
        // A boundary is a cut (a root of g) where realness changes or g ≤ 0 there.
        let mut cut = [T::Mask::splat(true); 6];
        for j in 1..5 {
            let rj = real[j - 1] & real[j];
            cut[j] = !rj | rs.dg.g(z[j]).le(T::zero());
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
            let x = match ppoly {
                // g's maxima as well as P's roots: in f32 a thin tube's P can lose them all
                // (see `Direct::g_breakpoints`); outside [lo, hi] they clamp to its ends.
                Some((bp, n)) => rs.polished_candidates(&bp[1..n - 1], &gb.extrema, lo, hi, true).0,
                None => rs.russig(lo, hi, method),
            };
            out[k] = rs.interval(ray, x, first, clip);
        }
        out
    }
}

/// Which way [`QuadTube::polynomial_line`] goes: the certified count where it certifies
/// (`Auto`, what [`Solver::Polynomial`] does) or `P`'s cascade everywhere (`Cascade`, tests).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Path {
    Auto,
    #[cfg_attr(not(test), allow(dead_code))]
    Cascade,
}
