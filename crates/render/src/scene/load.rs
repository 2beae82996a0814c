//! Loading a scene from a file, with the fallback for placeholder radii.

use super::{Node, Scene, SceneError};
use crate::io::{self, swc::SwcFile, IoError};
use std::collections::HashMap;
use std::path::Path;

/// How [`Scene::load_with`] turns a file into a scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LoadOptions {
    /// Radius of points the file gives none (`.trk`, `.tck`, OBJ vertices without one); a
    /// positive finite number.
    pub default_radius: f64,
    /// `Some(R)`: every radius below `R` — SWC placeholders `≤ 0` included — becomes `R`
    /// (`R` a positive finite number). `None`: radii are kept as read; a negative SWC radius,
    /// or an SWC link with radius 0 at both ends, is an error naming the line.
    pub min_radius: Option<f64>,
}

impl Default for LoadOptions {
    /// The `tubecast` defaults: radius 0.2, no minimum radius.
    fn default() -> Self {
        Self { default_radius: 0.2, min_radius: None }
    }
}

/// What [`Scene::load_with`] changed while loading.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LoadReport {
    /// Node radii raised to [`LoadOptions::min_radius`].
    pub replaced: usize,
    /// Of those, the radii that were `≤ 0` (placeholders).
    pub placeholders: usize,
}

impl Scene {
    /// Load a scene from a file, by extension: `.swc`, `.trk`, `.tck`, `.obj`. Formats without
    /// radii (and OBJ vertices without one) use `default_radius`. A file without streamlines
    /// or nodes gives the empty scene. ([`Self::load_with`] without a minimum radius.)
    pub fn load(path: &Path, default_radius: f64) -> Result<Self, SceneError> {
        Ok(Self::load_with(path, &LoadOptions { default_radius, min_radius: None })?.0)
    }

    /// [`Self::load`] with a minimum radius ([`LoadOptions`]); the report counts the radii
    /// it replaced.
    pub fn load_with(path: &Path, opts: &LoadOptions) -> Result<(Self, LoadReport), SceneError> {
        let name = path.display().to_string();
        if let Some(r) = opts.min_radius {
            if !(r.is_finite() && r > 0.0) {
                return Err(SceneError::MinRadius(r));
            }
        }
        let data = io::read_bytes(path)?;
        let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
        let lines = match ext.as_str() {
            "swc" => {
                let file = io::swc::read_with(&data, &name, opts.min_radius)?;
                if opts.min_radius.is_none() {
                    check_swc_volume(&file, &name)?;
                }
                let (nodes, links) = Self::swc_parts(&file.nodes, &name)?;
                let report = LoadReport { replaced: file.replaced, placeholders: file.placeholders };
                return Ok((Self::finish(nodes, links, &name)?, report));
            }
            "trk" => io::trk::read(&data, &name)?.1,
            "tck" => io::tck::read(&data, &name)?,
            "obj" => io::obj::read(&data, &name)?,
            _ => {
                let problem = format!("unknown extension {ext:?} (expected .swc, .trk, .tck or .obj)");
                return Err(SceneError::Io(IoError::file(&name, problem)));
            }
        };
        let (mut nodes, links) = Self::polyline_parts(&lines, opts.default_radius)?;
        let report = opts.min_radius.map(|r| raise(&mut nodes, r)).unwrap_or_default();
        Ok((Self::finish(nodes, links, &name)?, report))
    }
}

/// Raise every radius below `r` to `r`, counting.
fn raise(nodes: &mut [Node], r: f64) -> LoadReport {
    let mut rep = LoadReport::default();
    for n in nodes.iter_mut().filter(|n| n.radius < r) {
        rep.replaced += 1;
        rep.placeholders += (n.radius <= 0.0) as usize;
        n.radius = r;
    }
    rep
}

/// The first SWC node (in file order) whose radius 0 leaves a link without volume: its parent
/// has radius 0 too, or it has neither parent nor children. An error naming its line.
fn check_swc_volume(file: &SwcFile, name: &str) -> Result<(), SceneError> {
    let index: HashMap<i64, usize> = file.nodes.iter().enumerate().map(|(i, n)| (n.id, i)).collect();
    let mut has_child = vec![false; file.nodes.len()];
    for n in &file.nodes {
        if let Some(&p) = index.get(&n.parent) {
            has_child[p] = true;
        }
    }
    for (i, n) in file.nodes.iter().enumerate() {
        if n.radius != 0.0 {
            continue;
        }
        let parent = index.get(&n.parent).map(|&p| (p, &file.nodes[p]));
        let culprit = match parent {
            Some((p, pn)) if pn.radius == 0.0 => Some(Some((pn.id, file.lines[p]))),
            None if !has_child[i] => Some(None),
            _ => None,
        };
        if let Some(parent) = culprit {
            return Err(SceneError::ZeroRadius { file: name.to_string(), line: file.lines[i], node: n.id, parent });
        }
    }
    Ok(())
}
