//! Every check before the work: each bad invocation of the table exits 2 (usage: the command
//! line cannot work as written) or 1 (the job failed: the file system said no, or the input
//! is malformed), with a message naming the flag or file, the value and what is allowed; no
//! output file is created, and an existing one is left as it was.

use crate::common::bin;
use std::path::{Path, PathBuf};
crate::common::tmp_fn!();

/// What an existing output file holds before each case; it must hold it after.
const KEPT: &[u8] = b"kept";

/// The argument with its placeholder replaced: `IN` (an SWC helix), `TCK` (the helix as .tck),
/// `BAD` (a malformed SWC), `RAYS` (two rays), `NEW.ext` (a fresh path of case `i`),
/// `OLD.ext` (an existing file holding [`KEPT`]), `NODIR/...` (a path in a missing directory).
fn resolve(arg: &str, i: usize, files: &Files) -> String {
    let p: PathBuf = match arg {
        "IN" => files.swc.clone(),
        "TCK" => files.tck.clone(),
        "BAD" => files.bad.clone(),
        "RAYS" => files.rays.clone(),
        _ if arg.starts_with("NEW.") => tmp(&format!("new{i}.{}", &arg[4..])),
        _ if arg.starts_with("OLD.") => tmp(&format!("old.{}", &arg[4..])),
        _ if arg.starts_with("NODIR/") => tmp("missing-dir").join(&arg[6..]),
        _ => return arg.to_string(),
    };
    p.display().to_string()
}

struct Files {
    swc: PathBuf,
    tck: PathBuf,
    bad: PathBuf,
    rays: PathBuf,
}

/// The inputs, named after `test` (the tests run side by side).
fn files(test: &str) -> Files {
    let t = |name: &str| tmp(&format!("{test}-{name}"));
    let (swc, tck, bad, rays) = (t("in.swc"), t("in.tck"), t("bad.swc"), t("rays.npy"));
    for p in [&swc, &tck] {
        let out = bin().args(["generate", "helix", "--segments", "8", "-q", "-o"]).arg(p).output().unwrap();
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    }
    std::fs::write(&bad, "1 1 0 0 0 1\n").unwrap();
    let r = tubecast_render::io::npy::Array2 { rows: 2, cols: 6, data: [[0.0, 0.0, -20.0, 0.0, 0.0, 1.0]; 2].concat() };
    std::fs::write(&rays, tubecast_render::io::npy::write(&r)).unwrap();
    Files { swc, tck, bad, rays }
}

#[test]
fn bad_invocations_fail_before_any_work_and_touch_no_output() {
    let f = files("table");
    #[rustfmt::skip]
    let cases: &[(&[&str], i32, &[&str])] = &[
        // Outputs: format, directory, --force.
        (&["render", "IN", "-o", "NEW.jpg"], 2, &["-o", "extension .jpg", ".png"]),
        // Without the gpu feature: a build without the GPU; with it: no voxel grid on the GPU.
        (&["render", "IN", "-o", "NEW.png", "--device", "gpu", "--accel", "grid"], 2, &["--device gpu"]),
        (&["intersect", "IN", "--rays", "RAYS", "-o", "NEW.npy", "--device", "gpu", "--accel", "grid"], 2, &["--device gpu"]),
        (&["render", "IN", "-o", "NEW"], 2, &["no extension", ".png"]),
        (&["render", "IN", "-o", "NODIR/x.png"], 1, &["missing-dir", "does not exist"]),
        (&["render", "IN", "-o", "OLD.png"], 1, &["exists", "--force"]),
        (&["render", "IN", "-o", "NEW.png", "--depth", "NEW.txt"], 2, &["--depth", ".txt", ".npy"]),
        (&["render", "IN", "-o", "NEW.png", "--depth", "OLD.npy"], 1, &["exists", "--force"]),
        (&["intersect", "IN", "--rays", "RAYS", "-o", "NEW.txt"], 2, &["-o", ".txt", ".npy or .csv"]),
        (&["intersect", "IN", "--rays", "RAYS", "-o", "OLD.npy"], 1, &["exists", "--force"]),
        (&["intersect", "IN", "--rays", "RAYS", "-o", "NODIR/h.npy"], 1, &["does not exist"]),
        (&["generate", "helix", "-o", "NEW.jpg"], 2, &[".jpg", ".swc, .obj, .tck or .trk"]),
        (&["generate", "helix", "-o", "OLD.swc"], 1, &["exists", "--force"]),
        (&["generate", "neurons", "-o", "NEW.tck"], 2, &["neuron", ".swc"]),
        (&["generate", "bundle", "--count", "200000001", "--segments", "1", "-o", "NEW.tck"], 2, &["--count 200000001", "between 1 and 200000000"]),
        (&["mesh", "IN", "--tolerance", "0.01", "-o", "NEW.stl"], 2, &[".stl", ".ply, .obj or .glb"]),
        (&["mesh", "IN", "--tolerance", "0.01", "-o", "OLD.ply"], 1, &["exists", "--force"]),
        (&["simplify", "IN", "--tolerance", "0.1", "-o", "NEW.tck"], 2, &[".tck", ".swc", "input's format"]),
        (&["simplify", "IN", "--tolerance", "0.1", "-o", "OLD.swc"], 1, &["exists", "--force"]),
        // Values out of range: the flag, the value and what is allowed.
        (&["render", "IN", "-o", "NEW.png", "--up", "0,0,0"], 2, &["'0,0,0' for '--up", "zero vector"]),
        (&["render", "IN", "-o", "NEW.png", "--ao-samples", "0"], 2, &["'0' for '--ao-samples", "1..=1024"]),
        (&["render", "IN", "-o", "NEW.png", "--ao", "0"], 2, &["'0' for '--ao", "ray count in 1..=1024"]),
        (&["render", "IN", "-o", "NEW.png", "--min-pixels", "0"], 2, &["'0' for '--min-pixels", "> 0"]),
        (&["render", "IN", "-o", "NEW.png", "--tolerance", "0"], 2, &["'0' for '--tolerance", "> 0"]),
        (&["render", "IN", "-o", "NEW.png", "--tolerance", "-1"], 2, &["'-1' for '--tolerance", "> 0"]),
        (&["render", "IN", "-o", "NEW.png", "--pixel-error", "-0.5"], 2, &["'-0.5' for '--pixel-error", "> 0"]),
        (&["render", "IN", "-o", "NEW.png", "--min-radius", "-1"], 2, &["'-1' for '--min-radius", "> 0"]),
        (&["render", "IN", "-o", "NEW.png", "--radius", "200%"], 2, &["'200%' for '--radius", "(0%, 100%]"]),
        (&["render", "IN", "-o", "NEW.png", "--radius", "-0.2"], 2, &["'-0.2' for '--radius", "positive"]),
        (&["render", "IN", "-o", "NEW.png", "--opacity", "0"], 2, &["'0' for '--opacity", "(0, 1]"]),
        (&["render", "IN", "-o", "NEW.png", "--fov", "180"], 2, &["'180' for '--fov", "(0, 180)"]),
        (&["render", "IN", "-o", "NEW.png", "--width", "0"], 2, &["'0' for '--width", "1..=32768"]),
        (&["render", "IN", "-o", "NEW.png", "--aa", "0"], 2, &["'0' for '--aa", "1..=16"]),
        (&["render", "IN", "-o", "NEW.png", "--eye", "1,2"], 2, &["'1,2' for '--eye", "x,y,z"]),
        (&["render", "IN", "-o", "NEW.png", "--subsample", "2"], 2, &["'2' for '--subsample", "(0, 1]"]),
        (&["render", "IN", "-o", "NEW.png", "--memory-limit", "0"], 2, &["'0' for '--memory-limit", "positive byte count"]),
        (&["render", "IN", "-o", "NEW.png", "-j", "0"], 2, &["'0' for '--threads"]),
        (&["render", "IN", "-o", "NEW.png", "--colormap", "rainbow"], 2, &["'rainbow' for '--colormap"]),
        (&["render", "IN", "-o", "NEW.png", "--background", "#12"], 2, &["'#12' for '--background", "#rrggbb"]),
        (&["render", "IN", "-o", "NEW.png", "--quant-bins", "7"], 2, &["'7' for '--quant-bins", "8..=64"]),
        (&["intersect", "IN", "--rays", "RAYS", "-o", "NEW.npy", "--radius", "200%"], 2, &["'200%' for '--radius"]),
        (&["intersect", "IN", "--rays", "RAYS", "-o", "NEW.npy", "--model", "mesh"], 2, &["'mesh' for '--model", "exact, quantized"]),
        (&["generate", "bundle", "--count", "0", "-o", "NEW.swc"], 2, &["'0' for '--count"]),
        (&["generate", "neurons", "--n", "41", "-o", "NEW.swc"], 2, &["'41' for '--n", "1..=40"]),
        (&["mesh", "IN", "--tolerance", "0", "-o", "NEW.ply"], 2, &["'0' for '--tolerance", "> 0"]),
        (&["simplify", "IN", "--tolerance", "-1", "-o", "NEW.swc"], 2, &["'-1' for '--tolerance", "> 0"]),
        (&["info", "IN", "--radius", "200%"], 2, &["'200%' for '--radius"]),
        // Flags that do not go together.
        (&["render", "IN", "-o", "NEW.png", "--model", "mesh"], 2, &["--model mesh needs --tolerance"]),
        (&["render", "TCK", "-o", "NEW.png", "--model", "quantized", "--color", "scalar:fa"], 2, &["--color scalar:fa", "no data fields"]),
        (&["info", "IN", "--model", "mesh"], 2, &["--model mesh needs --tolerance"]),
        // The job fails: a malformed input; nothing written.
        (&["render", "BAD", "-o", "NEW.png"], 1, &["table-bad.swc: line 1"]),
        (&["intersect", "BAD", "--rays", "RAYS", "-o", "NEW.npy"], 1, &["table-bad.swc: line 1"]),
        (&["mesh", "BAD", "--tolerance", "0.1", "-o", "NEW.ply"], 1, &["table-bad.swc: line 1"]),
    ];
    for (i, (args, code, says)) in cases.iter().enumerate() {
        let args: Vec<String> = args.iter().map(|a| resolve(a, i, &f)).collect();
        let olds: Vec<PathBuf> = ["png", "npy", "swc", "ply"].iter().map(|e| tmp(&format!("old.{e}"))).collect();
        for o in &olds {
            std::fs::write(o, KEPT).unwrap();
        }
        let out = bin().args(&args).output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(*code), "{args:?}: {err}");
        assert!(err.starts_with("tubecast: error: "), "{args:?}: {err}");
        for s in *says {
            assert!(err.contains(s), "{args:?}: {s:?} not in {err}");
        }
        assert!(!err.contains("unexpected argument"), "{args:?}: a value read as a flag: {err}");
        for a in &args {
            if Path::new(a).file_name().is_some_and(|n| n.to_string_lossy().starts_with(&format!("new{i}."))) {
                assert!(!Path::new(a).exists(), "{args:?}: {a} was created");
            }
        }
        for o in &olds {
            assert_eq!(std::fs::read(o).unwrap(), KEPT, "{args:?}: {} was overwritten", o.display());
        }
    }
}

#[test]
fn negative_numbers_are_values_and_force_overwrites() {
    let f = files("negative");
    let png = tmp("neg.png");
    let run = |extra: &[&str]| {
        let mut c = bin();
        c.arg("render").arg(&f.swc).args(["--width", "16", "--height", "12", "-q", "-o"]).arg(&png).args(extra);
        c.output().unwrap()
    };
    let out = run(&["--eye", "-30,-5,-2", "--look-at", "0,0,-1", "--up", "0,-1,0"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    std::fs::write(&png, KEPT).unwrap();
    let out = run(&["--eye", "-30,-5,-2", "--force"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert_eq!(&std::fs::read(&png).unwrap()[1..4], b"PNG", "--force replaced the file");
    // Every command that writes a file takes --force and -o.
    let hits = tmp("neg.npy");
    for _ in 0..2 {
        let mut c = bin();
        c.arg("intersect").arg(&f.swc).arg("--rays").arg(&f.rays).args(["--force", "-o"]).arg(&hits);
        assert!(c.status().unwrap().success());
        let swc = tmp("neg.swc");
        assert!(bin()
            .args(["generate", "helix", "--segments", "4", "--force", "-o"])
            .arg(&swc)
            .status()
            .unwrap()
            .success());
        let ply = tmp("neg.ply");
        let mut c = bin();
        c.arg("mesh").arg(&f.swc).args(["--tolerance", "0.05", "--force", "-q", "-o"]).arg(&ply);
        assert!(c.output().unwrap().status.success());
        let mut c = bin();
        c.arg("simplify").arg(&f.swc).args(["--tolerance", "0.05", "--force", "-o"]).arg(&swc);
        assert!(c.output().unwrap().status.success());
    }
}

#[test]
fn help_lists_only_what_each_command_does() {
    let help = |cmd: &str| String::from_utf8(bin().args([cmd, "--help"]).output().unwrap().stdout).unwrap();
    let intersect = help("intersect");
    assert!(!intersect.contains("mesh"), "intersect refuses --model mesh: {intersect}");
    assert!(intersect.contains("-o, --out") && intersect.contains("--force") && intersect.contains("-j, --threads"));
    let mesh = help("mesh");
    assert!(mesh.contains("Output mesh: .ply (binary), .obj or .glb") && !mesh.contains(".stl"), "{mesh}");
    let simplify = help("simplify");
    assert!(simplify.contains("--min-radius") && simplify.contains("of the input's format"), "{simplify}");
    let generate = help("generate");
    assert!(generate.contains(".swc or .obj (with radii), .tck or .trk (without)") && !generate.contains(".trx"));
    for cmd in ["render", "info", "intersect", "generate", "mesh", "simplify"] {
        let h = help(cmd);
        assert!(h.contains("-q, --quiet") && h.contains("-j, --threads <N>"), "{cmd}: {h}");
        if cmd != "info" {
            assert!(h.contains("-o, --out") && h.contains("--force"), "{cmd}: {h}");
        }
        if matches!(cmd, "info" | "mesh" | "simplify") {
            assert!(h.contains("--json"), "{cmd}: {h}");
        }
        if cmd != "generate" {
            assert!(h.contains("--radius <RADIUS>") && h.contains("--min-radius <R>"), "{cmd}: {h}");
        }
    }
}
