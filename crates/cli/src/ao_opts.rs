//! `render --ao cone|lod|rays|off` and `--ao-samples N`: how ambient occlusion is estimated.
//! A bare number (`--ao 8`, the older form) means that many rays.

use tubecast_render::render::AoMethod;

/// The `--ao` value.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Ao {
    /// No ambient occlusion.
    Off,
    /// Rays through the accelerator (`--ao-samples` per pixel).
    Rays,
    /// Cones through the voxel occupancy pyramid (`--ao-samples` cones per pixel).
    Cone,
    /// Cones through Kanzler's LoD opacities of the quantized lines (`--ao-samples` cones).
    Lod,
    /// `--ao N`: N rays per pixel.
    RayCount(u32),
}

/// Parse `--ao`.
pub fn parse_ao(s: &str) -> Result<Ao, String> {
    match s {
        "off" => Ok(Ao::Off),
        "rays" => Ok(Ao::Rays),
        "cone" | "cones" => Ok(Ao::Cone),
        "lod" => Ok(Ao::Lod),
        _ => s.parse::<u32>().map(Ao::RayCount).map_err(|_| format!("{s:?}: use cone, rays, off, lod or a ray count")),
    }
}

impl Ao {
    /// `(samples, method)` for the render options, with `samples` from `--ao-samples`.
    pub fn resolve(self, samples: u32) -> (u32, AoMethod) {
        match self {
            Ao::Off => (0, AoMethod::Rays),
            Ao::Rays => (samples, AoMethod::Rays),
            Ao::Cone => (samples, AoMethod::Cone),
            Ao::Lod => (samples, AoMethod::Lod),
            Ao::RayCount(n) => (n, AoMethod::Rays),
        }
    }
}
