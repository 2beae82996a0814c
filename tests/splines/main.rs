//! The spline-tube kernel (quadratic sphere sweeps, Hermite segments split into them), against
//! an independent dense-sampling oracle, with its conditioning, bounding boxes and fuzz findings.
//! Expected values come from the oracle (`tubecast-oracle`) or are derived by hand beside each
//! test.
//!
//! Property runs are sized by proptest's `PROPTEST_CASES`: unset, each property runs the small
//! default passed to `common::config`, so `cargo test` stays fast; `PROPTEST_CASES=100000 cargo
//! test --release -p tubecast --test splines` is the long run.

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
