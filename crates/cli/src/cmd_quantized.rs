//! `render --model quantized` and `intersect --model quantized`: the scene replaced by Kanzler
//! et al.'s quantized lines ("model no more than the scene needs"), traced through the
//! ordinary accelerators.
//!
//! Each chain of links ([`Scene::chains`]) is one polyline; a grid of cubic voxels,
//! `--quant-voxels` along the longest side of the nodes' bounding box, cuts it at voxel faces,
//! and each piece becomes one segment whose ends snap to the centre of their bin on a
//! `Q × Q` face grid (`--quant-bins`, [`QuantizedLines`]). The segments, chained back into
//! polylines, are tubes of their chain's largest radius. No point of the quantized lines is
//! farther than the derived bound ([`QuantizedLines::max_bound`]) from the exact lines, nor the
//! other way round; with one radius the same holds between the two tube surfaces. Isolated
//! nodes (spheres) have no line and are dropped.

use crate::args::Surface;
use crate::error::CliError;
use clap::Args;
use std::fmt;
use std::ops::RangeInclusive;
use tubecast_render::quantized::{scene_lines, QuantizedLines};
use tubecast_render::scene::Scene;

/// Bins per face side that `--quant-bins` accepts (Kanzler et al.'s range).
pub const BINS: RangeInclusive<u32> = 8..=64;
/// Most voxels along the longest side (`--quant-voxels`).
pub const MAX_VOXELS: u32 = 4096;

/// The quantization options of `render` and `intersect`.
#[derive(Args, Clone, Copy, Debug)]
pub struct QuantArgs {
    /// With --model quantized: bins per voxel-face side Q (8 to 64) that line ends snap to.
    #[arg(long, value_name = "Q", default_value_t = 16)]
    pub quant_bins: u32,
    /// With --model quantized: voxels along the longest side of the scene (1 to 4096).
    #[arg(long, value_name = "N", default_value_t = 64)]
    pub quant_voxels: u32,
}

/// Why the quantized model cannot be built.
#[derive(Debug, Clone, PartialEq)]
pub enum QuantError {
    /// `--quant-bins` outside [`BINS`].
    Bins(u32),
    /// `--quant-voxels` outside `1..=MAX_VOXELS`.
    Voxels(u32),
    /// `--color scalar:/property:` with the quantized model (its lines carry no data).
    Data(String),
    /// `intersect --model mesh`.
    MeshIntersect,
}

impl fmt::Display for QuantError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Bins(q) => write!(f, "--quant-bins {q} must be in {}..={}", BINS.start(), BINS.end()),
            Self::Voxels(v) => write!(f, "--quant-voxels {v} must be in 1..={MAX_VOXELS}"),
            Self::Data(k) => write!(f, "--color {k}: the quantized lines carry no data fields; use direction or solid"),
            Self::MeshIntersect => f.write_str("intersect traces --model exact or quantized; mesh is for render"),
        }
    }
}

impl std::error::Error for QuantError {}

/// What the quantization did, for the summary line.
#[derive(Clone, Copy, Debug)]
pub struct Summary {
    /// Bins per face side.
    pub q: u32,
    /// Voxel side and voxels along x, y, z.
    pub h: f64,
    pub dims: [u32; 3],
    /// Links of the exact scene, segments of the quantized lines.
    pub links: usize,
    pub segments: usize,
    /// Derived Hausdorff bound (scene units).
    pub bound: f64,
    /// Packed bytes per segment, and in all (with a 4-byte offset per occupied voxel).
    pub bytes_per_segment: u32,
    pub bytes: usize,
    /// Bytes of the exact scene.
    pub exact_bytes: usize,
}

impl fmt::Display for Summary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let per_link = self.exact_bytes as f64 / self.links.max(1) as f64;
        write!(
            f,
            "quantized model: Q = {} bins per face side, {}×{}×{} voxels of side {:.4e}; {} segments from {} links; \
             derived Hausdorff bound {:.4e} (scene units); packed {} B per segment, {} B in all (+4 B per occupied \
             voxel), against the exact scene's {per_link:.1} B per link, {} B in all",
            self.q,
            self.dims[0],
            self.dims[1],
            self.dims[2],
            self.h,
            self.segments,
            self.links,
            self.bound,
            self.bytes_per_segment,
            self.bytes,
            self.exact_bytes
        )
    }
}

/// The scene a command traces for `--model`: `scene` itself (exact, mesh: render's own path),
/// or its quantized lines, whose summary is printed on stderr unless `quiet`.
pub fn model_scene(model: Surface, scene: Scene, q: &QuantArgs, quiet: bool) -> Result<Scene, CliError> {
    if model != Surface::Quantized {
        return Ok(scene);
    }
    let (out, summary) = quantize(&scene, q)?;
    if !quiet {
        eprintln!("tubecast: {summary}");
    }
    Ok(out)
}

/// Grid over the nodes: corner, side and voxels, `cells` along the longest side, every node
/// strictly inside.
fn grid(scene: &Scene, cells: u32) -> ([f64; 3], f64, [u32; 3]) {
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for n in &scene.nodes {
        for i in 0..3 {
            lo[i] = lo[i].min(n.pos[i]);
            hi[i] = hi[i].max(n.pos[i]);
        }
    }
    let ext = (0..3).map(|i| hi[i] - lo[i]).fold(0.0, f64::max);
    if ext <= 0.0 {
        return (lo.map(|x| if x.is_finite() { x - 0.5 } else { 0.0 }), 1.0, [1; 3]);
    }
    let h = ext / cells as f64 * (1.0 + 1e-9);
    let dims = std::array::from_fn(|i| (((hi[i] - lo[i]) / h).floor() as u32 + 1).min(cells));
    (lo, h, dims)
}

/// The quantized lines of `scene`'s chains as a scene, and what it cost ([`Summary`]).
pub fn quantize(scene: &Scene, a: &QuantArgs) -> Result<(Scene, Summary), CliError> {
    if !BINS.contains(&a.quant_bins) {
        return Err(QuantError::Bins(a.quant_bins).into());
    }
    if a.quant_voxels == 0 || a.quant_voxels > MAX_VOXELS {
        return Err(QuantError::Voxels(a.quant_voxels).into());
    }
    let (lines, radius) = scene_lines(scene);
    let (lo, h, dims) = grid(scene, a.quant_voxels);
    let ql = QuantizedLines::new(&lines, lo, h, dims, a.quant_bins);
    drop(lines);
    let occupied: std::collections::HashSet<[u32; 3]> = ql.segments.iter().map(|s| s.voxel).collect();
    let summary = Summary {
        q: ql.q,
        h,
        dims,
        links: scene.links.len(),
        segments: ql.segments.len(),
        bound: ql.max_bound(),
        bytes_per_segment: ql.bytes_per_segment(),
        bytes: ql.bytes_per_segment() as usize * ql.segments.len() + 4 * occupied.len(),
        exact_bytes: scene.memory_bytes(),
    };
    let polylines = ql.polylines_with(|line| radius[line as usize]);
    let fallback = radius.iter().copied().fold(0.0, f64::max);
    let out = Scene::from_polylines(&polylines, if fallback > 0.0 { fallback } else { 1.0 }, "quantized lines")?;
    Ok((out, summary))
}
