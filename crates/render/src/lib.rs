//! # tubecast-render
//!
//! Everything between files and pixels, built on the [`tubecast`] kernels: readers and
//! writers for SWC, TrackVis `.trk`, MRtrix `.tck`, OBJ polylines and `.npy` ([`io`]); scenes
//! of links and spline tubes with per-segment primitive choice ([`scene`]); a BVH with
//! closest-hit, any-hit and all-intervals queries ([`accel`]); and a CPU renderer with opaque
//! and CSG-correct transparent compositing ([`render`]).
#![deny(missing_docs)]

pub mod accel;
pub mod io;
pub mod render;
pub mod scene;
