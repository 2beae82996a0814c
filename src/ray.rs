//! Rays and the intervals the kernels return.

use crate::real::{Mask, Real, Scalar};
use crate::vec::V3;

/// A ray `o + t·d`, `t ∈ [t_min, t_max]`. `d` need not be unit length.
///
/// ```
/// use tubecast::{Ray, V3};
/// let ray = Ray::with_range(V3::new(0.0, 0.0, 0.0), V3::new(0.0, 0.0, 2.0), 0.0, 10.0);
/// assert_eq!(ray.at(1.5), V3::new(0.0, 0.0, 3.0));
/// assert!(ray.validate().is_ok());
/// assert!(Ray::new(ray.o, V3::new(0.0, 0.0, 0.0)).validate().is_err());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray<T> {
    /// Origin.
    pub o: V3<T>,
    /// Direction (any non-zero length).
    pub d: V3<T>,
    /// Start of the valid parameter range.
    pub t_min: T,
    /// End of the valid parameter range.
    pub t_max: T,
}

impl<T: Real> Ray<T> {
    /// A ray with range `[0, +∞)`.
    #[inline(always)]
    pub fn new(o: V3<T>, d: V3<T>) -> Self {
        Self { o, d, t_min: T::zero(), t_max: T::infinity() }
    }
    /// A ray with an explicit range.
    #[inline(always)]
    pub fn with_range(o: V3<T>, d: V3<T>, t_min: T, t_max: T) -> Self {
        Self { o, d, t_min, t_max }
    }
    /// The point `o + t·d`.
    #[inline(always)]
    pub fn at(&self, t: T) -> V3<T> {
        self.o + self.d * t
    }
    /// The same rays in every lane: broadcast a scalar ray.
    #[inline(always)]
    pub fn broadcast(r: Ray<T::Elem>) -> Self {
        Self { o: V3::broadcast(r.o), d: V3::broadcast(r.d), t_min: T::splat(r.t_min), t_max: T::splat(r.t_max) }
    }
    /// Lanes from a function of the lane index.
    #[inline]
    pub fn from_fn(mut f: impl FnMut(usize) -> Ray<T::Elem>) -> Self {
        let mut rs = [None; 16];
        assert!(T::LANES <= 16);
        for (i, r) in rs.iter_mut().take(T::LANES).enumerate() {
            *r = Some(f(i));
        }
        let g = |i: usize| rs[i].expect("lane");
        Self {
            o: V3::from_fn(|i| g(i).o),
            d: V3::from_fn(|i| g(i).d),
            t_min: T::from_fn(|i| g(i).t_min),
            t_max: T::from_fn(|i| g(i).t_max),
        }
    }
    /// Lane `i` as a scalar ray.
    #[inline]
    pub fn lane(&self, i: usize) -> Ray<T::Elem> {
        Ray { o: self.o.lane(i), d: self.d.lane(i), t_min: self.t_min.lane(i), t_max: self.t_max.lane(i) }
    }
}

impl<T: Scalar> Ray<T> {
    /// Check that origin, direction and range are usable: finite origin and direction,
    /// non-zero direction, `t_min ≤ t_max`, no NaN in the range.
    pub fn validate(&self) -> Result<(), crate::error::GeometryError> {
        use crate::error::GeometryError as E;
        if !self.o.is_finite() || !self.d.is_finite() {
            return Err(E::NonFinite { what: "ray origin or direction" });
        }
        // |d|² must be a normal number and |o|² finite: kernels square both.
        let d2 = self.d.length2();
        // (NaN compares as unordered: also an error.)
        if matches!(d2.partial_cmp(&T::MIN_POSITIVE), None | Some(core::cmp::Ordering::Less)) {
            return Err(E::ZeroDirection);
        }
        if !d2.is_finite() || !self.o.length2().is_finite() {
            return Err(E::NonFinite { what: "ray origin or direction (overflows when squared)" });
        }
        if self.t_min.to_f64().is_nan() || self.t_max.to_f64().is_nan() || self.t_min > self.t_max {
            return Err(E::BadRange);
        }
        Ok(())
    }
}

/// One surface crossing along a ray: the ray parameter `t`, the unit outward normal `n` and
/// the curve parameter `u` (`u ∈ [0, 1]` along the link or segment) where the ray crosses.
///
/// The building block of every answer: an [`Interval`] is an entry and an exit crossing, a
/// [`Hit`] is a crossing attributed to a primitive.
///
/// ```
/// use tubecast::{Crossing, Ray, V3};
/// let ray = Ray::new(V3::new(0.0, 0.0, 0.0), V3::new(0.0, 0.0, 2.0));
/// let c = Crossing { t: 1.5, n: V3::new(0.0, 0.0, -1.0), u: 0.0 };
/// assert_eq!(c.point(&ray), V3::new(0.0, 0.0, 3.0));
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Crossing<T> {
    /// Ray parameter.
    pub t: T,
    /// Unit outward normal.
    pub n: V3<T>,
    /// Curve parameter on the primitive.
    pub u: T,
}

impl<T: Real> Crossing<T> {
    /// The point `o + t·d` of `ray` where the crossing lies.
    #[inline(always)]
    pub fn point(&self, ray: &Ray<T>) -> V3<T> {
        ray.at(self.t)
    }
    /// Lane-wise choice between two crossings.
    #[inline(always)]
    pub fn select(m: T::Mask, a: Self, b: Self) -> Self {
        Self { t: T::select(m, a.t, b.t), n: V3::select(m, a.n, b.n), u: T::select(m, a.u, b.u) }
    }
    /// Lane `i` as a scalar crossing.
    #[inline]
    pub fn lane(&self, i: usize) -> Crossing<T::Elem> {
        Crossing { t: self.t.lane(i), n: self.n.lane(i), u: self.u.lane(i) }
    }
}

/// A surface crossing attributed to a primitive: what a query over many primitives returns
/// (a tracer's closest hit, a boundary of a CSG [`crate::csg::union`]).
///
/// `id` is the caller's primitive id; `entering` is false where the ray leaves the solid (it
/// started inside, or the crossing is the exit of a union component).
///
/// ```
/// use tubecast::{Hit, Ray, V3};
/// let n = V3::new(0.0, 0.0, -1.0);
/// let a = Hit { t: 2.0, n, u: 0.25, id: 7, entering: true };
/// let b = Hit { t: 2.0, n, u: 0.75, id: 3, entering: true };
/// assert!(a.closer(&b) && !b.closer(&a)); // equal t: the smaller u
/// let ray = Ray::new(V3::new(0.0, 0.0, 0.0), V3::new(0.0, 0.0, 1.0));
/// assert_eq!(a.point(&ray), V3::new(0.0, 0.0, 2.0));
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit<T> {
    /// Ray parameter.
    pub t: T,
    /// Unit outward normal.
    pub n: V3<T>,
    /// Curve parameter on the primitive.
    pub u: T,
    /// Caller's primitive id.
    pub id: u32,
    /// True for an entry, false for an exit.
    pub entering: bool,
}

impl<T: Scalar> Hit<T> {
    /// A crossing attributed to primitive `id`.
    #[inline(always)]
    pub fn new(c: Crossing<T>, id: u32, entering: bool) -> Self {
        Self { t: c.t, n: c.n, u: c.u, id, entering }
    }
    /// The crossing alone.
    #[inline(always)]
    pub fn crossing(&self) -> Crossing<T> {
        Crossing { t: self.t, n: self.n, u: self.u }
    }
    /// The point `o + t·d` of `ray` where the hit lies.
    #[inline(always)]
    pub fn point(&self, ray: &Ray<T>) -> V3<T> {
        ray.at(self.t)
    }
    /// The one rule that orders hits, used by every query and accelerator: the smaller `t`;
    /// at equal `t`, the smaller `u`, then the smaller normal (x, y, z), then the smaller `id`
    /// (a total order, IEEE `totalOrder` on each number).
    ///
    /// Why the crossing's own data before the id: accelerators number the same primitives
    /// differently (leaf order), so a rule on the data alone gives every accelerator the same
    /// answer bit for bit whatever order it visits the primitives in; the id decides only
    /// between crossings equal in every bit, i.e. the same crossing of coincident primitives.
    #[inline]
    pub fn closer(&self, other: &Self) -> bool {
        self.cmp_closer(other) == core::cmp::Ordering::Less
    }
    /// The total order behind [`Self::closer`]: `Less` where `self` is closer.
    #[inline]
    pub fn cmp_closer(&self, o: &Self) -> core::cmp::Ordering {
        let c = |a: T, b: T| a.to_f64().total_cmp(&b.to_f64());
        if self.t < o.t {
            return core::cmp::Ordering::Less;
        }
        if self.t > o.t {
            return core::cmp::Ordering::Greater;
        }
        c(self.t, o.t)
            .then(c(self.u, o.u))
            .then(c(self.n.x, o.n.x))
            .then(c(self.n.y, o.n.y))
            .then(c(self.n.z, o.n.z))
            .then(self.id.cmp(&o.id))
    }
    /// Keep the closer of `best` and `self` (by [`Self::closer`]) in `best`.
    #[inline]
    pub fn keep_closer(self, best: &mut Option<Self>) {
        if best.as_ref().map_or(true, |b| self.closer(b)) {
            *best = Some(self);
        }
    }
}

/// The overlap of a ray's **line** with a solid: its entry and exit [`Crossing`]s.
///
/// `entry.t ≤ exit.t` always holds where `hit` is set. The interval is that of the whole line
/// (not clipped to `[t_min, t_max]`), so `entry.t < t_min` means the ray starts inside the solid;
/// `hit` is set when the interval is non-empty **and** overlaps `[t_min, t_max]`.
/// Lanes without a hit hold `entry.t = +∞`, `exit.t = −∞`, zero normals and zero `u`.
///
/// ```
/// use tubecast::prelude::*;
/// let ball = Sphere::new(V3::new(0.0, 0.0, 0.0), 1.0).unwrap();
/// // A ray starting inside: the line interval begins behind the origin.
/// let iv = ball.intersect(&Ray::new(V3::new(0.0, 0.0, 0.5), V3::new(0.0, 0.0, 1.0)));
/// assert!(iv.hit && iv.entry.t == -1.5 && iv.exit.t == 0.5);
/// let first = iv.first_hit(0.0, f64::INFINITY).unwrap(); // the exit
/// assert!(first.t == 0.5 && !first.entering);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Interval<T: Real> {
    /// Where the line enters the solid.
    pub entry: Crossing<T>,
    /// Where the line leaves the solid.
    pub exit: Crossing<T>,
    /// Which lanes hit.
    pub hit: T::Mask,
}

impl<T: Real> Interval<T> {
    /// An interval from its two crossings and hit mask.
    #[inline(always)]
    pub fn new(entry: Crossing<T>, exit: Crossing<T>, hit: T::Mask) -> Self {
        Self { entry, exit, hit }
    }
    /// The empty interval (a miss in every lane).
    #[inline(always)]
    pub fn miss() -> Self {
        Self {
            entry: Crossing { t: T::infinity(), n: V3::zero(), u: T::zero() },
            exit: Crossing { t: -T::infinity(), n: V3::zero(), u: T::zero() },
            hit: T::Mask::splat(false),
        }
    }
    /// Keep lanes where `m` is set, make the others misses.
    #[inline(always)]
    pub fn masked(self, m: T::Mask) -> Self {
        let e = Self::miss();
        Self::select(m & self.hit, self, e)
    }
    /// A line interval clipped to a ray: lanes whose interval is non-empty and overlaps
    /// `[t_min, t_max]` keep it (unclipped: `entry.t < t_min` still says the ray starts inside),
    /// the others become misses. This is the step from a `line_interval` to an `intersect`
    /// ([`crate::Primitive::intersect`]).
    #[inline(always)]
    pub fn clip(self, ray: &Ray<T>) -> Self {
        self.masked(in_range(ray, self.entry.t, self.exit.t))
    }
    /// Lane-wise choice between two intervals.
    #[inline(always)]
    pub fn select(m: T::Mask, a: Self, b: Self) -> Self {
        Self {
            entry: Crossing::select(m, a.entry, b.entry),
            exit: Crossing::select(m, a.exit, b.exit),
            hit: (m & a.hit) | (!m & b.hit),
        }
    }
    /// Union of two intervals known to overlap or touch (e.g. pieces of one convex solid):
    /// the earlier entry and the later exit, each with its normal and parameter.
    #[inline(always)]
    pub fn hull(self, o: Self) -> Self {
        let a_in = self.hit & (!o.hit | self.entry.t.le(o.entry.t));
        let a_out = self.hit & (!o.hit | self.exit.t.ge(o.exit.t));
        Self {
            entry: Crossing::select(a_in, self.entry, o.entry),
            exit: Crossing::select(a_out, self.exit, o.exit),
            hit: self.hit | o.hit,
        }
    }
    /// Lanes from scalar intervals, lane `i` from `f(i)` (at most 16 lanes).
    #[inline]
    pub(crate) fn from_lanes(f: impl Fn(usize) -> Interval<T::Elem>) -> Self {
        assert!(T::LANES <= 16, "Interval::from_lanes: more than 16 lanes");
        let lanes: [Interval<T::Elem>; 16] =
            core::array::from_fn(|i| if i < T::LANES { f(i) } else { Interval::miss() });
        let one = |b: bool| if b { T::Elem::one() } else { T::Elem::zero() };
        let cross = |g: fn(&Interval<T::Elem>) -> &Crossing<T::Elem>| Crossing {
            t: T::from_fn(|i| g(&lanes[i]).t),
            n: V3::from_fn(|i| g(&lanes[i]).n),
            u: T::from_fn(|i| g(&lanes[i]).u),
        };
        Self {
            entry: cross(|iv| &iv.entry),
            exit: cross(|iv| &iv.exit),
            hit: T::from_fn(|i| one(lanes[i].hit)).gt(T::zero()),
        }
    }
    /// Lane `i` as a scalar interval.
    pub fn lane(&self, i: usize) -> Interval<T::Elem> {
        Interval { entry: self.entry.lane(i), exit: self.exit.lane(i), hit: self.hit.lane(i) }
    }
}

impl<T: Scalar> Crossing<T> {
    /// The same crossing in `f64` (exact: `f32` and `f64` convert without rounding).
    #[inline(always)]
    pub fn to_f64(&self) -> Crossing<f64> {
        Crossing { t: self.t.to_f64(), n: self.n.cast(), u: self.u.to_f64() }
    }
}

impl<T: Scalar> Interval<T> {
    /// The same interval in `f64` (exact).
    #[inline(always)]
    pub fn to_f64(&self) -> Interval<f64> {
        Interval { entry: self.entry.to_f64(), exit: self.exit.to_f64(), hit: self.hit }
    }
    /// `Some(self)` on a hit.
    #[inline]
    pub fn get(self) -> Option<Self> {
        if self.hit {
            Some(self)
        } else {
            None
        }
    }
    /// The first surface crossing inside `[t_min, t_max]`, as a [`Hit`] with `id` 0 — the
    /// entry, or the exit (`entering == false`) when the ray starts inside.
    #[inline]
    pub fn first_hit(&self, t_min: T, t_max: T) -> Option<Hit<T>> {
        if !self.hit {
            return None;
        }
        let entering = Self::first_end(self.entry.t, self.exit.t, t_min, t_max)?;
        Some(Hit::new(if entering { self.entry } else { self.exit }, 0, entering))
    }
    /// Which end of an interval `[t_in, t_out]` is its first crossing inside `[t_min, t_max]`:
    /// `Some(true)` the entry, `Some(false)` the exit (the ray starts inside), `None` neither —
    /// the rule of [`Self::first_hit`], for callers that hold only the two `t`.
    #[inline]
    pub fn first_end(t_in: T, t_out: T, t_min: T, t_max: T) -> Option<bool> {
        if t_in >= t_min && t_in <= t_max {
            Some(true)
        } else if t_out >= t_min && t_out <= t_max {
            Some(false)
        } else {
            None
        }
    }
}

/// The hit mask for a line interval `[t_in, t_out]` against the ray range.
#[inline(always)]
pub(crate) fn in_range<T: Real>(ray: &Ray<T>, t_in: T, t_out: T) -> T::Mask {
    t_in.le(t_out) & t_out.ge(ray.t_min) & t_in.le(ray.t_max)
}
