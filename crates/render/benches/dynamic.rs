//! Dynamic line sets: every frame moves the lines, so every frame rebuilds its acceleration
//! structure. Per frame and structure (grid: `accel::grid::Grid::build` at the default
//! `λ = 2` cells per link and at `λ = 8`, `32`; BVH: `Bvh::build`):
//! build time, render time (opaque, and transparent at opacity 0.3: CSG union along each ray)
//! and their sum, at 10⁴ … 10⁵ links (`TUBECAST_DYNAMIC_SIZES=10000,100000,1000000` for
//! others). Scene: a bundle (Russig's, radius 0.12) whose fibres sway with the frame number;
//! image 128×96, camera fitted, lit, no AO. Frames run on rayon's pool (all cores); the median
//! of `FRAMES` frames is printed as a markdown table (ratios against the BVH in the same run).
//!
//!     cargo bench -p tubecast-render --bench dynamic
use std::time::Instant;
use tubecast_render::accel::grid::{Grid, GridParams};
use tubecast_render::accel::{Bvh, Tracer};
use tubecast_render::io::Polyline;
use tubecast_render::render::{render, Camera, Options};
use tubecast_render::scene::{generate, Scene};

const W: u32 = 128;
const H: u32 = 96;
const FRAMES: usize = 5;

/// The bundle of `links` links (84 per fibre) swayed for frame `f`.
fn frame_lines(base: &[Polyline], f: usize) -> Vec<Polyline> {
    let ph = 0.4 * f as f64;
    base.iter()
        .map(|p| Polyline {
            points: p.points.iter().map(|q| [q[0], q[1] + 2.0 * (0.05 * q[0] + ph).sin(), q[2]]).collect(),
            radii: p.radii.clone(),
        })
        .collect()
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

type Build = fn(Vec<tubecast_render::scene::Prim>) -> Box<dyn Tracer>;

fn main() {
    let sizes: Vec<usize> = std::env::var("TUBECAST_DYNAMIC_SIZES")
        .ok()
        .map(|s| s.split(',').filter_map(|x| x.trim().parse().ok()).collect())
        .unwrap_or_else(|| vec![10_000, 100_000]);
    let builders: [(&str, Build); 5] = [
        ("grid auto (default)", |p| Box::new(Grid::build(p))),
        ("grid λ=2", |p| {
            Box::new(Grid::build_with(p, &GridParams { cells_per_prim: Some(2.0), ..GridParams::default() }))
        }),
        ("grid λ=8", |p| {
            Box::new(Grid::build_with(p, &GridParams { cells_per_prim: Some(8.0), ..GridParams::default() }))
        }),
        ("grid λ=32", |p| {
            Box::new(Grid::build_with(p, &GridParams { cells_per_prim: Some(32.0), ..GridParams::default() }))
        }),
        ("bvh", |p| Box::new(Bvh::build(p))),
    ];
    println!("| links | structure | mode | build ms | render ms | frame ms | frame / BVH frame |");
    println!("|---|---|---|---|---|---|---|");
    for links in sizes {
        let base = generate::bundle(links.div_ceil(84), 84, 1);
        for (mode, opacity) in [("opaque", 1.0), ("transparent", 0.3)] {
            let opts = Options { opacity, ..Options::default() };
            let mut rows = Vec::new();
            for (name, build) in builders {
                let (mut tb, mut tr) = (Vec::new(), Vec::new());
                for f in 0..FRAMES {
                    let scene = Scene::from_polylines(&frame_lines(&base, f), 0.12, "bundle").unwrap();
                    let prims = scene.primitives();
                    let st = scene.stats_of(&prims);
                    let cam = Camera::fit(st.bounds.0, st.bounds.1, 40.0, W, H).unwrap();
                    let t0 = Instant::now();
                    let tracer = build(prims);
                    let t1 = Instant::now();
                    std::hint::black_box(render(&scene, tracer.as_ref(), &cam, &opts).unwrap());
                    let t2 = Instant::now();
                    tb.push((t1 - t0).as_secs_f64() * 1e3);
                    tr.push((t2 - t1).as_secs_f64() * 1e3);
                }
                let (b, r) = (median(tb), median(tr));
                rows.push((name, b, r));
            }
            let bvh_frame = rows.iter().find(|r| r.0 == "bvh").map_or(f64::NAN, |r| r.1 + r.2);
            for (name, b, r) in rows {
                println!("| {links} | {name} | {mode} | {b:.1} | {r:.1} | {:.1} | {:.2} |", b + r, (b + r) / bvh_frame);
            }
        }
    }
}
