//! SWC neuron morphologies: one node per line, seven whitespace-separated columns
//! `id type x y z radius parent`; `#` starts a comment; rows may come in any order; a parent
//! of `-1` marks a root and there may be several roots; ids need not be contiguous or sorted.
//! Coordinates and radii are kept in the file's units. A file with no nodes (empty, or only
//! comments) is a valid empty morphology, as navis and NeuroM read it.
//!
//! # Placeholder radii
//! Files from the field often hold `0` or a negative number where the radius is unknown.
//! [`read`] keeps a radius of `0` (a tapering tip is legitimate; a link with radius `0` at
//! both ends is refused later, when a scene is built) and refuses a negative one, naming the
//! line. [`read_with`] with a minimum radius `R` instead replaces every radius below `R` —
//! so every placeholder `≤ 0` — by `R`, and counts the replacements (the `--min-radius R`
//! option of the `tubecast` command line).

use super::stream::Src;
use super::{parse_finite, IoError, Polyline};
use std::collections::HashMap;
use std::io::BufRead;

/// One SWC row.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SwcNode {
    /// Node id (unique in the file).
    pub id: i64,
    /// Structure type (1 soma, 2 axon, 3 basal dendrite, 4 apical dendrite, ...).
    pub kind: i32,
    /// Position.
    pub pos: [f64; 3],
    /// Radius (≥ 0).
    pub radius: f64,
    /// Parent id, or `-1` for a root.
    pub parent: i64,
}

/// What [`read_with`] read.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SwcFile {
    /// The nodes, in file order.
    pub nodes: Vec<SwcNode>,
    /// The 1-based line of each node.
    pub lines: Vec<usize>,
    /// Radii replaced by the minimum radius (all of them below it).
    pub replaced: usize,
    /// Of those, the radii that were `≤ 0` (placeholders).
    pub placeholders: usize,
}

/// The hint every placeholder-radius error carries.
pub const MIN_RADIUS_HINT: &str = "placeholder radius? `--min-radius R` replaces radii below R (and ≤ 0) by R";

fn parse_int(tok: &str) -> Option<i64> {
    if let Ok(v) = tok.parse::<i64>() {
        return Some(v);
    }
    // Some writers print integers as "12.0".
    let f = tok.parse::<f64>().ok()?;
    if f.is_finite() && f.fract() == 0.0 && f.abs() < 9.0e15 {
        Some(f as i64)
    } else {
        None
    }
}

/// Parse an SWC file. Errors name the line: wrong column count, a non-number, a negative or
/// non-finite value, a duplicate id, a parent that does not exist, or a node that is its own
/// ancestor (cycle). A file without nodes gives no nodes.
pub fn read(data: &[u8], name: &str) -> Result<Vec<SwcNode>, IoError> {
    Ok(read_with(data, name, None)?.nodes)
}

/// [`read`], with each node's line, and with `min_radius: Some(R)` every radius below `R`
/// (negative placeholders included) replaced by `R` and counted. `R` must be a positive
/// finite number (an error about the whole file otherwise).
pub fn read_with(data: &[u8], name: &str, min_radius: Option<f64>) -> Result<SwcFile, IoError> {
    read_from(data, name, min_radius)
}

/// [`read_with`] streaming from `r`, line by line (the file is never held whole).
pub fn read_from(r: impl BufRead, name: &str, min_radius: Option<f64>) -> Result<SwcFile, IoError> {
    if let Some(r) = min_radius {
        if !(r.is_finite() && r > 0.0) {
            return Err(IoError::file(name, format!("minimum radius {r} must be a positive finite number")));
        }
    }
    let (mut replaced, mut placeholders) = (0, 0);
    let mut nodes = Vec::new();
    let mut lines = Vec::new(); // line number of each node
    let mut index: HashMap<i64, usize> = HashMap::new();
    let (mut src, mut buf) = (Src::new(r, name), Vec::new());
    for ln in 1.. {
        let at = src.pos;
        if src.line(&mut buf, ln)? == 0 {
            break;
        }
        let raw = std::str::from_utf8(&buf)
            .map_err(|e| IoError::offset(name, at + e.valid_up_to() as u64, "not UTF-8 text (is this an SWC file?)"))?;
        let line = raw.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let cols: Vec<&str> = line.split_whitespace().collect();
        if cols.len() != 7 {
            return Err(IoError::line(
                name,
                ln,
                format!("expected 7 columns (id type x y z radius parent), found {}", cols.len()),
            ));
        }
        let id =
            parse_int(cols[0]).ok_or_else(|| IoError::line(name, ln, format!("id {:?} is not an integer", cols[0])))?;
        if id < 0 {
            return Err(IoError::line(name, ln, format!("id {id} is negative")));
        }
        let kind = parse_int(cols[1])
            .filter(|k| i32::try_from(*k).is_ok())
            .ok_or_else(|| IoError::line(name, ln, format!("type {:?} is not an integer", cols[1])))?
            as i32;
        let mut v = [0.0; 4];
        for (k, what) in ["x", "y", "z", "radius"].iter().enumerate() {
            v[k] = parse_finite(cols[2 + k])
                .ok_or_else(|| IoError::line(name, ln, format!("{what} {:?} is not a finite number", cols[2 + k])))?;
        }
        match min_radius {
            Some(r) if v[3] < r => {
                replaced += 1;
                placeholders += (v[3] <= 0.0) as usize;
                v[3] = r;
            }
            None if v[3] < 0.0 => {
                return Err(IoError::line(name, ln, format!("radius {} is negative ({MIN_RADIUS_HINT})", v[3])));
            }
            _ => {}
        }
        let parent = parse_int(cols[6])
            .ok_or_else(|| IoError::line(name, ln, format!("parent {:?} is not an integer", cols[6])))?;
        if parent < -1 {
            return Err(IoError::line(name, ln, format!("parent {parent} (roots use -1)")));
        }
        if parent == id {
            return Err(IoError::line(name, ln, format!("node {id} is its own parent")));
        }
        if let Some(&prev) = index.get(&id) {
            return Err(IoError::line(name, ln, format!("duplicate id {id} (first on line {})", lines[prev])));
        }
        index.insert(id, nodes.len());
        lines.push(ln);
        nodes.push(SwcNode { id, kind, pos: [v[0], v[1], v[2]], radius: v[3], parent });
    }
    check_parents(&nodes, &lines, &index, name)?;
    Ok(SwcFile { nodes, lines, replaced, placeholders })
}

/// Parents exist, and following parents always reaches a root (no cycles). `lines`: the line
/// of each node; `index`: node index by id.
fn check_parents(nodes: &[SwcNode], lines: &[usize], index: &HashMap<i64, usize>, name: &str) -> Result<(), IoError> {
    let mut state = vec![0u8; nodes.len()]; // 0 unknown, 1 on current path, 2 reaches a root
    for start in 0..nodes.len() {
        let mut path = Vec::new();
        let mut cur = start;
        loop {
            match state[cur] {
                2 => break,
                1 => {
                    return Err(IoError::line(
                        name,
                        lines[cur],
                        format!("node {} is its own ancestor (parent cycle)", nodes[cur].id),
                    ))
                }
                _ => {}
            }
            state[cur] = 1;
            path.push(cur);
            let p = nodes[cur].parent;
            if p == -1 {
                break;
            }
            match index.get(&p) {
                Some(&pi) => cur = pi,
                None => {
                    return Err(IoError::line(
                        name,
                        lines[cur],
                        format!("parent {p} of node {} does not exist", nodes[cur].id),
                    ))
                }
            }
        }
        for k in path {
            state[k] = 2;
        }
    }
    Ok(())
}

/// Write nodes as SWC text (shortest round-trip formatting of every number).
pub fn write(nodes: &[SwcNode]) -> String {
    let mut s = String::from("# written by tubecast\n# id type x y z radius parent\n");
    for n in nodes {
        s.push_str(&format!(
            "{} {} {:?} {:?} {:?} {:?} {}\n",
            n.id, n.kind, n.pos[0], n.pos[1], n.pos[2], n.radius, n.parent
        ));
    }
    s
}

/// SWC rows for polylines: each polyline a chain (first point a root), types 0.
pub fn from_polylines(lines: &[Polyline], default_radius: f64) -> Vec<SwcNode> {
    let mut out = Vec::new();
    for l in lines {
        for (k, p) in l.points.iter().enumerate() {
            let id = out.len() as i64 + 1;
            out.push(SwcNode {
                id,
                kind: 0,
                pos: *p,
                radius: l.radii.get(k).copied().unwrap_or(default_radius),
                parent: if k == 0 { -1 } else { id - 1 },
            });
        }
    }
    out
}

/// Read the SWC file at `path` ([`read`], streamed, named by its path in errors).
pub fn load(path: &std::path::Path) -> Result<Vec<SwcNode>, IoError> {
    Ok(read_from(super::stream::open(path)?.0, &path.display().to_string(), None)?.nodes)
}
