//! Thin structures stay visible: an image-space minimum radius with a coverage fade (the
//! "phone-wire anti-aliasing" idea Kraaijeveld et al. use for dynamic line sets, after Persson).
//!
//! A tube thinner than `min_px` pixels on screen is drawn `min_px` pixels wide and faded by
//! its true coverage, `α = r / r_min`, so a far or thin fibre covers about the same share of
//! each pixel it crosses instead of flickering in and out between pixel centres. The radius of
//! each node is raised to `r_min = ½·min_px·s(d)`, with `s(d)` the width of a pixel at the
//! node's depth `d` along the view axis (`2·d·tan(fov/2)/height`; orthographic:
//! `2·ortho/height`), and the node's coverage `α` is kept in [`Scene::coverage`]. The renderer
//! treats the coverage as the surface's opacity: an opaque render composites the surfaces the
//! ray enters front to back, each with its shaded colour `cᵢ` and weight `αᵢ`, down to the
//! first fully covered one, so a wire over the background gives `α·c + (1 − α)·bg` and a wire
//! in front of another tube shows that tube in the share it leaves uncovered; a transparent
//! render multiplies each surface's opacity by its coverage.

use super::Camera;
use crate::scene::Scene;
use tubecast::V3;

/// Raise the radius of every node of `scene` thinner than `min_px` pixels through `cam` to that
/// footprint, storing its coverage in [`Scene::coverage`] (1 for nodes left alone; nodes
/// behind the eye are left alone). Returns how many nodes were raised. `min_px` must be
/// positive and finite (otherwise nothing changes).
///
/// ```
/// use tubecast::V3;
/// use tubecast_render::render::{clamp_thin, Camera};
/// use tubecast_render::scene::{Node, Radii, Scene};
/// let (nodes, radii) = (vec![Node { pos: [0.0; 3] }], Radii::uniform(0.001));
/// let mut s = Scene { nodes, radii, links: vec![[0, 0]].into(), ..Scene::default() };
/// let cam = Camera::look_at(V3::new(0.0, 0.0, 10.0), V3::zero(), V3::new(0.0, 1.0, 0.0), 90.0, 100, 100).unwrap();
/// // A pixel at depth 10 is 2·10·tan(45°)/100 = 0.2 wide: r_min = 0.1 for one pixel.
/// assert_eq!(clamp_thin(&mut s, &cam, 1.0), 1);
/// assert!((s.radius(0) - 0.1).abs() < 1e-12);
/// assert!((s.coverage[0] - 0.01).abs() < 1e-6);
/// ```
pub fn clamp_thin(scene: &mut Scene, cam: &Camera, min_px: f64) -> usize {
    if !(min_px.is_finite() && min_px > 0.0) {
        return 0;
    }
    let h = cam.height as f64;
    let tan = (cam.fov_deg * 0.5).to_radians().tan();
    let mut coverage = vec![1.0f32; scene.nodes.len()];
    let mut raised = 0;
    for (i, c) in coverage.iter_mut().enumerate() {
        let (n, radius) = (&scene.nodes[i], scene.radius(i));
        let pixel = if cam.ortho > 0.0 {
            2.0 * cam.ortho / h
        } else {
            let d = (V3::from(n.pos) - cam.eye).dot(cam.forward);
            if d.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
                continue;
            }
            2.0 * d * tan / h
        };
        let r_min = 0.5 * min_px * pixel;
        if radius < r_min && r_min.is_finite() {
            *c = (radius.max(0.0) / r_min) as f32;
            scene.set_radius(i, r_min);
            raised += 1;
        }
    }
    scene.coverage = if raised > 0 { coverage } else { Vec::new() };
    raised
}
