//! Procedural test scenes of the papers, deterministic for a given seed.
//!
//! * [`bundle`] — Russig et al.'s *Bundle*: 1250 tubes × 84 segments (≈ 105k, their table:
//!   105,640), a twisting, bending bundle of parallel fibres of equal radius (cylinder links).
//! * [`furball`] — Russig et al.'s *Furball*: 10,000 hairs × 78 segments (≈ 787k, their table:
//!   787,327) growing outward from a sphere as smoothed random walks, tapering (cone links).
//! * [`neurons`] — Han et al.'s neuron assembly: `n³` transformed copies of base neurons placed
//!   at random in a box scaled with `n` (their §5: 4³ … 20³). The base neuron is either a given
//!   SWC morphology or a procedural one (soma, dendrites, apical dendrite, axon; tapering and
//!   branching, so cylinders, cones and a soma sphere all occur).
//! * [`helix`] — a double helix with radii varying along it (cone links), small and quick.
//!
//! The papers describe Bundle and Furball only by picture and counts; the constructions here
//! match the counts and the look, not unpublished generator code.

use crate::io::swc::SwcNode;
use crate::io::Polyline;
use rand_xoshiro::rand_core::{RngCore, SeedableRng};
use rand_xoshiro::SplitMix64;

/// The seeded generator of the scenes and of the renderer's ambient-occlusion directions:
/// [`SplitMix64`] (Steele, Lea & Flood 2014; `rand_xoshiro`) with the float draws the
/// generators need. Deterministic for a seed on every platform.
///
/// ```
/// use tubecast_render::scene::generate::Rng;
/// let mut rng = Rng::new(7);
/// let x = rng.uniform();
/// assert!((0.0..1.0).contains(&x));
/// assert_eq!(Rng::new(7).uniform(), x);
/// ```
#[derive(Clone, Debug)]
pub struct Rng(SplitMix64);

impl Rng {
    /// The generator whose state starts at `seed`.
    pub fn new(seed: u64) -> Self {
        Self(SplitMix64::seed_from_u64(seed))
    }
    /// Next value in `[0, 1)`: the top 53 bits of the next output, times `2⁻⁵³`.
    pub fn uniform(&mut self) -> f64 {
        (self.0.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
    /// Uniform in `[a, b)`.
    pub fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.uniform()
    }
    /// A uniformly distributed unit vector.
    pub fn unit(&mut self) -> [f64; 3] {
        let z = self.range(-1.0, 1.0);
        let phi = self.range(0.0, 2.0 * std::f64::consts::PI);
        let s = (1.0 - z * z).max(0.0).sqrt();
        [s * phi.cos(), s * phi.sin(), z]
    }
}

fn norm(v: [f64; 3]) -> [f64; 3] {
    let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    if l > 0.0 {
        v.map(|x| x / l)
    } else {
        [1.0, 0.0, 0.0]
    }
}

/// Russig's *Bundle*: `tubes` fibres of `segments` links each, along x over 100 units, in a
/// disc of radius 8 that twists half a turn and bends; radius 0.12.
pub fn bundle(tubes: usize, segments: usize, seed: u64) -> Vec<Polyline> {
    let mut rng = Rng::new(seed);
    let segments = segments.max(1);
    (0..tubes)
        .map(|_| {
            let rr = 8.0 * rng.uniform().sqrt();
            let a0 = rng.range(0.0, 2.0 * std::f64::consts::PI);
            let ph = rng.range(0.0, 2.0 * std::f64::consts::PI);
            let wob = rng.range(0.1, 0.4);
            let points = (0..=segments)
                .map(|k| {
                    let s = k as f64 / segments as f64; // 0..1
                    let x = -50.0 + 100.0 * s;
                    let a = a0 + std::f64::consts::PI * s; // half a turn of twist
                    let bend = 12.0 * (std::f64::consts::PI * s).sin();
                    let w = wob * (6.0 * std::f64::consts::PI * s + ph).sin();
                    [x, bend + (rr + w) * a.cos(), (rr + w) * a.sin()]
                })
                .collect::<Vec<_>>();
            let radii = vec![0.12; points.len()];
            Polyline { points, radii }
        })
        .collect()
}

/// Russig's *Furball*: `tubes` hairs of `segments` links each, rooted on a sphere of radius
/// 10, growing outward as a smoothed random walk with step 0.2, tapering from radius 0.06 to
/// 0.015.
pub fn furball(tubes: usize, segments: usize, seed: u64) -> Vec<Polyline> {
    let mut rng = Rng::new(seed);
    let segments = segments.max(1);
    (0..tubes)
        .map(|_| {
            let n = rng.unit();
            let mut p = n.map(|v| 10.0 * v);
            let mut dir = n;
            let mut points = vec![p];
            let mut radii = vec![0.06];
            for k in 1..=segments {
                let j = rng.unit();
                dir = norm([0, 1, 2].map(|i| dir[i] + 0.35 * j[i] + 0.08 * n[i]));
                p = [0, 1, 2].map(|i| p[i] + 0.2 * dir[i]);
                points.push(p);
                radii.push(0.06 - 0.045 * k as f64 / segments as f64);
            }
            Polyline { points, radii }
        })
        .collect()
}

/// A double helix: two strands of `segments` links each, 3 turns, axis z, helix radius 4,
/// height 20, tube radius varying between 0.25 and 0.6.
pub fn helix(segments: usize) -> Vec<Polyline> {
    let segments = segments.max(1);
    (0..2)
        .map(|strand| {
            let off = strand as f64 * std::f64::consts::PI;
            let mut points = Vec::new();
            let mut radii = Vec::new();
            for k in 0..=segments {
                let s = k as f64 / segments as f64;
                let a = off + 6.0 * std::f64::consts::PI * s;
                points.push([4.0 * a.cos(), 4.0 * a.sin(), -10.0 + 20.0 * s]);
                radii.push(0.425 + 0.175 * (4.0 * std::f64::consts::PI * s).sin());
            }
            Polyline { points, radii }
        })
        .collect()
}

/// A branch of [`base_neuron`] waiting to grow.
struct Branch {
    /// SWC id of the node it starts from.
    parent: i64,
    /// Start position.
    pos: [f64; 3],
    /// Start direction.
    dir: [f64; 3],
    /// Start radius.
    radius: f64,
    /// SWC structure type.
    kind: i32,
    /// Steps left.
    steps: usize,
    /// Branching depth.
    depth: u32,
}

/// A procedural base neuron: a soma (type 1, radius 6) with four basal dendrites (type 3), an
/// apical dendrite (type 4) and an axon (type 2), each a tapering random walk that branches.
pub fn base_neuron(seed: u64) -> Vec<SwcNode> {
    let mut rng = Rng::new(seed);
    let mut nodes = vec![SwcNode { id: 1, kind: 1, pos: [0.0; 3], radius: 6.0, parent: -1 }];
    let mut stack: Vec<Branch> = Vec::new();
    let kinds = [3, 3, 3, 3, 4, 2];
    for (i, &kind) in kinds.iter().enumerate() {
        let d = if kind == 4 {
            [0.0, 1.0, 0.0]
        } else if kind == 2 {
            [0.0, -1.0, 0.0]
        } else {
            let a = i as f64 * std::f64::consts::FRAC_PI_2 + rng.range(-0.3, 0.3);
            norm([a.cos(), rng.range(-0.4, 0.4), a.sin()])
        };
        let r0 = if kind == 2 { 0.8 } else { 1.6 };
        let steps = if kind == 2 { 70 } else { 35 };
        stack.push(Branch { parent: 1, pos: d.map(|v| 5.5 * v), dir: d, radius: r0, kind, steps, depth: 0 });
    }
    while let Some(Branch { parent, pos: mut p, dir: mut d, radius: mut r, kind, steps, depth }) = stack.pop() {
        let mut par = parent;
        for s in 0..steps {
            let j = rng.unit();
            d = norm([0, 1, 2].map(|i| d[i] + 0.3 * j[i]));
            p = [0, 1, 2].map(|i| p[i] + 3.0 * d[i]);
            // Taper every few steps, so runs of equal radius (cylinders) and cones alternate.
            if s % 3 == 0 {
                r = (r * 0.93).max(0.25);
            }
            let id = nodes.len() as i64 + 1;
            nodes.push(SwcNode { id, kind, pos: p, radius: r, parent: par });
            par = id;
            if depth < 3 && s + 5 < steps && rng.uniform() < 0.07 {
                let b = rng.unit();
                let bd = norm([0, 1, 2].map(|i| d[i] + 0.9 * b[i]));
                let steps = (steps - s) * 2 / 3;
                stack.push(Branch { parent: id, pos: p, dir: bd, radius: r * 0.8, kind, steps, depth: depth + 1 });
            }
        }
    }
    nodes
}

/// Han's neuron assembly: `n³` copies of the base neurons (cycled), each rotated about y by a
/// random angle and about x/z by up to ±0.3 rad, placed at uniformly random positions in a
/// box of side `60·n` (so density stays constant as `n` grows). Ids are renumbered.
pub fn neurons(n: usize, bases: &[Vec<SwcNode>], seed: u64) -> Vec<SwcNode> {
    let mut rng = Rng::new(seed);
    let side = 60.0 * n as f64;
    let mut out = Vec::new();
    if bases.is_empty() {
        return out;
    }
    for k in 0..n * n * n {
        let base = &bases[k % bases.len()];
        // 6.283, not τ: the pinned scenes (and the README render) were generated with it.
        #[allow(clippy::approx_constant)]
        let (ay, ax, az) = (rng.range(0.0, 6.283), rng.range(-0.3, 0.3), rng.range(-0.3, 0.3));
        let t = [rng.range(0.0, side), rng.range(0.0, side), rng.range(0.0, side)];
        let rot = |p: [f64; 3]| {
            let (c, s) = (ay.cos(), ay.sin());
            let p = [c * p[0] + s * p[2], p[1], -s * p[0] + c * p[2]];
            let (c, s) = (ax.cos(), ax.sin());
            let p = [p[0], c * p[1] - s * p[2], s * p[1] + c * p[2]];
            let (c, s) = (az.cos(), az.sin());
            [c * p[0] - s * p[1], s * p[0] + c * p[1], p[2]]
        };
        let off = out.len() as i64;
        let mut map = std::collections::HashMap::new();
        for (i, b) in base.iter().enumerate() {
            map.insert(b.id, off + i as i64 + 1);
        }
        for b in base {
            let p = rot(b.pos);
            out.push(SwcNode {
                id: map[&b.id],
                kind: b.kind,
                pos: [p[0] + t[0], p[1] + t[1], p[2] + t[2]],
                radius: b.radius,
                parent: if b.parent < 0 { -1 } else { *map.get(&b.parent).unwrap_or(&-1) },
            });
        }
    }
    out
}
