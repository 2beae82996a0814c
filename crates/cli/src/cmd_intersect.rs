//! `tubecast intersect --query hit|piece|all`: the scene's accelerator, the rays, and the
//! table the query asks for.

use crate::args::{Device, IntersectArgs, Query, Surface};
use crate::error::CliError;
use crate::setup::{self, Plan};
use tubecast_render::accel::{closest_table, crossings_table, hit_table};
use tubecast_render::io::{self, npy::Array2};

/// `tubecast intersect`.
pub fn intersect(a: &IntersectArgs) -> Result<(), CliError> {
    crate::options::intersect(a)?;
    // The rays first: their count sets the grid's resolution, which the memory estimate needs.
    let name = a.rays.display().to_string();
    let rays = io::npy::read(&crate::hits_io::read_input(&a.rays)?, &name, Some(6))?.rays(&name)?;
    let m = setup::model(a.splines);
    let plan = Plan { model: m, accel: a.accel, render: None, rays: Some(rays.len() as f64) };
    let scene = setup::load(&a.input, &a.radius, (&a.select, &a.run), plan, "every ray misses", false)?.scene;
    let scene = crate::quantized::model_scene(Surface::from(a.model), scene, &a.quant, a.run.quiet)?;
    if a.device == Device::Gpu {
        let rows = crate::gpu::table(a.query, &scene, &rays)?;
        return crate::hits_io::write_hits(&a.out, &Array2::from_rows(&rows), a.csv);
    }
    let rows = setup::with_threads(a.run.threads, || {
        let bvh = setup::scene_tracer(a.accel, &scene, m, None, Some(rays.len() as f64))?;
        Ok::<_, CliError>(match a.query {
            Query::Hit => closest_table(bvh.as_ref(), &rays),
            Query::Piece => hit_table(bvh.as_ref(), &rays),
            Query::All => crossings_table(bvh.as_ref(), &rays),
        })
    })??;
    crate::hits_io::write_hits(&a.out, &Array2::from_rows(&rows), a.csv)
}
