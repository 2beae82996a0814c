//! One argument struct per command.

use clap::{Args, ValueEnum};
use std::path::PathBuf;

/// Surface colouring (`--color`).
#[derive(Clone, Copy, ValueEnum)]
pub enum Color {
    /// |tangent| as RGB (tractography convention).
    Direction,
    /// Radius through a colour map.
    Radius,
    /// SWC structure type.
    Type,
}

/// A procedural scene (`generate`).
#[derive(Clone, Copy, ValueEnum)]
pub enum Kind {
    /// Russig's Bundle (1250 twisting fibres).
    Bundle,
    /// Russig's Furball (10,000 hairs).
    Furball,
    /// Han's neuron assembly (N³ neurons).
    Neurons,
    /// A double helix with varying radius.
    Helix,
}

/// `tubecast render`.
#[derive(Args)]
pub struct RenderArgs {
    /// Input file.
    pub input: PathBuf,
    /// Output PNG.
    #[arg(short, long)]
    pub out: PathBuf,
    /// Image width in pixels.
    #[arg(long, default_value_t = 800)]
    pub width: u32,
    /// Image height in pixels.
    #[arg(long, default_value_t = 600)]
    pub height: u32,
    /// Tube radius for formats without radii (.trk, .tck, OBJ without radius).
    #[arg(long, default_value_t = 0.2)]
    pub radius: f64,
    /// Replace every radius below R (and placeholder radii ≤ 0, which SWC files from the field
    /// often hold) by R; a warning counts them. Without it such a file is refused.
    #[arg(long, value_name = "R")]
    pub min_radius: Option<f64>,
    /// Colouring.
    #[arg(long, value_enum, default_value_t = Color::Direction)]
    pub color: Color,
    /// Surface opacity in (0, 1]; below 1 renders transparent tubes (CSG union).
    #[arg(long, default_value_t = 1.0)]
    pub opacity: f64,
    /// Ambient-occlusion rays per pixel.
    #[arg(long, default_value_t = 0)]
    pub ao: u32,
    /// Trace shadow rays.
    #[arg(long)]
    pub shadows: bool,
    /// Camera position x,y,z (default: fitted to the scene).
    #[arg(long, value_parser = parse_v3)]
    pub eye: Option<[f64; 3]>,
    /// Point the camera looks at x,y,z (default: scene centre).
    #[arg(long, value_parser = parse_v3)]
    pub look_at: Option<[f64; 3]>,
    /// Camera up direction x,y,z.
    #[arg(long, value_parser = parse_v3, default_value = "0,1,0")]
    pub up: [f64; 3],
    /// Vertical field of view in degrees.
    #[arg(long, default_value_t = 40.0)]
    pub fov: f64,
    /// Render the chains of links as C¹ cubic Hermite spline tubes (Catmull–Rom
    /// derivatives; each branch between bifurcations is its own spline; straight runs
    /// stay links).
    #[arg(long)]
    pub splines: bool,
    /// Hide the progress bar.
    #[arg(long)]
    pub quiet: bool,
}

/// `tubecast info`.
#[derive(Args)]
pub struct InfoArgs {
    /// Input file.
    pub input: PathBuf,
    /// Tube radius for formats without radii.
    #[arg(long, default_value_t = 0.2)]
    pub radius: f64,
    /// Replace every radius below R (and placeholder radii ≤ 0, which SWC files from the field
    /// often hold) by R; a warning counts them. Without it such a file is refused.
    #[arg(long, value_name = "R")]
    pub min_radius: Option<f64>,
    /// Count the primitives of the spline model (as `render --splines` uses them).
    #[arg(long)]
    pub splines: bool,
}

/// `tubecast intersect`.
#[derive(Args)]
pub struct IntersectArgs {
    /// Input scene.
    pub input: PathBuf,
    /// Rays, N×6 float64 .npy.
    #[arg(long)]
    pub rays: PathBuf,
    /// Output hits, N×8 float64 .npy.
    #[arg(long)]
    pub out: PathBuf,
    /// Trace the spline model (as `render --splines` does) instead of the links.
    #[arg(long)]
    pub splines: bool,
    /// Tube radius for formats without radii.
    #[arg(long, default_value_t = 0.2)]
    pub radius: f64,
    /// Replace every radius below R (and placeholder radii ≤ 0, which SWC files from the field
    /// often hold) by R; a warning counts them. Without it such a file is refused.
    #[arg(long, value_name = "R")]
    pub min_radius: Option<f64>,
}

/// `tubecast generate`.
#[derive(Args)]
pub struct GenerateArgs {
    /// Which scene.
    #[arg(value_enum)]
    pub kind: Kind,
    /// Output file.
    #[arg(short, long)]
    pub out: PathBuf,
    /// Number of tubes (bundle: 1250, furball: 10000 by default).
    #[arg(long)]
    pub count: Option<usize>,
    /// Segments per tube (bundle: 84, furball: 78, helix: 200 by default).
    #[arg(long)]
    pub segments: Option<usize>,
    /// Neurons per box side (the assembly has N³ neurons).
    #[arg(long, default_value_t = 3)]
    pub n: usize,
    /// Base neuron(s) for the assembly (SWC); default: a procedural neuron.
    #[arg(long)]
    pub base: Vec<PathBuf>,
    /// Random seed.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
}

fn parse_v3(s: &str) -> Result<[f64; 3], String> {
    let v: Vec<f64> = s
        .split(',')
        .map(|t| t.trim().parse::<f64>().map_err(|_| format!("{t:?} is not a number")))
        .collect::<Result<_, _>>()?;
    if v.len() != 3 || v.iter().any(|x| !x.is_finite()) {
        return Err(format!("expected three finite numbers x,y,z, got {s:?}"));
    }
    Ok([v[0], v[1], v[2]])
}
