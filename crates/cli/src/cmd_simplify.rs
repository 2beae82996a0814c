//! `tubecast simplify`: merge consecutive links within a tolerance and write the same format.
//! The file formats hold nodes only, so quadratic spline pieces cannot be written; the command
//! prints what the automatic choice (`render`/`info --tolerance`) makes of the input at the
//! same tolerance, links only and with quadratic spline fits.

use crate::args::SimplifyArgs;
use crate::error::CliError;
use tubecast_render::io::{self, IoError};
use tubecast_render::scene::choice::{choose, choose_with, Tolerance};
use tubecast_render::scene::simplify::{simplify_polyline, simplify_swc};
use tubecast_render::scene::Scene;

/// The counts of the automatic choice on `scene` at `eps`, links only and with splines.
fn print_choice(scene: &Scene, eps: f64) {
    let t = Tolerance::Absolute(eps);
    let (l, s) = (choose(scene, &t), choose_with(scene, &t, true));
    println!(
        "choice at {eps:e}: {} links → {} primitives with links only (worst {:e}); {} with quadratic splines: \
         {} spline pieces, {} links merged, {} fitted (worst {:e}; render/info --tolerance only, not written)",
        scene.links.len(),
        l.prims.len(),
        l.worst,
        s.prims.len(),
        s.splines,
        s.merged,
        s.fitted,
        s.worst
    );
}

pub fn simplify(a: &SimplifyArgs) -> Result<(), CliError> {
    if !(a.io.tolerance.is_finite() && a.io.tolerance >= 0.0) {
        return Err(CliError::Tolerance(a.io.tolerance));
    }
    let name = a.io.input.display().to_string();
    let ext = |p: &std::path::Path| p.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
    let (kind, out_kind) = (ext(&a.io.input), ext(&a.io.out));
    if kind != out_kind {
        return Err(
            IoError::file(&a.io.out.display().to_string(), format!("must have the input's extension .{kind}")).into()
        );
    }
    let data = io::read_bytes(&a.io.input)?;
    let (before, after, d, scene) = match kind.as_str() {
        "swc" => {
            let rows = io::swc::read(&data, &name)?;
            let (out, d) = simplify_swc(&rows, a.io.tolerance);
            io::write_bytes(&a.io.out, io::swc::write(&out).as_bytes())?;
            (rows.len(), out.len(), d, Scene::from_swc(&rows, &name).ok())
        }
        "trk" | "tck" | "obj" => {
            let (header, lines) = match kind.as_str() {
                "trk" => {
                    let (h, l) = io::trk::read(&data, &name)?;
                    (Some(h), l)
                }
                "tck" => (None, io::tck::read(&data, &name)?),
                _ => (None, io::obj::read(&data, &name)?),
            };
            let done: Vec<_> = lines.iter().map(|l| simplify_polyline(l, a.io.radius, a.io.tolerance)).collect();
            let d = done.iter().map(|x| x.1).fold(0.0, f64::max);
            let out: Vec<_> = done.into_iter().map(|x| x.0).collect();
            match header {
                Some(h) => io::write_bytes(&a.io.out, &io::trk::write(&h, &out, false))?,
                None => io::write_polylines(&a.io.out, &out)?,
            }
            let count = |ls: &[io::Polyline]| ls.iter().map(|l| l.points.len()).sum::<usize>();
            (count(&lines), count(&out), d, Scene::from_polylines(&lines, a.io.radius, &name).ok())
        }
        _ => return Err(IoError::file(&name, "simplify reads .swc, .trk, .tck or .obj").into()),
    };
    println!(
        "{}: {after} of {before} nodes kept, largest merge bound {d:e} (tolerance {:e})",
        a.io.out.display(),
        a.io.tolerance
    );
    if let Some(scene) = scene {
        print_choice(&scene, a.io.tolerance);
    }
    Ok(())
}
