//! The `tubecast` command line: render, info, intersect, generate.

use clap::{Parser, Subcommand, ValueEnum};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use tubecast::{Ray, V3};
use tubecast_render::accel::{first_component, Bvh};
use tubecast_render::io::{self, npy::Array2, Polyline};
use tubecast_render::render::{self, Camera, ColorBy, Options, Shading};
use tubecast_render::scene::{generate, Scene};

#[derive(Parser)]
#[command(name = "tubecast", version, about = "Exact ray–tube intersection and a minimal tube renderer")]
struct Cli {
    #[command(subcommand)]
    cmd: Cmd,
}

#[derive(Clone, Copy, ValueEnum)]
enum Color {
    /// |tangent| as RGB (tractography convention).
    Direction,
    /// Radius through a colour map.
    Radius,
    /// SWC structure type.
    Type,
}

#[derive(Clone, Copy, ValueEnum)]
enum Kind {
    /// Russig's Bundle (1250 twisting fibres).
    Bundle,
    /// Russig's Furball (10,000 hairs).
    Furball,
    /// Han's neuron assembly (N³ neurons).
    Neurons,
    /// A double helix with varying radius.
    Helix,
}

#[derive(Subcommand)]
enum Cmd {
    /// Render a scene (.swc, .trk, .tck, .obj) to a PNG.
    Render {
        /// Input file.
        input: PathBuf,
        /// Output PNG.
        #[arg(short, long)]
        out: PathBuf,
        /// Image width in pixels.
        #[arg(long, default_value_t = 800)]
        width: u32,
        /// Image height in pixels.
        #[arg(long, default_value_t = 600)]
        height: u32,
        /// Tube radius for formats without radii (.trk, .tck, OBJ without radius).
        #[arg(long, default_value_t = 0.2)]
        radius: f64,
        /// Colouring.
        #[arg(long, value_enum, default_value_t = Color::Direction)]
        color: Color,
        /// Surface opacity in (0, 1]; below 1 renders transparent tubes (CSG union).
        #[arg(long, default_value_t = 1.0)]
        opacity: f64,
        /// Ambient-occlusion rays per pixel.
        #[arg(long, default_value_t = 0)]
        ao: u32,
        /// Trace shadow rays.
        #[arg(long)]
        shadows: bool,
        /// Camera position x,y,z (default: fitted to the scene).
        #[arg(long, value_parser = parse_v3)]
        eye: Option<[f64; 3]>,
        /// Point the camera looks at x,y,z (default: scene centre).
        #[arg(long, value_parser = parse_v3)]
        look_at: Option<[f64; 3]>,
        /// Camera up direction x,y,z.
        #[arg(long, value_parser = parse_v3, default_value = "0,1,0")]
        up: [f64; 3],
        /// Vertical field of view in degrees.
        #[arg(long, default_value_t = 40.0)]
        fov: f64,
        /// Render the chains of links as C¹ cubic Hermite spline tubes (Catmull–Rom
        /// derivatives; each branch between bifurcations is its own spline; straight runs
        /// stay links).
        #[arg(long)]
        splines: bool,
        /// Hide the progress bar.
        #[arg(long)]
        quiet: bool,
    },
    /// Print counts of nodes, links and primitives, bounds and memory.
    Info {
        /// Input file.
        input: PathBuf,
        /// Tube radius for formats without radii.
        #[arg(long, default_value_t = 0.2)]
        radius: f64,
        /// Count the primitives of the spline model (as `render --splines` uses them).
        #[arg(long)]
        splines: bool,
    },
    /// Intersect rays (N×6 float64 .npy: origin, direction) with a scene; write N×8 hits.
    ///
    /// Hit columns: t_in, t_out (first component of the union of all tubes along the ray's
    /// line that meets t ≥ 0; t_in < 0 when the ray starts inside), normal at entry (x, y, z),
    /// link index of the entry, curve parameter u at entry, hit flag (1 or 0). Misses:
    /// t_in = t_out = +inf, normal 0, link −1, u 0, flag 0.
    Intersect {
        /// Input scene.
        input: PathBuf,
        /// Rays, N×6 float64 .npy.
        #[arg(long)]
        rays: PathBuf,
        /// Output hits, N×8 float64 .npy.
        #[arg(long)]
        out: PathBuf,
        /// Tube radius for formats without radii.
        #[arg(long, default_value_t = 0.2)]
        radius: f64,
    },
    /// Generate a procedural test scene (.swc, .tck, .obj or .trk by extension; neurons: .swc).
    Generate {
        /// Which scene.
        #[arg(value_enum)]
        kind: Kind,
        /// Output file.
        #[arg(short, long)]
        out: PathBuf,
        /// Number of tubes (bundle: 1250, furball: 10000 by default).
        #[arg(long)]
        count: Option<usize>,
        /// Segments per tube (bundle: 84, furball: 78, helix: 200 by default).
        #[arg(long)]
        segments: Option<usize>,
        /// Neurons per box side (the assembly has N³ neurons).
        #[arg(long, default_value_t = 3)]
        n: usize,
        /// Base neuron(s) for the assembly (SWC); default: a procedural neuron.
        #[arg(long)]
        base: Vec<PathBuf>,
        /// Random seed.
        #[arg(long, default_value_t = 1)]
        seed: u64,
    },
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

type Res<T> = Result<T, String>;

fn load(input: &Path, radius: f64) -> Res<Scene> {
    Scene::load(input, radius).map_err(|e| e.to_string())
}

/// The primitives of the link model, or of the spline model with `splines`.
fn primitives(scene: &Scene, splines: bool) -> Res<Vec<tubecast_render::scene::Prim>> {
    if splines {
        scene.spline_primitives().map_err(|e| e.to_string())
    } else {
        Ok(scene.primitives())
    }
}

fn cmd_render(a: RenderArgs) -> Res<()> {
    let scene = load(&a.input, a.radius)?;
    let prims = primitives(&scene, a.splines)?;
    // Bounds of the primitives in use (a spline can bulge beyond its links' boxes).
    let st = scene.stats_of(&prims);
    let bvh = Bvh::build(prims);
    let cam = match (a.eye, a.look_at) {
        (None, None) => Camera::fit(st.bounds.0, st.bounds.1, a.fov, a.width, a.height),
        (eye, at) => {
            let c = [0, 1, 2].map(|i| 0.5 * (st.bounds.0[i] + st.bounds.1[i]));
            let fit = Camera::fit(st.bounds.0, st.bounds.1, a.fov, a.width, a.height).map_err(|e| e.to_string())?;
            let eye = eye.map(V3::from).unwrap_or(fit.eye);
            Camera::look_at(eye, V3::from(at.unwrap_or(c)), V3::from(a.up), a.fov, a.width, a.height)
        }
    }
    .map_err(|e| e.to_string())?;
    let opts = Options {
        color: match a.color {
            Color::Direction => ColorBy::Direction,
            Color::Radius => ColorBy::Radius,
            Color::Type => ColorBy::Type,
        },
        shading: Shading::Lit,
        opacity: a.opacity,
        ao: a.ao,
        shadows: a.shadows,
        progress: !a.quiet && (a.width as u64 * a.height as u64) >= 256 * 256,
        ..Options::default()
    };
    let img = render::render(&scene, &bvh, &cam, &opts).map_err(|e| e.to_string())?;
    img.write_png(&a.out).map_err(|e| e.to_string())
}

struct RenderArgs {
    input: PathBuf,
    out: PathBuf,
    width: u32,
    height: u32,
    radius: f64,
    color: Color,
    opacity: f64,
    ao: u32,
    shadows: bool,
    eye: Option<[f64; 3]>,
    look_at: Option<[f64; 3]>,
    up: [f64; 3],
    fov: f64,
    splines: bool,
    quiet: bool,
}

fn cmd_info(input: &Path, radius: f64, splines: bool) -> Res<()> {
    let scene = load(input, radius)?;
    let prims = primitives(&scene, splines)?;
    let st = if splines { scene.stats_of(&prims) } else { scene.stats() };
    let bvh = Bvh::build(prims);
    let node_bytes = scene.nodes.len() * std::mem::size_of::<tubecast_render::scene::Node>()
        + scene.links.len() * std::mem::size_of::<[u32; 2]>();
    println!("file       {}", input.display());
    println!("nodes      {}", st.nodes);
    println!("links      {}", st.links);
    println!("cylinders  {}", st.cylinders);
    println!("cones      {}", st.cones);
    println!("spheres    {}", st.spheres);
    if splines {
        println!("splines    {} ({} quadratic sub-segments)", st.splines, 2 * st.splines);
    } else {
        println!("splines    {}", st.splines);
    }
    println!("bounds min {:?}", st.bounds.0);
    println!("bounds max {:?}", st.bounds.1);
    println!(
        "memory     scene {} B, primitives + BVH {} B ({} BVH nodes)",
        node_bytes,
        bvh.memory_bytes(),
        bvh.node_count()
    );
    Ok(())
}

fn cmd_intersect(input: &Path, rays: &Path, out: &Path, radius: f64) -> Res<()> {
    let scene = load(input, radius)?;
    let name = rays.display().to_string();
    let data = io::read_bytes(rays).map_err(|e| e.to_string())?;
    let arr = io::npy::read(&data, &name, Some(6)).map_err(|e| e.to_string())?;
    let mut rs = Vec::with_capacity(arr.rows);
    for i in 0..arr.rows {
        let r = arr.row(i);
        let ray = Ray::new(V3::new(r[0], r[1], r[2]), V3::new(r[3], r[4], r[5]));
        ray.validate().map_err(|e| format!("{name}: row {i}: {e}"))?;
        rs.push(ray);
    }
    let bvh = Bvh::build(scene.primitives());
    let mut hits = Array2 { rows: arr.rows, cols: 8, data: Vec::with_capacity(arr.rows * 8) };
    for ray in &rs {
        match first_component(&bvh, ray) {
            Some((e, x)) => hits.data.extend_from_slice(&[
                e.t,
                x.t,
                e.n.x,
                e.n.y,
                e.n.z,
                bvh.prims[e.id as usize].link as f64,
                e.u,
                1.0,
            ]),
            None => hits.data.extend_from_slice(&[f64::INFINITY, f64::INFINITY, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0]),
        }
    }
    io::write_bytes(out, &io::npy::write(&hits)).map_err(|e| e.to_string())
}

fn write_lines(out: &Path, lines: &[Polyline]) -> Res<()> {
    let ext = out.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
    let bytes = match ext.as_str() {
        "swc" => io::swc::write(&generate::polylines_to_swc(lines, 0.2)).into_bytes(),
        "tck" => io::tck::write(lines, false),
        "obj" => io::obj::write(lines).into_bytes(),
        "trk" => io::trk::write(&io::trk::TrkHeader::default(), lines, false),
        _ => return Err(format!("{}: unknown extension {ext:?} (use .swc, .tck, .obj or .trk)", out.display())),
    };
    io::write_bytes(out, &bytes).map_err(|e| e.to_string())
}

fn cmd_generate(
    kind: Kind,
    out: &Path,
    count: Option<usize>,
    segments: Option<usize>,
    n: usize,
    base: &[PathBuf],
    seed: u64,
) -> Res<()> {
    const MAX: usize = 50_000_000;
    let check = |c: usize, s: usize| {
        if c == 0 || s == 0 || c.saturating_mul(s) > MAX {
            Err(format!("--count × --segments must be between 1 and {MAX}"))
        } else {
            Ok(())
        }
    };
    match kind {
        Kind::Bundle => {
            let (c, s) = (count.unwrap_or(1250), segments.unwrap_or(84));
            check(c, s)?;
            write_lines(out, &generate::bundle(c, s, seed))
        }
        Kind::Furball => {
            let (c, s) = (count.unwrap_or(10_000), segments.unwrap_or(78));
            check(c, s)?;
            write_lines(out, &generate::furball(c, s, seed))
        }
        Kind::Helix => {
            let s = segments.unwrap_or(200);
            check(1, s)?;
            write_lines(out, &generate::helix(s))
        }
        Kind::Neurons => {
            if n == 0 || n > 40 {
                return Err("--n must be in 1..=40".into());
            }
            if !out.extension().is_some_and(|e| e.eq_ignore_ascii_case("swc")) {
                return Err(format!("{}: neuron assemblies branch; write them as .swc", out.display()));
            }
            let bases = if base.is_empty() {
                vec![generate::base_neuron(seed)]
            } else {
                base.iter()
                    .map(|p| {
                        let d = io::read_bytes(p).map_err(|e| e.to_string())?;
                        io::swc::read(&d, &p.display().to_string()).map_err(|e| e.to_string())
                    })
                    .collect::<Res<Vec<_>>>()?
            };
            let nodes = generate::neurons(n, &bases, seed);
            io::write_bytes(out, io::swc::write(&nodes).as_bytes()).map_err(|e| e.to_string())
        }
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let r = match cli.cmd {
        Cmd::Render {
            input,
            out,
            width,
            height,
            radius,
            color,
            opacity,
            ao,
            shadows,
            eye,
            look_at,
            up,
            fov,
            splines,
            quiet,
        } => cmd_render(RenderArgs {
            input,
            out,
            width,
            height,
            radius,
            color,
            opacity,
            ao,
            shadows,
            eye,
            look_at,
            up,
            fov,
            splines,
            quiet,
        }),
        Cmd::Info { input, radius, splines } => cmd_info(&input, radius, splines),
        Cmd::Intersect { input, rays, out, radius } => cmd_intersect(&input, &rays, &out, radius),
        Cmd::Generate { kind, out, count, segments, n, base, seed } => {
            cmd_generate(kind, &out, count, segments, n, &base, seed)
        }
    };
    match r {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("tubecast: error: {e}");
            ExitCode::FAILURE
        }
    }
}
