//! Grid construction: resolution, then count → prefix sum → fill, each pass parallel over
//! the primitives (rayon), voxel counters and cursors as relaxed atomics.

use super::resolution::resolution;
use super::{Grid, GridParams, Skip, Voxelizer, BLOCK};
use crate::scene::{Prim, Shape};
use rayon::prelude::*;
use std::sync::atomic::{AtomicU32, Ordering::Relaxed};
use tubecast::voxel;
use tubecast::{RoundCone, V3};

/// The extents of the box the grid over `prims` covers, padded as [`Grid::build_with`] pads
/// it (module docs, "Margin"): what [`GridParams::footprint`] takes.
///
/// ```
/// use tubecast_render::accel::grid::padded_extent;
/// use tubecast_render::io::Polyline;
/// use tubecast_render::scene::Scene;
/// let line = Polyline { points: vec![[0.0; 3], [4.0, 0.0, 0.0]], radii: vec![] };
/// let e = padded_extent(&Scene::from_polylines(&[line], 0.5, "tube").unwrap().primitives());
/// assert!(e[0] > 5.0 && e[1] > 1.0 && e[1] < 1.001);
/// ```
pub fn padded_extent(prims: &[Prim]) -> [f64; 3] {
    let (lo, hi, _) = scene_box(prims);
    std::array::from_fn(|i| hi[i] - lo[i])
}

/// The padded bounding box of `prims` and the padding `pad = max(D·2⁻¹⁶, 64·ε·|x|max)`
/// (module docs, "Margin").
fn scene_box(prims: &[Prim]) -> ([f64; 3], [f64; 3], f64) {
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for p in prims {
        let (a, b) = p.aabb();
        lo = std::array::from_fn(|i| lo[i].min(a[i]));
        hi = std::array::from_fn(|i| hi[i].max(b[i]));
    }
    if prims.is_empty() {
        return ([0.0; 3], [0.0; 3], 0.0);
    }
    let diag = (0..3).map(|i| (hi[i] - lo[i]).powi(2)).sum::<f64>().sqrt();
    let far = (0..3).fold(0.0f64, |m, i| m.max(lo[i].abs()).max(hi[i].abs()));
    let pad = (diag.max(f64::MIN_POSITIVE) * 2f64.powi(-16)).max(64.0 * f64::EPSILON * far);
    (lo.map(|x| x - 2.0 * pad), hi.map(|x| x + 2.0 * pad), pad)
}

/// The cells along x, y, z of each of up to `most` coarse occupancy levels over a grid of
/// `dims` voxels, finest first (module docs, "Empty-space skipping"): each level has a cell per
/// [`BLOCK`]³ cells of the one below; the levels stop once one is at most `BLOCK` cells along
/// every axis.
pub(super) fn skip_dims(dims: [u32; 3], most: u32) -> Vec<[u32; 3]> {
    let mut levels: Vec<[u32; 3]> = Vec::new();
    while (levels.len() as u32) < most {
        let fine = levels.last().copied().unwrap_or(dims);
        if !levels.is_empty() && fine.iter().all(|&d| d <= BLOCK) {
            break;
        }
        levels.push(fine.map(|d| d.div_ceil(BLOCK)));
    }
    levels
}

/// The world round cone of a link or sphere primitive with radii grown by `pad`; `None` for a
/// spline sub-segment.
fn world_cone(p: &Prim, pad: f64) -> Option<RoundCone<f64>> {
    let c = p.round_cone()?;
    let o = V3::from(p.origin);
    Some(RoundCone { a: o + c.a.cast(), ra: c.ra as f64 + pad, b: o + c.b.cast(), rb: c.rb as f64 + pad })
}

/// The list offsets (prefix sums of `counts`) and zeroed id slots; `counts` become the fill
/// cursors (each voxel's list start). `None` when the total exceeds `u32::MAX`.
fn cursors(counts: &[AtomicU32]) -> Option<(Vec<u32>, Vec<AtomicU32>)> {
    let total: u64 = counts.iter().map(|c| c.load(Relaxed) as u64).sum();
    if total > u32::MAX as u64 {
        return None;
    }
    let mut offsets = Vec::with_capacity(counts.len() + 1);
    let mut sum = 0u32;
    offsets.push(0);
    for c in counts {
        sum += c.load(Relaxed);
        offsets.push(sum);
    }
    counts.par_iter().zip(offsets.par_iter()).for_each(|(c, &o)| c.store(o, Relaxed));
    Some((offsets, (0..sum).map(|_| AtomicU32::new(0)).collect()))
}

impl Grid {
    /// Build over `prims` with explicit parameters. An empty list gives a grid every ray
    /// misses.
    pub fn build_with(prims: Vec<Prim>, params: &GridParams) -> Self {
        let (lo, hi, pad) = scene_box(&prims);
        let (h, dims) = resolution(std::array::from_fn(|i| hi[i] - lo[i]), &prims, params);
        let (offsets, ids, skip) = (Vec::new(), Vec::new(), Vec::new());
        let mut grid = Grid { prims, lo, h, inv_h: 1.0 / h, dims, offsets, ids, skip };
        let cells = grid.cells();
        let lists = if params.one_pass && cells <= u32::MAX as usize {
            grid.lists_once(pad, params.voxelizer)
        } else {
            grid.lists_twice(pad, params.voxelizer)
        };
        let Some((offsets, ids)) = lists else {
            // Lists too long for u32 offsets (huge radii against the voxel size): coarser. At
            // one voxel each primitive is listed once, so this ends.
            let lambda = grid.cells() as f64 / grid.prims.len().max(1) as f64;
            let coarser = GridParams { cells_per_prim: Some(lambda / 8.0), ..*params };
            return Self::build_with(grid.prims, &coarser);
        };
        grid.offsets = offsets;
        grid.ids = ids;
        grid.skip = grid.build_skip(params.skip_levels);
        grid
    }

    /// Per-voxel lists by voxelizing twice: count → prefix sum → voxelize again to fill.
    /// `None` when there are more than `u32::MAX` references.
    fn lists_twice(&self, pad: f64, how: Voxelizer) -> Option<(Vec<u32>, Vec<u32>)> {
        let cells = self.dims.iter().map(|&d| d as usize).product::<usize>();
        let counts: Vec<AtomicU32> = (0..cells).map(|_| AtomicU32::new(0)).collect();
        self.prims.par_iter().for_each(|p| {
            self.voxelize(p, pad, how, |v| {
                counts[v].fetch_add(1, Relaxed);
            })
        });
        let (offsets, ids) = cursors(&counts)?;
        self.prims.par_iter().enumerate().for_each(|(k, p)| {
            self.voxelize(p, pad, how, |v| {
                let slot = counts[v].fetch_add(1, Relaxed);
                ids[slot as usize].store(k as u32, Relaxed);
            })
        });
        Some((offsets, ids.into_iter().map(AtomicU32::into_inner).collect()))
    }

    /// Per-voxel lists by voxelizing once into (voxel, primitive) pairs, then a counting sort
    /// of the pairs by voxel (count → prefix sum → scatter). Needs voxel indices below 2³².
    fn lists_once(&self, pad: f64, how: Voxelizer) -> Option<(Vec<u32>, Vec<u32>)> {
        let pairs: Vec<[u32; 2]> = self
            .prims
            .par_iter()
            .enumerate()
            .fold(Vec::new, |mut acc, (k, p)| {
                self.voxelize(p, pad, how, |v| acc.push([v as u32, k as u32]));
                acc
            })
            .reduce(Vec::new, |mut a, mut b| {
                if a.len() < b.len() {
                    std::mem::swap(&mut a, &mut b);
                }
                a.extend_from_slice(&b);
                a
            });
        let cells = self.dims.iter().map(|&d| d as usize).product::<usize>();
        let counts: Vec<AtomicU32> = (0..cells).map(|_| AtomicU32::new(0)).collect();
        pairs.par_iter().for_each(|&[v, _]| {
            counts[v as usize].fetch_add(1, Relaxed);
        });
        let (offsets, ids) = cursors(&counts)?;
        pairs.par_iter().for_each(|&[v, k]| {
            let slot = counts[v as usize].fetch_add(1, Relaxed);
            ids[slot as usize].store(k, Relaxed);
        });
        Some((offsets, ids.into_iter().map(AtomicU32::into_inner).collect()))
    }

    /// Up to `most` coarse occupancy levels (module docs), each marking the cells of `BLOCK³`
    /// cells of the level below (voxels for the first) that hold a reference.
    fn build_skip(&self, most: u32) -> Vec<Skip> {
        let mut levels: Vec<Skip> = Vec::new();
        for dims in skip_dims(self.dims, most) {
            let (fine_dims, side) = levels.last().map_or((self.dims, 1), |l| (l.dims, l.side));
            let mut next =
                Skip { dims, side: side * BLOCK, occupied: vec![false; dims.iter().map(|&d| d as usize).product()] };
            for z in 0..fine_dims[2] {
                for y in 0..fine_dims[1] {
                    for x in 0..fine_dims[0] {
                        let full = match levels.last() {
                            None => {
                                let v = self.index([x, y, z]);
                                self.offsets[v + 1] > self.offsets[v]
                            }
                            Some(l) => l.occupied[l.index([x, y, z])],
                        };
                        if full {
                            let c = next.index([x / BLOCK, y / BLOCK, z / BLOCK]);
                            next.occupied[c] = true;
                        }
                    }
                }
            }
            levels.push(next);
        }
        levels
    }

    /// A world point in grid coordinates.
    #[inline]
    pub(super) fn to_grid(&self, x: V3<f64>) -> V3<f64> {
        V3::new((x.x - self.lo[0]) * self.inv_h, (x.y - self.lo[1]) * self.inv_h, (x.z - self.lo[2]) * self.inv_h)
    }

    /// Hand the linear index of every voxel `p` is assigned to to `f`.
    fn voxelize(&self, p: &Prim, pad: f64, how: Voxelizer, mut f: impl FnMut(usize)) {
        let s = self.inv_h;
        let cone = match (world_cone(p, pad), p.shape) {
            (Some(c), _) => RoundCone { a: self.to_grid(c.a), ra: c.ra * s, b: self.to_grid(c.b), rb: c.rb * s },
            (None, Shape::Spline { quad, .. }) if how == Voxelizer::CentreLine => {
                let o = V3::from(p.origin);
                RoundCone {
                    a: self.to_grid(o + quad.b[0].cast()),
                    ra: 0.0,
                    b: self.to_grid(o + quad.b[2].cast()),
                    rb: 0.0,
                }
            }
            _ => {
                // A spline sub-segment: its padded box, as a zero-radius "link" corner to corner.
                let (a, b) = p.aabb();
                let a = self.to_grid(V3::from(a.map(|x| x - pad)));
                let b = self.to_grid(V3::from(b.map(|x| x + pad)));
                return tubecast::baseline::voxel::voxelize_aabb(
                    &RoundCone { a, ra: 0.0, b, rb: 0.0 },
                    self.dims,
                    |c| f(self.index(c)),
                );
            }
        };
        match how {
            Voxelizer::Conservative => voxel::voxelize_round_cone(&cone, self.dims, |c| f(self.index(c))),
            Voxelizer::CentreLine => tubecast::baseline::voxel::voxelize_dda(&cone, self.dims, |c| f(self.index(c))),
        }
    }
}
