//! Parsing of the render/info options that take a value with a unit or a keyword
//! (`--background`, `--radius 0.5%`), and the output guard (`--force`).

use crate::error::CliError;
use std::path::Path;
use tubecast_render::io::IoError;

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
pub fn parse_rgb(s: &str) -> Result<[f32; 3], String> {
    let srgb: [f32; 3] = match s {
        "white" => [1.0; 3],
        "black" => [0.0; 3],
        "grey" | "gray" => [0.5; 3],
        _ if s.starts_with('#') && s.len() == 7 && s[1..].chars().all(|c| c.is_ascii_hexdigit()) => {
            std::array::from_fn(|k| u8::from_str_radix(&s[1 + 2 * k..3 + 2 * k], 16).unwrap() as f32 / 255.0)
        }
        _ => {
            let v: Vec<f32> = s.split(',').filter_map(|t| t.trim().parse::<f32>().ok()).collect();
            if v.len() != 3 || s.split(',').count() != 3 || v.iter().any(|c| !(0.0..=1.0).contains(c)) {
                return Err(format!("{s:?}: use #rrggbb, r,g,b in [0, 1], white, black or grey"));
            }
            [v[0], v[1], v[2]]
        }
    };
    Ok(srgb.map(linear))
}

/// `--background`: `transparent` or a colour ([`parse_rgb`]).
pub fn parse_background(s: &str) -> Result<Background, String> {
    if s == "transparent" || s == "none" {
        return Ok(Background::Transparent);
    }
    parse_rgb(s).map(Background::Color)
}

/// `--radius`: absolute (`0.2`) or relative to the scene's size (`0.5%`: half a percent of the
/// diagonal of the bounding box of the points).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Radius {
    /// In the file's units.
    Absolute(f64),
    /// A fraction of the bounding-box diagonal.
    Relative(f64),
}

/// Parse `--radius`.
pub fn parse_radius(s: &str) -> Result<Radius, String> {
    let bad = || format!("{s:?}: a positive number (file units) or a percentage of the scene size like 0.5%");
    let (num, rel) = match s.strip_suffix('%') {
        Some(n) => (n, true),
        None => (s, false),
    };
    let v = num.trim().parse::<f64>().map_err(|_| bad())?;
    if !(v.is_finite() && v > 0.0) {
        return Err(bad());
    }
    Ok(if rel { Radius::Relative(v / 100.0) } else { Radius::Absolute(v) })
}

/// Refuse to overwrite an existing `path` unless `force`.
pub fn check_out(path: &Path, force: bool) -> Result<(), CliError> {
    if !force && path.exists() {
        let problem = "exists; pass --force to overwrite it";
        return Err(CliError::Io(IoError::file(&path.display().to_string(), problem)));
    }
    Ok(())
}
