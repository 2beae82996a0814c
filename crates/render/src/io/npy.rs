//! NumPy `.npy` 2-D `float64` arrays (format versions 1, 2 and 3; either byte order; C or
//! Fortran order) — rays in (N×6: origin, direction), hits out (N×8).

use super::IoError;
use tubecast::{Ray, V3};

/// A row-major 2-D array of `f64`.
#[derive(Clone, Debug, PartialEq)]
pub struct Array2 {
    /// Rows.
    pub rows: usize,
    /// Columns.
    pub cols: usize,
    /// `rows × cols` values, row-major.
    pub data: Vec<f64>,
}

impl Array2 {
    /// Row `i`.
    pub fn row(&self, i: usize) -> &[f64] {
        &self.data[i * self.cols..(i + 1) * self.cols]
    }

    /// An array of `N`-column rows.
    pub fn from_rows<const N: usize>(rows: &[[f64; N]]) -> Self {
        Self { rows: rows.len(), cols: N, data: rows.concat() }
    }

    /// The rays of an N×6 array (origin x, y, z, direction x, y, z per row), each checked by
    /// [`Ray::validate`] ([`Self::check_rays`]); `name` names the array in errors.
    pub fn rays(&self, name: &str) -> Result<Vec<Ray<f64>>, IoError> {
        self.check_rays(name)?;
        Ok((0..self.rows).map(|i| self.ray(i)).collect())
    }

    /// Whether the array holds valid rays: 6 columns, each row's ray passing
    /// [`Ray::validate`]; `name` names the array in errors.
    pub fn check_rays(&self, name: &str) -> Result<(), IoError> {
        if self.cols != 6 {
            return Err(IoError::file(name, format!("has {} columns, expected 6", self.cols)));
        }
        for i in 0..self.rows {
            self.ray(i).validate().map_err(|e| IoError::file(name, format!("row {i}: {e}")))?;
        }
        Ok(())
    }

    /// The ray of row `i` of an N×6 array, unchecked (see [`Self::check_rays`]).
    #[inline]
    pub fn ray(&self, i: usize) -> Ray<f64> {
        let r = self.row(i);
        Ray::new(V3::new(r[0], r[1], r[2]), V3::new(r[3], r[4], r[5]))
    }
}

/// Parse a `.npy` file holding a 2-D `float32` or `float64` array (either byte order, C or
/// Fortran order) with `cols` columns (`None`: any), through the `npyz` crate; values are
/// returned as `f64` (exact for `float32`), row-major.
///
/// Errors: bad magic or version, header cut short or unparsable, a dtype other than `f4`/`f8`,
/// a shape that is not 2-D (or has the wrong column count), data shorter or longer than the
/// shape says. Values are returned as stored (NaN included); callers validate them.
pub fn read(data: &[u8], name: &str, cols: Option<usize>) -> Result<Array2, IoError> {
    if data.is_empty() {
        return Err(IoError::file(name, "empty file"));
    }
    if data.len() < 10 || &data[0..6] != b"\x93NUMPY" {
        return Err(IoError::offset(name, 0, "magic is not \\x93NUMPY (not a .npy file)"));
    }
    let (hlen, start) = match data[6] {
        1 => (u16::from_le_bytes([data[8], data[9]]) as usize, 10),
        2 | 3 => {
            if data.len() < 12 {
                return Err(IoError::offset(name, 8, "truncated header length"));
            }
            (u32::from_le_bytes([data[8], data[9], data[10], data[11]]) as usize, 12)
        }
        v => return Err(IoError::offset(name, 6, format!("unsupported format version {v}"))),
    };
    if data.len() - start < hlen {
        return Err(IoError::offset(
            name,
            start as u64,
            format!("truncated header: {hlen} bytes announced, {} left", data.len() - start),
        ));
    }
    let text = String::from_utf8_lossy(&data[start..start + hlen]).trim().to_string();
    let bad = |what: String| IoError::offset(name, start as u64, format!("header {what}: {text}"));
    // npyz 0.8 multiplies the shape's entries unchecked (a panic in debug builds, a wrapped
    // count in release): refuse a shape whose element count overflows before handing it over.
    let shape_text = text.split("shape").nth(1).and_then(|t| t.split(')').next()).unwrap_or("");
    let count = shape_text
        .split(|c: char| !c.is_ascii_digit())
        .filter(|t| !t.is_empty())
        .try_fold(1u64, |acc, t| t.parse::<u64>().ok().and_then(|v| acc.checked_mul(v)));
    if !matches!(count, Some(n) if n <= usize::MAX as u64 / 8) {
        return Err(bad("shape overflows".into()));
    }
    // npyz's header parser (py_literal's PEG grammar) backtracks exponentially on malformed
    // nesting and quoting: 118- and 392-byte headers ran for minutes (npy fuzz campaigns, seeds
    // 2001 and 2003). A plain float32/float64 array's header is a flat dict of strings, booleans
    // and one tuple of integers, so anything else is refused first, in one linear pass.
    if !plain_header(text.as_bytes()) {
        return Err(bad(
            "is not a plain dict of strings, True/False and an integer tuple (structured dtypes are not read)".into(),
        ));
    }
    let npy = npyz::NpyFile::new(data).map_err(|e| {
        let e = e.to_string();
        bad(format!("unparsable ({})", e.lines().next().unwrap_or("").trim()))
    })?;
    let size = match npy.dtype() {
        npyz::DType::Plain(t) if t.type_char() == npyz::TypeChar::Float && matches!(t.size_field(), 4 | 8) => {
            t.size_field() as usize
        }
        other => return Err(bad(format!("dtype {:?} is not float32 or float64", other.descr()))),
    };
    let dims = npy.shape().to_vec();
    if dims.len() != 2 {
        return Err(bad(format!("shape is {}-D, expected 2-D", dims.len())));
    }
    let (rows, ncols) = (dims[0] as usize, dims[1] as usize);
    if let Some(c) = cols {
        if ncols != c {
            return Err(bad(format!("has {ncols} columns, expected {c}")));
        }
    }
    let body = start + hlen;
    let n = rows.checked_mul(ncols).and_then(|n| n.checked_mul(size)).ok_or_else(|| bad("shape overflows".into()))?;
    if data.len() - body != n {
        return Err(IoError::offset(
            name,
            body as u64,
            format!("data is {} bytes, shape ({rows}, {ncols}) needs {n}", data.len() - body),
        ));
    }
    let fortran = npy.order() == npyz::Order::Fortran;
    let read_err = |e: std::io::Error| IoError::offset(name, body as u64, format!("data: {e}"));
    let flat: Vec<f64> = if size == 4 {
        npy.into_vec::<f32>().map_err(read_err)?.into_iter().map(f64::from).collect()
    } else {
        npy.into_vec::<f64>().map_err(read_err)?
    };
    // Column-major data is transposed into a second array; row-major data is the array.
    let data = if fortran {
        let mut out = vec![0.0; flat.len()];
        for (k, v) in flat.into_iter().enumerate() {
            let (r, c) = (k % rows.max(1), k / rows.max(1));
            out[r * ncols + c] = v;
        }
        out
    } else {
        flat
    };
    Ok(Array2 { rows, cols: ncols, data })
}

/// Whether `h` is a flat Python dict literal `{'key': value, ...}` whose values are quoted
/// strings (no escapes), bare words (`True`, `False`, numbers) or a tuple of bare words, with
/// optional trailing commas: the form numpy writes for a plain array. One pass, no
/// backtracking; npyz then judges the words themselves (and names what is wrong with them).
fn plain_header(h: &[u8]) -> bool {
    let mut i = 0;
    let ws = |i: &mut usize| {
        while *i < h.len() && h[*i].is_ascii_whitespace() {
            *i += 1;
        }
    };
    let eat = |i: &mut usize, c: u8| {
        ws(i);
        let ok = h.get(*i) == Some(&c);
        *i += ok as usize;
        ok
    };
    let string = |i: &mut usize| {
        ws(i);
        let Some(&q) = h.get(*i).filter(|&&q| q == b'\'' || q == b'"') else { return false };
        match h[*i + 1..].iter().position(|&c| c == q || c == b'\\') {
            Some(n) if h[*i + 1 + n] == q => {
                *i += n + 2;
                true
            }
            _ => false,
        }
    };
    let word = |i: &mut usize| {
        ws(i);
        let n = h[*i..].iter().take_while(|c| c.is_ascii_alphanumeric() || b"_.+-".contains(c)).count();
        *i += n;
        n > 0
    };
    let tuple = |i: &mut usize| {
        if !eat(i, b'(') {
            return false;
        }
        while word(i) {
            if !eat(i, b',') {
                break;
            }
        }
        eat(i, b')')
    };
    if !eat(&mut i, b'{') {
        return false;
    }
    while string(&mut i) {
        if !(eat(&mut i, b':') && (string(&mut i) || word(&mut i) || tuple(&mut i))) {
            return false;
        }
        if !eat(&mut i, b',') {
            break;
        }
    }
    let closed = eat(&mut i, b'}');
    ws(&mut i);
    closed && i == h.len()
}

/// Write a row-major 2-D `float64` array as `.npy` version 1.0, little endian, C order.
pub fn write(a: &Array2) -> Vec<u8> {
    let mut out = header(a.rows, a.cols);
    out.reserve(a.data.len() * 8);
    for v in &a.data {
        out.extend_from_slice(&v.to_le_bytes());
    }
    out
}

/// The header of a `rows × cols` `float64` array as [`write()`] writes it (`.npy` version 1.0,
/// little endian, C order), for a writer that streams the values after it.
pub fn header(rows: usize, cols: usize) -> Vec<u8> {
    let mut h = format!("{{'descr': '<f8', 'fortran_order': False, 'shape': ({rows}, {cols}), }}");
    // Pad so that the data starts at a multiple of 64 bytes; the header ends with '\n'.
    while (10 + h.len() + 1) % 64 != 0 {
        h.push(' ');
    }
    h.push('\n');
    let mut out = b"\x93NUMPY\x01\x00".to_vec();
    out.extend_from_slice(&(h.len() as u16).to_le_bytes());
    out.extend_from_slice(h.as_bytes());
    out
}

/// Stream `rows` as the values of a `.npy` array whose [`header`] was written before them.
pub fn write_rows<const N: usize>(w: &mut impl std::io::Write, rows: &[[f64; N]]) -> std::io::Result<()> {
    let mut buf = Vec::with_capacity(8 * N * rows.len().min(4096));
    for chunk in rows.chunks(4096) {
        buf.clear();
        for v in chunk.iter().flatten() {
            buf.extend_from_slice(&v.to_le_bytes());
        }
        w.write_all(&buf)?;
    }
    Ok(())
}
