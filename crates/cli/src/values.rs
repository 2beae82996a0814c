//! The values options take, parsed and range-checked as clap reads them, so that a bad value
//! is a usage error (exit 2) naming the flag, the value and what is allowed, before any work.
//! A leaf: it imports nothing of the crate.

use tubecast_render::render::AoMethod;

/// `--radius`: absolute (`0.2`) or relative to the scene's size (`0.5%`: half a percent of the
/// diagonal of the bounding box of the points).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Radius {
    /// In the file's units.
    Absolute(f64),
    /// A fraction of the bounding-box diagonal, in `(0, 1]`.
    Relative(f64),
}

/// Parse `--radius`: a positive number, or a percentage in `(0%, 100%]`.
pub fn radius(s: &str) -> Result<Radius, String> {
    let bad = || "use a positive number (file units) or a percentage of the scene's diagonal in (0%, 100%], like 0.5%";
    let (num, rel) = match s.strip_suffix('%') {
        Some(n) => (n, true),
        None => (s, false),
    };
    let v = num.trim().parse::<f64>().map_err(|_| bad())?;
    if !(v.is_finite() && v > 0.0) || (rel && v > 100.0) {
        return Err(bad().into());
    }
    Ok(if rel { Radius::Relative(v / 100.0) } else { Radius::Absolute(v) })
}

/// A finite number `> 0` (`--min-radius`, `--tolerance`, `--pixel-error`, `--min-pixels`).
pub fn positive(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 => Ok(v),
        _ => Err("use a finite number > 0".into()),
    }
}

/// A number in `(0, 1]` (`--opacity`, `--subsample`).
pub fn fraction(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(v) if v > 0.0 && v <= 1.0 => Ok(v),
        _ => Err("use a number in (0, 1]".into()),
    }
}

/// A field of view in degrees, in `(0, 180)`.
pub fn fov(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(v) if v > 0.0 && v < 180.0 => Ok(v),
        _ => Err("use an angle in degrees in (0, 180)".into()),
    }
}

/// A point `x,y,z` of three finite numbers (`--eye`, `--look-at`).
pub fn point(s: &str) -> Result<[f64; 3], String> {
    let v: Vec<f64> = s
        .split(',')
        .map(|t| t.trim().parse::<f64>().map_err(|_| format!("{t:?} is not a number; use x,y,z")))
        .collect::<Result<_, _>>()?;
    if v.len() != 3 || v.iter().any(|x| !x.is_finite()) {
        return Err("use three finite numbers x,y,z".into());
    }
    Ok([v[0], v[1], v[2]])
}

/// A direction `x,y,z`: a [`point`] that is not the zero vector (`--up`).
pub fn direction(s: &str) -> Result<[f64; 3], String> {
    let v = point(s)?;
    if v.iter().all(|c| *c == 0.0) {
        return Err("a direction cannot be the zero vector; use x,y,z with one component ≠ 0".into());
    }
    Ok(v)
}

/// `1234`, `512K`, `1.5G`, ...: bytes, with binary suffixes (`--memory-limit`).
pub fn bytes(s: &str) -> Result<u64, String> {
    let t = s.trim();
    let (num, mult) = match t.chars().last().map(|c| c.to_ascii_uppercase()) {
        Some('K') => (&t[..t.len() - 1], 1u64 << 10),
        Some('M') => (&t[..t.len() - 1], 1 << 20),
        Some('G') => (&t[..t.len() - 1], 1 << 30),
        Some('T') => (&t[..t.len() - 1], 1 << 40),
        _ => (t, 1),
    };
    match num.trim().parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 && v * (mult as f64) < 1.8e19 => Ok((v * mult as f64) as u64),
        _ => Err("use a positive byte count (e.g. 8G, 512M, 1000000)".into()),
    }
}

/// `--background`: a colour (linear RGB) or a transparent background (RGBA PNG).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Background {
    /// An opaque colour, linear RGB.
    Color([f32; 3]),
    /// Alpha 0 where no tube is seen.
    Transparent,
}

/// sRGB component in `[0, 1]` → linear.
fn linear(s: f32) -> f32 {
    if s <= 0.04045 {
        s / 12.92
    } else {
        ((s + 0.055) / 1.055).powf(2.4)
    }
}

/// A colour: `#rrggbb` (sRGB hex), `r,g,b` (sRGB components in `[0, 1]`), `white`, `black`
/// or `grey`; returned in linear RGB.
pub fn rgb(s: &str) -> Result<[f32; 3], String> {
    let srgb: [f32; 3] = match s {
        "white" => [1.0; 3],
        "black" => [0.0; 3],
        "grey" | "gray" => [0.5; 3],
        _ if s.starts_with('#') && s.len() == 7 && s[1..].chars().all(|c| c.is_ascii_hexdigit()) => {
            std::array::from_fn(|k| u8::from_str_radix(&s[1 + 2 * k..3 + 2 * k], 16).map_or(0.0, |b| b as f32 / 255.0))
        }
        _ => {
            let v: Vec<f32> = s.split(',').filter_map(|t| t.trim().parse::<f32>().ok()).collect();
            if v.len() != 3 || s.split(',').count() != 3 || v.iter().any(|c| !(0.0..=1.0).contains(c)) {
                return Err("use #rrggbb, r,g,b in [0, 1], white, black or grey".into());
            }
            [v[0], v[1], v[2]]
        }
    };
    Ok(srgb.map(linear))
}

/// `--background`: `transparent` or a colour ([`rgb`]).
pub fn background(s: &str) -> Result<Background, String> {
    if s == "transparent" || s == "none" {
        return Ok(Background::Transparent);
    }
    rgb(s).map(Background::Color).map_err(|e| format!("{e}, or transparent"))
}

/// Surface colouring (`--color`).
#[derive(Clone, Debug, PartialEq)]
pub enum Color {
    /// |tangent| as RGB (tractography convention).
    Direction,
    /// Radius through a colour map.
    Radius,
    /// SWC structure type.
    Type,
    /// A data field of the file (`scalar:NAME` or `property:NAME`) through `--colormap`.
    Data(String),
    /// One colour (`solid:#rrggbb`), linear RGB.
    Solid([f32; 3]),
}

/// `direction`, `radius`, `type`, `solid:COLOUR`, `scalar:NAME` or `property:NAME`.
pub fn color(s: &str) -> Result<Color, String> {
    match s {
        "direction" => Ok(Color::Direction),
        "radius" => Ok(Color::Radius),
        "type" => Ok(Color::Type),
        _ if s.starts_with("solid:") => rgb(&s[6..]).map(Color::Solid),
        _ if (s.starts_with("scalar:") || s.starts_with("property:")) && !s.ends_with(':') => Ok(Color::Data(s.into())),
        _ => Err("use direction, radius, type, solid:#rrggbb, scalar:NAME or property:NAME".into()),
    }
}

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
    /// `--ao N`: N rays per pixel (the older form of `--ao rays --ao-samples N`).
    RayCount(u32),
}

/// Rays per pixel the renderer accepts for ambient occlusion.
pub const MAX_AO: u32 = 1024;

/// Parse `--ao`: `off`, `rays`, `cone`, `lod`, or a ray count in `1..=1024`.
pub fn ao(s: &str) -> Result<Ao, String> {
    match s {
        "off" => Ok(Ao::Off),
        "rays" => Ok(Ao::Rays),
        "cone" | "cones" => Ok(Ao::Cone),
        "lod" => Ok(Ao::Lod),
        _ => match s.parse::<u32>() {
            Ok(n) if (1..=MAX_AO).contains(&n) => Ok(Ao::RayCount(n)),
            _ => Err(format!("use cone, rays, off, lod or a ray count in 1..={MAX_AO}")),
        },
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_are_enforced_at_parse_time() {
        assert_eq!(radius("0.5%"), Ok(Radius::Relative(0.005)));
        assert_eq!(radius("100%"), Ok(Radius::Relative(1.0)));
        for bad in ["200%", "0%", "-1", "0", "nan", "x"] {
            assert!(radius(bad).is_err(), "{bad}");
        }
        assert!(direction("0,0,0").is_err() && direction("0,-1,0").is_ok());
        assert!(positive("0").is_err() && positive("-1").is_err() && positive("inf").is_err());
        assert!(fraction("0").is_err() && fraction("1").is_ok() && fraction("1.5").is_err());
        assert!(ao("0").is_err() && ao("1025").is_err() && ao("8") == Ok(Ao::RayCount(8)));
        assert!(bytes("0").is_err() && bytes("1K") == Ok(1024));
        assert!(fov("180").is_err() && fov("40") == Ok(40.0));
    }
}
