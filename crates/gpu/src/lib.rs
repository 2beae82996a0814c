//! tubecast on the GPU: the stable round-cone link and sphere kernels in WGSL, and the wide BVH
//! the CPU builds ([`tubecast_render::accel::WideBvh`]) uploaded as it is and walked in WGSL,
//! through wgpu on any Vulkan adapter (Mesa's lavapipe included, which is how CI tests it).
//!
//! Nothing else in the workspace depends on this crate: a user who never asks for the GPU never
//! builds wgpu. Without a Vulkan driver, [`Gpu::new`] returns [`GpuError::NoAdapter`], naming
//! what to install.

#![deny(missing_docs)]

mod compute;
mod device;
pub mod kernel;
mod render;
pub mod scene;

pub use device::{Gpu, GpuError};
pub use render::{closest_table_gpu, crossings_table_gpu, piece_table_gpu, render_gpu};
pub use scene::{GpuScene, Piece, Walk};
