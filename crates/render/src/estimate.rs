//! The memory a scene will need, known before it is loaded: counts from the file's header and
//! size ([`probe`]), bytes per link measured on a sample built the same way ([`PerLink`]), what
//! the command builds besides ([`Work`]), and the memory there is ([`available`]). The command
//! line refuses, before allocating, a scene that would not fit ([`check_with`]), naming the
//! figures and the options that help.
//!
//! # The model
//! A command's peak is the largest of its phases, each the sum of what is alive then, plus
//! [`BASE_BYTES`] and the image ([`PIXEL_BYTES`] per pixel, `render` only). With `scene` and
//! `tracer` the bytes per link of [`crate::scene::Scene::memory_bytes`] and
//! [`crate::accel::Tracer::memory_bytes`] measured on a sample of the file (so they follow any
//! change of the layouts), and `scene'` the scene plus, when `render` clamps thin tubes
//! ([`crate::render::clamp_thin`]), a radius and a coverage per node ([`THIN_BYTES_PER_NODE`]):
//! - **the compact tree** (`info`, `intersect`, `render`; the CLI's `--accel bvh` over links),
//!   built in chunks: `links × (scene' + tracer × (1 + BUILD_OVERHEAD)) + min(links,
//!   BUILD_ITEMS) × BUILD_BYTES_PER_ITEM` ([`BUILD_OVERHEAD`]: the share of the tracer's size its
//!   build holds on top of it, the runs' heads and the tables in item order;
//!   [`BUILD_BYTES_PER_ITEM`]: the tree builder's buffers per item it builds at once, at most
//!   [`BUILD_ITEMS`]);
//! - **a tracer built whole over a primitive list** (`--accel bvh2`, the spline model):
//!   `links × (scene' + tracer + WHOLE_BUILD_BYTES)`: these builds are not chunked, so the
//!   builder's share ([`WHOLE_BUILD_BYTES`]) grows with every link;
//! - **the voxel grid** (`--accel grid`, [`Work::grid`]): `links × scene' +` the grid build's
//!   peak ([`Footprint::build_bytes`]: its primitives, pairs, counters, offsets and lists), at
//!   the resolution the build will choose for the whole scene ([`grid_footprint`]). A grid's
//!   bytes per link are not those of a sample: its cells and references per link depend on the
//!   link count, the box and the rays per build, so a sample's grid (built at the sample's own,
//!   coarser, resolution) said 0.49 GB where `render --accel grid` at 10⁶ links peaked at
//!   0.61 GB;
//! - **`render`'s primitive list** (every path but the compact tree's exact one, which takes
//!   the bounds from the scene one primitive at a time and builds from the scene alone):
//!   `render` computes one [`crate::scene::Prim`] per link ([`PRIM_BYTES`]) for the scene's
//!   bounds and after the clamp, beside `scene'`: `links × (scene' + PRIM_BYTES)`.

use crate::accel::grid::{Footprint, GridParams, SceneSums};
use crate::io::stream::{open, Selection};
use crate::io::{self, IoError};
use std::fmt;
use std::io::BufRead;
use std::path::Path;

/// Extra bytes the compact tree's build holds at its peak, as a share of the finished tracer's
/// [`crate::accel::Tracer::memory_bytes`], besides the builder's buffers
/// ([`BUILD_BYTES_PER_ITEM`]): while the chunks are built, the runs' heads (32 B per run of up
/// to eight links), the pieces' table and Morton keys (8 B per link each) and the chunks'
/// trees; while the clusters' nodes are stored in leaf order, the heads and the leaf order's
/// tables (about 5 B per link). The clusters' nodes are stored once, after the tree is built
/// (`accel::cluster`'s `Pending`): stored in run order and copied into leaf order they would be
/// held twice at once, and this share would be 1.0. Fitted with the builder's buffers to
/// the peaks of `TUBECAST_PEAK_RSS=1 tubecast info FILE --radius 0.12` on `generate bundle
/// --segments 84` scenes (plain release build, `VmHWM`; 24.4 B scene and 32.8 B tree per
/// link): 1150 MB at 10⁷ links is 50 B per link over the scene and 215 B per item of the
/// builder (2²¹ items); rounded up to a quarter of the tracer (see the tests for every row).
pub const BUILD_OVERHEAD: f64 = 0.25;

/// Bytes the tree builder holds per item it builds at once (obvhs's PLOC arrays, its binary
/// tree, the 8-wide conversion's cost table, the items' boxes): fitted as 215–218 B (see
/// [`BUILD_OVERHEAD`]), rounded up.
pub const BUILD_BYTES_PER_ITEM: f64 = 300.0;

/// Items the compact tree's builder holds at once at most: [`crate::accel::CHUNKS_AT_ONCE`]
/// chunks of [`crate::accel::CHUNK`] (one item per link).
pub const BUILD_ITEMS: u64 = (crate::accel::CHUNK * crate::accel::CHUNKS_AT_ONCE) as u64;

/// Bytes a process needs whatever the scene (code, thread stacks, buffers).
pub const BASE_BYTES: u64 = 16 << 20;

/// Bytes the thin-tube clamp adds per node: the scene then stores one `f64` radius per node
/// (instead of one shared radius) and an `f32` coverage ([`crate::render::clamp_thin`]).
pub const THIN_BYTES_PER_NODE: f64 = 12.0;

/// Bytes of one primitive in a list ([`crate::scene::Prim`], `render`'s list of the scene's
/// primitives).
pub const PRIM_BYTES: f64 = std::mem::size_of::<crate::scene::Prim>() as f64;

/// Bytes per link a tracer built whole over its primitive list (obvhs's binary BVH) holds
/// during its build beyond its finished size (builder arrays, item boxes): fitted to the peaks
/// of `tubecast intersect` and `render` with `--accel bvh2` at 10⁶ links (see the tests: 185 B;
/// the former λ = 2 grid needed 267 B), rounded up. The grid has its own model
/// ([`Work::grid`]).
pub const WHOLE_BUILD_BYTES: f64 = 280.0;

/// Bytes of one ray `intersect` holds (a [`tubecast::Ray`] in `f64`).
pub const RAY_BYTES: u64 = std::mem::size_of::<tubecast::Ray<f64>>() as u64;

/// The references a grid lists over Steiner's expectation ([`grid_footprint`]): the voxelizer is
/// conservative (it lists every voxel the padded solid may meet) and grows the radii by the
/// margin; the lab's voxel sweep and `generate bundle` at 10⁶ links list at most this factor
/// over the expectation (the voxel report's `refs / E(h)` column, `tubecast-lab voxel`).
pub const GRID_REFERENCE_MARGIN: f64 = 1.08;

/// Bytes per pixel of `render`'s image: linear RGB, alpha and depth (24 B, [`crate::render::
/// Image`]) and the 8-bit RGB(A) copy written to the PNG (3–4 B), rounded up.
pub const PIXEL_BYTES: u64 = 32;

/// What a command builds and holds besides the scene ([module docs](self)).
///
/// ```
/// use tubecast_render::estimate::{PerLink, Work};
/// let per_link = PerLink { scene: 24.4, tracer: 33.0 };
/// let render = Work { thin_nodes: 85.0 / 84.0, pixels: 512 * 512, ..Work::INFO };
/// // render's clamp of thin tubes stores 12 B more per node beside the scene.
/// let (info, r) = (per_link.needed_for(100_000_000, &Work::INFO), per_link.needed_for(100_000_000, &render));
/// assert!(r > info + 100_000_000.0 * 12.0);
/// // With --accel bvh2 render holds a list of 80-byte primitives besides.
/// let bvh2 = Work { compact: false, prim_list: true, ..render };
/// assert!(per_link.needed_for(100_000_000, &bvh2) > r + 100_000_000.0 * 80.0);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Work {
    /// The tracer is the compact tree, built in chunks (`false`: a tracer built whole over a
    /// primitive list, `--accel bvh2` or `grid`, or the spline model).
    pub compact: bool,
    /// The command holds a list of the scene's primitives beside the scene before building
    /// (`render`, except with the compact tree over links and exact surfaces).
    pub prim_list: bool,
    /// Nodes per link whose radius and coverage the thin-tube clamp stores (0: no clamp).
    pub thin_nodes: f32,
    /// Pixels of the image (0: no image).
    pub pixels: u64,
    /// The voxel grid the command builds over the whole scene (`--accel grid`,
    /// [`grid_footprint`]), whose build's peak replaces the tracer's bytes per link
    /// (`compact` is then `false`).
    pub grid: Option<Footprint>,
    /// Rays the command holds ([`RAY_BYTES`] each; `intersect`'s table of rays).
    pub rays: u64,
}

impl Work {
    /// `info`: the compact tree, nothing else.
    pub const INFO: Work = Work { compact: true, prim_list: false, thin_nodes: 0.0, pixels: 0, grid: None, rays: 0 };
}

/// The grid that `--accel grid` will build over `links` links, from a sample of the file: the
/// sample's primitive sums `sample` ([`SceneSums::of`]) over its `sample_links` links, scaled to
/// `links`, in the sample's padded box `ext` ([`crate::accel::grid::padded_extent`]), at the
/// resolution `params` (the command's rays per build) chooses for them
/// ([`GridParams::footprint`], the build's own resolution code), with
/// [`GRID_REFERENCE_MARGIN`] times Steiner's expected references.
///
/// The whole scene's box is not known before it is loaded; the sample's stands in. A sample
/// whose box is smaller than the scene's over-estimates: at a fixed link count a smaller box
/// packs the same links denser, and the cost models choose more cells and references per link
/// there (`the_grid_model_takes_more_in_a_smaller_box` checks it on the bundle's statistics).
///
/// ```
/// use tubecast_render::accel::grid::{padded_extent, GridParams, SceneSums};
/// use tubecast_render::estimate::grid_footprint;
/// use tubecast_render::scene::{generate, Scene};
/// let prims = Scene::from_polylines(&generate::bundle(200, 84, 1), 0.12, "sample").unwrap().primitives();
/// let (sums, ext) = (SceneSums::of(&prims), padded_extent(&prims));
/// let params = GridParams { rays_per_build: Some(512.0 * 512.0), ..GridParams::default() };
/// let big = grid_footprint(&sums, 16_800, ext, 1_000_020, &params);
/// assert_eq!(big.prims, 1_000_020);
/// assert!(big.cells() > params.footprint(ext, &sums).cells()); // finer than the sample's grid
/// ```
pub fn grid_footprint(
    sample: &SceneSums,
    sample_links: u64,
    ext: [f64; 3],
    links: u64,
    params: &GridParams,
) -> Footprint {
    let k = links as f64 / sample_links.max(1) as f64;
    let sums = SceneSums {
        count: (sample.count as f64 * k).round() as usize,
        length: sample.length * k,
        radius: sample.radius * k,
        cross: sample.cross * k,
        solid: sample.solid * k,
    };
    let f = params.footprint(ext, &sums);
    Footprint { references: f.references * GRID_REFERENCE_MARGIN, ..f }
}

/// What a file holds, from its header and size, without reading its body.
///
/// ```
/// use tubecast_render::estimate::{check, Counts, PerLink};
/// use tubecast_render::io::stream::Selection;
/// let c = Counts { streamlines: Some(10), points: 1010 };
/// assert_eq!(c.links(&Selection::default(), None), 1000);
/// let per_link = PerLink { scene: 48.0, tracer: 90.0 };
/// let e = check("big.trk", (100_000_000, Some(10)), per_link, (8 << 30, "MemAvailable".into())).unwrap_err();
/// assert!(e.to_string().contains("--subsample"));
/// assert!(e.needed > 8 << 30);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Counts {
    /// Streamlines, when the header says (`None`: SWC, OBJ, a `.trk` with `n_count` 0, a
    /// `.tck` whose `count` does not fit its size).
    pub streamlines: Option<u64>,
    /// Points (nodes): exact for `.trk` with `n_count` and `.trx`, an upper bound otherwise.
    pub points: u64,
}

impl Counts {
    /// Links of the streamlines `sel` keeps: `(points − streamlines) × share` (an SWC tree or
    /// unknown streamlines: `points × share`), with `avg_points` (points per streamline of a
    /// sample) standing in for an unknown streamline count.
    pub fn links(&self, sel: &Selection, avg_points: Option<f64>) -> u64 {
        let lines = self.lines(avg_points);
        let share = sel.fraction(lines.unwrap_or(0));
        (self.points.saturating_sub(lines.unwrap_or(0)) as f64 * share).ceil() as u64
    }

    /// Streamlines: the header's count, or points / `avg_points` (a sample's points per
    /// streamline); `None` when neither is known.
    pub fn lines(&self, avg_points: Option<f64>) -> Option<u64> {
        let guess = || avg_points.filter(|&a| a >= 1.0).map(|a| (self.points as f64 / a) as u64);
        self.streamlines.or_else(guess)
    }

    /// Streamlines `sel` keeps ([`Self::lines`] × its share), when known.
    pub fn kept_lines(&self, sel: &Selection, avg_points: Option<f64>) -> Option<u64> {
        self.lines(avg_points).map(|n| (n as f64 * sel.fraction(n)).round() as u64)
    }
}

/// The counts of the file at `path` (by extension), from its header and length; SWC and OBJ
/// files are read line by line (nothing kept) to count their nodes / vertices.
pub fn probe(path: &Path) -> Result<Counts, IoError> {
    let name = path.display().to_string();
    let (mut r, len) = open(path)?;
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
    Ok(match ext.as_str() {
        "trk" => {
            let info = io::trk::read_info(&mut r, &name)?;
            let per_point = 4 * (3 + info.header.n_scalars as u64);
            let n = info.n_count as u64;
            let fixed = 1000 + n * info.streamline_bytes(0);
            Counts { streamlines: (n > 0).then_some(n), points: len.saturating_sub(fixed) / per_point }
        }
        "tck" => {
            let info = io::tck::read_info(&mut r, &name, Some(len))?;
            let triplets = len.saturating_sub(info.offset) / 12;
            // Each streamline: its points and a NaN triplet; then one Inf triplet.
            match info.count.filter(|&c| c > 0 && 2 * c < triplets) {
                Some(c) => Counts { streamlines: Some(c), points: triplets - c - 1 },
                None => Counts { streamlines: None, points: triplets },
            }
        }
        "trx" => {
            let (ns, nv) = io::trx::read_counts(r, &name)?;
            Counts { streamlines: Some(ns as u64), points: nv as u64 }
        }
        _ => {
            let tag: &[u8] = if ext == "obj" { b"v " } else { b"" };
            Counts { streamlines: None, points: count_lines(r, &name, tag)? }
        }
    })
}

/// Lines of `r` that are not blank or comments (`#`) and start with `tag`.
fn count_lines(mut r: impl BufRead, name: &str, tag: &[u8]) -> Result<u64, IoError> {
    let (mut n, mut buf) = (0, Vec::new());
    loop {
        buf.clear();
        let got = r.read_until(b'\n', &mut buf).map_err(|e| IoError::file(name, format!("cannot read: {e}")))?;
        if got == 0 {
            return Ok(n);
        }
        let t = buf.trim_ascii_start();
        n += (!t.is_empty() && t[0] != b'#' && t.starts_with(tag)) as u64;
    }
}

/// Bytes per link measured on a sample: of the scene, and of the tracer over its primitives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PerLink {
    /// [`crate::scene::Scene::memory_bytes`] per link.
    pub scene: f64,
    /// [`crate::accel::Tracer::memory_bytes`] per link.
    pub tracer: f64,
}

impl PerLink {
    /// Peak bytes per link of loading and building the compact tree, the builder's buffers
    /// aside ([module docs](self)).
    pub fn peak(&self) -> f64 {
        self.scene + self.tracer * (1.0 + BUILD_OVERHEAD)
    }

    /// Peak bytes of loading and building `links` links for `info`, the base aside ([module
    /// docs](self)).
    pub fn needed(&self, links: u64) -> f64 {
        links as f64 * self.peak() + links.min(BUILD_ITEMS) as f64 * BUILD_BYTES_PER_ITEM
    }

    /// Peak bytes of `work` on `links` links, the base aside: the largest of its phases
    /// ([module docs](self)), plus its image.
    pub fn needed_for(&self, links: u64, work: &Work) -> f64 {
        let n = links as f64;
        let scene = self.scene + THIN_BYTES_PER_NODE * work.thin_nodes as f64;
        let build = match (work.compact, work.grid) {
            (true, _) => {
                n * (scene + self.tracer * (1.0 + BUILD_OVERHEAD))
                    + links.min(BUILD_ITEMS) as f64 * BUILD_BYTES_PER_ITEM
            }
            (false, Some(g)) => n * scene + g.build_bytes(),
            (false, None) => n * (scene + self.tracer + WHOLE_BUILD_BYTES),
        };
        let list = if work.prim_list { n * (scene + PRIM_BYTES) } else { 0.0 };
        build.max(list) + (work.pixels * PIXEL_BYTES + work.rays * RAY_BYTES) as f64
    }
}

/// A scene too large for the memory there is.
#[derive(Clone, Debug, PartialEq)]
pub struct TooLarge {
    /// The input file.
    pub file: String,
    /// Links the load would keep.
    pub links: u64,
    /// Streamlines it would keep, when known.
    pub streamlines: Option<u64>,
    /// Bytes per link (scene, tracer).
    pub per_link: PerLink,
    /// What the command builds besides the scene.
    pub work: Box<Work>,
    /// Estimated peak bytes.
    pub needed: u64,
    /// The bytes there are, and where that figure comes from.
    pub available: (u64, String),
}

impl TooLarge {
    /// How the peak is made up, in words, and the options of the command that lower it.
    fn parts(&self) -> (String, String) {
        let (w, p) = (&*self.work, &self.per_link);
        let mut how = format!("scene {:.1} B + primitives and tree {:.1} B", p.scene, p.tracer);
        let mut help = String::new();
        if w.thin_nodes > 0.0 {
            how += &format!(" + {:.0} B per node for the thin-tube clamp", THIN_BYTES_PER_NODE);
            help += ", --thin off";
        }
        let n = self.links as f64;
        let scene = n * (p.scene + THIN_BYTES_PER_NODE * w.thin_nodes as f64);
        if w.compact {
            how += &format!(
                ", built with {:.0}% more and {:.0} B per link built at once",
                100.0 * BUILD_OVERHEAD,
                BUILD_BYTES_PER_ITEM
            );
        } else if let Some(g) = w.grid {
            let more = (g.build_bytes() - g.finished_bytes()) / n.max(1.0);
            how += &format!(", a grid of {} voxels built whole with {more:.0} B more per link", g.cells());
            help += ", --accel bvh (built in chunks)";
        } else {
            how += &format!(", built whole with {WHOLE_BUILD_BYTES:.0} B more per link");
            help += ", --accel bvh (built in chunks)";
        }
        let build = p.needed_for(self.links, &Work { prim_list: false, pixels: 0, ..*w });
        if w.prim_list && scene + n * PRIM_BYTES > build {
            how +=
                &format!("; at the peak the list of primitives, {PRIM_BYTES:.0} B per link, is held beside the scene");
        }
        (how, help)
    }
}

impl fmt::Display for TooLarge {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let gib = |b: u64| b as f64 / (1u64 << 30) as f64;
        // The share of the links that fits, with a tenth to spare (at least 0.001).
        let room = self.available.0.saturating_sub(BASE_BYTES) as f64;
        let share = (room / self.needed.saturating_sub(BASE_BYTES).max(1) as f64 * 0.9).clamp(0.001, 1.0);
        let share = (share * 1000.0).floor() / 1000.0;
        let n = match self.streamlines {
            Some(s) => format!("N ≤ {}", (s as f64 * share) as u64),
            None => "N".to_string(),
        };
        let per = self.needed.saturating_sub(BASE_BYTES) as f64 / self.links.max(1) as f64;
        let (how, help) = self.parts();
        write!(
            f,
            "{}: the scene needs about {:.2} GiB ({} links × {per:.0} B: {how}), more than the {:.2} GiB available ({}); \
             load a part of it with --subsample F (F ≤ {share}) or --max-streamlines {n}{help}, \
             or set --memory-limit BYTES",
            self.file,
            gib(self.needed),
            self.links,
            gib(self.available.0),
            self.available.1,
        )
    }
}

impl std::error::Error for TooLarge {}

/// Refuse `(links, streamlines)` (the streamlines kept, when known) at `per_link` when the
/// estimated peak of `info` exceeds `available`; the estimate in bytes otherwise
/// ([`check_with`] for other commands).
pub fn check(
    file: &str,
    kept: (u64, Option<u64>),
    per_link: PerLink,
    available: (u64, String),
) -> Result<u64, TooLarge> {
    check_with(file, kept, per_link, Work::INFO, available)
}

/// Refuse `(links, streamlines)` (the streamlines kept, when known) at `per_link` when the
/// estimated peak of `work` ([`PerLink::needed_for`]) exceeds `available`; the estimate in
/// bytes otherwise.
pub fn check_with(
    file: &str,
    (links, streamlines): (u64, Option<u64>),
    per_link: PerLink,
    work: Work,
    available: (u64, String),
) -> Result<u64, TooLarge> {
    let needed = per_link.needed_for(links, &work) as u64 + BASE_BYTES;
    if needed > available.0 {
        return Err(TooLarge {
            file: file.to_string(),
            links,
            streamlines,
            per_link,
            work: Box::new(work),
            needed,
            available,
        });
    }
    Ok(needed)
}

/// The memory this process may still use: `MemAvailable` of `/proc/meminfo`, lowered to the
/// cgroup's `memory.max − memory.current` where a (v2) limit is set; `None` where neither is
/// readable (not Linux).
pub fn available() -> Option<(u64, String)> {
    let read = |p: &str| std::fs::read_to_string(p).ok();
    let meminfo = read("/proc/meminfo")?;
    let kib = meminfo.lines().find_map(|l| l.strip_prefix("MemAvailable:"))?;
    let mut best = (kib.trim().trim_end_matches("kB").trim().parse::<u64>().ok()? * 1024, "MemAvailable".to_string());
    let num = |p: &str| read(p).and_then(|s| s.trim().parse::<u64>().ok());
    if let (Some(max), Some(cur)) = (num("/sys/fs/cgroup/memory.max"), num("/sys/fs/cgroup/memory.current")) {
        if max.saturating_sub(cur) < best.0 {
            best = (max.saturating_sub(cur), "cgroup memory.max − memory.current".to_string());
        }
    }
    Some(best)
}

#[cfg(test)]
mod tests;
