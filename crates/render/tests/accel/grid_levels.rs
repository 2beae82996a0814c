//! The grid walk's coarse occupancy levels (`GridParams::skip_levels`) change which voxels are
//! skipped, never the answers: with 0 levels (plain DDA), 2, and all (up to a top level of
//! at most 4 cells per axis), every closest hit (all fields), any-hit and line
//! interval list is bit for bit the single-level walk's (one level of 4³ blocks, the walk
//! `grid_equivalence.rs` checks against the BVH). Rays: random through the scene, short
//! shadow/AO-like rays leaving tubes, axis-parallel rays on voxel and coarse-cell planes, and
//! space diagonals through coarse-cell corners. Fine grids (64 cells per primitive; 8192 for
//! the scattered links) so that these small scenes have several levels. Scenes with much empty space (two clusters
//! far apart, the hollow furball, short links scattered through a large box) and without (a bundle far from the origin, a neuron).

use tubecast::{Ray, V3};
use tubecast_render::accel::grid::{Grid, GridParams};
use tubecast_render::accel::Tracer;
use tubecast_render::io::Polyline;
use tubecast_render::scene::generate::{self, Rng};
use tubecast_render::scene::{Prim, Scene};

fn scenes() -> Vec<(&'static str, Vec<Prim>, f64)> {
    let lines = |l: &[Polyline]| Scene::from_polylines(l, 0.2, "s").unwrap().primitives();
    let shift = |l: Vec<Polyline>, by: [f64; 3]| -> Vec<Polyline> {
        l.into_iter()
            .map(|p| Polyline {
                points: p.points.iter().map(|q| std::array::from_fn(|i| q[i] + by[i])).collect(),
                radii: p.radii,
            })
            .collect()
    };
    let mut apart = generate::helix(40);
    apart.extend(shift(generate::helix(40), [300.0, -120.0, 80.0]));
    let neuron = Scene::from_swc(&generate::neurons(1, &[generate::base_neuron(4)], 6), "n").unwrap();
    // Short links scattered through a large box, on a fine grid (8192 cells per link): most
    // 16³-voxel cells hold one link or none.
    let mut rng = Rng::new(2);
    let scattered: Vec<Polyline> = (0..60)
        .map(|_| {
            let a: [f64; 3] = std::array::from_fn(|_| rng.range(0.0, 100.0));
            let u = rng.unit();
            Polyline { points: vec![a, std::array::from_fn(|i| a[i] + 0.5 * u[i])], radii: vec![] }
        })
        .collect();
    vec![
        ("scattered", lines(&scattered), 8192.0),
        ("two clusters", lines(&apart), 64.0),
        ("furball", lines(&generate::furball(200, 20, 3)), 64.0),
        ("far bundle", lines(&shift(generate::bundle(30, 20, 5), [1e5, -3e4, 7e4])), 64.0),
        ("neuron", neuron.primitives(), 64.0),
    ]
}

fn rays(grid: &Grid, prims: &[Prim], seed: u64) -> Vec<Ray<f64>> {
    let mut rng = Rng::new(seed);
    let (g, h, dims) = (grid.corner(), grid.voxel_size(), grid.dims());
    let ext: [f64; 3] = std::array::from_fn(|i| h * dims[i] as f64);
    let size = ext.iter().fold(0.0f64, |a, &b| a.max(b));
    let point = |rng: &mut Rng| {
        V3::new(g[0] + rng.range(0.0, ext[0]), g[1] + rng.range(0.0, ext[1]), g[2] + rng.range(0.0, ext[2]))
    };
    let mut out = Vec::new();
    for _ in 0..200 {
        let d = V3::from(rng.unit());
        out.push(Ray::new(point(&mut rng) - d * (2.0 * size), d));
        // From a tube's box centre: a short ray (t_max a tenth of the scene: the renderer's AO)
        // and a ray from far outside aimed at it.
        let p = &prims[(rng.uniform() * prims.len() as f64) as usize % prims.len()];
        let (a, b) = p.aabb();
        let c = V3::new(0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]), 0.5 * (a[2] + b[2]));
        out.push(Ray::with_range(c, V3::from(rng.unit()), 0.0, 0.1 * size));
        let d = V3::from(rng.unit());
        out.push(Ray::new(c - d * (2.0 * size), d));
    }
    for k in 0..120 {
        // On planes of voxels (k % 4 == 0), of 4³ blocks, of 16³ and of 64³ cells.
        let step = h * f64::from(1u32 << (2 * (k % 4)));
        let axis = k % 3;
        let (p, q) = ((axis + 1) % 3, (axis + 2) % 3);
        let mut o = [0.0; 3];
        o[axis] = g[axis] - h;
        o[p] = g[p] + step * (rng.uniform() * ext[p] / step).floor();
        o[q] = g[q] + step * (rng.uniform() * ext[q] / step).floor();
        let mut d = [0.0; 3];
        d[axis] = if k % 2 == 0 { 1.0 } else { -1.0 };
        if d[axis] < 0.0 {
            o[axis] = g[axis] + ext[axis] + h;
        }
        out.push(Ray::new(V3::from(o), V3::from(d)));
        // A space diagonal through a cell corner.
        let corner = V3::new(g[0], g[1], g[2]) + V3::new(1.0, 1.0, 1.0) * (step * (k / 4) as f64);
        out.push(Ray::new(corner - V3::new(1.0, 1.0, 1.0) * size, V3::new(1.0, 1.0, 1.0)));
    }
    out
}

/// Every answer of `t` on `ray`, printed exactly (`{:?}` keeps −0.0 and every digit).
fn answers(t: &dyn Tracer, ray: &Ray<f64>) -> String {
    let mut ivs = Vec::new();
    t.line_intervals(ray, &mut ivs);
    format!("{:?} {} {:?}", t.closest_hit(ray), t.any_hit(ray), ivs)
}

#[test]
fn skip_levels_give_the_single_level_answers_bit_for_bit() {
    for (name, prims, cells_per_prim) in scenes() {
        let with = |skip_levels| {
            Grid::build_with(
                prims.clone(),
                &GridParams { skip_levels, cells_per_prim: Some(cells_per_prim), ..GridParams::default() },
            )
        };
        let single = with(1);
        let others = [with(0), with(2), with(u32::MAX)];
        assert_eq!(single.skip_levels(), 1);
        assert!(others[2].skip_levels() >= 2, "{name}: the default built no coarser level");
        let rays = rays(&single, &prims, 17);
        let mut hits = 0;
        for (i, ray) in rays.iter().enumerate() {
            let want = answers(&single, ray);
            hits += usize::from(single.any_hit(ray));
            for g in &others {
                assert_eq!(answers(g, ray), want, "{name} ray {i}: {} skip levels", g.skip_levels());
            }
        }
        println!("{name}: {} rays, {hits} hitting, levels {}", rays.len(), others[2].skip_levels());
        assert!(hits > rays.len() / 10, "{name}: too few hits to compare");
    }
}

/// The one-pass build (voxelize once into pairs, sort by voxel) lists the same references as
/// the two-pass one (voxelize to count, again to fill), so every answer is the same bit for bit
/// (the order inside a list differs run to run with either; answers do not depend on it).
#[test]
fn one_pass_build_gives_the_two_pass_answers() {
    for (name, prims, cells_per_prim) in scenes() {
        let with = |one_pass| {
            Grid::build_with(
                prims.clone(),
                &GridParams { one_pass, cells_per_prim: Some(cells_per_prim), ..GridParams::default() },
            )
        };
        let (once, twice) = (with(true), with(false));
        assert_eq!(once.references(), twice.references(), "{name}");
        assert!(once.references() >= prims.len(), "{name}: a primitive is in no list");
        for (i, ray) in rays(&twice, &prims, 23).iter().enumerate() {
            assert_eq!(answers(&once, ray), answers(&twice, ray), "{name} ray {i}");
        }
    }
}
