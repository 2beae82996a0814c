//! Rays in and hits out for `intersect`: `-` for stdin/stdout, `.npy` or CSV.

use crate::error::CliError;
use std::io::{Read, Write};
use std::path::Path;
use tubecast_render::io::{self, npy::Array2, IoError};

/// The hit table's columns, in order (see `tubecast intersect --help`).
pub const HIT_COLUMNS: [&str; 8] = ["t_in", "t_out", "nx", "ny", "nz", "link", "u", "hit"];

/// The bytes of `path`, or of stdin for `-`.
pub fn read_input(path: &Path) -> Result<Vec<u8>, CliError> {
    if path.as_os_str() == "-" {
        let mut buf = Vec::new();
        std::io::stdin().read_to_end(&mut buf).map_err(|e| IoError::file("-", format!("cannot read stdin: {e}")))?;
        return Ok(buf);
    }
    Ok(io::read_bytes(path)?)
}

/// The hits as CSV: a header line of [`HIT_COLUMNS`], one row per ray; `link` and `hit` as
/// integers, the other columns with Rust's shortest round-trip formatting (`inf` for misses).
pub fn hits_csv(hits: &Array2) -> String {
    let mut s = HIT_COLUMNS.join(",");
    s.push('\n');
    for i in 0..hits.rows {
        let row: Vec<String> = hits
            .row(i)
            .iter()
            .enumerate()
            .map(|(k, v)| if k == 5 || k == 7 { format!("{}", *v as i64) } else { format!("{v}") })
            .collect();
        s.push_str(&row.join(","));
        s.push('\n');
    }
    s
}

/// Write the hits to `path` (`-`: stdout) as CSV when `csv` or the name ends in `.csv`, as
/// `.npy` otherwise.
pub fn write_hits(path: &Path, hits: &Array2, csv: bool) -> Result<(), CliError> {
    let csv = csv || path.extension().is_some_and(|e| e.eq_ignore_ascii_case("csv"));
    let bytes = if csv { hits_csv(hits).into_bytes() } else { io::npy::write(hits) };
    if path.as_os_str() == "-" {
        let mut out = std::io::stdout().lock();
        out.write_all(&bytes)
            .and_then(|_| out.flush())
            .map_err(|e| IoError::file("-", format!("cannot write stdout: {e}")))?;
        return Ok(());
    }
    Ok(io::write_bytes(path, &bytes)?)
}
