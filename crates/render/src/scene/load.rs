//! Loading a scene from a file, streamed ([`crate::io::stream`]), with the fallback for
//! placeholder radii and a selection of streamlines.

use super::{Links, Node, Radii, Scene, SceneError};
use crate::estimate;
use crate::io::data::Field;
use crate::io::stream::{Flow, Line, Selection};
use crate::io::{self, swc::SwcFile, IoError};
use indicatif::ProgressBar;
use std::collections::HashMap;
use std::io::BufRead;
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
        let all = Selection::default();
        Self::load_selected(path, opts, &all, false, &ProgressBar::hidden()).map(|(s, r, _)| (s, r))
    }

    /// [`Self::load_with`], also returning the file's data as per-node fields (one item per
    /// node) for colouring, named `scalar:NAME` (TrackVis scalars, the `.tsf` beside a `.tck`
    /// — `scalar:tsf` —, TRX `dpv`) and `property:NAME` (TrackVis properties, TRX `dps`, each
    /// node of a streamline getting its streamline's value), plus `scalar:radius` and
    /// `scalar:type` (SWC structure type; 0 for other formats) for every file.
    pub fn load_fields(path: &Path, opts: &LoadOptions) -> Result<(Self, LoadReport, Vec<Field>), SceneError> {
        Self::load_selected(path, opts, &Selection::default(), true, &ProgressBar::hidden())
    }

    /// [`Self::load_fields`] streaming the file ([`crate::io::stream`]): only the streamlines
    /// `sel` keeps are stored (the others are read past, never allocated, and reading stops
    /// after the last one `sel.max_streamlines` allows), built straight into the scene; the
    /// file's data fields are kept only with `data` (without it the result has no fields and
    /// a `.tsf` beside a `.tck` is not read). `progress` advances by the bytes read.
    /// A selection on an SWC file (one tree, not streamlines) is an error.
    pub fn load_selected(
        path: &Path,
        opts: &LoadOptions,
        sel: &Selection,
        data: bool,
        progress: &ProgressBar,
    ) -> Result<(Self, LoadReport, Vec<Field>), SceneError> {
        let name = path.display().to_string();
        if let Some(r) = opts.min_radius {
            if !(r.is_finite() && r > 0.0) {
                return Err(SceneError::MinRadius(r));
            }
        }
        sel.check().map_err(|p| SceneError::Io(IoError::file(&name, p)))?;
        let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
        if !matches!(ext.as_str(), "swc" | "trk" | "tck" | "trx" | "obj") {
            let problem = format!("unknown extension {ext:?} (expected .swc, .trk, .tck, .trx or .obj)");
            return Err(SceneError::Io(IoError::file(&name, problem)));
        }
        let (file, len) = io::stream::open(path)?;
        let file = progress.wrap_read(file);
        if ext == "swc" {
            return load_swc(file, &name, opts, sel, data);
        }
        if !(opts.default_radius.is_finite() && opts.default_radius > 0.0) {
            return Err(SceneError::DefaultRadius(opts.default_radius));
        }
        let hint = if ext == "obj" { 0 } else { estimate::probe(path).map(|c| c.points).unwrap_or(0) };
        let mut sink = Sink::new(sel, data, opts.default_radius, hint, &name);
        let (scalars, properties) = match ext.as_str() {
            "trk" => {
                let info = io::trk::stream(file, &name, &mut |l| sink.push(l))?;
                (info.scalars, info.properties)
            }
            "tck" => load_tck(file, path, len, &mut sink)?,
            "trx" => {
                // The streamlines through `file` (its progress), each data array through the
                // file opened again (TRX reads them side by side, streamline by streamline).
                let mut first = Some(file);
                let mut open = || match first.take() {
                    Some(f) => Ok(f),
                    None => io::stream::open(path).map(|(f, _)| ProgressBar::hidden().wrap_read(f)),
                };
                let info = io::trx::stream_from(&mut open, &name, data, &mut |l| sink.push(l))?;
                (info.scalars, info.properties)
            }
            _ => return load_obj(file, &name, opts, sel, data),
        };
        sink.finish(opts, &(scalars, properties))
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

/// An SWC file: a tree, so a selection of streamlines is refused.
fn load_swc(
    r: impl BufRead,
    name: &str,
    opts: &LoadOptions,
    sel: &Selection,
    data: bool,
) -> Result<(Scene, LoadReport, Vec<Field>), SceneError> {
    if !sel.is_all() {
        let problem = "--max-streamlines and --subsample select streamlines (.trk, .tck, .trx, .obj); \
                       an SWC file is one tree of nodes: drop them, or cut the tree first";
        return Err(SceneError::Io(IoError::file(name, problem)));
    }
    let file = io::swc::read_from(r, name, opts.min_radius)?;
    if opts.min_radius.is_none() {
        check_swc_volume(&file, name)?;
    }
    let parts = Scene::swc_parts(&file.nodes, name)?;
    drop(file.nodes);
    let report = LoadReport { replaced: file.replaced, placeholders: file.placeholders };
    let scene = Scene::finish(parts, name)?;
    let fields = if data { node_fields(&scene, Vec::new(), Vec::new()) } else { Vec::new() };
    Ok((scene, report, fields))
}

/// An OBJ file, streamed ([`io::obj::stream`]: its polylines index vertices anywhere before
/// them, so the vertices are kept while reading), the selection applied as it is read.
fn load_obj(
    r: impl BufRead,
    name: &str,
    opts: &LoadOptions,
    sel: &Selection,
    data: bool,
) -> Result<(Scene, LoadReport, Vec<Field>), SceneError> {
    let (mut lines, mut i, max) = (Vec::new(), 0, sel.max_streamlines.unwrap_or(usize::MAX));
    io::obj::stream(r, name, &mut |l| {
        (sel.keeps(i) && lines.len() < max).then(|| lines.push(l));
        i += 1;
        if lines.len() >= max {
            Flow::Stop
        } else {
            Flow::Continue
        }
    })?;
    let (nodes, links, kinds, mut radii) = Scene::polyline_parts(&lines, opts.default_radius)?;
    let report = opts.min_radius.map(|r| raise(&mut radii, nodes.len(), r)).unwrap_or_default();
    let scene = Scene::finish((nodes, links, kinds, radii), name)?;
    let fields = if data { node_fields(&scene, Vec::new(), Vec::new()) } else { Vec::new() };
    Ok((scene, report, fields))
}

/// A `.tck` file, with (when the sink keeps data) the `.tsf` beside it (same stem) read in
/// step, one value per point, as field `tsf`.
fn load_tck(file: impl BufRead, path: &Path, len: u64, sink: &mut Sink) -> Result<Groups, SceneError> {
    let name = path.display().to_string();
    let mut tck = io::tck::Records::new(file, &name, Some(len), false)?;
    let tsf_path = path.with_extension("tsf");
    let tsf_name = tsf_path.display().to_string();
    let mut tsf = match sink.data && tsf_path.is_file() {
        true => {
            let (f, tlen) = io::stream::open(&tsf_path)?;
            Some(io::tck::Records::new(f, &tsf_name, Some(tlen), true)?)
        }
        false => None,
    };
    let differ = || {
        let problem = "its streamline lengths differ from the .tck's (not its companion?)";
        SceneError::Io(IoError::file(&tsf_name, problem))
    };
    while let Some(l) = tck.next_line()? {
        let values = match tsf.as_mut() {
            Some(t) => Some(t.next_values()?.ok_or_else(differ)?),
            None => None,
        };
        if values.is_some_and(|v| v.len() != l.points.len()) {
            return Err(differ());
        }
        if sink.push(Line { scalars: values.unwrap_or(&[]), ..l }) == Flow::Stop {
            return Ok((tsf.map(|_| vec![("tsf".to_string(), 0, 1)]).unwrap_or_default(), Vec::new()));
        }
    }
    let Some(mut t) = tsf else { return Ok((Vec::new(), Vec::new())) };
    if t.next_values()?.is_some() {
        return Err(differ());
    }
    Ok((vec![("tsf".to_string(), 0, 1)], Vec::new()))
}

/// Column groups `(name, first column, width)` of the per-point and per-streamline data.
type Groups = (Vec<(String, usize, usize)>, Vec<(String, usize, usize)>);

/// The scene under construction from streamed [`Line`]s: the kept ones go straight into nodes
/// and links (and, with `data`, their values).
struct Sink<'a> {
    sel: &'a Selection,
    data: bool,
    radius: f64,
    name: &'a str,
    kept: usize,
    nodes: Vec<Node>,
    links: Links,
    scalars: Vec<f64>,
    properties: Vec<f64>,
    /// Points of each kept streamline (with `data`: per-streamline values go to its nodes).
    lens: Vec<usize>,
    error: Option<SceneError>,
}

impl<'a> Sink<'a> {
    /// `hint`: the points the file holds (0: unknown), to reserve the kept share at once.
    fn new(sel: &'a Selection, data: bool, radius: f64, hint: u64, name: &'a str) -> Self {
        let share = (hint as f64 * sel.subsample.unwrap_or(1.0).min(1.0) * 1.01) as usize;
        let share = share.min(u32::MAX as usize);
        let (nodes, links) = (Vec::with_capacity(share), Links::default());
        let (scalars, properties, lens) = (Vec::new(), Vec::new(), Vec::new());
        Self { sel, data, radius, name, kept: 0, nodes, links, scalars, properties, lens, error: None }
    }

    /// Take streamline `l` if the selection keeps it; stop after the last one it allows.
    fn push(&mut self, l: Line<'_>) -> Flow {
        if self.sel.max_streamlines.is_some_and(|m| self.kept >= m) {
            return Flow::Stop;
        }
        if !self.sel.keeps(l.index as u64) {
            return Flow::Continue;
        }
        let base = self.nodes.len();
        if base + l.points.len() > u32::MAX as usize - 1 {
            self.error = Some(SceneError::TooManyNodes { file: self.name.to_string() });
            return Flow::Stop;
        }
        self.nodes.extend(l.points.iter().map(|&pos| Node { pos }));
        self.links.extend((base + 1..self.nodes.len()).map(|i| [i as u32 - 1, i as u32]));
        if self.data {
            self.scalars.extend_from_slice(l.scalars);
            self.properties.extend_from_slice(l.properties);
            self.lens.push(l.points.len());
        }
        self.kept += 1;
        match self.sel.max_streamlines.is_some_and(|m| self.kept >= m) {
            true => Flow::Stop,
            false => Flow::Continue,
        }
    }

    /// The scene, with the data fields named by `groups` (per point, per streamline).
    fn finish(self, opts: &LoadOptions, groups: &Groups) -> Loaded {
        if let Some(e) = self.error {
            return Err(e);
        }
        let (nodes, mut radii) = (self.nodes, Radii::uniform(self.radius));
        let report = opts.min_radius.map(|r| raise(&mut radii, nodes.len(), r)).unwrap_or_default();
        let scene = Scene::finish((nodes, self.links, Vec::new(), radii), self.name)?;
        if !self.data {
            return Ok((scene, report, Vec::new()));
        }
        let width = |g: &[(String, usize, usize)]| g.iter().map(|c| c.2).sum::<usize>();
        let (wp, wl) = (width(&groups.0), width(&groups.1));
        let per_point = if wp == 0 { Vec::new() } else { io::trk::fields(&groups.0, &self.scalars, wp) };
        let per_line = if wl == 0 { Vec::new() } else { io::trk::fields(&groups.1, &self.properties, wl) };
        let per_line = per_line.into_iter().map(|f| {
            let values = self.lens.iter().enumerate().flat_map(|(i, &n)| {
                let item = &f.values[i * f.width..(i + 1) * f.width];
                std::iter::repeat(item).take(n).flatten().copied()
            });
            Field { values: values.collect(), ..f }
        });
        let fields = node_fields(&scene, per_point, per_line.collect());
        Ok((scene, report, fields))
    }
}

/// What a load returns.
type Loaded = Result<(Scene, LoadReport, Vec<Field>), SceneError>;

/// Per-node fields of a scene (nodes in point order): radius, type, then the file's
/// per-point fields and its per-streamline fields spread to their nodes.
fn node_fields(scene: &Scene, per_point: Vec<Field>, per_line: Vec<Field>) -> Vec<Field> {
    let n = scene.nodes.len();
    let mut out = vec![
        Field { name: "scalar:radius".into(), width: 1, values: (0..n).map(|i| scene.radius(i)).collect() },
        Field { name: "scalar:type".into(), width: 1, values: (0..n).map(|i| scene.kind(i) as f64).collect() },
    ];
    for f in per_point {
        if f.values.len() == n * f.width {
            out.push(Field { name: format!("scalar:{}", f.name), ..f });
        }
    }
    for f in per_line {
        out.push(Field { name: format!("property:{}", f.name), ..f });
    }
    out
}

/// Raise every radius of `n` nodes below `r` to `r`, counting.
fn raise(radii: &mut Radii, n: usize, r: f64) -> LoadReport {
    let (replaced, placeholders) = radii.raise(r, n);
    LoadReport { replaced, placeholders }
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
