//! Conversions to and from other vector libraries, each behind its own feature: `glam`
//! ([`V3<f32>`](crate::V3) ↔ `Vec3`, `Vec3A`; `V3<f64>` ↔ `DVec3`), `nalgebra` (`V3<T>` ↔
//! `Vector3<T>`, `Point3<T>` for `f32`, `f64` and the lane types `WideF32x8`, `WideF64x4`,
//! which are simba's, as nalgebra's are), `mint` (`V3<T>` ↔ `mint::Vector3<T>`,
//! `mint::Point3<T>`). A ray converts from an `(origin, direction)` pair with range `[0, ∞)`.
//!
//! ```
//! # #[cfg(feature = "glam")] {
//! use tubecast::{Primitive, Ray, RoundCone, V3};
//! let link = RoundCone::new(glam::Vec3::ZERO.into(), 1.0, glam::Vec3::new(4.0, 0.0, 0.0).into(), 0.5).unwrap();
//! let ray: Ray<f32> = (glam::Vec3::new(2.0, -10.0, 0.0), glam::Vec3::Y).into();
//! let iv = link.intersect(&ray);
//! let entry: glam::Vec3 = ray.at(iv.entry.t).into();
//! assert!(iv.hit && entry.y < 0.0);
//! # }
//! ```

#[cfg(feature = "glam")]
mod glam_impls {
    use crate::{Ray, V3};
    use glam::{DVec3, Vec3, Vec3A};

    macro_rules! both_ways {
        ($g:ty, $t:ty) => {
            impl From<$g> for V3<$t> {
                #[inline]
                fn from(v: $g) -> Self {
                    V3::new(v.x, v.y, v.z)
                }
            }
            impl From<V3<$t>> for $g {
                #[inline]
                fn from(v: V3<$t>) -> Self {
                    <$g>::new(v.x, v.y, v.z)
                }
            }
            impl From<($g, $g)> for Ray<$t> {
                /// `(origin, direction)`, range `[0, ∞)`.
                #[inline]
                fn from((o, d): ($g, $g)) -> Self {
                    Ray::new(o.into(), d.into())
                }
            }
        };
    }
    both_ways!(Vec3, f32);
    both_ways!(Vec3A, f32);
    both_ways!(DVec3, f64);
}

#[cfg(feature = "nalgebra")]
mod nalgebra_impls {
    use crate::{Ray, Real, V3};
    use nalgebra::{Point3, Scalar, Vector3};

    impl<T: Real + Scalar> From<Vector3<T>> for V3<T> {
        #[inline]
        fn from(v: Vector3<T>) -> Self {
            V3::new(v.x, v.y, v.z)
        }
    }
    impl<T: Real + Scalar> From<V3<T>> for Vector3<T> {
        #[inline]
        fn from(v: V3<T>) -> Self {
            Vector3::new(v.x, v.y, v.z)
        }
    }
    impl<T: Real + Scalar> From<Point3<T>> for V3<T> {
        #[inline]
        fn from(p: Point3<T>) -> Self {
            V3::new(p.x, p.y, p.z)
        }
    }
    impl<T: Real + Scalar> From<V3<T>> for Point3<T> {
        #[inline]
        fn from(v: V3<T>) -> Self {
            Point3::new(v.x, v.y, v.z)
        }
    }
    impl<T: Real + Scalar> From<(Point3<T>, Vector3<T>)> for Ray<T> {
        /// `(origin, direction)`, range `[0, ∞)`.
        #[inline]
        fn from((o, d): (Point3<T>, Vector3<T>)) -> Self {
            Ray::new(o.into(), d.into())
        }
    }
}

#[cfg(feature = "mint")]
mod mint_impls {
    use crate::{Real, V3};

    impl<T: Real> From<mint::Vector3<T>> for V3<T> {
        #[inline]
        fn from(v: mint::Vector3<T>) -> Self {
            V3::new(v.x, v.y, v.z)
        }
    }
    impl<T: Real> From<V3<T>> for mint::Vector3<T> {
        #[inline]
        fn from(v: V3<T>) -> Self {
            mint::Vector3 { x: v.x, y: v.y, z: v.z }
        }
    }
    impl<T: Real> From<mint::Point3<T>> for V3<T> {
        #[inline]
        fn from(p: mint::Point3<T>) -> Self {
            V3::new(p.x, p.y, p.z)
        }
    }
    impl<T: Real> From<V3<T>> for mint::Point3<T> {
        #[inline]
        fn from(v: V3<T>) -> Self {
            mint::Point3 { x: v.x, y: v.y, z: v.z }
        }
    }
}
