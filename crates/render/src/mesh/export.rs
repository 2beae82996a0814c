//! Writers for a [`SceneMesh`]: binary PLY, Wavefront OBJ, binary glTF (`.glb`, through the
//! `gltf` crate's JSON model and GLB container). PLY and OBJ are written here: both are a
//! header and two arrays, and the maintained PLY crate (`ply-rs-bw`) needs a newer Rust than
//! this workspace's 1.80.

use super::SceneMesh;
use crate::io::IoError;
use std::path::Path;

/// The formats [`write()`] chooses by extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// Binary little-endian PLY (`float x, y, z`; `list uchar int vertex_indices`).
    Ply,
    /// Wavefront OBJ (`v`, `f`, 1-based).
    Obj,
    /// Binary glTF 2.0 (one mesh, positions and `u32` indices).
    Glb,
}

impl Format {
    /// The format of a path's extension (`.ply`, `.obj`, `.glb`; case-insensitive).
    pub fn of(path: &Path) -> Option<Self> {
        let e = path.extension()?.to_str()?.to_ascii_lowercase();
        match e.as_str() {
            "ply" => Some(Self::Ply),
            "obj" => Some(Self::Obj),
            "glb" => Some(Self::Glb),
            _ => None,
        }
    }
}

/// Vertex positions as `f32` (what PLY readers and glTF expect).
fn f32s(m: &SceneMesh) -> impl Iterator<Item = [f32; 3]> + '_ {
    m.mesh.positions.iter().map(|p| [p.x as f32, p.y as f32, p.z as f32])
}

/// Binary little-endian PLY.
pub fn ply(m: &SceneMesh) -> Vec<u8> {
    let (nv, nf) = (m.mesh.positions.len(), m.mesh.triangles.len());
    let head = format!(
        "ply\nformat binary_little_endian 1.0\ncomment tubecast certified mesh, Hausdorff bound {:e}\n\
         element vertex {nv}\nproperty float x\nproperty float y\nproperty float z\n\
         element face {nf}\nproperty list uchar int vertex_indices\nend_header\n",
        m.mesh.certified
    );
    let mut out = head.into_bytes();
    out.reserve(nv * 12 + nf * 13);
    for p in f32s(m) {
        p.iter().for_each(|x| out.extend_from_slice(&x.to_le_bytes()));
    }
    for t in &m.mesh.triangles {
        out.push(3);
        t.iter().for_each(|&i| out.extend_from_slice(&(i as i32).to_le_bytes()));
    }
    out
}

/// Wavefront OBJ (positions in full `f64` precision).
pub fn obj(m: &SceneMesh) -> String {
    use std::fmt::Write;
    let mut s = format!("# tubecast certified mesh, Hausdorff bound {:e}\n", m.mesh.certified);
    for p in &m.mesh.positions {
        let _ = writeln!(s, "v {} {} {}", p.x, p.y, p.z);
    }
    for t in &m.mesh.triangles {
        let _ = writeln!(s, "f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1);
    }
    s
}

/// Binary glTF 2.0: one buffer (positions, then indices), one primitive of triangles.
pub fn glb(m: &SceneMesh) -> Vec<u8> {
    use gltf_json as json;
    use json::validation::Checked::Valid;
    use json::validation::USize64;
    let pos: Vec<[f32; 3]> = f32s(m).collect();
    let (mut min, mut max) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
    for p in &pos {
        (0..3).for_each(|i| (min[i], max[i]) = (min[i].min(p[i]), max[i].max(p[i])));
    }
    let mut bin: Vec<u8> = pos.iter().flatten().flat_map(|x| x.to_le_bytes()).collect();
    let pos_len = bin.len();
    bin.extend(m.mesh.triangles.iter().flatten().flat_map(|i| i.to_le_bytes()));
    let mut root = json::Root::default();
    let buffer = root.push(json::Buffer {
        byte_length: USize64::from(bin.len()),
        uri: None,
        extensions: None,
        extras: Default::default(),
    });
    let view = |root: &mut json::Root, offset: usize, len: usize, target| {
        root.push(json::buffer::View {
            buffer,
            byte_length: USize64::from(len),
            byte_offset: Some(USize64::from(offset)),
            byte_stride: None,
            target: Some(Valid(target)),
            extensions: None,
            extras: Default::default(),
        })
    };
    let pv = view(&mut root, 0, pos_len, json::buffer::Target::ArrayBuffer);
    let iv = view(&mut root, pos_len, bin.len() - pos_len, json::buffer::Target::ElementArrayBuffer);
    let accessor = |view, count: usize, ty, comp, minmax: Option<([f32; 3], [f32; 3])>| json::Accessor {
        buffer_view: Some(view),
        byte_offset: None,
        count: USize64::from(count),
        component_type: Valid(json::accessor::GenericComponentType(comp)),
        type_: Valid(ty),
        min: minmax.map(|m| json::Value::from(m.0.to_vec())),
        max: minmax.map(|m| json::Value::from(m.1.to_vec())),
        normalized: false,
        sparse: None,
        extensions: None,
        extras: Default::default(),
    };
    let empty = m.mesh.positions.is_empty();
    let pa = root.push(accessor(
        pv,
        pos.len(),
        json::accessor::Type::Vec3,
        json::accessor::ComponentType::F32,
        (!empty).then_some((min, max)),
    ));
    let ia = root.push(accessor(
        iv,
        3 * m.mesh.triangles.len(),
        json::accessor::Type::Scalar,
        json::accessor::ComponentType::U32,
        None,
    ));
    let prim = json::mesh::Primitive {
        attributes: [(Valid(json::mesh::Semantic::Positions), pa)].into_iter().collect(),
        indices: Some(ia),
        material: None,
        mode: Valid(json::mesh::Mode::Triangles),
        targets: None,
        extensions: None,
        extras: Default::default(),
    };
    let mesh =
        root.push(json::Mesh { primitives: vec![prim], weights: None, extensions: None, extras: Default::default() });
    let node = root.push(json::Node { mesh: Some(mesh), ..Default::default() });
    root.push(json::Scene { nodes: vec![node], extensions: None, extras: Default::default() });
    let json = json::serialize::to_vec(&root).expect("glTF JSON of plain data serialises");
    while bin.len() % 4 != 0 {
        bin.push(0);
    }
    let glb = gltf::binary::Glb {
        header: gltf::binary::Header { magic: *b"glTF", version: 2, length: 0 },
        json: std::borrow::Cow::Owned(json),
        bin: Some(std::borrow::Cow::Owned(bin)),
    };
    glb.to_vec().expect("GLB of in-memory buffers")
}

/// Writes the mesh to `path` in the format of its extension ([`Format::of`]).
///
/// ```
/// use tubecast_render::io::Polyline;
/// use tubecast_render::mesh::{export, tessellate};
/// use tubecast_render::scene::{Model, Scene};
/// let line = Polyline { points: vec![[0.0; 3], [4.0, 0.0, 0.0]], radii: vec![] };
/// let m = tessellate(&Scene::from_polylines(&[line], 0.5, "tube").unwrap(), Model::Links, 1e-2).unwrap();
/// let ply = export::ply(&m);
/// assert!(ply.starts_with(b"ply\nformat binary_little_endian 1.0\n"));
/// assert!(export::obj(&m).lines().filter(|l| l.starts_with("f ")).count() == m.mesh.triangles.len());
/// assert_eq!(&export::glb(&m)[..4], b"glTF");
/// ```
pub fn write(path: &Path, m: &SceneMesh) -> Result<(), IoError> {
    let bytes = match Format::of(path) {
        Some(Format::Ply) => ply(m),
        Some(Format::Obj) => obj(m).into_bytes(),
        Some(Format::Glb) => glb(m),
        None => return Err(IoError::file(&path.display().to_string(), "mesh output must end in .ply, .obj or .glb")),
    };
    crate::io::write_bytes(path, &bytes)
}
