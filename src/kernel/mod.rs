//! Pure ray–primitive kernels, generic over [`crate::Real`]: no allocation, no I/O.
#![deny(missing_docs)]

pub mod cone;
pub mod csg;
pub mod link;
pub mod sdf;
pub mod sphere;

pub use cone::{TangentCone, UnitConeTransform};
pub use link::{HanLink, LinkShape, RoundCone};
pub use sphere::intersect_sphere;
pub mod hermite;
pub mod obb;
pub mod roots;
pub mod spline;
pub use hermite::HermiteSegment;
pub use obb::Obb;
pub use roots::Solver;
pub use spline::QuadTube;
