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
    /// Surface model: the exact kernels, or a certified triangle mesh (needs --tolerance).
    #[arg(long, value_enum, default_value_t = Surface::Exact)]
    pub model: Surface,
    /// Tolerance ε (scene units). With `--model mesh`: the mesh's two-sided Hausdorff bound;
    /// with the exact model: pick per segment the cheapest primitive within ε (merged links,
    /// spheres, cylinders, cones).
    #[arg(long, value_name = "EPS")]
    pub tolerance: Option<f64>,
    /// Like --tolerance, per segment: P pixels of the camera's footprint at its distance.
    #[arg(long, value_name = "P", conflicts_with = "tolerance")]
    pub pixel_error: Option<f64>,
    /// Hide the progress bar.
    #[arg(long)]
    pub quiet: bool,
}

/// `render --model`.
#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Surface {
    /// Exact ray–tube kernels.
    Exact,
    /// A triangle mesh within `--tolerance` of the exact surface.
    Mesh,
}

/// Input, output, tolerance and default radius of `mesh` and `simplify`.
#[derive(Args)]
pub struct TolIo {
    /// Input file (.swc, .trk, .tck, .obj).
    pub input: PathBuf,
    /// Output file: `mesh` .ply (binary), .obj or .glb; `simplify` the input's format.
    #[arg(short, long)]
    pub out: PathBuf,
    /// Tolerance ε (scene units): the two-sided Hausdorff bound between the output and the
    /// exact tubes of the input.
    #[arg(long, value_name = "EPS")]
    pub tolerance: f64,
    /// Tube radius for formats without radii.
    #[arg(long, default_value_t = 0.2)]
    pub radius: f64,
}

/// `tubecast mesh`.
#[derive(Args)]
pub struct MeshArgs {
    #[command(flatten)]
    pub io: TolIo,
    /// Replace every radius below R (and placeholder radii ≤ 0) by R.
    #[arg(long, value_name = "R")]
    pub min_radius: Option<f64>,
    /// Mesh the C¹ spline tubes of the chains instead of the links.
    #[arg(long)]
    pub splines: bool,
}

/// `tubecast simplify`.
#[derive(Args)]
pub struct SimplifyArgs {
    #[command(flatten)]
    pub io: TolIo,
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
    /// Also report the automatic primitive choice within ε (counts, worst certified error).
    #[arg(long, value_name = "EPS")]
    pub tolerance: Option<f64>,
    /// The automatic choice within P pixels of the default fitted 800×600 view's footprint.
    #[arg(long, value_name = "P", conflicts_with = "tolerance")]
    pub pixel_error: Option<f64>,
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
