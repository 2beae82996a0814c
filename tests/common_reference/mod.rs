//! Reading the manifold3d + libigl fixtures of `reference/fixtures/` (see `reference/README.md`)
//! and evaluating our kernels on the same scenes. Nothing here computes an expected value: the
//! expected values (exact hits in numpy, mesh hits and SDF from libigl, the mesh bound `h`) all
//! come from the fixture files.
#![allow(dead_code)]

use serde_json::Value;
use tubecast::kernel::csg::{union, Boundary, Tagged};
use tubecast::kernel::roots::Solver;
use tubecast::kernel::spline::QuadTube;
use tubecast::{HanLink, Ray, RoundCone, V3};

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
    Fixture {
        name: name.to_string(),
        scene,
        mesh,
        centre: v3(&bs["centre"]),
        radius: f(bs, "radius"),
        rays,
        sdf,
    }
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
pub fn boundaries(fx: &Fixture, k: Kernel, ray: &Ray<f64>) -> Vec<Boundary<f64>> {
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
