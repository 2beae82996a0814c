//! The `tubecast` binary end to end, in one test binary (each file directly in `tests/` would
//! be a crate of its own to compile and link), one module per subject.

mod common;

mod accel;
mod ao;
mod color_data;
mod commands;
mod defaults;
mod field_files;
mod info;
mod intersect_splines;
mod memory;
mod memory_render;
mod mesh;
mod pipes;
mod quantized;
mod query;
mod rays_io;
mod render_options;
mod simplify_stream;
mod splines;
mod usage;
