use tubecast::*;
fn main() {
    let l = RoundCone::new(V3::new(0.0, 0.0, 0.0), 1.0, V3::new(4.0, 0.0, 0.0), 0.5).unwrap();
    for (o, d) in [
        (V3::new(2.0, -10.0, 0.0), V3::new(0.0, 1.0, 0.0)),
        (V3::new(-10.0, 0.0, 0.0), V3::new(1.0, 0.0, 0.0)),
        (V3::new(-10.0, 0.3, 0.2), V3::new(1.0, 0.0, 0.0)),
        (V3::new(1.0, 0.0, 0.0), V3::new(0.3, 1.0, 0.2)),
        (V3::new(2.0, 10.0, 0.74), V3::new(0.0, -1.0, 0.0)),
    ] {
        let r = Ray::new(o, d);
        let a = l.intersect(&r);
        let b = HanLink::new(&l).intersect(&r);
        let s = l.intersect_stump_stable(&r);
        println!("stable {:?} {:?} {:?} {:?} {:?}", a.hit, a.t_in, a.t_out, a.n_in, a.u_in);
        println!("han    {:?} {:?} {:?} {:?} {:?}", b.hit, b.t_in, b.t_out, b.n_in, b.u_in);
        println!("stump  {:?} {:?} {:?}", s.hit, s.t_in, s.t_out);
        if a.hit { let x = r.at(a.t_in); println!("  sdf {:e} {:e}", kernel::sdf::round_cone(x, &l), kernel::sdf::round_cone(r.at(a.t_out), &l)); }
    }
}
