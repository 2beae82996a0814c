//! The memory a grid build holds, known before it is built: the resolution the build would
//! choose ([`super::resolution`]'s own code) and the references Steiner's formula expects
//! ([`expected_references`]), priced by the buffers of `build.rs`.
//!
//! # The buffers (`build.rs`), with `N` primitives, `M` cells and `E` references
//! - the primitive list the grid owns: `N × size_of::<Prim>()` (80 B), alive throughout;
//! - one pass ([`GridParams::one_pass`], the default, while `M < 2³²`), all alive while the
//!   pairs are scattered into the lists (`lists_once`):
//!   - `pairs`, one `[u32; 2]` (voxel, primitive) per reference: `8E`;
//!   - `counts`, one `AtomicU32` per cell (the counters, then the fill cursors): `4M`;
//!   - `offsets`, the prefix sums: `4(M + 1)`;
//!   - `ids`, one `AtomicU32` per reference (turned into the `u32` lists in place): `4E`;
//!
//!   so `80N + 12E + 8M + 4` at the peak, and up to `min(8E, 32 MiB)` more
//!   ([`GROWTH_SLACK_CAP`]): the pairs are gathered in vectors that grow by doubling and are
//!   concatenated, and glibc's `realloc` copies a block below its mmap threshold (at most
//!   32 MiB) into a new one and keeps the old one's pages (blocks above it are moved by
//!   `mremap`, without a copy). Measured: a fresh process over `generate bundle --segments 84`
//!   peaked 31 MB over the buffers at 10⁶ links (36·10⁶ references) and 7 MB at 10⁵
//!   (1.4·10⁶), with 512² rays per build; 0 MB with 10⁵ rays on both;
//! - two passes (voxelize, count, voxelize again, `lists_twice`): `counts`, `offsets` and `ids`
//!   without the pairs, `80N + 4E + 8M + 4`;
//! - then `pairs` and `counts` are freed, and the occupancy levels are built: one `bool` per
//!   cell of each level ([`skip_dims`]), about `M/64` for the one default level. The finished
//!   grid is `80N + 4E + 4(M + 1) + levels`, exactly [`crate::accel::Tracer::memory_bytes`]
//!   with the grid's own `E` (a test checks it), and is never more than the lists' phase.
//!
//! Not counted: the voxel side's rounding of each axis up to whole voxels (in the dims, so
//! counted in `M`, but not in `E`, which takes the side the model chose); radii grown by the
//! margin `pad` (module docs, "Margin"; `D·2⁻¹⁶`, under 2 % of a 0.12 radius in a scene 120
//! across); the build's rebuild at a coarser resolution when `E > 2³²` (lists too long for `u32`
//! offsets), which then holds the pairs of the refused build no longer.

use super::build::skip_dims;
use super::resolution::resolution_for;
use super::{expected_references, GridParams, SceneSums};
use crate::scene::Prim;

/// Bytes of one primitive in the grid's list.
const PRIM_BYTES: f64 = std::mem::size_of::<Prim>() as f64;

/// The most the pairs' growth leaves resident besides them (module docs): glibc's largest mmap
/// threshold, `DEFAULT_MMAP_THRESHOLD_MAX` on 64-bit targets.
pub const GROWTH_SLACK_CAP: f64 = (32u64 << 20) as f64;

/// What a grid over a scene holds: its voxels and expected references, and the bytes of the
/// finished grid and of its build's peak (module docs of `footprint.rs`, in
/// [`GridParams::footprint`]'s source).
///
/// ```
/// use tubecast_render::accel::grid::{padded_extent, Grid, GridParams, SceneSums};
/// use tubecast_render::accel::Tracer;
/// use tubecast_render::scene::{generate, Scene};
/// let scene = Scene::from_polylines(&generate::bundle(40, 20, 1), 0.12, "bundle").unwrap();
/// let prims = scene.primitives();
/// let params = GridParams { rays_per_build: Some(65536.0), ..GridParams::default() };
/// let f = params.footprint(padded_extent(&prims), &SceneSums::of(&prims));
/// let grid = Grid::build_with(prims, &params);
/// assert_eq!(f.dims, grid.dims());
/// let e = grid.references() as f64 / f.references;
/// assert!(e > 0.8 && e < 1.25, "{e}");
/// assert!(f.build_bytes() > f.finished_bytes());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Footprint {
    /// Primitives `N`.
    pub prims: u64,
    /// Voxels along x, y, z (`M` = their product).
    pub dims: [u32; 3],
    /// (Voxel, primitive) references `E` (expected: [`expected_references`]).
    pub references: f64,
    /// Cells of the coarse occupancy levels, all together.
    pub level_cells: u64,
    /// Whether the lists are built in one pass (with the pairs).
    pub one_pass: bool,
}

impl Footprint {
    /// Voxels `M`.
    pub fn cells(&self) -> u64 {
        self.dims.iter().map(|&d| d as u64).product()
    }

    /// Bytes of the finished grid: `80N + 4E + 4(M + 1) + levels`.
    pub fn finished_bytes(&self) -> f64 {
        let m = self.cells() as f64;
        PRIM_BYTES * self.prims as f64 + 4.0 * self.references + 4.0 * (m + 1.0) + self.level_cells as f64
    }

    /// Bytes at the build's peak, while the lists are filled: `80N + 12E + 8M + 4` and the
    /// pairs' growth, `min(8E, 32 MiB)`, in one pass; `80N + 4E + 8M + 4` in two (or the
    /// finished grid, if that were more).
    pub fn build_bytes(&self) -> f64 {
        let (m, e) = (self.cells() as f64, self.references);
        let pairs = if self.one_pass { 8.0 * e + (8.0 * e).min(GROWTH_SLACK_CAP) } else { 0.0 };
        let lists = PRIM_BYTES * self.prims as f64 + pairs + 4.0 * m + 4.0 * (m + 1.0) + 4.0 * e;
        lists.max(self.finished_bytes())
    }
}

impl GridParams {
    /// What [`super::Grid::build_with`] with these parameters would build over `sums.count`
    /// primitives with the sums `sums` in a box of padded extents `ext`
    /// ([`super::padded_extent`]): the same resolution (the build's own code), the references
    /// Steiner's formula expects at its voxel side ([`expected_references`]), and the
    /// occupancy levels over its dims. Example at [`Footprint`].
    pub fn footprint(&self, ext: [f64; 3], sums: &SceneSums) -> Footprint {
        let (h, dims) = resolution_for(ext, sums.count, || *sums, self);
        let cells: u64 = dims.iter().map(|&d| d as u64).product();
        let references = if sums.count == 0 { 0.0 } else { expected_references(sums, h) };
        let level_cells =
            skip_dims(dims, self.skip_levels).iter().map(|d| d.iter().map(|&x| x as u64).product::<u64>()).sum();
        Footprint {
            prims: sums.count as u64,
            dims,
            references,
            level_cells,
            one_pass: self.one_pass && cells <= u32::MAX as u64,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::grid::{padded_extent, Grid, Voxelizer};
    use crate::accel::Tracer;
    use crate::scene::{generate, Scene};

    /// The scenes: a twisted bundle (long parallel links), Furball (short links in every
    /// direction), one link, and nothing.
    fn scenes() -> Vec<Vec<Prim>> {
        let of = |lines: &[crate::io::Polyline], r| Scene::from_polylines(lines, r, "t").unwrap().primitives();
        let link = crate::io::Polyline { points: vec![[0.0; 3], [3.0, 1.0, -2.0]], radii: vec![] };
        vec![of(&generate::bundle(60, 40, 3), 0.12), of(&generate::furball(80, 30, 5), 0.05), of(&[link], 0.5), vec![]]
    }

    fn params() -> Vec<GridParams> {
        let d = GridParams::default();
        vec![
            d,
            GridParams { rays_per_build: Some(1e4), ..d },
            GridParams { rays_per_build: Some(1e6), ..d },
            GridParams { cells_per_prim: Some(2.0), ..d },
            GridParams { one_pass: false, skip_levels: u32::MAX, ..d },
            GridParams { max_cells: 1000, ..d },
        ]
    }

    /// The footprint's resolution is the build's, bit for bit (the same code on the same sums),
    /// and with the build's own reference count its finished bytes are the grid's
    /// `memory_bytes` exactly.
    #[test]
    fn the_footprint_is_what_the_build_holds() {
        for prims in scenes() {
            for p in params() {
                let f = p.footprint(padded_extent(&prims), &SceneSums::of(&prims));
                let grid = Grid::build_with(prims.clone(), &p);
                assert_eq!((f.dims, f.prims), (grid.dims(), prims.len() as u64), "{p:?}");
                let built = Footprint { references: grid.references() as f64, ..f };
                assert_eq!(built.finished_bytes(), grid.memory_bytes() as f64, "{p:?}");
                assert!(built.build_bytes() >= built.finished_bytes());
                assert_eq!(built.level_cells, grid.skip.iter().map(|l| l.occupied.len() as u64).sum::<u64>());
            }
        }
    }

    /// The expected references against the build's count. Steiner's formula is the mean over
    /// random offsets and turns of the voxels a capsule meets; the voxelizer is conservative
    /// (more voxels than the solid meets, never fewer) and grows the radii by the margin, while
    /// links along an axis meet fewer voxels than a randomly turned one (`l/h` against `1.5·l/h`
    /// per unit length): the bundle runs along x. The lab's voxel sweep (`tubecast-lab voxel`)
    /// charts the ratio over scenes; a band of ±25 % holds both effects at these sizes and fails on a wrong term of `E`
    /// (without its `1.5Λ/h` term the bundle's static grid lists 1.93× the expectation).
    #[test]
    fn the_expected_references_are_near_the_built_ones() {
        for prims in scenes().into_iter().take(2) {
            for p in params().into_iter().filter(|p| p.voxelizer == Voxelizer::Conservative) {
                let f = p.footprint(padded_extent(&prims), &SceneSums::of(&prims));
                let grid = Grid::build_with(prims.clone(), &p);
                let ratio = grid.references() as f64 / f.references;
                assert!((0.75..=1.25).contains(&ratio), "{} prims, {p:?}: {ratio}", prims.len());
            }
        }
    }
}
