//! Rays in and hits out for `intersect`: `-` for stdin/stdout, `.npy` or CSV.

use crate::error::CliError;
use std::io::{Read, Write};
use std::path::Path;
use tubecast_render::io::{self, IoError};

/// The hit table's columns, in order (`--query hit` and `piece`; see `tubecast intersect --help`).
pub const HIT_COLUMNS: [&str; 8] = ["t_in", "t_out", "nx", "ny", "nz", "link", "u", "hit"];

/// The crossing table's columns (`--query all`): one row per boundary, with its ray's index.
pub const CROSSING_COLUMNS: [&str; 8] = ["ray", "t", "nx", "ny", "nz", "link", "u", "flag"];

/// The bytes of `path`, or of stdin for `-`.
pub fn read_input(path: &Path) -> Result<Vec<u8>, CliError> {
    if path.as_os_str() == "-" {
        let mut buf = Vec::new();
        std::io::stdin().read_to_end(&mut buf).map_err(|e| IoError::file("-", format!("cannot read stdin: {e}")))?;
        return Ok(buf);
    }
    Ok(io::read_bytes(path)?)
}

/// One CSV line of a table row: columns 5 and 7 (`link`, and `hit` or `flag`) as integers, the other columns with Rust's
/// shortest round-trip formatting (`inf` for misses).
fn csv_line(out: &mut String, row: &[f64]) {
    use std::fmt::Write as _;
    for (k, v) in row.iter().enumerate() {
        if k > 0 {
            out.push(',');
        }
        // Writing to a String cannot fail.
        let _ = if k == 5 || k == 7 { write!(out, "{}", *v as i64) } else { write!(out, "{v}") };
    }
    out.push('\n');
}

/// The hit table streamed to `-` (stdout) or a file as it is computed, in chunks of rows: CSV
/// when asked or the name ends in `.csv`, else `.npy` (whose header needs the row count up
/// front). Nothing is held but the chunk being written.
pub struct HitsOut {
    w: std::io::BufWriter<Box<dyn Write>>,
    csv: bool,
    name: String,
    rows_left: usize,
}

impl HitsOut {
    /// Open `path` (`-`: stdout) for a table of `rows` rows and write its header (`columns`
    /// name the CSV columns).
    pub fn create(path: &Path, csv: bool, rows: usize, columns: &[&str; 8]) -> Result<Self, CliError> {
        let csv = csv || path.extension().is_some_and(|e| e.eq_ignore_ascii_case("csv"));
        let name = path.display().to_string();
        let w: Box<dyn Write> = if path.as_os_str() == "-" {
            Box::new(std::io::stdout().lock())
        } else {
            let f = std::fs::File::create(path).map_err(|e| IoError::file(&name, format!("cannot write: {e}")))?;
            Box::new(f)
        };
        let mut out = Self { w: std::io::BufWriter::with_capacity(1 << 20, w), csv, name, rows_left: rows };
        let head = if csv { format!("{}\n", columns.join(",")).into_bytes() } else { io::npy::header(rows, 8) };
        out.put(&head)?;
        Ok(out)
    }

    fn put(&mut self, bytes: &[u8]) -> Result<(), CliError> {
        self.w.write_all(bytes).map_err(|e| self.error(e))
    }

    fn error(&self, e: std::io::Error) -> CliError {
        IoError::file(&self.name, format!("cannot write: {e}")).into()
    }

    /// Append `rows`.
    pub fn write(&mut self, rows: &[[f64; 8]]) -> Result<(), CliError> {
        assert!(rows.len() <= self.rows_left, "more rows than the header announced");
        self.rows_left -= rows.len();
        if self.csv {
            let mut s = String::with_capacity(rows.len() * 64);
            for r in rows {
                csv_line(&mut s, r);
            }
            return self.put(s.as_bytes());
        }
        io::npy::write_rows(&mut self.w, rows).map_err(|e| self.error(e))
    }

    /// Flush; every announced row must have been written.
    pub fn finish(mut self) -> Result<(), CliError> {
        assert_eq!(self.rows_left, 0, "fewer rows than the header announced");
        self.w.flush().map_err(|e| self.error(e))
    }
}

/// Write a table to `path` (`-`: stdout) as CSV when `csv` or the name ends in `.csv`, as
/// `.npy` otherwise.
pub fn write_hits(path: &Path, rows: &[[f64; 8]], csv: bool, columns: &[&str; 8]) -> Result<(), CliError> {
    let mut out = HitsOut::create(path, csv, rows.len(), columns)?;
    out.write(rows)?;
    out.finish()
}
