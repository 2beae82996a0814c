//! The pinhole (or orthographic) camera and how a view is chosen.

use super::RenderError;
use std::cmp::Ordering;
use tubecast::Ray;
use tubecast::V3;

/// A perspective pinhole camera.
///
/// ```
/// use tubecast::V3;
/// use tubecast_render::render::Camera;
///
/// let (eye, target, up) = (V3::new(0.0, 0.0, 10.0), V3::zero(), V3::new(0.0, 1.0, 0.0));
/// let cam = Camera::look_at(eye, target, up, 40.0, 64, 64).unwrap();
/// assert_eq!(cam.forward, V3::new(0.0, 0.0, -1.0));
/// // Pixel centres straddle the view axis of an even-sized image.
/// let (a, b) = (cam.ray(31, 31).d, cam.ray(32, 32).d);
/// assert_eq!((a.x, a.y), (-b.x, -b.y));
/// assert!(Camera::look_at(eye, eye, up, 40.0, 64, 64).is_err());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Eye position.
    pub eye: V3<f64>,
    /// Unit forward direction.
    pub forward: V3<f64>,
    /// Unit right direction (image +x).
    pub right: V3<f64>,
    /// Unit up direction (image +y).
    pub up: V3<f64>,
    /// Vertical field of view, degrees.
    pub fov_deg: f64,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// `0`: perspective. `> 0`: orthographic, the image spanning `±ortho` world units
    /// vertically around the eye ([`Camera::orthographic`]).
    pub ortho: f64,
}

/// A named view direction (`--view`): the direction from the scene's centre to the eye and
/// the up direction.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Preset {
    /// Looking down −z at the x–y plane, x right, y up.
    Xy,
    /// Looking along +y at the x–z plane, x right, z up.
    Xz,
    /// Looking along −x at the y–z plane, y right, z up.
    Yz,
    /// Isometric: from the (1, 1, 1) direction, y up.
    Iso,
}

impl Preset {
    /// (eye direction from the centre, up).
    pub fn axes(self) -> ([f64; 3], [f64; 3]) {
        match self {
            Preset::Xy => ([0.0, 0.0, 1.0], [0.0, 1.0, 0.0]),
            Preset::Xz => ([0.0, -1.0, 0.0], [0.0, 0.0, 1.0]),
            Preset::Yz => ([1.0, 0.0, 0.0], [0.0, 0.0, 1.0]),
            Preset::Iso => ([1.0, 1.0, 1.0], [0.0, 1.0, 0.0]),
        }
    }
}

impl std::str::FromStr for Preset {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "xy" => Ok(Preset::Xy),
            "xz" => Ok(Preset::Xz),
            "yz" => Ok(Preset::Yz),
            "iso" => Ok(Preset::Iso),
            _ => Err(format!("unknown view {s:?} (xy, xz, yz or iso)")),
        }
    }
}

fn finite3(v: V3<f64>) -> bool {
    v.x.is_finite() && v.y.is_finite() && v.z.is_finite()
}

impl Camera {
    /// A camera at `eye` looking at `target` with `up` roughly up and vertical field of view
    /// `fov_deg` (in `(0, 180)`). Errors: non-finite input, `eye == target`, `up` parallel to
    /// the view direction, a bad field of view, or a zero-sized image.
    pub fn look_at(
        eye: V3<f64>,
        target: V3<f64>,
        up: V3<f64>,
        fov_deg: f64,
        width: u32,
        height: u32,
    ) -> Result<Self, RenderError> {
        if !finite3(eye) || !finite3(target) || !finite3(up) {
            return Err(RenderError::NonFiniteCamera);
        }
        if !(fov_deg > 0.0 && fov_deg < 180.0) {
            return Err(RenderError::FieldOfView(fov_deg));
        }
        if width == 0 || height == 0 || width > 1 << 15 || height > 1 << 15 {
            return Err(RenderError::ImageSize { width, height });
        }
        let f = target - eye;
        if f.length().partial_cmp(&0.0) != Some(Ordering::Greater) {
            return Err(RenderError::EyeAtTarget);
        }
        let forward = f.normalize_or_zero();
        let right = forward.cross(up);
        if right.length().partial_cmp(&(1e-9 * up.length())) != Some(Ordering::Greater) {
            return Err(RenderError::UpParallel);
        }
        let right = right.normalize_or_zero();
        let up = right.cross(forward);
        Ok(Self { eye, forward, right, up, fov_deg, width, height, ortho: 0.0 })
    }

    /// The orthographic camera with the same eye, orientation and framing at `target`: the
    /// image spans `±tan(fov/2)·|target − eye|` vertically (what the perspective view shows
    /// in the plane through `target`); rays run along `forward` from the image plane through
    /// the eye, `t` measured in units of `forward` (unit length).
    ///
    /// ```
    /// use tubecast::V3;
    /// use tubecast_render::render::Camera;
    /// let cam = Camera::look_at(V3::new(0.0, 0.0, 10.0), V3::zero(), V3::new(0.0, 1.0, 0.0), 90.0, 4, 4).unwrap();
    /// let o = cam.orthographic([0.0; 3]);
    /// assert!((o.ortho - 10.0).abs() < 1e-12);
    /// let (a, b) = (o.ray(0, 0), o.ray(3, 3));
    /// assert_eq!((a.d, b.d), (cam.forward, cam.forward)); // parallel rays
    /// assert!((a.o.x + 7.5).abs() < 1e-12 && (a.o.y - 7.5).abs() < 1e-12); // pixel centres
    /// ```
    pub fn orthographic(&self, target: [f64; 3]) -> Self {
        let half = (self.fov_deg * 0.5).to_radians().tan() * (V3::from(target) - self.eye).length();
        Self { ortho: half, ..*self }
    }

    /// [`Camera::fit`] from a named view direction ([`Preset`]).
    pub fn fit_preset(
        lo: [f64; 3],
        hi: [f64; 3],
        preset: Preset,
        fov_deg: f64,
        width: u32,
        height: u32,
    ) -> Result<Self, RenderError> {
        let (dir, up) = preset.axes();
        Self::fit_from(lo, hi, V3::from(dir), V3::from(up), fov_deg, width, height)
    }

    /// A camera that frames the box `(lo, hi)`: looking at its centre from the direction
    /// `(0.25, 0.35, 1)` (a three-quarter view from +z), just far enough (plus 5%) that all
    /// eight corners of the box project inside both the vertical and horizontal field of view.
    pub fn fit(lo: [f64; 3], hi: [f64; 3], fov_deg: f64, width: u32, height: u32) -> Result<Self, RenderError> {
        Self::fit_from(lo, hi, V3::new(0.25, 0.35, 1.0), V3::new(0.0, 1.0, 0.0), fov_deg, width, height)
    }

    /// [`Camera::fit`] looking from the direction `dir` with `up`.
    fn fit_from(
        lo: [f64; 3],
        hi: [f64; 3],
        dir: V3<f64>,
        up: V3<f64>,
        fov_deg: f64,
        width: u32,
        height: u32,
    ) -> Result<Self, RenderError> {
        let c = V3::new(0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2]));
        let r = 0.5 * (V3::from(hi) - V3::from(lo)).length();
        if !(r.is_finite() && r > 0.0) {
            return Err(RenderError::EmptyBounds);
        }
        let aspect = width.max(1) as f64 / height.max(1) as f64;
        let half_v = (fov_deg.clamp(1e-3, 179.0) * 0.5).to_radians();
        let half_h = (half_v.tan() * aspect).atan();
        let dir = dir.normalize_or_zero();
        // Orientation only (eye distance 1), to measure the corners in the camera frame.
        let probe = Self::look_at(c + dir, c, up, fov_deg, width, height)?;
        let (tv, th) = (half_v.tan(), half_h.tan());
        let mut dist: f64 = 0.0;
        for k in 0..8 {
            let q = V3::new(
                if k & 1 == 0 { lo[0] } else { hi[0] },
                if k & 2 == 0 { lo[1] } else { hi[1] },
                if k & 4 == 0 { lo[2] } else { hi[2] },
            ) - c;
            // A corner at depth (dist + z) is inside when |x| ≤ th·(dist + z) and |y| ≤ tv·(dist + z).
            let z = q.dot(probe.forward);
            dist = dist.max(q.dot(probe.right).abs() / th - z).max(q.dot(probe.up).abs() / tv - z);
        }
        // Keep the eye outside the box's bounding sphere as well.
        let dist = (1.05 * dist).max(1.05 * r);
        Self::look_at(c + dir * dist, c, up, fov_deg, width, height)
    }

    /// This camera's view (direction, up, field of view, image size) moved so that the spheres
    /// `(centre, radius)` fill the image: their image centred (perspective draws the near side
    /// larger, so the eye moves sideways until it is), and the eye as close as keeps every
    /// sphere inside the image with 5% to spare on the side that limits (an orthographic camera: the image's half-height set
    /// likewise, the eye in front of every sphere). A box fitted from its corners leaves a
    /// scene that does not fill its box far smaller than the image; this fits what is there.
    /// `None` when there is no sphere or the extent is empty or not finite.
    ///
    /// ```
    /// use tubecast::V3;
    /// use tubecast_render::render::Camera;
    /// let cam = Camera::look_at(V3::new(0.0, 0.0, 10.0), V3::zero(), V3::new(0.0, 1.0, 0.0), 90.0, 100, 100).unwrap();
    /// // A sphere of radius 1 at (5, 0, 0): looked at, and seen at 95% of the image.
    /// let f = cam.framed([([5.0, 0.0, 0.0], 1.0)].into_iter()).unwrap();
    /// assert!((f.eye.x - 5.0).abs() < 1e-12 && f.forward == cam.forward);
    /// // tan 45° = 1: the sphere's silhouette, half-width 1/cos 45° = √2, is 0.95 of the view.
    /// assert!((f.eye.z - 2f64.sqrt() / 0.95).abs() < 1e-12);
    /// ```
    pub fn framed<I: Iterator<Item = ([f64; 3], f64)> + Clone>(&self, spheres: I) -> Option<Self> {
        const FILL: f64 = 0.95;
        let axes = |p: [f64; 3]| {
            let p = V3::from(p);
            [p.dot(self.right), p.dot(self.up), p.dot(self.forward)]
        };
        // Extents along right, up and forward, spheres included.
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        for (p, r) in spheres.clone() {
            let q = axes(p);
            for k in 0..3 {
                lo[k] = lo[k].min(q[k] - r.max(0.0));
                hi[k] = hi[k].max(q[k] + r.max(0.0));
            }
        }
        let mut mid: [f64; 3] = std::array::from_fn(|k| 0.5 * (lo[k] + hi[k]));
        let size = (0..2).map(|k| hi[k] - lo[k]).fold(0.0, f64::max);
        if !(mid.iter().all(|m| m.is_finite()) && size.is_finite() && size > 0.0) {
            return None;
        }
        let aspect = self.width as f64 / self.height as f64;
        let tv = (self.fov_deg * 0.5).to_radians().tan();
        let th = tv * aspect;
        if self.ortho > 0.0 {
            // Parallel rays: the half-height that holds both extents, the eye in front of all.
            let centre = self.right * mid[0] + self.up * mid[1] + self.forward * mid[2];
            let half = ((hi[1] - lo[1]) * 0.5).max((hi[0] - lo[0]) * 0.5 / aspect) / FILL;
            let back = (mid[2] - lo[2]) + 0.05 * size;
            return Some(Self { eye: centre - self.forward * back, ortho: half, ..*self });
        }
        // A sphere (x, y, z) about the point looked at, radius r, stays inside the horizontal
        // field when |x| + r·√(1 + th²) ≤ FILL·th·(dist + z): its silhouette's edge leans out by
        // 1/cos of the field's half-angle at most. Likewise vertically; and in front of the eye.
        let (kh, kv) = ((1.0 + th * th).sqrt(), (1.0 + tv * tv).sqrt());
        let local = |p: [f64; 3], r: f64, mid: &[f64; 3]| {
            let q = axes(p);
            (q[0] - mid[0], q[1] - mid[1], q[2] - mid[2], r.max(0.0))
        };
        let distance = |mid: &[f64; 3]| {
            let mut dist: f64 = 0.0;
            for (p, r) in spheres.clone() {
                let (x, y, z, r) = local(p, r, mid);
                let need = ((x.abs() + r * kh) / (FILL * th)).max((y.abs() + r * kv) / (FILL * tv)) - z;
                dist = dist.max(need).max(r - z + 1e-3 * size);
            }
            dist
        };
        let mut dist = distance(&mid);
        // Perspective draws the near side larger: centre the image of the spheres (their
        // silhouettes' extent in tangent units) rather than their extent, and fit again; each
        // round moves the eye sideways by the offset at the point looked at.
        for _ in 0..3 {
            let (mut u, mut v) = ([f64::INFINITY, f64::NEG_INFINITY], [f64::INFINITY, f64::NEG_INFINITY]);
            for (p, r) in spheres.clone() {
                let (x, y, z, r) = local(p, r, &mid);
                let d = dist + z;
                (u[0], u[1]) = (u[0].min((x - r * kh) / d), u[1].max((x + r * kh) / d));
                (v[0], v[1]) = (v[0].min((y - r * kv) / d), v[1].max((y + r * kv) / d));
            }
            let shift = [0.5 * (u[0] + u[1]) * dist, 0.5 * (v[0] + v[1]) * dist];
            if !(shift[0].is_finite() && shift[1].is_finite()) {
                return None;
            }
            (mid[0], mid[1]) = (mid[0] + shift[0], mid[1] + shift[1]);
            dist = distance(&mid);
        }
        let centre = self.right * mid[0] + self.up * mid[1] + self.forward * mid[2];
        dist.is_finite().then(|| Self { eye: centre - self.forward * dist, ..*self })
    }

    /// The camera whose ray for pixel `(x, y)` runs through the point `(dx, dy)` pixels off
    /// that pixel's centre (`dx` to the right, `dy` down): the view direction turned (or, for an
    /// orthographic camera, the eye moved) by that much. `forward` is then no longer of unit
    /// length; it is for sampling within pixels (antialiasing), not for framing.
    pub(super) fn offset(&self, dx: f64, dy: f64) -> Self {
        let th = (self.fov_deg * 0.5).to_radians().tan();
        let aspect = self.width as f64 / self.height as f64;
        let (sx, sy) = (2.0 * dx / self.width as f64 * th * aspect, -2.0 * dy / self.height as f64 * th);
        if self.ortho > 0.0 {
            let k = self.ortho / th;
            return Self { eye: self.eye + self.right * (sx * k) + self.up * (sy * k), ..*self };
        }
        Self { forward: self.forward + self.right * sx + self.up * sy, ..*self }
    }

    /// The primary ray through the centre of pixel `(x, y)` (`y = 0` is the top row). Its
    /// direction is `forward + sx·right + sy·up` (not unit length); `t` is measured in it.
    pub fn ray(&self, x: u32, y: u32) -> Ray<f64> {
        let th = (self.fov_deg * 0.5).to_radians().tan();
        let aspect = self.width as f64 / self.height as f64;
        let sx = ((x as f64 + 0.5) / self.width as f64 * 2.0 - 1.0) * th * aspect;
        let sy = (1.0 - (y as f64 + 0.5) / self.height as f64 * 2.0) * th;
        if self.ortho > 0.0 {
            let k = self.ortho / th;
            return Ray::new(self.eye + self.right * (sx * k) + self.up * (sy * k), self.forward);
        }
        Ray::new(self.eye, self.forward + self.right * sx + self.up * sy)
    }
}

/// How to place the camera for a scene: fitted to its bounds ([`Camera::fit`]) unless an eye
/// or a look-at point is given; a missing eye is the fitted one, a missing look-at point the
/// centre of the bounds.
///
/// ```
/// use tubecast_render::render::View;
/// let view = View { eye: None, look_at: Some([0.0, 0.0, 0.0]), ..View::default() };
/// let cam = view.camera(([-1.0; 3], [1.0; 3])).unwrap();
/// assert_eq!((cam.width, cam.height), (800, 600));
/// assert!(cam.forward.dot(-cam.eye).abs() > 0.999 * cam.eye.length());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct View {
    /// Eye position (default: fitted).
    pub eye: Option<[f64; 3]>,
    /// Point looked at (default: the centre of the bounds).
    pub look_at: Option<[f64; 3]>,
    /// Up direction, used with an eye or look-at point.
    pub up: [f64; 3],
    /// Vertical field of view, degrees.
    pub fov_deg: f64,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
}

impl Default for View {
    /// The `tubecast render` defaults: fitted, up `+y`, 40°, 800×600.
    fn default() -> Self {
        Self { eye: None, look_at: None, up: [0.0, 1.0, 0.0], fov_deg: 40.0, width: 800, height: 600 }
    }
}

impl View {
    /// The camera for a scene whose primitives have the bounds `(lo, hi)`.
    pub fn camera(&self, (lo, hi): ([f64; 3], [f64; 3])) -> Result<Camera, RenderError> {
        let fit = Camera::fit(lo, hi, self.fov_deg, self.width, self.height)?;
        if self.eye.is_none() && self.look_at.is_none() {
            return Ok(fit);
        }
        let eye = self.eye.map(V3::from).unwrap_or(fit.eye);
        let centre = std::array::from_fn(|i| 0.5 * (lo[i] + hi[i]));
        let at = V3::from(self.look_at.unwrap_or(centre));
        Camera::look_at(eye, at, V3::from(self.up), self.fov_deg, self.width, self.height)
    }
}
