//! The lab's tests, one binary (each file under `tests/` would be a crate of its own to compile
//! and link): every report run at its quick size writes its files, and the numbers read back
//! obey the error analysis they chart; the `tubecast-lab` binary end to end; chart legibility.
//!
//! Sizes are fixed by each test (the reports' `quick` options); none uses proptest, so
//! `PROPTEST_CASES` changes nothing here.

mod common;

mod accuracy;
mod charts;
mod cli;
mod mesh;
mod mesh_real;
mod mesh_size;
mod speed;
mod spline_lanes;
mod stability;
mod thin;
mod voxel;
mod voxel_ao;
