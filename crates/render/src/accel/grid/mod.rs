//! A uniform voxel grid over the scene's primitives, rebuilt from scratch in parallel in a few
//! passes: voxelize every primitive once into (voxel, primitive) pairs, count them per voxel,
//! prefix-sum the counts into per-voxel list offsets, scatter the pairs into the lists
//! ([`GridParams::one_pass`]); or Kraaijeveld et al.'s voxelize → scan → voxelize, which
//! voxelizes twice instead of holding the pairs.
//! Links and spheres are voxelized conservatively by [`tubecast::voxel::voxelize_round_cone`],
//! spline sub-segments by their bounding box. Rays walk the grid by Amanatides–Woo DDA
//! ([`tubecast::voxel::dda`]); it implements [`Tracer`], so the renderer and `hit_table` use it
//! unchanged.
//!
//! # Correct closest hit with early termination
//! Every primitive a voxel meets is in its list, so any hit at `t` lies in the voxel the walk
//! is in at `t` and is found there at the latest. The walk keeps the best hit of every
//! primitive tested so far (even one beyond the current voxel) and stops after the voxel whose
//! exit `t₁` is at or beyond the best `t`: no untested primitive can be hit before `t₁`.
//!
//! # Margin
//! The kernels run in `f32` relative to each primitive's origin, so a reported hit point may
//! lie slightly off the exact solid of the stored primitive; the voxel walk's boundaries carry
//! `f64` roundings. As for the BVH's boxes (see `accel` docs), every primitive is voxelized
//! with its radii grown by `pad = max(D·2⁻¹⁶, 64·ε·|x|max)` (`D` the scene diagonal, `|x|max`
//! the largest coordinate of the scene box, `ε = 2⁻⁵³`), far above both errors, so a hit point
//! within `pad` of a voxel boundary is listed on both sides of it. The second term covers the
//! `f64` rounding of world positions themselves (`≤ ε·|x|` per coordinate, in the primitives'
//! world ends and in the walk's grid coordinates): in a scene far smaller than its distance
//! from the origin it is the larger one. Without it a scene of one point of radius 2.4·10⁻³⁹ at
//! `|x| ≈ 1` had `D = 0` (the `f64` box of `origin ± r` is the origin), a zero-volume box, and a
//! fallback voxel of side 1 with the point on its corner, which rays through the point from the
//! other seven octants never entered (`tests/accel/long_link.rs`). The box always has positive
//! extent now, and the resolution is computed in units of the padded box's diagonal (no
//! under- or overflow of the volume at any scale).
//!
//! # Empty-space skipping
//! Coarse occupancy levels: level 1 marks which blocks of [`BLOCK`]³ voxels hold any
//! reference, level `k + 1` which blocks of `BLOCK³` level-`k` cells are marked
//! ([`GridParams::skip_levels`] of them: by default only the first; at most until a level is
//! at most `BLOCK` cells along every axis). The walk runs DDA over the coarsest level and, only inside marked cells,
//! DDA over the next finer level on that cell's `t` range, down to the voxels; an empty cell is
//! crossed in one step. Cells abut in `t`, so the fine walks cover the ray's range outside
//! empty cells; a voxel revisited at a cell boundary (rounding) is harmless (closest hit takes
//! the minimum, intervals are deduplicated). Every level's DDA runs on the grid coordinates
//! scaled by a power of two (`4⁻ᵏ`), so its boundary `t = (plane − o·s)/(d·s)` is bit for bit
//! the finest walk's `t` at the same plane: the levels change which voxels are skipped, never
//! the answers (`tests/accel/grid_levels.rs` checks hits, any-hits and intervals bit for bit).
//!
//! # Resolution
//! Cubic voxels of side `h` over the padded scene box of volume `V` (each extent floored at
//! `D/1000` so flat scenes get a volume), at most [`GridParams::max_cells`] cells.
//!
//! By default (`cells_per_prim: None`) `h` minimises a per-ray cost model built from four
//! numbers of the scene ([`SceneSums`], one pass): the link count `N`, total length
//! `Λ = Σ lᵢ`, total radius `R = Σ rᵢ`, and `V`. A ray crossing the box over a chord `c`
//! steps over `≈ 1.5·c/h` voxels (a random direction's `|d|₁/|d|₂` averages 3/2), each at cost
//! `C_T`; it tests each primitive whose voxels it meets once (the walk's mailbox skips the
//! repeats in consecutive voxels), at cost `C_I`. A primitive's voxels cover it grown by `≈ h/2`
//! on every side, a capsule of radius `rᵢ + h/2` and length `lᵢ`, whose mean projected area over
//! random directions is `π·(rᵢ + h/2)·(rᵢ + h/2 + lᵢ/2)`; a random line through the box meets it
//! with probability that area over the box's projected area `V/c`. So
//!
//! `cost(h) = c·[1.5·C_T/h + (π·C_I/V)·Σ (rᵢ + h/2)(rᵢ + lᵢ/2 + h/2)]`,
//!
//! and `cost′(h) = 0` gives `N·h³ + (2R + Λ/2)·h² = (3/π)·ρ·V` with `ρ = C_T/C_I`
//! ([`STEP_COST`]); the chord `c` cancels, so where rays stop early (opaque frames) does not
//! move the optimum. Its positive root is unique ([`voxel_size_for`]). Two regimes: links short
//! against `h` give `V/h³ = π·N/(3ρ)` cells, the classic "cells ≈ λ·N" rule with
//! `λ = π/(3ρ)`; long links give `h = √(3ρV/(π·(2R + Λ/2)))`, a finer grid the longer
//! they are. Scaling the scene scales `h` with it (same dims); doubling `N` at fixed `V`
//! divides `h` by between `∛2` and `√2`. This per-ray model counts no build (next section)
//! and no empty-space skipping; both models are checked against a sweep of fixed `λ` in
//! `tubecast-lab voxel` ("Grid resolution").
//!
//! # Resolution with a build
//! A scene rebuilt every frame pays the build once per `n` rays
//! ([`GridParams::rays_per_build`]: `Some(n)`), so `h` minimises the frame cost
//! `F(h) = B(h) + n·c̄·cost(h)/c`, with the per-ray cost above at the mean chord of random lines
//! through the box, `c̄ = 4V/S` (Cauchy; `S` the box's surface area: the chord no longer
//! cancels). Rays that stop early (opaque frames) cross less than `c̄`, so this leans fine.
//!
//! The build (`build.rs`, one pass) is: voxelize each primitive into (voxel, primitive) pairs,
//! count the pairs per voxel, prefix-sum the counts, scatter the pairs, then mark the occupied
//! blocks. Counting operations, with `M = V/h³` cells and `E(h)` references, everything in
//! units of one primitive test `C_I` (about a dozen operations with a square root, ~4 steps):
//! - per primitive: the voxelizer's set-up, `β_P·N`, independent of `h` (dropped);
//! - per cell `β_C`: zero a counter, one prefix-sum step (load, add, store), a cursor store and
//!   the block occupancy test (two offset loads, a compare): about a dozen streaming
//!   operations, `β_C ≈ 0.1`;
//! - per reference `β_E`: the voxelizer's inner step and an 8-byte push, a random atomic
//!   increment (count), a random atomic fetch-add and a random 4-byte store (scatter), and a
//!   copy: two locked read-modify-writes of ~20 cycles each dominate, `β_E ≈ 0.5`
//!   ([`BUILD_COST`]; cache misses on grids far beyond the caches make both larger).
//!
//! The expected references: a conservative voxelization lists the voxels that meet the
//! primitive, and a cube of side `h` at a random offset meets a convex body `K` with
//! probability `vol(K ⊕ cube)/h³`. For a capsule (length `l`, radius `r`) and a randomly turned
//! cube, Steiner's formula (cube: volume `h³`, surface `6h²`, mean width `3h/2`, mean
//! projected area `1.5h²` and perimeter `1.5πh`) gives `vol = h³ + (6r + 1.5l)·h² +
//! 3π·r·(r + l/2)·h + πr²l + 4πr³/3`, so over the scene ([`expected_references`])
//!
//! `E(h) = N + (6R + 1.5Λ)/h + 3π·X/h² + W/h³`, `X = Σ rᵢ(rᵢ + lᵢ/2)`, `W = Σ (πrᵢ²lᵢ + 4πrᵢ³/3)`,
//!
//! and `B(h) = β_C·V/h³ + β_E·E(h)`. Every term of `F` is convex in `h > 0` (and `F″ > 0`), so
//! `F′(h) = 0` has one root, found by bisection ([`frame_voxel_size_for`]). `B′ < 0`
//! everywhere and the per-ray part's slope is 0 at the static `h`, so the frame optimum is
//! coarser than the static one and grows as `n` falls; as `n → ∞` it tends to the static `h`.
//! Like the static rule it is computed in units of the box diagonal, so scaling the scene
//! leaves the dims unchanged.
//!
//! With `cells_per_prim: Some(λ)`: `h = ∛(V/(λ·N))`, the Cleary–Wyvill/Wald rule "cells ≈ λ·N"
//! (λ = 2 was the default before the cost model).
//!
//! # Memory
//! [`GridParams::footprint`] tells, before building, the bytes of the finished grid and of its
//! build's peak (`80N + 12E + 8M` and the pairs' growth in one pass: every buffer of `build.rs`
//! is counted in [`Footprint`]'s source) from the same resolution code and the expected
//! references `E(h)` above; the CLI's memory estimate asks it for `--accel grid`.

mod build;
mod footprint;
mod frame;
mod pyramid;
mod resolution;
mod walk;

pub use build::padded_extent;
pub use footprint::{Footprint, GROWTH_SLACK_CAP};
pub use frame::{expected_references, frame_voxel_size_for, BuildCost, BUILD_COST};
pub use pyramid::{Level, Pyramid};
pub use resolution::{voxel_size_for, SceneSums, STEP_COST};

use super::{Hit, Tracer};
use crate::scene::Prim;
use tubecast::csg::Tagged;
use tubecast::Ray;

/// How primitives are assigned to voxels.
///
/// ```
/// use tubecast_render::accel::grid::{Grid, GridParams, Voxelizer};
/// use tubecast_render::io::Polyline;
/// use tubecast_render::scene::Scene;
/// let line = Polyline { points: vec![[0.0; 3], [9.0, 3.0, 1.0]], radii: vec![] };
/// let prims = Scene::from_polylines(&[line], 0.5, "tube").unwrap().primitives();
/// let fine = GridParams { cells_per_prim: Some(64.0), ..GridParams::default() };
/// let exact = Grid::build_with(prims.clone(), &fine);
/// let thin = Grid::build_with(prims, &GridParams { voxelizer: Voxelizer::CentreLine, ..fine });
/// assert!(thin.references() < exact.references()); // the centre line meets fewer voxels
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Voxelizer {
    /// Conservative: every voxel a primitive's (padded) solid meets (the default).
    Conservative,
    /// Only the voxels the centre line passes through (DDA, as Kanzler et al. build their
    /// grid). **Not conservative**: rays miss primitives whose solid enters a voxel that its
    /// centre line does not; kept to count those false misses in tests and reports.
    CentreLine,
}

/// Grid build parameters ([`Grid::build_with`]; example at [`Voxelizer`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GridParams {
    /// Fixed target cells per primitive `λ`; `None` (the default): the voxel side minimising
    /// the cost model (both rules in the module docs, "Resolution").
    pub cells_per_prim: Option<f64>,
    /// Rays expected per build (the frame's rays, for a scene rebuilt every frame), for the
    /// default resolution (`cells_per_prim: None`): `None` (the default), a static scene, the
    /// per-ray model alone; `Some(n)`: minimise build + `n` rays (module docs, "Resolution with
    /// a build"), a coarser grid the fewer the rays.
    pub rays_per_build: Option<f64>,
    /// Upper bound on the number of cells.
    pub max_cells: usize,
    /// Voxel assignment.
    pub voxelizer: Voxelizer,
    /// Coarse occupancy levels the walk skips empty space on (module docs): 0 none (a plain
    /// DDA over the voxels), 1 the [`BLOCK`]³ blocks only (the default); larger values stop at
    /// the level with at most `BLOCK` cells along every axis (`u32::MAX`: all of them). More
    /// levels did not pay at the default resolution (`tubecast-lab voxel`, "Grid ablations",
    /// compares the frame times level by level).
    pub skip_levels: u32,
    /// Voxelize each primitive once into (voxel, primitive) pairs and sort them by voxel
    /// (the default), instead of voxelizing twice (count, then fill): 8 more bytes per
    /// reference while building.
    pub one_pass: bool,
}

impl Default for GridParams {
    fn default() -> Self {
        Self {
            cells_per_prim: None,
            rays_per_build: None,
            max_cells: 1 << 24,
            voxelizer: Voxelizer::Conservative,
            skip_levels: 1,
            one_pass: true,
        }
    }
}

/// A uniform grid of per-voxel primitive lists.
///
/// ```
/// use tubecast::{Ray, V3};
/// use tubecast_render::accel::grid::Grid;
/// use tubecast_render::accel::Tracer;
/// use tubecast_render::io::Polyline;
/// use tubecast_render::scene::Scene;
///
/// let line = Polyline { points: vec![[0.0; 3], [4.0, 0.0, 0.0]], radii: vec![] };
/// let scene = Scene::from_polylines(&[line], 0.5, "tube").unwrap();
/// let grid = Grid::build(scene.primitives());
/// let down = Ray::new(V3::new(2.0, 3.0, 0.0), V3::new(0.0, -1.0, 0.0));
/// let hit = grid.closest_hit(&down).unwrap();
/// assert_eq!((hit.t, grid.prim(hit.id).link, hit.entering), (2.5, 0, true));
/// assert!(!grid.any_hit(&Ray::new(V3::new(2.0, 3.0, 0.0), V3::new(0.0, 1.0, 0.0))));
/// ```
pub struct Grid {
    prims: Vec<Prim>,
    /// World position of the grid's corner (voxel `[0, 0, 0]`'s minimum).
    lo: [f64; 3],
    /// Voxel side (world units) and its inverse.
    h: f64,
    inv_h: f64,
    dims: [u32; 3],
    /// Per voxel `v`: its list is `ids[offsets[v]..offsets[v + 1]]`.
    offsets: Vec<u32>,
    ids: Vec<u32>,
    /// The coarse occupancy levels, finest (blocks of [`BLOCK`]³ voxels) first.
    skip: Vec<Skip>,
}

/// One coarse occupancy level: cells of `side` voxels along each axis.
struct Skip {
    dims: [u32; 3],
    side: u32,
    occupied: Vec<bool>,
}

impl Skip {
    /// Linear index of cell `c`.
    #[inline]
    fn index(&self, c: [u32; 3]) -> usize {
        (c[2] as usize * self.dims[1] as usize + c[1] as usize) * self.dims[0] as usize + c[0] as usize
    }
}

/// Side of an empty-space-skipping block, in voxels.
pub const BLOCK: u32 = 4;

impl Grid {
    /// Build with [`GridParams::default`].
    pub fn build(prims: Vec<Prim>) -> Self {
        Self::build_with(prims, &GridParams::default())
    }

    /// Voxels along x, y, z.
    pub fn dims(&self) -> [u32; 3] {
        self.dims
    }

    /// World position of the grid's corner (the minimum of voxel `[0, 0, 0]`); voxel
    /// `[i, j, k]` is the cube of side [`Self::voxel_size`] at `corner + h·(i, j, k)`.
    pub fn corner(&self) -> [f64; 3] {
        self.lo
    }

    /// Voxel side in world units.
    pub fn voxel_size(&self) -> f64 {
        self.h
    }

    /// Total length of the per-voxel lists (primitive references).
    pub fn references(&self) -> usize {
        self.ids.len()
    }

    /// Fraction of [`BLOCK`]³ blocks that hold a reference (1 without skip levels).
    pub fn occupied_fraction(&self) -> f64 {
        let Some(b) = self.skip.first() else {
            return 1.0;
        };
        b.occupied.iter().filter(|&&o| o).count() as f64 / b.occupied.len().max(1) as f64
    }

    /// Number of coarse occupancy levels the walk uses (module docs).
    pub fn skip_levels(&self) -> usize {
        self.skip.len()
    }

    /// Number of voxels.
    fn cells(&self) -> usize {
        self.dims.iter().map(|&d| d as usize).product()
    }

    /// Linear index of voxel `c`.
    #[inline]
    fn index(&self, c: [u32; 3]) -> usize {
        (c[2] as usize * self.dims[1] as usize + c[1] as usize) * self.dims[0] as usize + c[0] as usize
    }

    /// The primitive list of voxel `c`.
    #[inline]
    fn list(&self, c: [u32; 3]) -> &[u32] {
        let v = self.index(c);
        &self.ids[self.offsets[v] as usize..self.offsets[v + 1] as usize]
    }
}

impl Tracer for Grid {
    fn prim(&self, id: u32) -> Prim {
        self.prims[id as usize]
    }
    fn prim_count(&self) -> usize {
        self.prims.len()
    }
    fn closest_hit(&self, ray: &Ray<f64>) -> Option<Hit> {
        self.closest(ray)
    }
    fn any_hit(&self, ray: &Ray<f64>) -> bool {
        self.any(ray)
    }
    fn line_intervals(&self, ray: &Ray<f64>, out: &mut Vec<Tagged<f64>>) {
        self.intervals(ray, out)
    }
    fn memory_bytes(&self) -> usize {
        (self.offsets.len() + self.ids.len()) * 4
            + self.skip.iter().map(|l| l.occupied.len()).sum::<usize>()
            + self.prims.len() * std::mem::size_of::<Prim>()
    }
}
