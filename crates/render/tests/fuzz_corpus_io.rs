//! Replays the committed fuzz corpora of the file readers (fuzz/corpus/{swc,trk,tck,obj,npy,trx})
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
mod trx {
    include!("../../../fuzz/checks/trx.rs");
}

include!("../../../fuzz/checks/replay.rs");

fn replay(name: &str, check: fn(&[u8])) {
    let corpus = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fuzz/corpus");
    replay_corpus(&corpus, name, check, 3);
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
#[test]
fn trx_corpus() {
    replay("trx", trx::check);
}
