//! Bounds: one axis-aligned [`Aabb`] for every primitive ([`crate::Primitive::aabb`]), the
//! oriented [`Obb`] where a tight one is defined ([`QuadTube::obb`], [`RoundCone::obb`]), and
//! the spline kernel's error band ([`spline_error_band`], [`QuadTube::error_band`]).

use crate::kernel::link::RoundCone;
use crate::kernel::spline::QuadTube;
use crate::real::{Real, Scalar};
use crate::vec::V3;

pub use crate::kernel::obb::Obb;

/// An axis-aligned box `{x : min ≤ x ≤ max}` (component-wise). For lane types each lane is
/// one box.
///
/// Primitives' boxes ([`crate::Primitive::aabb`]) are formed from their defining data with a
/// few roundings to nearest, so they can be short of the exact box by a few ulps of the
/// coordinates: pad them for conservative culling (see `tests/kernels/primitive.rs` for the bound).
///
/// ```
/// use tubecast::{Aabb, Primitive, RoundCone, Sphere, V3};
/// let link = RoundCone::new(V3::new(0.0f64, 0.0, 0.0), 1.0, V3::new(4.0, 0.0, 0.0), 0.5)?;
/// let ball = Sphere::new(V3::new(0.0, 3.0, 0.0), 0.5)?;
/// let all = Aabb::empty().union(link.aabb()).union(ball.aabb());
/// assert_eq!(all, Aabb::new(V3::new(-1.0, -1.0, -1.0), V3::new(4.5, 3.5, 1.0)));
/// assert!(all.contains(V3::new(2.0, 3.0, 0.0)));
/// assert_eq!(all.center(), V3::new(1.75, 1.25, 0.0));
/// assert_eq!(all.extent(), V3::new(5.5, 4.5, 2.0));
/// # Ok::<(), tubecast::GeometryError>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb<T> {
    /// Least corner.
    pub min: V3<T>,
    /// Greatest corner.
    pub max: V3<T>,
}

impl<T: Real> Aabb<T> {
    /// The box with corners `min` and `max`.
    #[inline(always)]
    pub fn new(min: V3<T>, max: V3<T>) -> Self {
        Self { min, max }
    }
    /// The empty box (`min = +∞`, `max = −∞`): the identity of [`Self::union`].
    #[inline(always)]
    pub fn empty() -> Self {
        let inf = T::infinity();
        Self { min: V3::new(inf, inf, inf), max: V3::new(-inf, -inf, -inf) }
    }
    /// The smallest box containing both.
    #[inline(always)]
    pub fn union(self, o: Self) -> Self {
        let (a, b) = (self.min, o.min);
        let (c, d) = (self.max, o.max);
        Self {
            min: V3::new(a.x.min(b.x), a.y.min(b.y), a.z.min(b.z)),
            max: V3::new(c.x.max(d.x), c.y.max(d.y), c.z.max(d.z)),
        }
    }
    /// Whether `p` lies in the box (boundary included), lane-wise.
    #[inline(always)]
    pub fn contains(&self, p: V3<T>) -> T::Mask {
        let (lo, hi) = (self.min, self.max);
        p.x.ge(lo.x) & p.y.ge(lo.y) & p.z.ge(lo.z) & p.x.le(hi.x) & p.y.le(hi.y) & p.z.le(hi.z)
    }
    /// The centre `(min + max)/2`.
    #[inline(always)]
    pub fn center(&self) -> V3<T> {
        (self.min + self.max) * T::cst(0.5)
    }
    /// The edge lengths `max − min`.
    #[inline(always)]
    pub fn extent(&self) -> V3<T> {
        self.max - self.min
    }
    /// Lane `i` as a scalar box.
    #[inline]
    pub fn lane(&self, i: usize) -> Aabb<T::Elem> {
        Aabb { min: self.min.lane(i), max: self.max.lane(i) }
    }
}

impl<T: Real> QuadTube<T> {
    /// Russig's oriented box of the segment ([`Obb::fit`]).
    #[inline(always)]
    pub fn obb(&self) -> Obb<T> {
        Obb::fit(self)
    }
}

impl<T: Real> RoundCone<T> {
    /// The oriented box of the link: [`Obb::fit`] of the straight segment with the same sweep
    /// (`x̂` along the axis), which is tight (every face touches one of the two spheres).
    #[inline(always)]
    pub fn obb(&self) -> Obb<T> {
        let h = T::cst(0.5);
        Obb::fit(&QuadTube {
            b: [self.a, (self.a + self.b) * h, self.b],
            r: [self.ra, (self.ra + self.rb) * h, self.rb],
        })
    }
}

/// The spline kernel's backward-error band, in length units:
///
/// `E = 1024·ε·R + 8·ε·|o − p(½)|`
///
/// for a segment of bounding radius `R = max|bᵢ − p(½)| + max|rᵢ|` (its
/// [`QuadTube::bounding_radius`]), a ray from `o` at `origin_distance = |o − p(½)|`, and the
/// unit roundoff `eps` of the precision the kernel ran in (`f32::EPSILON` or `f64::EPSILON`,
/// as `f64`). [`QuadTube::error_band`] forms both sizes from a segment and a ray origin.
///
/// *What it bounds.* The interval of [`QuadTube::intersect_with`] (every solver but
/// `Bisection` with fewer than 40 steps) is, up to a shift of at most `E` along the ray,
/// exactly the interval of a tube whose radius is within `E` of the given one. So a hit where
/// the tube inflated by `E` is missed, or a miss where the tube deflated by `E` is hit, is a
/// defect, and so is an entry or exit outside the inflated and deflated tubes' (± `E` along
/// the ray, `E/|d|` in `t`).
///
/// *Why.* The kernel works in units of `R` with the origin moved near `p(½)`, where its
/// ray-space coefficients sum to at most 18 (positions) and 9 (radii). Forming them perturbs
/// the input by `≲ 40ε`; evaluating the gap `r − |w|` from them adds `≤ 432ε`, so a computed
/// half chord is exact for a radius off by `≤ 864ε·R`; the position along the line errs by
/// `≤ 408ε·R`, and converting back to `t` from the moved origin adds `≤ 4ε(R + |o − p(½)|)`.
/// Both the radius change and the shift are within `E`. One assumption is tested, not proven:
/// the entry's critical point is among the polished candidates. The full derivation is the
/// "Conditioning" section of `src/kernel/spline.rs`; `docs/design/spline-kernel.md` has the
/// reasoning and `tests/splines/conditioning.rs` the test over `L/r = 1 … 10⁵`.
///
/// `E/r` grows linearly in `L/r`: in `f32` it reaches the radius itself near `L/r ≈ 10⁴`.
///
/// ```
/// use tubecast::spline_error_band;
/// let e = spline_error_band(f32::EPSILON as f64, 2.0, 10.0);
/// assert_eq!(e, (1024.0 * 2.0 + 8.0 * 10.0) * f32::EPSILON as f64);
/// assert!(spline_error_band(f64::EPSILON, 2.0, 10.0) < 1e-12);
/// ```
#[inline]
pub fn spline_error_band(eps: f64, bounding_radius: f64, origin_distance: f64) -> f64 {
    1024.0 * eps * bounding_radius + 8.0 * eps * origin_distance
}

impl<T: Scalar> QuadTube<T> {
    /// The bounding radius `R = max|bᵢ − p(½)| + max|rᵢ|` (in `f64`): the sphere about
    /// `p(½)` of that radius holds the sweep, and the kernel works in units of it.
    ///
    /// ```
    /// use tubecast::{QuadTube, V3};
    /// let tube = QuadTube::new([V3::new(-2.0, 0.0, 0.0), V3::new(0.0, 2.0, 0.0), V3::new(2.0, 0.0, 0.0)], [0.5; 3])?;
    /// // p(½) = (0, 1, 0): the ends are √5 from it, the middle control point 1.
    /// assert_eq!(tube.bounding_radius(), 5f64.sqrt() + 0.5);
    /// # Ok::<(), tubecast::GeometryError>(())
    /// ```
    pub fn bounding_radius(&self) -> f64 {
        let b = self.b.map(|p| p.cast::<f64>());
        let m = (b[0] + b[1] * 2.0 + b[2]) * 0.25;
        let far = b.iter().map(|&p| (p - m).length()).fold(0.0, f64::max);
        far + self.r.iter().fold(0.0, |a, &x| a.max(x.to_f64().abs()))
    }

    /// [`spline_error_band`] of this segment for a ray from `o`, at unit roundoff `eps` (of
    /// the precision the kernel runs in, which may differ from `T`: a `QuadTube<f64>` can
    /// describe the segment an `f32` kernel saw).
    ///
    /// ```
    /// use tubecast::{QuadTube, Ray, Solver, V3};
    /// let tube = QuadTube::new([V3::new(-2.0f64, 0.0, 0.0), V3::new(0.0, 2.0, 0.0), V3::new(2.0, 0.0, 0.0)], [0.5; 3])?;
    /// let ray = Ray::new(V3::new(0.0, 1.0, -10.0), V3::new(0.0, 0.0, 1.0));
    /// let e = tube.error_band(ray.o, f64::EPSILON);
    /// // Through p(½) = (0, 1, 0) head on: the exact entry is at t = 9.5.
    /// let iv = tube.intersect_with(&ray, Solver::Polynomial);
    /// assert!(iv.hit && (iv.entry.t - 9.5).abs() <= 2.0 * e);
    /// # Ok::<(), tubecast::GeometryError>(())
    /// ```
    pub fn error_band(&self, o: V3<T>, eps: f64) -> f64 {
        let b = self.b.map(|p| p.cast::<f64>());
        let m = (b[0] + b[1] * 2.0 + b[2]) * 0.25;
        spline_error_band(eps, self.bounding_radius(), (o.cast::<f64>() - m).length())
    }
}
