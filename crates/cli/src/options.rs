//! Checks that need more than one flag or the file system, made before any work: every
//! output's extension (what the command writes), its directory and whether it may be
//! overwritten, and the combinations of flags a command refuses. Single values are checked
//! as clap parses them ([`crate::values`]).
//!
//! Exit status: a command line that cannot work as written (a format the command does not
//! write, flags that do not go together) is a usage error, 2; the file system saying no (a
//! missing directory, an existing file without `--force`) fails the job, 1.

use crate::args::{GenerateArgs, IntersectArgs, Kind, MeshArgs, RenderArgs, SimplifyArgs, Surface};
use crate::error::CliError;
use crate::values::Color;
use std::path::Path;
use tubecast_render::io::IoError;

/// Generated scenes hold at most this many links. The polylines are held as f64 points
/// (24 B each) while the file is written: 10⁸ links (a whole brain) peak near 4.4 GB
/// resident, so the cap of 2·10⁸ stays under 9 GB.
pub const MAX_GENERATED_LINKS: u64 = 200_000_000;

/// The lower-case extension of `path` (empty when it has none).
pub fn extension(path: &Path) -> String {
    path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase()
}

/// `.a`, `.a or .b`, `.a, .b or .c`.
fn one_of(exts: &[&str]) -> String {
    let dotted: Vec<String> = exts.iter().map(|e| format!(".{e}")).collect();
    match dotted.split_last() {
        Some((last, [])) => last.clone(),
        Some((last, rest)) => format!("{} or {last}", rest.join(", ")),
        None => String::new(),
    }
}

/// Whether `path` means stdin/stdout.
pub fn is_dash(path: &Path) -> bool {
    path.as_os_str() == "-"
}

/// Check an output `path` given with `flag` before any work: its extension is one of `exts`
/// (a usage error otherwise), its directory exists, it is not a directory, and it does not
/// exist unless `force`.
pub fn output(flag: &str, path: &Path, exts: &[&str], force: bool) -> Result<(), CliError> {
    let ext = extension(path);
    if !exts.contains(&ext.as_str()) {
        let got = if ext.is_empty() { "no extension".to_string() } else { format!("extension .{ext}") };
        return Err(CliError::usage(format!(
            "{flag} {}: {got} is not a format this command writes; use {}",
            path.display(),
            one_of(exts)
        )));
    }
    let name = path.display().to_string();
    let fail = |problem: String| Err(CliError::Io(IoError::file(&name, problem)));
    let dir = path.parent().filter(|d| !d.as_os_str().is_empty()).unwrap_or(Path::new("."));
    if !dir.is_dir() {
        return fail(format!("cannot write: directory {} does not exist", dir.display()));
    }
    if path.is_dir() {
        return fail("cannot write: it is a directory".into());
    }
    if path.exists() && !force {
        return fail("exists; pass --force to overwrite it".into());
    }
    Ok(())
}

/// `render`: the PNG and the depth file, the mesh model's tolerance, the quantized model's
/// colours.
pub fn render(a: &RenderArgs) -> Result<(), CliError> {
    crate::gpu::check_render(a)?;
    output("-o", &a.out, &["png"], a.force)?;
    if let Some(d) = &a.depth {
        output("--depth", d, &["npy"], a.force)?;
    }
    if a.model == Surface::Mesh && a.tolerance.is_none() {
        return Err(CliError::usage("--model mesh needs --tolerance EPS (the mesh's certified Hausdorff bound)"));
    }
    if a.model == Surface::Mesh && a.pixel_error.is_some() {
        return Err(CliError::usage("--model mesh takes --tolerance EPS, not --pixel-error"));
    }
    if let (Surface::Quantized, Color::Data(key)) = (a.model, &a.color) {
        return Err(CliError::usage(format!(
            "--color {key}: the quantized lines carry no data fields; use direction, radius or solid:COLOUR"
        )));
    }
    Ok(())
}

/// `intersect`: the hits go to `.npy`, `.csv` or `-` (stdout).
pub fn intersect(a: &IntersectArgs) -> Result<(), CliError> {
    crate::gpu::check_intersect(a)?;
    if is_dash(&a.out) {
        return Ok(());
    }
    output("-o", &a.out, &["npy", "csv"], a.force)
}

/// `generate`: a format that holds the scene, and a scene of at most
/// [`MAX_GENERATED_LINKS`] links.
pub fn generate(a: &GenerateArgs) -> Result<(), CliError> {
    if matches!(a.kind, Kind::Neurons) {
        if extension(&a.out) != "swc" {
            return Err(CliError::usage(format!(
                "-o {}: neuron assemblies branch; write them as .swc",
                a.out.display()
            )));
        }
    } else {
        let (count, segments) = generate_size(a);
        if count.saturating_mul(segments) > MAX_GENERATED_LINKS {
            return Err(CliError::usage(format!(
                "--count {count} × --segments {segments}: the scene must have between 1 and {MAX_GENERATED_LINKS} links"
            )));
        }
    }
    output("-o", &a.out, &["swc", "obj", "tck", "trk"], a.force)
}

/// `generate`'s tubes and segments per tube, with the defaults of each scene.
pub fn generate_size(a: &GenerateArgs) -> (u64, u64) {
    match a.kind {
        Kind::Bundle => (a.count.unwrap_or(1250), a.segments.unwrap_or(84)),
        Kind::Furball => (a.count.unwrap_or(10_000), a.segments.unwrap_or(78)),
        Kind::Helix => (2, a.segments.unwrap_or(200)),
        Kind::Neurons => (0, 0),
    }
}

/// `mesh`: PLY, OBJ or binary glTF.
pub fn mesh(a: &MeshArgs) -> Result<(), CliError> {
    output("-o", &a.out, &["ply", "obj", "glb"], a.force)
}

/// `simplify`: an input format it streams, written back in the same format.
pub fn simplify(a: &SimplifyArgs) -> Result<(), CliError> {
    let kind = extension(&a.input);
    if !matches!(kind.as_str(), "swc" | "trk" | "tck" | "obj") {
        return Err(CliError::usage(format!(
            "{}: simplify reads .swc, .trk, .tck or .obj (the extension names the format)",
            a.input.display()
        )));
    }
    output("-o", &a.out, &[kind.as_str()], a.force).map_err(|e| match e {
        CliError::Usage(m) => CliError::Usage(format!("{m} (simplify writes the input's format)")),
        e => e,
    })
}
