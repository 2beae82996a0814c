//! The error budget of a tessellation: how a tolerance ε is split between the terms of the
//! two-sided Hausdorff bound, and the ring/arc/segment counts that meet each term.
//!
//! # The bound (derivation)
//! A tube component is meshed as rings of `n` vertices on circles that lie on the exact
//! surface (the tangent circles of each link's cone, and circles on the node spheres), joined
//! by quads, with a pole at each end. Let `K` be the exact solid and `P` the mesh's solid.
//!
//! * **Ring chord** — a regular `n`-gon inscribed in a circle of radius `ρ ≤ R` stays within
//!   `e_ring = R(1 − cos(π/n))` of the circle (the sagitta of a chord of angle `2π/n`).
//! * **Arc (cap, joint, cone/sphere seam)** — along a meridian, consecutive rings on a sphere of
//!   radius `r` are at most `Δ` apart in angle, so the profile polyline stays within
//!   `e_arc = R(1 − cos(Δ/2))` of the arc. The cone between its two tangent circles is a
//!   straight meridian segment, exact: the seam ring is the tangent circle itself, so the seam
//!   adds no term. For one link the mesh is convex and inscribed (a concave piecewise-linear
//!   radius profile times a fixed `n`-gon), so `P ⊂ K` and
//!   `d_H(∂P, ∂K) = max_{y∈∂K} d(y, P) ≤ e_arc + e_ring` (revolve the polyline profile with exact
//!   circles, then replace each circle by its `n`-gon).
//! * **Joint fold** — at an interior node the rings turn from one link's tangent circle to the
//!   next one's over the node sphere. On the inner side of a bend by `φ` (with half-angles
//!   `θ₋`, `θ₊`, `sin θ = (r_a − r_b)/L`, tangent circles at polar angle `π/2 − θ`) the ring goes back by `ψ = φ + θ₋ − θ₊` over the
//!   sphere, into the other link; the deepest such mesh point is `r(1 − cos ψ)` inside the
//!   union (the distance from a point `ψ` along a circle to the tangent line at the start).
//!   It is inside, so it never makes the mesh stick out. Where `e_fold` would exceed its share
//!   the chain is split at that node into two closed components that share the node sphere.
//! * **Joint sweep (full 3-D bound)** — at an interior node `(c, r)` the rings are the circles
//!   `C(s)` of polar angle `α(s) = α₋ + s(α₊ − α₋)` about the axis `w(s) = R(sφ)w₋` (`R` the
//!   rotation about `e = w₋ × w₊/|…|`), `s ∈ [0, 1]`. *Coverage:* a point `x` of the node
//!   sphere on the exact surface lies outside both links' solids, so its angle to `w₋` is
//!   `≤ α₋` and to `w₊` is `≥ α₊`; `f(s) = ∠(x, w(s)) − α(s)` is continuous with `f(0) ≤ 0 ≤ f(1)`,
//!   so `x` lies on some `C(s)`. *Discretisation:* with `σ = s(φ + |Δα|)` and the frame angle
//!   `β`, the swept point is `p(σ, β) = c + r·R(sφ)·Q(α(s), β)` (`Q` the unit vector of polar
//!   angle `α`, azimuth `β` in the joint's first frame) and the mesh vertices are exactly
//!   `p(σᵢ, βⱼ)`, `Δβ = 2π/n`, `Δσ = (φ + |Δα|)/m`. Along a unit parameter direction `ξ`,
//!   `∂²p/∂ξ² = r·R(Ω²Q + 2ΩQ' + Q'')` with `|Ω| = a₁|ξ₁|`, `|Q'| ≤ a₂|ξ₁| + |ξ₂|`,
//!   `|Q''| ≤ (a₂|ξ₁| + |ξ₂|)²` (`|Q_αα| = 1`, `|Q_αβ| = |cos α|`, `|Q_ββ| = sin α`), with
//!   `a₁ + a₂ = 1`, so `|∂²p/∂ξ²| ≤ r(|ξ₁| + |ξ₂|)² ≤ r((1+t)ξ₁² + (1+1/t)ξ₂²)` for any `t > 0`.
//!   On each triangle `T` of the parameter grid (half a `Δσ × Δβ` cell) and any unit `ν`,
//!   `g = (r/2)((1+t)(σ−σᵢ)(σᵢ₊₁−σ) + (1+1/t)(β−βⱼ)(βⱼ₊₁−β))` vanishes at `T`'s corners, so
//!   `ν·(p − Lp) ∓ g` is convex / concave and zero at the corners (`Lp` the triangle), hence
//!   `|p − Lp| ≤ max g = (r/8)((1+t)Δσ² + (1+1/t)Δβ²)`, at `t = Δβ/Δσ`:
//!   `e_joint = (r/8)(Δσ + Δβ)²` (Waldron's argument for linear interpolation). This is exact,
//!   not leading order; it is up to twice the ring + arc terms' leading order, so joints get
//!   their own, finer ring spacing ([`joint_step`]) that keeps `e_joint` within the ring and
//!   arc terms reached at `r_max` (possible: `(r/8)Δβ² − r(1 − cos(π/n)) ≤ r(π/n)⁴/6`, far
//!   below the arc term). Cone strips join points at equal `β` on the two tangent circles:
//!   cone generators, exact, so a strip is within the ring chord. Caps are surfaces of
//!   revolution: arc + ring as above.
//! * **Solid (render) meshes: folded triangles lie inside the exact solid** — every triangle
//!   has its three vertices on one convex piece of the exact solid `K`: cap and joint triangles
//!   on one node sphere (inside that ball), strip triangles on the two tangent circles of one
//!   link (inside that link's round cone, the convex hull of its balls), the pole fans on a
//!   sphere. So the whole mesh lies in `K`, whatever the fold (up to the rounding of the
//!   vertex coordinates), and with the coverage above, every point of the exact surface is
//!   within the certified bound of the mesh. A ray therefore never meets the mesh before it
//!   enters `K`. Not derived: that a ray cannot slip between the mesh and `∂K` into a fold's
//!   pocket deeper than the bound (each pocket is enclosed by mesh sheets; checked by ray
//!   tests, `crates/render/tests/accel/mesh_tracer.rs`).
//! * **Axial (spline tubes)** — a quadratic sweep `(p(t), r(t))` is replaced by the links
//!   between samples `h` apart in `t`; linear interpolation of a quadratic is off by at most
//!   `h²/8·|p''| = h²/4·|b₀ − 2b₁ + b₂|` (likewise `r`), and the signed distance of a union of
//!   balls moves by at most `|Δp| + |Δr|` when every ball does, so
//!   `e_axial = h²/4·(|b₀ − 2b₁ + b₂| + |r₀ − 2r₁ + r₂|)` bounds the sweep-to-chain distance both ways.
//!
//! The tolerance is split evenly between the terms that occur: ε/2 each for a single link
//! (ring, arc), ε/3 for a chain (and fold), ε/4 for a spline (and axial); a mesh reports the sum of the terms it actually reached
//! ([`crate::Mesh::certified`]), which is ≤ ε up to the rounding of the output coordinates.

use crate::error::GeometryError;

/// Most ring vertices a tessellation may use (a tolerance asking for more is rejected).
pub const MAX_RING: usize = 1 << 16;

/// Ring vertex count and arc step for one component.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Budget {
    /// Vertices per ring.
    pub n: usize,
    /// Largest angle (radians) between consecutive rings along a meridian.
    pub step: f64,
    /// Share of ε for the fold at joints.
    pub fold: f64,
}

/// Smallest `n ≥ 3` with `r(1 − cos(π/n)) ≤ e`, or `None` past [`MAX_RING`].
pub fn ring_count(r: f64, e: f64) -> Option<usize> {
    if r <= 0.0 {
        return Some(3);
    }
    let c = 1.0 - e / r;
    if c <= -1.0 {
        return Some(3);
    }
    let n = (core::f64::consts::PI / c.acos()).ceil();
    let mut n = if n.is_finite() { (n as usize).max(3) } else { return None };
    // acos and the division round: step up until the bound holds in f64.
    while n <= MAX_RING && r * (1.0 - (core::f64::consts::PI / n as f64).cos()) > e {
        n += 1;
    }
    (n <= MAX_RING).then_some(n)
}

/// Largest step `Δ ≤ π/2` with `r(1 − cos(Δ/2)) ≤ e`.
pub fn arc_step(r: f64, e: f64) -> f64 {
    if r <= 0.0 {
        return core::f64::consts::FRAC_PI_2;
    }
    let c = (1.0 - e / r).max(-1.0);
    (2.0 * c.acos()).min(core::f64::consts::FRAC_PI_2)
}

/// The budget for a component of largest radius `r_max` at tolerance `eps` split evenly
/// between `terms` terms.
pub fn budget(r_max: f64, eps: f64, terms: u32) -> Result<Budget, GeometryError> {
    if !eps.is_finite() || !r_max.is_finite() {
        return Err(GeometryError::NonFinite { what: "mesh tolerance" });
    }
    if eps <= 0.0 {
        return Err(GeometryError::TooSmall { what: "mesh tolerance (must be > 0)" });
    }
    let e = eps / f64::from(terms);
    let n = ring_count(r_max, e).ok_or(GeometryError::TooSmall { what: "mesh tolerance relative to the radius" })?;
    let step = arc_step(r_max, e);
    if step * (MAX_RING as f64) < core::f64::consts::PI {
        return Err(GeometryError::TooSmall { what: "mesh tolerance relative to the radius" });
    }
    Ok(Budget { n, step, fold: e })
}

/// Largest parameter step `Δσ` between joint rings (see [`joint_term`]) that keeps a joint of
/// radius `r` within `e`: `(r/8)(Δσ + 2π/n)² ≤ e`, at most the arc step. `None` when even
/// `Δσ → 0` cannot (`(r/8)(2π/n)² > e`; it does not happen for `e` = [`reached`] at
/// `r ≤ r_max`, see the module docs, but the caller then keeps the arc step and certifies
/// the larger [`joint_term`]).
pub fn joint_step(b: &Budget, r: f64, e: f64) -> Option<f64> {
    if r <= 0.0 {
        return Some(b.step);
    }
    let d = (8.0 * e / r).sqrt() - core::f64::consts::TAU / b.n as f64;
    (d > 0.0).then(|| d.min(b.step))
}

/// The distance bound `(r/8)(Δσ + Δβ)²`, `Δβ = 2π/n`, between a joint's exact sweep and its
/// triangles, for rings `Δσ` apart (see the module docs: *Joint sweep*).
pub fn joint_term(b: &Budget, r: f64, d_sigma: f64) -> f64 {
    let s = d_sigma + core::f64::consts::TAU / b.n as f64;
    0.125 * r * s * s
}

/// The actual ring-chord and arc terms of a budget at radius `r_max`.
pub fn reached(b: &Budget, r_max: f64) -> f64 {
    let ring = r_max * (1.0 - (core::f64::consts::PI / b.n as f64).cos());
    let arc = r_max * (1.0 - (0.5 * b.step).cos());
    ring + arc
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ring_count_is_the_smallest_that_meets_the_chord_bound() {
        for (r, e) in [(1.0, 1e-2), (1.0, 1e-3), (3.0, 1e-4), (1e-6, 1e-9), (1e6, 1.0)] {
            let n = ring_count(r, e).unwrap();
            let chord = |n: usize| r * (1.0 - (core::f64::consts::PI / n as f64).cos());
            assert!(chord(n) <= e, "r {r} e {e} n {n}");
            assert!(n == 3 || chord(n - 1) > e, "r {r} e {e}: n {n} not the smallest");
        }
        assert_eq!(ring_count(1.0, 1e-14), None);
    }

    #[test]
    fn arc_step_meets_its_sagitta() {
        for (r, e) in [(1.0, 1e-2), (2.0, 1e-5), (1e-3, 1e-7)] {
            let s = arc_step(r, e);
            // acos rounds to ~1 ulp of its argument's distance from 1: the sagitta is e to ~1e-12 relative.
            assert!(r * (1.0 - (0.5 * s).cos()) <= e * (1.0 + 1e-9), "r {r} e {e}");
        }
    }

    #[test]
    fn joint_step_keeps_the_joint_term_within_ring_and_arc() {
        // The module docs: the step exists for e = ring + arc reached at r ≤ r_max, and the
        // joint term at that step (or any smaller one) is ≤ e.
        for (r_max, eps) in [(1.0, 1e-2), (1.0, 1e-3), (3.0, 1e-5), (1.0, 0.9), (1e-6, 1e-9)] {
            let b = budget(r_max, eps, 2).unwrap();
            let e = reached(&b, r_max);
            for r in [r_max, 0.5 * r_max, 1e-3 * r_max] {
                let d = joint_step(&b, r, e).expect("a positive joint step");
                assert!(d > 0.0 && d <= b.step);
                for m in [1.0, 0.5, 0.1] {
                    assert!(joint_term(&b, r, m * d) <= e * (1.0 + 1e-12), "r {r} eps {eps}");
                }
            }
        }
    }

    #[test]
    fn bad_tolerances_are_errors() {
        assert!(budget(1.0, 0.0, 2).is_err());
        assert!(budget(1.0, -1.0, 2).is_err());
        assert!(budget(1.0, f64::NAN, 2).is_err());
        assert!(budget(1.0, 1e-15, 2).is_err());
    }
}
