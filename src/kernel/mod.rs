//! Pure ray–primitive kernels, generic over [`crate::Real`]: no allocation, no I/O. The
//! crate root re-exports what callers use.
#![deny(missing_docs)]

pub mod csg;
pub mod link;
pub mod sdf;
pub mod sphere;
pub mod voxel;

pub mod hermite;
pub mod mesh;
pub mod obb;
pub mod roots;
pub mod spline;
