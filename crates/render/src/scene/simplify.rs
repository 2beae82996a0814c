//! Error-bounded simplification of chains: consecutive links merged into one round cone while
//! the merged solid stays within ε of the union it replaces, both ways.
//!
//! # Bound
//! Nodes `(pᵢ, rᵢ)`, `i = a..b`, their links' union `U` is the sphere sweep of the
//! piecewise-linear `(p(t), r(t))`; the merged link `L` is the sweep of the linear
//! `(q(s), ρ(s))` from `(p_a, r_a)` to `(p_b, r_b)`. Give every node any parameter
//! `sᵢ ∈ [0, 1]` (`s_a = 0`, `s_b = 1`) and interpolate `s` linearly between nodes: the map
//! `t ↦ s` is continuous and onto `[0, 1]`, so every ball of either sweep is paired with a ball
//! of the other, and balls `B(p, r)`, `B(q, ρ)` are within Hausdorff distance `|p − q| + |r − ρ|`.
//! On each link the gap `|p(t) − q(s(t))| + |r(t) − ρ(s(t))|` is convex in `t` (a norm of a
//! linear function plus an absolute value of one), so its maximum is at a node:
//!
//! `d_H(U, L) ≤ D = max_i min_{sᵢ} (|pᵢ − q(sᵢ)| + |rᵢ − ρ(sᵢ)|)`,
//!
//! and the same `D` bounds the change of `min_t (|x − p(t)| − r(t))` (the signed distance
//! outside) at every point `x`. `sᵢ` is taken as the better of the projection of `pᵢ` on the
//! chord (clamped) and the chord-length fraction; any choice is valid, a better one only
//! tightens `D`.

use tubecast::V3;

/// `D` for merging the nodes `nodes[0..]` (first to last) into one link (see the module docs).
///
/// ```
/// use tubecast_render::scene::simplify::merge_bound;
/// let n = |x: f64, y: f64, r: f64| ([x, y, 0.0], r);
/// assert_eq!(merge_bound(&[n(0.0, 0.0, 1.0), n(1.0, 0.0, 1.0), n(2.0, 0.0, 1.0)]), 0.0);
/// assert!((merge_bound(&[n(0.0, 0.0, 1.0), n(1.0, 0.1, 1.0), n(2.0, 0.0, 1.0)]) - 0.1).abs() < 1e-12);
/// ```
pub fn merge_bound(nodes: &[([f64; 3], f64)]) -> f64 {
    let (Some(&(a, ra)), Some(&(b, rb))) = (nodes.first(), nodes.last()) else { return 0.0 };
    let (a, b) = (V3::from(a), V3::from(b));
    let chord = b - a;
    let l2 = chord.length2();
    let total: f64 = nodes.windows(2).map(|w| (V3::from(w[1].0) - V3::from(w[0].0)).length()).sum();
    let gap = |p: V3<f64>, r: f64, s: f64| (p - (a + chord * s)).length() + (r - (ra + (rb - ra) * s)).abs();
    let mut run = 0.0;
    let mut worst: f64 = 0.0;
    for (i, &(p, r)) in nodes.iter().enumerate() {
        if i > 0 {
            run += (V3::from(p) - V3::from(nodes[i - 1].0)).length();
        }
        let p = V3::from(p);
        let proj = if l2 > 0.0 { ((p - a).dot(chord) / l2).clamp(0.0, 1.0) } else { 0.0 };
        let frac = if total > 0.0 { run / total } else { 0.0 };
        let s = match i {
            0 => 0.0,
            _ if i + 1 == nodes.len() => 1.0,
            _ => proj,
        };
        let g = if i == 0 || i + 1 == nodes.len() { gap(p, r, s) } else { gap(p, r, proj).min(gap(p, r, frac)) };
        worst = worst.max(g);
    }
    worst
}

/// The nodes to keep of a chain (indices into `nodes`, the first and last always kept):
/// greedily, each kept node is followed by the farthest node whose merged link stays within
/// `eps` ([`merge_bound`]). Returns the kept indices and the largest `D` reached (≤ `eps`).
///
/// ```
/// use tubecast_render::scene::simplify::simplify_chain;
/// let line: Vec<([f64; 3], f64)> = (0..10).map(|i| ([i as f64, 0.0, 0.0], 0.5)).collect();
/// assert_eq!(simplify_chain(&line, 1e-9), (vec![0, 9], 0.0)); // straight: one link
/// ```
pub fn simplify_chain(nodes: &[([f64; 3], f64)], eps: f64) -> (Vec<usize>, f64) {
    if nodes.len() <= 2 {
        return ((0..nodes.len()).collect(), 0.0);
    }
    let (mut keep, mut worst) = (vec![0], 0.0f64);
    let mut a = 0;
    while a + 1 < nodes.len() {
        let mut b = a + 1;
        let mut d_b = 0.0;
        while b + 1 < nodes.len() {
            let d = merge_bound(&nodes[a..=b + 1]);
            if d > eps {
                break;
            }
            b += 1;
            d_b = d;
        }
        worst = worst.max(d_b);
        keep.push(b);
        a = b;
    }
    (keep, worst)
}

/// A polyline simplified within `eps` (points without radii use `default_radius` for the bound
/// and stay without radii). Returns the polyline and the largest `D` reached.
///
/// ```
/// use tubecast_render::io::Polyline;
/// use tubecast_render::scene::simplify::simplify_polyline;
/// let line = Polyline { points: (0..5).map(|i| [i as f64, 0.0, 0.0]).collect(), radii: vec![] };
/// assert_eq!(simplify_polyline(&line, 0.2, 1e-6).0.points.len(), 2);
/// ```
pub fn simplify_polyline(line: &crate::io::Polyline, default_radius: f64, eps: f64) -> (crate::io::Polyline, f64) {
    let r = |i: usize| line.radii.get(i).copied().unwrap_or(default_radius);
    let nodes: Vec<([f64; 3], f64)> = line.points.iter().enumerate().map(|(i, &p)| (p, r(i))).collect();
    let (keep, d) = simplify_chain(&nodes, eps);
    let points = keep.iter().map(|&i| line.points[i]).collect();
    let radii = if line.radii.is_empty() { Vec::new() } else { keep.iter().map(|&i| line.radii[i]).collect() };
    (crate::io::Polyline { points, radii }, d)
}

/// An SWC tree simplified within `eps`: runs of nodes with one parent and one child (of the
/// same structure type) are chains; each is simplified and the kept nodes re-parented to the
/// previous kept node. Roots, branch points, tips and type changes are kept; ids are kept.
///
/// ```
/// use tubecast_render::io::swc::SwcNode;
/// use tubecast_render::scene::simplify::simplify_swc;
/// let n = |id: i64, x: f64, parent: i64| SwcNode { id, kind: 3, pos: [x, 0.0, 0.0], radius: 0.5, parent };
/// let (rows, d) = simplify_swc(&[n(1, 0.0, -1), n(2, 1.0, 1), n(3, 2.0, 2), n(4, 3.0, 3)], 1e-6);
/// assert_eq!(rows.iter().map(|r| (r.id, r.parent)).collect::<Vec<_>>(), vec![(1, -1), (4, 1)]);
/// assert_eq!(d, 0.0);
/// ```
pub fn simplify_swc(rows: &[crate::io::swc::SwcNode], eps: f64) -> (Vec<crate::io::swc::SwcNode>, f64) {
    use std::collections::HashMap;
    let at: HashMap<i64, usize> = rows.iter().enumerate().map(|(i, r)| (r.id, i)).collect();
    let mut children = vec![0usize; rows.len()];
    for r in rows {
        if let Some(&p) = at.get(&r.parent) {
            children[p] += 1;
        }
    }
    let parent = |i: usize| at.get(&rows[i].parent).copied();
    // Interior chain node: one child, a parent, the same type as both neighbours.
    let interior = |i: usize| children[i] == 1 && parent(i).is_some_and(|p| rows[p].kind == rows[i].kind);
    let mut out: Vec<crate::io::swc::SwcNode> = rows.to_vec();
    let mut drop = vec![false; rows.len()];
    let mut worst: f64 = 0.0;
    for v in (0..rows.len()).filter(|&v| !interior(v)) {
        // Walk up from v through interior nodes to the next kept ancestor.
        let mut path = vec![v];
        let mut cur = v;
        while let Some(p) = parent(cur) {
            path.push(p);
            if !interior(p) || path.len() > rows.len() {
                break;
            }
            cur = p;
        }
        if path.len() < 3 || interior(path[path.len() - 1]) {
            continue;
        }
        path.reverse(); // ancestor … v
        let nodes: Vec<([f64; 3], f64)> = path.iter().map(|&i| (rows[i].pos, rows[i].radius)).collect();
        let (keep, d) = simplify_chain(&nodes, eps);
        worst = worst.max(d);
        let kept: std::collections::HashSet<usize> = keep.iter().map(|&k| path[k]).collect();
        path.iter().filter(|i| !kept.contains(i)).for_each(|&i| drop[i] = true);
        for w in keep.windows(2) {
            out[path[w[1]]].parent = rows[path[w[0]]].id;
        }
    }
    let rows = out.into_iter().zip(drop).filter(|(_, d)| !d).map(|(r, _)| r).collect();
    (rows, worst)
}
