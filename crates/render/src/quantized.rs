//! Kanzler et al.'s quantized lines (2018): each polyline is cut at voxel faces, each voxel's
//! piece is replaced by one segment from its entry to its exit point, and each end is snapped
//! to the centre of its bin on a `Q × Q` grid over the voxel face it lies on (a polyline end
//! inside a voxel: to the centre of its bin of a `Q³` lattice). An end then takes
//! `3 + 2·⌈log₂ Q⌉` bits (face, two bin indices) instead of three floats.
//!
//! # Error bound
//! For a voxel of side `h`, a face end moves by at most half a bin diagonal, `e_f = h/(√2·Q)`;
//! an interior end by `e_i = √3·h/(2Q)`. Between the exact piece `P` (the polyline from entry
//! `A` to exit `B`, with any vertices inside the voxel) and the quantized segment `S`:
//! * `H(P, AB) ≤ D`, `D` the largest distance of `P`'s vertices from the line `AB`: `P`→`AB`
//!   because the distance to a segment is convex along each sub-segment; `AB`→`P` because the
//!   plane through any `x ∈ AB` perpendicular to `AB` separates `A` from `B`, so `P` crosses it
//!   at a point whose distance to `x` is its distance to the line;
//! * `H(AB, S) ≤ max(e_A, e_B)`: `|(1−s)A + sB − ((1−s)A' + sB')| ≤ max(|A − A'|, |B − B'|)`.
//!
//! So `H(P, S) ≤ D + max(e_A, e_B)` ([`QSegment::bound`]), measured by
//! [`QuantizedLines::hausdorff`].

use crate::io::Polyline;
use crate::scene::Scene;
use tubecast::{voxel, V3};

mod lod;
pub use lod::{Lod, LodLevel, RepLine};

/// One quantized segment: the voxel it lies in, its two packed ends, its source polyline, and
/// the chord deviation `D` of the piece it replaces.
///
/// ```
/// use tubecast_render::io::Polyline;
/// use tubecast_render::quantized::QuantizedLines;
/// let line = Polyline { points: vec![[0.5, 0.5, 0.5], [1.5, 0.5, 0.5]], radii: vec![] };
/// let q = QuantizedLines::new(&[line], [0.0; 3], 1.0, [2, 1, 1], 8);
/// let s = q.segments[0];
/// assert_eq!((s.voxel, s.ends[0] & 7, s.ends[1] & 7), ([0, 0, 0], 6, 1)); // interior → +x face
/// assert_eq!(q.decode(s.ends[1], s.voxel), [1.0, 0.5625, 0.5625]); // bin centre on the face
/// assert!(s.bound(1.0, 8) >= 0.5f64.sqrt() / 8.0);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QSegment {
    /// Voxel `[i, j, k]`.
    pub voxel: [u32; 3],
    /// Packed ends: face (0–5: −x, +x, −y, +y, −z, +z; 6: interior) in the low 3 bits, then
    /// the bin indices (6 bits each).
    pub ends: [u32; 2],
    /// Index of the source polyline.
    pub line: u32,
    /// Chord deviation `D` (world units, rounded up by [`QSegment::bound`]'s factor) of the
    /// exact piece: its vertices' largest distance from the entry–exit line.
    pub chord_deviation: f32,
}

/// Quantized lines over a grid of cubic voxels.
///
/// ```
/// use tubecast_render::io::Polyline;
/// use tubecast_render::quantized::QuantizedLines;
/// let line = Polyline { points: vec![[0.1, 0.2, 0.3], [3.7, 1.4, 0.9]], radii: vec![] };
/// let q = QuantizedLines::new(&[line.clone()], [0.0; 3], 1.0, [4, 4, 4], 16);
/// assert_eq!(q.segments.len(), 5); // the voxels its straight path crosses
/// let err = q.hausdorff(&[line]);
/// assert!(err.max > 0.0 && err.worst_ratio <= 1.0);
/// ```
pub struct QuantizedLines {
    /// Grid corner and voxel side.
    pub lo: [f64; 3],
    /// Voxel side.
    pub h: f64,
    /// Voxels along x, y, z.
    pub dims: [u32; 3],
    /// Bins per face side `Q` (1–64).
    pub q: u32,
    /// The segments, in polyline order.
    pub segments: Vec<QSegment>,
}

/// A voxel piece under construction: voxel, entry point, interior vertices (grid units).
type Piece = ([u32; 3], [f64; 3], Vec<[f64; 3]>);

/// Face of a point `x` (grid coordinates) on the boundary of voxel `c`: the axis and side it is
/// nearest to.
fn face(x: [f64; 3], c: [u32; 3]) -> (usize, usize) {
    let mut best = (0, 0, f64::INFINITY);
    for i in 0..3 {
        for (side, d) in [(0, x[i] - c[i] as f64), (1, c[i] as f64 + 1.0 - x[i])] {
            if d.abs() < best.2 {
                best = (i, side, d.abs());
            }
        }
    }
    (best.0, best.1)
}

impl QuantizedLines {
    /// Cut `lines` at the faces of the grid (`lo`, side `h`, `dims` voxels; parts outside are
    /// dropped) and quantize each piece's ends with `q` bins per face side (clamped to 1–64).
    pub fn new(lines: &[Polyline], lo: [f64; 3], h: f64, dims: [u32; 3], q: u32) -> Self {
        let mut out = Self { lo, h, dims, q: q.clamp(1, 64), segments: Vec::new() };
        for (k, l) in lines.iter().enumerate() {
            out.add(l, k as u32);
        }
        out
    }

    fn to_grid(&self, p: [f64; 3]) -> [f64; 3] {
        std::array::from_fn(|i| (p[i] - self.lo[i]) / self.h)
    }

    /// Cut one polyline into voxel pieces and quantize them.
    fn add(&mut self, l: &Polyline, line: u32) {
        let mut pieces = Vec::new();
        self.pieces(l, |c, entry, mid, exit| pieces.push((c, entry, mid.to_vec(), exit)));
        for (c, entry, mid, exit) in pieces {
            self.push(c, entry, &mid, exit, line);
        }
    }

    /// The voxel pieces of a polyline in order: `f(voxel, entry, interior vertices, exit)`,
    /// grid coordinates.
    fn pieces(&self, l: &Polyline, mut f: impl FnMut([u32; 3], [f64; 3], &[[f64; 3]], [f64; 3])) {
        let mut cur: Option<Piece> = None;
        let mut last = [0.0; 3];
        let pts: Vec<[f64; 3]> = l.points.iter().map(|&p| self.to_grid(p)).collect();
        for w in pts.windows(2) {
            let (a, b) = (V3::from(w[0]), V3::from(w[1]));
            let at = |t: f64| (a + (b - a) * t).to_array();
            voxel::dda(a, b - a, 0.0, 1.0, self.dims, |c, t0, t1| {
                match &mut cur {
                    Some((v, _, mid)) if *v == c => mid.push(at(t0)),
                    _ => {
                        if let Some((v, entry, mid)) = cur.take() {
                            f(v, entry, &mid, last);
                        }
                        cur = Some((c, at(t0), Vec::new()));
                    }
                }
                last = at(t1);
                true
            });
        }
        if let Some((v, entry, mid)) = cur {
            f(v, entry, &mid, last);
        }
    }

    /// Hausdorff distance of every segment to the exact piece it replaces (`lines` must be the
    /// polylines it was built from), against the derived bound. The directed distance from the
    /// piece to the segment is exact (convex along each sub-segment: at its vertices); from the
    /// segment to the piece it is sampled at 64 points and is a lower estimate.
    pub fn hausdorff(&self, lines: &[Polyline]) -> Hausdorff {
        let mut out = Hausdorff { max: 0.0, max_bound: 0.0, worst_ratio: 0.0 };
        let mut k = 0;
        for l in lines {
            self.pieces(l, |c, entry, mid, exit| {
                let s = &self.segments[k];
                k += 1;
                let (a, b) = (V3::from(self.decode(s.ends[0], c)), V3::from(self.decode(s.ends[1], c)));
                let world = |p: [f64; 3]| V3::from(std::array::from_fn(|i| self.lo[i] + p[i] * self.h));
                let path: Vec<V3<f64>> =
                    std::iter::once(entry).chain(mid.iter().copied()).chain([exit]).map(world).collect();
                let to_seg = path.iter().map(|&p| seg_dist(p, a, b)).fold(0.0, f64::max);
                let to_path = (0..=64)
                    .map(|i| {
                        let x = a + (b - a) * (i as f64 / 64.0);
                        path.windows(2).map(|w| seg_dist(x, w[0], w[1])).fold(seg_dist(x, path[0], path[0]), f64::min)
                    })
                    .fold(0.0, f64::max);
                let (d, bound) = (to_seg.max(to_path), s.bound(self.h, self.q));
                out.max = out.max.max(d);
                out.max_bound = out.max_bound.max(bound);
                out.worst_ratio = out.worst_ratio.max(d / bound);
            });
        }
        out
    }

    /// Quantize a piece from `entry` to `exit` (through `mid`) in voxel `c`.
    fn push(&mut self, c: [u32; 3], entry: [f64; 3], mid: &[[f64; 3]], exit: [f64; 3], line: u32) {
        let (a, b) = (V3::from(entry), V3::from(exit));
        let ab = b - a;
        let dev = mid
            .iter()
            .map(|&m| {
                let m = V3::from(m) - a;
                let l2 = ab.length2();
                if l2 > 0.0 {
                    (m - ab * (m.dot(ab) / l2)).length()
                } else {
                    m.length()
                }
            })
            .fold(0.0, f64::max);
        let ends = [self.encode(entry, c), self.encode(exit, c)];
        self.segments.push(QSegment { voxel: c, ends, line, chord_deviation: (dev * self.h) as f32 });
    }

    /// Pack a point of voxel `c` (grid coordinates): its face and bin, or its interior bin.
    fn encode(&self, x: [f64; 3], c: [u32; 3]) -> u32 {
        let q = self.q as f64;
        let bin = |i: usize| ((x[i] - c[i] as f64) * q).floor().clamp(0.0, q - 1.0) as u32;
        let (axis, side) = face(x, c);
        let on_face = (x[axis] - (c[axis] + side as u32) as f64).abs() <= 1e-9;
        if on_face {
            let (p, r) = ((axis + 1) % 3, (axis + 2) % 3);
            (2 * axis + side) as u32 | bin(p) << 3 | bin(r) << 9
        } else {
            6 | bin(0) << 3 | bin(1) << 9 | bin(2) << 15
        }
    }

    /// World position of a packed end of a segment in voxel `c`.
    pub fn decode(&self, code: u32, c: [u32; 3]) -> [f64; 3] {
        let q = self.q as f64;
        let f = (code & 7) as usize;
        let idx = [(code >> 3) & 63, (code >> 9) & 63, (code >> 15) & 63].map(|i| (i as f64 + 0.5) / q);
        let mut local = [0.0; 3];
        if f == 6 {
            local = idx;
        } else {
            let (axis, side) = (f / 2, f % 2);
            local[axis] = side as f64;
            local[(axis + 1) % 3] = idx[0];
            local[(axis + 2) % 3] = idx[1];
        }
        std::array::from_fn(|i| self.lo[i] + (c[i] as f64 + local[i]) * self.h)
    }

    /// The quantized lines as polylines to render: each source line's segments chained where
    /// one's end decodes to the next one's start (always, inside the grid: both snap to the
    /// same bin of the shared face), every point with radius `r`.
    ///
    /// ```
    /// use tubecast_render::io::Polyline;
    /// use tubecast_render::quantized::QuantizedLines;
    /// let line = Polyline { points: vec![[0.1, 0.2, 0.3], [3.7, 1.4, 0.9]], radii: vec![] };
    /// let q = QuantizedLines::new(&[line], [0.0; 3], 1.0, [4, 4, 4], 16);
    /// let p = q.polylines(0.1);
    /// assert_eq!((p.len(), p[0].points.len()), (1, 6)); // 5 segments, one chain
    /// ```
    pub fn polylines(&self, r: f64) -> Vec<Polyline> {
        self.polylines_with(|_| r)
    }

    /// [`QuantizedLines::polylines`] with the radius of each source line: `radius(line)` for
    /// every point of the pieces of source polyline `line`.
    ///
    /// ```
    /// use tubecast_render::io::Polyline;
    /// use tubecast_render::quantized::QuantizedLines;
    /// let lines: Vec<Polyline> =
    ///     (0..2).map(|k| Polyline { points: vec![[0.5, 0.5 + k as f64, 0.5], [2.5, 0.5 + k as f64, 0.5]], radii: vec![] }).collect();
    /// let q = QuantizedLines::new(&lines, [0.0; 3], 1.0, [3, 2, 1], 16);
    /// let p = q.polylines_with(|line| 0.1 * (line + 1) as f64);
    /// assert_eq!((p[0].radii[0], p[1].radii[0]), (0.1, 0.2));
    /// ```
    pub fn polylines_with(&self, radius: impl Fn(u32) -> f64) -> Vec<Polyline> {
        let mut out: Vec<Polyline> = Vec::new();
        let mut last: Option<(u32, [f64; 3])> = None;
        for s in &self.segments {
            let (a, b) = (self.decode(s.ends[0], s.voxel), self.decode(s.ends[1], s.voxel));
            let r = radius(s.line);
            match (last, out.last_mut()) {
                (Some((line, end)), Some(p)) if line == s.line && end == a => {
                    p.points.push(b);
                    p.radii.push(r);
                }
                _ => out.push(Polyline { points: vec![a, b], radii: vec![r; 2] }),
            }
            last = Some((s.line, b));
        }
        out
    }

    /// The largest derived Hausdorff bound over the segments ([`QSegment::bound`]): no point
    /// of the quantized lines is farther than this from the exact lines, nor the other way
    /// round; 0 without segments.
    ///
    /// ```
    /// use tubecast_render::io::Polyline;
    /// use tubecast_render::quantized::QuantizedLines;
    /// let line = Polyline { points: vec![[0.5, 0.5, 0.5], [3.5, 0.5, 0.5]], radii: vec![] };
    /// let q = QuantizedLines::new(&[line], [0.0; 3], 1.0, [4, 1, 1], 8);
    /// assert!((q.max_bound() - 3f64.sqrt() / 16.0).abs() < 1e-15); // an interior end: half a Q³ bin diagonal
    /// ```
    pub fn max_bound(&self) -> f64 {
        self.segments.iter().map(|s| s.bound(self.h, self.q)).fold(0.0, f64::max)
    }

    /// Bytes of one packed segment: its two ends ([`QuantizedLines::bits_per_end`]), rounded up
    /// to whole bytes (the voxel is implied by the per-voxel list the segment sits in).
    pub fn bytes_per_segment(&self) -> u32 {
        (2 * self.bits_per_end()).div_ceil(8)
    }

    /// Bits of one end in a packed store: face (3) and the bin indices.
    pub fn bits_per_end(&self) -> u32 {
        3 + 2 * self.q.next_power_of_two().trailing_zeros()
    }
}

impl QSegment {
    /// The derived Hausdorff bound of this segment against its exact piece (module docs), for
    /// voxels of side `h` and `q` bins.
    pub fn bound(&self, h: f64, q: u32) -> f64 {
        let e = |code: u32| if code & 7 == 6 { 3f64.sqrt() / 2.0 } else { 0.5f64.sqrt() } * h / q as f64;
        self.chord_deviation as f64 * (1.0 + 1e-6) + e(self.ends[0]).max(e(self.ends[1]))
    }
}

/// Measured Hausdorff distances of quantized segments against their bounds
/// ([`QuantizedLines::hausdorff`]).
///
/// ```
/// use tubecast_render::io::Polyline;
/// use tubecast_render::quantized::QuantizedLines;
/// let line = Polyline { points: vec![[0.3, 0.3, 0.3], [3.3, 0.6, 0.4]], radii: vec![] };
/// let e = QuantizedLines::new(&[line.clone()], [0.0; 3], 1.0, [4, 1, 1], 32).hausdorff(&[line]);
/// assert!(e.max <= e.max_bound && e.worst_ratio <= 1.0);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hausdorff {
    /// Largest measured distance (world units).
    pub max: f64,
    /// Largest per-segment bound.
    pub max_bound: f64,
    /// Largest measured / bound over the segments (≤ 1 when the bound holds).
    pub worst_ratio: f64,
}

/// The lines of a scene for [`QuantizedLines::new`]: each chain of links ([`Scene::chains`]) as
/// one polyline, and each chain's largest node radius. Isolated nodes (spheres) have no line.
///
/// ```
/// use tubecast_render::io::Polyline;
/// use tubecast_render::quantized::scene_lines;
/// use tubecast_render::scene::Scene;
/// let line = Polyline { points: vec![[0.0; 3], [1.0, 0.0, 0.0], [2.0, 1.0, 0.0]], radii: vec![0.1, 0.3, 0.2] };
/// let (lines, radii) = scene_lines(&Scene::from_polylines(&[line], 1.0, "t").unwrap());
/// assert_eq!((lines.len(), lines[0].points.len(), radii), (1, 3, vec![0.3]));
/// ```
pub fn scene_lines(scene: &Scene) -> (Vec<Polyline>, Vec<f64>) {
    let chains = scene.chains();
    let lines = chains
        .iter()
        .map(|c| Polyline { points: c.nodes.iter().map(|&i| scene.nodes[i as usize].pos).collect(), radii: vec![] })
        .collect();
    let radii = chains.iter().map(|c| c.nodes.iter().map(|&i| scene.radius(i as usize)).fold(0.0, f64::max)).collect();
    (lines, radii)
}

/// Distance from `x` to the segment `ab`.
fn seg_dist(x: V3<f64>, a: V3<f64>, b: V3<f64>) -> f64 {
    let ab = b - a;
    let l2 = ab.length2();
    let t = if l2 > 0.0 { ((x - a).dot(ab) / l2).clamp(0.0, 1.0) } else { 0.0 };
    (x - (a + ab * t)).length()
}
