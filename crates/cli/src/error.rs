//! The one error type of the command line.

use std::fmt;
use std::path::PathBuf;
use tubecast_render::io::IoError;
use tubecast_render::mesh::MeshError;
use tubecast_render::render::RenderError;
use tubecast_render::scene::SceneError;

/// Why a command failed; printed as `tubecast: error: {self}`.
#[derive(Debug)]
pub enum CliError {
    /// Reading or writing a file.
    Io(IoError),
    /// Loading or modelling the scene.
    Scene(SceneError),
    /// Camera, render options or the PNG.
    Render(RenderError),
    /// `generate`: `--count × --segments` outside `1..=max`.
    SceneSize {
        /// The largest product.
        max: usize,
    },
    /// `generate neurons`: `--n` outside `1..=40`.
    NeuronsPerSide,
    /// `generate neurons` to a file that is not `.swc`.
    NeuronsNeedSwc(PathBuf),
    /// `--threads`: the worker pool could not be started.
    Threads(rayon::ThreadPoolBuildError),
    /// Tessellating the scene (`mesh`, `render --model mesh`).
    Mesh(MeshError),
    /// `render --model mesh` without `--tolerance`.
    MeshTolerance,
    /// `simplify --tolerance` not a finite number ≥ 0.
    Tolerance(f64),
    /// The scene would not fit in memory (estimated before loading).
    Memory(tubecast_render::estimate::TooLarge),
    /// `--model quantized` options.
    Quantized(crate::cmd_quantized::QuantError),
}

impl fmt::Display for CliError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Io(e) => e.fmt(f),
            Self::Scene(e) => e.fmt(f),
            Self::Render(e) => e.fmt(f),
            Self::SceneSize { max } => write!(f, "--count × --segments must be between 1 and {max}"),
            Self::NeuronsPerSide => f.write_str("--n must be in 1..=40"),
            Self::NeuronsNeedSwc(p) => write!(f, "{}: neuron assemblies branch; write them as .swc", p.display()),
            Self::Threads(e) => write!(f, "--threads: {e}"),
            Self::Mesh(e) => e.fmt(f),
            Self::MeshTolerance => f.write_str("--model mesh needs --tolerance EPS"),
            Self::Tolerance(t) => write!(f, "--tolerance {t} must be a finite number ≥ 0"),
            Self::Memory(e) => e.fmt(f),
            Self::Quantized(e) => e.fmt(f),
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

impl From<crate::cmd_quantized::QuantError> for CliError {
    fn from(e: crate::cmd_quantized::QuantError) -> Self {
        Self::Quantized(e)
    }
}

impl From<MeshError> for CliError {
    fn from(e: MeshError) -> Self {
        Self::Mesh(e)
    }
}
