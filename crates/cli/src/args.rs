//! One argument struct per command.

use clap::{Args, ValueEnum};
use std::path::PathBuf;

/// Surface colouring (`--color`).
#[derive(Clone, Debug, PartialEq)]
pub enum Color {
    /// |tangent| as RGB (tractography convention).
    Direction,
    /// Radius through a colour map.
    Radius,
    /// SWC structure type.
    Type,
    /// A data field of the file (`scalar:NAME` or `property:NAME`) through `--colormap`.
    Data(String),
    /// One colour (`solid:#rrggbb`), linear RGB.
    Solid([f32; 3]),
}

/// `direction`, `radius`, `type`, `scalar:NAME` or `property:NAME`.
pub fn parse_color(s: &str) -> Result<Color, String> {
    match s {
        "direction" => Ok(Color::Direction),
        "radius" => Ok(Color::Radius),
        "type" => Ok(Color::Type),
        _ if s.starts_with("solid:") => crate::render_opts::parse_rgb(&s[6..]).map(Color::Solid),
        _ if (s.starts_with("scalar:") || s.starts_with("property:")) && !s.ends_with(':') => Ok(Color::Data(s.into())),
        _ => Err(format!("{s:?}: use direction, radius, type, solid:#rrggbb, scalar:NAME or property:NAME")),
    }
}

/// Minimum pixel footprint for thin tubes (`--thin`).
#[derive(Clone, Copy, ValueEnum)]
pub enum Thin {
    /// On for wireframe-like data (.trk, .tck, .trx, .obj), off for SWC.
    Auto,
    /// Always.
    On,
    /// Never: tubes keep their radii, thinner than a pixel they alias.
    Off,
}

/// Acceleration structure (`--accel`).
#[derive(Clone, Copy, ValueEnum)]
pub enum Accel {
    /// 8-wide bounding volume hierarchy (obvhs CWBVH): the fastest here.
    Bvh,
    /// Binary bounding volume hierarchy (obvhs Bvh2).
    Bvh2,
    /// Uniform voxel grid, conservatively voxelized; its resolution weighs the build against the
    /// command's rays (`accel::grid` docs, "Resolution with a build").
    Grid,
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

/// What `intersect` answers (`--query`).
#[derive(Clone, Copy, ValueEnum)]
pub enum Query {
    /// The closest surface crossing (the renderer's fast path): t, the hit primitive's exit t,
    /// normal x y z, link, u, flag (1 entry, −1 the ray starts inside, 0 miss).
    Hit,
    /// The first solid piece of the CSG union: t_in, t_out, entry normal x y z, link, u, flag.
    Piece,
    /// Every boundary of the union: one row each, ray index, t, normal x y z, link, u,
    /// 1 (entry) or −1 (exit).
    All,
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
    /// Tube radius for formats without radii (.trk, .tck, .trx, OBJ without radius): in the
    /// file's units (0.2), or relative to the scene, e.g. 0.5% of the diagonal of the points'
    /// bounding box (shows tubes whatever the units, nm or mm).
    #[arg(long, value_parser = crate::render_opts::parse_radius, default_value = "0.2")]
    pub radius: crate::render_opts::Radius,
    /// Replace every radius below R (and placeholder radii ≤ 0, which SWC files from the field
    /// often hold) by R; a warning counts them. Without it such a file is refused.
    #[arg(long, value_name = "R")]
    pub min_radius: Option<f64>,
    /// Background: #rrggbb, r,g,b (sRGB in [0, 1]), white, black, grey, or transparent (an RGBA
    /// PNG, alpha 0 where no tube is seen).
    #[arg(long, value_parser = crate::render_opts::parse_background, default_value = "white")]
    pub background: crate::render_opts::Background,
    /// View preset: xy (down −z), xz (along +y), yz (along −x) or iso; fitted to the scene.
    #[arg(long, value_parser = |s: &str| s.parse::<tubecast_render::render::Preset>())]
    pub view: Option<tubecast_render::render::Preset>,
    /// Orthographic projection (parallel rays), framed as the perspective view would be.
    #[arg(long)]
    pub ortho: bool,
    /// Also write the depth (ray parameter of the first surface, inf where none) as an
    /// H×W float64 .npy.
    #[arg(long, value_name = "OUT.npy")]
    pub depth: Option<PathBuf>,
    /// Thin tubes stay visible: tubes thinner than --min-pixels on screen are drawn that wide
    /// and faded toward the background by their true coverage (phone-wire anti-aliasing).
    #[arg(long, value_enum, default_value_t = Thin::Auto)]
    pub thin: Thin,
    /// Minimum on-screen tube diameter in pixels for --thin.
    #[arg(long, default_value_t = 1.0)]
    pub min_pixels: f64,
    /// Overwrite existing output files (refused otherwise).
    #[arg(long)]
    pub force: bool,
    /// Colouring: direction, radius, type, solid:#rrggbb, or a data field of the file through --colormap:
    /// scalar:NAME (TrackVis scalar, TRX dpv, `scalar:tsf` for the .tsf beside a .tck,
    /// `scalar:radius`, `scalar:type`) or property:NAME (TrackVis property, TRX dps).
    #[arg(long, value_parser = parse_color, default_value = "direction")]
    pub color: Color,
    /// Colour map for --color scalar:/property: (viridis, magma, inferno, plasma, cividis,
    /// turbo, greys, rdylbu).
    #[arg(long, value_parser = |s: &str| s.parse::<tubecast_render::render::Colormap>(), default_value = "viridis")]
    pub colormap: tubecast_render::render::Colormap,
    /// Draw a colour bar with the value range at the right edge (with --color scalar:/property:).
    #[arg(long)]
    pub legend: bool,
    /// Surface opacity in (0, 1]; below 1 renders transparent tubes (CSG union).
    #[arg(long, default_value_t = 1.0)]
    pub opacity: f64,
    /// Ambient occlusion: rays (through the accelerator), cone (voxel cone tracing on the
    /// occupancy pyramid), lod (cones on Kanzler's LoD opacities) or off; a number N means N rays.
    #[arg(long, value_parser = crate::ao_opts::parse_ao, default_value = "off")]
    pub ao: crate::ao_opts::Ao,
    /// Rays or cones per pixel for --ao rays|cone|lod.
    #[arg(long, default_value_t = 16, value_name = "N")]
    pub ao_samples: u32,
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
    /// Surface model: the exact kernels, a certified triangle mesh (needs --tolerance), or
    /// Kanzler's quantized lines (--quant-bins, --quant-voxels; the derived error on stderr).
    #[arg(long, value_enum, default_value_t = Surface::Exact)]
    pub model: Surface,
    /// Quantized-lines model.
    #[command(flatten)]
    pub quant: crate::cmd_quantized::QuantArgs,
    /// Tolerance ε (scene units). With `--model mesh`: the mesh's two-sided Hausdorff bound;
    /// with the exact model: pick per segment the cheapest primitive within ε (merged links,
    /// spheres, cylinders, cones, fitted quadratic spline pieces).
    #[arg(long, value_name = "EPS")]
    pub tolerance: Option<f64>,
    /// Like --tolerance, per segment: P pixels of the camera's footprint at its distance.
    #[arg(long, value_name = "P", conflicts_with = "tolerance")]
    pub pixel_error: Option<f64>,
    /// Selection, memory limit, progress.
    #[command(flatten)]
    pub load: crate::cmd_load::LoadArgs,
    /// Acceleration structure.
    #[arg(long, value_enum, default_value_t = Accel::Bvh)]
    pub accel: Accel,
    /// Worker threads (default: one per core).
    #[arg(long, value_parser = clap::value_parser!(u16).range(1..), value_name = "N")]
    pub threads: Option<u16>,
}

/// `render --model`.
#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Surface {
    /// Exact ray–tube kernels.
    Exact,
    /// A triangle mesh within `--tolerance` of the exact surface.
    Mesh,
    /// Kanzler et al.'s quantized lines: per-voxel segments, ends snapped to Q×Q face bins.
    Quantized,
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
    /// Tube radius for formats without radii: absolute, or relative to the scene (0.5%).
    #[arg(long, value_parser = crate::render_opts::parse_radius, default_value = "0.2")]
    pub radius: crate::render_opts::Radius,
    /// Replace every radius below R (and placeholder radii ≤ 0, which SWC files from the field
    /// often hold) by R; a warning counts them. Without it such a file is refused.
    #[arg(long, value_name = "R")]
    pub min_radius: Option<f64>,
    /// Print a JSON object instead of the table.
    #[arg(long)]
    pub json: bool,
    /// Count the primitives of the spline model (as `render --splines` uses them).
    #[arg(long)]
    pub splines: bool,
    /// Also report the automatic primitive choice within ε (counts, worst certified error).
    #[arg(long, value_name = "EPS")]
    pub tolerance: Option<f64>,
    /// The automatic choice within P pixels of the default fitted 800×600 view's footprint.
    #[arg(long, value_name = "P", conflicts_with = "tolerance")]
    pub pixel_error: Option<f64>,
    /// Selection, memory limit, progress.
    #[command(flatten)]
    pub load: crate::cmd_load::LoadArgs,
}

/// `tubecast intersect`.
#[derive(Args)]
pub struct IntersectArgs {
    /// Input scene.
    pub input: PathBuf,
    /// Rays, N×6 float32 or float64 .npy (C or Fortran order); `-` reads stdin.
    #[arg(long)]
    pub rays: PathBuf,
    /// Output hits, N×8: float64 .npy, or CSV (with --csv or a .csv name); `-` writes stdout
    /// (`--query all`: one row per crossing).
    #[arg(long)]
    pub out: PathBuf,
    /// Acceleration structure (the hits are the same).
    #[arg(long, value_enum, default_value_t = Accel::Bvh)]
    pub accel: Accel,
    /// Write the hits as CSV (header t_in,t_out,nx,ny,nz,link,u,hit).
    #[arg(long)]
    pub csv: bool,
    /// What to answer per ray.
    #[arg(long, value_enum, default_value_t = Query::Hit)]
    pub query: Query,
    /// Worker threads (default: one per core).
    #[arg(long, value_parser = clap::value_parser!(u16).range(1..), value_name = "N")]
    pub threads: Option<u16>,
    /// Trace the spline model (as `render --splines` does) instead of the links.
    #[arg(long)]
    pub splines: bool,
    /// Surface model: exact, or quantized lines (link indices then count the quantized scene's links).
    #[arg(long, value_enum, default_value_t = Surface::Exact)]
    pub model: Surface,
    /// Quantized-lines model.
    #[command(flatten)]
    pub quant: crate::cmd_quantized::QuantArgs,
    /// Tube radius for formats without radii.
    #[arg(long, default_value_t = 0.2)]
    pub radius: f64,
    /// Replace every radius below R (and placeholder radii ≤ 0, which SWC files from the field
    /// often hold) by R; a warning counts them. Without it such a file is refused.
    #[arg(long, value_name = "R")]
    pub min_radius: Option<f64>,
    /// Selection, memory limit, progress.
    #[command(flatten)]
    pub load: crate::cmd_load::LoadArgs,
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
