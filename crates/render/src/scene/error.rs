//! Why a scene could not be built or loaded.

use super::{MAX_COORD, MIN_RADIUS};
use crate::io::swc::MIN_RADIUS_HINT;
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
    /// Two SWC rows share an id (so a parent id would name either).
    DuplicateId {
        /// Input name.
        file: String,
        /// The id.
        id: i64,
    },
    /// The radius for points without one is not a positive number.
    DefaultRadius(f64),
    /// The minimum radius is not a positive number.
    MinRadius(f64),
    /// An SWC node's radius 0 (a placeholder, most likely) leaves a link without volume: its
    /// parent's radius is 0 too, or it has no parent and no children.
    ZeroRadius {
        /// Input name.
        file: String,
        /// The node's 1-based line.
        line: usize,
        /// The node's id.
        node: i64,
        /// Its parent's id and line, when the link to the parent is the one without volume.
        parent: Option<(i64, usize)>,
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
    /// A node's radius is not zero but below [`MIN_RADIUS`]: its square underflows in the
    /// renderer's `f32` primitives.
    RadiusTooSmall {
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
            Self::DuplicateId { file, id } => write!(f, "{file}: two nodes have id {id}"),
            Self::DefaultRadius(r) => write!(f, "radius {r} must be a positive number"),
            Self::MinRadius(r) => write!(f, "minimum radius {r} must be a positive number"),
            Self::ZeroRadius { file, line, node, parent: Some((p, pl)) } => write!(
                f,
                "{file}: line {line}: node {node} and its parent {p} (line {pl}) both have radius 0, so the link \
                 between them has no volume ({MIN_RADIUS_HINT})"
            ),
            Self::ZeroRadius { file, line, node, parent: None } => write!(
                f,
                "{file}: line {line}: node {node} has radius 0 and no links, so it has no volume ({MIN_RADIUS_HINT})"
            ),
            Self::TooManyNodes { file } => write!(f, "{file}: too many nodes"),
            Self::OutOfRange { file, node } => {
                write!(f, "{file}: node {node} has a coordinate or radius that is not finite or exceeds {MAX_COORD:e}")
            }
            Self::NegativeRadius { file, node, radius } => {
                write!(f, "{file}: node {node} has negative radius {radius}")
            }
            Self::RadiusTooSmall { file, node, radius } => write!(
                f,
                "{file}: node {node} has radius {radius:e}, below the smallest non-zero radius the renderer \
                 resolves, {MIN_RADIUS:e} (2⁻⁴⁴: smaller ones underflow in its f32 primitives); \
                 scale the scene up (e.g. to micrometres), or raise such radii (`--min-radius R`)"
            ),
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
