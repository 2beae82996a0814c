//! TRX tractograms (`.trx`, <https://github.com/tee-ar-ex/trx-spec>): a zip archive (stored or
//! deflated) of flat little-endian arrays named `NAME[.DIM].DTYPE`, and `header.json`.
//!
//! * `header.json`: `NB_STREAMLINES`, `NB_VERTICES`, `VOXEL_TO_RASMM` (16 numbers),
//!   `DIMENSIONS` (3).
//! * `positions.3.{float16,float32,float64}`: `NB_VERTICES × 3` coordinates, RAS+ mm.
//! * `offsets.{uint32,uint64}`: `NB_STREAMLINES + 1` indices into the positions, the last
//!   being `NB_VERTICES` (what trx-python writes and reads).
//! * `dpv/NAME[.DIM].DTYPE`: data per vertex (`NB_VERTICES × DIM`), `dps/NAME[.DIM].DTYPE`:
//!   data per streamline, `groups/NAME.DTYPE`: streamline indices of a group. `dpg/`
//!   (data per group) is skipped.
//!
//! As trx-python, a header with zero streamlines or zero vertices is the empty tractogram, an
//! entry whose dtype is unknown is skipped, and missing `positions`/`offsets`, a name with more
//! than three dot-separated parts, or an array whose size does not match the header is an error.

use super::data::{Field, Tractogram};
use super::stream::{Flow, Line, Src};
use super::{IoError, Polyline};
use serde_json::Value;
use std::io::{Read, Seek};

/// An array entry of the archive: its index, folder, name, columns, dtype and byte size.
struct Entry {
    index: usize,
    folder: String,
    base: String,
    dim: usize,
    dtype: String,
    bytes: u64,
}

/// Bytes per value of numpy dtype `dtype`; `None` for an unknown dtype.
fn dtype_size(dtype: &str) -> Option<usize> {
    match dtype {
        "int8" | "uint8" | "bool" | "bit" => Some(1),
        "float16" | "int16" | "uint16" => Some(2),
        "float32" | "int32" | "uint32" => Some(4),
        "float64" | "int64" | "uint64" => Some(8),
        _ => None,
    }
}

/// Decode `bytes` of numpy dtype `dtype` (little endian) to `f64`; `None` for an unknown dtype.
fn decode(bytes: &[u8], dtype: &str) -> Option<Result<Vec<f64>, usize>> {
    macro_rules! conv {
        ($t:ty, $n:expr, $f:expr) => {{
            #[allow(clippy::modulo_one)]
            let ragged = bytes.len() % $n != 0;
            if ragged {
                return Some(Err($n));
            }
            Some(Ok(bytes.chunks_exact($n).map(|c| $f(<$t>::from_le_bytes(c.try_into().unwrap()))).collect()))
        }};
    }
    match dtype {
        "float16" => conv!(half::f16, 2, |v: half::f16| v.to_f64()),
        "float32" => conv!(f32, 4, |v: f32| v as f64),
        "float64" => conv!(f64, 8, |v: f64| v),
        "int8" => conv!(i8, 1, |v: i8| v as f64),
        "int16" => conv!(i16, 2, |v: i16| v as f64),
        "int32" => conv!(i32, 4, |v: i32| v as f64),
        "int64" => conv!(i64, 8, |v: i64| v as f64),
        "uint8" | "bool" | "bit" => conv!(u8, 1, |v: u8| v as f64),
        "uint16" => conv!(u16, 2, |v: u16| v as f64),
        "uint32" => conv!(u32, 4, |v: u32| v as f64),
        "uint64" => conv!(u64, 8, |v: u64| v as f64),
        _ => None,
    }
}

/// The header's non-negative integer `key`.
fn count(h: &Value, key: &str, name: &str) -> Result<usize, IoError> {
    h.get(key)
        .and_then(Value::as_u64)
        .map(|v| v as usize)
        .ok_or_else(|| IoError::file(name, format!("header.json: {key} is missing or not a non-negative integer")))
}

type Zip<R> = zip::ZipArchive<R>;

/// The array entries of the archive (skipping JSON, folders and unknown dtypes), from its
/// directory: nothing is decompressed.
fn entries<R: Read + Seek>(zip: &mut Zip<R>, name: &str) -> Result<Vec<Entry>, IoError> {
    let mut out = Vec::new();
    for index in 0..zip.len() {
        let f = zip.by_index(index).map_err(|e| IoError::file(name, format!("zip entry {index}: {e}")))?;
        let path = f.name().to_string();
        if f.is_dir() || path.ends_with(".json") {
            continue;
        }
        let (folder, file) = path.rsplit_once('/').unwrap_or(("", path.as_str()));
        let parts: Vec<&str> = file.split('.').collect();
        let (base, dim, dtype) = match parts.as_slice() {
            [b, t] => (*b, "1", *t),
            [b, d, t] => (*b, *d, *t),
            _ => return Err(IoError::file(name, format!("entry {path:?}: not NAME[.DIM].DTYPE"))),
        };
        let Some(size) = dtype_size(dtype) else { continue };
        if f.size() % size as u64 != 0 {
            let problem = format!("entry {path:?}: {} bytes is not a whole number of {size}-byte {dtype}", f.size());
            return Err(IoError::file(name, problem));
        }
        let dim = dim.parse::<usize>().ok().filter(|&d| d > 0);
        let dim =
            dim.ok_or_else(|| IoError::file(name, format!("entry {path:?}: dimension is not a positive integer")))?;
        let (folder, base, dtype) = (folder.to_string(), base.to_string(), dtype.to_string());
        out.push(Entry { index, folder, base, dim, dtype, bytes: f.size() });
    }
    Ok(out)
}

/// The values of entry `e`, decoded whole (offsets, data, groups: small beside positions).
fn values<R: Read + Seek>(zip: &mut Zip<R>, e: &Entry, name: &str) -> Result<Vec<f64>, IoError> {
    let path = format!("{}{}", e.folder, e.base);
    let mut f = zip.by_index(e.index).map_err(|err| IoError::file(name, format!("entry {path:?}: {err}")))?;
    let mut bytes = Vec::new();
    // At most one byte more than the directory declares: enough to tell a longer entry apart
    // without reading a lying one to its end.
    (&mut f)
        .take(e.bytes.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(|err| IoError::file(name, format!("entry {path:?}: {err}")))?;
    // The counts checked against the directory's sizes must be the counts decoded: an entry
    // whose data are shorter or longer than its directory record says is an error, not a
    // shorter array (which would index past its end).
    if bytes.len() as u64 != e.bytes {
        let problem = format!("entry {path:?} holds {} bytes where the zip directory says {}", bytes.len(), e.bytes);
        return Err(IoError::file(name, problem));
    }
    match decode(&bytes, &e.dtype) {
        Some(Ok(v)) => Ok(v),
        _ => Err(IoError::file(name, format!("entry {path:?}: {} bytes do not hold whole {}", bytes.len(), e.dtype))),
    }
}

/// What [`stream`] reads beside the streamlines: the column groups of the per-point data
/// (the `dpv` arrays, by name) and per-streamline data (`dps`) that each [`Line`] carries,
/// and the groups, as [`super::trk::TrkInfo`] names its scalars.
///
/// ```
/// // Not a zip archive: a clear error, nothing read.
/// use tubecast_render::io::{stream::Flow, trx};
/// let e = trx::stream(std::io::Cursor::new(b"nope"), "x.trx", false, &mut |_| Flow::Continue);
/// assert!(e.unwrap_err().problem.contains("zip"));
/// ```
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TrxInfo {
    /// `NB_STREAMLINES` and `NB_VERTICES`.
    pub counts: (usize, usize),
    /// Per-point groups `(name, first column, width)` of [`Line::scalars`].
    pub scalars: Vec<(String, usize, usize)>,
    /// Per-streamline groups `(name, first column, width)` of [`Line::properties`].
    pub properties: Vec<(String, usize, usize)>,
    /// Named groups of streamline indices.
    pub groups: Vec<(String, Vec<u64>)>,
}

/// Column groups of `fields` (name, width) laid side by side, and the total width.
fn columns(fields: &[(String, usize)]) -> (Vec<(String, usize, usize)>, usize) {
    let mut at = 0;
    let groups = fields
        .iter()
        .map(|(n, w)| {
            at += w;
            (n.clone(), at - w, *w)
        })
        .collect();
    (groups, at)
}

/// Read the `header.json` of a TRX archive: `(NB_STREAMLINES, NB_VERTICES)`.
pub fn read_counts(r: impl Read + Seek, name: &str) -> Result<(usize, usize), IoError> {
    let mut zip =
        zip::ZipArchive::new(r).map_err(|e| IoError::file(name, format!("not a TRX file (zip archive): {e}")))?;
    counts(&mut zip, name)
}

fn counts<R: Read + Seek>(zip: &mut Zip<R>, name: &str) -> Result<(usize, usize), IoError> {
    let header: Value = {
        let mut f = zip.by_name("header.json").map_err(|_| IoError::file(name, "no header.json in the archive"))?;
        let mut s = String::new();
        f.read_to_string(&mut s).map_err(|e| IoError::file(name, format!("header.json: {e}")))?;
        serde_json::from_str(&s).map_err(|e| IoError::file(name, format!("header.json: {e}")))?
    };
    Ok((count(&header, "NB_STREAMLINES", name)?, count(&header, "NB_VERTICES", name)?))
}

/// Stream a `.trx` file: each streamline goes to `each` as its positions are decompressed,
/// with, when `data`, its per-vertex values ([`Line::scalars`]) and per-streamline values
/// ([`Line::properties`]) laid out as the returned [`TrxInfo`] says, and the groups read and
/// checked. Every array is read streamline by streamline, from its own clone of `r` (one
/// view of the archive per `dpv`/`dps` array): nothing is held whole but the offsets (8 bytes
/// per streamline) and the groups. The checks of [`read`].
pub fn stream<R: Read + Seek + Clone>(
    r: R,
    name: &str,
    data: bool,
    each: &mut dyn FnMut(Line<'_>) -> Flow,
) -> Result<TrxInfo, IoError> {
    stream_from(&mut || Ok(r.clone()), name, data, each)
}

/// [`stream`] with a reader per view of the archive from `open` (called once for the
/// streamlines and once per `dpv`/`dps` array when `data`): e.g. the file opened again, so
/// that a reader need not be `Clone`.
pub fn stream_from<R: Read + Seek>(
    open: &mut dyn FnMut() -> Result<R, IoError>,
    name: &str,
    data: bool,
    each: &mut dyn FnMut(Line<'_>) -> Flow,
) -> Result<TrxInfo, IoError> {
    let archive =
        |r: R| zip::ZipArchive::new(r).map_err(|e| IoError::file(name, format!("not a TRX file (zip archive): {e}")));
    let mut zip = archive(open()?)?;
    let (ns, nv) = counts(&mut zip, name)?;
    let mut info = TrxInfo { counts: (ns, nv), ..TrxInfo::default() };
    if ns == 0 || nv == 0 {
        return Ok(info);
    }
    let (mut positions, mut offsets) = (None, None);
    let (mut dpv, mut dps) = (Vec::new(), Vec::new());
    for e in entries(&mut zip, name)? {
        let size = (e.bytes / dtype_size(&e.dtype).unwrap_or(1) as u64) as usize;
        let bad =
            |what: &str| IoError::file(name, format!("{}{}: wrong size or dimension for {what}", e.folder, e.base));
        match (e.folder.as_str(), e.base.as_str()) {
            ("", "positions") if size == nv * 3 && e.dim == 3 => positions = Some(e),
            ("", "positions") => return Err(bad(&format!("{nv} vertices × 3"))),
            ("", "offsets") if size == ns + 1 && e.dim == 1 => offsets = Some(values(&mut zip, &e, name)?),
            ("", "offsets") => return Err(bad(&format!("{ns} streamlines + 1"))),
            ("dpv", _) if size == nv * e.dim => dpv.push(e),
            ("dps", _) if size == ns * e.dim => dps.push(e),
            ("dpv", _) | ("dps", _) => return Err(bad("its folder's count × DIM")),
            ("groups", _) if e.dim == 1 && data => {
                let v = values(&mut zip, &e, name)?;
                if v.iter().any(|&i| i >= ns as f64 || i < 0.0 || i.fract() != 0.0) {
                    return Err(IoError::file(name, format!("group {:?} has an index outside 0..{ns}", e.base)));
                }
                info.groups.push((e.base, v.iter().map(|&i| i as u64).collect()));
            }
            ("groups", _) if e.dim == 1 => {}
            ("groups", _) => return Err(bad("a group (DIM 1)")),
            _ => {} // dpg/ and anything else: not needed to draw the streamlines.
        }
    }
    let (Some(pos), Some(off)) = (positions, offsets) else {
        return Err(IoError::file(name, "missing positions or offsets"));
    };
    if off[0] != 0.0 || off[ns] != nv as f64 || off.windows(2).any(|w| w[1] < w[0]) {
        return Err(IoError::file(name, format!("offsets must rise from 0 to NB_VERTICES = {nv}")));
    }
    let off: Vec<u64> = off.iter().map(|&v| v as u64).collect();
    if !data {
        (dpv, dps) = (Vec::new(), Vec::new());
    }
    dpv.sort_by(|a, b| a.base.cmp(&b.base));
    dps.sort_by(|a, b| a.base.cmp(&b.base));
    let fields = |list: &[Entry]| columns(&list.iter().map(|e| (e.base.clone(), e.dim)).collect::<Vec<_>>()).0;
    (info.scalars, info.properties) = (fields(&dpv), fields(&dps));
    info.groups.sort();
    // One view of the archive per data array, each read as the streamlines go.
    let mut views = Vec::with_capacity(dpv.len() + dps.len());
    for _ in 0..dpv.len() + dps.len() {
        views.push(archive(open()?)?);
    }
    let mut cols = Vec::with_capacity(views.len());
    for (z, e) in views.iter_mut().zip(dpv.iter().chain(&dps)) {
        cols.push(Column::new(z, e, name)?);
    }
    let (cv, cs) = cols.split_at_mut(dpv.len());
    let f = zip.by_index(pos.index).map_err(|e| IoError::file(name, format!("entry \"positions\": {e}")))?;
    walk(Src::new(f, name), &pos.dtype, &off, (cv, cs), each).map(|()| info)
}

/// A `dpv`/`dps` array read item by item (`dim` values each) from its own view of the archive.
struct Column<'a, R: Read> {
    src: Src<'a, zip::read::ZipFile<'a, R>>,
    path: String,
    dim: usize,
    dtype: String,
    buf: Vec<u8>,
    vals: Vec<f64>,
}

impl<'a, R: Read + Seek> Column<'a, R> {
    fn new(zip: &'a mut Zip<R>, e: &Entry, name: &'a str) -> Result<Self, IoError> {
        let path = format!("{}/{}", e.folder, e.base);
        let f = zip.by_index(e.index).map_err(|err| IoError::file(name, format!("entry {path:?}: {err}")))?;
        let (dim, dtype) = (e.dim, e.dtype.clone());
        Ok(Self { src: Src::new(f, name), path, dim, dtype, buf: Vec::new(), vals: Vec::new() })
    }

    /// The next `n` items' values into `self.vals`. An entry shorter than its directory record
    /// says is an error, as in [`values`].
    fn next(&mut self, n: u64) -> Result<(), IoError> {
        let need = n * self.dim as u64 * dtype_size(&self.dtype).unwrap_or(1) as u64;
        let name = self.src.name;
        if (self.src.chunk(need, &mut self.buf)? as u64) < need {
            return Err(IoError::file(
                name,
                format!("entry {:?} holds fewer bytes than the zip directory says", self.path),
            ));
        }
        self.vals = match decode(&self.buf, &self.dtype) {
            Some(Ok(v)) => v,
            _ => return Err(IoError::file(name, format!("entry {:?}: not {}", self.path, self.dtype))),
        };
        Ok(())
    }

    /// After the last item: an entry longer than its directory record says is an error.
    fn end(&mut self) -> Result<(), IoError> {
        let mut one = [0u8; 1];
        match self.src.fill(&mut one)? {
            0 => Ok(()),
            _ => Err(IoError::file(
                self.src.name,
                format!("entry {:?} holds more bytes than the zip directory says", self.path),
            )),
        }
    }
}

/// Decode the positions from `src` streamline by streamline (offsets `off`), with the data
/// `(dpv, dps)` of each, into `each`.
fn walk<'a, R: Read, C: Read + Seek>(
    mut src: Src<'_, R>,
    dtype: &str,
    off: &[u64],
    (dpv, dps): (&mut [Column<'a, C>], &mut [Column<'a, C>]),
    each: &mut dyn FnMut(Line<'_>) -> Flow,
) -> Result<(), IoError> {
    let name = src.name;
    let size = dtype_size(dtype).unwrap_or(4) as u64;
    let (mut buf, mut points, mut scal, mut prop) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for (k, w) in off.windows(2).enumerate() {
        let need = (w[1] - w[0]) * 3 * size;
        if (src.chunk(need, &mut buf)? as u64) < need {
            return Err(IoError::file(name, format!("entry \"positions\": ends inside streamline {k}")));
        }
        let v = match decode(&buf, dtype) {
            Some(Ok(v)) => v,
            _ => return Err(IoError::file(name, format!("entry \"positions\": not {dtype}"))),
        };
        if let Some(i) = v.iter().position(|x| !x.is_finite()) {
            let problem = format!("position {} has NaN or infinite coordinates", w[0] as usize + i / 3);
            return Err(IoError::file(name, problem));
        }
        points.clear();
        points.extend(v.chunks_exact(3).map(|c| [c[0], c[1], c[2]]));
        for c in dpv.iter_mut() {
            c.next(w[1] - w[0])?;
        }
        scal.clear();
        for i in 0..(w[1] - w[0]) as usize {
            for c in dpv.iter() {
                scal.extend_from_slice(&c.vals[i * c.dim..(i + 1) * c.dim]);
            }
        }
        prop.clear();
        for c in dps.iter_mut() {
            c.next(1)?;
            prop.extend_from_slice(&c.vals);
        }
        if each(Line { index: k, points: &points, scalars: &scal, properties: &prop }) == Flow::Stop {
            return Ok(());
        }
    }
    for c in dpv.iter_mut().chain(dps.iter_mut()) {
        c.end()?;
    }
    Ok(())
}

/// Parse a `.trx` file into streamlines (RAS+ mm) with their per-vertex and per-streamline
/// data and groups ([`stream`], collected).
///
/// Errors: not a zip archive, no or malformed `header.json`, missing `positions` or `offsets`,
/// an array whose size or dimension does not match the header, offsets that do not start at 0,
/// decrease or do not end at `NB_VERTICES`, a group index out of range, or non-finite positions.
pub fn read(data: &[u8], name: &str) -> Result<Tractogram, IoError> {
    let (mut lines, mut scal, mut prop) = (Vec::new(), Vec::new(), Vec::new());
    let info = stream(std::io::Cursor::new(data), name, true, &mut |l| {
        lines.push(Polyline { points: l.points.to_vec(), radii: Vec::new() });
        scal.extend_from_slice(l.scalars);
        prop.extend_from_slice(l.properties);
        Flow::Continue
    })?;
    let width = |g: &[(String, usize, usize)]| g.iter().map(|c| c.2).sum::<usize>();
    let per_point = split(&info.scalars, &scal, width(&info.scalars));
    let per_line = split(&info.properties, &prop, width(&info.properties));
    Ok(Tractogram { lines, per_point, per_line, groups: info.groups, affine: None })
}

/// Fields of the column groups of `all` (`n` columns per item).
fn split(groups: &[(String, usize, usize)], all: &[f64], n: usize) -> Vec<Field> {
    if n == 0 {
        return Vec::new();
    }
    super::trk::fields(groups, all, n)
}
