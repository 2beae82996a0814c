//! Runs of equal-radius links meshed as one closed body each, before the union: a ring of `n`
//! vertices at every node (in the plane that bisects the joint, a *mitre*: on the node sphere,
//! and on the bend's inner side on the ellipse where the two links' cylinders meet; where the
//! refinement asks, a *wedge* of rings on the ball across the bend's outer side),
//! bands of triangles between consecutive rings, and a polyhedral half-sphere at each end of
//! the run. A streamline of a tractogram becomes one body of about `2n` triangles per link,
//! where a hull of two sphere polyhedra per link (`hull.rs`) leaves every joint a crease of
//! the sphere's facets.
//!
//! The body is inscribed (every vertex on a node sphere or, at a fork ring or a mitre's inner
//! side, on its links' cylinders within the links; every triangle in one link's round cone or
//! one ball), and it contains every link's round cone shrunk by the run's sagitta
//! `s = r − R` (`R` measured on the triangles, below), which is all the union's certificate
//! needs from a construction (`docs/design/union-mesh.md`, "Runs"). Joints that cannot be
//! mitred within the budget, or whose neighbouring links are too short for the rings to stay
//! apart, end the run there: both sides then close with a half-sphere, and manifold's union
//! joins them.

use super::tube::{unit, P};
use crate::scene::Chain;
use std::collections::HashMap;
use std::f64::consts::{FRAC_PI_2, PI};
use tubecast::V3;

/// A direction about which a node's ring is graded finer: across link `link`'s axis towards
/// the tube or chain `key` it grazes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Focus {
    pub dir: P,
    pub key: u32,
    pub link: u32,
}

/// Where a run's body is made finer than its ring sizes: per node, the directions its rings
/// are graded about and whether its mitre spans its ball by a wedge of rings; per link, the
/// stations where a ring is put across its axis.
#[derive(Clone, Copy)]
pub(super) struct Grading<'a> {
    pub focus: &'a [Vec<Focus>],
    pub stations: &'a [Vec<P>],
    pub wedge: &'a [bool],
}

/// Ring vertices at most (a ring's sagitta goes as `1/n²`: `r·1.2·10⁻⁶` at the cap).
pub(super) const MAX_RING: u32 = 2048;

/// Rings on either side of a wedged mitre at most (a cost limit: each adds about `n`
/// triangles on the bend's outer half).
const MAX_WEDGE: usize = 64;

/// A run of links to mesh as one body: nodes in chain order, the links between them, one
/// radius.
#[derive(Clone, Debug)]
pub(super) struct Run {
    pub nodes: Vec<usize>,
    pub links: Vec<u32>,
    pub r: f64,
}

/// One run's closed body: outward-oriented triangles, per triangle the link (tube index) it
/// stands for, the ring size and the certified sagitta (every point of the run's links'
/// surfaces is within it of the body).
pub(super) struct Body {
    pub positions: Vec<P>,
    pub triangles: Vec<[u32; 3]>,
    pub tags: Vec<u32>,
    pub ring: u32,
    pub sagitta: f64,
    /// The run's mitres that a wedge would change (scene node indices): its interior nodes
    /// where the run bends by more than half the wedge's step (`ε/(2r)`; below it the
    /// mitre's outer gap is already within the wedge's).
    pub mitres: Vec<usize>,
}

/// A unit vector perpendicular to the unit vector `d`.
fn perpendicular(d: P) -> P {
    let helper = if d.x.abs() < 0.6 { V3::new(1.0, 0.0, 0.0) } else { V3::new(0.0, 1.0, 0.0) };
    unit(helper - d * helper.dot(d))
}

/// Half-angle cosine and sine of the bend between unit directions `d1` and `d2`.
fn half(d1: P, d2: P) -> (f64, f64) {
    let t = d1.cross(d2).length().atan2(d1.dot(d2)) / 2.0;
    (t.cos(), t.sin())
}

/// The runs of the scene's chains: maximal stretches of links of positive length whose nodes
/// all have the same radius, cut at joints that cannot be mitred (see [`mitre`]). `target` is
/// the sagitta target per node. Links in no run are left to the hulls.
pub(super) fn runs(chains: &[Chain], centres: &[P], radii: &[f64], target: &[f64]) -> Vec<Run> {
    let mut out = Vec::new();
    for chain in chains {
        let node = |i: usize| chain.nodes[i] as usize;
        let mut k = 0;
        while k + 1 < chain.nodes.len() {
            let r = radii[node(k)];
            // The stretch of equal radii and positive lengths from k.
            let mut e = k;
            while e + 1 < chain.nodes.len() && radii[node(e + 1)] == r && centres[node(e + 1)] != centres[node(e)] {
                e += 1;
            }
            if e == k {
                k += 1;
                continue;
            }
            let nodes: Vec<usize> = (k..=e).map(node).collect();
            let links: Vec<u32> = chain.links[k..e].to_vec();
            // Cut where a joint cannot be mitred.
            let dirs: Vec<P> = nodes.windows(2).map(|w| unit(centres[w[1]] - centres[w[0]])).collect();
            let lens: Vec<f64> = nodes.windows(2).map(|w| (centres[w[1]] - centres[w[0]]).length()).collect();
            let bend: Vec<(f64, f64)> = (0..nodes.len())
                .map(|j| if j == 0 || j + 1 == nodes.len() { (1.0, 0.0) } else { half(dirs[j - 1], dirs[j]) })
                .collect();
            let mut start = 0;
            let mut cuts = Vec::new();
            for j in 1..nodes.len() {
                if j + 1 == nodes.len() || !mitre(j, &bend, &lens, r, target[nodes[j]]) {
                    cuts.push((start, j));
                    start = j;
                }
            }
            for (a, b) in cuts {
                out.push(Run { nodes: nodes[a..=b].to_vec(), links: links[a..b].to_vec(), r });
            }
            k = e;
        }
    }
    out
}

/// Whether interior node `j` of a stretch may be a mitre: the bend costs at most half the
/// sagitta target (`r·(1 − cos(θ/2))`, which also keeps `θ` below a right angle), and each of
/// its two links is long enough for the conditions of `docs/design/union-mesh.md` ("Runs"):
/// each end ring (reaching `r/cos(θ/2)` from its node) lies strictly on its link's side of
/// the other end's plane, a shrunk round
/// cone's part beyond a mitre stays within the next link's cylinder (`L ≥ r·sin θ` for the
/// bends at both ends), and the outer wedge of a joint's ball stays behind the next plane
/// (`L·cos(θ/2) > r·sin(θ/2)`). The neighbours' bends are taken as mitred: a cut there (a
/// bend of 0) only relaxes every condition.
fn mitre(j: usize, bend: &[(f64, f64)], lens: &[f64], r: f64, target: f64) -> bool {
    let (c, s) = bend[j];
    if r * (1.0 - c) > 0.5 * target {
        return false;
    }
    let r = r * (1.0 + 1e-9);
    // The sine of the angle between two mitre planes' normals: at most the sine of the sum
    // of the half-bends, or 1 past a right angle.
    let tilt =
        |(c1, s1): (f64, f64), (c2, s2): (f64, f64)| if c1 * c2 - s1 * s2 >= 0.0 { s1 * c2 + c1 * s2 } else { 1.0 };
    // A mitre ring reaches `r/cos(θ/2)` from its node in its plane (the inner side's
    // ellipse): each end ring stays on its side of the other's plane when
    // `L·cos(θ₁/2)·cos(θ₂/2) > r·sin∠(u₁, u₂)`.
    let ok = |len: f64, (co, so): (f64, f64)| {
        let t = tilt((co, so), (c, s));
        len * c * co > r * t
            && len >= r * 2.0 * s * c
            && len >= r * 2.0 * so * co
            && len * c > r * s
            && len * co > r * so
    };
    ok(lens[j - 1], bend[j - 1]) && ok(lens[j], bend[j + 1])
}

/// The ring sizes of a run, per node: the least `n` whose ring keeps within the node's
/// sagitta target `s`, `r·(1 − cos(π/n)·cos(θ/2)) ≤ s` at a mitre of bend `θ`, and at the
/// run's ends `r·(1 − cos(π/n)·cos(Δφ/2))` on the caps' latitude bands of
/// `Δφ = π/(2·⌈n/2⌉)`. Sizes vary along the run: a refinement raises them only near the
/// crease that asked for it.
pub(super) fn ring_sizes(run: &Run, centres: &[P], target: &[f64]) -> Vec<u32> {
    let m = run.nodes.len() - 1;
    (0..=m)
        .map(|j| {
            let c = if j == 0 || j == m {
                1.0
            } else {
                let [a, b, d] = [j - 1, j, j + 1].map(|i| centres[run.nodes[i]]);
                half(unit(b - a), unit(d - b)).0
            };
            let s = target[run.nodes[j]];
            // Margin for the bands' diagonals and the rounding, which the body measures.
            let want = 1.0 - 0.8 * s / run.r;
            let end = j == 0 || j == m;
            let fits = |n: u32| {
                let ring = (PI / n as f64).cos();
                let lat = if end { (FRAC_PI_2 / latitudes(n) as f64 / 2.0).cos() } else { 1.0 };
                ring * c >= want && ring * lat >= want
            };
            // The sagitta goes as 1/n²: start from that estimate.
            let mut n = ((PI * PI * run.r / (1.6 * s)).sqrt() as u32).clamp(4, MAX_RING);
            while n > 4 && fits(n - 1) {
                n -= 1;
            }
            while n < MAX_RING && !fits(n) {
                n += 1;
            }
            n
        })
        .collect()
}

/// A node ring's angles (radians, ascending in `[0, 2π)`): `n` uniform ones, graded finer
/// about each `focus` direction (projected on the ring's frame `f1`, `f2`). Where two tubes
/// separate at a grazing angle, the exterior is a narrow notch; a polygon of sagitta `s`
/// there leaves a slit in the union `√(2·r·s)` deep, and where the crease meets the ring at
/// angle `φ` from the notch, about `s/φ` deep (its walls meet at an angle `2φ`). So the
/// spacing is `fine` at the notch (sagitta `r·fine²/8`, a slit `r·fine/2` deep) and grows as
/// `2·√(tol·φ)` (sagitta `tol·φ/2`) until it reaches the uniform spacing (`fine` and `tol`
/// relative to `r`). The body's sagitta is measured on its triangles whatever the angles.
fn graded(n: u32, focus: &[Focus], f1: P, f2: P, fine: f64, tol: f64) -> Vec<f64> {
    let base = 2.0 * PI / n as f64;
    let mut out = Vec::new();
    let mut spans: Vec<(f64, f64)> = Vec::new();
    for f in focus {
        let (x, y) = (f.dir.dot(f1), f.dir.dot(f2));
        // A direction mostly along the axis names no angle of this ring.
        if x.hypot(y) < 0.5 {
            continue;
        }
        let a = y.atan2(x);
        out.push(a);
        let mut phi = 0.0;
        loop {
            let step = fine.max(2.0 * (tol * phi).sqrt());
            if step >= base || phi + step >= PI {
                break;
            }
            phi += step;
            out.extend([a + phi, a - phi]);
        }
        spans.push((a, phi));
    }
    let off = |t: f64, a: f64| {
        let d = (t - a).rem_euclid(2.0 * PI);
        d.min(2.0 * PI - d)
    };
    out.extend((0..n).map(|i| base * i as f64).filter(|&t| spans.iter().all(|&(a, w)| off(t, a) >= w)));
    let mut out: Vec<f64> = out.into_iter().map(|t| t.rem_euclid(2.0 * PI)).collect();
    out.sort_by(f64::total_cmp);
    // Angles closer than a quarter of the finest spacing add nothing but slivers.
    let close = 0.25 * fine.min(base);
    out.dedup_by(|b, a| *b - *a < close);
    while out.len() > 3 && out[0] + 2.0 * PI - out[out.len() - 1] < close {
        out.pop();
    }
    out
}

/// Latitude bands of a half-sphere cap for rings of `n`.
fn latitudes(n: u32) -> u32 {
    n.div_ceil(2).max(2)
}

/// Meshes a run with ring sizes `sizes` (per node). `Err(j)`: the bodies of two links that
/// are not neighbours may overlap (the run turns back on itself); cut the run at its node `j`.
pub(super) fn body(run: &Run, centres: &[P], sizes: &[u32], grading: Grading, eps: f64) -> Result<Body, usize> {
    let Grading { focus, stations, wedge } = grading;
    let r = run.r;
    let pts: Vec<P> = run.nodes.iter().map(|&i| centres[i]).collect();
    let m = pts.len() - 1;
    let dirs: Vec<P> = pts.windows(2).map(|w| unit(w[1] - w[0])).collect();
    let mut positions: Vec<P> = Vec::new();
    // Rings in order along the run (`Rings`): ring vertex i of size n sits at angle 2πi/n in
    // a frame carried along the run by each joint's rotation, so rings of equal size line up.
    let mut rr = Rings::default();
    let uniform = |n: u32| (0..n).map(|i| 2.0 * PI * i as f64 / n as f64).collect::<Vec<f64>>();
    let node_angles = |j: usize, f1: P, f2: P| graded(sizes[j], &focus[run.nodes[j]], f1, f2, eps / r, eps / r);
    let d0 = dirs[0];
    let mut e1 = perpendicular(d0);
    let lat = |n: u32| -> Vec<f64> {
        let k = latitudes(n);
        (1..k).map(|j| FRAC_PI_2 * j as f64 / k as f64).collect()
    };
    // Start cap: its pole, then its latitudes towards the equator (ring of node 0).
    let (lat0, lat1) = (lat(sizes[0]), lat(sizes[m]));
    positions.push(pts[0] - d0 * r);
    let e2 = d0.cross(e1);
    // A latitude ring of radius r·cos φ dips r·cos²φ·(1 − cos(π/n)) below the sphere between
    // its vertices: n·cos φ vertices keep the equator's dip.
    let cap_size = |n: u32, phi: f64| ((n as f64 * phi.cos()).ceil() as u32).max(3);
    for &phi in lat0.iter().rev() {
        rr.add(pts[0] - d0 * (r * phi.sin()), r * phi.cos(), e1, e2, uniform(cap_size(sizes[0], phi)), &mut positions);
    }
    // The node rings: the equator at each end, the mitre (bisecting plane) in between; and
    // within a link, a ring across its axis at each of its stations (the link's forks with
    // a grazing tube). A mitre ring lies inside the link's cylinder by up to
    // `r·(1 − cos(θ/2))`; where two tubes part, any such gap opens a slit about
    // `√(r·gap)` deep, so the fork's ring is exact: every vertex on the cylinder.
    let mut normals = vec![d0];
    // The run's mitres that a wedge would change.
    let mut mitres: Vec<usize> = Vec::new();
    // Per node, the index of its ring; per ring after node 0's, the link of the band that
    // ends at it.
    let mut node_ring = Vec::with_capacity(m + 1);
    let mut band_link: Vec<usize> = Vec::new();
    node_ring.push(rr.idx.len());
    rr.add(pts[0], r, e1, e2, node_angles(0, e1, e2), &mut positions);
    // The tangent of each node's half-bend: its mitre ring reaches `r·tan(θ/2)` along either
    // link (the inner side's ellipse).
    let half_tan: Vec<f64> = (0..=m)
        .map(|j| {
            if j == 0 || j == m {
                return 0.0;
            }
            let (c, s) = half(dirs[j - 1], dirs[j]);
            s / c
        })
        .collect();
    // Link l's station rings, in frame `f1` across its axis.
    let station_rings = |l: usize, f1: P, rr: &mut Rings, positions: &mut Vec<P>, band_link: &mut Vec<usize>| {
        let (a, d, len) = (pts[l], dirs[l], (pts[l + 1] - pts[l]).length());
        // A station stays clear of both node rings (a band between rings that cross would
        // fold the body), by a hundredth of the radius more (nearer, it adds only slivers).
        let gap = 0.01 * r / len;
        let (lo, hi) = (gap + r * half_tan[l] / len, 1.0 - gap - r * half_tan[l + 1] / len);
        let mut at: Vec<f64> = stations[run.links[l] as usize]
            .iter()
            .map(|&x| (x - a).dot(d) / len)
            .filter(|&s| lo <= s && s <= hi)
            .collect();
        if at.is_empty() {
            return;
        }
        at.sort_by(f64::total_cmp);
        at.dedup_by(|b, a| *b - *a < gap);
        let f2 = d.cross(f1);
        let n = sizes[l].max(sizes[l + 1]);
        // The link's own foci (its two rings carry the same ones).
        let link = run.links[l];
        let here: Vec<Focus> = focus[run.nodes[l]].iter().filter(|f| f.link == link).copied().collect();
        // Every station of the link is graded alike (its frame and foci are the link's).
        let angles = graded(n, &here, f1, f2, eps / r, eps / r);
        for s in at {
            rr.add(a + d * (len * s), r, f1, f2, angles.clone(), positions);
            band_link.push(l);
        }
    };
    for j in 1..m {
        let (a, b) = (dirs[j - 1], dirs[j]);
        station_rings(j - 1, e1, &mut rr, &mut positions, &mut band_link);
        let axis = a.cross(b);
        let theta = axis.length().atan2(a.dot(b));
        let rot = |v: P, t: f64| {
            if axis.length() == 0.0 {
                return v;
            }
            let k = unit(axis);
            v * t.cos() + k.cross(v) * t.sin() + k * (k.dot(v) * (1.0 - t.cos()))
        };
        let u = unit(a + b);
        let h = unit(rot(e1, theta / 2.0));
        let h = unit(h - u * h.dot(u));
        // On the inner side of the bend (`v·a < 0`) the two links' cylinders meet in the
        // bisecting plane on an ellipse, `r/√(1 − (v·a)²)` from the node, within both links:
        // the ring lies there, on both cylinders, with no gap where a tube parts. On the outer
        // side the cylinders end before the plane, and the ring lies on the node's ball.
        let mitre = |v: P| {
            let k = v.dot(a);
            if k < 0.0 {
                r / (1.0 - k * k).sqrt()
            } else {
                r
            }
        };
        let angles = node_angles(j, h, u.cross(h));
        // A flagged mitre's outer half spans its ball's wedge by `steps` rings on either side
        // (below), each within `fine/2` of the next in angle (up to `MAX_WEDGE` a side): the
        // wedge's chords then dip `r·fine²/32` below the ball, where the mitre's one ring
        // leaves `r·(1 − cos(θ/2))`.
        let fine = eps / r;
        let wedgeable = theta > 0.5 * fine;
        let steps = if wedge[run.nodes[j]] && wedgeable { ((theta / fine).ceil() as usize).min(MAX_WEDGE) } else { 0 };
        // The mitre ring, and a wedge's `steps` rings on either side of it (none unless
        // flagged): they share its inner half (where the two cylinders meet, the rings
        // coincide: their bands there have no triangles) and put its outer half on the ball,
        // in planes through the node turning from the first link's normal `a` to the
        // second's `b`: exact on the ball, and at `a` and `b` exact on each link's cylinder.
        let dirs = directions(h, u.cross(h), &angles);
        let mid = Rings::place(pts[j], mitre, &dirs, &mut positions);
        for i in 0..=2 * steps {
            band_link.push(if i <= steps { j - 1 } else { j });
            if i == steps {
                node_ring.push(rr.idx.len());
                rr.add_shared(mid.clone(), &angles);
                continue;
            }
            let n = rot(a, theta * i as f64 / (2 * steps) as f64);
            let verts = dirs
                .iter()
                .zip(&mid)
                .map(|(&v, &k)| {
                    if v.dot(a) <= 0.0 {
                        return k;
                    }
                    positions.push(pts[j] + unit(v - n * v.dot(n)) * r);
                    positions.len() as u32 - 1
                })
                .collect();
            rr.add_shared(verts, &angles);
        }
        if wedgeable {
            mitres.push(run.nodes[j]);
        }
        normals.push(u);
        e1 = unit(rot(e1, theta));
        e1 = unit(e1 - b * e1.dot(b));
    }
    let d = dirs[m - 1];
    e1 = unit(e1 - d * e1.dot(d));
    station_rings(m - 1, e1, &mut rr, &mut positions, &mut band_link);
    let e2 = d.cross(e1);
    node_ring.push(rr.idx.len());
    band_link.push(m - 1);
    rr.add(pts[m], r, e1, e2, node_angles(m, e1, e2), &mut positions);
    normals.push(d);
    // End cap: its latitudes, then its pole.
    for &phi in &lat1 {
        rr.add(pts[m] + d * (r * phi.sin()), r * phi.cos(), e1, e2, uniform(cap_size(sizes[m], phi)), &mut positions);
    }
    positions.push(pts[m] + d * r);
    let Rings { idx: rings, turns } = rr;
    let nl = lat0.len();
    // The link of band b (ring b to b + 1), if it lies between node rings (not a cap's).
    let link_band = |b: usize| (b >= nl && b < node_ring[m]).then(|| band_link[b - nl]);

    // Bands: band b joins ring b and b + 1; start cap bands come first, then one per link,
    // then the end cap's. Rings of different sizes are zipped by angle.
    let mut triangles: Vec<[u32; 3]> = Vec::new();
    let mut band_of: Vec<usize> = Vec::new();
    const START_FAN: usize = usize::MAX;
    const END_FAN: usize = usize::MAX - 1;
    let r0 = &rings[0];
    for i in 0..r0.len() {
        triangles.push([0, r0[(i + 1) % r0.len()], r0[i]]);
        band_of.push(START_FAN);
    }
    for b in 0..rings.len() - 1 {
        let (ra, rb) = (&rings[b], &rings[b + 1]);
        let (na, nb) = (ra.len(), rb.len());
        let va = |i: usize| ra[i % na];
        let vb = |i: usize| rb[i % nb];
        let (ta, tb) = (&turns[b], &turns[b + 1]);
        let next = |t: &[f64], i: usize| if i + 1 < t.len() { t[i + 1] } else { t[0] + 1.0 };
        let (mut i, mut k) = (0, 0);
        while i < na || k < nb {
            // Advance the ring whose next vertex comes first in angle (ties: the lower ring
            // when its next quad diagonal is the shorter).
            let next_a = next(ta, i);
            let next_b = next(tb, k);
            let step_a = if i == na {
                false
            } else if k == nb || next_a < next_b {
                true
            } else if next_b < next_a {
                false
            } else {
                let dist = |x: u32, y: u32| (positions[x as usize] - positions[y as usize]).length2();
                dist(va(i + 1), vb(k)) <= dist(va(i), vb(k + 1))
            };
            let t = if step_a {
                i += 1;
                [va(i - 1), va(i), vb(k)]
            } else {
                k += 1;
                [va(i), vb(k), vb(k - 1)]
            };
            // Rings that share a vertex (a wedge's, on the inner half) leave no triangle there.
            if t[0] != t[1] && t[1] != t[2] && t[2] != t[0] {
                triangles.push(t);
                band_of.push(b);
            }
        }
    }
    let last = positions.len() as u32 - 1;
    let rl = rings.last().expect("a run has rings");
    for i in 0..rl.len() {
        triangles.push([last, rl[i], rl[(i + 1) % rl.len()]]);
        band_of.push(END_FAN);
    }
    // Which link each triangle stands for.
    let link_of = |b: usize| -> usize {
        match b {
            START_FAN => 0,
            END_FAN => m - 1,
            b if b < nl => 0,
            b => link_band(b).unwrap_or(m - 1),
        }
    };
    let tags: Vec<u32> = band_of.iter().map(|&b| run.links[link_of(b)]).collect();
    // Outward: the enclosed volume is positive.
    let vol: f64 = triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| positions[i as usize] - pts[0]);
            a.dot(b.cross(c))
        })
        .sum();
    if vol < 0.0 {
        triangles.iter_mut().for_each(|t| t.swap(1, 2));
    }

    // Bodies of links that are not neighbours must be apart: a plane at a node ring between
    // them separates them, or the run is cut.
    let body_verts = |l: usize| -> Vec<usize> {
        let lo = if l == 0 { 0 } else { node_ring[l] };
        let hi = if l + 1 == m { rings.len() - 1 } else { node_ring[l + 1] };
        let mut v: Vec<usize> = rings[lo..=hi].iter().flatten().map(|&k| k as usize).collect();
        if l == 0 {
            v.push(0);
        }
        if l + 1 == m {
            v.push(positions.len() - 1);
        }
        v
    };
    if m >= 3 {
        let boxes: Vec<(P, P)> = (0..m)
            .map(|l| {
                let (a, b) = (pts[l], pts[l + 1]);
                let lo = V3::new(a.x.min(b.x), a.y.min(b.y), a.z.min(b.z));
                let hi = V3::new(a.x.max(b.x), a.y.max(b.y), a.z.max(b.z));
                (lo - V3::new(r, r, r) * 1.001, hi + V3::new(r, r, r) * 1.001)
            })
            .collect();
        let cell = boxes.iter().map(|(a, b)| (*b - *a).max_abs()).fold(0.0, f64::max);
        let key = |p: P| [p.x, p.y, p.z].map(|x| (x / cell).floor() as i64);
        let mut grid: HashMap<[i64; 3], Vec<usize>> = HashMap::new();
        for (l, (lo, hi)) in boxes.iter().enumerate() {
            let (a, b) = (key(*lo), key(*hi));
            for x in a[0]..=b[0] {
                for y in a[1]..=b[1] {
                    for z in a[2]..=b[2] {
                        grid.entry([x, y, z]).or_default().push(l);
                    }
                }
            }
        }
        let overlap = |a: &(P, P), b: &(P, P)| {
            a.0.x <= b.1.x && b.0.x <= a.1.x && a.0.y <= b.1.y && b.0.y <= a.1.y && a.0.z <= b.1.z && b.0.z <= a.1.z
        };
        let side = |node: usize, v: &[usize]| {
            let (c, u) = (pts[node], normals[node]);
            v.iter()
                .map(|&i| u.dot(positions[i] - c))
                .fold((f64::INFINITY, f64::NEG_INFINITY), |m, x| (m.0.min(x), m.1.max(x)))
        };
        for cellv in grid.values() {
            for (x, &l) in cellv.iter().enumerate() {
                for &q in &cellv[x + 1..] {
                    let (l, q) = (l.min(q), l.max(q));
                    if q < l + 2 || !overlap(&boxes[l], &boxes[q]) {
                        continue;
                    }
                    // Link l's body is behind the plane of its far ring (node l + 1), q's is
                    // beyond the plane of its near ring (node q).
                    let tol = 1e-12 * (r + pts[l].max_abs());
                    if !(side(l + 1, &body_verts(q)).0 > tol || side(q, &body_verts(l)).1 < -tol) {
                        return Err(l + 1);
                    }
                }
            }
        }
    }

    // The certificate: R, the radius of the shrunk round cones the body holds. Bands: a line
    // parallel to link l's axis within R of it meets no band triangle of l (their projections
    // along the axis keep R from it), so it runs inside the body from one ring's polygon to
    // the other's. Caps: the half-ball of radius R behind the end ring's plane meets no cap
    // triangle.
    let mut big_r = f64::INFINITY;
    for (t, &b) in triangles.iter().zip(&band_of) {
        let corners = t.map(|i| positions[i as usize]);
        let band = if b == START_FAN || b == END_FAN { None } else { link_band(b) };
        let d = if let Some(l) = band {
            let (o, d) = (pts[l], dirs[l]);
            let g1 = perpendicular(d);
            let g2 = d.cross(g1);
            dist_2d_triangle(corners.map(|v| [(v - o).dot(g1), (v - o).dot(g2)]))
        } else {
            let end = if b == START_FAN || b < nl { 0 } else { m };
            dist_point_triangle(pts[end], corners[0], corners[1], corners[2])
        };
        big_r = big_r.min(d);
    }
    let extent = pts.iter().map(|p| p.max_abs()).fold(0.0, f64::max) + r;
    let sagitta = (r - big_r).max(0.0) + 16.0 * f64::EPSILON * extent;
    let ring = rings[nl..=node_ring[m]].iter().map(|r| r.len() as u32).max().unwrap_or(0);
    Ok(Body { positions, triangles, tags, ring, sagitta, mitres })
}

/// A body's rings in order along the run: per ring its vertices, and their angles in turns
/// (ascending in `[0, 1)`). Angles are taken in a frame carried along the run by each
/// joint's rotation (parallel transport), so that rings line up.
#[derive(Default)]
struct Rings {
    idx: Vec<Vec<u32>>,
    turns: Vec<Vec<f64>>,
}

impl Rings {
    /// A ring of radius `rad` about `c` in the plane of `f1`, `f2`, at `angles` (radians).
    fn add(&mut self, c: P, rad: f64, f1: P, f2: P, angles: Vec<f64>, positions: &mut Vec<P>) {
        self.add_with(c, |_| rad, f1, f2, angles, positions);
    }

    /// A ring about `c` in the plane of `f1`, `f2`, at `angles`, each vertex at the distance
    /// `rad(v)` along its unit direction `v`.
    fn add_with(&mut self, c: P, rad: impl Fn(P) -> f64, f1: P, f2: P, angles: Vec<f64>, positions: &mut Vec<P>) {
        let verts = Self::place(c, rad, &directions(f1, f2, &angles), positions);
        self.add_shared(verts, &angles);
    }

    /// New vertices about `c`, one along each unit direction `v` of `dirs` at the distance
    /// `rad(v)`: their indices.
    fn place(c: P, rad: impl Fn(P) -> f64, dirs: &[P], positions: &mut Vec<P>) -> Vec<u32> {
        let first = positions.len() as u32;
        positions.extend(dirs.iter().map(|&v| c + v * rad(v)));
        (first..positions.len() as u32).collect()
    }

    /// A ring of existing vertices `verts` at `angles` (radians).
    fn add_shared(&mut self, verts: Vec<u32>, angles: &[f64]) {
        self.idx.push(verts);
        self.turns.push(angles.iter().map(|a| a / (2.0 * PI)).collect());
    }
}

/// The unit directions at `angles` (radians) in the plane of the orthonormal `f1`, `f2`.
fn directions(f1: P, f2: P, angles: &[f64]) -> Vec<P> {
    angles
        .iter()
        .map(|a| {
            let (sa, ca) = a.sin_cos();
            f1 * ca + f2 * sa
        })
        .collect()
}

/// Distance from the origin to a filled 2-D triangle.
fn dist_2d_triangle(q: [[f64; 2]; 3]) -> f64 {
    let cross = |a: [f64; 2], b: [f64; 2]| a[0] * b[1] - a[1] * b[0];
    let s: Vec<f64> = (0..3).map(|i| cross(q[i], q[(i + 1) % 3])).collect();
    if (s[0] >= 0.0 && s[1] >= 0.0 && s[2] >= 0.0) || (s[0] <= 0.0 && s[1] <= 0.0 && s[2] <= 0.0) {
        return 0.0;
    }
    (0..3)
        .map(|i| {
            let (a, b) = (q[i], q[(i + 1) % 3]);
            let ab = [b[0] - a[0], b[1] - a[1]];
            let l2 = ab[0] * ab[0] + ab[1] * ab[1];
            let t = if l2 > 0.0 { (-(a[0] * ab[0] + a[1] * ab[1]) / l2).clamp(0.0, 1.0) } else { 0.0 };
            let p = [a[0] + t * ab[0], a[1] + t * ab[1]];
            p[0].hypot(p[1])
        })
        .fold(f64::INFINITY, f64::min)
}

/// Distance from `p` to the filled triangle `abc`.
fn dist_point_triangle(p: P, a: P, b: P, c: P) -> f64 {
    let n = (b - a).cross(c - a);
    let nn = n.length2();
    let seg = |a: P, b: P| {
        let ab = b - a;
        let l2 = ab.length2();
        let t = if l2 > 0.0 { ((p - a).dot(ab) / l2).clamp(0.0, 1.0) } else { 0.0 };
        (p - (a + ab * t)).length()
    };
    let edges = seg(a, b).min(seg(b, c)).min(seg(c, a));
    if nn == 0.0 {
        return edges;
    }
    let inside = [(a, b), (b, c), (c, a)].iter().all(|&(x, y)| (y - x).cross(p - x).dot(n) >= 0.0);
    if inside {
        (p - a).dot(n).abs() / nn.sqrt()
    } else {
        edges
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The exit distance from `o` along the unit `d` through the body's triangles (the
    /// farthest crossing, inclusive of edges to rounding), or `None` where no triangle is met.
    fn exit(b: &Body, o: P, d: P) -> Option<f64> {
        let mut far: Option<f64> = None;
        for t in &b.triangles {
            let [p, q, s] = t.map(|i| b.positions[i as usize]);
            let (e1, e2) = (q - p, s - p);
            let h = d.cross(e2);
            let det = e1.dot(h);
            if det.abs() < 1e-300 {
                continue;
            }
            let w = o - p;
            let u = w.dot(h) / det;
            let k = w.cross(e1);
            let v = d.dot(k) / det;
            let tol = 1e-9;
            if u < -tol || v < -tol || u + v > 1.0 + tol {
                continue;
            }
            let t = e2.dot(k) / det;
            if t > 0.0 {
                far = Some(far.map_or(t, |f: f64| f.max(t)));
            }
        }
        far
    }

    /// Each undirected edge in exactly two triangles, once each way (closed, oriented), and no
    /// triangle with a repeated vertex.
    fn closed(b: &Body) -> bool {
        let mut edges: HashMap<(u32, u32), i32> = HashMap::new();
        for t in &b.triangles {
            if t[0] == t[1] || t[1] == t[2] || t[2] == t[0] {
                return false;
            }
            for e in 0..3 {
                let (x, y) = (t[e], t[(e + 1) % 3]);
                *edges.entry((x.min(y), x.max(y))).or_default() += if x < y { 1 } else { -1 };
            }
        }
        let mut count: HashMap<(u32, u32), usize> = HashMap::new();
        for t in &b.triangles {
            for e in 0..3 {
                let (x, y) = (t[e], t[(e + 1) % 3]);
                *count.entry((x.min(y), x.max(y))).or_default() += 1;
            }
        }
        edges.values().all(|&s| s == 0) && count.values().all(|&c| c == 2)
    }

    /// A run of two links of length 2 and radius `r` bending by `θ` at its middle node, in the
    /// xy-plane, its rings graded about the bend's outer side (so that a ring vertex lies in
    /// the bend's plane there), with or without the wedge at the bend.
    fn bent(theta: f64, r: f64, eps: f64, wedge: bool) -> Body {
        let centres =
            [V3::new(-2.0, 0.0, 0.0), V3::new(0.0, 0.0, 0.0), V3::new(2.0 * theta.cos(), 2.0 * theta.sin(), 0.0)];
        let run = Run { nodes: vec![0, 1, 2], links: vec![0, 1], r };
        let target = [0.7 * eps; 3];
        let sizes = ring_sizes(&run, &centres, &target);
        // The outer side is -y: across both links' axes, in the bend's plane.
        let outer = [V3::new(0.0, -1.0, 0.0), V3::new(theta.sin(), -theta.cos(), 0.0)];
        let focus: Vec<Vec<Focus>> = (0..3)
            .map(|j: usize| {
                let links: &[u32] = [&[0u32][..], &[0, 1], &[1]][j];
                links.iter().map(|&l| Focus { dir: outer[l as usize], key: 9, link: l }).collect()
            })
            .collect();
        let grading = Grading { focus: &focus, stations: &[vec![], vec![]], wedge: &[false, wedge, false] };
        body(&run, &centres, &sizes, grading, eps).expect("a body")
    }

    /// A mitre's one ring lies on the node's ball on the bend's outer side, so its bands
    /// there cut inside the links' cylinders by up to `r·(1 − cos(θ/2))`; the wedge's rings
    /// follow the ball. Along the bend's plane on its outer side, between the two links'
    /// normal planes through the node, the union's surface is the ball: the exit distance
    /// from the node is `r`. The wedge's rings lie in planes at most `fine/2` apart in angle
    /// (`fine = ε/r`), and each has a vertex in the bend's plane, so its section there is a
    /// polygon inscribed in the circle with chords of at most that angle: it dips at most
    /// `r·(1 − cos(fine/4))` (plus rounding, 10⁻¹²·r here), for bends of up to
    /// `MAX_WEDGE·fine` (these: 12, 2 and 30 rings a side). The mitre alone has, in the
    /// bend's plane, the chord from the first node's ring at `(−L, −r)` to its own vertex
    /// on the ball at `(r·sin(θ/2), −r·cos(θ/2))`: at the first link's normal plane
    /// (`ψ = 0`) it dips `r·(1 − cos(θ/2))·L/(L + r·sin(θ/2))`.
    #[test]
    fn a_wedge_follows_the_ball_on_the_bend_outer_side() {
        for (theta, r, eps) in [(0.1f64, 0.12, 1e-3), (0.0115, 0.12, 1.2e-3), (0.3, 1.0, 1e-2)] {
            let fine = eps / r;
            let plain = bent(theta, r, eps, false);
            let wedged = bent(theta, r, eps, true);
            assert!(closed(&plain) && closed(&wedged), "θ {theta}");
            let depth =
                |b: &Body, psi: f64| r - exit(b, V3::new(0.0, 0.0, 0.0), V3::new(psi.sin(), -psi.cos(), 0.0)).unwrap();
            let limit = r * (1.0 - (fine / 4.0).cos()) + 1e-12 * r;
            let mut worst = f64::NEG_INFINITY;
            for i in 0..=400 {
                let psi = theta * i as f64 / 400.0;
                let d = depth(&wedged, psi);
                // Inscribed: never outside the ball (rounding aside).
                assert!(d >= -1e-12 * r && d <= limit, "θ {theta}, ψ {psi}: depth {d} against {limit}");
                worst = worst.max(d);
            }
            let mitre = depth(&plain, 0.0);
            let expect = r * (1.0 - (theta / 2.0).cos()) * 2.0 / (2.0 + r * (theta / 2.0).sin());
            // Rounding: a few ulps of r in each coordinate, 10⁻⁹ of the dip at the least.
            assert!((mitre - expect).abs() <= 1e-9 * expect + 1e-13 * r, "θ {theta}: {mitre} against {expect}");
            assert!(worst < 0.1 * mitre, "θ {theta}: {worst} against the mitre's {mitre}");
            // The wedge adds triangles on the outer half only: about n per ring pair.
            assert!(wedged.triangles.len() > plain.triangles.len());
        }
    }
}
