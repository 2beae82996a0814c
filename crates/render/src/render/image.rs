//! The rendered image and its PNG encoding.

use super::RenderError;
use crate::io::IoError;
use std::path::Path;

/// A rendered image: linear RGB and the depth (ray parameter of the first surface crossing,
/// `+∞` where the pixel sees nothing).
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    /// Width.
    pub width: u32,
    /// Height.
    pub height: u32,
    /// Row-major linear RGB.
    pub rgb: Vec<[f32; 3]>,
    /// Row-major depth in the camera ray's parameter ([`super::Camera::ray`]).
    pub depth: Vec<f64>,
}

impl Image {
    /// Pixel `(x, y)`.
    pub fn at(&self, x: u32, y: u32) -> [f32; 3] {
        self.rgb[(y * self.width + x) as usize]
    }
    /// 8-bit sRGB bytes, row-major RGB.
    pub fn to_srgb8(&self) -> Vec<u8> {
        let enc = |c: f32| {
            let c = c.clamp(0.0, 1.0);
            let s = if c <= 0.003_130_8 { 12.92 * c } else { 1.055 * c.powf(1.0 / 2.4) - 0.055 };
            (s * 255.0 + 0.5) as u8
        };
        self.rgb.iter().flat_map(|p| p.map(enc)).collect()
    }
    /// Write an 8-bit RGB PNG.
    pub fn write_png(&self, path: &Path) -> Result<(), RenderError> {
        self.write_png_as(path, false)
    }

    /// Write an 8-bit RGBA PNG whose alpha is 0 where the pixel sees no surface (infinite
    /// depth) and 1 elsewhere: a transparent background. (With transparent tubes the colour
    /// of a covered pixel is already composited over the render's background colour.)
    pub fn write_png_rgba(&self, path: &Path) -> Result<(), RenderError> {
        self.write_png_as(path, true)
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
        let mut data = self.to_srgb8();
        if alpha {
            data = data
                .chunks_exact(3)
                .zip(&self.depth)
                .flat_map(|(c, d)| [c[0], c[1], c[2], if d.is_finite() { 255 } else { 0 }])
                .collect();
        }
        w.write_image_data(&data).map_err(|e| err(e.to_string()))?;
        w.finish().map_err(|e| err(e.to_string()))
    }
}
