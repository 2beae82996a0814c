//! Replays the committed fuzz corpora of the kernel targets (fuzz/corpus/{link,sphere,spline,csg})
//! on stable Rust, through the same checks the fuzz targets run (fuzz/checks/*.rs).

include!("../../fuzz/checks/replay.rs");

mod link {
    include!("../../fuzz/checks/link.rs");
}
mod sphere {
    include!("../../fuzz/checks/sphere.rs");
}
mod spline {
    include!("../../fuzz/checks/spline.rs");
}
mod csg {
    include!("../../fuzz/checks/csg.rs");
}
mod differential {
    include!("../../fuzz/checks/differential.rs");
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

#[test]
fn replay_differential_corpus() {
    replay("differential", differential::check);
}

/// The differential check does fire: a "Han" answer moved by far more than its bound is a
/// finding (a hand-made disagreement: a cylinder of radius 1 along x, a ray down the y axis
/// at x = 1; the stable kernel's entry is t = 2, exact).
#[test]
fn differential_check_catches_a_disagreement() {
    use tubecast::{Primitive, Ray, RoundCone, V3};
    let link = RoundCone::new(V3::new(0.0, 0.0, 0.0), 1.0, V3::new(2.0, 0.0, 0.0), 1.0).unwrap();
    let ray = Ray::new(V3::new(1.0, 3.0, 0.0), V3::new(0.0, -1.0, 0.0));
    assert!(differential::agree(&link, &ray).is_ok());
    let stable = link.intersect(&ray);
    assert_eq!((stable.hit, stable.entry.t), (true, 2.0));
    let mut moved = stable;
    moved.entry.t += 1e-6;
    let e = 1e-12; // far above E₆₄ ≈ 64ε·5 ≈ 7e-14 for this case, far below the 1e-6 shift
    assert!(differential::same_t(&stable, &moved, &link, &ray, e).is_err());
}

/// The check does fire: a hand-made interval with t_in > t_out is rejected by `sane`.
#[test]
#[should_panic(expected = "t_in > t_out")]
fn check_catches_a_bad_interval() {
    let mut iv = tubecast::Interval::<f64>::miss();
    iv.hit = true;
    iv.entry.t = 1.0;
    iv.exit.t = 0.0;
    iv.entry.n = tubecast::V3::new(1.0, 0.0, 0.0);
    iv.exit.n = iv.entry.n;
    spline::sane(&iv);
}
