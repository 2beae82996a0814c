//! Kanzler et al.'s level of detail over quantized lines (2018, Sec. 3.4): per voxel and level,
//! an opacity (how much light the voxel's lines block) and one representative line.
//!
//! * **Opacity.** At level 0 a voxel of side `h` holding segments of lengths `lᵢ` of tubes of
//!   radius `r` gets `α = min(1, Σ 2r·lᵢ / h²)`: the tubes' projected area over a face's area,
//!   the share of light they block when it falls across them and they do not overlap (Kanzler's
//!   Eq. 1 is this length-weighted sum, scaled to an opacity). A coarser voxel averages its 2³
//!   children (missing ones beyond the grid count as empty), as the paper's octree does.
//! * **Representative line.** The ends of the voxel's segments are averaged separately, each
//!   segment flipped first when it points more than 90° away from the running sum of directions,
//!   and both averages are snapped to the centre of their bin on the nearest voxel face. A
//!   coarser voxel averages its children's representative lines the same way, weighted by the
//!   number of lines each represents. Its radius keeps the projected area:
//!   `r_rep = min(H/2, r·Σlᵢ / l_rep)` (`H` the level's voxel side, `Σlᵢ` the represented length),
//!   "one single yet thicker line to represent many thinner lines".
//! * **Joining across faces.** Then, as the paper "attempts to establish connectivity between
//!   representative lines in adjacent voxels if their endpoints are in the same voxel face", at
//!   every level: where two non-empty voxels share a face and each one's representative line
//!   has exactly one end on it, both ends move to the centre of the face bin into which their
//!   average falls, so the two lines meet there (the radius is recomputed for the new length).
//!   A line with both ends on the shared face is left alone (which end would join is
//!   ambiguous). Coarser levels average the joined lines. Counts, represented lengths and
//!   opacities do not change.
//!
//! Shadow and AO rays are traced against the representative lines of a chosen level
//! ([`Lod::polylines`] → a scene), the paper's first approach; the opacities feed cone tracing.

use super::QuantizedLines;
use crate::io::Polyline;
use tubecast::V3;

/// One voxel's representative line at some level (world coordinates).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RepLine {
    /// Voxel `[i, j, k]` at its level.
    pub voxel: [u32; 3],
    /// Averaged, snapped start.
    pub a: [f64; 3],
    /// Averaged, snapped end.
    pub b: [f64; 3],
    /// Number of original segments it represents.
    pub count: u32,
    /// Total length of the original segments it represents.
    pub length: f64,
    /// Tube radius that keeps their projected area (capped at half a voxel).
    pub radius: f64,
}

/// One level: voxel side, dimensions, dense per-voxel opacities (x fastest) and the
/// representative lines of the non-empty voxels.
#[derive(Clone, Debug)]
pub struct LodLevel {
    /// Voxel side.
    pub h: f64,
    /// Voxels along x, y, z.
    pub dims: [u32; 3],
    /// Opacity per voxel in `[0, 1]`.
    pub opacity: Vec<f32>,
    /// Representative lines, one per non-empty voxel, by voxel index.
    pub lines: Vec<RepLine>,
}

/// Kanzler's LoD over [`QuantizedLines`]: level 0 at the quantization voxels, each next level
/// with voxels twice as large, down to one voxel.
///
/// ```
/// use tubecast_render::io::Polyline;
/// use tubecast_render::quantized::{Lod, QuantizedLines};
/// let lines: Vec<Polyline> = (0..4)
///     .map(|k| Polyline { points: vec![[0.1, 0.2 + 0.1 * k as f64, 0.5], [3.9, 0.3 + 0.1 * k as f64, 0.5]], radii: vec![] })
///     .collect();
/// let q = QuantizedLines::new(&lines, [0.0; 3], 1.0, [4, 1, 1], 16);
/// let lod = Lod::build(&q, 0.05);
/// assert_eq!(lod.levels.len(), 3); // 4, 2, 1 voxels along x
/// assert_eq!(lod.levels[0].lines[1].count, 4); // four lines cross voxel 1
/// assert!(lod.levels[2].lines[0].radius > 0.05); // one thicker line for all of them
/// ```
#[derive(Clone, Debug)]
pub struct Lod {
    /// Grid corner (world).
    pub lo: [f64; 3],
    /// Bins per face side.
    pub q: u32,
    /// Levels, finest first.
    pub levels: Vec<LodLevel>,
}

/// Running average of oriented segments.
#[derive(Clone, Copy, Default)]
struct Acc {
    a: V3<f64>,
    b: V3<f64>,
    w: f64,
    count: u32,
    length: f64,
}

impl Acc {
    /// Adds a segment `a → b` of weight `w`, flipped when it opposes the running direction.
    fn add(&mut self, a: V3<f64>, b: V3<f64>, w: f64, count: u32, length: f64) {
        let (a, b) = if self.w > 0.0 && (b - a).dot(self.b - self.a) < 0.0 { (b, a) } else { (a, b) };
        self.a += a * w;
        self.b += b * w;
        self.w += w;
        self.count += count;
        self.length += length;
    }
}

/// Snaps `x` (world) to the centre of its bin on the nearest face of the voxel `c` of side `h`
/// of the grid at `lo`, with `q` bins per face side.
fn snap(x: V3<f64>, lo: [f64; 3], h: f64, c: [u32; 3], q: u32) -> [f64; 3] {
    let local: [f64; 3] = std::array::from_fn(|i| ((x.to_array()[i] - lo[i]) / h - c[i] as f64).clamp(0.0, 1.0));
    let (mut axis, mut side, mut best) = (0, 0.0, f64::INFINITY);
    for (i, &u) in local.iter().enumerate() {
        for (s, d) in [(0.0, u), (1.0, 1.0 - u)] {
            if d < best {
                (axis, side, best) = (i, s, d);
            }
        }
    }
    let qf = q as f64;
    std::array::from_fn(|i| {
        let u = if i == axis { side } else { ((local[i] * qf).floor().min(qf - 1.0) + 0.5) / qf };
        lo[i] + (c[i] as f64 + u) * h
    })
}

impl LodLevel {
    fn index(&self, c: [u32; 3]) -> usize {
        (c[0] as usize) + self.dims[0] as usize * (c[1] as usize + self.dims[1] as usize * c[2] as usize)
    }

    /// Representative lines from the accumulators of the non-empty voxels.
    fn finish(&mut self, accs: Vec<([u32; 3], Acc)>, lo: [f64; 3], q: u32, r: f64) {
        for (c, acc) in accs {
            let (a, b) = (acc.a * (1.0 / acc.w), acc.b * (1.0 / acc.w));
            let (a, b) = (snap(a, lo, self.h, c, q), snap(b, lo, self.h, c, q));
            let radius = rep_radius(r, acc.length, (V3::from(b) - V3::from(a)).length(), self.h);
            self.lines.push(RepLine { voxel: c, a, b, count: acc.count, length: acc.length, radius });
        }
    }
}

impl LodLevel {
    /// The face (0–5: −x, +x, −y, +y, −z, +z) of voxel `c` that the point `p` lies on, when
    /// exactly one does (a corner or edge point lies on several: `None`).
    fn face_of(&self, p: [f64; 3], lo: [f64; 3], c: [u32; 3]) -> Option<usize> {
        let mut found = None;
        for i in 0..3 {
            let u = (p[i] - lo[i]) / self.h - c[i] as f64;
            for (side, at) in [(0, 0.0), (1, 1.0)] {
                if (u - at).abs() <= 1e-9 {
                    if found.is_some() {
                        return None;
                    }
                    found = Some(2 * i + side);
                }
            }
        }
        found
    }

    /// Joins representative lines across shared faces (module docs).
    fn join(&mut self, lo: [f64; 3], q: u32, r: f64) {
        let at: std::collections::HashMap<[u32; 3], usize> =
            self.lines.iter().enumerate().map(|(k, l)| (l.voxel, k)).collect();
        // The one end (0: a, 1: b) of line k on face f, if exactly one lies on it.
        let end_on = |lev: &Self, k: usize, f: usize| {
            let l = &lev.lines[k];
            let on = [lev.face_of(l.a, lo, l.voxel) == Some(f), lev.face_of(l.b, lo, l.voxel) == Some(f)];
            match on {
                [true, false] => Some(0),
                [false, true] => Some(1),
                _ => None,
            }
        };
        for k in 0..self.lines.len() {
            for axis in 0..3 {
                let mut c = self.lines[k].voxel;
                c[axis] += 1;
                let Some(&j) = at.get(&c) else { continue };
                let (Some(ek), Some(ej)) = (end_on(self, k, 2 * axis + 1), end_on(self, j, 2 * axis)) else { continue };
                let (pk, pj) = (self.lines[k].end(ek), self.lines[j].end(ej));
                let mid: [f64; 3] = std::array::from_fn(|i| 0.5 * (pk[i] + pj[i]));
                let p = snap(V3::from(mid), lo, self.h, self.lines[k].voxel, q);
                self.lines[k].set_end(ek, p, self.h, r);
                self.lines[j].set_end(ej, p, self.h, r);
            }
        }
    }
}

impl RepLine {
    fn end(&self, e: usize) -> [f64; 3] {
        if e == 0 {
            self.a
        } else {
            self.b
        }
    }

    /// Moves end `e` to `p` and recomputes the radius that keeps the projected area.
    fn set_end(&mut self, e: usize, p: [f64; 3], h: f64, r: f64) {
        if e == 0 {
            self.a = p;
        } else {
            self.b = p;
        }
        self.radius = rep_radius(r, self.length, (V3::from(self.b) - V3::from(self.a)).length(), h);
    }
}

/// `min(H/2, r·Σl/l_rep)`, at least `r` (`r` for a zero-length line).
fn rep_radius(r: f64, length: f64, l: f64, h: f64) -> f64 {
    if l > 0.0 {
        (r * length / l).min(h / 2.0).max(r)
    } else {
        r
    }
}

impl Lod {
    /// The LoD of `q`'s segments as tubes of radius `r` (see the module docs).
    pub fn build(q: &QuantizedLines, r: f64) -> Self {
        Self::build_with(q, r, true)
    }

    /// [`Lod::build`], joining representative lines across shared faces only with `join`.
    ///
    /// ```
    /// use tubecast_render::io::Polyline;
    /// use tubecast_render::quantized::{Lod, QuantizedLines};
    /// // Line A crosses the face x = 1 at y = 0.2 (bin 1 of 8); line C starts just inside voxel 1
    /// // at y = 0.95: voxel 0's averaged line ends at y = 0.1875, voxel 1's starts at 0.5625.
    /// let lines = vec![
    ///     Polyline { points: vec![[0.5, 0.2, 0.5], [1.5, 0.2, 0.5]], radii: vec![] },
    ///     Polyline { points: vec![[1.05, 0.95, 0.5], [1.9, 0.95, 0.5]], radii: vec![] },
    /// ];
    /// let q = QuantizedLines::new(&lines, [0.0; 3], 1.0, [2, 1, 1], 8);
    /// let (apart, joined) = (Lod::build_with(&q, 0.01, false), Lod::build(&q, 0.01));
    /// let (a0, a1) = (&apart.levels[0].lines[0], &apart.levels[0].lines[1]);
    /// assert_eq!((a0.b[1], a1.a[1]), (0.1875, 0.5625));
    /// let (l0, l1) = (&joined.levels[0].lines[0], &joined.levels[0].lines[1]);
    /// assert_eq!(l0.b, l1.a); // joined on the face x = 1, in the bin of the mean y = 0.375
    /// assert_eq!(l0.b, [1.0, 0.4375, 0.5625]);
    /// ```
    pub fn build_with(q: &QuantizedLines, r: f64, join: bool) -> Self {
        let mut lod = Self { lo: q.lo, q: q.q, levels: Vec::new() };
        let mut level = LodLevel { h: q.h, dims: q.dims, opacity: Vec::new(), lines: Vec::new() };
        level.opacity = vec![0.0; q.dims.iter().map(|&d| d as usize).product()];
        let mut accs: std::collections::BTreeMap<usize, ([u32; 3], Acc)> = Default::default();
        for s in &q.segments {
            let (a, b) = (V3::from(q.decode(s.ends[0], s.voxel)), V3::from(q.decode(s.ends[1], s.voxel)));
            let l = (b - a).length();
            let k = level.index(s.voxel);
            level.opacity[k] += (2.0 * r * l / (q.h * q.h)) as f32;
            accs.entry(k).or_insert((s.voxel, Acc::default())).1.add(a, b, 1.0, 1, l);
        }
        level.opacity.iter_mut().for_each(|o| *o = o.min(1.0));
        level.finish(accs.into_values().collect(), q.lo, q.q, r);
        if join {
            level.join(q.lo, q.q, r);
        }
        while level.dims.iter().any(|&d| d > 1) {
            let mut next = lod.coarser(&level, r);
            if join {
                next.join(q.lo, q.q, r);
            }
            lod.levels.push(std::mem::replace(&mut level, next));
        }
        lod.levels.push(level);
        lod
    }

    /// The next coarser level of `fine`.
    fn coarser(&self, fine: &LodLevel, r: f64) -> LodLevel {
        let dims = fine.dims.map(|d| d.div_ceil(2));
        let mut out = LodLevel { h: 2.0 * fine.h, dims, opacity: Vec::new(), lines: Vec::new() };
        out.opacity = vec![0.0; dims.iter().map(|&d| d as usize).product()];
        for z in 0..fine.dims[2] {
            for y in 0..fine.dims[1] {
                for x in 0..fine.dims[0] {
                    let k = out.index([x / 2, y / 2, z / 2]);
                    out.opacity[k] += fine.opacity[fine.index([x, y, z])] / 8.0;
                }
            }
        }
        let mut accs: std::collections::BTreeMap<usize, ([u32; 3], Acc)> = Default::default();
        for l in &fine.lines {
            let c = l.voxel.map(|v| v / 2);
            let w = l.count as f64;
            accs.entry(out.index(c)).or_insert((c, Acc::default())).1.add(
                V3::from(l.a),
                V3::from(l.b),
                w,
                l.count,
                l.length,
            );
        }
        out.finish(accs.into_values().collect(), self.lo, self.q, r);
        out
    }

    /// The representative lines of `level` as two-point polylines with their radii (skipping
    /// those whose ends snapped together), for a scene that shadow and AO rays trace.
    pub fn polylines(&self, level: usize) -> Vec<Polyline> {
        let Some(l) = self.levels.get(level) else { return Vec::new() };
        l.lines
            .iter()
            .filter(|r| r.a != r.b)
            .map(|r| Polyline { points: vec![r.a, r.b], radii: vec![r.radius; 2] })
            .collect()
    }
}
