//! `--device gpu` (cargo feature `gpu`): `render`, and `intersect --query hit|piece|all`, with every
//! ray answered by `tubecast-gpu` on a Vulkan adapter over the same 8-wide tree the CPU builds;
//! and the checks `--device gpu` needs, made before any work.

use crate::args::{Accel, Device, IntersectArgs, Query, RenderArgs, Surface, TraceSurface};
use crate::error::CliError;
use tubecast::Ray;
use tubecast_render::render::{Camera, Image, Options};
use tubecast_render::scene::{Model, Scene};

/// Usage error unless this binary was built with the `gpu` feature.
fn built() -> Result<(), CliError> {
    if cfg!(feature = "gpu") {
        return Ok(());
    }
    Err(CliError::usage(
        "--device gpu: this tubecast was built without the GPU; rebuild it with `--features gpu` \
         (e.g. `cargo install --path crates/cli --features gpu`; it needs a Vulkan driver)",
    ))
}

/// What `--device gpu` does not cover: a usage error naming it.
fn unsupported(what: &str) -> CliError {
    CliError::usage(format!("--device gpu: {what} is not on the GPU yet; use --device cpu"))
}

/// `render --device gpu`: exact links or `--splines` (no --model, --tolerance, --pixel-error),
/// the 8-wide tree; opaque or transparent, thin tubes faded or not.
pub fn check_render(a: &RenderArgs) -> Result<(), CliError> {
    if a.device == Device::Cpu {
        return Ok(());
    }
    built()?;
    if a.model != Surface::Exact || a.tolerance.is_some() || a.pixel_error.is_some() {
        return Err(unsupported("a surface model other than the exact kernels (--model, --tolerance, --pixel-error)"));
    }
    if a.accel != Accel::Bvh {
        return Err(unsupported("--accel other than bvh"));
    }
    Ok(())
}

/// `intersect --device gpu`: exact links or `--splines`, the 8-wide tree, any `--query`.
pub fn check_intersect(a: &IntersectArgs) -> Result<(), CliError> {
    if a.device == Device::Cpu {
        return Ok(());
    }
    built()?;
    if a.model != TraceSurface::Exact {
        return Err(unsupported("--model quantized"));
    }
    if a.accel != Accel::Bvh {
        return Err(unsupported("--accel other than bvh"));
    }
    Ok(())
}

#[cfg(feature = "gpu")]
mod run {
    use super::*;
    use tubecast_gpu::{Gpu, GpuError, GpuScene};
    use tubecast_render::accel::{WideBvh, HIT_COLUMNS};

    fn err(e: GpuError) -> CliError {
        CliError::Gpu(e.to_string())
    }

    /// The scene's tree over the primitives of `model` (the CPU's own tree), the device, and
    /// the upload.
    fn with_scene<R>(
        scene: &Scene,
        model: Model,
        f: impl FnOnce(&GpuScene<'_>, &WideBvh) -> Result<R, GpuError>,
    ) -> Result<R, CliError> {
        let bvh = WideBvh::from_scene(scene, model)?;
        let gpu = Gpu::new().map_err(err)?;
        let gs = GpuScene::upload(&gpu, &bvh).map_err(err)?;
        f(&gs, &bvh).map_err(err)
    }

    pub fn render(scene: &Scene, model: Model, cam: &Camera, opts: &Options) -> Result<Image, CliError> {
        with_scene(scene, model, |gs, bvh| tubecast_gpu::render_gpu(gs, scene, bvh, cam, opts))
    }

    pub fn table(
        query: Query,
        scene: &Scene,
        model: Model,
        rays: &[Ray<f64>],
    ) -> Result<Vec<[f64; HIT_COLUMNS]>, CliError> {
        with_scene(scene, model, |gs, bvh| match query {
            Query::Hit => tubecast_gpu::closest_table_gpu(gs, bvh, rays),
            Query::Piece => tubecast_gpu::piece_table_gpu(gs, bvh, rays),
            Query::All => tubecast_gpu::crossings_table_gpu(gs, bvh, rays),
        })
    }
}

/// `render`'s image of the primitives of `model` with every ray answered on the GPU
/// ([`check_render`] passed).
pub fn render(scene: &Scene, model: Model, cam: &Camera, opts: &Options) -> Result<Image, CliError> {
    #[cfg(feature = "gpu")]
    return run::render(scene, model, cam, opts);
    #[cfg(not(feature = "gpu"))]
    {
        let _ = (scene, model, cam, opts);
        built().map(|_| unreachable!("checked before any work"))
    }
}

/// `intersect`'s table (any `--query`) of the primitives of `model` with every ray answered
/// on the GPU ([`check_intersect`] passed).
pub fn table(query: Query, scene: &Scene, model: Model, rays: &[Ray<f64>]) -> Result<Vec<[f64; 8]>, CliError> {
    #[cfg(feature = "gpu")]
    return run::table(query, scene, model, rays);
    #[cfg(not(feature = "gpu"))]
    {
        let _ = (query, scene, model, rays);
        built().map(|_| unreachable!("checked before any work"))
    }
}
