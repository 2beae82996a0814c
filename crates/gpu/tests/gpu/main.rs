//! GPU tests: every GPU answer compared with the CPU's. Without a Vulkan adapter each test says
//! it skipped, unless `TUBECAST_REQUIRE_GPU=1` (CI sets it), which turns a missing adapter into
//! a failure.

mod constants;
mod kernels;
mod piece;
mod render;
mod tree;

use std::io::Write;
use tubecast_gpu::{Gpu, GpuError};

/// The device, or `None` (with a message) when there is none and none is required.
pub fn gpu(test: &str) -> Option<Gpu> {
    match Gpu::new() {
        Ok(g) => Some(g),
        Err(e @ GpuError::NoAdapter(_)) if std::env::var("TUBECAST_REQUIRE_GPU").map_or(true, |v| v != "1") => {
            // Straight to stderr, past the test harness's capture, so that a passing run shows it.
            let _ = writeln!(std::io::stderr(), "{test}: skipped, {e}");
            None
        }
        Err(e) => panic!("{test}: {e}"),
    }
}
