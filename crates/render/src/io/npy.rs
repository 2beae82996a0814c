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
    /// [`Ray::validate`]; `name` names the array in errors.
    pub fn rays(&self, name: &str) -> Result<Vec<Ray<f64>>, IoError> {
        if self.cols != 6 {
            return Err(IoError::file(name, format!("has {} columns, expected 6", self.cols)));
        }
        (0..self.rows)
            .map(|i| {
                let r = self.row(i);
                let ray = Ray::new(V3::new(r[0], r[1], r[2]), V3::new(r[3], r[4], r[5]));
                ray.validate().map_err(|e| IoError::file(name, format!("row {i}: {e}")))?;
                Ok(ray)
            })
            .collect()
    }
}

fn dict_value<'a>(h: &'a str, key: &str) -> Option<&'a str> {
    let k = h.find(&format!("'{key}'")).or_else(|| h.find(&format!("\"{key}\"")))?;
    let rest = &h[k + key.len() + 2..];
    let rest = rest.trim_start().strip_prefix(':')?.trim_start();
    Some(rest)
}

/// Parse a `.npy` file holding a 2-D `float64` array with `cols` columns (`None`: any).
///
/// Errors: bad magic or version, header cut short or unparsable, dtype other than `f8`,
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
    let h = std::str::from_utf8(&data[start..start + hlen])
        .map_err(|_| IoError::offset(name, start as u64, "header is not text"))?;
    let bad = |what: &str| IoError::offset(name, start as u64, format!("header {what}: {}", h.trim()));
    let descr = dict_value(h, "descr").ok_or_else(|| bad("has no 'descr'"))?;
    let big = if descr.starts_with("'<f8'") || descr.starts_with("\"<f8\"") {
        false
    } else if descr.starts_with("'>f8'") || descr.starts_with("\">f8\"") {
        true
    } else {
        return Err(bad("dtype is not float64 ('<f8' or '>f8')"));
    };
    let fo = dict_value(h, "fortran_order").ok_or_else(|| bad("has no 'fortran_order'"))?;
    let fortran = if fo.starts_with("True") {
        true
    } else if fo.starts_with("False") {
        false
    } else {
        return Err(bad("fortran_order is not True or False"));
    };
    let shape = dict_value(h, "shape").ok_or_else(|| bad("has no 'shape'"))?;
    let inner = shape.strip_prefix('(').and_then(|s| s.split(')').next()).ok_or_else(|| bad("shape is not a tuple"))?;
    let dims: Vec<usize> = inner
        .split(',')
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .map(|s| s.parse::<usize>())
        .collect::<Result<_, _>>()
        .map_err(|_| bad("shape has a non-integer"))?;
    if dims.len() != 2 {
        return Err(bad(&format!("shape is {}-D, expected 2-D", dims.len())));
    }
    let (rows, ncols) = (dims[0], dims[1]);
    if let Some(c) = cols {
        if ncols != c {
            return Err(bad(&format!("has {ncols} columns, expected {c}")));
        }
    }
    let body = start + hlen;
    let n = rows.checked_mul(ncols).and_then(|n| n.checked_mul(8)).ok_or_else(|| bad("shape overflows"))?;
    if data.len() - body != n {
        return Err(IoError::offset(
            name,
            body as u64,
            format!("data is {} bytes, shape ({rows}, {ncols}) needs {n}", data.len() - body),
        ));
    }
    let mut out = vec![0.0; rows * ncols];
    for (k, ch) in data[body..].chunks_exact(8).enumerate() {
        let b: [u8; 8] = ch.try_into().expect("chunks of 8");
        let v = if big { f64::from_be_bytes(b) } else { f64::from_le_bytes(b) };
        let (r, c) = if fortran { (k % rows.max(1), k / rows.max(1)) } else { (k / ncols, k % ncols) };
        out[r * ncols + c] = v;
    }
    Ok(Array2 { rows, cols: ncols, data: out })
}

/// Write a row-major 2-D `float64` array as `.npy` version 1.0, little endian, C order.
pub fn write(a: &Array2) -> Vec<u8> {
    let mut h = format!("{{'descr': '<f8', 'fortran_order': False, 'shape': ({}, {}), }}", a.rows, a.cols);
    // Pad so that the data starts at a multiple of 64 bytes; the header ends with '\n'.
    while (10 + h.len() + 1) % 64 != 0 {
        h.push(' ');
    }
    h.push('\n');
    let mut out = b"\x93NUMPY\x01\x00".to_vec();
    out.extend_from_slice(&(h.len() as u16).to_le_bytes());
    out.extend_from_slice(h.as_bytes());
    for v in &a.data {
        out.extend_from_slice(&v.to_le_bytes());
    }
    out
}
