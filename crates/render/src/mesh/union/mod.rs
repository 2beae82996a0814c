//! The surface of the union of a scene's links: one closed, oriented, embedded 2-manifold
//! per boundary component, with a certified two-sided Hausdorff bound to the surface of the
//! union of the exact round cones (derivation in `docs/design/union-mesh.md`).
//!
//! Built on the exact union SDF `f = minᵢ fᵢ` ([`tubecast::Primitive::sdf`] of each link):
//! marching tetrahedra on a sparse uniform grid (`grid.rs`, closed and embedded by
//! construction), vertices at the exact roots of `f` on the grid edges, crease edges split at
//! the exact crease (`crease.rs`), then every triangle measured against the tubes
//! (`certify.rs`). The step starts from the curvature bound and is refined until the measured
//! bound meets the tolerance, or a try limit is reached (the bound reached is then reported).

mod certify;
mod crease;
mod embed;
mod field;
mod grid;
mod triple;

use super::{MeshError, SceneMesh};
use crate::scene::Scene;
use field::{Field, INDEX_LIMIT};
use tubecast::{GeometryError, Mesh, Part, RoundCone, V3};

/// How a union mesh was made, and the parts of its certificate.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct UnionReport {
    /// The grid step of the last try (scene units).
    pub step: f64,
    /// Tries made (each with a finer step than the last).
    pub tries: usize,
    /// The deepest any triangle goes inside the union (`max aₜ`).
    pub depth: f64,
    /// The farthest any triangle goes outside the union (`max bₜ`, 0 when none does).
    pub out: f64,
    /// Triangles that go outside the union beyond rounding (a crease that could not be split,
    /// a gap narrower than the grid bridged).
    pub outside: usize,
    /// Crease edges split.
    pub crease_splits: usize,
    /// The least `sin(β/2)` over the split crease points (`β` the crease's exterior opening),
    /// 1 when none.
    pub min_sin_half: f64,
}

impl UnionReport {
    /// The certified two-sided Hausdorff bound: `max(depth, out / sin(β_min/2))`.
    pub fn certified(&self) -> f64 {
        self.depth.max(self.out / self.min_sin_half)
    }
}

/// Tries before the bound reached is accepted as it is.
const TRIES: usize = 3;

/// A refinement may multiply the first try's triangle count by at most this.
const REFINE_COUNT: f64 = 6.0;

/// Grid steps per cell of the tube hash.
const CELL_STEPS: i64 = 8;

/// Meshes the surface of the union of the scene's links within `eps` (absolute, scene units),
/// both ways. The mesh's [`Mesh::certified`] is [`UnionReport::certified`]; it is at most `eps`
/// unless the report says otherwise (see [`UnionReport::outside`]).
///
/// Errors: a tolerance that is not a positive number, a node that is not finite or has radius
/// 0 (the union's certificate needs a ball inside every point of the surface: raise such radii
/// first, e.g. with the CLI's `--min-radius`), or a scene too large for the grid at this
/// tolerance. A tube inside another needs nothing: it adds no surface.
///
/// ```
/// use tubecast_render::io::Polyline;
/// use tubecast_render::mesh::tessellate_union;
/// use tubecast_render::scene::Scene;
/// let line = Polyline { points: vec![[0.0; 3], [4.0, 0.0, 0.0], [6.0, 2.0, 0.0]], radii: vec![] };
/// let scene = Scene::from_polylines(&[line], 0.5, "tube").unwrap();
/// let (m, report) = tessellate_union(&scene, 1e-2).unwrap();
/// assert!(m.mesh.certified <= 1e-2 && m.mesh.parts.len() == 1);
/// assert_eq!(report.certified(), m.mesh.certified);
/// ```
pub fn tessellate_union(scene: &Scene, eps: f64) -> Result<(SceneMesh, UnionReport), MeshError> {
    if !(eps.is_finite() && eps > 0.0) {
        let cause = GeometryError::TooSmall { what: "mesh tolerance (must be a positive number)" };
        return Err(MeshError::Tolerance { eps, cause });
    }
    let (tubes, links) = tubes(scene)?;
    if tubes.is_empty() {
        return Ok((SceneMesh::default(), UnionReport { min_sin_half: 1.0, ..Default::default() }));
    }
    let r_min = tubes.iter().map(|t| t.ra.min(t.rb)).fold(f64::INFINITY, f64::min);
    let (mut lo, mut hi) =
        (V3::new(f64::INFINITY, f64::INFINITY, f64::INFINITY), -V3::new(1.0, 1.0, 1.0) * f64::INFINITY);
    for t in &tubes {
        let b = tubecast::Primitive::aabb(t);
        lo = V3::new(lo.x.min(b.min.x), lo.y.min(b.min.y), lo.z.min(b.min.z));
        hi = V3::new(hi.x.max(b.max.x), hi.y.max(b.max.y), hi.z.max(b.max.z));
    }
    // A triangle with corners on a sphere of radius ρ, within a grid cube's diagonal √3·h of
    // each other, is at most h²/(2ρ)·(1 + O(h²/ρ²)) deep; the step is capped at ρ/2 so that
    // every tube, shrunk by the bound, still holds a grid vertex (the certificate's condition).
    let mut h = (1.6 * eps * r_min).sqrt().min(0.5 * r_min);
    let mut best: Option<(grid::Raw, UnionReport)> = None;
    let mut first_count: Option<usize> = None;
    for tries in 1..=TRIES {
        let extent = (hi - lo).length() + 8.0 * CELL_STEPS as f64 * h;
        if extent / h >= (INDEX_LIMIT / 2) as f64 || !extent.is_finite() {
            if best.is_some() {
                break;
            }
            let cause = GeometryError::TooSmall {
                what: "mesh tolerance (the union grid would exceed 2^19 steps across the scene)",
            };
            return Err(MeshError::Tolerance { eps, cause });
        }
        // Offset by irrational fractions of a step, so that the grid's corners do not fall on
        // the surfaces of axis-aligned tubes with round coordinates (a corner exactly on the
        // surface puts a vertex at the end gap, off the surface by that gap).
        let shift = V3::new(std::f64::consts::FRAC_1_PI, 0.1 * std::f64::consts::E, 0.1 * std::f64::consts::SQRT_2) * h;
        let origin = lo - V3::new(1.0, 1.0, 1.0) * (2.0 * CELL_STEPS as f64 * h) - shift;
        let field = Field::new(tubes.clone(), origin, h, CELL_STEPS, 3.0 * h);
        let mut raw = grid::contour(&field);
        let creases = crease::split(&field, &mut raw);
        triple::fan(&field, &mut raw);
        let ex = certify::excursion(&field, &raw);
        let mut report = UnionReport {
            step: h,
            tries,
            depth: ex.depth,
            out: ex.out,
            outside: ex.outside,
            crease_splits: creases.split,
            min_sin_half: creases.min_sin_half,
        };
        // The certificate needs each tube, shrunk by the depth, to hold a ball of radius √3·h/2.
        if r_min - report.depth < 0.5 * 3f64.sqrt() * h {
            report.depth = f64::INFINITY;
        }
        let done = report.certified() <= eps;
        let count = raw.triangles.len();
        best = Some((raw, report));
        if done {
            break;
        }
        // The depth falls with h², a crease's excursion with h: take the step that would meet
        // eps under the first, within [1/2, 0.9] of the last, while the triangle count (∝ 1/h²)
        // stays within REFINE_COUNT of the first try's.
        let next = h * (0.9 * (eps / report.certified()).sqrt()).clamp(0.5, 0.9);
        first_count.get_or_insert(count);
        if first_count.map_or(true, |c| (count as f64) * (h / next).powi(2) > REFINE_COUNT * c as f64) {
            break;
        }
        h = next;
    }
    let (raw, report) = best.expect("at least one try ran");
    Ok((assemble(scene, raw, &links, report.certified()), report))
}

/// The scene's links as round cones (radius 0 and non-finite data refused), with their
/// scene link indices.
fn tubes(scene: &Scene) -> Result<(Vec<RoundCone<f64>>, Vec<u32>), MeshError> {
    let mut tubes = Vec::with_capacity(scene.links.len());
    let mut links = Vec::with_capacity(scene.links.len());
    for (k, [a, b]) in scene.links.iter().enumerate() {
        let err = |cause| MeshError::Chain { link: k as u32, cause };
        let (a, b) = (a as usize, b as usize);
        let (ra, rb) = (scene.radius(a), scene.radius(b));
        if ra == 0.0 || rb == 0.0 {
            return Err(err(GeometryError::TooSmall {
                what: "radius 0 at a node (the union mesh needs positive radii: raise them, or mesh the shells)",
            }));
        }
        let (pa, pb) = (V3::from(scene.nodes[a].pos), V3::from(scene.nodes[b].pos));
        tubes.push(RoundCone::new(pa, ra, pb, rb).map_err(err)?);
        links.push(k as u32);
    }
    Ok((tubes, links))
}

/// The scene mesh: triangles grouped by connected component (one [`Part`] each), tagged with
/// the scene link of their first corner's tube.
fn assemble(scene: &Scene, raw: grid::Raw, links: &[u32], certified: f64) -> SceneMesh {
    let n = raw.positions.len();
    let mut parent: Vec<u32> = (0..n as u32).collect();
    fn find(p: &mut [u32], mut i: u32) -> u32 {
        while p[i as usize] != i {
            p[i as usize] = p[p[i as usize] as usize];
            i = p[i as usize];
        }
        i
    }
    for t in &raw.triangles {
        for e in 1..3 {
            let (a, b) = (find(&mut parent, t[0]), find(&mut parent, t[e]));
            if a != b {
                parent[a.max(b) as usize] = a.min(b);
            }
        }
    }
    let roots: Vec<u32> = raw.triangles.iter().map(|t| find(&mut parent, t[0])).collect();
    let mut order: Vec<usize> = (0..raw.triangles.len()).collect();
    order.sort_by_key(|&k| (roots[k], k));
    let mut out = SceneMesh { mesh: Mesh { positions: raw.positions, certified, ..Default::default() }, part: vec![] };
    let link_of = |t: &[u32; 3]| links.get(raw.owner[t[0] as usize] as usize).copied().unwrap_or(0);
    let mut start = 0;
    for (i, &k) in order.iter().enumerate() {
        let t = raw.triangles[k];
        out.mesh.triangles.push(t);
        out.mesh.tags.push(link_of(&t));
        let last = i + 1 == order.len() || roots[order[i + 1]] != roots[k];
        if last {
            let (mut n0, mut n1) = (u32::MAX, 0);
            for &l in &out.mesh.tags[start..=i] {
                let [a, b] = scene.links.get(l as usize);
                (n0, n1) = (n0.min(a.min(b)), n1.max(a.max(b)));
            }
            out.mesh.parts.push(Part { triangles: start..i + 1, nodes: n0 as usize..=n1 as usize });
            out.part.extend(std::iter::repeat(out.mesh.parts.len() as u32 - 1).take(i + 1 - start));
            start = i + 1;
        }
    }
    out
}
