//! The exact union SDF `f = minᵢ fᵢ` over the scene's round cones, read through a hash of
//! cells so that a query visits only the tubes whose surface band reaches its cell.
//!
//! Cells are cubes of `n` grid steps aligned with the contouring grid. A tube is registered in
//! a cell when `|fᵢ(centre)| ≤ reach + d` (`d` the cell's half diagonal): every tube with
//! `|fᵢ(x)| ≤ reach` somewhere in the cell passes, by the 1-Lipschitz bound. A cell with
//! `fᵢ(centre) + d < −reach` for some tube lies `reach` deep inside it and is marked solid.
//! So [`Field::clamped`] returns `f` exactly wherever `|f| < reach`, and otherwise a value of
//! the right sign, clamped to `±reach`.

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};
use tubecast::{Primitive, RoundCone, V3};

/// SplitMix64's finaliser over a packed cell key: the keys are small integers in a few bits,
/// which the standard library's SipHash spends several times longer on, and they come from
/// our own grid, so no hash-flooding defence is needed.
#[derive(Default)]
pub(super) struct CellHasher(u64);

impl Hasher for CellHasher {
    fn finish(&self) -> u64 {
        let mut z = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    fn write(&mut self, bytes: &[u8]) {
        bytes.iter().for_each(|&b| self.0 = self.0.rotate_left(8) ^ u64::from(b));
    }
    fn write_u64(&mut self, x: u64) {
        self.0 = self.0.rotate_left(21) ^ x;
    }
}

/// A hash map keyed by packed integer coordinates.
pub(super) type CellMap<V> = HashMap<u64, V, BuildHasherDefault<CellHasher>>;

/// Grid edges (lower corner's packed index, offset bits) to vertex indices.
pub(super) type EdgeMap = HashMap<(u64, u8), u32, BuildHasherDefault<CellHasher>>;

/// Grid indices must stay within ±`INDEX_LIMIT` on each axis (21 bits each in a key).
pub(super) const INDEX_LIMIT: i64 = 1 << 20;

/// Packs three indices within ±[`INDEX_LIMIT`] into one key.
pub(super) fn pack(i: [i64; 3]) -> u64 {
    let b = |v: i64| ((v + INDEX_LIMIT) as u64) & 0x1f_ffff;
    b(i[0]) | b(i[1]) << 21 | b(i[2]) << 42
}

/// What a cell holds.
enum Cell {
    /// At least `reach` deep inside one tube throughout.
    Solid,
    /// The tubes whose band `|fᵢ| ≤ reach` may meet the cell.
    Band(Vec<u32>),
}

/// The union of round cones, with its grid (`origin + h·index`) and cell hash.
pub(super) struct Field {
    /// The tubes (validated round cones, scene units).
    pub tubes: Vec<RoundCone<f64>>,
    /// Grid origin and step.
    pub origin: V3<f64>,
    pub h: f64,
    /// Grid steps per cell edge.
    pub n: i64,
    /// The band half-width within which values are exact.
    pub reach: f64,
    cells: CellMap<Cell>,
}

/// Floor division (grid index → cell index).
pub(super) fn floor_div(a: i64, b: i64) -> i64 {
    a.div_euclid(b)
}

impl Field {
    /// Builds the cell hash. `reach` must exceed the grid cube's diagonal `√3·h` for the
    /// contouring (see `grid.rs`), and `n·h` is the cell edge.
    pub fn new(tubes: Vec<RoundCone<f64>>, origin: V3<f64>, h: f64, n: i64, reach: f64) -> Self {
        let mut cells: CellMap<Cell> = CellMap::default();
        let edge = n as f64 * h;
        // The centre-to-corner distance, padded for the rounding of the centre itself.
        let d = 0.5 * 3f64.sqrt() * edge * (1.0 + 1e-9);
        for (k, t) in tubes.iter().enumerate() {
            let bb = t.aabb();
            let pad = reach + d;
            let lo = |c: f64, o: f64| ((c - pad - o) / edge).floor() as i64;
            let hi = |c: f64, o: f64| ((c + pad - o) / edge).floor() as i64;
            let (l, u) = (bb.min, bb.max);
            for i in lo(l.x, origin.x)..=hi(u.x, origin.x) {
                for j in lo(l.y, origin.y)..=hi(u.y, origin.y) {
                    for m in lo(l.z, origin.z)..=hi(u.z, origin.z) {
                        let c = origin + V3::new(i as f64 + 0.5, j as f64 + 0.5, m as f64 + 0.5) * edge;
                        let f = t.sdf(c);
                        if f > reach + d {
                            continue;
                        }
                        let e = cells.entry(pack([i, j, m])).or_insert_with(|| Cell::Band(Vec::new()));
                        if f + d < -reach {
                            *e = Cell::Solid;
                        } else if let Cell::Band(v) = e {
                            v.push(k as u32);
                        }
                    }
                }
            }
        }
        Self { tubes, origin, h, n, reach, cells }
    }

    /// Position of grid vertex `i`.
    pub fn at(&self, i: [i64; 3]) -> V3<f64> {
        self.origin + V3::new(i[0] as f64, i[1] as f64, i[2] as f64) * self.h
    }

    /// The cell index of a point.
    fn cell_of(&self, x: V3<f64>) -> [i64; 3] {
        let edge = self.n as f64 * self.h;
        let q = (x - self.origin) * (1.0 / edge);
        [q.x.floor() as i64, q.y.floor() as i64, q.z.floor() as i64]
    }

    /// The band cells (their indices) — every cube of the grid that the surface can cross
    /// has its lowest corner in one of them.
    pub fn band_cells(&self) -> Vec<[i64; 3]> {
        let unpack = |k: u64| {
            let g = |s: u32| ((k >> s) & 0x1f_ffff) as i64 - INDEX_LIMIT;
            [g(0), g(21), g(42)]
        };
        let mut v: Vec<[i64; 3]> =
            self.cells.iter().filter(|(_, c)| matches!(c, Cell::Band(_))).map(|(&k, _)| unpack(k)).collect();
        // Hash order is arbitrary; sorted, the mesh is the same from run to run.
        v.sort_unstable();
        v
    }

    /// The tubes registered in cell `c`, or `None` when it is solid; empty when far outside.
    fn tubes_in(&self, c: [i64; 3]) -> Option<&[u32]> {
        match self.cells.get(&pack(c)) {
            Some(Cell::Solid) => None,
            Some(Cell::Band(v)) => Some(v),
            None => Some(&[]),
        }
    }

    /// `(f, tube)` at `x` from the tubes of `x`'s cell: exact where `|f| < reach`, else
    /// `±reach` (tube `u32::MAX` when none is near).
    pub fn eval_in(&self, x: V3<f64>, cell: [i64; 3]) -> (f64, u32) {
        match self.tubes_in(cell) {
            None => (-self.reach, u32::MAX),
            Some(ts) => {
                let mut best = (self.reach, u32::MAX);
                for &k in ts {
                    let f = self.tubes[k as usize].sdf(x);
                    if f < best.0 {
                        best = (f, k);
                    }
                }
                best
            }
        }
    }

    /// [`Self::eval_in`] at a grid vertex (its cell from the integer index, so that every
    /// cube sharing the vertex reads the same value).
    pub fn at_vertex(&self, i: [i64; 3]) -> f64 {
        let c = i.map(|v| floor_div(v, self.n));
        self.eval_in(self.at(i), c).0
    }

    /// [`Self::eval_in`] at any point.
    pub fn eval(&self, x: V3<f64>) -> (f64, u32) {
        self.eval_in(x, self.cell_of(x))
    }

    /// The tubes that may come within `reach` of `x` (all of them with `fᵢ < reach` there);
    /// `None` inside a solid cell.
    pub fn near(&self, x: V3<f64>) -> Option<&[u32]> {
        self.tubes_in(self.cell_of(x))
    }
}

/// The gradient of a round cone's exact SDF at `x` (unit; a subgradient where it is not
/// differentiable: on the axis, at a sphere's centre). It follows the region split of
/// `tubecast`'s `round_cone` SDF: the nearest of sphere `a`, the cone side, sphere `b`.
pub(super) fn gradient(l: &RoundCone<f64>, x: V3<f64>) -> V3<f64> {
    let unit = |v: V3<f64>| {
        let n = v.length();
        if n > 0.0 {
            v * (1.0 / n)
        } else {
            V3::new(1.0, 0.0, 0.0)
        }
    };
    let v = l.b - l.a;
    let len = v.length();
    let dr = l.ra - l.rb;
    if dr.abs() >= len {
        return unit(x - if l.ra >= l.rb { l.a } else { l.b });
    }
    let axis = v * (1.0 / len);
    let s = dr / len;
    let c = ((1.0 - s) * (1.0 + s)).sqrt();
    let y = x - l.a;
    let z = y.dot(axis);
    let radial = y - axis * z;
    let rho = radial.length();
    let k = c * z - s * rho;
    if k < 0.0 {
        unit(y)
    } else if k > c * len {
        unit(x - l.b)
    } else {
        let rdir = if rho > 0.0 { radial * (1.0 / rho) } else { unit(axis.cross(V3::new(0.3, 0.5, 0.8))) };
        axis * s + rdir * c
    }
}
