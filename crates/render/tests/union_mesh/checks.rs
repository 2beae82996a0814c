//! Independent checks of a union mesh: topology (closed, oriented, 2-manifold), embedding (no
//! two triangles cross), and geometry against the exact union SDF (the minimum of the links'
//! round-cone SDFs, computed here from the scene, not from the mesher's hash).

use rand::{Rng, SeedableRng};
use std::collections::HashMap;
use tubecast::{Primitive, RoundCone, V3};
use tubecast_render::mesh::SceneMesh;
use tubecast_render::scene::Scene;

pub type P = V3<f64>;

/// The scene's links.
pub fn tubes(scene: &Scene) -> Vec<RoundCone<f64>> {
    (0..scene.links.len()).map(|k| scene.link(k)).collect()
}

/// The exact union SDF.
pub fn sdf(tubes: &[RoundCone<f64>], x: P) -> f64 {
    tubes.iter().map(|t| t.sdf(x)).fold(f64::INFINITY, f64::min)
}

/// Every undirected edge in exactly two triangles, each directed edge in exactly one
/// (consistent winding), no repeated corner, and the triangles around every vertex one
/// cycle (no pinched vertex). Panics with the offending element.
pub fn closed_manifold(m: &SceneMesh) {
    let tris = &m.mesh.triangles;
    let mut directed: HashMap<(u32, u32), usize> = HashMap::new();
    for (k, t) in tris.iter().enumerate() {
        assert!(t[0] != t[1] && t[1] != t[2] && t[0] != t[2], "triangle {k} repeats a corner: {t:?}");
        for e in 0..3 {
            let d = (t[e], t[(e + 1) % 3]);
            assert!(
                directed.insert(d, k).is_none(),
                "directed edge {d:?} twice (inconsistent winding or a 3-way edge)"
            );
        }
    }
    for &(a, b) in directed.keys() {
        assert!(directed.contains_key(&(b, a)), "edge ({a}, {b}) is on the border (open surface)");
    }
    // Around vertex v: the map a → b over its triangles (v, a, b) must be one cycle.
    let mut around: HashMap<u32, HashMap<u32, u32>> = HashMap::new();
    for t in tris {
        for e in 0..3 {
            around.entry(t[e]).or_default().insert(t[(e + 1) % 3], t[(e + 2) % 3]);
        }
    }
    for (v, next) in &around {
        let start = *next.keys().next().unwrap();
        let (mut a, mut n) = (start, 0);
        loop {
            a = next[&a];
            n += 1;
            if a == start {
                break;
            }
            assert!(n <= next.len(), "vertex {v}: its fan is not a cycle");
        }
        assert_eq!(n, next.len(), "vertex {v} is pinched: {} fans", next.len() as f64 / n as f64);
    }
}

/// The number of connected components (by shared vertices).
pub fn components(m: &SceneMesh) -> usize {
    let n = m.mesh.positions.len();
    let mut p: Vec<usize> = (0..n).collect();
    fn f(p: &mut [usize], mut i: usize) -> usize {
        while p[i] != i {
            p[i] = p[p[i]];
            i = p[i];
        }
        i
    }
    for t in &m.mesh.triangles {
        for e in 1..3 {
            let (a, b) = (f(&mut p, t[0] as usize), f(&mut p, t[e] as usize));
            p[a] = b;
        }
    }
    let used: std::collections::HashSet<usize> =
        m.mesh.triangles.iter().flatten().map(|&i| f(&mut p, i as usize)).collect();
    used.len()
}

/// Segment `a–b` against triangle `t`: whether they cross (Möller–Trumbore, strict).
fn seg_tri(a: P, b: P, t: [P; 3]) -> bool {
    let d = b - a;
    let (e1, e2) = (t[1] - t[0], t[2] - t[0]);
    let p = d.cross(e2);
    let det = e1.dot(p);
    // A segment in the triangle's plane (to rounding) is not a crossing: pieces of adjacent
    // tetrahedra can be coplanar where the surface is a plane or a ruled surface's line.
    if det.abs() <= 1e-12 * d.length() * e1.length() * e2.length() {
        return false;
    }
    let inv = 1.0 / det;
    let s = a - t[0];
    let u = s.dot(p) * inv;
    let q = s.cross(e1);
    let v = d.dot(q) * inv;
    let w = e2.dot(q) * inv;
    let eps = 1e-12;
    u > eps && v > eps && u + v < 1.0 - eps && w > eps && w < 1.0 - eps
}

/// No two triangles that share no corner cross (an edge of one through the other), and no
/// two that share one corner overlap along their opposite edges. Sweep over x.
pub fn embedded(m: &SceneMesh) {
    let tri = |k: usize| m.mesh.corners(k);
    let boxes: Vec<(f64, f64, usize)> = (0..m.mesh.triangles.len())
        .map(|k| {
            let c = tri(k);
            let lo = c.iter().map(|p| p.x).fold(f64::INFINITY, f64::min);
            let hi = c.iter().map(|p| p.x).fold(f64::NEG_INFINITY, f64::max);
            (lo, hi, k)
        })
        .collect();
    let mut order = boxes.clone();
    order.sort_by(|a, b| a.0.total_cmp(&b.0));
    let bb = |c: &[P; 3]| {
        let lo = V3::new(
            c.iter().map(|p| p.x).fold(f64::INFINITY, f64::min),
            c.iter().map(|p| p.y).fold(f64::INFINITY, f64::min),
            c.iter().map(|p| p.z).fold(f64::INFINITY, f64::min),
        );
        let hi = V3::new(
            c.iter().map(|p| p.x).fold(f64::NEG_INFINITY, f64::max),
            c.iter().map(|p| p.y).fold(f64::NEG_INFINITY, f64::max),
            c.iter().map(|p| p.z).fold(f64::NEG_INFINITY, f64::max),
        );
        (lo, hi)
    };
    for (i, &(_, hi_i, ki)) in order.iter().enumerate() {
        let (ti, ci) = (m.mesh.triangles[ki], tri(ki));
        let (li, ui) = bb(&ci);
        for &(lo_j, _, kj) in &order[i + 1..] {
            if lo_j > hi_i {
                break;
            }
            let (tj, cj) = (m.mesh.triangles[kj], tri(kj));
            let (lj, uj) = bb(&cj);
            if lj.y > ui.y || uj.y < li.y || lj.z > ui.z || uj.z < li.z {
                continue;
            }
            let shared = ti.iter().filter(|v| tj.contains(v)).count();
            if shared >= 2 {
                continue;
            }
            // Edges not incident to a shared corner.
            let edges = |t: [u32; 3], c: [P; 3]| {
                (0..3)
                    .filter(move |&e| {
                        !(tj.contains(&t[e]) && ti.contains(&t[e])
                            || tj.contains(&t[(e + 1) % 3]) && ti.contains(&t[(e + 1) % 3]))
                    })
                    .map(move |e| (c[e], c[(e + 1) % 3]))
            };
            let hit = edges(ti, ci).any(|(a, b)| seg_tri(a, b, cj)) || edges(tj, cj).any(|(a, b)| seg_tri(a, b, ci));
            assert!(!hit, "triangles {ki} {ti:?} {ci:?} and {kj} {tj:?} {cj:?} cross");
        }
    }
}

/// Distance from `p` to triangle `t` (Ericson's closest point).
pub fn point_tri(p: P, t: [P; 3]) -> f64 {
    let [a, b, c] = t;
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return ap.length();
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return bp.length();
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return (p - (a + ab * (d1 / (d1 - d3)))).length();
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return cp.length();
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return (p - (a + ac * (d2 / (d2 - d6)))).length();
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return (p - (b + (c - b) * w)).length();
    }
    let denom = 1.0 / (va + vb + vc);
    let (v, w) = (vb * denom, vc * denom);
    (p - (a + ab * v + ac * w)).length()
}

/// The largest distance from `samples` to the mesh (brute force over triangles within a
/// search radius `r`; `r` when none is that close).
pub fn farthest_from_mesh(m: &SceneMesh, samples: &[P], r: f64) -> f64 {
    let cells = 1.0 / r;
    let key = |p: P| [(p.x * cells).floor() as i64, (p.y * cells).floor() as i64, (p.z * cells).floor() as i64];
    let mut grid: HashMap<[i64; 3], Vec<usize>> = HashMap::new();
    for k in 0..m.mesh.triangles.len() {
        let c = m.mesh.corners(k);
        let lo = key(V3::new(
            c.iter().map(|p| p.x).fold(f64::INFINITY, f64::min),
            c.iter().map(|p| p.y).fold(f64::INFINITY, f64::min),
            c.iter().map(|p| p.z).fold(f64::INFINITY, f64::min),
        ));
        let hi = key(V3::new(
            c.iter().map(|p| p.x).fold(f64::NEG_INFINITY, f64::max),
            c.iter().map(|p| p.y).fold(f64::NEG_INFINITY, f64::max),
            c.iter().map(|p| p.z).fold(f64::NEG_INFINITY, f64::max),
        ));
        for i in lo[0]..=hi[0] {
            for j in lo[1]..=hi[1] {
                for l in lo[2]..=hi[2] {
                    grid.entry([i, j, l]).or_default().push(k);
                }
            }
        }
    }
    let mut worst = 0.0f64;
    for &s in samples {
        let c = key(s);
        let mut d = r;
        for i in -1..=1 {
            for j in -1..=1 {
                for l in -1..=1 {
                    for &k in grid.get(&[c[0] + i, c[1] + j, c[2] + l]).map(|v| &v[..]).unwrap_or(&[]) {
                        d = d.min(point_tri(s, m.mesh.corners(k)));
                    }
                }
            }
        }
        worst = worst.max(d);
    }
    worst
}

/// Points of the union's surface: random points near a random tube projected onto its
/// surface (Newton along the numerical gradient of that tube's SDF), kept where no other tube
/// covers them; plus points of the creases between pairs of tubes, found the same way on
/// both SDFs, which is where a mesh cut across the valley would be farthest.
pub fn surface_samples(tubes: &[RoundCone<f64>], n: usize, seed: u64) -> Vec<P> {
    let mut rng = rand::rngs::StdRng::seed_from_u64(seed);
    let mut out = Vec::new();
    let mut tries = 0;
    while out.len() < n && tries < 50 * n {
        tries += 1;
        let t = &tubes[rng.gen_range(0..tubes.len())];
        let bb = t.aabb();
        let mut x = V3::new(
            rng.gen_range(bb.min.x..=bb.max.x),
            rng.gen_range(bb.min.y..=bb.max.y),
            rng.gen_range(bb.min.z..=bb.max.z),
        );
        for _ in 0..6 {
            x = x - num_grad(t, x) * t.sdf(x);
        }
        // Every other sample: slide onto the crease with the nearest other tube.
        if out.len() % 2 == 1 {
            if let Some(u) = tubes.iter().filter(|u| !std::ptr::eq(*u, t)).min_by(|a, b| a.sdf(x).total_cmp(&b.sdf(x)))
            {
                if u.sdf(x).abs() < 0.3 * t.ra.max(t.rb) {
                    x = onto_crease(t, u, x, 20, 1e-6);
                }
            }
        }
        let f = sdf(tubes, x);
        if f.abs() <= 1e-9 * (1.0 + t.ra.max(t.rb)) {
            out.push(x);
        }
    }
    out
}

/// The mesh's enclosed volume (divergence theorem) and area.
pub fn volume_area(m: &SceneMesh) -> (f64, f64) {
    let (mut v, mut a) = (0.0, 0.0);
    for k in 0..m.mesh.triangles.len() {
        let [p, q, r] = m.mesh.corners(k);
        v += p.dot(q.cross(r)) / 6.0;
        a += 0.5 * (q - p).cross(r - p).length();
    }
    (v, a)
}

/// The numerical unit gradient of one tube's SDF (central differences: independent of the
/// mesher's closed form).
fn num_grad(t: &RoundCone<f64>, x: P) -> P {
    let e = 1e-7 * (1.0 + t.ra.max(t.rb));
    let g = V3::new(
        t.sdf(x + V3::new(e, 0.0, 0.0)) - t.sdf(x - V3::new(e, 0.0, 0.0)),
        t.sdf(x + V3::new(0.0, e, 0.0)) - t.sdf(x - V3::new(0.0, e, 0.0)),
        t.sdf(x + V3::new(0.0, 0.0, e)) - t.sdf(x - V3::new(0.0, 0.0, e)),
    );
    let l = g.length();
    if l > 0.0 {
        g * (1.0 / l)
    } else {
        V3::new(1.0, 0.0, 0.0)
    }
}

/// `x` moved onto the crease of tubes `a` and `b` (both SDFs zero): at most `steps` Gauss–Newton
/// steps on the pair, stopped where the two normals are parallel to within `det_min`
/// (`1 − (nₐ·n_b)²`), where the crease is ill-defined.
fn onto_crease(a: &RoundCone<f64>, b: &RoundCone<f64>, mut x: P, steps: usize, det_min: f64) -> P {
    for _ in 0..steps {
        let (fa, fb, ga, gb) = (a.sdf(x), b.sdf(x), num_grad(a, x), num_grad(b, x));
        let c = ga.dot(gb);
        let det = 1.0 - c * c;
        if det < det_min {
            break;
        }
        x = x - ga * ((fa - c * fb) / det) - gb * ((fb - c * fa) / det);
    }
    x
}

/// The point nearest `x` where the surfaces of three tubes meet (Newton on their three SDFs),
/// with the direction `w` along which all three grow at unit rate (`gᵢ·w = 1`: out of each,
/// down the channel between them); `None` where the normals are coplanar there.
fn onto_channel(t: [&RoundCone<f64>; 3], mut x: P) -> Option<(P, P)> {
    let solve = |x: P, f: [f64; 3]| {
        let g = t.map(|t| num_grad(t, x));
        let c = [g[1].cross(g[2]), g[2].cross(g[0]), g[0].cross(g[1])];
        let det = g[0].dot(c[0]);
        (det.abs() > 1e-12).then(|| (c[0] * f[0] + c[1] * f[1] + c[2] * f[2]) * (1.0 / det))
    };
    for _ in 0..30 {
        x = x - solve(x, t.map(|t| t.sdf(x)))?;
    }
    Some((x, solve(x, [1.0; 3])?))
}

/// An upper bound on the distance from `p` to the union's surface, found by witnesses: points
/// `q` outside the union (`sdf(q) ≥ 0`, checked with the brute-force union SDF), so that the
/// distance is at most `|p − q|`. Outside the union that distance is `sdf(p)` itself (the
/// distance to a union is the least distance to its parts). Inside, where `−sdf(p)` (the least
/// depth in one tube) only bounds the true depth from **below** near a crease, the witnesses
/// are: `p` moved out of each tube along its gradient (the nearest point of that tube's
/// surface), the nearest crease point of each pair of tubes near `p` (Newton on both SDFs,
/// then a push of `push` along the bisector of the two normals), where none of those is within
/// `d` the nearest point where three tubes meet (pushed along their channel), and 4,000 directions at
/// distance `d` (the bound to check), the eight least inside of them climbed over the sphere
/// where all are inside. Returns the least witness distance, or infinity when none within `d` is
/// found.
pub fn depth_witness(tubes: &[RoundCone<f64>], p: P, d: f64) -> f64 {
    let f = sdf(tubes, p);
    if f >= 0.0 {
        return f;
    }
    let push = 1e-10 * (1.0 + d);
    let best = std::cell::Cell::new(f64::INFINITY);
    let take = |q: P| {
        if sdf(tubes, q) >= 0.0 {
            best.set(best.get().min((q - p).length()));
        }
    };
    let near: Vec<&RoundCone<f64>> = tubes.iter().filter(|t| t.sdf(p) < 2.0 * d + push).collect();
    for t in &near {
        let mut q = p;
        for _ in 0..4 {
            q = q - num_grad(t, q) * (t.sdf(q) - push);
        }
        take(q);
    }
    for (i, a) in near.iter().enumerate() {
        for b in &near[i + 1..] {
            let x = onto_crease(a, b, p, 30, 1e-12);
            let (ga, gb) = (num_grad(a, x), num_grad(b, x));
            let n = ga + gb;
            if n.length() > 0.0 {
                take(x + n * (push / n.length()));
            }
        }
    }
    // Where three tubes meet, the exterior nearest a point by their channel's closing point
    // is the channel itself, a sliver whose walls' normals are nearly coplanar (thinner than
    // the samples below can find): the closing point, then pushed along the channel.
    if best.get() > d {
        for (i, a) in near.iter().enumerate() {
            for (j, b) in near.iter().enumerate().skip(i + 1) {
                for c in &near[j + 1..] {
                    if let Some((x, w)) = onto_channel([a, b, c], p) {
                        for k in [1.0, 10.0, 100.0] {
                            take(x + w * (k * push));
                        }
                    }
                }
            }
        }
    }
    // The directions at distance `d`; where the bound is within a hair of the true depth, the
    // exterior there is a small cap of the sphere, which the samples may straddle: the eight
    // directions whose points are least inside the union are then climbed (rotations of
    // shrinking angle towards whichever of eight neighbours is less inside: a crease's ridge
    // runs diagonally) until a point is outside.
    if best.get() > d {
        let k = 4000;
        let mut tops: Vec<(f64, P)> = (0..k)
            .map(|i| {
                let z = 1.0 - 2.0 * (i as f64 + 0.5) / k as f64;
                let phi = i as f64 * std::f64::consts::PI * (3.0 - 5f64.sqrt());
                let s = (1.0 - z * z).sqrt();
                let u = V3::new(s * phi.cos(), s * phi.sin(), z);
                take(p + u * d);
                (sdf(tubes, p + u * d), u)
            })
            .collect();
        tops.sort_by(|a, b| b.0.total_cmp(&a.0));
        for &(mut f, mut u) in tops.iter().take(8) {
            let mut step = 0.05;
            while best.get() > d && step > 1e-9 {
                let e1 = if u.x.abs() < 0.9 { V3::new(1.0, 0.0, 0.0) } else { V3::new(0.0, 1.0, 0.0) };
                let t1 = e1 - u * e1.dot(u);
                let t1 = t1 * (1.0 / t1.length());
                let t2 = u.cross(t1);
                let mut moved = false;
                for (a, b) in [
                    (1.0, 0.0),
                    (-1.0, 0.0),
                    (0.0, 1.0),
                    (0.0, -1.0),
                    (1.0, 1.0),
                    (1.0, -1.0),
                    (-1.0, 1.0),
                    (-1.0, -1.0),
                ] {
                    let v = u + (t1 * a + t2 * b) * step;
                    let v = v * (1.0 / v.length());
                    let g = sdf(tubes, p + v * d);
                    if g > f {
                        (f, u, moved) = (g, v, true);
                        take(p + v * d);
                    }
                }
                if !moved {
                    step *= 0.5;
                }
            }
        }
    }
    best.get()
}
