//! Reading the manifold3d + libigl fixtures of `reference/fixtures/` (see `reference/README.md`)
//! and evaluating our kernels on the same scenes. Nothing here computes an expected value: the
//! expected values (exact hits in numpy, mesh hits and SDF from libigl, the mesh bound `h`) all
//! come from the fixture files.
#![allow(dead_code)]

use serde_json::Value;
use tubecast::baseline::HanLink;
use tubecast::csg::{union, Tagged};
use tubecast::Hit;
use tubecast::QuadTube;
use tubecast::Solver;
use tubecast::{Primitive, Ray, RoundCone, V3};

pub type V = V3<f64>;

/// What libigl and the numpy generator say about one ray.
#[derive(Clone, Debug)]
pub struct RayRec {
    pub kind: String,
    pub o: V,
    pub d: V,
    pub exact: Option<Exact>,
    /// Certified lower bound on the distance of a missing ray to the solid.
    pub clearance: Option<f64>,
    /// libigl's first hit, t recomputed in double from the hit triangle.
    pub mesh_t: Option<f64>,
    pub mesh_bary_min: Option<f64>,
}

/// The exact first boundary (numpy, independent of the Rust code).
#[derive(Clone, Debug)]
pub struct Exact {
    pub t: f64,
    pub entering: bool,
    pub point: V,
    pub normal: V,
    pub piece: usize,
    pub u: f64,
    /// Radius of the generating sphere touching the surface at the hit point.
    pub radius: f64,
    pub cos_angle: f64,
    /// libigl's signed distance at `point`.
    pub mesh_sdf: f64,
    /// Inside rays: certified inside the mesh on `[0, deep_until]`.
    pub deep_until: Option<f64>,
}

#[derive(Clone, Debug)]
pub struct SdfRec {
    pub x: V,
    pub exact: f64,
    pub mesh: f64,
}

#[derive(Clone, Debug)]
pub struct MeshInfo {
    pub n: u32,
    pub triangles: u64,
    /// Largest sphere-to-mesh gap of the scene's sphere meshes (measured on the triangles).
    pub sagitta: f64,
    pub sagitta_coeff: f64,
    pub chord_error: f64,
    pub manifold_tolerance: f64,
    pub vertex_radius_error: f64,
}

impl MeshInfo {
    /// How far mesh vertices may sit outside the exact surface by rounding: manifold3d's
    /// merge tolerance plus the vertex radius rounding, plus the spline's chord error.
    pub fn outward_slack(&self) -> f64 {
        self.manifold_tolerance + self.vertex_radius_error + self.chord_error
    }
    /// The inward bound: every point of the solid is within this of the mesh.
    pub fn inward_bound(&self) -> f64 {
        self.sagitta + self.chord_error + self.manifold_tolerance + self.vertex_radius_error
    }
}

pub enum Scene {
    Links(Vec<RoundCone<f64>>),
    Spline(QuadTube<f64>),
}

pub struct Fixture {
    pub name: String,
    pub scene: Scene,
    pub mesh: MeshInfo,
    pub centre: V,
    pub radius: f64,
    pub rays: Vec<RayRec>,
    pub sdf: Vec<SdfRec>,
}

fn v3(v: &Value) -> V {
    let a = v.as_array().expect("3-vector");
    V::new(a[0].as_f64().unwrap(), a[1].as_f64().unwrap(), a[2].as_f64().unwrap())
}
fn f(v: &Value, k: &str) -> f64 {
    v[k].as_f64().unwrap_or_else(|| panic!("fixture field {k} missing or not a number"))
}

pub fn load(name: &str) -> Fixture {
    let path = format!("{}/reference/fixtures/{name}.json", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("cannot read {path}: {e}"));
    let j: Value = serde_json::from_str(&text).unwrap_or_else(|e| panic!("{path}: {e}"));
    assert_eq!(j["format"].as_u64(), Some(1), "{path}: unknown fixture format");
    let m = &j["mesh"];
    let mesh = MeshInfo {
        n: m["circular_segments"].as_u64().unwrap() as u32,
        triangles: m["triangles"].as_u64().unwrap(),
        sagitta: f(m, "sagitta"),
        sagitta_coeff: f(m, "sagitta_coeff"),
        chord_error: f(m, "chord_error"),
        manifold_tolerance: f(m, "manifold_tolerance"),
        vertex_radius_error: f(m, "vertex_radius_error"),
    };
    let scene = match j["kind"].as_str() {
        Some("links") => {
            let nodes: Vec<(V, f64)> = j["nodes"]
                .as_array()
                .unwrap()
                .iter()
                .map(|n| {
                    let a = n.as_array().unwrap();
                    let g = |i: usize| a[i].as_f64().unwrap();
                    (V::new(g(0), g(1), g(2)), g(3))
                })
                .collect();
            let links = j["links"]
                .as_array()
                .unwrap()
                .iter()
                .map(|l| {
                    let (ia, ib) = (l[0].as_u64().unwrap() as usize, l[1].as_u64().unwrap() as usize);
                    RoundCone::new(nodes[ia].0, nodes[ia].1, nodes[ib].0, nodes[ib].1).expect("valid link")
                })
                .collect();
            Scene::Links(links)
        }
        Some("spline") => {
            let cp = j["control_points"].as_array().unwrap();
            let cr = j["control_radii"].as_array().unwrap();
            let b = [v3(&cp[0]), v3(&cp[1]), v3(&cp[2])];
            let r = [cr[0].as_f64().unwrap(), cr[1].as_f64().unwrap(), cr[2].as_f64().unwrap()];
            Scene::Spline(QuadTube::new(b, r).expect("valid spline"))
        }
        k => panic!("{path}: unknown kind {k:?}"),
    };
    let rays = j["rays"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| {
            let exact = if r["exact"].is_null() {
                None
            } else {
                let e = &r["exact"];
                Some(Exact {
                    t: f(e, "t"),
                    entering: e["entering"].as_bool().unwrap(),
                    point: v3(&e["point"]),
                    normal: v3(&e["normal"]),
                    piece: e["piece"].as_u64().unwrap() as usize,
                    u: f(e, "u"),
                    radius: f(e, "radius"),
                    cos_angle: f(e, "cos_angle"),
                    mesh_sdf: f(e, "mesh_sdf"),
                    deep_until: e.get("deep_until").and_then(|x| x.as_f64()),
                })
            };
            RayRec {
                kind: r["kind"].as_str().unwrap().to_string(),
                o: v3(&r["o"]),
                d: v3(&r["d"]),
                exact,
                clearance: r.get("clearance").and_then(|x| x.as_f64()),
                mesh_t: r["mesh"].get("t").and_then(|x| x.as_f64()),
                mesh_bary_min: r["mesh"].get("triangle_bary_min").and_then(|x| x.as_f64()),
            }
        })
        .collect();
    let sdf = j["sdf"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| SdfRec { x: v3(&s["x"]), exact: f(s, "exact"), mesh: f(s, "mesh") })
        .collect();
    let bs = &j["bounding_sphere"];
    Fixture { name: name.to_string(), scene, mesh, centre: v3(&bs["centre"]), radius: f(bs, "radius"), rays, sdf }
}

/// Which of our kernels to run on a scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Kernel {
    /// `RoundCone::intersect` per link, CSG union.
    Stable,
    /// `HanLink::new(&link).intersect` per link, CSG union.
    Han,
    /// `QuadTube::intersect_pieces` with a solver, CSG union.
    Spline(Solver),
}

/// Every exterior boundary of the union along the ray with `t ≥ 0` (in increasing t).
pub fn boundaries(fx: &Fixture, k: Kernel, ray: &Ray<f64>) -> Vec<Hit<f64>> {
    let mut tagged: Vec<Tagged<f64>> = Vec::new();
    match (&fx.scene, k) {
        (Scene::Links(links), Kernel::Stable) => {
            for (i, l) in links.iter().enumerate() {
                tagged.push(Tagged { iv: l.intersect(ray), id: i as u32 });
            }
        }
        (Scene::Links(links), Kernel::Han) => {
            for (i, l) in links.iter().enumerate() {
                tagged.push(Tagged { iv: HanLink::new(l).intersect(ray), id: i as u32 });
            }
        }
        (Scene::Spline(s), Kernel::Spline(solver)) => {
            for iv in s.intersect_pieces(ray, solver) {
                tagged.push(Tagged { iv, id: 0 });
            }
        }
        _ => panic!("kernel {k:?} does not apply to fixture {}", fx.name),
    }
    let mut out = Vec::new();
    union(&mut tagged, ray.t_min, ray.t_max, |b| out.push(b));
    out
}

/// Radius of the generating sphere at curve parameter `u` of piece `id`.
pub fn radius_at(fx: &Fixture, id: u32, u: f64) -> f64 {
    match &fx.scene {
        Scene::Links(l) => {
            let l = &l[id as usize];
            l.ra + (l.rb - l.ra) * u
        }
        Scene::Spline(s) => s.radius(u),
    }
}

/// The largest radius in the scene (the sagitta scales with it).
pub fn max_radius(fx: &Fixture) -> f64 {
    match &fx.scene {
        Scene::Links(l) => l.iter().map(|l| l.ra.max(l.rb)).fold(0.0, f64::max),
        Scene::Spline(s) => s.r.iter().cloned().fold(0.0, f64::max),
    }
}

/// Ray parameter beyond a boundary at which the ray is more than `h` deep inside the
/// generating ball `B(c, r)` that touches the surface there, per unit of `|d|`
/// (see the derivation at its use). `None` when the ray never gets that deep (grazing).
pub fn depth_reach(r: f64, cos_a: f64, h: f64) -> Option<f64> {
    let disc = r * r * cos_a * cos_a - (2.0 * r * h - h * h);
    if disc < 0.0 {
        None
    } else {
        Some(r * cos_a - disc.sqrt())
    }
}

pub const EPS: f64 = f64::EPSILON;

/// What one scene × kernel comparison saw (printed with --nocapture).
#[derive(Default, Debug)]
pub struct Stats {
    rays: usize,
    compared_exact: usize,
    ambiguous_graze: usize,
    mesh_compared: usize,
    mesh_band_misses: usize,
    mesh_band_hits_in_band: usize,
    sdf_at_hit_checked: usize,
    max_point_err: f64,
    max_rel_t_err: f64,
    max_mesh_dt: f64,
    min_mesh_dt: f64,
    max_mesh_sdf_at_hit: f64,
    min_mesh_sdf_at_hit: f64,
    inside_rays: usize,
    inside_shallow: usize,
}

pub fn kernel_budget(fx: &Fixture, k: Kernel, o: V) -> f64 {
    let s = fx.radius;
    let d = (o - fx.centre).length();
    match k {
        Kernel::Stable | Kernel::Spline(_) => 64.0 * EPS * (s + d),
        Kernel::Han => {
            let Scene::Links(links) = &fx.scene else { unreachable!() };
            links
                .iter()
                .map(|l: &RoundCone<f64>| {
                    let len = (l.b - l.a).length();
                    let dr = (l.ra - l.rb).abs();
                    let p2 = if dr == 0.0 || dr >= len { 0.0 } else { len * l.ra.max(l.rb) / dr };
                    let dd = d + p2 + s;
                    let r_min = l.ra.min(l.rb);
                    64.0 * EPS * dd * (dd / r_min).max(1.0)
                })
                .fold(0.0, f64::max)
        }
    }
}

/// Compare a kernel to one fixture; tolerances and their analysis: the module docs of
/// `tests/reference/links.rs`. Panics with the list of failures.
pub fn check_scene(name: &str, k: Kernel) -> Stats {
    let fx = load(name);
    let m = &fx.mesh;
    let mu = m.manifold_tolerance + m.vertex_radius_error + m.chord_error;
    let h_in = m.inward_bound();
    let mut st = Stats { min_mesh_dt: f64::INFINITY, min_mesh_sdf_at_hit: f64::INFINITY, ..Default::default() };
    let mut fails: Vec<String> = Vec::new();
    for (j, r) in fx.rays.iter().enumerate() {
        st.rays += 1;
        let ray = Ray::new(r.o, r.d);
        let dl = r.d.length();
        let dist = (r.o - fx.centre).length();
        let e_k = kernel_budget(&fx, k, r.o);
        let e_ref = 32.0 * EPS * (dist + fx.radius + fx.centre.length());
        let bs = boundaries(&fx, k, &ray);
        let b0 = bs.first().copied();
        let tag = format!("{name} {k:?} ray {j} ({})", r.kind);
        // (1) kernel vs exact
        let mut graze = false;
        match (&r.exact, b0) {
            (None, None) => {}
            (None, Some(b)) => {
                let c = r.clearance.unwrap_or(0.0);
                if c > e_k + e_ref {
                    fails.push(format!("{tag}: exact misses with clearance {c:e}, kernel hits at t={}", b.t));
                } else {
                    st.ambiguous_graze += 1;
                    graze = true;
                }
            }
            (Some(e), kb) => {
                // depth of the ray in the generating ball at the exact hit: a lower bound on
                // how deep it goes into the solid
                let pen = e.radius * (1.0 - (1.0 - e.cos_angle * e.cos_angle).max(0.0).sqrt());
                let touch = e.entering && pen <= e_k + e_ref;
                match kb {
                    None if touch => {
                        st.ambiguous_graze += 1;
                        graze = true;
                    }
                    None => fails.push(format!("{tag}: kernel misses, exact hits at t={} (depth {pen:e})", e.t)),
                    Some(b) => {
                        let x = ray.at(b.t);
                        let perr = (x - e.point).length();
                        let tol_t = (e_k + e_ref) / (e.cos_angle * dl);
                        if touch && (b.t - e.t).abs() > tol_t {
                            st.ambiguous_graze += 1; // tangential contact seen by one side only
                            graze = true;
                        } else {
                            st.compared_exact += 1;
                            st.max_point_err = st.max_point_err.max(perr);
                            st.max_rel_t_err = st.max_rel_t_err.max((b.t - e.t).abs() / tol_t);
                            if (b.t - e.t).abs() > tol_t {
                                fails.push(format!("{tag}: t {} vs exact {} (tol {tol_t:e})", b.t, e.t));
                            }
                            if b.entering != e.entering {
                                fails.push(format!("{tag}: entering {} vs exact {}", b.entering, e.entering));
                            }
                            // (3) libigl's SDF at the exact point must be in the mesh band; at our
                            // point it then lies within perr of it (1-Lipschitz).
                            if !(-mu..=h_in).contains(&e.mesh_sdf) {
                                fails.push(format!(
                                    "{tag}: libigl sdf at exact hit {:e} outside [-{mu:e}, {h_in:e}]",
                                    e.mesh_sdf
                                ));
                            }
                            if perr <= h_in / 16.0 {
                                st.sdf_at_hit_checked += 1;
                                let lo = e.mesh_sdf - perr;
                                let hi = e.mesh_sdf + perr;
                                st.max_mesh_sdf_at_hit = st.max_mesh_sdf_at_hit.max(hi);
                                st.min_mesh_sdf_at_hit = st.min_mesh_sdf_at_hit.min(lo);
                                if lo < -mu - perr || hi > h_in + perr {
                                    fails.push(format!("{tag}: libigl sdf at our hit in [{lo:e}, {hi:e}]"));
                                }
                            }
                        }
                    }
                }
            }
        }
        // (2) kernel vs mesh, one-sided
        let b = match b0 {
            Some(b) if !graze => b,
            _ => {
                if let (Some(tm), None, false) = (r.mesh_t, b0, graze) {
                    fails.push(format!("{tag}: mesh hits at t={tm} but the kernel misses"));
                }
                continue;
            }
        };
        let n = b.n;
        let cos_a = (n.dot(r.d) / dl).abs();
        let rad = radius_at(&fx, b.id, b.u);
        let slack = (mu + e_k + e_ref + 8.0 * EPS * (dist + fx.radius)) / (cos_a * dl);
        if b.entering {
            let reach = depth_reach(rad, cos_a, h_in + e_k);
            match (r.mesh_t, reach) {
                (None, Some(s)) => fails
                    .push(format!("{tag}: mesh misses a non-grazing ray (cos α {cos_a:e}, reach {s:e}, t_K {})", b.t)),
                (None, None) => st.mesh_band_misses += 1,
                (Some(tm), reach) => {
                    let dt = (tm - b.t) * dl;
                    if tm < b.t - slack {
                        fails.push(format!("{tag}: mesh hit {tm} before the kernel's {} (slack {slack:e})", b.t));
                    }
                    match reach {
                        Some(s) => {
                            st.mesh_compared += 1;
                            st.max_mesh_dt = st.max_mesh_dt.max(dt / s.max(1e-300));
                            st.min_mesh_dt = st.min_mesh_dt.min(dt);
                            if tm > b.t + s / dl + slack {
                                fails.push(format!(
                                    "{tag}: mesh hit {tm} beyond the band: kernel {} + reach {:e}",
                                    b.t,
                                    s / dl
                                ));
                            }
                        }
                        None => {
                            // grazing band: the mesh point must lie inside our solid
                            let inside = bs.windows(2).any(|w| {
                                w[0].entering && !w[1].entering && tm >= w[0].t - slack && tm <= w[1].t + slack
                            });
                            if !inside {
                                fails.push(format!("{tag}: grazing mesh hit {tm} outside every kernel interval"));
                            } else {
                                st.mesh_band_hits_in_band += 1;
                            }
                        }
                    }
                }
            }
        } else {
            let deep = r.exact.as_ref().and_then(|e| e.deep_until).unwrap_or(0.0);
            match r.mesh_t {
                None => fails.push(format!("{tag}: ray from inside, the mesh reports no exit")),
                Some(tm) => {
                    st.mesh_compared += 1;
                    st.min_mesh_dt = st.min_mesh_dt.min((b.t - tm) * dl);
                    if tm > b.t + slack || tm < deep - slack {
                        fails.push(format!("{tag}: mesh exit {tm} outside [deep_until {deep}, kernel {}]", b.t));
                    }
                    // Usually the certified-deep stretch reaches the resolution band before the
                    // exit; a ray that passes within h of the surface from inside (near a crease,
                    // or skimming the wall) is certified only up to there, and the mesh may let it
                    // out early. Counted, and bounded below.
                    if let Some(s) = depth_reach(rad, cos_a, h_in + e_k) {
                        st.inside_rays += 1;
                        if deep < b.t - s / dl - slack {
                            st.inside_shallow += 1;
                        }
                    }
                }
            }
        }
    }
    eprintln!("{name} {k:?}: {st:?}");
    assert!(fails.is_empty(), "{} failures, first ones:\n{}", fails.len(), fails[..fails.len().min(12)].join("\n"));
    // Not vacuous: most rays were compared, and both outcomes occur.
    assert!(st.compared_exact >= fx.rays.len() / 3, "{name}: only {} rays compared", st.compared_exact);
    assert!(st.mesh_compared >= fx.rays.len() / 3, "{name}: only {} mesh comparisons", st.mesh_compared);
    assert!(
        st.inside_shallow * 10 <= st.inside_rays,
        "{name}: {} of {} inside rays skim the wall",
        st.inside_shallow,
        st.inside_rays
    );
    assert!(st.sdf_at_hit_checked * 10 >= st.compared_exact * 9, "{name}: SDF-at-hit check skipped too often");
    st
}
