//! # tubecast
//!
//! Exact, fast, verified ray–tube intersection kernels: spheres, tangent cones and cone
//! stumps (Han et al. 2019), round-cone links in a faithful and a numerically stable
//! formulation, and CSG union of intervals for correct transparency. Every kernel is a pure
//! function written once against [`Real`] and instantiated for `f32`, `f64` and SIMD lanes
//! (`WideF32x8`, `WideF64x4`, feature `wide`).
//!
//! ```
//! use tubecast::{Ray, RoundCone, V3};
//! let link = RoundCone::new(V3::new(0.0, 0.0, 0.0), 1.0, V3::new(4.0, 0.0, 0.0), 0.5).unwrap();
//! let ray = Ray::new(V3::new(2.0, -10.0, 0.0), V3::new(0.0, 1.0, 0.0));
//! let iv = link.intersect(&ray).get().expect("hits");
//! assert!(iv.t_in < iv.t_out);
//! ```
//!
//! Conventions: rays are `o + t·d` with `t ∈ [t_min, t_max]`; kernels return the interval of
//! the ray's whole line with the solid ([`Interval`]) with unit outward normals and the curve
//! parameter `u`, and a hit mask that says whether it overlaps the ray's range.
#![deny(missing_docs)]

pub mod kernel;
mod math;
pub mod ray;
pub mod real;
pub mod vec;

pub use kernel::{HanLink, LinkShape, RoundCone};
pub use ray::{Interval, Ray};
pub use real::{Mask, Real, Scalar};
pub use vec::V3;

/// Invalid geometry or rays given to a constructor or validator.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GeometryError {
    /// A coordinate, radius or extent is NaN or infinite.
    NonFinite {
        /// What was not finite.
        what: &'static str,
    },
    /// A radius is negative.
    NegativeRadius,
    /// A radius is zero where a volume is required.
    ZeroRadius,
    /// A ray direction is zero.
    ZeroDirection,
    /// A non-zero size is so small that its square (nearly) underflows.
    TooSmall {
        /// What was too small.
        what: &'static str,
    },
    /// A ray range is NaN or has `t_min > t_max`.
    BadRange,
}

impl core::fmt::Display for GeometryError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::NonFinite { what } => write!(f, "{what} is NaN or infinite"),
            Self::NegativeRadius => write!(f, "radius is negative"),
            Self::ZeroRadius => write!(f, "radius is zero (the primitive has no volume)"),
            Self::ZeroDirection => write!(f, "ray direction is zero (or its squared length underflows)"),
            Self::TooSmall { what } => write!(f, "{what} is too small"),
            Self::BadRange => write!(f, "ray range is NaN or t_min > t_max"),
        }
    }
}

impl std::error::Error for GeometryError {}
