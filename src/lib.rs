//! # tubecast
//!
//! Exact, fast, verified ray–tube intersection kernels: spheres, round-cone links in a
//! numerically stable formulation, sphere-swept quadratic spline tubes, and CSG union of
//! intervals for correct transparency (Han et al. 2019's faithful link, which the stable one
//! replaces, is kept for comparison in [`baseline`]). Every kernel is a pure function written once against [`Real`] and
//! instantiated for `f32`, `f64` and SIMD lanes ([`WideF32x8`], [`WideF64x4`], feature `wide`).
//!
//! ```
//! use tubecast::{union, Primitive, QuadTube, Ray, RoundCone, Sphere, Tagged, V3};
//! // One ray along z through a ball, a link overlapping it and a bent spline tube.
//! let ray = Ray::new(V3::new(0.0, 0.0, -5.0), V3::new(0.0, 0.0, 1.0));
//! let ball = Sphere::new(V3::new(0.0, 0.0, 0.0), 1.0)?;
//! let link = RoundCone::new(V3::new(0.0, 0.0, 0.5), 1.0, V3::new(0.0, 0.0, 4.0), 0.5)?;
//! let tube = QuadTube::new([V3::new(-1.0, 0.0, 8.0), V3::new(0.0, 0.0, 9.0), V3::new(1.0, 0.0, 8.0)], [0.25; 3])?;
//! let iv = ball.intersect(&ray); // entry and exit crossings: t, unit normal, curve parameter
//! assert_eq!((iv.entry.t, iv.exit.t, iv.entry.n), (4.0, 6.0, V3::new(0.0, 0.0, -1.0)));
//! let lines = [ball.line_interval(&ray), link.line_interval(&ray), tube.line_interval(&ray)];
//! let mut tagged: Vec<_> = lines.into_iter().zip(0..).map(|(iv, id)| Tagged { iv, id }).collect();
//! let mut surfaces = Vec::new(); // the union's boundaries: what a transparent renderer shades
//! union(&mut tagged, ray.t_min, ray.t_max, |h| surfaces.push((h.id, h.entering, h.t)));
//! // Ball ∪ link is one solid from t = 4 to 9.5; the tube crosses the ray at z = 8.25 … 8.75.
//! assert_eq!(surfaces, [(0, true, 4.0), (1, false, 9.5), (2, true, 13.25), (2, false, 13.75)]);
//! # Ok::<(), tubecast::GeometryError>(())
//! ```
//!
//! Every primitive ([`Sphere`], [`RoundCone`], [`QuadTube`], and the baseline
//! [`baseline::HanLink`]) implements [`Primitive`]: the interval of the ray's whole line with
//! the solid ([`Interval`]: entry and exit `t`, unit outward normals, the curve parameter
//! `u`), the same clipped to the ray's range `[t_min, t_max]`, an [`Aabb`] and the exact
//! signed distance. [`csg::union`] merges line intervals into the exterior boundaries for
//! transparency. Cubic Hermite segments ([`HermiteSegment`]) split into quadratic tubes; the
//! spline kernel's error is bounded by [`spline_error_band`]. Bad input to a constructor is a
//! [`GeometryError`]; kernels never panic and never return NaN for validated input.
//!
//! Optional features: `wide` (default; SIMD lanes), `glam`, `nalgebra`, `mint` (conversions
//! of [`V3`] and [`Ray`], see [`interop`]).
#![deny(missing_docs)]

pub mod baseline;
mod bounds;
mod error;
pub mod interop;
mod kernel;
mod math;
mod primitive;
mod ray;
mod real;
mod vec;

pub use bounds::{spline_error_band, Aabb, Obb};
pub use error::GeometryError;
pub use kernel::csg::{self, union, Tagged};
pub use kernel::hermite::{AdaptiveSplit, HermiteEnd, HermiteSegment};
pub use kernel::link::{LinkShape, PendingInterval, RoundCone};
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
        union, Aabb, Crossing, GeometryError, HermiteEnd, HermiteSegment, Hit, Interval, Mask, Primitive, QuadTube,
        Ray, Real, RoundCone, Scalar, Solver, Sphere, Tagged, V3,
    };
    #[cfg(feature = "wide")]
    pub use crate::{WideF32x8, WideF64x4};
}

/// The README's Rust snippet, compiled and run by `cargo test --doc`.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
