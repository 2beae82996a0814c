//! `tubecast intersect --query hit|piece|all`: the scene's accelerator, the rays, and the
//! table the query asks for.

use crate::args::{Device, IntersectArgs, Query, Surface};
use crate::error::CliError;
use crate::hits_io::{write_hits, HitsOut, CROSSING_COLUMNS, HIT_COLUMNS};
use crate::setup::{self, Plan};
use tubecast_render::accel::{closest_rows, crossings_table, hit_rows, MISS_ROW};
use tubecast_render::io;

/// Rays per chunk of the streamed table: enough to keep every thread busy, few enough that
/// the rows in flight stay small (2 MB).
const CHUNK: usize = 1 << 15;

/// `tubecast intersect`.
pub fn intersect(a: &IntersectArgs) -> Result<(), CliError> {
    crate::options::intersect(a)?;
    // The rays first: their count sets the grid's resolution, which the memory estimate needs.
    let name = a.rays.display().to_string();
    let rays = io::npy::read(&crate::hits_io::read_input(&a.rays)?, &name, Some(6))?;
    rays.check_rays(&name)?;
    let m = setup::model(a.splines);
    let plan = Plan { model: m, accel: a.accel, render: None, rays: Some(rays.rows as f64) };
    let scene = setup::load(&a.input, &a.radius, (&a.select, &a.run), plan, "every ray misses", false)?.scene;
    let scene = crate::quantized::model_scene(Surface::from(a.model), scene, &a.quant, a.run.quiet)?;
    if a.device == Device::Gpu {
        let rows = crate::gpu::table(a.query, &scene, m, &rays.rays(&name)?)?;
        let columns = if matches!(a.query, Query::All) { &CROSSING_COLUMNS } else { &HIT_COLUMNS };
        return write_hits(&a.out, &rows, a.csv, columns);
    }
    setup::with_threads(a.run.threads, || {
        let bvh = setup::scene_tracer(a.accel, &scene, m, None, Some(rays.rows as f64))?;
        let fill = match a.query {
            Query::Hit => closest_rows,
            Query::Piece => hit_rows,
            Query::All => {
                let rows = crossings_table(bvh.as_ref(), &rays.rays(&name)?);
                return write_hits(&a.out, &rows, a.csv, &CROSSING_COLUMNS);
            }
        };
        // One row per ray: stream the table chunk by chunk instead of holding it (and its
        // bytes) whole; fresh pages for a table of 10⁶ rows cost more system time than the
        // tracing takes.
        let mut out = HitsOut::create(&a.out, a.csv, rays.rows, &HIT_COLUMNS)?;
        let mut rows = vec![MISS_ROW; CHUNK.min(rays.rows)];
        let mut chunk = Vec::with_capacity(CHUNK.min(rays.rows));
        for start in (0..rays.rows).step_by(CHUNK) {
            chunk.clear();
            chunk.extend((start..(start + CHUNK).min(rays.rows)).map(|i| rays.ray(i)));
            let rows = &mut rows[..chunk.len()];
            fill(bvh.as_ref(), &chunk, rows);
            out.write(rows)?;
        }
        out.finish()
    })?
}
