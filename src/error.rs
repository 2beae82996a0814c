//! [`GeometryError`]: what constructors and validators report for bad input.

/// Invalid geometry or rays given to a constructor or validator.
///
/// ```
/// use tubecast::{GeometryError, RoundCone, V3};
/// let bad = RoundCone::new(V3::new(0.0, 0.0, 0.0), -1.0, V3::new(1.0, 0.0, 0.0), 0.5);
/// assert_eq!(bad, Err(GeometryError::NegativeRadius));
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GeometryError {
    /// A coordinate, radius or extent is NaN or infinite.
    NonFinite {
        /// What was not finite.
        what: &'static str,
    },
    /// A radius is negative.
    NegativeRadius,
    /// A radius is zero where a volume is required.
    ZeroRadius,
    /// A ray direction is zero.
    ZeroDirection,
    /// A non-zero size is so small that its square (nearly) underflows.
    TooSmall {
        /// What was too small.
        what: &'static str,
    },
    /// A ray range is NaN or has `t_min > t_max`.
    BadRange,
}

impl core::fmt::Display for GeometryError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::NonFinite { what } => write!(f, "{what} is NaN or infinite"),
            Self::NegativeRadius => write!(f, "radius is negative"),
            Self::ZeroRadius => write!(f, "radius is zero (the primitive has no volume)"),
            Self::ZeroDirection => write!(f, "ray direction is zero (or its squared length underflows)"),
            Self::TooSmall { what } => write!(f, "{what} is too small"),
            Self::BadRange => write!(f, "ray range is NaN or t_min > t_max"),
        }
    }
}

impl std::error::Error for GeometryError {}
