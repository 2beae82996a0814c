//! The rendered image and its PNG encoding.

use super::RenderError;
use crate::io::IoError;
use std::path::Path;

/// A rendered image: linear RGB composited over [`Image::background`], the alpha (accumulated
/// opacity of the surfaces the pixel sees) and the depth (ray parameter of the first surface
/// crossing, `+∞` where the pixel sees nothing).
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    /// Width.
    pub width: u32,
    /// Height.
    pub height: u32,
    /// Row-major linear RGB, composited over the background: `premultiplied + (1 − α)·background`.
    pub rgb: Vec<[f32; 3]>,
    /// Row-major alpha in `[0, 1]`: 0 where the pixel sees nothing, 1 behind an opaque surface,
    /// `1 − Π(1 − aᵢ)` through surfaces of opacity `aᵢ` (front-to-back compositing).
    pub alpha: Vec<f32>,
    /// Row-major depth in the camera ray's parameter ([`super::Camera::ray`]).
    pub depth: Vec<f64>,
    /// The background colour `rgb` was composited over (linear RGB).
    pub background: [f32; 3],
}

impl Image {
    /// Pixel `(x, y)`.
    pub fn at(&self, x: u32, y: u32) -> [f32; 3] {
        self.rgb[(y * self.width + x) as usize]
    }
    /// 8-bit sRGB bytes, row-major RGB.
    pub fn to_srgb8(&self) -> Vec<u8> {
        self.rgb.iter().flat_map(|p| p.map(srgb8)).collect()
    }
    /// Write an 8-bit RGB PNG.
    pub fn write_png(&self, path: &Path) -> Result<(), RenderError> {
        self.write_png_as(path, false)
    }

    /// Write an 8-bit RGBA PNG with a transparent background: alpha is [`Image::alpha`] (0
    /// where the pixel sees no surface, the accumulated opacity of transparent tubes), and the
    /// colour is straight (not premultiplied, as PNG defines it), see [`Image::straight`].
    pub fn write_png_rgba(&self, path: &Path) -> Result<(), RenderError> {
        self.write_png_as(path, true)
    }

    /// The straight (not premultiplied) linear colour and the alpha of pixel `i`: the
    /// background taken back out, `(rgb − (1 − α)·background) / α`; black where α = 0.
    ///
    /// ```
    /// use tubecast_render::render::Image;
    /// // Red at opacity ½ over a white background: rgb = ½·red + ½·white.
    /// let img = Image { width: 1, height: 1, rgb: vec![[1.0, 0.5, 0.5]], alpha: vec![0.5], depth: vec![1.0], background: [1.0; 3] };
    /// assert_eq!(img.straight(0), ([1.0, 0.0, 0.0], 0.5));
    /// ```
    pub fn straight(&self, i: usize) -> ([f32; 3], f32) {
        let a = self.alpha[i];
        if a <= 0.0 {
            return ([0.0; 3], 0.0);
        }
        let c = self.rgb[i];
        (std::array::from_fn(|k| ((c[k] - (1.0 - a) * self.background[k]) / a).clamp(0.0, 1.0)), a.min(1.0))
    }

    fn write_png_as(&self, path: &Path, alpha: bool) -> Result<(), RenderError> {
        let name = path.display().to_string();
        let err = |problem: String| RenderError::Io(IoError::file(&name, problem));
        let f = std::fs::File::create(path).map_err(|e| err(format!("cannot create: {e}")))?;
        let mut enc = png::Encoder::new(std::io::BufWriter::new(f), self.width, self.height);
        enc.set_color(if alpha { png::ColorType::Rgba } else { png::ColorType::Rgb });
        enc.set_depth(png::BitDepth::Eight);
        enc.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
        let mut w = enc.write_header().map_err(|e| err(e.to_string()))?;
        let data = if alpha {
            (0..self.rgb.len())
                .flat_map(|i| {
                    let (c, a) = self.straight(i);
                    [srgb8(c[0]), srgb8(c[1]), srgb8(c[2]), (a * 255.0 + 0.5) as u8]
                })
                .collect()
        } else {
            self.to_srgb8()
        };
        w.write_image_data(&data).map_err(|e| err(e.to_string()))?;
        w.finish().map_err(|e| err(e.to_string()))
    }
}

/// Linear `[0, 1]` → 8-bit sRGB.
fn srgb8(c: f32) -> u8 {
    let c = c.clamp(0.0, 1.0);
    let s = if c <= 0.003_130_8 { 12.92 * c } else { 1.055 * c.powf(1.0 / 2.4) - 0.055 };
    (s * 255.0 + 0.5) as u8
}
