//! `tubecast intersect --query hit|piece|all` and the `--threads N` pool that it and `render`
//! run in.

use crate::args::{IntersectArgs, Query};
use crate::error::CliError;
use tubecast_render::accel::{closest_table, crossings_table, hit_table};
use tubecast_render::io::{self, npy::Array2};

/// Run `f` on a rayon pool of `threads` threads (`None`: one per core, rayon's default).
pub fn with_threads<R: Send>(threads: Option<usize>, f: impl FnOnce() -> R + Send) -> Result<R, CliError> {
    match threads {
        None => Ok(f()),
        Some(n) => Ok(rayon::ThreadPoolBuilder::new().num_threads(n).build().map_err(CliError::Threads)?.install(f)),
    }
}

/// `tubecast intersect`: the scene's BVH, the rays, and the table the query asks for.
pub fn intersect(a: &IntersectArgs) -> Result<(), CliError> {
    // The rays first: their count sets the grid's resolution, which the memory estimate needs.
    let name = a.rays.display().to_string();
    let rays = io::npy::read(&crate::hits_io::read_input(&a.rays)?, &name, Some(6))?.rays(&name)?;
    let (model, accel) = (crate::commands::model(a.splines), a.accel);
    let plan = crate::cmd_load::Plan { model, accel, render: None, rays: Some(rays.len() as f64) };
    let radius = (crate::render_opts::Radius::Absolute(a.radius), a.min_radius);
    let scene = crate::commands::load(&a.input, radius, &a.load, plan, "every ray misses", None)?;
    if a.model == crate::args::Surface::Mesh {
        return Err(crate::cmd_quantized::QuantError::MeshIntersect.into());
    }
    let scene = crate::cmd_quantized::model_scene(a.model, scene, &a.quant, a.load.quiet)?;
    let rows = with_threads(a.threads.map(usize::from), || {
        let m = crate::commands::model(a.splines);
        let bvh = crate::commands::scene_tracer(a.accel, &scene, m, None, Some(rays.len() as f64))?;
        Ok::<_, CliError>(match a.query {
            Query::Hit => closest_table(bvh.as_ref(), &rays),
            Query::Piece => hit_table(bvh.as_ref(), &rays),
            Query::All => crossings_table(bvh.as_ref(), &rays),
        })
    })??;
    crate::hits_io::write_hits(&a.out, &Array2::from_rows(&rows), a.csv)
}
