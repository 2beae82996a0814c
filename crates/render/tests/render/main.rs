//! The renderer, one binary (each file under `tests/` would be a crate of its own to compile
//! and link): depth buffers against direct kernel calls, transparency and alpha, colouring by
//! data, thin tubes, ambient occlusion against exact occlusion, and the camera (view presets,
//! framing, antialiasing) and the legend's contrast.
//!
//! Sizes are fixed by each test; none uses proptest, so `PROPTEST_CASES` changes nothing here.

mod common;

mod alpha;
mod ao_cone;
mod ao_cone_partial;
mod ao_lod_partial;
mod camera_options;
mod color_data;
mod kernels;
mod splines;
mod thin;
