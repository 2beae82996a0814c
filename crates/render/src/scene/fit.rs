//! One quadratic sphere-swept piece fitted to a run of chain links, with a certified bound.
//!
//! # Bound
//! Nodes `(pᵢ, rᵢ)`, `i = 0..n`; their links' union `U` is the sphere sweep of the
//! piecewise-linear `(p(t), r(t))` (node `i` at `t = i`). The fitted piece `Q` is the sweep of
//! the quadratic Bézier `(q(s), ρ(s))` with control points `b₀ = p₀`, `b₁`, `b₂ = pₙ` and
//! radii `ρ₀ = r₀`, `ρ₁`, `ρ₂ = rₙ`. As in [`super::simplify::merge_bound`], give node `i` a
//! parameter `sᵢ` (`s₀ = 0`, `sₙ = 1`) and interpolate `s` linearly in `t` between nodes: the
//! map is continuous and onto `[0, 1]`, so every ball of either sweep is paired with a ball of
//! the other, and `d_H(U, Q) ≤ sup_t g(t)`, `g(t) = |p(t) − q(s(t))| + |r(t) − ρ(s(t))|`
//! (balls `B(p, r)`, `B(q, ρ)` with `r, ρ ≥ 0` are within `|p − q| + |r − ρ|`).
//!
//! On link `i → i+1`, write `λ ∈ [0, 1]`, `Δs = sᵢ₊₁ − sᵢ`, `f(λ) = (q, ρ)(sᵢ + λΔs)`. `f` is a
//! quadratic in `λ` with constant second derivative `Δs²·(q'', ρ'')`, `q'' = 2(b₀ − 2b₁ + b₂)`,
//! `ρ'' = 2(ρ₀ − 2ρ₁ + ρ₂)`, so it differs from its chord `ℓ(λ) = (1−λ)f(0) + λf(1)` by exactly
//! `λ(1−λ)/2 · f''`, at most `Δs²·|(q'', ρ'')|/8` per component. Splitting
//! `g ≤ |p − ℓ_x| + |r − ℓ_r| + |ℓ_x − f_x| + |ℓ_r − f_r|`, the first two terms are a norm of
//! an affine function of `λ` plus the absolute value of one — convex, largest at a node — so
//!
//! `d_H(U, Q) ≤ D = max_i [ max(gᵢ, gᵢ₊₁) + Δsᵢ²/4 · (|b₀ − 2b₁ + b₂| + |ρ₀ − 2ρ₁ + ρ₂|) ]`,
//!
//! with `gᵢ = |pᵢ − q(sᵢ)| + |rᵢ − ρ(sᵢ)|`. The same `D` bounds the change of the distance
//! outside (`min_t |x − p(t)| − r(t)`) at every point. Any `sᵢ` gives a valid `D`; the fit uses
//! the chord-length parameters, then the nodes' projections on the last fit's curve (a few
//! rounds), and keeps the smallest `D`. `b₁`, `ρ₁` are least squares for the chosen `sᵢ` (4-space, separable).

use super::{Chain, Prim, Scene};
use tubecast::{QuadTube, V3};

/// A fitted piece and its certified bound `D` (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QuadFit {
    /// The quadratic piece (`f64`, validated: radius curve `> 0` on `[0, 1]`).
    pub quad: QuadTube<f64>,
    /// The certified bound of the Hausdorff distance between the run's union and the piece.
    pub bound: f64,
}

/// Rounds of re-parameterisation (project the nodes on the last fit, fit again); the best
/// bound of all rounds is kept, so more rounds only tighten it.
const FIT_ROUNDS: usize = 6;

fn bern(s: f64) -> [f64; 3] {
    let u = 1.0 - s;
    [u * u, 2.0 * u * s, s * s]
}

/// Least-squares `b₁`, `ρ₁` for parameters `s`; `None` when no interior weight is positive.
fn solve(nodes: &[([f64; 3], f64)], s: &[f64]) -> Option<(V3<f64>, f64)> {
    let (p0, r0) = (V3::from(nodes[0].0), nodes[0].1);
    let (p2, r2) = (V3::from(nodes[nodes.len() - 1].0), nodes[nodes.len() - 1].1);
    let (mut num, mut rn, mut den) = (V3::zero(), 0.0, 0.0);
    for (&(p, r), &si) in nodes.iter().zip(s) {
        let [w0, w1, w2] = bern(si);
        num += (V3::from(p) - p0 * w0 - p2 * w2) * w1;
        rn += (r - r0 * w0 - r2 * w2) * w1;
        den += w1 * w1;
    }
    (den > 0.0).then(|| (num * (1.0 / den), rn / den))
}

/// `D` of `quad` against `nodes` at parameters `s` (see the module docs).
pub fn quad_bound(nodes: &[([f64; 3], f64)], quad: &QuadTube<f64>, s: &[f64]) -> f64 {
    let [b0, b1, b2] = quad.b;
    let [r0, r1, r2] = quad.r;
    let curv = (b0 - b1 * 2.0 + b2).length() + (r0 - 2.0 * r1 + r2).abs();
    let g: Vec<f64> = nodes
        .iter()
        .zip(s)
        .map(|(&(p, r), &si)| (V3::from(p) - quad.point(si)).length() + (r - quad.radius(si)).abs())
        .collect();
    (0..nodes.len().saturating_sub(1))
        .map(|i| g[i].max(g[i + 1]) + (s[i + 1] - s[i]).powi(2) * 0.25 * curv)
        .fold(g.first().copied().unwrap_or(0.0), f64::max)
}

/// The smallest value of a quadratic Bézier on `[0, 1]`.
fn bezier_min(c: [f64; 3]) -> f64 {
    let den = c[0] - 2.0 * c[1] + c[2];
    let mut m = c[0].min(c[2]);
    if den > 0.0 {
        let t = (c[0] - c[1]) / den;
        if t > 0.0 && t < 1.0 {
            let [w0, w1, w2] = bern(t);
            m = m.min(c[0] * w0 + c[1] * w1 + c[2] * w2);
        }
    }
    m
}

/// The parameter of the point of `quad` nearest `p` near `s0` (a few Newton steps on
/// `|q(s) − p|²`, clamped to `[0, 1]`; any result is a valid parameter).
fn project(quad: &QuadTube<f64>, p: V3<f64>, s0: f64) -> f64 {
    let dd = (quad.b[0] - quad.b[1] * 2.0 + quad.b[2]) * 2.0;
    let mut s = s0;
    for _ in 0..4 {
        let d = quad.point(s) - p;
        let t = quad.tangent(s);
        let h = t.length2() + d.dot(dd);
        if h.is_nan() || h <= 0.0 {
            break;
        }
        s = (s - d.dot(t) / h).clamp(0.0, 1.0);
    }
    if s.is_finite() {
        s
    } else {
        s0
    }
}

fn fit_at(nodes: &[([f64; 3], f64)], s: &[f64]) -> Option<QuadFit> {
    let (b1, r1) = solve(nodes, s)?;
    let (a, b) = (nodes[0], nodes[nodes.len() - 1]);
    let r = [a.1, r1, b.1];
    if bezier_min(r).is_nan() || bezier_min(r) <= 0.0 {
        return None;
    }
    let quad = QuadTube::new([V3::from(a.0), b1, V3::from(b.0)], r).ok()?;
    let bound = quad_bound(nodes, &quad, s);
    bound.is_finite().then_some(QuadFit { quad, bound })
}

/// One quadratic piece for the run `nodes` (first to last, at least 3 nodes), or `None` when
/// the input is degenerate or the fitted radius curve is not positive on `[0, 1]`.
///
/// ```
/// use tubecast_render::scene::fit::fit_quad;
/// // Nodes on the parabola y = x², equal radii, 8 links: the nodes lie on the fitted curve
/// // (up to the parameters), the links' chords are off it by up to h²/4 ≈ 0.004 (h = 1/8).
/// let nodes: Vec<([f64; 3], f64)> = (0..=8).map(|i| {
///     let x = i as f64 / 8.0;
///     ([x, x * x, 0.0], 0.1)
/// }).collect();
/// let f = fit_quad(&nodes).unwrap();
/// assert!(f.bound < 1e-2 && f.quad.b[1].y.abs() < 0.05);
/// ```
pub fn fit_quad(nodes: &[([f64; 3], f64)]) -> Option<QuadFit> {
    if nodes.len() < 3 || nodes.iter().any(|(p, r)| !(p.iter().all(|x| x.is_finite()) && r.is_finite())) {
        return None;
    }
    let n = nodes.len() - 1;
    let steps: Vec<f64> = nodes.windows(2).map(|w| (V3::from(w[1].0) - V3::from(w[0].0)).length()).collect();
    let total: f64 = steps.iter().sum();
    let mut s = vec![0.0; nodes.len()];
    let mut run = 0.0;
    for i in 1..=n {
        run += steps[i - 1];
        s[i] = if total > 0.0 { run / total } else { i as f64 / n as f64 };
    }
    s[n] = 1.0;
    let start = fit_at(nodes, &s)?;
    let mut best = refine(nodes, &mut s.clone(), start, start);
    if let Some(b1) = tangent_corner(nodes) {
        let r = [nodes[0].1, 0.5 * (nodes[0].1 + nodes[n].1), nodes[n].1];
        if let Ok(quad) = QuadTube::new([V3::from(nodes[0].0), b1, V3::from(nodes[n].0)], r) {
            let seed = QuadFit { quad, bound: f64::INFINITY };
            best = refine(nodes, &mut s, seed, best);
        }
    }
    Some(best)
}

/// [`FIT_ROUNDS`] rounds from `cur`: project the interior nodes on it, fit again; returns the
/// fit of smallest bound among them and `best`.
fn refine(nodes: &[([f64; 3], f64)], s: &mut [f64], mut cur: QuadFit, mut best: QuadFit) -> QuadFit {
    for _ in 0..FIT_ROUNDS {
        for i in 1..nodes.len() - 1 {
            s[i] = project(&cur.quad, V3::from(nodes[i].0), s[i]);
        }
        let Some(g) = fit_at(nodes, s) else { break };
        if g.bound < best.bound {
            best = g;
        }
        cur = g;
    }
    best
}

/// The midpoint of the closest points of the end tangent lines (the first and last links
/// extended), when they meet ahead of both ends; a start for the fit, not part of the bound.
fn tangent_corner(nodes: &[([f64; 3], f64)]) -> Option<V3<f64>> {
    let n = nodes.len() - 1;
    let (p0, pn) = (V3::from(nodes[0].0), V3::from(nodes[n].0));
    let (d0, d1) = (V3::from(nodes[1].0) - p0, pn - V3::from(nodes[n - 1].0));
    // p0 + u·d0 ≈ pn − v·d1: normal equations of the 2×2 least squares.
    let w = pn - p0;
    let (a, b, c) = (d0.dot(d0), d0.dot(d1), d1.dot(d1));
    let det = a * c - b * b;
    if det.is_nan() || det <= 1e-12 * a * c {
        return None;
    }
    let (e, f) = (d0.dot(w), d1.dot(w));
    let (u, v) = ((c * e - b * f) / det, (a * f - b * e) / det);
    (u > 0.0 && v > 0.0).then(|| (p0 + d0 * u + pn - d1 * v) * 0.5)
}

/// Where each scene link sits in the scene's chains, to find the run of nodes a fitted spline
/// piece of [`super::choice::choose_with`] replaces (the piece names only the first link of
/// its run; it starts at that link's chain node and ends on a later node of the same chain).
///
/// ```
/// use tubecast_render::io::Polyline;
/// use tubecast_render::scene::choice::{choose_with, Tolerance};
/// use tubecast_render::scene::fit::RunIndex;
/// use tubecast_render::scene::Scene;
/// let pts: Vec<[f64; 3]> = (0..=32)
///     .map(|i| { let a = i as f64 / 32.0 * std::f64::consts::FRAC_PI_2; [10.0 * a.cos(), 10.0 * a.sin(), 0.0] })
///     .collect();
/// let mut scene = Scene::from_polylines(&[Polyline { points: pts, radii: vec![] }], 0.5, "arc").unwrap();
/// scene.values = (0..=32).map(|i| i as f64).collect(); // per node: its index along the arc
/// let c = choose_with(&scene, &Tolerance::Absolute(0.01), true);
/// let index = RunIndex::new(&scene);
/// let piece = c.prims.iter().find(|p| p.quad().is_some()).unwrap();
/// let run = index.run(&scene, piece).unwrap();
/// assert!(run.len() >= 3); // a piece replaces two links or more
/// // At its end the piece carries the value of the run's last node, not of its first link's.
/// let v = index.value(&scene, piece, 1.0).unwrap();
/// assert!((v - scene.values[run[run.len() - 1] as usize]).abs() < 1e-6);
/// ```
pub struct RunIndex {
    chains: Vec<Chain>,
    /// Per scene link: its chain and position in it.
    at: Vec<Option<(u32, u32)>>,
}

impl RunIndex {
    /// The index of `scene`'s chains (one pass over [`Scene::chains`]).
    pub fn new(scene: &Scene) -> Self {
        let chains = scene.chains();
        let mut at = vec![None; scene.links.len()];
        for (c, chain) in chains.iter().enumerate() {
            for (i, &l) in chain.links.iter().enumerate() {
                at[l as usize] = Some((c as u32, i as u32));
            }
        }
        Self { chains, at }
    }

    /// The chain nodes (scene node indices, in order) of the run a spline primitive replaces:
    /// from its link's chain node to the first later node at the piece's end (within the `f32`
    /// rounding of the stored control point). `None` for other primitives and for pieces that
    /// do not end on a node of their chain or replace a single link (the spline model's
    /// sub-segments).
    pub fn run(&self, scene: &Scene, prim: &Prim) -> Option<&[u32]> {
        let q = prim.quad()?;
        let (c, i) = (*self.at.get(prim.link as usize)?)?;
        let nodes = &self.chains[c as usize].nodes;
        let origin = V3::from(prim.origin);
        let (start, end) = (origin + q.b[0].cast::<f64>(), origin + q.b[2].cast::<f64>());
        // Each stored coordinate is within 2⁻²⁴ of its own size (relative to the origin);
        // the f64 sums add a few ulps of the world coordinates.
        let tol = |rel: V3<f32>, w: V3<f64>| {
            4.0 * 2f64.powi(-24) * rel.cast::<f64>().length() + 8.0 * f64::EPSILON * w.max_abs()
        };
        let near = |n: u32, p: V3<f64>, t: f64| (V3::from(scene.nodes[n as usize].pos) - p).length() <= t;
        let i = i as usize;
        if !near(nodes[i], start, tol(q.b[0], start)) {
            return None;
        }
        let last = (i + MAX_RUN_LINKS).min(nodes.len() - 1);
        let j = (i + 1..=last).find(|&j| near(nodes[j], end, tol(q.b[2], end)))?;
        (j >= i + 2).then(|| &nodes[i..=j])
    }

    /// Per-node data along a fitted piece at its curve parameter `u`: the piece's axis point
    /// `q(u)` projected on the nearest link of its run, the scene's node values interpolated
    /// linearly there. `None` where [`RunIndex::run`] is, or without node values.
    pub fn value(&self, scene: &Scene, prim: &Prim, u: f64) -> Option<f64> {
        let run = self.run(scene, prim)?;
        let q = prim.quad()?.cast::<f64>();
        let x = V3::from(prim.origin) + q.point(u.clamp(0.0, 1.0));
        let mut best: Option<(f64, f64)> = None;
        for w in run.windows(2) {
            let (a, b) = (V3::from(scene.nodes[w[0] as usize].pos), V3::from(scene.nodes[w[1] as usize].pos));
            let (va, vb) = (*scene.values.get(w[0] as usize)?, *scene.values.get(w[1] as usize)?);
            let ab = b - a;
            let l2 = ab.length2();
            let lam = if l2 > 0.0 { ((x - a).dot(ab) / l2).clamp(0.0, 1.0) } else { 0.0 };
            let d = (x - (a + ab * lam)).length();
            if best.map_or(true, |(bd, _)| d < bd) {
                best = Some((d, va + (vb - va) * lam));
            }
        }
        best.map(|b| b.1)
    }
}

/// Longest run one fitted piece may replace, in links (the choice's limit).
const MAX_RUN_LINKS: usize = super::choice::MAX_FIT_LINKS;
