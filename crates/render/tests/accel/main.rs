//! The accelerators, one binary (each file under `tests/` would be a crate of its own to
//! compile and link): the voxel grid, its occupancy pyramid and quantized lines against the BVH
//! and brute force, the wide tree on extreme scenes, and the mesh tracer against the exact
//! kernels.
//!
//! Sizes are fixed by each test; none uses proptest, so `PROPTEST_CASES` changes nothing here.

mod grid_degenerate;
mod grid_equivalence;
mod grid_levels;
mod grid_pyramid;
mod grid_pyramid_parallel;
mod grid_quantized_lines;
mod grid_quantized_lod;
mod grid_resolution;
mod long_link;
mod mesh_tracer;
