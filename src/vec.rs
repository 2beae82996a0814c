//! A tiny generic 3-vector, [`V3`], over any [`Real`] (scalar or lanes).

use crate::real::{Real, Scalar};
use core::ops::{Add, AddAssign, Mul, Neg, Sub, SubAssign};

/// A 3-vector of [`Real`]s. For lane types each component holds one value per lane.
///
/// ```
/// use tubecast::V3;
/// let (x, y) = (V3::new(1.0, 0.0, 0.0), V3::new(0.0, 2.0, 0.0));
/// assert_eq!(x.cross(y), V3::new(0.0, 0.0, 2.0));
/// assert_eq!((x + y).length2(), 5.0);
/// assert_eq!(y.normalize_or_zero(), V3::new(0.0, 1.0, 0.0));
/// assert_eq!(V3::from([1.0, 2.0, 3.0]).to_array(), [1.0, 2.0, 3.0]);
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct V3<T> {
    /// x component.
    pub x: T,
    /// y component.
    pub y: T,
    /// z component.
    pub z: T,
}

impl<T: Real> V3<T> {
    /// A vector from components.
    #[inline(always)]
    pub fn new(x: T, y: T, z: T) -> Self {
        Self { x, y, z }
    }
    /// The zero vector.
    #[inline(always)]
    pub fn zero() -> Self {
        Self::new(T::zero(), T::zero(), T::zero())
    }
    /// Every lane set to the scalar vector `v`.
    #[inline(always)]
    pub fn broadcast(v: V3<T::Elem>) -> Self {
        Self::new(T::splat(v.x), T::splat(v.y), T::splat(v.z))
    }
    /// Lanes from a function of the lane index.
    #[inline(always)]
    pub fn from_fn(mut f: impl FnMut(usize) -> V3<T::Elem>) -> Self {
        let mut xs = [V3::<T::Elem>::default(); 16];
        assert!(T::LANES <= 16);
        for (i, v) in xs.iter_mut().take(T::LANES).enumerate() {
            *v = f(i);
        }
        Self::new(T::from_fn(|i| xs[i].x), T::from_fn(|i| xs[i].y), T::from_fn(|i| xs[i].z))
    }
    /// Lane `i` as a scalar vector.
    #[inline(always)]
    pub fn lane(self, i: usize) -> V3<T::Elem> {
        V3::new(self.x.lane(i), self.y.lane(i), self.z.lane(i))
    }
    /// Dot product.
    #[inline(always)]
    pub fn dot(self, o: Self) -> T {
        self.x * o.x + self.y * o.y + self.z * o.z
    }
    /// Cross product.
    #[inline(always)]
    pub fn cross(self, o: Self) -> Self {
        Self::new(self.y * o.z - self.z * o.y, self.z * o.x - self.x * o.z, self.x * o.y - self.y * o.x)
    }
    /// Squared length.
    #[inline(always)]
    pub fn length2(self) -> T {
        self.dot(self)
    }
    /// Length.
    #[inline(always)]
    pub fn length(self) -> T {
        self.length2().sqrt()
    }
    /// `self * s`.
    #[inline(always)]
    pub fn scale(self, s: T) -> Self {
        Self::new(self.x * s, self.y * s, self.z * s)
    }
    /// `self / |self|`; the zero vector (and only it) maps to zero instead of NaN.
    ///
    /// Scaled by the largest component first, so components whose squares under- or overflow
    /// still give a unit vector.
    #[inline(always)]
    pub fn normalize_or_zero(self) -> Self {
        let m = self.max_abs();
        let pos = m.gt(T::zero()) & m.is_finite();
        let v = self.scale(T::one() / T::select(pos, m, T::one()));
        let l = v.length();
        v.scale(T::select(pos, T::one() / l, T::zero()))
    }
    /// Lane-wise `if m { a } else { b }`.
    #[inline(always)]
    pub fn select(m: T::Mask, a: Self, b: Self) -> Self {
        Self::new(T::select(m, a.x, b.x), T::select(m, a.y, b.y), T::select(m, a.z, b.z))
    }
    /// All components finite, lane-wise.
    #[inline(always)]
    pub fn is_finite(self) -> T::Mask {
        self.x.is_finite() & self.y.is_finite() & self.z.is_finite()
    }
    /// Largest absolute component.
    #[inline(always)]
    pub fn max_abs(self) -> T {
        self.x.abs().max(self.y.abs()).max(self.z.abs())
    }
}

impl<T: Scalar> V3<T> {
    /// Convert the precision (`f32` ↔ `f64`), rounding to nearest.
    #[inline]
    pub fn cast<U: Scalar>(self) -> V3<U> {
        V3::new(U::from_f64(self.x.to_f64()), U::from_f64(self.y.to_f64()), U::from_f64(self.z.to_f64()))
    }
    /// As an array.
    #[inline]
    pub fn to_array(self) -> [T; 3] {
        [self.x, self.y, self.z]
    }
}

impl<T: Real> From<[T; 3]> for V3<T> {
    #[inline(always)]
    fn from(a: [T; 3]) -> Self {
        Self::new(a[0], a[1], a[2])
    }
}

impl<T: Real> Add for V3<T> {
    type Output = Self;
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        Self::new(self.x + o.x, self.y + o.y, self.z + o.z)
    }
}
impl<T: Real> Sub for V3<T> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        Self::new(self.x - o.x, self.y - o.y, self.z - o.z)
    }
}
impl<T: Real> Neg for V3<T> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        Self::new(-self.x, -self.y, -self.z)
    }
}
impl<T: Real> Mul<T> for V3<T> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, s: T) -> Self {
        self.scale(s)
    }
}
impl<T: Real> AddAssign for V3<T> {
    #[inline(always)]
    fn add_assign(&mut self, o: Self) {
        *self = *self + o;
    }
}
impl<T: Real> SubAssign for V3<T> {
    #[inline(always)]
    fn sub_assign(&mut self, o: Self) {
        *self = *self - o;
    }
}
