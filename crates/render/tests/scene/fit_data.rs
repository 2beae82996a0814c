//! Colouring by per-node data along a fitted spline piece ([`RunIndex::value`], what the
//! renderer's data colouring uses): the piece interpolates the data of the whole run of nodes
//! it replaces. Expected values come from the chain's own geometry: nodes on an arc of radius
//! `R` at angles `θᵢ`, data a function of `θᵢ`, so the value at a point of the piece is that
//! function's node interpolation at the point's angle.

use tubecast::V3;
use tubecast_render::io::Polyline;
use tubecast_render::scene::choice::{choose_with, Tolerance};
use tubecast_render::scene::fit::RunIndex;
use tubecast_render::scene::{Model, Scene};

const R: f64 = 10.0;

/// A data function of the angle, its name and its largest slope.
type Data<'a> = (&'a str, &'a dyn Fn(f64) -> f64, f64);
const LINKS: usize = 64;

fn theta(i: usize) -> f64 {
    i as f64 / LINKS as f64 * std::f64::consts::PI // a half circle
}

/// The chain's data interpolated linearly between nodes, at angle `phi`.
fn along(data: &dyn Fn(f64) -> f64, phi: f64) -> f64 {
    let d = theta(1);
    let i = ((phi / d).floor().max(0.0) as usize).min(LINKS - 1);
    let (a, b) = (data(theta(i)), data(theta(i + 1)));
    a + (b - a) * ((phi - theta(i)) / d).clamp(0.0, 1.0)
}

#[test]
fn a_fitted_piece_carries_the_data_of_its_whole_run() {
    let pts: Vec<[f64; 3]> = (0..=LINKS).map(|i| [R * theta(i).cos(), R * theta(i).sin(), 0.0]).collect();
    let base = Scene::from_polylines(&[Polyline { points: pts, radii: vec![] }], 0.5, "arc").unwrap();
    let datas: [Data; 2] = [("θ", &|t| t, 1.0), ("θ²", &|t| t * t, 2.0 * std::f64::consts::PI)];
    for eps in [2e-2, 5e-3] {
        for (name, data, slope) in datas {
            let mut scene = base.clone();
            scene.values = (0..=LINKS).map(|i| data(theta(i))).collect();
            let c = choose_with(&scene, &Tolerance::Absolute(eps), true);
            let index = RunIndex::new(&scene);
            // Error analysis. A point x = q(u) of a piece is within its certified bound D ≤ ε of
            // the run's polyline (the bound pairs every ball of the piece with one of the run),
            // so its projection y on the nearest link is within ε: their angles differ by at
            // most 2·asin(ε / 2ρ), ρ = R·cos h − ε the least distance from the centre (h = Δθ/2).
            // On a chord the value is linear in λ while the angle is θᵢ + h + atan((2λ−1)·tan h):
            // they differ by at most tan h − h (atan concave). The node interpolation of the
            // data has slope ≤ `slope` in θ.
            let h = 0.5 * theta(1);
            let rho = R * h.cos() - eps;
            let tol = slope * (2.0 * (eps / (2.0 * rho)).asin() + (h.tan() - h)) + 1e-12;
            let mut pieces = 0;
            for p in c.prims.iter().filter(|p| p.quad().is_some()) {
                let run = index.run(&scene, p).expect("a fitted piece names its run");
                assert!(run.len() >= 3);
                pieces += 1;
                let q = p.quad().unwrap().cast::<f64>();
                for k in 0..=20 {
                    let u = k as f64 / 20.0;
                    let x = V3::from(p.origin) + q.point(u);
                    // The arc spans [0, π]: a point just below the x axis at its far end is at π.
                    let phi = x.y.atan2(x.x);
                    let phi = if phi < -std::f64::consts::FRAC_PI_2 { phi + std::f64::consts::TAU } else { phi };
                    let want = along(data, phi);
                    let got = index.value(&scene, p, u).unwrap();
                    assert!((got - want).abs() <= tol, "{name} ε {eps}: u {u}: {got} vs {want} (tol {tol:e})");
                }
                // The piece's two ends carry its run's end values.
                let (first, last) = (run[0] as usize, run[run.len() - 1] as usize);
                assert!((index.value(&scene, p, 0.0).unwrap() - scene.values[first]).abs() <= tol);
                assert!((index.value(&scene, p, 1.0).unwrap() - scene.values[last]).abs() <= tol);
            }
            assert!(pieces >= 1, "{name} ε {eps}: the arc was fitted");
        }
    }
}

#[test]
fn links_and_the_spline_models_halves_have_no_run() {
    // Only the choice's fitted pieces name a run; the spline model's sub-segments (each within
    // one link) and plain links keep the per-link interpolation.
    let pts: Vec<[f64; 3]> = (0..=8).map(|i| [R * theta(i).cos(), R * theta(i).sin(), 0.0]).collect();
    let mut scene = Scene::from_polylines(&[Polyline { points: pts, radii: vec![] }], 0.5, "arc").unwrap();
    scene.values = (0..=8).map(|i| i as f64).collect();
    let index = RunIndex::new(&scene);
    for p in scene.primitives() {
        assert!(index.run(&scene, &p).is_none() && index.value(&scene, &p, 0.5).is_none());
    }
    let splines = scene.model_primitives(Model::Splines).unwrap();
    assert!(splines.iter().any(|p| p.quad().is_some()));
    for p in &splines {
        assert!(index.run(&scene, p).is_none(), "a spline-model piece covers one link");
    }
}
