//! Automatic primitive choice: given a tolerance (absolute, or pixels of the camera's
//! footprint), each chain is modelled by the cheapest primitives whose certified error is
//! within it — runs of links merged into one round cone ([`super::simplify::merge_bound`]),
//! then each link as a **sphere** when its larger end ball is within the remaining budget
//! (`d_H = max(0, L + r_small − r_big)`: the far side of the small ball), a **cylinder** when
//! equal radii are (`d_H = |r_a − r_b|/2`: every ball's radius moves by that much), else a
//! **cone** (exact). Errors add (triangle inequality of the Hausdorff distance).
//! [`choose_with`] with `splines = true` also tries one **quadratic spline** piece per run
//! ([`super::fit::fit_quad`], certified bound in [`super::fit`]): at each chain position the
//! longest run one merged link covers and the longest run one quadratic covers are compared,
//! and the one covering more links wins (a tie keeps the link, the cheaper kernel); a single
//! link is always kept as a link (exact). The default model stays exact; this is only used
//! when a tolerance is given.

use super::fit::{fit_quad, QuadFit};
use super::simplify::merge_bound;
use super::{Prim, Scene};
use tubecast::{QuadTube, RoundCone, V3};

/// Longest run (in links) one quadratic piece may replace: bounds the fitting cost
/// (`O(k²)` per run) on long, nearly straight chains, which merged links cover anyway.
pub(crate) const MAX_FIT_LINKS: usize = 128;

/// How large an error each segment may have.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Tolerance {
    /// The same absolute error everywhere (scene units).
    Absolute(f64),
    /// `pixels` times the footprint of one pixel at the segment's nearest distance from the
    /// eye: `2·d·tan(fov/2)/height` (0, hence exact, for a segment around the eye).
    Pixels {
        /// Eye position.
        eye: [f64; 3],
        /// Vertical field of view, degrees.
        fov_deg: f64,
        /// Image height in pixels.
        height: u32,
        /// Allowed error in pixels.
        pixels: f64,
    },
}

impl Tolerance {
    /// The allowed error for a segment with bounding box `lo..hi`.
    pub fn at(&self, lo: [f64; 3], hi: [f64; 3]) -> f64 {
        match *self {
            Self::Absolute(e) => e.max(0.0),
            Self::Pixels { eye, fov_deg, height, pixels } => {
                let d2: f64 = (0..3).map(|i| (eye[i] - eye[i].clamp(lo[i], hi[i])).powi(2)).sum();
                let foot = 2.0 * d2.sqrt() * (0.5 * fov_deg.to_radians()).tan() / height.max(1) as f64;
                (pixels * foot).max(0.0)
            }
        }
    }
}

/// What [`choose`] picked.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Choice {
    /// The primitives (each names the first scene link of its run).
    pub prims: Vec<Prim>,
    /// The link primitives (spheres, cylinders, cones; not the spline pieces) as `f64` links,
    /// in the order of `prims` (a sphere: both ends equal).
    pub links: Vec<RoundCone<f64>>,
    /// The spline pieces as `f64` quadratics, in the order of `prims`.
    pub quads: Vec<QuadTube<f64>>,
    /// Primitives that are spheres, cylinders, cones.
    pub spheres: usize,
    /// Cylinders.
    pub cylinders: usize,
    /// Cones.
    pub cones: usize,
    /// Links merged into a longer link (each run of `k` links counts `k − 1`).
    pub merged: usize,
    /// Quadratic spline pieces (each replaces a run of at least two links).
    pub splines: usize,
    /// Links replaced by spline pieces (each run of `k` links counts `k − 1`), so that
    /// `prims.len() + merged + fitted` is the scene's link count.
    pub fitted: usize,
    /// The largest certified error of any primitive (scene units).
    pub worst: f64,
}

fn link_box(l: &RoundCone<f64>) -> ([f64; 3], [f64; 3]) {
    let r = l.ra.max(l.rb);
    let (a, b) = (l.a.to_array(), l.b.to_array());
    (std::array::from_fn(|i| a[i].min(b[i]) - r), std::array::from_fn(|i| a[i].max(b[i]) + r))
}

/// One merged link: the cheapest shape within `budget`, its error, and the primitive.
fn shape(a: ([f64; 3], f64), b: ([f64; 3], f64), budget: f64, link: u32, c: &mut Choice) -> f64 {
    let (pa, pb) = (V3::from(a.0), V3::from(b.0));
    let l = (pb - pa).length();
    let (big, small) = if a.1 >= b.1 { ((pa, a.1), b.1) } else { ((pb, b.1), a.1) };
    let to_sphere = (l + small - big.1).max(0.0);
    let (cone, err) = if to_sphere <= budget {
        c.spheres += 1;
        (RoundCone { a: big.0, ra: big.1, b: big.0, rb: big.1 }, to_sphere)
    } else if (a.1 - b.1).abs() * 0.5 <= budget {
        c.cylinders += 1;
        let r = 0.5 * (a.1 + b.1);
        (RoundCone { a: pa, ra: r, b: pb, rb: r }, (a.1 - b.1).abs() * 0.5)
    } else {
        c.cones += 1;
        (RoundCone { a: pa, ra: a.1, b: pb, rb: b.1 }, 0.0)
    };
    c.prims.push(Prim::from_link(&cone, link));
    c.links.push(cone);
    err
}

/// Picks the primitives of `scene` within `tol` from links only: spheres, cylinders, cones
/// and merged links (see the module docs); the same as [`choose_with`]`(scene, tol, false)`.
///
/// ```
/// use tubecast_render::io::Polyline;
/// use tubecast_render::scene::choice::{choose, Tolerance};
/// use tubecast_render::scene::Scene;
/// let pts: Vec<[f64; 3]> = (0..11).map(|i| [i as f64, 0.001 * (i % 2) as f64, 0.0]).collect();
/// let scene = Scene::from_polylines(&[Polyline { points: pts, radii: vec![] }], 0.5, "x").unwrap();
/// let c = choose(&scene, &Tolerance::Absolute(0.01));
/// assert_eq!((c.prims.len(), c.merged, c.cylinders), (1, 9, 1));
/// assert!(c.worst <= 0.01);
/// ```
pub fn choose(scene: &Scene, tol: &Tolerance) -> Choice {
    choose_with(scene, tol, false)
}

/// The longest quadratic fit from node `a` within the per-link budgets `eps`: its last node,
/// the fit and the budget it met. `None` when no run of two or more links fits.
fn quad_reach(nodes: &[([f64; 3], f64)], eps: &[f64], a: usize) -> Option<(usize, QuadFit, f64)> {
    let (mut best, mut e) = (None, eps[a]);
    for b in a + 2..=(a + MAX_FIT_LINKS).min(eps.len()) {
        e = e.min(eps[b - 1]);
        match fit_quad(&nodes[a..=b]) {
            Some(f) if f.bound <= e => best = Some((b, f, e)),
            _ => break,
        }
    }
    best
}

/// Picks the primitives of `scene` within `tol` (see the module docs); with `splines`, runs of
/// links may become one quadratic spline piece ([`super::PrimKind::Spline`]).
///
/// ```
/// use tubecast_render::io::Polyline;
/// use tubecast_render::scene::choice::{choose_with, Tolerance};
/// use tubecast_render::scene::Scene;
/// // A quarter circle of radius 10 sampled by 32 links: a handful of quadratics at 1e-2.
/// let pts: Vec<[f64; 3]> = (0..=32)
///     .map(|i| { let a = i as f64 / 32.0 * std::f64::consts::FRAC_PI_2; [10.0 * a.cos(), 10.0 * a.sin(), 0.0] })
///     .collect();
/// let scene = Scene::from_polylines(&[Polyline { points: pts, radii: vec![] }], 0.5, "arc").unwrap();
/// let c = choose_with(&scene, &Tolerance::Absolute(0.01), true);
/// assert!(c.splines >= 1 && c.prims.len() < 8 && c.worst <= 0.01);
/// assert_eq!(c.prims.len() + c.merged + c.fitted, 32);
/// ```
pub fn choose_with(scene: &Scene, tol: &Tolerance, splines: bool) -> Choice {
    let mut c = Choice::default();
    for chain in scene.chains() {
        let nodes: Vec<([f64; 3], f64)> =
            chain.nodes.iter().map(|&n| (scene.nodes[n as usize].pos, scene.radius(n as usize))).collect();
        let eps: Vec<f64> = chain
            .links
            .iter()
            .map(|&k| {
                let (lo, hi) = link_box(&scene.link(k as usize));
                tol.at(lo, hi)
            })
            .collect();
        let mut a = 0;
        while a < chain.links.len() {
            let (mut b, mut d_b, mut e_b) = (a + 1, 0.0, eps[a]);
            while b < chain.links.len() {
                let e = e_b.min(eps[b]);
                let d = merge_bound(&nodes[a..=b + 1]);
                if d > e {
                    break;
                }
                (b, d_b, e_b) = (b + 1, d, e);
            }
            let quad = if splines { quad_reach(&nodes, &eps, a) } else { None };
            if let Some((bq, f, _)) = quad.filter(|q| q.0 > b) {
                if let Ok(p) = Prim::from_quad(&f.quad, chain.links[a], 0) {
                    (c.splines, c.fitted, c.worst) = (c.splines + 1, c.fitted + bq - a - 1, c.worst.max(f.bound));
                    c.prims.push(p);
                    c.quads.push(f.quad);
                    a = bq;
                    continue;
                }
            }
            c.merged += b - a - 1;
            let err = d_b + shape(nodes[a], nodes[b], e_b - d_b, chain.links[a], &mut c);
            c.worst = c.worst.max(err);
            a = b;
        }
    }
    c
}
