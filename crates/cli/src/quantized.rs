//! `--model quantized` (`render`, `intersect`, `info`): the scene replaced by Kanzler
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

use crate::args::{QuantArgs, Surface};
use crate::error::CliError;
use std::fmt;
use tubecast_render::quantized::{scene_lines, QuantizedLines};
use tubecast_render::scene::Scene;

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

/// The quantized lines of `scene`'s chains as a scene, and what it cost ([`Summary`]); the
/// resolution was range-checked as it was parsed ([`QuantArgs`]).
pub fn quantize(scene: &Scene, a: &QuantArgs) -> Result<(Scene, Summary), CliError> {
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
