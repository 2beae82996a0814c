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

/// Node index by SWC id: a table where the ids are dense (files number their nodes 1..n, or
/// nearly), a hash map otherwise. Looking up a million parents in a table instead of a hashed
/// map is most of what reading a large file costs.
#[derive(Clone, Debug, Default)]
pub struct IdIndex {
    /// Smallest id of a dense table.
    base: i64,
    /// Node index per `id − base` (`u32::MAX`: no node), when dense.
    dense: Vec<u32>,
    /// The map, when sparse.
    sparse: std::collections::HashMap<i64, u32>,
}

impl IdIndex {
    /// The index of nodes with ids `ids` (in file order, each `≥ 0`); on a repeated id,
    /// `Err((first, second))`: the positions of its first two occurrences, the second the
    /// earliest repeat in file order.
    pub fn new(ids: &[i64]) -> Result<Self, (usize, usize)> {
        let (lo, hi) = ids.iter().fold((i64::MAX, i64::MIN), |(l, h), &id| (l.min(id), h.max(id)));
        let span = hi.checked_sub(lo).and_then(|d| usize::try_from(d).ok()).map(|d| d + 1);
        if let Some(span) = span.filter(|&n| n <= 2 * ids.len() + 16) {
            let mut dense = vec![u32::MAX; span];
            for (i, &id) in ids.iter().enumerate() {
                let slot = &mut dense[(id - lo) as usize];
                if *slot != u32::MAX {
                    return Err((*slot as usize, i));
                }
                *slot = i as u32;
            }
            return Ok(Self { base: lo, dense, sparse: Default::default() });
        }
        let mut sparse = std::collections::HashMap::with_capacity(ids.len());
        for (i, &id) in ids.iter().enumerate() {
            if let Some(&prev) = sparse.get(&id) {
                return Err((prev as usize, i));
            }
            sparse.insert(id, i as u32);
        }
        Ok(Self { base: 0, dense: Vec::new(), sparse })
    }

    /// The position of the node with id `id`.
    #[inline]
    pub fn get(&self, id: i64) -> Option<usize> {
        if self.dense.is_empty() {
            return self.sparse.get(&id).map(|&i| i as usize);
        }
        let k = usize::try_from(id.checked_sub(self.base)?).ok()?;
        self.dense.get(k).filter(|&&i| i != u32::MAX).map(|&i| i as usize)
    }
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
        let mut cols = [""; 7];
        let mut found = 0;
        for tok in line.split_whitespace() {
            if found < 7 {
                cols[found] = tok;
            }
            found += 1;
        }
        if found != 7 {
            return Err(IoError::line(
                name,
                ln,
                format!("expected 7 columns (id type x y z radius parent), found {found}"),
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
        lines.push(ln);
        nodes.push(SwcNode { id, kind, pos: [v[0], v[1], v[2]], radius: v[3], parent });
    }
    let ids: Vec<i64> = nodes.iter().map(|n| n.id).collect();
    let index = IdIndex::new(&ids).map_err(|(a, b)| {
        IoError::line(name, lines[b], format!("duplicate id {} (first on line {})", ids[b], lines[a]))
    })?;
    drop(ids);
    check_parents(&nodes, &lines, &index, name)?;
    Ok(SwcFile { nodes, lines, replaced, placeholders })
}

/// Parents exist, and following parents always reaches a root (no cycles). `lines`: the line
/// of each node; `index`: node index by id.
fn check_parents(nodes: &[SwcNode], lines: &[usize], index: &IdIndex, name: &str) -> Result<(), IoError> {
    let mut state = vec![0u8; nodes.len()]; // 0 unknown, 1 on current path, 2 reaches a root
    let mut path = Vec::new();
    for start in 0..nodes.len() {
        path.clear();
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
            match index.get(p) {
                Some(pi) => cur = pi,
                None => {
                    return Err(IoError::line(
                        name,
                        lines[cur],
                        format!("parent {p} of node {} does not exist", nodes[cur].id),
                    ))
                }
            }
        }
        for &k in &path {
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

#[cfg(test)]
mod tests {
    use super::IdIndex;

    /// Both layouts answer every id of the file with its position, nothing for other ids, and
    /// report the earliest repeat with its first occurrence.
    #[test]
    fn id_index_dense_and_sparse() {
        let dense: Vec<i64> = (1..=1000).rev().collect();
        let sparse: Vec<i64> = (0..1000).map(|i| i * 7919 + 3).collect();
        for ids in [&dense, &sparse] {
            let ix = IdIndex::new(ids).unwrap();
            assert_eq!(ix.dense.is_empty(), std::ptr::eq(ids, &sparse), "layout");
            for (k, &id) in ids.iter().enumerate() {
                assert_eq!(ix.get(id), Some(k));
            }
            for id in [-1, 0, 1001, 4, i64::MAX, i64::MIN] {
                if !ids.contains(&id) {
                    assert_eq!(ix.get(id), None, "id {id}");
                }
            }
            let mut dup = ids.clone();
            dup[700] = ids[300];
            dup[900] = ids[100];
            assert_eq!(IdIndex::new(&dup).unwrap_err(), (300, 700));
        }
        assert_eq!(IdIndex::new(&[]).map(|ix| ix.get(0)), Ok(None));
        assert_eq!(IdIndex::new(&[0, i64::MAX]).map(|ix| (ix.get(0), ix.get(i64::MAX))), Ok((Some(0), Some(1))));
    }
}
