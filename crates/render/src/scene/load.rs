//! Loading a scene from a file, with the fallback for placeholder radii.

use super::{Node, Scene, SceneError};
use crate::io::data::{Field, Tractogram};
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
    /// Load a scene from a file, by extension: `.swc`, `.trk`, `.tck`, `.trx`, `.obj`. Formats without
    /// radii (and OBJ vertices without one) use `default_radius`. A file without streamlines
    /// or nodes gives the empty scene. ([`Self::load_with`] without a minimum radius.)
    pub fn load(path: &Path, default_radius: f64) -> Result<Self, SceneError> {
        Ok(Self::load_with(path, &LoadOptions { default_radius, min_radius: None })?.0)
    }

    /// [`Self::load`] with a minimum radius ([`LoadOptions`]); the report counts the radii
    /// it replaced.
    pub fn load_with(path: &Path, opts: &LoadOptions) -> Result<(Self, LoadReport), SceneError> {
        Self::load_fields(path, opts).map(|(s, r, _)| (s, r))
    }

    /// [`Self::load_with`], also returning the file's data as per-node fields (one item per
    /// node) for colouring, named `scalar:NAME` (TrackVis scalars, the `.tsf` beside a `.tck`
    /// — `scalar:tsf` —, TRX `dpv`) and `property:NAME` (TrackVis properties, TRX `dps`, each
    /// node of a streamline getting its streamline's value), plus `scalar:radius` and
    /// `scalar:type` (SWC structure type; 0 for other formats) for every file.
    pub fn load_fields(path: &Path, opts: &LoadOptions) -> Result<(Self, LoadReport, Vec<Field>), SceneError> {
        let name = path.display().to_string();
        if let Some(r) = opts.min_radius {
            if !(r.is_finite() && r > 0.0) {
                return Err(SceneError::MinRadius(r));
            }
        }
        let data = io::read_bytes(path)?;
        let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
        let t = match ext.as_str() {
            "swc" => {
                let file = io::swc::read_with(&data, &name, opts.min_radius)?;
                if opts.min_radius.is_none() {
                    check_swc_volume(&file, &name)?;
                }
                let (nodes, links) = Self::swc_parts(&file.nodes, &name)?;
                let report = LoadReport { replaced: file.replaced, placeholders: file.placeholders };
                let scene = Self::finish(nodes, links, &name)?;
                let fields = node_fields(&scene, &Tractogram::default());
                return Ok((scene, report, fields));
            }
            "trk" => io::trk::read_data(&data, &name)?.1,
            "tck" => with_tsf(path, io::tck::read(&data, &name)?)?,
            "trx" => io::trx::read(&data, &name)?,
            "obj" => Tractogram { lines: io::obj::read(&data, &name)?, ..Tractogram::default() },
            _ => {
                let problem = format!("unknown extension {ext:?} (expected .swc, .trk, .tck, .trx or .obj)");
                return Err(SceneError::Io(IoError::file(&name, problem)));
            }
        };
        let (mut nodes, links) = Self::polyline_parts(&t.lines, opts.default_radius)?;
        let report = opts.min_radius.map(|r| raise(&mut nodes, r)).unwrap_or_default();
        let scene = Self::finish(nodes, links, &name)?;
        let fields = node_fields(&scene, &t);
        Ok((scene, report, fields))
    }

    /// Colour by the field called `key` (`scalar:NAME` or `property:NAME`, from
    /// [`Self::load_fields`]): [`Self::values`] gets its values, the Euclidean norm of each
    /// item for a field of several columns (a colour, a vector). An unknown key is an error
    /// listing the fields there are.
    pub fn select_values(&mut self, fields: &[Field], key: &str) -> Result<(), SceneError> {
        let Some(f) = fields.iter().find(|f| f.name == key) else {
            let have: Vec<&str> = fields.iter().map(|f| f.name.as_str()).collect();
            let problem = format!("no data field {key:?} (the file has: {})", have.join(", "));
            return Err(SceneError::Io(IoError::file("--color", problem)));
        };
        self.values = (0..f.len()).map(|i| (0..f.width).map(|c| f.get(i, c).powi(2)).sum::<f64>().sqrt()).collect();
        if f.width == 1 {
            self.values = f.values.clone();
        }
        Ok(())
    }
}

/// The scalars of the `.tsf` file beside a `.tck` (same stem), if there is one: one value per
/// point, as field `tsf`.
fn with_tsf(path: &Path, lines: Vec<io::Polyline>) -> Result<Tractogram, SceneError> {
    let mut t = Tractogram { lines, ..Tractogram::default() };
    let tsf = path.with_extension("tsf");
    if tsf.is_file() {
        let name = tsf.display().to_string();
        let values = io::tck::read_tsf(&io::read_bytes(&tsf)?, &name)?;
        let lens: Vec<usize> = values.iter().map(Vec::len).collect();
        if lens != t.lines.iter().map(|l| l.points.len()).collect::<Vec<_>>() {
            let problem = "its streamline lengths differ from the .tck's (not its companion?)";
            return Err(SceneError::Io(IoError::file(&name, problem)));
        }
        t.per_point.push(Field { name: "tsf".into(), width: 1, values: values.concat() });
    }
    Ok(t)
}

/// Per-node fields of a scene built from `t` (nodes in point order).
fn node_fields(scene: &Scene, t: &Tractogram) -> Vec<Field> {
    let n = scene.nodes.len();
    let mut out = vec![
        Field { name: "scalar:radius".into(), width: 1, values: scene.nodes.iter().map(|v| v.radius).collect() },
        Field { name: "scalar:type".into(), width: 1, values: scene.nodes.iter().map(|v| v.kind as f64).collect() },
    ];
    for f in &t.per_point {
        if f.values.len() == n * f.width {
            out.push(Field { name: format!("scalar:{}", f.name), ..f.clone() });
        }
    }
    for f in &t.per_line {
        let values = t.lines.iter().enumerate().flat_map(|(i, l)| {
            let item = &f.values[i * f.width..(i + 1) * f.width];
            std::iter::repeat(item).take(l.points.len()).flatten().copied()
        });
        out.push(Field { name: format!("property:{}", f.name), width: f.width, values: values.collect() });
    }
    out
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
