//! Render settings.

use super::RenderError;

/// How surfaces are coloured.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ColorBy {
    /// Tractography convention: `|unit link direction|` as RGB (x red, y green, z blue); the
    /// curve's unit tangent at the hit for spline tubes.
    Direction,
    /// Radius at the hit (interpolated along the link, or the spline's radius curve), through
    /// a blue→yellow colour map over the scene's node radius range.
    Radius,
    /// SWC structure type (1 soma, 2 axon, 3 basal, 4 apical dendrite, others by palette).
    Type,
    /// One colour.
    Solid([f32; 3]),
    /// The scene's per-node data values ([`crate::scene::Scene::values`], e.g. a TrackVis
    /// scalar, a TRX `dpv`), interpolated along each link, through a named colour map over
    /// their finite range; a NaN value shows grey.
    Values(super::Colormap),
}

/// Lighting model.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Shading {
    /// Ambient + Lambert diffuse + Blinn-Phong specular from a light at the camera's upper left.
    Lit,
    /// The surface colour itself (no lighting): what the compositing tests check.
    Flat,
}

/// Render settings.
///
/// ```
/// use tubecast_render::render::{ColorBy, Options};
///
/// let glass = Options { opacity: 0.4, color: ColorBy::Radius, ..Options::default() };
/// assert!(glass.validate().is_ok());
/// assert!(Options { opacity: 0.0, ..glass }.validate().is_err());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Options {
    /// Surface colouring.
    pub color: ColorBy,
    /// Lighting.
    pub shading: Shading,
    /// Surface opacity in `(0, 1]`; below 1 renders transparent tubes with CSG.
    pub opacity: f64,
    /// Ambient-occlusion rays per pixel (0: none). Opaque mode only.
    pub ao: u32,
    /// How the `ao` samples estimate ambient occlusion: rays or cones.
    pub ao_method: super::AoMethod,
    /// Trace a shadow ray toward the light. Opaque mode only.
    pub shadows: bool,
    /// Background colour (linear RGB).
    pub background: [f32; 3],
    /// Antialiasing: `aa × aa` samples per pixel in `1..=16`, one per cell of an `aa × aa`
    /// grid over the pixel, jittered within its cell; 1 traces the pixel's centre.
    pub aa: u32,
    /// Show a progress bar on stderr.
    pub progress: bool,
}

impl Default for Options {
    fn default() -> Self {
        Self {
            color: ColorBy::Direction,
            shading: Shading::Lit,
            opacity: 1.0,
            ao: 0,
            ao_method: super::AoMethod::Rays,
            shadows: false,
            background: [1.0, 1.0, 1.0],
            aa: 1,
            progress: false,
        }
    }
}

impl Options {
    /// Check the settings: opacity in `(0, 1]`, AO rays ≤ 1024, finite background in `[0, 1]`,
    /// antialiasing in `1..=16`.
    pub fn validate(&self) -> Result<(), RenderError> {
        if !(self.opacity > 0.0 && self.opacity <= 1.0) {
            return Err(RenderError::Opacity(self.opacity));
        }
        if self.ao > 1024 {
            return Err(RenderError::AoRays(self.ao));
        }
        if !(1..=16).contains(&self.aa) {
            return Err(RenderError::Antialiasing(self.aa));
        }
        if self.background.iter().any(|c| !(0.0..=1.0).contains(c)) {
            return Err(RenderError::Background);
        }
        if let ColorBy::Solid(c) = self.color {
            if c.iter().any(|v| !(0.0..=1.0).contains(v)) {
                return Err(RenderError::Colour);
            }
        }
        Ok(())
    }
}
