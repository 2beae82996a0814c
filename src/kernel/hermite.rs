//! Cubic Hermite segment → two quadratic Bézier sub-segments (Russig §3.2).
//!
//! For a segment between nodes `i`, `j` with values `nᵢ`, `nⱼ` and derivatives `tᵢ`, `tⱼ`
//! (positions and radii alike), the sub-segments' control points are
//! `a₁ = nᵢ`, `a₂ = nᵢ + c₁tᵢ`, `b₂ = nⱼ − c₂tⱼ`, `b₃ = nⱼ`, `a₃ = b₁ = (a₂ + b₂)/2` with
//! `c₁ = c₂ = 1/3` (the Hermite → cubic Bézier basis change). The junction is C¹: both
//! sub-segments have derivative `b₂ − a₂` there (in their own parameters). The pair is a
//! **model**, not a reparametrisation of the cubic: the sweep differs from the cubic Hermite
//! sweep (`tests/splines/hermite.rs` measures by how much); it is exact for straight segments
//! whose node derivatives are the chord (`tᵢ = tⱼ = nⱼ − nᵢ`).
//!
//! **Faithful split** ([`HermiteSegment::split_adaptive`], unlike Russig's fixed pair): the cubic (its Bézier
//! form `P = [p₀, p₀ + m₀/3, p₁ − m₁/3, p₁]`, radius likewise) is halved by de Casteljau — an
//! exact restriction — until every piece's *mid-point quadratic*
//! `[L₀, (3(L₁ + L₂) − L₀ − L₃)/4, L₃]` is within the tolerance of it. That quadratic keeps the
//! piece's ends (the pieces join C⁰ on the cubic's own spheres) and differs from the cubic by
//! `O(h³)` (the third difference), where Russig's C¹ pair differs by the second difference,
//! `O(h²)`. The **certified distance** between the cubic's sweep and a piece's is
//! `max_k |ΔP_k| + max_k |Δr_k|` over the Bernstein coefficients of the difference (the
//! quadratic degree-elevated to cubic): a Bézier curve lies in the convex hull of its
//! coefficients, and a sphere moved by `δp` and grown by `δr` stays within `|δp| + |δr|` of the
//! other, so the two sweeps are within that Hausdorff distance (to rounding of the coefficients).

use crate::error::GeometryError;
use crate::kernel::spline::QuadTube;
use crate::real::{Real, Scalar};
use crate::vec::V3;

/// One node of a [`HermiteSegment`]: position, position derivative (tangent), radius and
/// radius derivative there, all with respect to the segment's parameter on `[0, 1]`.
///
/// ```
/// use tubecast::{HermiteEnd, V3};
/// let end = HermiteEnd { p: V3::new(1.0f64, 0.0, 0.0), tangent: V3::new(0.0, 2.0, 0.0), r: 0.1, dr: 0.0 };
/// assert_eq!(end.r, 0.1);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HermiteEnd<T> {
    /// Position.
    pub p: V3<T>,
    /// Position derivative `p'` (per unit of the segment's parameter, so its length scales
    /// with the segment's length: for Catmull–Rom, half the difference of the neighbours).
    pub tangent: V3<T>,
    /// Radius.
    pub r: T,
    /// Radius derivative `r'` (per unit of the segment's parameter).
    pub dr: T,
}

/// A cubic Hermite segment: positions, position derivatives (tangents), radii and radius
/// derivatives at both nodes; the parameter runs over `[0, 1]`. Build it from its two ends
/// with [`HermiteSegment::from_ends`] (named fields), or with [`HermiteSegment::new`]
/// (positional).
///
/// ```
/// use tubecast::{HermiteEnd, HermiteSegment, V3};
/// let (p0, p1) = (V3::new(0.0f64, 0.0, 0.0), V3::new(3.0, 0.0, 0.0));
/// let seg = HermiteSegment::from_ends(
///     HermiteEnd { p: p0, tangent: p1 - p0, r: 0.5, dr: 0.0 },
///     HermiteEnd { p: p1, tangent: p1 - p0, r: 0.5, dr: 0.0 },
/// );
/// let [a, b] = seg.split()?; // two quadratic sphere-swept segments, joined at t = ½
/// assert_eq!(a.b[2], b.b[0]);
/// assert_eq!(a.point(1.0), seg.point(0.5)); // straight, chord tangents: exact
/// # Ok::<(), tubecast::GeometryError>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HermiteSegment<T> {
    /// Start position.
    pub p0: V3<T>,
    /// Start tangent `p'(0)`.
    pub m0: V3<T>,
    /// End position.
    pub p1: V3<T>,
    /// End tangent `p'(1)`.
    pub m1: V3<T>,
    /// Start radius.
    pub r0: T,
    /// Start radius derivative `r'(0)`.
    pub dr0: T,
    /// End radius.
    pub r1: T,
    /// End radius derivative `r'(1)`.
    pub dr1: T,
}

/// The two sub-segments' control data: `(positions, radii)` of the first and of the second.
pub type QuadControls<T> = (([V3<T>; 3], [T; 3]), ([V3<T>; 3], [T; 3]));

impl<T: Real> HermiteSegment<T> {
    /// Hermite basis weights `[h00, h10, h01, h11]` at `t`.
    #[inline(always)]
    fn basis(t: T) -> [T; 4] {
        let (two, three) = (T::cst(2.0), T::cst(3.0));
        let t2 = t * t;
        let t3 = t2 * t;
        [two * t3 - three * t2 + T::one(), t3 - two * t2 + t, three * t2 - two * t3, t3 - t2]
    }
    /// Cubic position `p(t)`.
    #[inline(always)]
    pub fn point(&self, t: T) -> V3<T> {
        let [a, b, c, d] = Self::basis(t);
        self.p0 * a + self.m0 * b + self.p1 * c + self.m1 * d
    }
    /// Cubic radius `r(t)`.
    #[inline(always)]
    pub fn radius(&self, t: T) -> T {
        let [a, b, c, d] = Self::basis(t);
        self.r0 * a + self.dr0 * b + self.r1 * c + self.dr1 * d
    }
    /// Russig's split control points (`c₁ = c₂ = 1/3`), unvalidated.
    #[inline(always)]
    pub fn quad_controls(&self) -> QuadControls<T> {
        let third = T::cst(1.0 / 3.0);
        let half = T::cst(0.5);
        let a2 = self.p0 + self.m0 * third;
        let b2 = self.p1 - self.m1 * third;
        let mid = (a2 + b2) * half;
        let ra2 = self.r0 + self.dr0 * third;
        let rb2 = self.r1 - self.dr1 * third;
        let rmid = (ra2 + rb2) * half;
        (([self.p0, a2, mid], [self.r0, ra2, rmid]), ([mid, b2, self.p1], [rmid, rb2, self.r1]))
    }
}

impl<T: Scalar> HermiteSegment<T> {
    /// A segment from its start and end node (no validation here; [`Self::split`] and
    /// [`Self::split_adaptive`] validate the pieces they build). Example at [`HermiteSegment`].
    pub fn from_ends(start: HermiteEnd<T>, end: HermiteEnd<T>) -> Self {
        Self {
            p0: start.p,
            m0: start.tangent,
            p1: end.p,
            m1: end.tangent,
            r0: start.r,
            dr0: start.dr,
            r1: end.r,
            dr1: end.dr,
        }
    }
    /// The same as [`Self::from_ends`] with the node data positional: start position,
    /// tangent, radius, radius derivative, then the end's.
    #[allow(clippy::too_many_arguments)]
    pub fn new(p0: V3<T>, m0: V3<T>, r0: T, dr0: T, p1: V3<T>, m1: V3<T>, r1: T, dr1: T) -> Self {
        Self { p0, m0, p1, m1, r0, dr0, r1, dr1 }
    }
    /// The start and the end node.
    ///
    /// ```
    /// use tubecast::{HermiteEnd, HermiteSegment, V3};
    /// let a = HermiteEnd { p: V3::new(0.0f64, 0.0, 0.0), tangent: V3::new(1.0, 1.0, 0.0), r: 0.5, dr: -0.1 };
    /// let b = HermiteEnd { p: V3::new(2.0, 0.0, 0.0), tangent: V3::new(1.0, -1.0, 0.0), r: 0.4, dr: 0.0 };
    /// assert_eq!(HermiteSegment::from_ends(a, b).ends(), [a, b]);
    /// ```
    pub fn ends(&self) -> [HermiteEnd<T>; 2] {
        [
            HermiteEnd { p: self.p0, tangent: self.m0, r: self.r0, dr: self.dr0 },
            HermiteEnd { p: self.p1, tangent: self.m1, r: self.r1, dr: self.dr1 },
        ]
    }
    /// The two validated quadratic sub-segments. Errors as [`QuadTube::new`] (non-finite
    /// data, a sub-segment radius negative somewhere, zero radius).
    pub fn split(&self) -> Result<[QuadTube<T>; 2], GeometryError> {
        let ((pa, ra), (pb, rb)) = self.quad_controls();
        Ok([QuadTube::new(pa, ra)?, QuadTube::new(pb, rb)?])
    }
}

/// A cubic in Bézier form on `[0, 1]`: four position and four radius coefficients.
type Cubic<T> = ([V3<T>; 4], [T; 4]);

/// The result of [`HermiteSegment::split_adaptive`].
#[derive(Clone, Debug, PartialEq)]
pub struct AdaptiveSplit<T> {
    /// The quadratic pieces, in order along the segment (consecutive pieces share an end).
    pub quads: Vec<QuadTube<T>>,
    /// The certified distance (see the module docs) between the cubic's sweep and the pieces',
    /// greatest over the pieces.
    pub distance: T,
    /// The greatest ratio of a piece's certified distance to its local radius: the least radius
    /// of the cubic over the piece (a certified lower bound: the least Bernstein coefficient of
    /// its halves), or, where that bound is not positive (a taper to 0), the piece's greatest
    /// radius coefficient.
    pub relative: T,
}

/// `(a + b)/2` for points and radii.
fn mid<T: Scalar>(a: (V3<T>, T), b: (V3<T>, T)) -> (V3<T>, T) {
    let h = T::cst(0.5);
    ((a.0 + b.0) * h, (a.1 + b.1) * h)
}

/// de Casteljau at ½: the two halves of a cubic.
fn halve<T: Scalar>(c: &Cubic<T>) -> (Cubic<T>, Cubic<T>) {
    let p = |i: usize| (c.0[i], c.1[i]);
    let (a, b, e) = (mid(p(0), p(1)), mid(p(1), p(2)), mid(p(2), p(3)));
    let (f, g) = (mid(a, b), mid(b, e));
    let m = mid(f, g);
    let l = ([c.0[0], a.0, f.0, m.0], [c.1[0], a.1, f.1, m.1]);
    let r = ([m.0, g.0, e.0, c.0[3]], [m.1, g.1, e.1, c.1[3]]);
    (l, r)
}

/// Certified distance between the sweeps of a quadratic and a cubic over the same parameter:
/// the greatest coefficient of their difference (the quadratic degree-elevated,
/// `[q₀, (q₀ + 2q₁)/3, (2q₁ + q₂)/3, q₂]`), positions plus radii (see the module docs).
fn quad_vs_cubic<T: Scalar>(q: &([V3<T>; 3], [T; 3]), c: &Cubic<T>) -> T {
    let ((qp, qr), (p, r)) = (q, c);
    let (two, third) = (T::cst(2.0), T::cst(1.0 / 3.0));
    let ep = [qp[0], (qp[0] + qp[1] * two) * third, (qp[1] * two + qp[2]) * third, qp[2]];
    let er = [qr[0], (qr[0] + two * qr[1]) * third, (two * qr[1] + qr[2]) * third, qr[2]];
    let (mut dp, mut dr) = (T::zero(), T::zero());
    for k in 0..4 {
        dp = dp.max((p[k] - ep[k]).length());
        dr = dr.max((r[k] - er[k]).abs());
    }
    dp + dr
}

/// The mid-point quadratic of a cubic piece (radius control raised to `−√(r₀r₂)` if needed so
/// that the radius stays `≥ 0`), and its certified distance to the cubic.
fn midpoint_quad<T: Scalar>(c: &Cubic<T>) -> (([V3<T>; 3], [T; 3]), T) {
    let (p, r) = c;
    let (three, quarter) = (T::cst(3.0), T::cst(0.25));
    let q1 = ((p[1] + p[2]) * three - p[0] - p[3]) * quarter;
    let r1 = ((r[1] + r[2]) * three - r[0] - r[3]) * quarter;
    // r₁ ≥ −√(r₀r₂) ⇔ min ≥ 0; shrunk by 8ε so the rounded minimum is not below 0.
    let floor = (r[0].max(T::zero()) * r[3].max(T::zero())).sqrt() * (T::one() - T::cst(8.0) * T::EPS);
    let q = ([p[0], q1, p[3]], [r[0], r1.max(-floor), r[3]]);
    let d = quad_vs_cubic(&q, c);
    (q, d)
}

impl<T: Scalar> HermiteSegment<T> {
    /// The cubic's Bézier coefficients.
    fn bezier(&self) -> Cubic<T> {
        let third = T::cst(1.0 / 3.0);
        (
            [self.p0, self.p0 + self.m0 * third, self.p1 - self.m1 * third, self.p1],
            [self.r0, self.r0 + self.dr0 * third, self.r1 - self.dr1 * third, self.r1],
        )
    }

    /// Certified distance (see the module docs) between the cubic's sweep and Russig's pair's
    /// ([`Self::split`]): each half of the pair against the cubic's half (de Casteljau), greatest
    /// of the two. On Catmull–Rom helices of 8/12/16 points per turn it is a few 10⁻² of the
    /// helix radius (`tests/splines/hermite.rs`), radii for thin tubes.
    pub fn pair_distance(&self) -> T {
        let ((pa, ra), (pb, rb)) = self.quad_controls();
        let (l, r) = halve(&self.bezier());
        quad_vs_cubic(&(pa, ra), &l).max(quad_vs_cubic(&(pb, rb), &r))
    }

    /// The faithful split (see the module docs): pieces halved until each piece's certified
    /// distance is at most `rel_tol` times its local radius ([`AdaptiveSplit::relative`]), or
    /// `max_depth` halvings (`2^max_depth` pieces at most). The default
    /// tolerance of the renderer is `1e-3`. Errors as [`QuadTube::new`].
    ///
    /// ```
    /// use tubecast::{HermiteEnd, HermiteSegment, V3};
    /// // A quarter circle of radius 1 (Hermite tangents π/2), tube radius 0.05.
    /// let h = std::f64::consts::FRAC_PI_2;
    /// let seg = HermiteSegment::from_ends(
    ///     HermiteEnd { p: V3::new(1.0, 0.0, 0.0), tangent: V3::new(0.0, h, 0.0), r: 0.05, dr: 0.0 },
    ///     HermiteEnd { p: V3::new(0.0, 1.0, 0.0), tangent: V3::new(-h, 0.0, 0.0), r: 0.05, dr: 0.0 },
    /// );
    /// let s = seg.split_adaptive(1e-3, 8)?;
    /// assert!(s.relative <= 1e-3 && s.distance <= 0.05e-3);
    /// assert_eq!(s.quads[0].b[0], seg.p0);
    /// # Ok::<(), tubecast::GeometryError>(())
    /// ```
    pub fn split_adaptive(&self, rel_tol: T, max_depth: u32) -> Result<AdaptiveSplit<T>, GeometryError> {
        let mut out = AdaptiveSplit { quads: Vec::new(), distance: T::zero(), relative: T::zero() };
        let mut stack = vec![(self.bezier(), 0u32)];
        while let Some((c, depth)) = stack.pop() {
            let ((b, r), d) = midpoint_quad(&c);
            let (lh, rh) = halve(&c);
            // Least radius over the piece: the least Bernstein coefficient of its halves.
            let rmin = lh.1.iter().chain(&rh.1).fold(T::infinity(), |a, &x| a.min(x));
            let rmax = c.1.iter().fold(T::zero(), |a, &x| a.max(x));
            // A radius reaching 0 (a taper to a point): relative to the piece's greatest radius.
            let local = if rmin > T::zero() { rmin } else { rmax };
            let rel = if local > T::zero() {
                d / local
            } else if d > T::zero() {
                T::infinity()
            } else {
                T::zero()
            };
            if rel <= rel_tol || depth >= max_depth {
                out.quads.push(QuadTube::new(b, r)?);
                out.distance = out.distance.max(d);
                out.relative = out.relative.max(rel);
            } else {
                stack.push((rh, depth + 1));
                stack.push((lh, depth + 1));
            }
        }
        Ok(out)
    }
}
