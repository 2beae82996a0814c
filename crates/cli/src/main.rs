//! The `tubecast` command line: render, info, intersect, generate.

mod ao_opts;
mod args;
mod cmd_intersect;
mod cmd_load;
mod cmd_mesh;
mod cmd_quantized;
mod cmd_simplify;
mod commands;
mod error;
mod hits_io;
mod progress;
mod render_opts;

use args::{GenerateArgs, InfoArgs, IntersectArgs, MeshArgs, RenderArgs, SimplifyArgs};
use clap::{Parser, Subcommand};
use std::process::ExitCode;

#[derive(Parser)]
#[command(name = "tubecast", version, about = "Exact ray–tube intersection and a minimal tube renderer")]
struct Cli {
    #[command(subcommand)]
    cmd: Cmd,
}

#[derive(Subcommand)]
// Parsed once per process: the size of the largest variant costs nothing worth a Box.
#[allow(clippy::large_enum_variant)]
enum Cmd {
    /// Render a scene (.swc, .trk, .tck, .trx, .obj) to a PNG.
    Render(RenderArgs),
    /// Print counts of nodes, links and primitives, bounds and memory.
    Info(InfoArgs),
    /// Intersect rays (N×6 float32/float64 .npy, C or Fortran order: origin, direction; `-`:
    /// stdin) with a scene; write N×8 hits (.npy, or CSV with --csv or a .csv name; `-`: stdout).
    ///
    /// `--query hit` (default), the closest crossing: t, exit t of the hit primitive, normal
    /// (x, y, z), link, u, flag (1 entry, −1 the ray starts inside). `--query piece`, the first
    /// component of the union of all tubes along the line that meets t ≥ 0: t_in (< 0 when the
    /// ray starts inside), t_out, entry normal, link, u, 1. Misses (both): t = +inf, +inf,
    /// normal 0, link −1, u 0, flag 0. `--query all`: one row per union boundary: ray index,
    /// t, normal, link, u, 1 entry / −1 exit.
    Intersect(IntersectArgs),
    /// Generate a procedural test scene (.swc, .tck, .obj or .trk by extension; neurons: .swc).
    Generate(GenerateArgs),
    /// Tessellate a scene within a certified tolerance; write .ply, .obj or .glb.
    Mesh(MeshArgs),
    /// Merge consecutive links while the merged tube stays within --tolerance; same format out.
    ///
    /// Writes merged links only, each certified within ε of the links it replaces (both ways).
    /// SWC, TRK, TCK and OBJ hold nodes, not quadratic pieces, so the spline fitting of the
    /// automatic choice is not written: it applies where the model stays in memory
    /// (`render`/`info --tolerance`), and this command prints its counts at the same ε.
    Simplify(SimplifyArgs),
}

fn main() -> ExitCode {
    let r = match Cli::parse().cmd {
        Cmd::Render(a) => commands::render(&a),
        Cmd::Info(a) => commands::info(&a),
        Cmd::Intersect(a) => cmd_intersect::intersect(&a),
        Cmd::Generate(a) => commands::generate(&a),
        Cmd::Mesh(a) => cmd_mesh::mesh(&a),
        Cmd::Simplify(a) => cmd_simplify::simplify(&a),
    };
    progress::report_peak(None);
    match r {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("tubecast: error: {e}");
            ExitCode::FAILURE
        }
    }
}
