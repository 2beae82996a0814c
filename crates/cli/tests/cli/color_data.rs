//! `render --color scalar:NAME / property:NAME --colormap MAP` on nibabel's own complex.trk
//! (scalars "fa", "colors"; properties "mean_curvature", ...) and a trx-python TRX file.

use crate::common::bin;
crate::common::tmp_fn!();
use std::path::Path;

fn reference(rel: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../reference/readers").join(rel)
}

fn render(input: &Path, out: &Path, extra: &[&str]) -> std::process::Output {
    let mut args = vec![
        "render".to_string(),
        input.display().to_string(),
        "-o".into(),
        out.display().to_string(),
        "--width".into(),
        "48".into(),
        "--height".into(),
        "32".into(),
        "--quiet".into(),
    ];
    args.extend(extra.iter().map(|s| s.to_string()));
    bin().args(&args).output().unwrap()
}

#[test]
fn colour_by_scalar_and_property_from_trk_and_trx() {
    for (file, field) in [
        ("nibabel/complex.trk", "scalar:fa"),
        ("nibabel/complex.trk", "property:mean_curvature"),
        ("trx/complex_float16_uint64_stored.trx", "scalar:colors"),
        ("trx/complex_float32_uint32_stored.trx", "property:mean_torsion"),
    ] {
        let out = tmp(&format!("color-{}.png", field.replace(':', "-")));
        let o = render(&reference(file), &out, &["--color", field, "--colormap", "magma", "--radius", "0.3"]);
        assert!(o.status.success(), "{file} {field}: {}", String::from_utf8_lossy(&o.stderr));
        assert!(std::fs::metadata(&out).unwrap().len() > 0);
    }
}

#[test]
fn unknown_field_and_colormap_are_clear_errors() {
    let out = tmp("color-bad.png");
    let o = render(&reference("nibabel/complex.trk"), &out, &["--color", "scalar:nope"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success() && err.contains("scalar:nope") && err.contains("scalar:fa"), "{err}");
    let o = render(&reference("nibabel/complex.trk"), &out, &["--color", "scalar:fa", "--colormap", "rainbowz"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success() && err.contains("viridis"), "{err}");
    let o = render(&reference("nibabel/complex.trk"), &out, &["--color", "fa"]);
    assert!(!o.status.success() && String::from_utf8_lossy(&o.stderr).contains("scalar:NAME"));
}

#[test]
fn legend_changes_the_image_and_needs_a_data_colouring() {
    let input = reference("nibabel/complex.trk");
    let (plain, with) = (tmp("legend-off.png"), tmp("legend-on.png"));
    assert!(render(&input, &plain, &["--color", "scalar:fa"]).status.success());
    let o = render(&input, &with, &["--color", "scalar:fa", "--legend"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_ne!(std::fs::read(&plain).unwrap(), std::fs::read(&with).unwrap(), "--legend drew nothing");
    let o = render(&input, &with, &["--legend", "--force"]);
    assert!(o.status.success() && String::from_utf8_lossy(&o.stderr).contains("--legend needs"));
}
