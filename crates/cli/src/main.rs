//! The `tubecast` command line: render, info, intersect, generate.

mod args;
mod cmd_mesh;
mod cmd_simplify;
mod commands;
mod error;

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
enum Cmd {
    /// Render a scene (.swc, .trk, .tck, .obj) to a PNG.
    Render(RenderArgs),
    /// Print counts of nodes, links and primitives, bounds and memory.
    Info(InfoArgs),
    /// Intersect rays (N×6 float64 .npy: origin, direction) with a scene; write N×8 hits.
    ///
    /// Hit columns: t_in, t_out (first component of the union of all tubes along the ray's
    /// line that meets t ≥ 0; t_in < 0 when the ray starts inside), normal at entry (x, y, z),
    /// link index of the entry, curve parameter u at entry, hit flag (1 or 0). Misses:
    /// t_in = t_out = +inf, normal 0, link −1, u 0, flag 0.
    Intersect(IntersectArgs),
    /// Generate a procedural test scene (.swc, .tck, .obj or .trk by extension; neurons: .swc).
    Generate(GenerateArgs),
    /// Tessellate a scene within a certified tolerance; write .ply, .obj or .glb.
    Mesh(MeshArgs),
    /// Merge consecutive links while the merged tube stays within --tolerance; same format out.
    Simplify(SimplifyArgs),
}

fn main() -> ExitCode {
    let r = match Cli::parse().cmd {
        Cmd::Render(a) => commands::render(&a),
        Cmd::Info(a) => commands::info(&a),
        Cmd::Intersect(a) => commands::intersect(&a),
        Cmd::Generate(a) => commands::generate(&a),
        Cmd::Mesh(a) => cmd_mesh::mesh(&a),
        Cmd::Simplify(a) => cmd_simplify::simplify(&a),
    };
    match r {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("tubecast: error: {e}");
            ExitCode::FAILURE
        }
    }
}
