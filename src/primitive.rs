//! The [`Primitive`] trait — one call across primitives, after parry3d's `RayCast` +
//! `compute_aabb` — and the [`Sphere`] primitive.

use crate::baseline::HanLink;
use crate::bounds::{Aabb, Obb};
use crate::error::GeometryError;
use crate::kernel::link::RoundCone;
use crate::kernel::roots::Solver;
use crate::kernel::sdf;
use crate::kernel::sphere::sphere_line;
use crate::kernel::spline::{quadratic_tube, QuadTube};
use crate::ray::{Interval, Ray};
use crate::real::{Real, Scalar};
use crate::vec::V3;

/// A solid that rays can be cast against, generic over the number type `T` (scalars or
/// lanes: a lane type evaluates one primitive–ray pair per lane).
///
/// One required ray method, [`Self::line_interval`]; [`Self::intersect`] clips it to the ray
/// (a default method: implementors never write that step). Every primitive also has its
/// axis-aligned box and its exact signed distance (negative inside, zero on the surface).
/// The trait is object safe.
///
/// A renderer's inner loop, over one kind of primitive or over a mix:
///
/// ```
/// use tubecast::{Primitive, Ray, RoundCone, Sphere, V3};
///
/// /// Index and `t` of the closest surface crossing in the ray's range.
/// fn closest(prims: &[impl Primitive<f32>], ray: &Ray<f32>) -> Option<(usize, f32)> {
///     let hits = prims.iter().enumerate();
///     let first = hits.filter_map(|(k, p)| Some((k, p.intersect(ray).first_hit(ray.t_min, ray.t_max)?.t)));
///     first.min_by(|a, b| a.1.total_cmp(&b.1))
/// }
///
/// let v = |x: f32, y: f32, z: f32| V3::new(x, y, z);
/// let links = [
///     RoundCone::new(v(0.0, 0.0, 5.0), 1.0, v(4.0, 0.0, 5.0), 0.5)?,
///     RoundCone::new(v(0.0, 0.0, 2.0), 0.5, v(0.0, 3.0, 2.0), 0.5)?,
/// ];
/// let ray = Ray::new(v(0.0, 0.0, 0.0), v(0.0, 0.0, 1.0));
/// let (k, t) = closest(&links, &ray).expect("hits");
/// assert!(k == 1 && (t - 1.5).abs() < 1e-6);
///
/// // Mixed kinds through trait objects.
/// let ball = Sphere::new(v(0.0, 0.0, 1.0), 0.25)?;
/// let scene: [&dyn Primitive<f32>; 3] = [&links[0], &links[1], &ball];
/// let t = scene.iter().filter_map(|p| p.intersect(&ray).first_hit(0.0, f32::INFINITY)).map(|h| h.t);
/// assert_eq!(t.reduce(f32::min), Some(0.75));
/// # Ok::<(), tubecast::GeometryError>(())
/// ```
///
/// Lanes: eight rays against one link in one call, equal bit for bit to eight scalar calls.
///
/// ```
/// # #[cfg(feature = "wide")] {
/// use tubecast::{Primitive, Ray, RoundCone, WideF32x8, V3};
/// let link = RoundCone::new(V3::new(0.0, 0.0, 0.0), 1.0, V3::new(4.0, 0.0, 0.0), 0.5).unwrap();
/// let ray = |i: usize| Ray::new(V3::new(0.5 * i as f32, -10.0, 0.3), V3::new(0.0, 1.0, 0.0));
/// let iv = RoundCone::<WideF32x8>::broadcast(link).intersect(&Ray::from_fn(ray));
/// for i in 0..8 {
///     assert_eq!(iv.lane(i), link.intersect(&ray(i)));
/// }
/// # }
/// ```
pub trait Primitive<T: Real> {
    /// The interval of the ray's whole **line** with the solid (`hit`: non-empty), not
    /// clipped to `[t_min, t_max]`: what CSG unions are formed from.
    fn line_interval(&self, ray: &Ray<T>) -> Interval<T>;

    /// The line interval with `hit` set where it overlaps the ray's range
    /// ([`Interval::clip`]); `t_in < t_min` says the ray starts inside.
    #[inline(always)]
    fn intersect(&self, ray: &Ray<T>) -> Interval<T> {
        self.line_interval(ray).clip(ray)
    }

    /// The axis-aligned bounding box (to a few roundings of the coordinates: see [`Aabb`]).
    fn aabb(&self) -> Aabb<T>;

    /// Exact signed distance from `p` to the surface (negative inside).
    fn sdf(&self, p: V3<T>) -> T;
}

/// A ball `|x − c| ≤ r` (curve parameter `u = 0` on its whole surface).
///
/// The origin is moved to the point of the line closest to the centre before the quadratic is
/// formed, so far origins lose only what representing the origin itself loses.
///
/// ```
/// use tubecast::{Primitive, Ray, Sphere, V3};
/// let ball = Sphere::new(V3::new(0.0, 0.0, 10.0), 2.0)?;
/// let iv = ball.intersect(&Ray::new(V3::new(0.0, 0.0, 0.0), V3::new(0.0, 0.0, 1.0)));
/// assert_eq!((iv.entry.t, iv.exit.t), (8.0, 12.0));
/// assert_eq!(iv.entry.n, V3::new(0.0, 0.0, -1.0));
/// assert_eq!(ball.sdf(V3::new(0.0, 3.0, 10.0)), 1.0);
/// # Ok::<(), tubecast::GeometryError>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere<T> {
    /// Centre.
    pub c: V3<T>,
    /// Radius.
    pub r: T,
}

impl<T: Scalar> Sphere<T> {
    /// A validated ball. Errors: non-finite centre or radius, a negative or zero radius, a
    /// radius whose square (nearly) underflows, an extent whose square overflows.
    pub fn new(c: V3<T>, r: T) -> Result<Self, GeometryError> {
        if !c.is_finite() || !r.is_finite() {
            return Err(GeometryError::NonFinite { what: "sphere centre or radius" });
        }
        if r < T::zero() {
            return Err(GeometryError::NegativeRadius);
        }
        if r == T::zero() {
            return Err(GeometryError::ZeroRadius);
        }
        if r * r < T::MIN_POSITIVE / T::EPS {
            return Err(GeometryError::TooSmall { what: "sphere radius (its square underflows)" });
        }
        let e = c.max_abs().max(r);
        if !(e * e * T::cst(4.0)).is_finite() {
            return Err(GeometryError::NonFinite { what: "sphere extent (overflows when squared)" });
        }
        Ok(Self { c, r })
    }
}

impl<T: Real> Sphere<T> {
    /// Lanes from validated scalar balls (one per lane).
    pub fn from_lanes(f: impl Fn(usize) -> Sphere<T::Elem>) -> Self {
        Self { c: V3::from_fn(|i| f(i).c), r: T::from_fn(|i| f(i).r) }
    }
    /// Every lane the same ball.
    pub fn splat(s: Sphere<T::Elem>) -> Self {
        Self { c: V3::broadcast(s.c), r: T::splat(s.r) }
    }
}

impl<T: Real> Primitive<T> for Sphere<T> {
    #[inline(always)]
    fn line_interval(&self, ray: &Ray<T>) -> Interval<T> {
        sphere_line(ray, self.c, self.r, T::zero())
    }
    #[inline(always)]
    fn aabb(&self) -> Aabb<T> {
        let r = V3::new(self.r, self.r, self.r);
        Aabb::new(self.c - r, self.c + r)
    }
    #[inline(always)]
    fn sdf(&self, p: V3<T>) -> T {
        sdf::sphere(p, self.c, self.r)
    }
}

/// The stable kernel (no apex; the derivation is in `src/kernel/link.rs`).
impl<T: Real> Primitive<T> for RoundCone<T> {
    #[inline(always)]
    fn line_interval(&self, ray: &Ray<T>) -> Interval<T> {
        self.stable_line(ray, true)
    }
    #[inline(always)]
    fn aabb(&self) -> Aabb<T> {
        let lo = |p: T, q: T| (p - self.ra).min(q - self.rb);
        let hi = |p: T, q: T| (p + self.ra).max(q + self.rb);
        Aabb::new(
            V3::new(lo(self.a.x, self.b.x), lo(self.a.y, self.b.y), lo(self.a.z, self.b.z)),
            V3::new(hi(self.a.x, self.b.x), hi(self.a.y, self.b.y), hi(self.a.z, self.b.z)),
        )
    }
    #[inline(always)]
    fn sdf(&self, p: V3<T>) -> T {
        sdf::round_cone(p, self)
    }
}

/// The faithful Han et al. kernel; box and distance are those of the same round cone.
impl<T: Real> Primitive<T> for HanLink<T> {
    #[inline(always)]
    fn line_interval(&self, ray: &Ray<T>) -> Interval<T> {
        self.line(ray)
    }
    #[inline(always)]
    fn aabb(&self) -> Aabb<T> {
        self.link.aabb()
    }
    #[inline(always)]
    fn sdf(&self, p: V3<T>) -> T {
        sdf::round_cone(p, &self.link)
    }
}

/// The hull interval with [`Solver::Polynomial`] ([`QuadTube::intersect_with`] for others).
impl<T: Real> Primitive<T> for QuadTube<T> {
    #[inline(always)]
    fn line_interval(&self, ray: &Ray<T>) -> Interval<T> {
        self.line_interval_with(ray, Solver::Polynomial)
    }
    /// The tightest axis-aligned box, by the extent computation of [`Obb`], in world
    /// coordinates.
    #[inline(always)]
    fn aabb(&self) -> Aabb<T> {
        let (o, l) = (T::zero(), T::one());
        let b = Obb::with_axes(self, [V3::new(l, o, o), V3::new(o, l, o), V3::new(o, o, l)]);
        Aabb::new(b.origin + b.lo, b.origin + b.hi)
    }
    /// Lane by lane (a 1-D minimisation with data-dependent iteration counts).
    #[inline]
    fn sdf(&self, p: V3<T>) -> T {
        T::from_fn(|i| quadratic_tube(p.lane(i), &self.lane(i)))
    }
}
