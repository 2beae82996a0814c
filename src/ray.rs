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
    pub fn splat(r: Ray<T::Elem>) -> Self {
        Self { o: V3::splat(r.o), d: V3::splat(r.d), t_min: T::splat(r.t_min), t_max: T::splat(r.t_max) }
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

/// The overlap of a ray's **line** with a solid: entry and exit with unit outward normals
/// and curve parameters.
///
/// `t_in ≤ t_out` always hold where `hit` is set. The interval is that of the whole line
/// (not clipped to `[t_min, t_max]`), so `t_in < t_min` means the ray starts inside the solid;
/// `hit` is set when the interval is non-empty **and** overlaps `[t_min, t_max]`.
/// Lanes without a hit hold `t_in = +∞`, `t_out = −∞`, zero normals and zero `u`.
///
/// ```
/// use tubecast::{Primitive, Ray, Sphere, V3};
/// let ball = Sphere::new(V3::new(0.0, 0.0, 0.0), 1.0).unwrap();
/// // A ray starting inside: the line interval begins behind the origin.
/// let iv = ball.intersect(&Ray::new(V3::new(0.0, 0.0, 0.5), V3::new(0.0, 0.0, 1.0)));
/// assert!(iv.hit && iv.t_in == -1.5 && iv.t_out == 0.5);
/// assert_eq!(iv.first_hit(0.0, f64::INFINITY).map(|h| h.0), Some(0.5)); // the exit
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Interval<T: Real> {
    /// Entry parameter.
    pub t_in: T,
    /// Exit parameter.
    pub t_out: T,
    /// Unit outward normal at entry.
    pub n_in: V3<T>,
    /// Unit outward normal at exit.
    pub n_out: V3<T>,
    /// Curve parameter (`u ∈ [0, 1]` along the link or segment) at entry.
    pub u_in: T,
    /// Curve parameter at exit.
    pub u_out: T,
    /// Which lanes hit.
    pub hit: T::Mask,
}

impl<T: Real> Interval<T> {
    /// The empty interval (a miss in every lane).
    #[inline(always)]
    pub fn miss() -> Self {
        Self {
            t_in: T::infinity(),
            t_out: -T::infinity(),
            n_in: V3::zero(),
            n_out: V3::zero(),
            u_in: T::zero(),
            u_out: T::zero(),
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
    /// `[t_min, t_max]` keep it (unclipped: `t_in < t_min` still says the ray starts inside),
    /// the others become misses. This is the step from a `line_interval` to an `intersect`
    /// ([`crate::Primitive::intersect`]).
    #[inline(always)]
    pub fn clip(self, ray: &Ray<T>) -> Self {
        self.masked(in_range(ray, self.t_in, self.t_out))
    }
    /// Lane-wise choice between two intervals.
    #[inline(always)]
    pub fn select(m: T::Mask, a: Self, b: Self) -> Self {
        Self {
            t_in: T::select(m, a.t_in, b.t_in),
            t_out: T::select(m, a.t_out, b.t_out),
            n_in: V3::select(m, a.n_in, b.n_in),
            n_out: V3::select(m, a.n_out, b.n_out),
            u_in: T::select(m, a.u_in, b.u_in),
            u_out: T::select(m, a.u_out, b.u_out),
            hit: (m & a.hit) | (!m & b.hit),
        }
    }
    /// Union of two intervals known to overlap or touch (e.g. pieces of one convex solid):
    /// the earlier entry and the later exit, each with its normal and parameter.
    #[inline(always)]
    pub fn hull(self, o: Self) -> Self {
        let a_in = self.hit & (!o.hit | self.t_in.le(o.t_in));
        let a_out = self.hit & (!o.hit | self.t_out.ge(o.t_out));
        Self {
            t_in: T::select(a_in, self.t_in, o.t_in),
            n_in: V3::select(a_in, self.n_in, o.n_in),
            u_in: T::select(a_in, self.u_in, o.u_in),
            t_out: T::select(a_out, self.t_out, o.t_out),
            n_out: V3::select(a_out, self.n_out, o.n_out),
            u_out: T::select(a_out, self.u_out, o.u_out),
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
        Self {
            t_in: T::from_fn(|i| lanes[i].t_in),
            t_out: T::from_fn(|i| lanes[i].t_out),
            n_in: V3::from_fn(|i| lanes[i].n_in),
            n_out: V3::from_fn(|i| lanes[i].n_out),
            u_in: T::from_fn(|i| lanes[i].u_in),
            u_out: T::from_fn(|i| lanes[i].u_out),
            hit: T::from_fn(|i| one(lanes[i].hit)).gt(T::zero()),
        }
    }
    /// Lane `i` as a scalar interval.
    pub fn lane(&self, i: usize) -> Interval<T::Elem> {
        Interval {
            t_in: self.t_in.lane(i),
            t_out: self.t_out.lane(i),
            n_in: self.n_in.lane(i),
            n_out: self.n_out.lane(i),
            u_in: self.u_in.lane(i),
            u_out: self.u_out.lane(i),
            hit: self.hit.lane(i),
        }
    }
}

impl<T: Scalar> Interval<T> {
    /// `Some(self)` on a hit.
    #[inline]
    pub fn get(self) -> Option<Self> {
        if self.hit {
            Some(self)
        } else {
            None
        }
    }
    /// The first surface crossing inside `[t_min, t_max]`: `(t, normal, u)` — the entry, or
    /// the exit when the ray starts inside.
    #[inline]
    pub fn first_hit(&self, t_min: T, t_max: T) -> Option<(T, V3<T>, T)> {
        if !self.hit {
            return None;
        }
        if self.t_in >= t_min && self.t_in <= t_max {
            Some((self.t_in, self.n_in, self.u_in))
        } else if self.t_out >= t_min && self.t_out <= t_max {
            Some((self.t_out, self.n_out, self.u_out))
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
