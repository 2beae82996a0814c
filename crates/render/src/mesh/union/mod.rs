//! The surface of the union of a scene's links, built with manifold (the pure-Rust port
//! `manifold-rust`): every node sphere an inscribed polyhedron, every link the convex hull of
//! its two end polyhedra (or, where the chains are streamlines, each run of a chain one body of
//! mitred rings, `piece.rs`: [`Bodies`]), all united by manifold's booleans, by halves in space
//! (`hull.rs`); the result is one closed, oriented 2-manifold per component (manifold's
//! guarantee, checked by the tests), measured triangle by triangle against the exact round
//! cones (`certify.rs`), with a certified two-sided Hausdorff bound to the union's exact
//! surface (derivation in `docs/design/union-mesh.md`).
//!
//! The polyhedra's resolution is set per node by its sagitta (a thin branch needs fewer
//! segments than the soma); where the measured bound exceeds the tolerance (sharp notches,
//! where the bound is the sagitta over `sin(β/2)`), the spheres of the tubes that set it are
//! refined by the measured factor and the union rebuilt, three times at most.

mod certify;
mod hull;
mod piece;
mod tube;

use super::{MeshError, SceneMesh};
use crate::scene::Scene;
use piece::Focus;
use std::collections::HashMap;
use tube::P;
use tubecast::{GeometryError, Mesh, Part, RoundCone, V3};

/// How a union mesh was made, and the parts of its certificate.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct UnionReport {
    /// Builds made (each after refining the spheres where the bound exceeded the tolerance).
    pub tries: usize,
    /// The largest sagitta of a node's polyhedron (radius minus the least distance from its
    /// centre to a face's plane): every point of the union's surface is within it of the mesh.
    pub sagitta: f64,
    /// The largest depth bound over the mesh: every mesh point inside the union is within it
    /// of the union's surface (the sagitta on a tube's side, up to `sagitta / sin(β/2)` at a
    /// crease of exterior opening β).
    pub depth: f64,
    /// The farthest any triangle goes outside the union (rounding: the hulls lie inside their
    /// tubes).
    pub out: f64,
    /// Triangles whose depth bound exceeds the tolerance in the mesh returned (tangent or
    /// nearly tangent tubes after the refinement budget).
    pub outside: usize,
    /// The least `sin(β/2)` over the creases the certificate met (1 when none).
    pub min_sin_half: f64,
    /// The least and largest subdivisions per octant edge of a node's polyhedron (a sphere of
    /// `8·k²` triangles).
    pub subdiv: (u32, u32),
    /// The least and largest ring size of the runs' bodies (vertices per ring).
    pub ring: (u32, u32),
    /// The runs meshed as one body each (equal-radius stretches of chains).
    pub runs: usize,
    /// Manifold's input triangles: the runs' bodies and the other links' hulls (counted at
    /// their bound `2·(points) − 4`).
    pub hull_triangles: usize,
    /// The estimated peak (bytes) of the refinement that `UnionOptions::memory_limit` refused,
    /// where one was: the mesh returned is the best build made before it.
    pub refused_estimate: Option<u64>,
}

impl UnionReport {
    /// The certified two-sided Hausdorff bound: `max(sagitta, depth) + out`.
    pub fn certified(&self) -> f64 {
        self.sagitta.max(self.depth) + self.out
    }
}

/// Options of [`tessellate_union_with`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct UnionOptions {
    /// Refuse, before building, a union whose estimated peak memory exceeds this many bytes
    /// (`None`: no limit).
    pub memory_limit: Option<u64>,
    /// The bodies united: hulls per link, runs per streamline, or chosen by the scene.
    pub bodies: Bodies,
}

/// The bodies manifold unites (`docs/design/union-mesh.md`, "Construction"). Both are
/// inscribed in the exact union and certified the same way; they differ in size and in
/// where they reach ε.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Bodies {
    /// Runs where at least half of the scene's links lie on runs of several links
    /// ([`Bodies::chosen`]: streamlines), hulls otherwise (neurons, piles of short chains).
    #[default]
    Auto,
    /// The convex hull of a link's two sphere polyhedra, per link: fewest triangles where
    /// chains are a link or two long, but a grazing crease between two tubes needs a sagitta
    /// of about `ε²/(2r)` all over their spheres, so bundles of nearly parallel streamlines
    /// can stay over ε within the builds' budget.
    Hulls,
    /// Each stretch of a chain with one radius (a streamline) as one body of mitred rings,
    /// graded towards grazing tubes (`docs/design/union-mesh.md`, "Runs"): fewer triangles on
    /// long streamlines at the same ε, and ε reached where they graze; more than the hulls,
    /// and slower to certify, on piles of short streamlines.
    Runs,
}

impl Bodies {
    /// Whether runs are meshed for `scene` at tolerance `eps`: [`Bodies::Runs`], or
    /// [`Bodies::Auto`] where at least half of the scene's links lie on runs of at least
    /// `AUTO_RUN_LINKS` links (equal-radius stretches of a chain, cut where a joint bends
    /// too sharply to be mitred at `eps`).
    ///
    /// ```
    /// use tubecast_render::io::Polyline;
    /// use tubecast_render::mesh::Bodies;
    /// use tubecast_render::scene::Scene;
    /// let long = Polyline { points: (0..9).map(|i| [i as f64, 0.0, 0.0]).collect(), radii: vec![] };
    /// let short = Polyline { points: vec![[0.0; 3], [1.0, 0.0, 0.0]], radii: vec![] };
    /// let tract = Scene::from_polylines(&[long], 0.1, "t").unwrap();
    /// let pile = Scene::from_polylines(&[short.clone(), short], 0.1, "t").unwrap();
    /// assert!(Bodies::Auto.chosen(&tract, 1e-3) && !Bodies::Auto.chosen(&pile, 1e-3));
    /// assert!(Bodies::Runs.chosen(&pile, 1e-3) && !Bodies::Hulls.chosen(&tract, 1e-3));
    /// ```
    pub fn chosen(self, scene: &Scene, eps: f64) -> bool {
        match self {
            Bodies::Hulls => false,
            Bodies::Runs => true,
            Bodies::Auto => {
                let n = scene.nodes.len();
                let centres: Vec<P> = scene.nodes.iter().map(|x| V3::from(x.pos)).collect();
                let radii: Vec<f64> = (0..n).map(|i| scene.radius(i)).collect();
                let target = vec![FIRST_SAGITTA * eps; n];
                runs_pay(&piece::runs(&scene.chains(), &centres, &radii, &target), scene.links.len())
            }
        }
    }
}

/// [`Bodies::Auto`]'s rule on the runs at the first sagitta target: at least half of the
/// scene's `links` lie on runs of at least `AUTO_RUN_LINKS` links.
fn runs_pay(runs: &[piece::Run], links: usize) -> bool {
    let long: usize = runs.iter().map(|run| run.links.len()).filter(|&k| k >= AUTO_RUN_LINKS).sum();
    links > 0 && 2 * long >= links
}

/// The least run that counts towards runs in [`Bodies::Auto`]: a run's two caps cost about
/// as much as a hull's two spheres, and its rings pay only along several links.
const AUTO_RUN_LINKS: usize = 4;

/// Builds made at most (the first, then refinements where the bound exceeds ε; the larger
/// neuron assemblies need a fourth, `docs/design/union-mesh.md`, "Size and cost").
const TRIES: usize = 4;

/// Builds made at most with runs: a crease's grading; where it falls short, the grading about
/// the excess itself, then a mitre's wedge, then a node's rings; each may take a build or two
/// more in a dense bundle (the 10⁵-link Bundle's bound is infinite in the first two builds and
/// never rises over the later ones, `docs/design/union-mesh.md`).
const RUN_TRIES: usize = 6;

/// The first sagitta target, as a fraction of ε: a crease of exterior opening β multiplies
/// the sagitta by `1/sin(β/2)`, and most of a tree's creases (bends, branches) are wider than
/// a right angle (`1/sin(45°) ≈ 1.41`).
const FIRST_SAGITTA: f64 = 0.7;

/// The forks graded before the first build (`pregrade`): where the axes cross at less than
/// 30°. Where streamlines cross at wide angles, as on `fuzz/corpus/tck/standard.tck`'s pile,
/// grading every fork added a fifth to the mesh that the refinement did not ask for (272,132
/// triangles at ε = 10⁻²·r, against 228,078 with this limit and 220,078 with none graded
/// before); the Bundle's forks are all within 8°.
const GRAZING_SIN: f64 = 0.5;

/// The focus key of a direction graded about an excess itself, not about a partner tube
/// (partners' keys are chains and links, far below it).
const POINT: u32 = u32::MAX;

/// Directions graded about excesses per link at most (a cost limit). A link meets few
/// junctions, but while its rings are coarse one junction's excess spans many directions
/// more than half a step apart: with four, links beside a channel closing by three
/// streamlines' aligned ends had spent theirs by the second build and stayed 8·ε deep; with
/// sixteen, the first links of streamlines starting side by side spent theirs by the third
/// build on one channel's few hundred triangles and ended just over ε. Each direction costs
/// its grading's ramp (about `base/fine` angles) on the link's two rings, only where an
/// excess asked for it.
const MAX_POINTS: usize = 64;

/// Peak bytes per hull triangle (manifold's input): the hulls, the boolean's working set, the
/// result and its certificate. Calibrated on the generator's 900-link neuron at ε = 10⁻²·r̄,
/// whose peak resident memory was 164 bytes per counted hull triangle above the base, with
/// margin (`docs/design/union-mesh.md`, "Memory guard").
pub const UNION_BYTES_PER_HULL_TRIANGLE: f64 = 250.0;

/// Peak bytes per triangle of a run's body (manifold's input with `Bodies::Runs`): the
/// bodies' triangles are mostly kept (long streamlines overlap little), so the result and its
/// certificate weigh more per input triangle than the hulls'. Calibrated on the Bundles with
/// runs, whose peak resident memory was 890–1,160 bytes per body triangle of the last build
/// (5,040 links at ε = 10⁻³ and 10⁻² of the radius, 20,000 links at 10⁻²), with margin.
pub const UNION_BYTES_PER_BODY_TRIANGLE: f64 = 1400.0;

/// The process's own memory beside the union (code, the scene, the thread pool).
pub const UNION_BASE_BYTES: f64 = 64e6;

/// Meshes the surface of the union of the scene's links within `eps` (absolute, scene units),
/// both ways, from the bodies [`Bodies::Auto`] chooses for the scene. The mesh's
/// [`Mesh::certified`] is [`UnionReport::certified`]; it is at most `eps` unless the report
/// says otherwise (tubes tangent or nearly tangent: see [`UnionReport::outside`]).
///
/// Errors: a tolerance that is not a positive number, a node that is not finite or has radius
/// 0 (the union's certificate needs a ball inside every point of the surface: raise such radii
/// first, e.g. with the CLI's `--min-radius`), or manifold failing on the input. A tube inside
/// another, coincident tubes and zero-length links need nothing: they add no surface.
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
    tessellate_union_with(scene, eps, &UnionOptions::default())
}

/// [`tessellate_union`] with options: the bodies ([`Bodies`]), and a memory limit: a union
/// whose estimated peak exceeds `options.memory_limit` is refused before it is built
/// ([`MeshError::Memory`]).
///
/// ```
/// use tubecast_render::io::Polyline;
/// use tubecast_render::mesh::{tessellate_union_with, MeshError, UnionOptions};
/// use tubecast_render::scene::Scene;
/// let line = Polyline { points: vec![[0.0; 3], [4.0, 0.0, 0.0]], radii: vec![] };
/// let scene = Scene::from_polylines(&[line], 0.5, "tube").unwrap();
/// let small = UnionOptions { memory_limit: Some(1000), ..Default::default() };
/// assert!(matches!(tessellate_union_with(&scene, 1e-3, &small), Err(MeshError::Memory { .. })));
/// ```
pub fn tessellate_union_with(
    scene: &Scene,
    eps: f64,
    options: &UnionOptions,
) -> Result<(SceneMesh, UnionReport), MeshError> {
    if !(eps.is_finite() && eps > 0.0) {
        let cause = GeometryError::TooSmall { what: "mesh tolerance (must be a positive number)" };
        return Err(MeshError::Tolerance { eps, cause });
    }
    let (tubes, links, pairs) = tubes(scene)?;
    if tubes.is_empty() {
        return Ok((SceneMesh::default(), UnionReport { min_sin_half: 1.0, ..Default::default() }));
    }
    let n = scene.nodes.len();
    let centres: Vec<P> = scene.nodes.iter().map(|x| V3::from(x.pos)).collect();
    let radii: Vec<f64> = (0..n).map(|i| scene.radius(i)).collect();
    // Sagitta targets per node (only the links' nodes matter).
    let mut target = vec![FIRST_SAGITTA * eps; n];
    // The runs at the first targets decide `Bodies::Auto` (as `Bodies::chosen`) and are the
    // ones pregraded below; only the runs need the chains.
    let mut chains = if options.bodies == Bodies::Hulls { Vec::new() } else { scene.chains() };
    let first_runs = piece::runs(&chains, &centres, &radii, &target);
    let runs = match options.bodies {
        Bodies::Hulls => false,
        Bodies::Runs => true,
        Bodies::Auto => runs_pay(&first_runs, scene.links.len()),
    };
    if !runs {
        chains.clear();
    }
    let mut spheres = hull::Spheres::default();
    // Directions about which a node's ring is graded finer (runs only: `piece::graded`).
    let mut focus: Vec<Vec<Focus>> = vec![Vec::new(); n];
    // The build in which each (node, partner, link) focus was added: one focus per link and
    // partner at each of the link's nodes (the notch where two tubes part lies in one
    // direction of each ring, and the deepest excess, handled first, names it; a node shared
    // by two links may carry one from each).
    let mut graded_in: HashMap<(usize, u32, u32), usize> = HashMap::new();
    // Per link, the directions graded about an excess (`POINT`), with the build of each.
    let mut excess_dirs: HashMap<u32, Vec<(P, usize)>> = HashMap::new();
    // Per link, the points of its axis where a grazing tube parts from it (`piece::body`).
    let mut stations: Vec<Vec<P>> = vec![Vec::new(); pairs.len()];
    // Per node, whether its mitre spans the outer half of its ball by a wedge of rings
    // (`piece::body`).
    let mut wedge = vec![false; n];
    // The partner a focus points to: a tube's chain (one focus per chain a node's ring meets).
    let mut partner: Vec<u32> = (0..pairs.len() as u32).map(|k| k + chains.len() as u32).collect();
    for (c, chain) in chains.iter().enumerate() {
        chain.links.iter().for_each(|&l| partner[l as usize] = c as u32);
    }
    if runs {
        let mut run_link = vec![false; pairs.len()];
        for run in &first_runs {
            run.links.iter().for_each(|&l| run_link[l as usize] = true);
        }
        pregrade(&tubes, &pairs, &run_link, &partner, &mut focus, &mut graded_in, &mut stations);
    }
    let mut best: Option<(hull::Built, UnionReport)> = None;
    let most = if runs { RUN_TRIES } else { TRIES };
    for tries in 1..=most {
        let bodies = if runs {
            bodies(
                &chains,
                &centres,
                &radii,
                &target,
                piece::Grading { focus: &focus, stations: &stations, wedge: &wedge },
                eps,
            )
        } else {
            Vec::new()
        };
        // Per link: whether its run's rings may still grow (`None`: a hull).
        let mut body_of = vec![None; pairs.len()];
        let mut mitre = vec![false; n];
        for b in &bodies {
            b.tags.iter().for_each(|&t| body_of[t as usize] = Some(b.ring < piece::MAX_RING));
            b.mitres.iter().for_each(|&j| mitre[j] = true);
        }
        let hull_links: Vec<(u32, [usize; 2])> =
            pairs.iter().enumerate().filter(|(k, _)| body_of[*k].is_none()).map(|(k, &p)| (k as u32, p)).collect();
        let subdiv: Vec<u32> = (0..n).map(|i| spheres.subdivisions_for(radii[i], target[i])).collect();
        // Every hull has at most 2·(its points) − 4 triangles.
        let points = |k: u32| 4 * (k as usize) * (k as usize) + 2;
        let hull_tris: usize =
            hull_links.iter().map(|&(_, [a, b])| 2 * (points(subdiv[a]) + points(subdiv[b]))).sum::<usize>();
        let body_tris: usize = bodies.iter().map(|b| b.triangles.len()).sum::<usize>();
        let input_tris = hull_tris + body_tris;
        if let Some(limit) = options.memory_limit {
            let estimate = (UNION_BASE_BYTES
                + hull_tris as f64 * UNION_BYTES_PER_HULL_TRIANGLE
                + body_tris as f64 * UNION_BYTES_PER_BODY_TRIANGLE) as u64;
            if estimate > limit {
                if let Some((b, mut r)) = best.take() {
                    // A refinement that would not fit: keep the mesh already made.
                    r.refused_estimate = Some(estimate);
                    best = Some((b, r));
                    break;
                }
                return Err(MeshError::Memory { eps, estimate, limit, hull_triangles: input_tris });
            }
        }
        let built = hull::union(&centres, &radii, &subdiv, &hull_links, &bodies, &mut spheres)
            .map_err(|e| MeshError::Union { eps, what: e.0 })?;
        // Every point of a tube's polyhedra-hull boundary is within the larger sagitta of its
        // two spheres; positions carry rounding of a few ulps of the coordinates. A run's
        // body certifies its own sagitta.
        let sag: Vec<f64> = (0..n)
            .map(|i| {
                let c = centres[i];
                let ulps = 8.0 * f64::EPSILON * (c.x.abs().max(c.y.abs()).max(c.z.abs()) + radii[i]);
                radii[i] * spheres.get(subdiv[i]).sagitta + ulps
            })
            .collect();
        let sagitta = hull_links
            .iter()
            .map(|&(_, [a, b])| sag[a].max(sag[b]))
            .chain(bodies.iter().map(|b| b.sagitta))
            .fold(0.0, f64::max);
        let hull_nodes = || hull_links.iter().flat_map(|(_, p)| p.map(|i| subdiv[i]));
        let margin = 4.0 * eps.max(sagitta);
        let m = certify::measure(&tubes, &built.positions, &built.triangles, margin, eps, sagitta);
        let mut report = UnionReport {
            tries,
            sagitta,
            depth: m.depth,
            out: m.out,
            outside: m.over.len(),
            min_sin_half: m.min_sin_half,
            subdiv: (hull_nodes().min().unwrap_or(0), hull_nodes().max().unwrap_or(0)),
            ring: (bodies.iter().map(|b| b.ring).min().unwrap_or(0), bodies.iter().map(|b| b.ring).max().unwrap_or(0)),
            runs: bodies.len(),
            hull_triangles: input_tris,
            refused_estimate: None,
        };
        if !report.certified().is_finite() {
            report.depth = f64::INFINITY;
        }
        let done = report.certified() <= eps;
        if best.as_ref().map_or(true, |(_, r)| report.certified() <= r.certified()) {
            best = Some((built, report));
        }
        if done || tries == most {
            break;
        }
        // The depth bound is about the sagitta over sin(β/2): refine the spheres of the tubes
        // that set each excess by the factor that would meet ε (at most 1/16 per build).
        let mut changed = false;
        // A run's links are graded (or their nodes' rings raised), a hull's spheres refined.
        let before = target.clone();
        // The deepest excess first: its focus directions are the ones kept.
        let mut over: Vec<&certify::Over> = m.over.iter().collect();
        over.sort_by(|a, b| b.d.total_cmp(&a.d));
        for certify::Over { d, tubes: set, at: x, sin_half, witness } in over {
            let (d, x, sin_half) = (*d, *x, *sin_half);
            let f = if d.is_finite() { (0.9 * eps / d).clamp(1.0 / 16.0, 0.9) } else { 1.0 / 16.0 };
            let run_links: Vec<u32> = set.iter().copied().filter(|&t| body_of[t as usize].is_some()).collect();
            if !run_links.is_empty() {
                let mut graded = false;
                let mut nodes = Vec::new();
                for &t in &run_links {
                    let ends = pairs[t as usize];
                    // Whether this link was graded for the excess (towards a partner or
                    // about the excess itself).
                    let mut here = false;
                    // Not its neighbours: they meet it at a joint, not at a crease.
                    for &u in set.iter().filter(|&&u| !pairs[u as usize].iter().any(|k| ends.contains(k))) {
                        let key = partner[u as usize];
                        let when = ends.map(|node| graded_in.get(&(node, key, t)).copied());
                        // Graded towards `key` in an earlier build at both ends: the excess
                        // persists beside its grading, so grading more does not reach it.
                        if when.iter().all(|w| w.is_some_and(|b| b < tries)) {
                            continue;
                        }
                        // Graded in this build by a deeper excess: it names the same fork.
                        if when.iter().all(Option::is_some) {
                            here = true;
                            continue;
                        }
                        if let Some((v, fork)) = toward(&tubes[t as usize], &tubes[u as usize], x) {
                            for (node, w) in ends.into_iter().zip(when) {
                                if w.is_none() {
                                    focus[node].push(Focus { dir: v, key, link: t });
                                    graded_in.insert((node, key, t), tries);
                                }
                            }
                            if let Some(p) = fork {
                                stations[t as usize].push(p);
                            }
                            here = true;
                        }
                    }
                    // Graded towards every tube here and still over: where three tubes meet, the
                    // exterior is a channel between them that closes at a point, off the
                    // direction of each partner (about halfway between two), where the
                    // grading about the partners has coarsened. Grade about the excess itself:
                    // a direction within half of `fine` of one already graded is not graded
                    // again (the rings grow instead): `piece::graded` spaces a focus's first
                    // steps by `fine` either side, so such a direction lies on a chord of the
                    // finest spacing, with a half step's margin for a ring's tilt at a mitre.
                    // Any farther, its chord may be twice as long, its sagitta four times as
                    // deep, and a channel closing there stays over.
                    if !here {
                        if let Some(v) = across(&tubes[t as usize], x) {
                            let fine = eps / tubes[t as usize].ra;
                            let list = excess_dirs.entry(t).or_default();
                            match list.iter().find(|(u, _)| u.dot(v) >= (0.5 * fine).cos()) {
                                Some(&(_, when)) => here = when == tries,
                                None if list.len() < MAX_POINTS => {
                                    list.push((v, tries));
                                    for node in ends {
                                        focus[node].push(Focus { dir: v, key: POINT, link: t });
                                    }
                                    here = true;
                                }
                                None => {}
                            }
                        }
                    }
                    graded |= here;
                    if body_of[t as usize] == Some(true) {
                        nodes.extend(near_nodes(&tubes[t as usize], pairs[t as usize], x));
                    }
                }
                changed |= graded;
                // Graded before and still over: the excess is at a node (a cap, a mitre's
                // bend) or the grading falls short (where three tubes meet); the rings there
                // grow all around, where one build can plausibly fix the crease (a finite
                // bound within 8ε: a triple junction 4.2·ε deep stayed through every build
                // of a 20,000-link Bundle at 4ε).
                if !(graded || d.is_nan() || d > 8.0 * eps) {
                    // A mitre's one ring lies inside its links' cylinders on the bend's outer
                    // half, by up to `r·(1 − cos(θ/2))`, and its bands with it: a wedge of
                    // rings there first (raising the rings does not move them).
                    let mut wedged = false;
                    for &node in &nodes {
                        if mitre[node] && !wedge[node] {
                            wedge[node] = true;
                            wedged = true;
                        }
                    }
                    changed |= wedged;
                    if !wedged {
                        for node in nodes {
                            // A notch's depth goes as the square root of the sagitta.
                            let s = before[node] * (f * f).max(1.0 / 16.0);
                            if s < target[node] {
                                target[node] = s;
                                changed = true;
                            }
                        }
                    }
                }
            }
            // The hulls beside them refine their spheres by `f`: the depth at a crease goes as
            // the sagitta, `d ≈ s/sin(β/2)`. Where the bound is far below that, or a point
            // witness's, the polyhedra do not cross there yet: two surfaces nearly face each
            // other (a ball overlapping a tube's side by a hair, in a lens), and the mesh
            // points in the lens lie as deep as the lens's radius whatever the sagitta until
            // the polyhedra overlap inside it. `d` then says nothing of the sagitta needed, and
            // the opening does: at least to the sagitta at which a crease of that opening
            // meets ε (at most 1/16 per build).
            for &t in set.iter().filter(|&&t| body_of[t as usize].is_none()) {
                for node in pairs[t as usize] {
                    let (now, room) = (sag[node].min(before[node]), subdiv[node] < hull::MAX_SUBDIV);
                    let lens = *witness || d * sin_half < 0.25 * now;
                    let crease = if lens { (0.9 * eps * sin_half).max(now / 16.0) } else { f64::INFINITY };
                    let s = (now * f).min(crease).min(target[node]);
                    if s < target[node] && room {
                        target[node] = s;
                        changed = true;
                    }
                }
            }
        }
        if !changed {
            break;
        }
    }
    let (built, report) = best.expect("at least one build");
    Ok((assemble(scene, built, &links, report.certified()), report))
}

/// The unit direction across `own`'s axis towards `x`, or `None` where `x` lies on the axis.
fn across(own: &RoundCone<f64>, x: P) -> Option<P> {
    let ax = tube::unit(own.b - own.a);
    let y = x - own.a;
    let v = y - ax * y.dot(ax);
    (v.length() > 1e-3 * own.ra).then(|| tube::unit(v))
}

/// The direction, across link `own`'s axis, towards the tube `o` (not its neighbour), with
/// the fork where they part, if any: where two tubes cross or graze, the crease's opening
/// shrinks towards the other tube, to a notch where they part. The notch is where the axes
/// are the two radii apart (the fork nearest `x`); where the axes stay nearer or farther
/// along the whole link, the direction at `x` stands in. `None` where the other axis passes
/// through this one there (no direction).
fn toward(own: &RoundCone<f64>, o: &RoundCone<f64>, x: P) -> Option<(P, Option<P>)> {
    let w = own.b - own.a;
    let ow = o.b - o.a;
    let on = |p: P| o.a + ow * ((p - o.a).dot(ow) / ow.length2()).clamp(0.0, 1.0);
    // The gap between the two tubes' sides over the axis point at `s` (convex in s).
    let at = |s: f64| own.a + w * s;
    let gap = |s: f64| (on(at(s)) - at(s)).length() - own.ra - o.ra;
    let sx = ((x - own.a).dot(w) / w.length2()).clamp(0.0, 1.0);
    let f = fork(gap, sx);
    let s = f.unwrap_or(sx);
    across(own, on(at(s))).map(|v| (v, f.map(at)))
}

/// Where two tubes part at a grazing angle their crease ends in a notch, which a uniform ring
/// leaves up to `√(2·r·s)` deep (`piece::graded`): the forks of every run link `t` with every
/// other chain that meets it, as foci of `t`'s two rings (towards the other chain's axis) and
/// stations of `t`, before the first build. A fork is where the distance from `t`'s axis to
/// the other chain's axes crosses the sum of the radii: to the chain, not to each of its
/// links, since a link of it that ends is no fork where the next one goes on (counted per
/// link, the Bundle's forks were five times as many as the grading the certificate asked for,
/// and graded that way its mesh had a quarter more triangles). Only grazing forks: the
/// other chain's link there within `asin(GRAZING_SIN)` of parallel to `t`.
fn pregrade(
    tubes: &[RoundCone<f64>],
    pairs: &[[usize; 2]],
    run_link: &[bool],
    partner: &[u32],
    focus: &mut [Vec<Focus>],
    graded_in: &mut HashMap<(usize, u32, u32), usize>,
    stations: &mut [Vec<P>],
) {
    const SAMPLES: usize = 32;
    let r_max = tubes.iter().fold(0.0f64, |m, t| m.max(t.ra).max(t.rb));
    let index = tube::Index::new(tubes, 4.0 * r_max);
    let mut near = Vec::new();
    for (t, own) in tubes.iter().enumerate() {
        if !run_link[t] {
            continue;
        }
        let b = tubecast::Primitive::aabb(own);
        index.near(b.min, b.max, 0.0, &mut near);
        let ends = pairs[t];
        let w = own.b - own.a;
        let ax = tube::unit(w);
        let mut groups: HashMap<u32, Vec<u32>> = HashMap::new();
        for &u in &near {
            if u as usize != t && !pairs[u as usize].iter().any(|k| ends.contains(k)) {
                groups.entry(partner[u as usize]).or_default().push(u);
            }
        }
        let at = |s: f64| own.a + w * s;
        for (key, us) in groups {
            // The other chain's nearest axis point to `x`, and the gap between the sides there.
            let nearest = |x: P| {
                us.iter()
                    .map(|&u| {
                        let o = &tubes[u as usize];
                        let ow = o.b - o.a;
                        let k =
                            if ow.length2() > 0.0 { ((x - o.a).dot(ow) / ow.length2()).clamp(0.0, 1.0) } else { 0.0 };
                        let y = o.a + ow * k;
                        ((y - x).length() - own.ra - (o.ra + (o.rb - o.ra) * k), y, u)
                    })
                    .fold((f64::INFINITY, x, u32::MAX), |m, c| if c.0 < m.0 { c } else { m })
            };
            let gap = |s: f64| nearest(at(s)).0;
            let g: Vec<f64> = (0..=SAMPLES).map(|i| gap(i as f64 / SAMPLES as f64)).collect();
            for i in 0..SAMPLES {
                if (g[i] < 0.0) == (g[i + 1] < 0.0) {
                    continue;
                }
                let (inside, outside) = if g[i] < 0.0 { (i, i + 1) } else { (i + 1, i) };
                let s = bisect(gap, inside as f64 / SAMPLES as f64, outside as f64 / SAMPLES as f64);
                let (_, y, u) = nearest(at(s));
                let ou = &tubes[u as usize];
                if ou.b != ou.a && ax.cross(tube::unit(ou.b - ou.a)).length() >= GRAZING_SIN {
                    continue;
                }
                // No direction where the other axis passes through this one (nor a NaN one).
                let Some(v) = across(own, y) else {
                    continue;
                };
                for node in ends {
                    focus[node].push(Focus { dir: v, key, link: t as u32 });
                    // Graded before the first build: an excess there raises the rings.
                    graded_in.entry((node, key, t as u32)).or_insert(0);
                }
                stations[t].push(at(s));
            }
        }
    }
}

/// The root in `[0, 1]` of the convex `gap` nearest `sx`, if any: its least point by golden
/// section, then bisection on each side where the sign changes.
fn fork(gap: impl Fn(f64) -> f64, sx: f64) -> Option<f64> {
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    let g = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..60 {
        let (m1, m2) = (hi - g * (hi - lo), lo + g * (hi - lo));
        if gap(m1) < gap(m2) {
            hi = m2;
        } else {
            lo = m1;
        }
    }
    let m = 0.5 * (lo + hi);
    if gap(m) >= 0.0 {
        return None;
    }
    let root = |inside: f64, outside: f64| (gap(outside) >= 0.0).then(|| bisect(&gap, inside, outside));
    match (root(m, 0.0), root(m, 1.0)) {
        (Some(a), Some(b)) => Some(if (a - sx).abs() <= (b - sx).abs() { a } else { b }),
        (a, b) => a.or(b),
    }
}

/// The root of `gap` between `inside` (`gap < 0`) and `outside` (`gap ≥ 0`), by bisection to
/// 2⁻⁶⁰ of their distance.
fn bisect(gap: impl Fn(f64) -> f64, mut inside: f64, mut outside: f64) -> f64 {
    for _ in 0..60 {
        let mid = 0.5 * (inside + outside);
        if gap(mid) < 0.0 {
            inside = mid;
        } else {
            outside = mid;
        }
    }
    0.5 * (inside + outside)
}

/// The nodes of a link whose rings set the mesh at `x`: the one within half a radius of `x`
/// along the axis (a cap or a mitre), or both.
fn near_nodes(own: &RoundCone<f64>, [a, b]: [usize; 2], x: P) -> Vec<usize> {
    let w = own.b - own.a;
    let k = (x - own.a).dot(w) / w.length2();
    let end = 0.5 * own.ra / w.length();
    if k < end {
        vec![a]
    } else if k > 1.0 - end {
        vec![b]
    } else {
        vec![a, b]
    }
}

/// The runs' bodies at the current sagitta targets: each run at its ring size, cut where its
/// body would turn back onto itself (both parts then close with half-spheres).
fn bodies(
    chains: &[crate::scene::Chain],
    centres: &[P],
    radii: &[f64],
    target: &[f64],
    grading: piece::Grading,
    eps: f64,
) -> Vec<piece::Body> {
    use rayon::prelude::*;
    piece::runs(chains, centres, radii, target)
        .into_par_iter()
        .flat_map_iter(|run| {
            let mut todo = vec![run];
            let mut out = Vec::new();
            while let Some(run) = todo.pop() {
                let sizes = piece::ring_sizes(&run, centres, target);
                match piece::body(&run, centres, &sizes, grading, eps) {
                    Ok(b) => out.push(b),
                    Err(j) => {
                        let r = run.r;
                        todo.push(piece::Run { nodes: run.nodes[..=j].to_vec(), links: run.links[..j].to_vec(), r });
                        todo.push(piece::Run { nodes: run.nodes[j..].to_vec(), links: run.links[j..].to_vec(), r });
                    }
                }
            }
            out
        })
        .collect()
}

/// The scene's links as round cones (radius 0 and non-finite data refused), with their
/// scene link indices and node pairs.
#[allow(clippy::type_complexity)]
fn tubes(scene: &Scene) -> Result<(Vec<RoundCone<f64>>, Vec<u32>, Vec<[usize; 2]>), MeshError> {
    let mut tubes = Vec::with_capacity(scene.links.len());
    let mut links = Vec::with_capacity(scene.links.len());
    let mut pairs = Vec::with_capacity(scene.links.len());
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
        pairs.push([a, b]);
    }
    Ok((tubes, links, pairs))
}

/// The scene mesh: triangles grouped by connected component (one [`Part`] each), tagged with
/// the scene link whose hull they lie on.
fn assemble(scene: &Scene, raw: hull::Built, links: &[u32], certified: f64) -> SceneMesh {
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
    let link_of = |k: usize| links.get(raw.link[k] as usize).copied().unwrap_or(0);
    let mut start = 0;
    for (i, &k) in order.iter().enumerate() {
        let t = raw.triangles[k];
        out.mesh.triangles.push(t);
        out.mesh.tags.push(link_of(k));
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Two chains crossing at `angle` (their axes 0.1 apart, radius 0.1: the tubes overlap,
    /// so each has two forks on the other), graded before the first build: the stations made.
    fn crossing_stations(angle: f64) -> usize {
        let mut tubes = Vec::new();
        let mut pairs = Vec::new();
        for (chain, angle, z) in [(0usize, 0.0f64, 0.0), (1, angle, 0.1)] {
            let p = |t: f64| V3::new(t * angle.cos(), t * angle.sin(), z);
            for k in 0..8 {
                tubes.push(RoundCone::new(p(0.25 * k as f64 - 1.0), 0.1, p(0.25 * (k + 1) as f64 - 1.0), 0.1).unwrap());
                pairs.push([9 * chain + k, 9 * chain + k + 1]);
            }
        }
        let partner: Vec<u32> = (0..16).map(|k| (k / 8) as u32).collect();
        let mut focus = vec![Vec::new(); 18];
        let mut stations = vec![Vec::new(); 16];
        pregrade(&tubes, &pairs, &[true; 16], &partner, &mut focus, &mut HashMap::new(), &mut stations);
        assert_eq!(focus.iter().map(Vec::len).sum::<usize>(), 2 * stations.iter().map(Vec::len).sum::<usize>());
        stations.iter().map(Vec::len).sum()
    }

    /// Only grazing crossings are graded before the first build: the notch where tubes part
    /// is theirs.
    #[test]
    fn pregrade_leaves_wide_crossings_alone() {
        assert_eq!(crossing_stations(60f64.to_radians()), 0);
        assert_eq!(crossing_stations(20f64.to_radians()), 4);
    }

    /// Two straight chains of radius `r` crossing at the origin at angle β, links of 0.5 with
    /// nodes at `0.5·k + t0`: every fork of chain 0 with chain 1 is where `|t|·sin β = 2r`,
    /// mid-link, and chain 1's joints (where one of its links ends and the next goes on) are
    /// no forks.
    #[test]
    fn pregrade_grades_the_forks_of_chains_not_of_links() {
        let (r, beta, t0) = (0.1, 0.02f64, -15.25);
        let mut tubes = Vec::new();
        let mut pairs = Vec::new();
        let mut partner = Vec::new();
        for (chain, angle) in [(0u32, 0.0f64), (1, beta)] {
            for k in 0..60 {
                let p = |t: f64| V3::new(t * angle.cos(), t * angle.sin(), 0.0);
                let (a, b) = (0.5 * k as f64 + t0, 0.5 * (k + 1) as f64 + t0);
                tubes.push(RoundCone::new(p(a), r, p(b), r).unwrap());
                let base = 61 * chain as usize;
                pairs.push([base + k, base + k + 1]);
                partner.push(chain);
            }
        }
        let run_link = vec![true; tubes.len()];
        let mut focus = vec![Vec::new(); 122];
        let mut graded_in = HashMap::new();
        let mut stations = vec![Vec::new(); tubes.len()];
        pregrade(&tubes, &pairs, &run_link, &partner, &mut focus, &mut graded_in, &mut stations);
        let fork = 2.0 * r / beta.sin();
        for (chain, angle) in [(0usize, 0.0f64), (1, beta)] {
            let along = V3::new(angle.cos(), angle.sin(), 0.0);
            let mut found: Vec<f64> =
                stations[60 * chain..60 * chain + 60].iter().flatten().map(|p| p.dot(along)).collect();
            found.sort_by(f64::total_cmp);
            assert_eq!(found.len(), 2, "chain {chain}: forks at {found:?}");
            // The bisection ends 2⁻⁶⁰ of a sample apart; the gap, about 10 from the origin,
            // rounds to ~10⁻¹⁵ and rises at sin β = 0.02 per unit along the axis, so the root
            // is found to ~10⁻¹³: 10⁻⁹ is slack for that, far below a link (0.5).
            assert!((found[0] + fork).abs() < 1e-9 && (found[1] - fork).abs() < 1e-9, "{found:?} against ±{fork}");
        }
        // Each fork's link grades both its rings towards the other chain, across its axis.
        let graded: Vec<&Focus> = focus.iter().flatten().collect();
        assert_eq!(graded.len(), 8, "{graded:?}");
        for f in graded {
            let own = &tubes[f.link as usize];
            assert_eq!(f.key, 1 - partner[f.link as usize], "{f:?}");
            // Towards the other chain's line, from the fork.
            let at = stations[f.link as usize][0];
            let other = if f.key == 1 { V3::new(beta.cos(), beta.sin(), 0.0) } else { V3::new(1.0, 0.0, 0.0) };
            let to = other * at.dot(other) - at;
            // `to` is perpendicular to the other line, `dir` to this one: they differ by at
            // most β = 0.02 rad, cos β = 0.9998.
            assert!(f.dir.dot(tube::unit(to)) > 0.999, "{f:?} from {at:?}");
            // `dir` is the unit of a vector with its axial part removed: a few ulps of 1.
            assert!(f.dir.dot(tube::unit(own.b - own.a)).abs() < 1e-12, "{f:?}");
            assert!((f.dir.length() - 1.0).abs() < 1e-12, "{f:?}");
        }
    }
}
