//! # tubecast
//!
//! Exact, fast, verified ray–tube intersection kernels: spheres, tangent cones and cone
//! stumps (Han et al. 2019), round-cone links in a faithful and a numerically stable
//! formulation, sphere-swept quadratic spline tubes, and CSG union of intervals for correct
//! transparency. Every kernel is a pure function written once against [`Real`] and
//! instantiated for `f32`, `f64` and SIMD lanes ([`WideF32x8`], [`WideF64x4`], feature `wide`).
//!
//! ```
//! use tubecast::{Primitive, Ray, RoundCone, V3};
//! let link = RoundCone::new(V3::new(0.0, 0.0, 0.0), 1.0, V3::new(4.0, 0.0, 0.0), 0.5)?;
//! let ray = Ray::new(V3::new(2.0, -10.0, 0.0), V3::new(0.0, 1.0, 0.0));
//! let iv = link.intersect(&ray).get().expect("hits");
//! assert!(iv.entry.t < iv.exit.t);
//! # Ok::<(), tubecast::GeometryError>(())
//! ```
//!
//! Every primitive ([`Sphere`], [`RoundCone`], [`HanLink`], [`QuadTube`]) implements
//! [`Primitive`]: the interval of the ray's whole line with the solid ([`Interval`]: entry
//! and exit `t`, unit outward normals, the curve parameter `u`), the same clipped to the ray's
//! range `[t_min, t_max]`, an [`Aabb`] and the exact signed distance. [`csg::union`] merges
//! line intervals into the exterior boundaries for transparency. Bad input to a constructor
//! is a [`GeometryError`]; kernels never panic and never return NaN for validated input.
//!
//! Optional features: `wide` (default; SIMD lanes), `glam`, `nalgebra`, `mint` (conversions
//! of [`V3`] and [`Ray`], see [`interop`]).
#![deny(missing_docs)]

mod bounds;
mod error;
pub mod interop;
mod kernel;
mod math;
mod primitive;
mod ray;
mod real;
mod vec;

pub use bounds::{Aabb, Obb};
pub use error::GeometryError;
pub use kernel::csg::{self, union, Tagged};
pub use kernel::hermite::{AdaptiveSplit, HermiteSegment};
pub use kernel::link::{HanLink, LinkShape, PendingInterval, RoundCone};
pub use kernel::mesh::{
    tessellate_chain, tessellate_chain_solid, tessellate_link, tessellate_spline, Mesh, Part, MAX_RING,
};
pub use kernel::roots::Solver;
pub use kernel::spline::QuadTube;
pub use kernel::voxel;
pub use primitive::{Primitive, Sphere};
pub use ray::{Crossing, Hit, Interval, Ray};
pub use real::{Mask, Real, Scalar};
#[cfg(feature = "wide")]
pub use real::{WideBoolF32x8, WideBoolF64x4, WideF32x8, WideF64x4};
pub use vec::V3;

/// The faithful pieces of Han et al. 2019 on their own, for comparisons and benchmarks: the
/// tangent cone of two spheres (§3.2.2), the unit-cone transform and the ray–stump slab test
/// (§4.1) with the transform precomputed (Table 1 option d) or built per call (option c), and
/// the textbook cylinder. [`HanLink`] composes them into the round cone.
///
/// ```
/// use tubecast::cone::{intersect_stump_precomputed, TangentCone, UnitConeTransform};
/// use tubecast::{Ray, V3};
/// let cone = TangentCone::new(V3::new(0.0, 0.0, 0.0), 1.0, V3::new(4.0, 0.0, 0.0), 0.5);
/// assert!(cone.is_cone && cone.swapped); // apex behind the smaller sphere
/// let xf = UnitConeTransform::new(&cone);
/// let ray = Ray::new(V3::new(2.0, -10.0, 0.0), V3::new(0.0, 1.0, 0.0));
/// let iv = intersect_stump_precomputed(&ray, &cone, &xf);
/// assert!(iv.hit && iv.entry.u > 0.0 && iv.entry.u < 1.0); // on the cone side
/// ```
pub mod cone {
    pub use crate::kernel::cone::{
        intersect_cylinder_naive, intersect_stump_on_the_fly, intersect_stump_precomputed, TangentCone,
        UnitConeTransform,
    };
}

/// What a renderer imports in one line: the primitives, rays and their answers, the number
/// traits and, with `wide`, the lane types.
///
/// ```
/// use tubecast::prelude::*;
/// let ball = Sphere::new(V3::new(0.0, 0.0, 5.0), 1.0)?;
/// let hit = ball.intersect(&Ray::new(V3::zero(), V3::new(0.0, 0.0, 1.0))).first_hit(0.0, f64::MAX);
/// assert_eq!(hit.map(|h| h.t), Some(4.0));
/// # Ok::<(), GeometryError>(())
/// ```
pub mod prelude {
    pub use crate::{
        union, Aabb, Crossing, GeometryError, HermiteSegment, Hit, Interval, Mask, Primitive, QuadTube, Ray, Real,
        RoundCone, Scalar, Solver, Sphere, Tagged, V3,
    };
    #[cfg(feature = "wide")]
    pub use crate::{WideF32x8, WideF64x4};
}

/// The README's Rust snippet, compiled and run by `cargo test --doc`.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
