//! One closed tube component: rings on the exact surface joined by quads, a pole at each end.
//!
//! Frames are carried along the polyline axis by parallel transport: along a link the frame
//! does not turn, and at a joint it is turned by the minimal rotation taking one link's axis
//! to the next (about `w₋ × w₊`), which is the rotation-minimising frame of the polyline
//! (the double-reflection method of Wang et al. 2008 reduces to it for straight pieces). Ring
//! vertex `j` sits at the same frame angle `2πj/n` on every ring, so the quads do not twist.

use super::budget::{joint_step, joint_term, Budget};
use super::Mesh;
use crate::math::frame::orthonormal_basis;
use crate::vec::V3;

type P = V3<f64>;

/// A circle of the mesh: centre, in-plane frame `(u, v)` (with `u × v` the forward axis), radius.
#[derive(Clone, Copy)]
struct Ring {
    c: P,
    u: P,
    v: P,
    rho: f64,
}

/// One straight piece of a component: unit axis and the tangent circles' polar angle
/// `α = π/2 − θ`, `sin θ = (r_a − r_b)/L` (the cone normal leans towards the smaller end), measured from the axis on both end spheres.
#[derive(Clone, Copy, Debug)]
pub struct Piece {
    /// Unit axis from the first node to the second.
    pub w: P,
    /// Polar angle of both tangent circles from `w`.
    pub alpha: f64,
    /// Slant length of the cone between the tangent circles, `√(L² − (r_a − r_b)²)`.
    pub slant: f64,
}

impl Piece {
    /// The piece between two nodes; `None` when one ball contains the other (`|Δr| ≥ L`).
    pub fn new(a: (P, f64), b: (P, f64)) -> Option<Self> {
        let d = b.0 - a.0;
        let l = d.length();
        let s = (a.1 - b.1) / l;
        // NaN-aware: a NaN length or ratio fails both tests.
        if l.partial_cmp(&0.0) != Some(core::cmp::Ordering::Greater)
            || s.abs().partial_cmp(&1.0) != Some(core::cmp::Ordering::Less)
        {
            return None;
        }
        let slant = l * ((1.0 - s) * (1.0 + s)).sqrt();
        Some(Self { w: d.scale(1.0 / l), alpha: core::f64::consts::FRAC_PI_2 - s.asin(), slant })
    }
}

/// Bend angle `φ` between two axes and the backward turn `ψ = φ + α₊ − α₋` of the rings over
/// the node sphere (the fold, when positive).
pub fn joint(prev: &Piece, next: &Piece) -> (f64, f64) {
    let phi = prev.w.cross(next.w).length().atan2(prev.w.dot(next.w));
    (phi, phi + next.alpha - prev.alpha)
}

/// The fold depth `r(1 − cos ψ)` at a joint of radius `r`, or `None` when the joint must be
/// split: a zero radius, or a cone shorter than the distance `r·tan(ψ/2)` at which the two
/// tangent lines cross (the fold bound assumes both cones emerge within their length).
pub fn fold(prev: &Piece, next: &Piece, r: f64) -> Option<f64> {
    let psi = joint(prev, next).1.max(0.0);
    let short = r * (0.5 * psi).tan() > prev.slant.min(next.slant);
    (r > 0.0 && !short).then(|| r * (1.0 - psi.cos()))
}

/// Rodrigues: `x` turned by the angle with cosine `c`, sine `s` about the unit axis `e`.
fn rotate(x: P, e: P, c: f64, s: f64) -> P {
    x.scale(c) + e.cross(x).scale(s) + e.scale(e.dot(x) * (1.0 - c))
}

/// Appends the vertices of a ring (`n` of them) and returns the index of the first.
fn push_ring(mesh: &mut Mesh, g: &Ring, n: usize, origin: P) -> u32 {
    let base = mesh.positions.len() as u32;
    for j in 0..n {
        let a = core::f64::consts::TAU * j as f64 / n as f64;
        let off = g.u.scale(a.cos()) + g.v.scale(a.sin());
        mesh.positions.push(origin + g.c + off.scale(g.rho));
    }
    base
}

/// Emits the triangles of a strip of rings between two poles, oriented outward (the forward
/// axis is `u × v`, the start pole behind the first ring, the end pole ahead of the last).
/// Ring `i` carries a tag (an input link index) that the triangles between it and ring `i + 1`
/// get; the end fan gets the last ring's.
fn emit(mesh: &mut Mesh, rings: &[(Ring, u32)], poles: [P; 2], n: usize, origin: P) {
    let start = mesh.positions.len() as u32;
    mesh.positions.push(origin + poles[0]);
    let bases: Vec<u32> = rings.iter().map(|(g, _)| push_ring(mesh, g, n, origin)).collect();
    let end = mesh.positions.len() as u32;
    mesh.positions.push(origin + poles[1]);
    let n32 = n as u32;
    let nx = |j: u32| (j + 1) % n32;
    let (first, last) = (bases[0], bases[bases.len() - 1]);
    let mut tri = |t: [u32; 3], tag: u32| {
        mesh.triangles.push(t);
        mesh.tags.push(tag);
    };
    for j in 0..n32 {
        tri([start, first + nx(j), first + j], rings[0].1);
        tri([end, last + j, last + nx(j)], rings[rings.len() - 1].1);
    }
    for (i, pair) in bases.windows(2).enumerate() {
        let (a, b) = (pair[0], pair[1]);
        for j in 0..n32 {
            tri([a + j, a + nx(j), b + nx(j)], rings[i].1);
            tri([a + j, b + nx(j), b + j], rings[i].1);
        }
    }
}

/// A ring on the sphere `(c, r)` at polar angle `alpha` from the axis `u × v`.
fn sphere_ring(c: P, r: f64, u: P, v: P, alpha: f64) -> Ring {
    let w = u.cross(v);
    Ring { c: c + w.scale(r * alpha.cos()), u, v, rho: r * alpha.sin() }
}

/// Rings on the sphere `(c, r)` from polar angle `from` to `to` (both included unless the
/// radius there is zero), at most `step` apart.
fn cap(rings: &mut Vec<(Ring, u32)>, (c, r): (P, f64), (u, v): (P, P), (from, to): (f64, f64), step: f64, tag: u32) {
    let m = ((from - to).abs() / step).ceil().max(1.0) as usize;
    for i in 0..=m {
        let a = if i == m { to } else { from + (to - from) * i as f64 / m as f64 };
        // The poles are emitted as single vertices, never as rings.
        if r > 0.0 && a != 0.0 && a != core::f64::consts::PI {
            rings.push((sphere_ring(c, r, u, v, a), tag));
        }
    }
}

/// A single ball, meshed as a sphere of revolution about `z`.
pub fn ball(mesh: &mut Mesh, (c, r): (P, f64), b: &Budget, origin: P, tag: u32) {
    let (u, v) = (V3::new(1.0, 0.0, 0.0), V3::new(0.0, 1.0, 0.0));
    let mut rings = Vec::new();
    cap(&mut rings, (c, r), (u, v), (core::f64::consts::PI, 0.0), b.step, tag);
    let w = V3::new(0.0, 0.0, r);
    emit(mesh, &rings, [c - w, c + w], b.n, origin);
}

/// A run of at least two nodes whose consecutive pieces are valid ([`Piece::new`]) and whose
/// interior nodes have a positive radius. `origin` is added to every vertex. Joint rings are
/// spaced so that the joint sweep's bound ([`joint_term`]) stays within `bound`; returns the
/// largest joint term reached (0 without joints).
pub fn tube(
    mesh: &mut Mesh,
    nodes: &[(P, f64)],
    pieces: &[Piece],
    b: &Budget,
    origin: P,
    tag0: u32,
    bound: f64,
) -> f64 {
    let mut worst: f64 = 0.0;
    let w0 = pieces[0].w;
    let (u0, _) = orthonormal_basis(w0);
    let (mut u, mut v) = (u0, w0.cross(u0));
    let mut rings = Vec::new();
    let (c0, r0) = nodes[0];
    cap(&mut rings, nodes[0], (u, v), (core::f64::consts::PI, pieces[0].alpha), b.step, tag0);
    for k in 1..pieces.len() {
        let (prev, next) = (&pieces[k - 1], &pieces[k]);
        let (phi, _) = joint(prev, next);
        let axis = prev.w.cross(next.w);
        let e = if axis.length() > 0.0 { axis.scale(1.0 / axis.length()) } else { axis };
        let da = next.alpha - prev.alpha;
        let sweep = phi + da.abs();
        let step = joint_step(b, nodes[k].1, bound).unwrap_or(b.step);
        let m = (sweep / step).ceil() as usize;
        if m > 0 {
            worst = worst.max(joint_term(b, nodes[k].1, sweep / m as f64));
        }
        for i in 0..=m {
            let s = if m == 0 { 0.0 } else { i as f64 / m as f64 };
            let (c, sn) = ((s * phi).cos(), (s * phi).sin());
            let (us, vs) = (rotate(u, e, c, sn), rotate(v, e, c, sn));
            // The first ring ends link k − 1's cone; the rest belong to link k.
            let tag = tag0 + k as u32 - u32::from(i == 0);
            rings.push((sphere_ring(nodes[k].0, nodes[k].1, us, vs, prev.alpha + s * da), tag));
        }
        // Transport the frame and re-orthogonalise it against the new axis (no drift).
        let ut = rotate(u, e, phi.cos(), phi.sin());
        u = (ut - next.w.scale(ut.dot(next.w))).normalize_or_zero();
        v = next.w.cross(u);
    }
    let last = pieces[pieces.len() - 1];
    let (cn, rn) = nodes[nodes.len() - 1];
    let tag = tag0 + pieces.len() as u32 - 1;
    cap(&mut rings, (cn, rn), (u, v), (last.alpha, 0.0), b.step, tag);
    let start = if r0 > 0.0 { c0 - w0.scale(r0) } else { c0 };
    let end = if rn > 0.0 { cn + last.w.scale(rn) } else { cn };
    emit(mesh, &rings, [start, end], b.n, origin);
    worst
}
