//! Why a scene could not be built or loaded.

use super::MAX_COORD;
use crate::io::IoError;
use std::fmt;
use tubecast::GeometryError;

/// Why a scene could not be built or loaded. `file` is the name the caller gave the input.
#[derive(Clone, Debug, PartialEq)]
pub enum SceneError {
    /// A reader failed.
    Io(IoError),
    /// An SWC node names a parent id that no node has.
    MissingParent {
        /// Input name.
        file: String,
        /// The parent id.
        parent: i64,
        /// The node's id.
        node: i64,
    },
    /// The radius for points without one is not a positive number.
    DefaultRadius(f64),
    /// The input has no nodes.
    NoNodes {
        /// Input name.
        file: String,
    },
    /// The input has more nodes than `u32` link indices can address.
    TooManyNodes {
        /// Input name.
        file: String,
    },
    /// A node's coordinate or radius is not finite or exceeds [`MAX_COORD`].
    OutOfRange {
        /// Input name.
        file: String,
        /// Node index.
        node: usize,
    },
    /// A node has a negative radius.
    NegativeRadius {
        /// Input name.
        file: String,
        /// Node index.
        node: usize,
        /// The radius.
        radius: f64,
    },
    /// A link has zero radius at both ends, so no volume.
    NoVolume {
        /// Input name.
        file: String,
        /// Link index.
        link: usize,
        /// Its node indices.
        nodes: [u32; 2],
    },
    /// A link cannot be stored as a spline primitive ([`super::Prim::from_quad`]).
    Spline {
        /// Link index.
        link: u32,
        /// Its node indices.
        nodes: [u32; 2],
        /// What the kernel rejected.
        cause: GeometryError,
    },
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Io(e) => e.fmt(f),
            Self::MissingParent { file, parent, node } => {
                write!(f, "{file}: parent {parent} of node {node} does not exist")
            }
            Self::DefaultRadius(r) => write!(f, "radius {r} must be a positive number"),
            Self::NoNodes { file } => write!(f, "{file}: no nodes"),
            Self::TooManyNodes { file } => write!(f, "{file}: too many nodes"),
            Self::OutOfRange { file, node } => {
                write!(f, "{file}: node {node} has a coordinate or radius that is not finite or exceeds {MAX_COORD:e}")
            }
            Self::NegativeRadius { file, node, radius } => {
                write!(f, "{file}: node {node} has negative radius {radius}")
            }
            Self::NoVolume { file, link, nodes: [a, b] } => {
                write!(f, "{file}: link {link} (nodes {a} and {b}) has zero radius at both ends, so no volume")
            }
            Self::Spline { link, nodes: [a, b], cause } => {
                write!(f, "link {link} (nodes {a} and {b}): cannot model it as a spline: {cause}")
            }
        }
    }
}

impl std::error::Error for SceneError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Io(e) => Some(e),
            Self::Spline { cause, .. } => Some(cause),
            _ => None,
        }
    }
}

impl From<IoError> for SceneError {
    fn from(e: IoError) -> Self {
        Self::Io(e)
    }
}
