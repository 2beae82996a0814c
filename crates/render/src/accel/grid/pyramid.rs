//! The occupancy pyramid (Kraaijeveld et al. §3.1): the base level holds each voxel's
//! estimated volume fraction, accumulated over the links by [`tubecast::voxel::occupancy`]
//! (clipped round-cone SDF with planes from central-difference tangents at interior nodes,
//! PWAA radius clamp) at the voxel centres the conservative voxelization visits, clamped to 1;
//! each further level averages 2×2×2 voxels of the one below (missing children count as
//! empty), down to a single voxel.

use crate::scene::Scene;
use rayon::prelude::*;
use tubecast::voxel::{self, Clip};

/// Links whose contributions are computed in parallel before they are added.
const CHUNK: usize = 4096;
use tubecast::{RoundCone, V3};

/// One level: its size and per-voxel occupancy in `[0, 1]`, x fastest.
///
/// ```
/// use tubecast_render::accel::grid::Level;
/// let l = Level { dims: [2, 1, 1], values: vec![0.25, 1.0] };
/// assert_eq!((l.get([1, 0, 0]), l.get([2, 0, 0])), (1.0, 0.0)); // outside: empty
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Level {
    /// Voxels along x, y, z.
    pub dims: [u32; 3],
    /// Occupancy per voxel.
    pub values: Vec<f32>,
}

impl Level {
    /// Occupancy of voxel `c` (0 outside the level).
    pub fn get(&self, c: [u32; 3]) -> f32 {
        if c.iter().zip(self.dims).any(|(&x, n)| x >= n) {
            return 0.0;
        }
        self.values[(c[2] as usize * self.dims[1] as usize + c[1] as usize) * self.dims[0] as usize + c[0] as usize]
    }
}

/// Occupancy mip levels, finest first.
///
/// ```
/// use tubecast_render::accel::grid::Pyramid;
/// use tubecast_render::io::Polyline;
/// use tubecast_render::scene::Scene;
/// let line = Polyline { points: vec![[1.0, 4.5, 4.5], [7.0, 4.5, 4.5]], radii: vec![] };
/// let scene = Scene::from_polylines(&[line], 1.0, "tube").unwrap();
/// let p = Pyramid::build(&scene, [0.0; 3], 1.0, [8, 8, 8], 0.5);
/// assert_eq!(p.levels.len(), 4); // 8³, 4³, 2³, 1³
/// assert_eq!(p.levels[0].get([4, 4, 4]), 1.0); // on the axis
/// assert!(p.levels[3].values[0] > 0.0);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Pyramid {
    /// Levels, from the base (`dims`) to one voxel.
    pub levels: Vec<Level>,
}

/// Unit tangent at node `i` by central difference when it has exactly two links, oriented
/// along `along`; `None` at ends and bifurcations (their caps stay).
fn tangent(scene: &Scene, adj: &[Vec<u32>], i: u32, along: V3<f64>) -> Clip<f64> {
    let [p, q] = adj[i as usize][..] else {
        return None;
    };
    let t = (V3::from(scene.nodes[q as usize].pos) - V3::from(scene.nodes[p as usize].pos)).normalize_or_zero();
    Some(if t.dot(along) < 0.0 { t * -1.0 } else { t })
}

impl Pyramid {
    /// Build over `scene`'s links on the grid with corner `lo`, voxel side `h` and `dims`
    /// voxels; `r_min` is the PWAA radius clamp in world units.
    pub fn build(scene: &Scene, lo: [f64; 3], h: f64, dims: [u32; 3], r_min: f64) -> Self {
        let mut adj = vec![Vec::new(); scene.nodes.len()];
        for [a, b] in &scene.links {
            if a != b {
                adj[a as usize].push(b);
                adj[b as usize].push(a);
            }
        }
        let cells = dims.iter().map(|&d| d as usize).product();
        let mut base = Level { dims, values: vec![0.0; cells] };
        let g = |p: V3<f64>| V3::new((p.x - lo[0]) / h, (p.y - lo[1]) / h, (p.z - lo[2]) / h);
        let rmin = r_min / h;
        // One link's (voxel, occupancy) contributions.
        let contributions = |k: usize, out: &mut Vec<(u32, f32)>| {
            let [a, b] = scene.links.get(k);
            let w = scene.link(k);
            let l = RoundCone { a: g(w.a), ra: w.ra / h, b: g(w.b), rb: w.rb / h };
            let along = l.b - l.a;
            let (n0, n1) = (tangent(scene, &adj, a, along), tangent(scene, &adj, b, along));
            // Occupancy is non-zero where the clamped tube's SDF is below ½: visit that tube.
            let reach = RoundCone { a: l.a, ra: l.ra.max(rmin) + 0.5, b: l.b, rb: l.rb.max(rmin) + 0.5 };
            voxel::voxelize_round_cone(&reach, dims, |c| {
                let x = V3::new(c[0] as f64 + 0.5, c[1] as f64 + 0.5, c[2] as f64 + 0.5);
                let v = (c[2] as usize * dims[1] as usize + c[1] as usize) * dims[0] as usize + c[0] as usize;
                out.push((v as u32, voxel::occupancy(x, &l, n0, n1, rmin) as f32));
            });
        };
        // Contributions are computed in parallel, a chunk of links at a time (bounded memory),
        // and added in link order: the sums, so the pyramid, are the same bits on any number of
        // threads.
        for start in (0..scene.links.len()).step_by(CHUNK) {
            let parts: Vec<Vec<(u32, f32)>> = (start..(start + CHUNK).min(scene.links.len()))
                .into_par_iter()
                .map(|k| {
                    let mut out = Vec::new();
                    contributions(k, &mut out);
                    out
                })
                .collect();
            for (v, o) in parts.into_iter().flatten() {
                base.values[v as usize] += o;
            }
        }
        base.values.iter_mut().for_each(|v| *v = v.min(1.0));
        let mut levels = vec![base];
        while levels.last().is_some_and(|l| l.dims.iter().any(|&d| d > 1)) {
            let next = Self::halve(levels.last().expect("non-empty"));
            levels.push(next);
        }
        Self { levels }
    }

    /// The next coarser level: means of 2×2×2 voxels, one z-slice per task.
    fn halve(fine: &Level) -> Level {
        let dims = fine.dims.map(|d| d.div_ceil(2));
        let slice = dims[0] as usize * dims[1] as usize;
        let mut values = vec![0.0; slice * dims[2] as usize];
        values.par_chunks_mut(slice).enumerate().for_each(|(z, out)| {
            let z = z as u32;
            for y in 0..dims[1] {
                for x in 0..dims[0] {
                    let mut s = 0.0;
                    for k in 0..8u32 {
                        s += fine.get([2 * x + (k & 1), 2 * y + ((k >> 1) & 1), 2 * z + (k >> 2)]);
                    }
                    out[(y * dims[0] + x) as usize] = s / 8.0;
                }
            }
        });
        Level { dims, values }
    }
}
