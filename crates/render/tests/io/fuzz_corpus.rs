//! Replays the committed fuzz corpora of the file readers (fuzz/corpus/{swc,trk,tck,obj,npy,trx})
//! through the same checks the fuzz targets run (fuzz/checks/*.rs), on stable Rust.

mod swc {
    include!("../../../../fuzz/checks/swc.rs");
}
mod trk {
    include!("../../../../fuzz/checks/trk.rs");
}
mod tck {
    include!("../../../../fuzz/checks/tck.rs");
}
mod obj {
    include!("../../../../fuzz/checks/obj.rs");
}
mod npy {
    include!("../../../../fuzz/checks/npy.rs");
}
mod accel {
    include!("../../../../fuzz/checks/accel.rs");
}
mod trx {
    include!("../../../../fuzz/checks/trx.rs");
}

include!("../../../../fuzz/checks/replay.rs");

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
fn accel_corpus() {
    replay("accel", accel::check);
}

/// The accelerator check fires: a tracer that answers from a different primitive set (one of the
/// two links dropped) disagrees with brute force on a ray through the dropped link only
/// (hand-made: links along x at y = 0 and y = 10, radius 1; the ray goes down through x = 1,
/// y = 10).
#[test]
#[should_panic(expected = "closest hit")]
fn accel_check_catches_a_missing_primitive() {
    use tubecast::{Ray, RoundCone, V3};
    use tubecast_render::accel::Bvh;
    use tubecast_render::scene::Prim;
    let l = |y: f64| RoundCone::new(V3::new(0.0, y, 0.0), 1.0, V3::new(2.0, y, 0.0), 1.0).unwrap();
    let prims = vec![Prim::from_link(&l(0.0), 0), Prim::from_link(&l(10.0), 1)];
    let partial = Bvh::build(vec![prims[0]]);
    let ray = Ray::new(V3::new(1.0, 10.0, 5.0), V3::new(0.0, 0.0, -1.0));
    accel::agree("partial", &partial, &prims, &ray);
}

#[test]
fn trx_corpus() {
    replay("trx", trx::check);
}
