//! Conversions to glam, nalgebra and mint (one section per feature): round trips are exact,
//! and a kernel fed from the other library's values gives the same interval as one fed
//! from `V3` directly.
#![allow(unused_imports)]
use tubecast::{Primitive, Ray, RoundCone, Sphere, V3};

/// A link and a ray that hits it, in f64 (exactly representable in f32).
#[cfg(any(feature = "glam", feature = "nalgebra", feature = "mint"))]
fn link_and_ray() -> (RoundCone<f64>, Ray<f64>) {
    let link = RoundCone::new(V3::new(0.5, -1.0, 2.0), 1.0, V3::new(4.5, 0.25, 2.0), 0.5).unwrap();
    (link, Ray::new(V3::new(2.0, -10.0, 2.25), V3::new(0.125, 1.0, 0.0)))
}

#[cfg(feature = "glam")]
mod glam_section {
    use super::*;
    use glam::{DVec3, Vec3, Vec3A};

    #[test]
    fn round_trips() {
        let v = V3::new(1.5f32, -2.25, 1e-30);
        assert_eq!(V3::from(Vec3::from(v)), v);
        assert_eq!(V3::from(Vec3A::from(v)), v);
        assert_eq!(Vec3::from(v), Vec3::new(1.5, -2.25, 1e-30));
        assert_eq!(Vec3A::from(v), Vec3A::new(1.5, -2.25, 1e-30));
        let w = V3::new(1.5f64, -2.25, 1e-300);
        assert_eq!(V3::from(DVec3::from(w)), w);
        assert_eq!(DVec3::from(w), DVec3::new(1.5, -2.25, 1e-300));
    }

    #[test]
    fn kernel_fed_from_glam() {
        let (l, r) = link_and_ray();
        let (a, b) = (DVec3::new(0.5, -1.0, 2.0), DVec3::new(4.5, 0.25, 2.0));
        let link = RoundCone::new(a.into(), 1.0, b.into(), 0.5).unwrap();
        let ray: Ray<f64> = (DVec3::new(2.0, -10.0, 2.25), DVec3::new(0.125, 1.0, 0.0)).into();
        assert_eq!(ray, r);
        let iv = link.intersect(&ray);
        assert!(iv.hit);
        assert_eq!(iv, l.intersect(&r));
        // f32 through Vec3 and Vec3A.
        let (l32, r32) = (l.cast::<f32>(), Ray::new(r.o.cast::<f32>(), r.d.cast::<f32>()));
        let ray3: Ray<f32> = (Vec3::from(r32.o), Vec3::from(r32.d)).into();
        let ray3a: Ray<f32> = (Vec3A::from(r32.o), Vec3A::from(r32.d)).into();
        assert_eq!(l32.intersect(&ray3), l32.intersect(&r32));
        assert_eq!(l32.intersect(&ray3a), l32.intersect(&r32));
        let entry: Vec3 = ray3.at(l32.intersect(&ray3).entry.t).into();
        assert!(entry.y < 0.0);
    }
}

#[cfg(feature = "nalgebra")]
mod nalgebra_section {
    use super::*;
    use nalgebra::{Point3, Vector3};
    use tubecast::{Mask, Real, WideF32x8, WideF64x4};

    #[test]
    fn round_trips() {
        let v = V3::new(1.5f32, -2.25, 1e-30);
        assert_eq!(V3::from(Vector3::from(v)), v);
        assert_eq!(V3::from(Point3::from(v)), v);
        assert_eq!(Vector3::from(v), Vector3::new(1.5, -2.25, 1e-30));
        let w = V3::new(1.5f64, -2.25, 1e-300);
        assert_eq!(V3::from(Vector3::from(w)), w);
        assert_eq!(Point3::from(w), Point3::new(1.5, -2.25, 1e-300));
        // Lanes: simba's types, shared with nalgebra.
        let l8 = V3::<WideF32x8>::from_fn(|i| V3::new(i as f32, -(i as f32), 0.5));
        let n8: Vector3<WideF32x8> = l8.into();
        for i in 0..8 {
            assert_eq!(V3::from(n8).lane(i), l8.lane(i));
            assert_eq!(n8.x.lane(i), i as f32);
        }
        let l4 = V3::<WideF64x4>::from_fn(|i| V3::new(0.5, i as f64, 1e-300));
        let p4: Point3<WideF64x4> = l4.into();
        for i in 0..4 {
            assert_eq!(V3::from(p4).lane(i), l4.lane(i));
            assert_eq!(p4.y.lane(i), i as f64);
        }
    }

    #[test]
    fn kernel_fed_from_nalgebra() {
        let (l, r) = link_and_ray();
        let link = RoundCone::new(Point3::new(0.5, -1.0, 2.0).into(), 1.0, Vector3::new(4.5, 0.25, 2.0).into(), 0.5);
        let ray: Ray<f64> = (Point3::new(2.0, -10.0, 2.25), Vector3::new(0.125, 1.0, 0.0)).into();
        assert_eq!(ray, r);
        let iv = link.unwrap().intersect(&ray);
        assert!(iv.hit);
        assert_eq!(iv, l.intersect(&r));
        // Eight lanes from nalgebra lane vectors.
        let o8: Point3<WideF32x8> = V3::broadcast(r.o.cast::<f32>()).into();
        let d8: Vector3<WideF32x8> = V3::from_fn(|i| r.d.cast::<f32>() + V3::new(0.01 * i as f32, 0.0, 0.0)).into();
        let ray8: Ray<WideF32x8> = (o8, d8).into();
        let l32 = l.cast::<f32>();
        let iv8 = RoundCone::<WideF32x8>::broadcast(l32).intersect(&ray8);
        for i in 0..8 {
            assert_eq!(iv8.lane(i), l32.intersect(&ray8.lane(i)));
        }
        assert!(iv8.hit.lane(0));
    }
}

#[cfg(feature = "mint")]
mod mint_section {
    use super::*;

    #[test]
    fn round_trips() {
        let v = V3::new(1.5f32, -2.25, 1e-30);
        let m: mint::Vector3<f32> = v.into();
        assert_eq!((m.x, m.y, m.z), (1.5, -2.25, 1e-30));
        assert_eq!(V3::from(m), v);
        let w = V3::new(1.5f64, -2.25, 1e-300);
        let p: mint::Point3<f64> = w.into();
        assert_eq!((p.x, p.y, p.z), (1.5, -2.25, 1e-300));
        assert_eq!(V3::from(p), w);
    }

    #[test]
    fn kernel_fed_from_mint() {
        let c = mint::Point3 { x: 0.0, y: 0.0, z: 10.0 };
        let ball = Sphere::new(c.into(), 2.0).unwrap();
        let ray =
            Ray::new(mint::Point3 { x: 0.0, y: 0.0, z: 0.0 }.into(), mint::Vector3 { x: 0.0, y: 0.0, z: 1.0 }.into());
        let iv = ball.intersect(&ray);
        assert_eq!((iv.entry.t, iv.exit.t), (8.0, 12.0));
        let n: mint::Vector3<f64> = iv.entry.n.into();
        assert_eq!((n.x, n.y, n.z), (0.0, 0.0, -1.0));
    }
}
