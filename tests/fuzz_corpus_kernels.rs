//! Replays the committed fuzz corpora of the kernel targets (fuzz/corpus/{link,sphere,spline,csg})
//! on stable Rust, through the same checks the fuzz targets run (fuzz/checks/*.rs).

include!("../fuzz/checks/replay.rs");

mod link {
    include!("../fuzz/checks/link.rs");
}
mod sphere {
    include!("../fuzz/checks/sphere.rs");
}
mod spline {
    include!("../fuzz/checks/spline.rs");
}
mod csg {
    include!("../fuzz/checks/csg.rs");
}

fn replay(name: &str, check: fn(&[u8])) {
    replay_corpus(&std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("fuzz/corpus"), name, check, 10);
}

#[test]
fn replay_link_corpus() {
    replay("link", link::check);
}

#[test]
fn replay_sphere_corpus() {
    replay("sphere", sphere::check);
}

#[test]
fn replay_spline_corpus() {
    replay("spline", spline::check);
}

#[test]
fn replay_csg_corpus() {
    replay("csg", csg::check);
}

/// The check does fire: a hand-made interval with t_in > t_out is rejected by `sane`.
#[test]
#[should_panic(expected = "t_in > t_out")]
fn check_catches_a_bad_interval() {
    let mut iv = tubecast::Interval::<f64>::miss();
    iv.hit = true;
    iv.t_in = 1.0;
    iv.t_out = 0.0;
    iv.n_in = tubecast::V3::new(1.0, 0.0, 0.0);
    iv.n_out = iv.n_in;
    spline::sane(&iv);
}
