//! Methods kept only to be measured against: the published formulations the kernels replace,
//! for the tests, benchmarks and reports that compare them. Nothing in a renderer should call
//! them; use the crate root's kernels instead.
//!
//! | baseline | what it is | the kernel to call | compared in |
//! |---|---|---|---|
//! | [`HanLink`], [`RoundCone::intersect_han_on_the_fly`](crate::RoundCone::intersect_han_on_the_fly) | Han et al. 2019's round cone: apex, unit-cone transform, slab (their Table 1 options d and c) | [`RoundCone`](crate::RoundCone) (stable, no apex) | `docs/design/stable-link.md`, the stability report |
//! | [`cone`] | its pieces: the tangent cone, the transform, the stump and the textbook cylinder | — | `benches/kernels.rs` |
//! | [`voxel`] | bounding-box fill, DDA along the axis, Kraaijeveld's Eq. 1 radius | [`crate::voxel::voxelize_round_cone`] (conservative) | `docs/design/voxelization.md`, `tests/kernels/voxel/conservative.rs` |
//!
//! ```
//! use tubecast::baseline::HanLink;
//! use tubecast::{Primitive, Ray, RoundCone, V3};
//! let link = RoundCone::new(V3::new(0.0f64, 0.0, 0.0), 1.0, V3::new(4.0, 0.0, 0.0), 0.5)?;
//! let ray = Ray::new(V3::new(2.0, -10.0, 0.0), V3::new(0.0, 1.0, 0.0));
//! // Both hit the cone side; far from the cases where the apex costs Han's form its digits.
//! let (stable, han) = (link.intersect(&ray), HanLink::new(&link).intersect(&ray));
//! assert!(stable.hit && han.hit && stable.entry.u > 0.0 && han.entry.u > 0.0);
//! # Ok::<(), tubecast::GeometryError>(())
//! ```

pub mod cone;
mod link;
pub mod voxel;

pub use link::HanLink;
