//! The command line as clap reads it: one struct per command, built from shared groups so
//! that every command spells the same thing the same way (the input positional, `-o/--out`
//! and `--force` for every file written, `-j/--threads`, `-q/--quiet`, `--json` where a
//! command reports, `--radius` and `--model`). Values are range-checked as they are parsed
//! ([`crate::values`]); what needs several flags or the file system is checked in
//! [`crate::options`], still before any work.

use crate::values::{self, Ao, Background, Color, Radius};
use clap::{Args, Parser, Subcommand, ValueEnum};
use std::path::PathBuf;
use tubecast_render::render::{Colormap, Preset};

/// `tubecast`.
#[derive(Parser)]
#[command(name = "tubecast", version, about = "Exact ray–tube intersection and a minimal tube renderer")]
pub struct Cli {
    /// The command.
    #[command(subcommand)]
    pub cmd: Cmd,
}

/// The commands.
#[derive(Subcommand)]
// Parsed once per process: the size of the largest variant costs nothing worth a Box.
#[allow(clippy::large_enum_variant)]
pub enum Cmd {
    /// Render a scene (.swc, .trk, .tck, .trx, .obj) to a PNG.
    Render(RenderArgs),
    /// Print what a scene holds: streamlines, points, links, bounds, voxel size and space, data
    /// fields with their ranges, the model the renderer would use and its certified error.
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
    /// Generate a procedural test scene (.swc, .obj, .tck or .trk by extension; neurons: .swc).
    /// .swc and .obj keep the radii; .tck and .trk cannot hold them (a warning says so).
    Generate(GenerateArgs),
    /// Tessellate a scene within a certified tolerance; write .ply, .obj or .glb.
    Mesh(MeshArgs),
    /// Merge consecutive links while the merged tube stays within --tolerance; write the
    /// input's format (.swc, .trk, .tck or .obj).
    ///
    /// Writes merged links only, each certified within ε of the links it replaces (both ways).
    /// SWC, TRK, TCK and OBJ hold nodes, not quadratic pieces, so the spline fitting of the
    /// automatic choice is not written: it applies where the model stays in memory
    /// (`render`/`info --tolerance`), and this command prints its counts at the same ε.
    Simplify(SimplifyArgs),
}

/// Threads and what a command says on stderr: every command has them.
#[derive(Args, Clone, Copy, Debug, Default)]
pub struct RunArgs {
    /// Worker threads (default: one per core).
    #[arg(short = 'j', long, value_parser = clap::value_parser!(u16).range(1..), value_name = "N")]
    pub threads: Option<u16>,
    /// No progress bars and no summaries on stderr (warnings and errors still print).
    #[arg(short, long)]
    pub quiet: bool,
    /// Show the progress bars even where stderr is not a terminal.
    #[arg(long)]
    pub progress: bool,
}

/// The tube radius where the file has none, and the floor under the radii it has.
#[derive(Args, Clone, Copy, Debug)]
pub struct RadiusArgs {
    /// Tube radius for formats without radii (.trk, .tck, .trx, OBJ without radius): in the
    /// file's units (0.2), or relative to the scene, e.g. 0.5% of the diagonal of the points'
    /// bounding box (shows tubes whatever the units, nm or mm); at most 100%.
    #[arg(long, value_parser = values::radius, default_value = "0.2", allow_hyphen_values = true)]
    pub radius: Radius,
    /// Replace every radius below R (and placeholder radii ≤ 0, which SWC files from the field
    /// often hold) by R; a warning counts them. Without it such a file is refused.
    #[arg(long, value_name = "R", value_parser = values::positive, allow_hyphen_values = true)]
    pub min_radius: Option<f64>,
}

/// Which streamlines are loaded, and the memory they may take.
#[derive(Args, Clone, Copy, Debug, Default)]
pub struct SelectArgs {
    /// Keep only the first N streamlines (after --subsample); the rest of the file is not
    /// read. Not for SWC files (one tree).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..))]
    pub max_streamlines: Option<u64>,
    /// Keep about a fraction F of the streamlines, 0 < F ≤ 1: streamline i (file order) is
    /// kept when SplitMix64 seeded with i draws below F·2⁶⁴ (deterministic, the same on every
    /// run; no aliasing of an interleaved file as a stride would). Not for SWC files.
    #[arg(long, value_name = "F", value_parser = values::fraction, allow_hyphen_values = true)]
    pub subsample: Option<f64>,
    /// Refuse a scene whose estimated peak memory exceeds BYTES (suffixes K, M, G, T: powers
    /// of 1024) instead of the memory available (MemAvailable, or the cgroup's limit).
    #[arg(long, value_name = "BYTES", value_parser = values::bytes)]
    pub memory_limit: Option<u64>,
}

/// The quantized-lines model's resolution (`--model quantized`).
#[derive(Args, Clone, Copy, Debug)]
pub struct QuantArgs {
    /// With --model quantized: bins per voxel-face side Q (8 to 64) that line ends snap to.
    #[arg(long, value_name = "Q", default_value_t = 16, value_parser = clap::value_parser!(u32).range(8..=64))]
    pub quant_bins: u32,
    /// With --model quantized: voxels along the longest side of the scene (1 to 4096).
    #[arg(long, value_name = "N", default_value_t = 64, value_parser = clap::value_parser!(u32).range(1..=4096))]
    pub quant_voxels: u32,
}

/// Acceleration structure (`--accel`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Accel {
    /// 8-wide bounding volume hierarchy (obvhs CWBVH): the fastest here.
    Bvh,
    /// Binary bounding volume hierarchy (obvhs Bvh2).
    Bvh2,
    /// Uniform voxel grid, conservatively voxelized; its resolution weighs the build against the
    /// command's rays (`accel::grid` docs, "Resolution with a build").
    Grid,
}

/// Where the rays are traced (`--device`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Device {
    /// The CPU (every core).
    Cpu,
    /// A Vulkan GPU (built with the `gpu` feature): the same 8-wide tree and kernels in WGSL.
    Gpu,
}

/// The surface model of `render` and `info` (`--model`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Surface {
    /// Exact ray–tube kernels (with --tolerance: the cheapest primitive per segment within ε).
    Exact,
    /// A triangle mesh within `--tolerance` of the exact surface.
    Mesh,
    /// Kanzler et al.'s quantized lines: per-voxel segments, ends snapped to Q×Q face bins.
    Quantized,
}

/// The surface model `intersect` traces (`--model`): no mesh (its hits name no link).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum TraceSurface {
    /// Exact ray–tube kernels.
    Exact,
    /// Kanzler et al.'s quantized lines (link indices then count the quantized scene's links).
    Quantized,
}

impl From<TraceSurface> for Surface {
    fn from(s: TraceSurface) -> Self {
        match s {
            TraceSurface::Exact => Surface::Exact,
            TraceSurface::Quantized => Surface::Quantized,
        }
    }
}

/// Minimum pixel footprint for thin tubes (`--thin`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Thin {
    /// Tubes thinner than --min-pixels are drawn that wide and faded by their coverage (`auto`,
    /// the older default, means the same now that every format gets it).
    #[value(alias = "auto")]
    On,
    /// Tubes keep their radii: thinner than a pixel they alias (look dotted).
    Off,
}

/// A procedural scene (`generate`).
#[derive(Clone, Copy, Debug, ValueEnum)]
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
#[derive(Clone, Copy, Debug, ValueEnum)]
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
    /// Input scene (.swc, .trk, .tck, .trx, .obj).
    pub input: PathBuf,
    /// Output image (.png).
    #[arg(short, long, value_name = "OUT.png")]
    pub out: PathBuf,
    /// Also write the depth (ray parameter of the first surface, inf where none) as an
    /// H×W float64 .npy.
    #[arg(long, value_name = "OUT.npy")]
    pub depth: Option<PathBuf>,
    /// Overwrite existing output files (refused otherwise, before any work).
    #[arg(long)]
    pub force: bool,
    /// Image width in pixels (1 to 32768).
    #[arg(long, default_value_t = 800, value_parser = clap::value_parser!(u32).range(1..=32768))]
    pub width: u32,
    /// Image height in pixels (1 to 32768).
    #[arg(long, default_value_t = 600, value_parser = clap::value_parser!(u32).range(1..=32768))]
    pub height: u32,
    /// Antialiasing: N×N jittered samples per pixel (1 to 16).
    #[arg(long, value_name = "N", default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=16))]
    pub aa: u32,
    /// Radius and minimum radius.
    #[command(flatten)]
    pub radius: RadiusArgs,
    /// Background: #rrggbb, r,g,b (sRGB in [0, 1]), white, black, grey, or transparent (an RGBA
    /// PNG, alpha 0 where no tube is seen).
    #[arg(long, value_parser = values::background, default_value = "white")]
    pub background: Background,
    /// View preset: xy (down −z), xz (along +y), yz (along −x) or iso; fitted to the scene.
    #[arg(long, value_parser = |s: &str| s.parse::<Preset>())]
    pub view: Option<Preset>,
    /// Orthographic projection (parallel rays), framed as the perspective view would be.
    #[arg(long)]
    pub ortho: bool,
    /// Thin tubes stay visible: tubes thinner than --min-pixels on screen are drawn that wide
    /// and faded toward the background by their true coverage (phone-wire anti-aliasing).
    #[arg(long, value_enum, default_value_t = Thin::On)]
    pub thin: Thin,
    /// Minimum on-screen tube diameter in pixels for --thin (> 0).
    #[arg(long, default_value = "1", value_parser = values::positive, allow_hyphen_values = true)]
    pub min_pixels: f64,
    /// Colouring: direction, radius, type, solid:#rrggbb, or a data field of the file through
    /// --colormap: scalar:NAME (TrackVis scalar, TRX dpv, `scalar:tsf` for the .tsf beside a
    /// .tck, `scalar:radius`, `scalar:type`) or property:NAME (TrackVis property, TRX dps).
    #[arg(long, value_parser = values::color, default_value = "direction")]
    pub color: Color,
    /// Colour map for --color scalar:/property: (viridis, magma, inferno, plasma, cividis,
    /// turbo, greys, rdylbu).
    #[arg(long, value_parser = |s: &str| s.parse::<Colormap>(), default_value = "viridis")]
    pub colormap: Colormap,
    /// Draw a colour bar with the value range at the right edge (with --color scalar:/property:),
    /// its text dark or light, whichever contrasts with the background.
    #[arg(long)]
    pub legend: bool,
    /// Surface opacity in (0, 1]; below 1 renders transparent tubes (CSG union).
    #[arg(long, default_value = "1", value_parser = values::fraction, allow_hyphen_values = true)]
    pub opacity: f64,
    /// Ambient occlusion: rays (through the accelerator), cone (voxel cone tracing on the
    /// occupancy pyramid), lod (cones on Kanzler's LoD opacities) or off; a number N means N rays.
    #[arg(long, value_parser = values::ao, default_value = "off")]
    pub ao: Ao,
    /// Rays or cones per pixel for --ao rays|cone|lod (1 to 1024).
    #[arg(long, default_value_t = 16, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=1024))]
    pub ao_samples: u32,
    /// Trace shadow rays.
    #[arg(long)]
    pub shadows: bool,
    /// Camera position x,y,z (default: fitted to the scene).
    #[arg(long, value_parser = values::point, allow_hyphen_values = true)]
    pub eye: Option<[f64; 3]>,
    /// Point the camera looks at x,y,z (default: scene centre).
    #[arg(long, value_parser = values::point, allow_hyphen_values = true)]
    pub look_at: Option<[f64; 3]>,
    /// Camera up direction x,y,z (not zero).
    #[arg(long, value_parser = values::direction, default_value = "0,1,0", allow_hyphen_values = true)]
    pub up: [f64; 3],
    /// Vertical field of view in degrees, in (0, 180).
    #[arg(long, default_value = "40", value_parser = values::fov, allow_hyphen_values = true)]
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
    pub quant: QuantArgs,
    /// Tolerance ε > 0 (scene units). With `--model mesh`: the mesh's two-sided Hausdorff
    /// bound; with the exact model: pick per segment the cheapest primitive within ε (merged
    /// links, spheres, cylinders, cones, fitted quadratic spline pieces).
    #[arg(long, value_name = "EPS", value_parser = values::positive, allow_hyphen_values = true)]
    pub tolerance: Option<f64>,
    /// Like --tolerance, per segment: P > 0 pixels of the camera's footprint at its distance.
    #[arg(long, value_name = "P", conflicts_with = "tolerance", value_parser = values::positive, allow_hyphen_values = true)]
    pub pixel_error: Option<f64>,
    /// Selection and memory limit.
    #[command(flatten)]
    pub select: SelectArgs,
    /// Acceleration structure.
    #[arg(long, value_enum, default_value_t = Accel::Bvh)]
    pub accel: Accel,
    /// Where to trace the rays: cpu (default) or gpu (a build with the `gpu` feature).
    #[arg(long, value_enum, default_value_t = Device::Cpu)]
    pub device: Device,
    /// Threads, quiet, progress.
    #[command(flatten)]
    pub run: RunArgs,
}

/// `tubecast info`.
#[derive(Args)]
pub struct InfoArgs {
    /// Input scene (.swc, .trk, .tck, .trx, .obj).
    pub input: PathBuf,
    /// Print one JSON object (the schema is in the CLI's README) instead of the table.
    #[arg(long)]
    pub json: bool,
    /// Radius and minimum radius.
    #[command(flatten)]
    pub radius: RadiusArgs,
    /// Count the primitives of the spline model (as `render --splines` uses them).
    #[arg(long)]
    pub splines: bool,
    /// The model to report, as `render --model` would build it.
    #[arg(long, value_enum, default_value_t = Surface::Exact)]
    pub model: Surface,
    /// Quantized-lines model.
    #[command(flatten)]
    pub quant: QuantArgs,
    /// Also report the automatic primitive choice within ε > 0 (counts, worst certified error);
    /// with --model mesh, the mesh's tolerance.
    #[arg(long, value_name = "EPS", value_parser = values::positive, allow_hyphen_values = true)]
    pub tolerance: Option<f64>,
    /// The automatic choice within P > 0 pixels of the default fitted 800×600 view's footprint.
    #[arg(long, value_name = "P", conflicts_with = "tolerance", value_parser = values::positive, allow_hyphen_values = true)]
    pub pixel_error: Option<f64>,
    /// Selection and memory limit.
    #[command(flatten)]
    pub select: SelectArgs,
    /// Threads, quiet, progress.
    #[command(flatten)]
    pub run: RunArgs,
}

/// `tubecast intersect`.
#[derive(Args)]
pub struct IntersectArgs {
    /// Input scene (.swc, .trk, .tck, .trx, .obj).
    pub input: PathBuf,
    /// Rays, N×6 float32 or float64 .npy (C or Fortran order); `-` reads stdin.
    #[arg(long, value_name = "RAYS.npy")]
    pub rays: PathBuf,
    /// Output hits, N×8: float64 .npy, or CSV (with --csv or a .csv name); `-` writes stdout
    /// (`--query all`: one row per crossing).
    #[arg(short, long, value_name = "OUT")]
    pub out: PathBuf,
    /// Overwrite an existing output file (refused otherwise, before any work).
    #[arg(long)]
    pub force: bool,
    /// Write the hits as CSV (header t_in,t_out,nx,ny,nz,link,u,hit).
    #[arg(long)]
    pub csv: bool,
    /// What to answer per ray.
    #[arg(long, value_enum, default_value_t = Query::Hit)]
    pub query: Query,
    /// Acceleration structure (the hits are the same).
    #[arg(long, value_enum, default_value_t = Accel::Bvh)]
    pub accel: Accel,
    /// Where to trace the rays: cpu (default) or gpu (a build with the `gpu` feature).
    #[arg(long, value_enum, default_value_t = Device::Cpu)]
    pub device: Device,
    /// Radius and minimum radius.
    #[command(flatten)]
    pub radius: RadiusArgs,
    /// Trace the spline model (as `render --splines` does) instead of the links.
    #[arg(long)]
    pub splines: bool,
    /// Surface model: exact, or quantized lines.
    #[arg(long, value_enum, default_value_t = TraceSurface::Exact)]
    pub model: TraceSurface,
    /// Quantized-lines model.
    #[command(flatten)]
    pub quant: QuantArgs,
    /// Selection and memory limit.
    #[command(flatten)]
    pub select: SelectArgs,
    /// Threads, quiet, progress.
    #[command(flatten)]
    pub run: RunArgs,
}

/// `tubecast generate`.
#[derive(Args)]
pub struct GenerateArgs {
    /// Which scene.
    #[arg(value_enum)]
    pub kind: Kind,
    /// Output scene: .swc or .obj (with radii), .tck or .trk (without); neurons: .swc.
    #[arg(short, long, value_name = "OUT")]
    pub out: PathBuf,
    /// Overwrite an existing output file (refused otherwise, before any work).
    #[arg(long)]
    pub force: bool,
    /// Number of tubes (bundle: 1250, furball: 10000 by default).
    #[arg(long, value_parser = clap::value_parser!(u64).range(1..))]
    pub count: Option<u64>,
    /// Segments per tube (bundle: 84, furball: 78, helix: 200 by default).
    #[arg(long, value_parser = clap::value_parser!(u64).range(1..))]
    pub segments: Option<u64>,
    /// Neurons per box side, 1 to 40 (the assembly has N³ neurons).
    #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u64).range(1..=40))]
    pub n: u64,
    /// Base neuron(s) for the assembly (SWC); default: a procedural neuron.
    #[arg(long)]
    pub base: Vec<PathBuf>,
    /// Random seed.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Threads, quiet, progress.
    #[command(flatten)]
    pub run: RunArgs,
}

/// `tubecast mesh`.
#[derive(Args)]
pub struct MeshArgs {
    /// Input scene (.swc, .trk, .tck, .trx, .obj).
    pub input: PathBuf,
    /// Output mesh: .ply (binary), .obj or .glb.
    #[arg(short, long, value_name = "OUT")]
    pub out: PathBuf,
    /// Overwrite an existing output file (refused otherwise, before any work).
    #[arg(long)]
    pub force: bool,
    /// Tolerance ε > 0 (scene units): the two-sided Hausdorff bound between the mesh and the
    /// surface of the union of the exact tubes (with --shells: each shell and its chain's tubes).
    #[arg(long, value_name = "EPS", value_parser = values::positive, allow_hyphen_values = true)]
    pub tolerance: f64,
    /// Radius and minimum radius.
    #[command(flatten)]
    pub radius: RadiusArgs,
    /// Mesh the C¹ spline tubes of the chains instead of the links (as shells: implies --shells).
    #[arg(long)]
    pub splines: bool,
    /// Write one closed shell per chain (and split joint), overlapping where chains meet,
    /// instead of the surface of the union: for renderers that composite through a depth buffer.
    #[arg(long)]
    pub shells: bool,
    /// Union: mesh each stretch of a chain with one radius (a streamline) as one body of
    /// mitred rings instead of a hull per link: fewer triangles on tractograms at the same
    /// tolerance; slower to certify where streamlines nearly coincide. The default where at
    /// least half the links lie on such stretches of four links or more.
    #[arg(long, conflicts_with_all = ["shells", "splines", "hulls"])]
    pub runs: bool,
    /// Union: a hull of the two end spheres per link, whatever the chains (the default
    /// where fewer than half the links lie on equal-radius stretches of four links or more).
    #[arg(long, conflicts_with_all = ["shells", "splines"])]
    pub hulls: bool,
    /// Print the summary as one JSON object.
    #[arg(long)]
    pub json: bool,
    /// Selection and memory limit.
    #[command(flatten)]
    pub select: SelectArgs,
    /// Threads, quiet, progress.
    #[command(flatten)]
    pub run: RunArgs,
}

/// `tubecast simplify`.
#[derive(Args)]
pub struct SimplifyArgs {
    /// Input scene (.swc, .trk, .tck, .obj).
    pub input: PathBuf,
    /// Output file, of the input's format (extension).
    #[arg(short, long, value_name = "OUT")]
    pub out: PathBuf,
    /// Overwrite an existing output file, the input included (refused otherwise, before any work).
    #[arg(long)]
    pub force: bool,
    /// Tolerance ε > 0 (scene units): the two-sided Hausdorff bound between the output and the
    /// exact tubes of the input.
    #[arg(long, value_name = "EPS", value_parser = values::positive, allow_hyphen_values = true)]
    pub tolerance: f64,
    /// Radius and minimum radius.
    #[command(flatten)]
    pub radius: RadiusArgs,
    /// Print the counts as one JSON object.
    #[arg(long)]
    pub json: bool,
    /// Threads, quiet, progress.
    #[command(flatten)]
    pub run: RunArgs,
}
