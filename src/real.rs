//! The [`Real`] trait: one numeric interface for `f32`, `f64` and SIMD lanes.
//!
//! Every kernel in [`crate::kernel`] is written once against [`Real`] and instantiated for
//! `f32`, `f64`, and (feature `wide`) simba's [`WideF32x8`] and [`WideF64x4`]. A lane type
//! evaluates eight (or four) independent ray–primitive problems at once; control flow that
//! depends on data is expressed with comparison masks ([`Real::Mask`]) and [`Real::select`],
//! so the same source is branch-free for lanes and plain `if`s for scalars.
//!
//! For full-width lanes in benchmarks build with AVX2 enabled, e.g.
//! `RUSTFLAGS="-C target-cpu=x86-64-v3" cargo bench` (see `README.md`); without it `wide`
//! falls back to two SSE halves, which is correct but slower.

use core::fmt::Debug;
use core::ops::{Add, AddAssign, BitAnd, BitOr, Div, Mul, MulAssign, Neg, Not, Sub, SubAssign};

/// A lane mask: the result of comparing two [`Real`] values lane by lane.
///
/// For scalars this is `bool`.
///
/// ```
/// use tubecast::{Mask, Real};
/// let m = 1.0f32.lt(2.0);
/// assert!(m.any() && m.all() && !m.none() && m.lane(0));
/// ```
pub trait Mask: Copy + Debug + BitAnd<Output = Self> + BitOr<Output = Self> + Not<Output = Self> + Send + Sync {
    /// A mask with every lane set to `b`.
    fn splat(b: bool) -> Self;
    /// True if any lane is set.
    fn any(self) -> bool;
    /// True if every lane is set.
    fn all(self) -> bool;
    /// True if no lane is set.
    #[inline(always)]
    fn none(self) -> bool {
        !self.any()
    }
    /// The value of lane `i` (panics if `i` is out of range).
    fn lane(self, i: usize) -> bool;
}

impl Mask for bool {
    #[inline(always)]
    fn splat(b: bool) -> Self {
        b
    }
    #[inline(always)]
    fn any(self) -> bool {
        self
    }
    #[inline(always)]
    fn all(self) -> bool {
        self
    }
    #[inline(always)]
    fn lane(self, i: usize) -> bool {
        assert!(i == 0, "lane index out of range");
        self
    }
}

/// A real number type, scalar or SIMD lanes, as the kernels need it.
///
/// Arithmetic follows IEEE 754 lane by lane. [`Real::min`] and [`Real::max`] return the
/// non-NaN operand when exactly one operand is NaN (like `f64::min`), for every implementor.
///
/// ```
/// use tubecast::Real;
/// /// `|x|` clamped to 1, one source for scalars and lanes.
/// fn f<T: Real>(x: T) -> T {
///     T::select(x.lt(T::zero()), -x, x).min(T::one())
/// }
/// assert_eq!(f(-0.5f64), 0.5);
/// # #[cfg(feature = "wide")] {
/// let x = tubecast::WideF32x8::from_fn(|i| i as f32 - 4.0);
/// for i in 0..8 {
///     assert_eq!(f(x).lane(i), f(i as f32 - 4.0));
/// }
/// # }
/// ```
pub trait Real:
    Copy
    + Debug
    + Send
    + Sync
    + 'static
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + AddAssign
    + SubAssign
    + MulAssign
{
    /// The lane mask type.
    type Mask: Mask;
    /// The scalar type of one lane (`f32` or `f64`).
    type Elem: Scalar;
    /// Number of lanes (1 for scalars).
    const LANES: usize;

    /// Every lane set to `x`.
    fn splat(x: Self::Elem) -> Self;
    /// A constant, rounded to the lane precision.
    fn cst(x: f64) -> Self;
    /// Lanes from a function of the lane index.
    fn from_fn(f: impl FnMut(usize) -> Self::Elem) -> Self;
    /// The value of lane `i` (panics if `i` is out of range).
    fn lane(self, i: usize) -> Self::Elem;

    /// Square root.
    fn sqrt(self) -> Self;
    /// Absolute value.
    fn abs(self) -> Self;
    /// Lane-wise minimum (NaN-ignoring).
    fn min(self, o: Self) -> Self;
    /// Lane-wise maximum (NaN-ignoring).
    fn max(self, o: Self) -> Self;
    /// `self * a + b`, fused where the target supports it.
    fn mul_add(self, a: Self, b: Self) -> Self;

    /// `self < o`, lane-wise.
    fn lt(self, o: Self) -> Self::Mask;
    /// `self <= o`, lane-wise.
    fn le(self, o: Self) -> Self::Mask;
    /// `self > o`, lane-wise.
    fn gt(self, o: Self) -> Self::Mask;
    /// `self >= o`, lane-wise.
    fn ge(self, o: Self) -> Self::Mask;
    /// `self == o`, lane-wise.
    fn eq(self, o: Self) -> Self::Mask;
    /// Finite (not NaN, not ±∞), lane-wise.
    fn is_finite(self) -> Self::Mask;
    /// `if m { a } else { b }`, lane-wise.
    fn select(m: Self::Mask, a: Self, b: Self) -> Self;

    /// Zero.
    #[inline(always)]
    fn zero() -> Self {
        Self::cst(0.0)
    }
    /// One.
    #[inline(always)]
    fn one() -> Self {
        Self::cst(1.0)
    }
    /// +∞.
    #[inline(always)]
    fn infinity() -> Self {
        Self::cst(f64::INFINITY)
    }
    /// Machine epsilon of the lane precision (2⁻²³ or 2⁻⁵²).
    #[inline(always)]
    fn epsilon() -> Self {
        Self::splat(Self::Elem::EPS)
    }
    /// `x` with the sign of `s` (`s = ±0` counts as positive).
    #[inline(always)]
    fn copysign_of(self, s: Self) -> Self {
        let a = self.abs();
        Self::select(s.lt(Self::zero()), -a, a)
    }
    /// Clamp into `[lo, hi]`.
    #[inline(always)]
    fn clamp(self, lo: Self, hi: Self) -> Self {
        self.max(lo).min(hi)
    }
}

/// A scalar [`Real`]: `f32` or `f64`. Masks are `bool`.
///
/// ```
/// use tubecast::Scalar;
/// assert_eq!(f32::from_f64(0.1).to_f64(), 0.1f32 as f64);
/// ```
pub trait Scalar: Real<Mask = bool, Elem = Self> + PartialOrd + Default + core::fmt::Display {
    /// Machine epsilon.
    const EPS: Self;
    /// Smallest positive normal number.
    const MIN_POSITIVE: Self;
    /// Convert from `f64` (rounding to nearest).
    fn from_f64(x: f64) -> Self;
    /// Convert to `f64` (exact).
    fn to_f64(self) -> f64;
}

/// The lane-wise comparisons of a [`Real`] implementation: `name: |a, b| body` becomes
/// `fn name(self, o: Self) -> Mask` with `a = self`, `b = o`.
macro_rules! comparisons {
    ($mask:ty; $($name:ident: |$a:ident, $b:ident| $body:expr),+ $(,)?) => {
        $(
            #[inline(always)]
            fn $name(self, o: Self) -> $mask {
                let ($a, $b) = (self, o);
                $body
            }
        )+
    };
}

macro_rules! impl_scalar {
    ($t:ty) => {
        impl Real for $t {
            type Mask = bool;
            type Elem = $t;
            const LANES: usize = 1;
            #[inline(always)]
            fn splat(x: $t) -> Self {
                x
            }
            #[inline(always)]
            fn cst(x: f64) -> Self {
                x as $t
            }
            #[inline(always)]
            fn from_fn(mut f: impl FnMut(usize) -> $t) -> Self {
                f(0)
            }
            #[inline(always)]
            fn lane(self, i: usize) -> $t {
                assert!(i == 0, "lane index out of range");
                self
            }
            #[inline(always)]
            fn sqrt(self) -> Self {
                <$t>::sqrt(self)
            }
            #[inline(always)]
            fn abs(self) -> Self {
                <$t>::abs(self)
            }
            #[inline(always)]
            fn min(self, o: Self) -> Self {
                <$t>::min(self, o)
            }
            #[inline(always)]
            fn max(self, o: Self) -> Self {
                <$t>::max(self, o)
            }
            #[inline(always)]
            fn mul_add(self, a: Self, b: Self) -> Self {
                // A plain multiply-add: `f64::mul_add` is a slow libm call without FMA hardware.
                self * a + b
            }
            comparisons!(bool; lt: |a, b| a < b, le: |a, b| a <= b, gt: |a, b| a > b, ge: |a, b| a >= b, eq: |a, b| a == b);
            #[inline(always)]
            fn is_finite(self) -> bool {
                <$t>::is_finite(self)
            }
            #[inline(always)]
            fn select(m: bool, a: Self, b: Self) -> Self {
                if m {
                    a
                } else {
                    b
                }
            }
        }
        impl Scalar for $t {
            const EPS: Self = <$t>::EPSILON;
            const MIN_POSITIVE: Self = <$t>::MIN_POSITIVE;
            #[inline(always)]
            fn from_f64(x: f64) -> Self {
                x as $t
            }
            #[inline(always)]
            fn to_f64(self) -> f64 {
                self as f64
            }
        }
    };
}
impl_scalar!(f32);
impl_scalar!(f64);

#[cfg(feature = "wide")]
pub use self::lanes::*;

#[cfg(feature = "wide")]
mod lanes {
    use super::{Mask, Real};
    use simba::simd::{SimdBool, SimdPartialOrd, SimdValue};
    pub use simba::simd::{WideBoolF32x8, WideBoolF64x4, WideF32x8, WideF64x4};

    macro_rules! impl_wide {
        ($w:ident, $b:ident, $inner:ty, $e:ty, $n:expr) => {
            impl Mask for $b {
                #[inline(always)]
                fn splat(b: bool) -> Self {
                    <$b as SimdValue>::splat(b)
                }
                #[inline(always)]
                fn any(self) -> bool {
                    SimdBool::any(self)
                }
                #[inline(always)]
                fn all(self) -> bool {
                    SimdBool::all(self)
                }
                #[inline(always)]
                fn lane(self, i: usize) -> bool {
                    SimdValue::extract(&self, i)
                }
            }
            impl Real for $w {
                type Mask = $b;
                type Elem = $e;
                const LANES: usize = $n;
                #[inline(always)]
                fn splat(x: $e) -> Self {
                    <$w as SimdValue>::splat(x)
                }
                #[inline(always)]
                fn cst(x: f64) -> Self {
                    <$w as SimdValue>::splat(x as $e)
                }
                #[inline(always)]
                fn from_fn(mut f: impl FnMut(usize) -> $e) -> Self {
                    let mut a = [0.0 as $e; $n];
                    for (i, v) in a.iter_mut().enumerate() {
                        *v = f(i);
                    }
                    $w(<$inner>::from(a))
                }
                #[inline(always)]
                fn lane(self, i: usize) -> $e {
                    SimdValue::extract(&self, i)
                }
                #[inline(always)]
                fn sqrt(self) -> Self {
                    $w(self.0.sqrt())
                }
                #[inline(always)]
                fn abs(self) -> Self {
                    $w(self.0.abs())
                }
                #[inline(always)]
                fn min(self, o: Self) -> Self {
                    // `wide`'s `min` picks the other operand when one lane is NaN, like f64::min.
                    $w(self.0.min(o.0))
                }
                #[inline(always)]
                fn max(self, o: Self) -> Self {
                    $w(self.0.max(o.0))
                }
                #[inline(always)]
                fn mul_add(self, a: Self, b: Self) -> Self {
                    $w(self.0.mul_add(a.0, b.0))
                }
                comparisons!($b;
                    lt: |a, b| SimdPartialOrd::simd_lt(a, b),
                    le: |a, b| SimdPartialOrd::simd_le(a, b),
                    gt: |a, b| SimdPartialOrd::simd_gt(a, b),
                    ge: |a, b| SimdPartialOrd::simd_ge(a, b),
                    eq: |a, b| SimdPartialOrd::simd_eq(a, b),
                );
                #[inline(always)]
                fn is_finite(self) -> $b {
                    $b(self.0.is_finite())
                }
                #[inline(always)]
                fn select(m: $b, a: Self, b: Self) -> Self {
                    SimdValue::select(a, m, b)
                }
            }
        };
    }
    impl_wide!(WideF32x8, WideBoolF32x8, wide::f32x8, f32, 8);
    impl_wide!(WideF64x4, WideBoolF64x4, wide::f64x4, f64, 4);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scalar_min_max_ignore_nan() {
        assert_eq!(Real::min(f64::NAN, 1.0), 1.0);
        assert_eq!(Real::max(1.0f32, f32::NAN), 1.0);
    }

    #[cfg(feature = "wide")]
    #[test]
    fn lanes_match_scalar_ops() {
        let a = WideF32x8::from_fn(|i| i as f32 - 3.5);
        let b = WideF32x8::from_fn(|i| if i == 2 { f32::NAN } else { 0.25 * i as f32 });
        let m = a.lt(b);
        let s = WideF32x8::select(m, a, b);
        for i in 0..8 {
            let (x, y) = (a.lane(i), b.lane(i));
            assert_eq!(m.lane(i), x < y);
            let want = if x < y { x } else { y };
            assert!(s.lane(i) == want || (s.lane(i).is_nan() && want.is_nan()));
            assert_eq!(a.min(b).lane(i), Real::min(x, y));
            assert_eq!(a.max(b).lane(i), Real::max(x, y));
        }
        assert!(m.any() && !m.all());
        let z = WideF64x4::from_fn(|i| [1.0, f64::INFINITY, f64::NAN, -2.0][i]);
        let f = z.is_finite();
        assert_eq!([f.lane(0), f.lane(1), f.lane(2), f.lane(3)], [true, false, false, true]);
        assert_eq!(z.abs().sqrt().lane(3), 2f64.sqrt());
    }
}
