//! How far the union mesh lies from the union's exact surface, measured triangle by triangle
//! (the derivation is in `docs/design/union-mesh.md`, "The bound").
//!
//! Write `fᵢ` for tube i's exact signed distance (convex: a round cone is convex) and
//! `Ω = ∪ Cᵢ` for the union. The depth of a point `p ∈ Ω` is `D(p) = dist(p, ℝ³ ∖ Ω)`, which
//! near a crease is **larger** than `−minᵢ fᵢ(p)`: a point `s` deep in each of two tubes, on
//! the crease of their polyhedra, is up to `s / sin(β/2)` from the union's surface (β the
//! exterior opening of the exact crease). So the depth is bounded through witnesses outside
//! the union, not through `min fᵢ`:
//!
//! - For a tube m and any unit `n`, the half-space `Hₘ = {y : n·y ≥ hₘ(n)}` (`hₘ` the support
//!   function, [`support`]) holds no interior point of the tube.
//! - For a (piece of a) triangle T, let `Lₘ ≤ min_T fₘ` (tangent plane of the convex `fₘ` at
//!   the centroid, or `fₘ(c) − R`), `A = {m : Lₘ < d}` and `W = ∩_{m∈A} Hₘ` (convex), with
//!   `d = maxⱼ dist(vⱼ, W)` over T's corners. `dist(·, W)` is convex, so every `p ∈ T` is within
//!   `d` of its projection `q ∈ W`; `q` is outside every tube of A (in its half-space) and
//!   outside every other tube (`fₘ(q) ≥ fₘ(p) − d ≥ Lₘ − d ≥ 0`). So `D(p) ≤ d` on T.
//! - Tubes not listed near T are farther than the query's margin; `d` is accepted only below
//!   it.
//!
//! A triangle's `d` is about the sagitta on a tube's side (one half-space, the face's own
//! plane's distance to the parallel support plane), about `s / sin(β/2)` at a crease of
//! opening β (two half-spaces), and unbounded as β → 0 (tangent tubes). A long triangle on a
//! curved or creased region is split into four (its midpoints) and measured piece by piece
//! while that lowers its bound, since one half-space per tube fits only a small region.
//!
//! And outward: `f ≤ bₜ = minₘ maxⱼ fₘ(vⱼ)` on T (convexity of each `fₘ`); manifold's triangles
//! lie on the faces of hulls inside their tubes, so `bₜ` is rounding.

use super::tube::{gradient, side, support, unit, Index, P};
use rayon::prelude::*;
use tubecast::{Primitive, RoundCone};

/// Splits of a triangle into four at most.
const MAX_DEPTH: u32 = 10;

/// How far the tubes' query margin may grow for one triangle whose bound exceeds it.
const MARGIN_GROWTH: f64 = 16.0;

/// Splits of a triangle into four where its bound is far above the goal.
const PLANE_DEPTH: u32 = 6;

/// A measured mesh.
#[derive(Clone, Debug, Default)]
pub(super) struct Measure {
    /// The largest depth bound `d` over the mesh (mesh → surface, inside).
    pub depth: f64,
    /// The largest `max(bₜ, 0)` (mesh → surface, outside: rounding).
    pub out: f64,
    /// The least `sin(β/2) = √((1 + nᵢ·nⱼ)/2)` over the pairs of half-spaces that bound a
    /// piece (1 when none).
    pub min_sin_half: f64,
    /// Triangles whose bound exceeds the goal.
    pub over: Vec<Over>,
}

/// A triangle whose bound exceeds the goal.
#[derive(Clone, Debug)]
pub(super) struct Over {
    /// Its bound.
    pub d: f64,
    /// The tubes whose half-spaces set it.
    pub tubes: Vec<u32>,
    /// The centroid of its deepest piece.
    pub at: P,
    /// The least `sin(β/2)` among the half-spaces of its pieces (1 when none).
    pub sin_half: f64,
    /// Whether a point witness, not the half-spaces, bounds its deepest piece: the bound is
    /// then a distance to the exterior that the sagitta does not set (a lens, a notch).
    pub witness: bool,
}

/// What the pieces of a triangle over the goal leave: the tubes of their half-spaces, and the
/// deepest one's centroid and bound.
#[derive(Default)]
struct Hot {
    tubes: Vec<u32>,
    /// The deepest piece: centroid, bound, and whether a point witness set it.
    deepest: Option<(P, f64, bool)>,
}

struct Ctx<'a> {
    tubes: &'a [RoundCone<f64>],
    index: &'a Index,
    goal: f64,
    /// A bound that is good enough: the search for a smaller one stops below it (the caller's
    /// certificate is at least this much anyway).
    enough: f64,
    /// Relative rounding allowed in a witness's feasibility (its excess is added to `d`).
    tol: f64,
}

/// Measures every triangle; `goal` is the tolerance (pieces are split while above it);
/// `enough` a bound below which no tighter one is sought (the sagitta, which the certificate
/// counts whatever the depth).
pub(super) fn measure(
    tubes: &[RoundCone<f64>],
    positions: &[P],
    triangles: &[[u32; 3]],
    margin: f64,
    goal: f64,
    enough: f64,
) -> Measure {
    let mut lo = f64::INFINITY;
    let mut hi = f64::NEG_INFINITY;
    let mut r_max = 0.0f64;
    for t in tubes {
        let b = t.aabb();
        lo = lo.min(b.min.x.min(b.min.y).min(b.min.z));
        hi = hi.max(b.max.x.max(b.max.y).max(b.max.z));
        r_max = r_max.max(t.ra).max(t.rb);
    }
    let scale = lo.abs().max(hi.abs());
    let index = Index::new(tubes, (4.0 * r_max).max(margin));
    let ctx = Ctx { tubes, index: &index, goal, enough: enough.min(goal), tol: 1e-13 * scale };
    triangles
        .par_iter()
        .map_init(Vec::new, |near, t| {
            let v = t.map(|i| positions[i as usize]);
            triangle(&ctx, v, margin, near)
        })
        .reduce(
            || Measure { min_sin_half: 1.0, ..Default::default() },
            |mut a, b| {
                a.depth = a.depth.max(b.depth);
                a.out = a.out.max(b.out);
                a.min_sin_half = a.min_sin_half.min(b.min_sin_half);
                a.over.extend(b.over);
                a
            },
        )
}

fn triangle(ctx: &Ctx, v: [P; 3], margin: f64, near: &mut Vec<u32>) -> Measure {
    let lo = P::new(v[0].x.min(v[1].x).min(v[2].x), v[0].y.min(v[1].y).min(v[2].y), v[0].z.min(v[1].z).min(v[2].z));
    let hi = P::new(v[0].x.max(v[1].x).max(v[2].x), v[0].y.max(v[1].y).max(v[2].y), v[0].z.max(v[1].z).max(v[2].z));
    let nt = unit((v[1] - v[0]).cross(v[2] - v[0]));
    let first = margin;
    let mut margin = margin;
    let mut m = Measure { min_sin_half: 1.0, ..Default::default() };
    let c = (v[0] + v[1] + v[2]) * (1.0 / 3.0);
    let r = v.iter().map(|&x| (x - c).length()).fold(0.0, f64::max);
    for _ in 0..3 {
        ctx.index.near(lo, hi, margin, near);
        // The index answers by bounding boxes (a long link's box holds much that is far from
        // it): keep the tubes that may come within `margin` of the triangle, where
        // `fₘ ≥ fₘ(c) − r` on it (a distance is 1-Lipschitz). The others stay farther than
        // `margin` from every point of it, as the bound needs.
        near.retain(|&k| ctx.tubes[k as usize].sdf(c) - r <= margin);
        // Outside: bₜ against the tubes near (a tube holding the three corners is among them).
        let b = near
            .iter()
            .map(|&k| v.iter().map(|&x| ctx.tubes[k as usize].sdf(x)).fold(f64::NEG_INFINITY, f64::max))
            .fold(f64::INFINITY, f64::min);
        m.out = b.max(0.0);
        let mut hot = Hot::default();
        let (d, sh) = piece(ctx, near, v, nt, 0, margin, &mut hot);
        m.min_sin_half = sh;
        if d <= margin {
            m.depth = d;
            if d > ctx.goal {
                let Hot { mut tubes, deepest } = hot;
                tubes.sort_unstable();
                tubes.dedup();
                let (at, witness) = deepest.map_or((c, false), |x| (x.0, x.2));
                m.over.push(Over { d, tubes, at, sin_half: sh, witness });
            }
            return m;
        }
        // A bound past the margin needs the tubes within it listed. Past `MARGIN_GROWTH` times
        // the first margin it is reported infinite instead: the refinement takes its largest
        // step either way, and in a dense bundle such a margin lists hundreds of tubes per
        // triangle (most of the certificate's time); where no point is outside them all
        // (`d` infinite), listing more cannot help.
        if d.is_nan() || d >= MARGIN_GROWTH * first {
            break;
        }
        margin = 2.0 * d;
    }
    m.depth = f64::INFINITY;
    m.over.push(Over { d: f64::INFINITY, tubes: near.clone(), at: c, sin_half: m.min_sin_half, witness: false });
    m
}

/// The depth bound of the piece `v` of a triangle with outward unit normal `nt`, split while
/// that lowers it (`margin`: the tubes' query margin); where it exceeds the goal, `hot` gains
/// the tubes whose half-spaces bound it and keeps the deepest piece. Returns
/// `(d, least sin(β/2))`.
fn piece(ctx: &Ctx, near: &[u32], v: [P; 3], nt: P, depth: u32, margin: f64, hot: &mut Hot) -> (f64, f64) {
    let c = (v[0] + v[1] + v[2]) * (1.0 / 3.0);
    let r = v.iter().map(|&x| (x - c).length()).fold(0.0, f64::max);
    let (d, sh, a, hopeful, witness) = leaf(ctx, near, v, nt, depth, r, margin);
    // Splitting helps where one tangent plane per tube cannot fit the piece: the piece is
    // large against its own bound.
    // Past the splits that fit tangent planes (`PLANE_DEPTH`), only a point witness near
    // enough the centroid still gains.
    let deep = depth >= PLANE_DEPTH && !hopeful;
    if d <= ctx.goal || depth == MAX_DEPTH || deep || (d.is_finite() && r < 0.25 * d) {
        if d > ctx.goal {
            hot.tubes.extend(a);
            if hot.deepest.map_or(true, |s| d > s.1) {
                hot.deepest = Some((c, d, witness));
            }
        }
        return (d, sh);
    }
    let m = [(v[0] + v[1]) * 0.5, (v[1] + v[2]) * 0.5, (v[2] + v[0]) * 0.5];
    let mut out = (0.0f64, 1.0f64);
    for p in [[v[0], m[0], m[2]], [m[0], v[1], m[1]], [m[2], m[1], v[2]], [m[0], m[1], m[2]]] {
        let (d, sh) = piece(ctx, near, p, nt, depth + 1, margin, hot);
        out = (out.0.max(d), out.1.min(sh));
    }
    out
}

/// One piece, unsplit: `(d, least sin(β/2) among its half-spaces, the tubes of A)`; `d` the
/// lesser of the half-spaces' bound and a point witness's: a point `q` outside every tube
/// (checked on each tube near, and nearer the piece's centroid `c` than `margin`, so outside
/// the others) bounds the depth of every point `p` of the piece by `|p − q|`, at most
/// `maxⱼ |vⱼ − q|` over the piece's corners (`|· − q|` is convex). The half-spaces need one
/// tangent plane per tube to fit the piece; where two streamlines' joints nearly touch, none
/// does, while the surface is a hair's breadth from the centroid.
///
/// Also whether smaller pieces would meet the goal through the point witness (its distance
/// from the centroid, the bound's limit as the piece shrinks about it, is below 0.9 of the
/// goal), and whether the witness set `d`. A lens where two surfaces nearly touch (a ball
/// against a node's sphere) keeps mesh points up to the lens's radius deep however fine the
/// spheres, which may be just within the goal: only smaller pieces show it.
///
/// `depth` and `r` (its largest corner distance from the centroid) are the piece's in `piece`.
fn leaf(
    ctx: &Ctx,
    near: &[u32],
    v: [P; 3],
    nt: P,
    depth: u32,
    r: f64,
    margin: f64,
) -> (f64, f64, Vec<u32>, bool, bool) {
    let (d, sh, a) = planes(ctx, near, v, nt);
    let c = (v[0] + v[1] + v[2]) * (1.0 / 3.0);
    // Below the goal nothing is gained; far above it (a crease to refine) the witness is
    // rarely nearer, except on a piece that the planes' bound would not split further
    // (`piece`): there the planes may just not fit (two tubes all but tangent where they
    // part at a joint; measured: a bound of 6.2·ε, 300 times the true depth, kept through
    // four builds).
    let last = depth >= PLANE_DEPTH || r < 0.25 * d;
    if d <= ctx.goal || (d > 4.0 * ctx.goal && !last) {
        return (d, sh, a, false, false);
    }
    let outside = |q: P| near.iter().all(|&k| ctx.tubes[k as usize].sdf(q) >= ctx.tol);
    let push = 4.0 * ctx.tol;
    // The witnesses' least bound over the piece, and least distance from the centroid (a
    // lower bound of the former: the centroid is a mean of the corners).
    let (mut best, mut least) = (f64::INFINITY, f64::INFINITY);
    let mut take = |q: P| {
        let e = (q - c).length();
        if e < margin && e < best && outside(q) {
            best = best.min(v.iter().map(|&x| (x - q).length()).fold(0.0, f64::max));
            least = least.min(e);
        }
    };
    // The centroid itself, its projections out of each tube holding it, and the crease points
    // of the three tubes least at it, pairwise.
    let mut by_depth: Vec<(f64, u32)> = near.iter().map(|&k| (ctx.tubes[k as usize].sdf(c), k)).collect();
    by_depth.sort_by(|x, y| x.0.total_cmp(&y.0));
    let inside = by_depth.iter().take_while(|x| x.0 < 0.0).count();
    if inside == 0 {
        take(c);
    }
    for &(f, k) in &by_depth[..inside] {
        take(c + gradient(&ctx.tubes[k as usize], c) * (push - f));
    }
    // A crease is the nearest exterior where the centroid lies in one tube and just outside
    // the other (a notch's narrow slit: the push out of the one lands in the other), as well
    // as where it lies inside both.
    let three = by_depth.len().min(3);
    for i in 0..three {
        for j in i + 1..three {
            let (ta, tb) = (&ctx.tubes[by_depth[i].1 as usize], &ctx.tubes[by_depth[j].1 as usize]);
            // The landing and the nearest point: either may lie in a third tube.
            for x in [crease(ta, tb, c, false), crease(ta, tb, c, true)].into_iter().flatten() {
                // Along the bisector of the two outward normals, each distance grows by
                // `cos` of half their angle (`|g_a + g_b|/2`): small in a notch, where the
                // two surfaces face each other.
                let g = gradient(ta, x) + gradient(tb, x);
                let h = 0.5 * g.length();
                if h > 1e-9 {
                    take(x + unit(g) * (push / h));
                }
            }
        }
    }
    (best.min(d), sh, a, least < 0.9 * ctx.goal, best < d)
}

/// The half-spaces' bound of one piece (see [`leaf`]).
fn planes(ctx: &Ctx, near: &[u32], v: [P; 3], nt: P) -> (f64, f64, Vec<u32>) {
    let c = (v[0] + v[1] + v[2]) * (1.0 / 3.0);
    let r = v.iter().map(|&x| (x - c).length()).fold(0.0, f64::max);
    // Lower bounds of each tube's distance on the piece, and its gradient at the centroid.
    let lower: Vec<(u32, f64, P)> = near
        .iter()
        .map(|&k| {
            let t = &ctx.tubes[k as usize];
            let fc = t.sdf(c);
            let g = gradient(t, c);
            let lin = v.iter().map(|&x| g.dot(x - c)).fold(f64::INFINITY, f64::min);
            (k, (fc + lin).max(fc - r), g)
        })
        .collect();
    let mut d_req = 0.0f64;
    loop {
        let active: Vec<&(u32, f64, P)> = lower.iter().filter(|l| l.1 < d_req || l.1 < 0.0).collect();
        // One half-space per tube, from one of five choices of normals, whichever gives
        // the least bound: per tube the triangle's own normal (exact on the face of a hull)
        // or the tube's gradient at the centroid, whichever puts the corners nearer; the same
        // with its side's normal there as a third choice (`side`); every tube's
        // gradient at the centroid; and, with two tubes or more, every tube's gradient at the
        // nearest crease point of the two least, and of the least and the next one apart
        // (there the half-spaces meet in the exterior wedge of the crease; at the centroid,
        // inside two tubes overlapping at a narrow angle, they face apart and may not meet at
        // all). The first choice alone is the bound's earlier form: the others only lower it.
        let plane = |k: u32, n: P| (n, support(&ctx.tubes[k as usize], n));
        let mut options: Vec<Vec<(P, f64)>> = Vec::with_capacity(5);
        // Per tube, the normal with the least gap among `choices` at the piece.
        let nearest = |choices: &dyn Fn(&RoundCone<f64>, P) -> Vec<P>| -> Vec<(P, f64)> {
            active
                .iter()
                .map(|&&(k, _, g)| {
                    let t = &ctx.tubes[k as usize];
                    choices(t, g)
                        .into_iter()
                        .map(|n| {
                            let h = support(t, n);
                            (n, h, v.iter().map(|&x| h - n.dot(x)).fold(0.0, f64::max))
                        })
                        .min_by(|a, b| a.2.total_cmp(&b.2))
                        .map(|(n, h, _)| (n, h))
                        .expect("two choices")
                })
                .collect()
        };
        options.push(nearest(&|_, g| vec![nt, g]));
        let sides = nearest(&|t, g| vec![nt, g, side(t, c)]);
        if sides != options[0] {
            options.push(sides);
        }
        if active.len() >= 2 {
            options.push(active.iter().map(|&&(k, _, g)| plane(k, g)).collect());
            let mut two: Vec<&&(u32, f64, P)> = active.iter().collect();
            two.sort_by(|a, b| a.1.total_cmp(&b.1));
            // The crease of the two least tubes, and of the least with the next one that is
            // not its neighbour along a chain (neighbours meet at a joint's ball, not at the
            // crease of two crossing tubes).
            let first = &ctx.tubes[two[0].0 as usize];
            let apart = |k: u32| {
                let t = &ctx.tubes[k as usize];
                t.a != first.a && t.a != first.b && t.b != first.a && t.b != first.b
            };
            let mut partners = vec![two[1].0];
            if let Some(l) = two[1..].iter().find(|l| apart(l.0)) {
                if l.0 != two[1].0 {
                    partners.push(l.0);
                }
            }
            for k in partners {
                if let Some(x) = crease(first, &ctx.tubes[k as usize], c, false) {
                    options
                        .push(active.iter().map(|&&(k, _, _)| plane(k, gradient(&ctx.tubes[k as usize], x))).collect());
                }
            }
        }
        let mut best: Option<(f64, Vec<(P, f64)>)> = None;
        for mut planes in options {
            // Tubes of one streamline or parallel ones give the same normal: the farther
            // plane implies the nearer, which is dropped (fewer candidates, same W).
            planes.sort_by(|a, b| (a.0.x, a.0.y, a.0.z, -a.1).partial_cmp(&(b.0.x, b.0.y, b.0.z, -b.1)).unwrap());
            planes.dedup_by(|b, a| a.0 == b.0);
            let d = v.iter().map(|&x| distance(&planes, x, ctx.tol, ctx.enough)).fold(0.0, f64::max);
            if best.as_ref().map_or(true, |b| d < b.0) {
                best = Some((d, planes));
            }
            if d <= ctx.enough {
                break;
            }
        }
        let (d, planes) = best.expect("one option at least");
        let mut sh = 1.0f64;
        for i in 0..planes.len() {
            for j in i + 1..planes.len() {
                sh = sh.min(((1.0 + planes[i].0.dot(planes[j].0)) * 0.5).max(0.0).sqrt());
            }
        }
        let more = lower.iter().any(|l| l.1 < d && l.1 >= d_req && l.1 >= 0.0);
        if !d.is_finite() || !more {
            return (d, sh, active.iter().map(|l| l.0).collect());
        }
        d_req = d;
    }
}

/// A point of the crease `f_a = f_b = 0` near `p` (with `nearest`, the nearest), or `None`
/// where the steps fail (the two surfaces tangent on the way). Least-norm steps from `p` land
/// on the crease (quadratic convergence), but not at its point nearest `p`: where two surfaces
/// nearly face each other (a ball against a node's sphere), the landing is where their normals
/// first part, much farther than the crease's nearest point. So with `nearest`, the steps first
/// linearise both exact distances at the current point and move to the point of that linear
/// crease nearest `p` (Gauss–Newton on the least distance, linear convergence; ten steps at
/// most, to 10⁻⁶ of the coordinates: a witness needs no more), and the least-norm steps then
/// settle the point reached on the crease. The point witnesses need the
/// nearest point; the tangent planes' choice needs only normals near the crease (any point of
/// it gives valid half-spaces), and is made on far more pieces. A witness is checked outside
/// every tube.
fn crease(a: &RoundCone<f64>, b: &RoundCone<f64>, p: P, nearest: bool) -> Option<P> {
    let mut x = p;
    let mut anchored = nearest;
    for k in 0..if nearest { 30 } else { 20 } {
        let (fa, fb, ga, gb) = (a.sdf(x), b.sdf(x), gradient(a, x), gradient(b, x));
        let c = ga.dot(gb);
        let det = 1.0 - c * c;
        if det < 1e-12 {
            return None;
        }
        // The point `o + ga·λa + gb·λb` where both linearised distances vanish, `o` the anchor.
        let o = if anchored { p } else { x };
        let (ra, rb) = (fa + ga.dot(o - x), fb + gb.dot(o - x));
        let y = o - ga * ((ra - c * rb) / det) - gb * ((rb - c * ra) / det);
        let moved = (y - x).length();
        x = y;
        let size = 1.0 + x.length();
        if anchored && (moved <= 1e-6 * size || k == 9) {
            anchored = false;
        } else if !anchored && moved <= 1e-13 * size {
            break;
        }
    }
    x.is_finite().then_some(x)
}

/// An upper bound on the distance from `x` to `W = {y : n·y ≥ h for every (n, h)}`: the
/// distance to the nearest point of `W` among the projections of `x` onto the planes of one,
/// two or three constraints (the projection onto W is one of them when W is not empty);
/// infinite when none is in `W`; the search stops at a candidate within `enough`. A candidate
/// may violate a constraint by rounding (`tol`):
/// that excess is added.
fn distance(planes: &[(P, f64)], x: P, tol: f64, enough: f64) -> f64 {
    let excess = |y: P| planes.iter().map(|&(n, h)| h - n.dot(y)).fold(0.0, f64::max);
    let ok = |y: P| {
        let e = excess(y);
        (e <= tol).then(|| (y - x).length() + e)
    };
    if let Some(d) = ok(x) {
        return d;
    }
    let mut best = f64::INFINITY;
    let n = planes.len();
    for &(ni, hi) in planes {
        let y = x + ni * (hi - ni.dot(x));
        if let Some(d) = ok(y) {
            best = best.min(d);
        }
    }
    if best <= enough {
        return best;
    }
    for i in 0..n {
        for j in i + 1..n {
            let ((a, ha), (b, hb)) = (planes[i], planes[j]);
            let cab = a.dot(b);
            let det = 1.0 - cab * cab;
            if det < 1e-12 {
                continue;
            }
            let (ra, rb) = (ha - a.dot(x), hb - b.dot(x));
            let la = (ra - cab * rb) / det;
            let lb = (rb - cab * ra) / det;
            if let Some(d) = ok(x + a * la + b * lb) {
                best = best.min(d);
            }
        }
    }
    if best <= enough {
        return best;
    }
    // Vertices of three constraints (the projection can be one where W is a narrow cone);
    // many tubes at one piece (a hub of branches) keep to the cheaper candidates.
    if n <= 16 {
        for i in 0..n {
            for j in i + 1..n {
                for k in j + 1..n {
                    let ((a, ha), (b, hb), (c, hc)) = (planes[i], planes[j], planes[k]);
                    let bc = b.cross(c);
                    let det = a.dot(bc);
                    if det.abs() < 1e-9 {
                        continue;
                    }
                    let y = (bc * ha + c.cross(a) * hb + a.cross(b) * hc) * (1.0 / det);
                    if let Some(d) = ok(y) {
                        best = best.min(d);
                    }
                }
            }
        }
    }
    best
}
