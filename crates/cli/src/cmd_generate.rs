//! `tubecast generate`: a procedural test scene written to a file.

use crate::args::{GenerateArgs, Kind};
use crate::error::CliError;
use crate::options::{extension, generate_size};
use tubecast_render::io;
use tubecast_render::scene::generate;

/// `tubecast generate`.
pub fn generate(a: &GenerateArgs) -> Result<(), CliError> {
    crate::options::generate(a)?;
    let size = |v: u64| usize::try_from(v).unwrap_or(usize::MAX);
    let (count, segments) = generate_size(a);
    let ext = extension(&a.out);
    if matches!(ext.as_str(), "tck" | "trk") {
        crate::setup::warn(&format!(
            "{}: .{ext} holds no radii; the scene's radii are dropped (write .swc or .obj to keep them)",
            a.out.display()
        ));
    }
    let lines = crate::setup::with_threads(a.run.threads, || match a.kind {
        Kind::Bundle => Some(generate::bundle(size(count), size(segments), a.seed)),
        Kind::Furball => Some(generate::furball(size(count), size(segments), a.seed)),
        Kind::Helix => Some(generate::helix(size(segments))),
        Kind::Neurons => None,
    })?;
    match lines {
        Some(lines) => Ok(io::write_polylines(&a.out, &lines)?),
        None => neurons(a),
    }
}

/// Han's assembly of `n³` neurons, from the base neurons given or a procedural one.
fn neurons(a: &GenerateArgs) -> Result<(), CliError> {
    let bases = if a.base.is_empty() {
        vec![generate::base_neuron(a.seed)]
    } else {
        a.base.iter().map(|p| io::swc::load(p)).collect::<Result<Vec<_>, _>>()?
    };
    let nodes = generate::neurons(a.n as usize, &bases, a.seed);
    Ok(io::write_bytes(&a.out, io::swc::write(&nodes).as_bytes())?)
}
