//! The spline-tube kernel (quadratic sphere sweeps, Hermite segments split into them), against
//! an independent dense-sampling oracle, with its conditioning, bounding boxes and fuzz findings.

pub mod common;

mod approximate_solvers;
mod conditioning;
mod derivative_roots;
mod extreme_scales;
mod hermite;
mod kernel;
mod obb;
mod regressions;
mod straight_link;
