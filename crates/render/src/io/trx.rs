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
use super::{IoError, Polyline};
use serde_json::Value;
use std::io::Read;

/// An array entry: its folder, name, columns and little-endian values as `f64`.
struct Entry {
    folder: String,
    base: String,
    dim: usize,
    values: Vec<f64>,
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

/// Read every array entry of the archive (skipping JSON, folders and unknown dtypes).
fn entries(zip: &mut zip::ZipArchive<std::io::Cursor<&[u8]>>, name: &str) -> Result<Vec<Entry>, IoError> {
    let mut out = Vec::new();
    for i in 0..zip.len() {
        let mut f = zip.by_index(i).map_err(|e| IoError::file(name, format!("zip entry {i}: {e}")))?;
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
        let mut bytes = Vec::new();
        f.read_to_end(&mut bytes).map_err(|e| IoError::file(name, format!("entry {path:?}: {e}")))?;
        let values = match decode(&bytes, dtype) {
            None => continue,
            Some(Err(size)) => {
                let problem =
                    format!("entry {path:?}: {} bytes is not a whole number of {size}-byte {dtype}", bytes.len());
                return Err(IoError::file(name, problem));
            }
            Some(Ok(v)) => v,
        };
        let dim = dim.parse::<usize>().ok().filter(|&d| d > 0);
        let dim =
            dim.ok_or_else(|| IoError::file(name, format!("entry {path:?}: dimension is not a positive integer")))?;
        out.push(Entry { folder: folder.to_string(), base: base.to_string(), dim, values });
    }
    Ok(out)
}

/// Parse a `.trx` file into streamlines (RAS+ mm) with their per-vertex and per-streamline
/// data and groups.
///
/// Errors: not a zip archive, no or malformed `header.json`, missing `positions` or `offsets`,
/// an array whose size or dimension does not match the header, offsets that do not start at 0,
/// decrease or do not end at `NB_VERTICES`, a group index out of range, or non-finite positions.
pub fn read(data: &[u8], name: &str) -> Result<Tractogram, IoError> {
    let mut zip = zip::ZipArchive::new(std::io::Cursor::new(data))
        .map_err(|e| IoError::file(name, format!("not a TRX file (zip archive): {e}")))?;
    let header: Value = {
        let mut f = zip.by_name("header.json").map_err(|_| IoError::file(name, "no header.json in the archive"))?;
        let mut s = String::new();
        f.read_to_string(&mut s).map_err(|e| IoError::file(name, format!("header.json: {e}")))?;
        serde_json::from_str(&s).map_err(|e| IoError::file(name, format!("header.json: {e}")))?
    };
    let (ns, nv) = (count(&header, "NB_STREAMLINES", name)?, count(&header, "NB_VERTICES", name)?);
    if ns == 0 || nv == 0 {
        return Ok(Tractogram::default());
    }
    let mut t = Tractogram::default();
    let (mut positions, mut offsets) = (None, None);
    for e in entries(&mut zip, name)? {
        let size = e.values.len();
        let bad =
            |what: &str| IoError::file(name, format!("{}{}: wrong size or dimension for {what}", e.folder, e.base));
        match (e.folder.as_str(), e.base.as_str()) {
            ("", "positions") if size == nv * 3 && e.dim == 3 => positions = Some(e.values),
            ("", "positions") => return Err(bad(&format!("{nv} vertices × 3"))),
            ("", "offsets") if size == ns + 1 && e.dim == 1 => offsets = Some(e.values),
            ("", "offsets") => return Err(bad(&format!("{ns} streamlines + 1"))),
            ("dpv", _) if size == nv * e.dim => {
                t.per_point.push(Field { name: e.base, width: e.dim, values: e.values })
            }
            ("dps", _) if size == ns * e.dim => t.per_line.push(Field { name: e.base, width: e.dim, values: e.values }),
            ("dpv", _) | ("dps", _) => return Err(bad("its folder's count × DIM")),
            ("groups", _) if e.dim == 1 => {
                if e.values.iter().any(|&i| i >= ns as f64 || i < 0.0 || i.fract() != 0.0) {
                    return Err(IoError::file(name, format!("group {:?} has an index outside 0..{ns}", e.base)));
                }
                t.groups.push((e.base, e.values.iter().map(|&i| i as u64).collect()));
            }
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
    if let Some(i) = pos.iter().position(|v| !v.is_finite()) {
        return Err(IoError::file(name, format!("position {} has NaN or infinite coordinates", i / 3)));
    }
    t.lines = off
        .windows(2)
        .map(|w| {
            let (a, b) = (w[0] as usize, w[1] as usize);
            Polyline { points: (a..b).map(|i| [pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]]).collect(), radii: vec![] }
        })
        .collect();
    t.per_point.sort_by(|a, b| a.name.cmp(&b.name));
    t.per_line.sort_by(|a, b| a.name.cmp(&b.name));
    t.groups.sort();
    Ok(t)
}
