//! The round-cone link kernels (stable and Han's), against the independent sphere-sweep
//! oracle and on the inputs where floating point is hardest.

mod extreme_scales;
mod far_from_world;
mod properties;
mod regressions;
