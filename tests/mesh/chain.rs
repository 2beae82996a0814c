//! Certified tessellation of chains, bifurcations and spline tubes: every closed part of the
//! mesh is within ε (two-sided: |exact SDF| at dense mesh samples, mesh distance at dense
//! exact-surface samples) of the union of the links it stands for; the whole mesh never sticks
//! out of the exact union by more than ε and covers its whole boundary within ε (no cracks at
//! joints and bifurcations); parts are closed and consistently oriented.

use crate::common::{assert_watertight, link_surface, perp, triangle_samples, volume, MeshDist, P};
use tubecast::{tessellate_chain, tessellate_spline, HermiteSegment, Mesh, Primitive, QuadTube, RoundCone, V3};

/// Rounding allowance, as in `mesh_link.rs`: 64 ulps of the coordinate scale.
fn slack(scale: f64) -> f64 {
    64.0 * f64::EPSILON * scale
}

fn v(x: f64, y: f64, z: f64) -> P {
    V3::new(x, y, z)
}

fn union_sdf(nodes: &[(P, f64)], range: std::ops::RangeInclusive<usize>) -> impl Fn(P) -> f64 + '_ {
    move |p| {
        let (s, e) = (*range.start(), *range.end());
        if s == e {
            return RoundCone::new(nodes[s].0, nodes[s].1, nodes[s].0, nodes[s].1).unwrap().sdf(p);
        }
        (s..e)
            .map(|k| RoundCone::new(nodes[k].0, nodes[k].1, nodes[k + 1].0, nodes[k + 1].1).unwrap().sdf(p))
            .fold(f64::INFINITY, f64::min)
    }
}

fn surface(nodes: &[(P, f64)], k: usize) -> Vec<P> {
    if nodes.len() == 1 {
        return link_surface(nodes[0].0, nodes[0].1, nodes[0].0, nodes[0].1, k);
    }
    nodes.windows(2).flat_map(|w| link_surface(w[0].0, w[0].1, w[1].0, w[1].1, k)).collect()
}

fn sub_mesh(m: &Mesh, tris: std::ops::Range<usize>) -> Mesh {
    Mesh { positions: m.positions.clone(), triangles: m.triangles[tris].to_vec(), ..Mesh::default() }
}

/// Two-sided check of one solid: |sdf| at mesh samples and mesh distance at surface samples.
fn check_part(mesh: &Mesh, sdf: &dyn Fn(P) -> f64, surf: &[P], eps: f64, scale: f64) {
    assert_watertight(mesh);
    assert!(volume(mesh) > 0.0, "inward orientation");
    let tol = eps + slack(scale);
    for x in triangle_samples(mesh, 3) {
        let d = sdf(x);
        assert!(d.abs() <= tol, "mesh point {x:?} at sdf {d} (ε {eps})");
    }
    let md = MeshDist::new(mesh);
    for &y in surf.iter().filter(|&&y| sdf(y) >= -slack(scale)) {
        let d = md.dist(y);
        assert!(d <= tol, "surface point {y:?} at distance {d} from the mesh (ε {eps})");
    }
}

/// Every part against its own links; returns the mesh.
fn check_chain(nodes: &[(P, f64)], eps: f64) -> Mesh {
    let mesh = tessellate_chain(nodes, eps).unwrap();
    assert!(mesh.certified <= eps, "certified {}", mesh.certified);
    let scale = nodes.iter().map(|n| n.0.max_abs() + n.1).fold(0.0, f64::max);
    // Tags: every triangle lies within its tagged link's solid (up to ε).
    assert_eq!(mesh.tags.len(), mesh.triangles.len());
    for (k, &tag) in mesh.tags.iter().enumerate() {
        let [a, b, c] = mesh.corners(k);
        let x = (a + b + c).scale(1.0 / 3.0);
        let t = (tag as usize).min(nodes.len().saturating_sub(2));
        let d = union_sdf(nodes, t..=(t + 1).min(nodes.len() - 1))(x);
        assert!(d <= eps + slack(scale), "triangle {k} tagged {tag} is {d} outside its link");
    }
    let covered: usize = mesh.parts.iter().map(|p| p.triangles.len()).sum();
    assert_eq!(covered, mesh.triangles.len());
    for part in &mesh.parts {
        let sub = &nodes[part.nodes.clone()];
        check_part(
            &sub_mesh(&mesh, part.triangles.clone()),
            &union_sdf(nodes, part.nodes.clone()),
            &surface(sub, 30),
            eps,
            scale,
        );
    }
    mesh
}

#[test]
fn bent_chains_with_varying_radii() {
    let nodes = [(v(0.0, 0.0, 0.0), 0.5), (v(2.0, 0.0, 0.0), 0.45), (v(3.5, 1.0, 0.3), 0.35), (v(4.0, 2.5, 1.0), 0.3)];
    check_chain(&nodes, 1e-2);
    // Bends of 2°: the fold r(1 − cos ψ) ≈ 3e-4 stays within ε/4, so the chain is one surface.
    let gentle: Vec<(P, f64)> = (0..6)
        .map(|i| {
            let a = i as f64 * 0.035;
            (v(2.0 * a.sin() / 0.035, 2.0 * (1.0 - a.cos()) / 0.035, 0.0), 0.5)
        })
        .collect();
    assert_eq!(check_chain(&gentle, 4e-3).parts.len(), 1, "gentle bends stay one closed surface");
}

#[test]
fn tight_bends_waists_and_zero_radii_split_into_closed_parts() {
    // 150° turn: the fold would be deep, so the chain splits at the node.
    let sharp = [(v(0.0, 0.0, 0.0), 0.5), (v(3.0, 0.0, 0.0), 0.5), (v(0.5, 1.3, 0.0), 0.5)];
    assert!(check_chain(&sharp, 1e-2).parts.len() >= 2);
    // A waist (radius dips at the middle node) and a bulge.
    check_chain(&[(v(0.0, 0.0, 0.0), 1.0), (v(1.5, 0.0, 0.0), 0.4), (v(3.0, 0.0, 0.0), 1.0)], 1e-2);
    check_chain(&[(v(0.0, 0.0, 0.0), 0.3), (v(1.5, 0.2, 0.0), 1.0), (v(3.0, 0.0, 0.0), 0.3)], 1e-2);
    // A zero radius inside the chain (two tips meeting), a degenerate link in the middle.
    check_chain(&[(v(0.0, 0.0, 0.0), 0.5), (v(2.0, 0.0, 0.0), 0.0), (v(4.0, 1.0, 0.0), 0.5)], 1e-2);
    check_chain(
        &[(v(0.0, 0.0, 0.0), 0.5), (v(2.0, 0.0, 0.0), 0.5), (v(2.1, 0.0, 0.0), 0.9), (v(4.0, 0.0, 0.0), 0.2)],
        1e-2,
    );
}

#[test]
fn far_and_short_links() {
    let far = v(-3e6, 5e6, 1e6);
    let nodes: Vec<(P, f64)> = (0..8)
        .map(|i| {
            let a = i as f64 * 0.3;
            (far + v(a.cos() * 2.0, a.sin() * 2.0, 0.05 * i as f64), 0.2 + 0.01 * i as f64)
        })
        .collect();
    check_chain(&nodes, 1e-2);
}

#[test]
fn bifurcation_has_no_crack() {
    // Three branches off one node, each its own chain capped on the node's sphere.
    let c = (v(0.0, 0.0, 0.0), 0.6);
    let branches = [
        vec![c, (v(3.0, 0.0, 0.0), 0.45), (v(5.0, 0.5, 0.0), 0.3)],
        vec![c, (v(-1.5, 2.0, 0.0), 0.3)],
        vec![c, (v(-1.5, -2.0, 0.5), 0.22), (v(-2.5, -3.0, 0.5), 0.2)],
    ];
    let eps = 1e-2;
    let mut mesh = Mesh::default();
    for b in &branches {
        mesh.append(&check_chain(b, eps));
    }
    let sdf = |p: P| branches.iter().map(|b| union_sdf(b, 0..=b.len() - 1)(p)).fold(f64::INFINITY, f64::min);
    let tol = eps + slack(6.0);
    // The union of the parts never sticks out of the exact union...
    for x in triangle_samples(&mesh, 2) {
        assert!(sdf(x) <= tol, "mesh point {x:?} outside by {}", sdf(x));
    }
    // ...and covers its whole boundary, the node's sphere between the branches included.
    let md = MeshDist::new(&mesh);
    let mut ball = link_surface(c.0, c.1, c.0, c.1, 200);
    ball.extend(branches.iter().flat_map(|b| surface(b, 30)));
    let mut used = 0;
    for y in ball.into_iter().filter(|&y| sdf(y) >= -slack(6.0)) {
        used += 1;
        assert!(md.dist(y) <= tol, "boundary point {y:?} is {} from the mesh", md.dist(y));
    }
    assert!(used > 100);
}

/// Points on the envelope of a quadratic sweep: the characteristic circles (unit normal
/// `−(r'/|p'|)·t̂ + √(1 − (r'/|p'|)²)·e`, `e ⊥ t̂`), from the closed form of the Bézier here.
fn spline_surface(q: &QuadTube<f64>, k: usize) -> Vec<P> {
    let [b0, b1, b2] = q.b;
    let [r0, r1, r2] = q.r;
    let mut out = Vec::new();
    for i in 0..k {
        let t = (i as f64 + 0.5) / k as f64;
        let p = b0.scale((1.0 - t) * (1.0 - t)) + b1.scale(2.0 * t * (1.0 - t)) + b2.scale(t * t);
        let r = r0 * (1.0 - t) * (1.0 - t) + r1 * 2.0 * t * (1.0 - t) + r2 * t * t;
        let dp = (b1 - b0).scale(2.0 * (1.0 - t)) + (b2 - b1).scale(2.0 * t);
        let dr = 2.0 * (1.0 - t) * (r1 - r0) + 2.0 * t * (r2 - r1);
        let (len, tt) = (dp.length(), dp.normalize_or_zero());
        let s = dr / len;
        for j in 0..12 {
            let e = perp(tt, j as f64 * std::f64::consts::FRAC_PI_6 + t);
            out.push(p + (tt.scale(-s) + e.scale((1.0 - s * s).sqrt())).scale(r));
        }
    }
    out.extend(link_surface(b0, r0, b0, r0, 40));
    out.extend(link_surface(b2, r2, b2, r2, 40));
    out
}

#[test]
fn spline_tubes_within_eps() {
    let (p0, p1) = (v(0.0, 0.0, 0.0), v(4.0, 0.0, 0.0));
    let cases = [
        HermiteSegment::new(p0, v(2.0, 4.0, 0.0), 0.5, 0.0, p1, v(2.0, -4.0, 1.0), 0.3, 0.0),
        HermiteSegment::new(p0, v(0.0, 6.0, 0.0), 0.3, 0.4, p1, v(0.0, -6.0, 0.0), 0.3, -0.4), // tight turn
        HermiteSegment::new(p0, v(4.0, 0.0, 0.0), 0.8, -1.0, p1, v(4.0, 0.0, 0.0), 0.05, -0.2), // steep taper
    ];
    for (i, seg) in cases.iter().enumerate() {
        let tubes = seg.split().unwrap();
        for eps in if i == 0 { vec![1e-2] } else { vec![2e-2] } {
            let mesh = tessellate_spline(&tubes, eps).unwrap();
            assert!(mesh.certified <= eps);
            let sdf = |p: P| tubes[0].sdf(p).min(tubes[1].sdf(p));
            let surf: Vec<P> = tubes.iter().flat_map(|q| spline_surface(q, 24)).collect();
            // Parts: checked against the whole sweep (a split part is still within ε of
            // its piece, which is inside the sweep; its surface inside another part is not on the
            // union's boundary), so mesh points get the one-sided test and the boundary the other.
            for part in &mesh.parts {
                let sub = sub_mesh(&mesh, part.triangles.clone());
                assert_watertight(&sub);
                assert!(volume(&sub) > 0.0);
            }
            let tol = eps + slack(6.0);
            for (k, &tag) in mesh.tags.iter().enumerate() {
                let [a, b, c] = mesh.corners(k);
                let d = tubes[tag as usize].sdf((a + b + c).scale(1.0 / 3.0));
                assert!(d <= tol, "case {i}: triangle {k} tagged {tag} is {d} outside its segment");
            }
            for x in triangle_samples(&mesh, 2) {
                assert!(sdf(x) <= tol, "case {i}: mesh point outside by {}", sdf(x));
                if mesh.parts.len() == 1 {
                    assert!(sdf(x) >= -tol, "case {i} ε {eps}: mesh point inside by {}", -sdf(x));
                }
            }
            let md = MeshDist::new(&mesh);
            for y in surf.into_iter().filter(|&y| sdf(y) >= -slack(6.0)) {
                assert!(md.dist(y) <= tol, "case {i} ε {eps}: surface point {} from the mesh", md.dist(y));
            }
        }
    }
}

#[test]
fn solid_variant_never_sticks_out_and_covers_the_boundary() {
    // Bent chains stay one surface; the enclosed-region bound is checked by ray tests in the
    // render crate; here the two surface facts that do not depend on the folds.
    let nodes = [(v(0.0, 0.0, 0.0), 0.5), (v(2.0, 0.0, 0.0), 0.45), (v(3.5, 1.0, 0.3), 0.35), (v(4.0, 2.5, 1.0), 0.3)];
    let eps = 1e-2;
    let mesh = tubecast::tessellate_chain_solid(&nodes, eps).unwrap();
    assert_eq!(mesh.parts.len(), 1);
    assert!(mesh.certified <= eps);
    assert_watertight(&mesh);
    assert!(volume(&mesh) > 0.0);
    let sdf = union_sdf(&nodes, 0..=3);
    let tol = eps + slack(5.0);
    for x in triangle_samples(&mesh, 2) {
        assert!(sdf(x) <= tol, "mesh point outside by {}", sdf(x));
    }
    let md = MeshDist::new(&mesh);
    for y in surface(&nodes, 30).into_iter().filter(|&y| sdf(y) >= -slack(5.0)) {
        assert!(md.dist(y) <= tol, "boundary point {} from the mesh", md.dist(y));
    }
}

#[test]
fn solid_variant_lies_inside_the_exact_solid_at_sharp_folds() {
    // budget.rs (*Solid meshes*): every triangle has its corners on one convex piece of the
    // exact solid (a node ball, or one link's round cone), so the mesh lies inside the union
    // whatever the fold: the exact SDF at mesh samples is ≤ 0 up to rounding, not merely ≤ ε.
    // And every exact-surface point is within the certified bound (joint sweep bound, exact).
    let bends: [&[(P, f64)]; 4] = [
        &[(v(0.0, 0.0, 0.0), 0.5), (v(2.0, 0.0, 0.0), 0.5), (v(2.0, 2.0, 0.0), 0.5)], // 90°
        &[(v(0.0, 0.0, 0.0), 0.5), (v(2.0, 0.0, 0.0), 0.5), (v(0.6, 1.4, 0.2), 0.5)], // ~135°
        &[(v(0.0, 0.0, 0.0), 0.2), (v(3.0, 0.0, 0.0), 0.6), (v(3.5, 2.0, 1.0), 0.1), (v(1.5, 2.5, 0.5), 0.4)],
        &[(v(1e6, 0.0, 0.0), 0.01), (v(1e6 + 0.05, 0.0, 0.0), 0.01), (v(1e6 + 0.05, 0.04, 0.03), 0.012)],
    ];
    for nodes in bends {
        let scale = nodes.iter().map(|n| n.0.max_abs() + n.1).fold(0.0, f64::max);
        let r = nodes.iter().map(|n| n.1).fold(0.0, f64::max);
        for eps in [1e-2 * r, 1e-3 * r] {
            let mesh = tubecast::tessellate_chain_solid(nodes, eps).unwrap();
            assert!(mesh.certified <= eps, "certified {} > ε {eps}", mesh.certified);
            assert_watertight(&mesh);
            let sdf = union_sdf(nodes, 0..=nodes.len() - 1);
            for x in triangle_samples(&mesh, 3) {
                assert!(sdf(x) <= slack(scale), "mesh point {x:?} outside the union by {}", sdf(x));
            }
            let md = MeshDist::new(&mesh);
            for y in surface(nodes, 40).into_iter().filter(|&y| sdf(y) >= -slack(scale)) {
                let d = md.dist(y);
                assert!(
                    d <= mesh.certified + slack(scale),
                    "boundary point {d} from the mesh (bound {})",
                    mesh.certified
                );
            }
        }
    }
}
