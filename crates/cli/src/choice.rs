//! The automatic primitive choice within a tolerance (`--tolerance EPS` or `--pixel-error P`)
//! as `render` traces it and `info` reports it.

use tubecast_render::render::{Camera, View};
use tubecast_render::scene::choice::{choose_with, Choice, Tolerance};
use tubecast_render::scene::{Prim, Scene};

/// The choice's tolerance from `--tolerance` or `--pixel-error` and a camera.
pub fn tolerance(eps: Option<f64>, pixels: Option<f64>, cam: &Camera) -> Option<Tolerance> {
    match (eps, pixels) {
        (Some(e), _) => Some(Tolerance::Absolute(e)),
        (None, Some(p)) => {
            Some(Tolerance::Pixels { eye: cam.eye.to_array(), fov_deg: cam.fov_deg, height: cam.height, pixels: p })
        }
        _ => None,
    }
}

/// `render` with the exact model: the chosen primitives when a tolerance is given, else `prims`.
pub fn chosen(scene: &Scene, prims: Vec<Prim>, eps: Option<f64>, pixels: Option<f64>, cam: &Camera) -> Vec<Prim> {
    match tolerance(eps, pixels, cam) {
        Some(t) => choose_with(scene, &t, true).prims,
        None => prims,
    }
}

/// `info --tolerance` / `--pixel-error`: the choice for the default fitted 800×600 view
/// (`None` without either flag).
pub fn for_info(
    scene: &Scene,
    eps: Option<f64>,
    pixels: Option<f64>,
) -> Result<Option<Choice>, crate::error::CliError> {
    if eps.is_none() && pixels.is_none() {
        return Ok(None);
    }
    let st = scene.stats();
    let bounds = if st.is_empty() { ([-1.0; 3], [1.0; 3]) } else { st.bounds };
    let cam = View::default().camera(bounds)?;
    Ok(tolerance(eps, pixels, &cam).map(|t| choose_with(scene, &t, true)))
}
