//! The one error type of the command line. A leaf: it imports nothing of the crate.

use std::fmt;
use tubecast_render::io::IoError;
use tubecast_render::mesh::MeshError;
use tubecast_render::render::RenderError;
use tubecast_render::scene::SceneError;

/// Why a command failed; printed as `tubecast: error: {self}`.
#[derive(Debug)]
pub enum CliError {
    /// The command line asks for something impossible (a value out of range, flags that do
    /// not go together, an output format the command does not write): exit status 2, found
    /// before any work.
    Usage(String),
    /// Reading or writing a file.
    Io(IoError),
    /// Loading or modelling the scene.
    Scene(SceneError),
    /// Camera, render options or the PNG.
    Render(RenderError),
    /// `--threads`: the worker pool could not be started.
    Threads(rayon::ThreadPoolBuildError),
    /// Tessellating the scene (`mesh`, `render --model mesh`).
    Mesh(MeshError),
    /// The scene would not fit in memory (estimated before loading).
    Memory(tubecast_render::estimate::TooLarge),
    /// `--device gpu`: no adapter, or the device failed.
    #[cfg_attr(not(feature = "gpu"), allow(dead_code))]
    Gpu(String),
}

impl CliError {
    /// A usage error: `flag` and `value` named, and what is allowed.
    pub fn usage(msg: impl Into<String>) -> Self {
        Self::Usage(msg.into())
    }

    /// The process exit status: 2 for usage, 1 for a job that failed.
    pub fn exit_code(&self) -> u8 {
        match self {
            Self::Usage(_) => 2,
            _ => 1,
        }
    }
}

impl fmt::Display for CliError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Usage(m) => f.write_str(m),
            Self::Io(e) => e.fmt(f),
            Self::Scene(e) => e.fmt(f),
            Self::Render(e) => e.fmt(f),
            Self::Threads(e) => write!(f, "--threads: {e}"),
            Self::Mesh(e) => e.fmt(f),
            Self::Memory(e) => e.fmt(f),
            Self::Gpu(m) => f.write_str(m),
        }
    }
}

impl std::error::Error for CliError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Io(e) => Some(e),
            Self::Scene(e) => Some(e),
            Self::Render(e) => Some(e),
            Self::Mesh(e) => Some(e),
            _ => None,
        }
    }
}

impl From<IoError> for CliError {
    fn from(e: IoError) -> Self {
        Self::Io(e)
    }
}

impl From<SceneError> for CliError {
    fn from(e: SceneError) -> Self {
        Self::Scene(e)
    }
}

impl From<RenderError> for CliError {
    fn from(e: RenderError) -> Self {
        Self::Render(e)
    }
}

impl From<MeshError> for CliError {
    fn from(e: MeshError) -> Self {
        Self::Mesh(e)
    }
}
