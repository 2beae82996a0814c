//! Replays the committed fuzz corpora of the file readers (fuzz/corpus/{swc,trk,tck,obj,npy})
//! through the same checks the fuzz targets run (fuzz/checks/*.rs), on stable Rust.

mod swc {
    include!("../../../fuzz/checks/swc.rs");
}
mod trk {
    include!("../../../fuzz/checks/trk.rs");
}
mod tck {
    include!("../../../fuzz/checks/tck.rs");
}
mod obj {
    include!("../../../fuzz/checks/obj.rs");
}
mod npy {
    include!("../../../fuzz/checks/npy.rs");
}

fn replay(name: &str, check: fn(&[u8])) {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fuzz/corpus").join(name);
    let mut n = 0;
    for e in std::fs::read_dir(&dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display())) {
        let p = e.unwrap().path();
        if p.is_file() {
            let data = std::fs::read(&p).unwrap();
            let r = std::panic::catch_unwind(|| check(&data));
            assert!(r.is_ok(), "{} violates the {name} invariants", p.display());
            n += 1;
        }
    }
    assert!(n >= 3, "corpus {name} has {n} files");
}

#[test]
fn swc_corpus() {
    replay("swc", swc::check);
}
#[test]
fn trk_corpus() {
    replay("trk", trk::check);
}
#[test]
fn tck_corpus() {
    replay("tck", tck::check);
}
#[test]
fn obj_corpus() {
    replay("obj", obj::check);
}
#[test]
fn npy_corpus() {
    replay("npy", npy::check);
}
