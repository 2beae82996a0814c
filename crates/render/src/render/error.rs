//! Why a render could not start or its image could not be written.

use crate::io::IoError;
use std::fmt;

/// A camera or option that cannot be used, or an image that cannot be written.
#[derive(Clone, Debug, PartialEq)]
pub enum RenderError {
    /// Camera eye, target or up is not finite.
    NonFiniteCamera,
    /// The field of view (degrees) is not in `(0, 180)`.
    FieldOfView(f64),
    /// The image size is not `1..=32768` per side.
    ImageSize {
        /// Width.
        width: u32,
        /// Height.
        height: u32,
    },
    /// Camera eye and look-at point coincide.
    EyeAtTarget,
    /// The camera's up direction is zero or parallel to the view direction.
    UpParallel,
    /// The scene bounds to frame are empty or not finite.
    EmptyBounds,
    /// Opacity not in `(0, 1]`.
    Opacity(f64),
    /// More than 1024 ambient-occlusion rays.
    AoRays(u32),
    /// Antialiasing samples per side outside `1..=16`.
    Antialiasing(u32),
    /// A background component outside `[0, 1]`.
    Background,
    /// A solid-colour component outside `[0, 1]`.
    Colour,
    /// The PNG could not be written.
    Io(IoError),
}

impl fmt::Display for RenderError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NonFiniteCamera => f.write_str("camera eye, target and up must be finite"),
            Self::FieldOfView(fov) => write!(f, "field of view {fov} must be in (0, 180) degrees"),
            Self::ImageSize { width, height } => write!(f, "image size {width}x{height} must be 1..=32768 per side"),
            Self::EyeAtTarget => f.write_str("camera eye and look-at point coincide"),
            Self::UpParallel => f.write_str("camera up direction is zero or parallel to the view direction"),
            Self::EmptyBounds => f.write_str("scene bounds are empty or not finite"),
            Self::Opacity(a) => write!(f, "opacity {a} must be in (0, 1]"),
            Self::AoRays(n) => write!(f, "ambient-occlusion rays {n} exceed 1024"),
            Self::Antialiasing(n) => write!(f, "antialiasing {n} samples per side must be in 1..=16"),
            Self::Background => f.write_str("background components must be in [0, 1]"),
            Self::Colour => f.write_str("colour components must be in [0, 1]"),
            Self::Io(e) => e.fmt(f),
        }
    }
}

impl std::error::Error for RenderError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Io(e) => Some(e),
            _ => None,
        }
    }
}

impl From<IoError> for RenderError {
    fn from(e: IoError) -> Self {
        Self::Io(e)
    }
}
