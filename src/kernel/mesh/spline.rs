//! Samples of a run of quadratic sweeps for the chain mesher: uniform in `t` per segment so
//! that the axial term `h²/4·(|b₀ − 2b₁ + b₂| + |r₀ − 2r₁ + r₂|)` is within ε/4, then halved
//! where a joint would fold deeper than ε/4 (each halving roughly halves the bend `φ` and the
//! change of half-angle at the joints it touches, so the fold `r(1 − cos ψ)` drops ~4×).

use super::rings::{fold, Piece};
use crate::error::GeometryError;
use crate::kernel::spline::QuadTube;
use crate::vec::V3;

/// Most samples a run may get.
const MAX_SAMPLES: usize = 1 << 20;
/// Most halving passes for folds.
const PASSES: usize = 16;

/// `|b₀ − 2b₁ + b₂| + |r₀ − 2r₁ + r₂|`: the second differences that bound the axial term.
fn curvature(q: &QuadTube<f64>) -> f64 {
    (q.b[0] - q.b[1].scale(2.0) + q.b[2]).length() + (q.r[0] - 2.0 * q.r[1] + q.r[2]).abs()
}

fn at(q: &QuadTube<f64>, t: f64) -> (V3<f64>, f64) {
    let w = [(1.0 - t) * (1.0 - t), 2.0 * t * (1.0 - t), t * t];
    let p = q.b[0].scale(w[0]) + q.b[1].scale(w[1]) + q.b[2].scale(w[2]);
    (p, (q.r[0] * w[0] + q.r[1] * w[1] + q.r[2] * w[2]).max(0.0))
}

/// The samples of a run.
pub struct Samples {
    /// Nodes `(centre, radius)`.
    pub nodes: Vec<(V3<f64>, f64)>,
    /// Per interval between consecutive nodes: the tube it samples.
    pub owner: Vec<u32>,
    /// The axial term reached.
    pub axial: f64,
}

/// The nodes of a run of tubes sharing their end spheres, and the axial term reached.
pub fn samples(tubes: &[QuadTube<f64>], eps: f64) -> Result<Samples, GeometryError> {
    let share = 0.25 * eps;
    let too_many = GeometryError::TooSmall { what: "mesh tolerance relative to the spline's curvature" };
    // Intervals (tube, t₀, t₁) in order along the run.
    let mut iv: Vec<(usize, f64, f64)> = Vec::new();
    for (j, q) in tubes.iter().enumerate() {
        let c = curvature(q);
        let m = if c > 0.0 { (c / (4.0 * share)).sqrt().ceil().max(1.0) } else { 1.0 };
        if m.is_nan() || m > MAX_SAMPLES as f64 {
            return Err(too_many);
        }
        let m = m as usize;
        iv.extend((0..m).map(|i| (j, i as f64 / m as f64, if i + 1 == m { 1.0 } else { (i + 1) as f64 / m as f64 })));
    }
    for _ in 0..PASSES {
        let nodes = nodes_of(tubes, &iv);
        let pieces: Vec<Option<Piece>> = nodes.windows(2).map(|w| Piece::new(w[0], w[1])).collect();
        let mut split = vec![false; iv.len()];
        for k in 1..nodes.len() - 1 {
            if let (Some(p), Some(n)) = (&pieces[k - 1], &pieces[k]) {
                // Halving cures a fold; a zero radius or a bend tighter than the radius (no
                // bound: `fold` is None) stays a split joint, two closed parts, also within ε.
                let bad = fold(p, n, nodes[k].1).is_some_and(|d| d > share);
                if bad {
                    split[k - 1] = true;
                    split[k] = true;
                }
            }
        }
        if !split.contains(&true) || iv.len() * 2 > MAX_SAMPLES {
            break;
        }
        iv = iv
            .iter()
            .zip(&split)
            .flat_map(|(&(j, a, b), &s)| {
                let mid = 0.5 * (a + b);
                if s {
                    vec![(j, a, mid), (j, mid, b)]
                } else {
                    vec![(j, a, b)]
                }
            })
            .collect();
    }
    let axial = iv.iter().map(|&(j, a, b)| (b - a) * (b - a) / 4.0 * curvature(&tubes[j])).fold(0.0, f64::max);
    Ok(Samples { nodes: nodes_of(tubes, &iv), owner: iv.iter().map(|i| i.0 as u32).collect(), axial })
}

fn nodes_of(tubes: &[QuadTube<f64>], iv: &[(usize, f64, f64)]) -> Vec<(V3<f64>, f64)> {
    let mut out: Vec<(V3<f64>, f64)> = iv.iter().map(|&(j, a, _)| at(&tubes[j], a)).collect();
    if let Some(&(j, _, b)) = iv.last() {
        out.push(at(&tubes[j], b));
    }
    out
}
