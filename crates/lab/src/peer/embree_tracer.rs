//! Embree 3 behind the renderer's [`Tracer`] trait, so the dynamic-scene report can build it
//! every frame and render through the same per-pixel code as the grid and the BVH.
//!
//! Embree answers in `f32` with its own curve intersector, so this tracer does **not** meet
//! [`Tracer`]'s "same answers as the BVH" contract: hits are Embree's (`t`, `Ng`, `u`, rounded
//! to `f32`), and the report only times it and compares its images with ours.
//!
//! # Transparency as an Embree user does it
//! A closest-hit query reports one surface crossing per segment, not the segment's interval,
//! so Embree cannot feed our CSG union directly. [`Tracer::line_intervals`] therefore does what
//! an Embree application does for transparent tubes: it collects every surface Embree reports
//! along the ray ([`EmbreeTracer::surfaces`]: closest hit, then the ray cast again from just
//! past it, until a cast misses; a cast from inside a segment reports where it leaves) and
//! hands each as an *entry-only* interval, whose exit is `−∞`. [`tubecast::csg::union`] merges
//! an interval into the previous one only when it starts at or before that one's exit, and
//! emits an exit only inside the ray's range, so every reported surface comes out as a
//! boundary of its own and the renderer composites all of them front to back with the same
//! opacity. Unlike our union, surfaces inside other tubes (every joint of a polyline, where
//! consecutive links overlap, and crossings) are composited too: overlaps count once per
//! surface.
//!
//! Re-casting rather than an intersection-filter callback that records and rejects every
//! candidate: the re-cast needs no new `unsafe` FFI (a filter is a C callback writing through
//! a raw pointer), its hits come back already sorted and each is Embree's own closest hit
//! (a filter sees candidates in traversal order, possibly several per segment), at the price
//! of one traversal per surface.

use super::embree::{Device, EmbreeError, Scene};
use std::sync::Arc;
use tubecast::csg::Tagged;
use tubecast::{Crossing, Interval, Ray, RoundCone, V3};
use tubecast_render::accel::{Hit, Tracer};
use tubecast_render::scene::Prim;

/// An Embree `ROUND_LINEAR_CURVE` scene over link primitives (one isolated segment each).
pub struct EmbreeTracer {
    prims: Vec<Prim>,
    scene: Scene,
    bytes: usize,
}

/// The world-space `f32` round cone of a link or sphere primitive (`None` for a spline piece).
fn world_cone(p: &Prim) -> Option<RoundCone<f32>> {
    let c = p.round_cone()?;
    let o = V3::from(p.origin);
    let a = (o + c.a.cast::<f64>()).cast::<f32>();
    let b = (o + c.b.cast::<f64>()).cast::<f32>();
    Some(RoundCone { a, ra: c.ra, b, rb: c.rb })
}

impl EmbreeTracer {
    /// Builds (commits) an Embree scene of `prims` on `device`. Errors: a spline primitive
    /// (Embree's curves are not our sphere-swept splines), no primitives, or an Embree failure.
    pub fn build(device: &Arc<Device>, prims: Vec<Prim>) -> Result<Self, EmbreeError> {
        let links: Vec<RoundCone<f32>> = prims
            .iter()
            .map(|p| world_cone(p).ok_or_else(|| EmbreeError("spline primitives are not supported".into())))
            .collect::<Result<_, _>>()?;
        let before = device.memory_bytes();
        let scene = Scene::round_linear(device, &links)?;
        let bytes = (device.memory_bytes() - before).max(0) as usize;
        Ok(Self { prims, scene, bytes })
    }
}

impl EmbreeTracer {
    /// Embree's closest hit of `ray` with `t ∈ [t_near, t_max]`, as a [`Hit`] whose normal is
    /// unit and faces the ray.
    fn hit_from(&self, ray: &Ray<f64>, t_near: f64) -> Option<Hit> {
        let h = self.scene.intersect(to32(ray.o), to32(ray.d), t_near as f32, ray.t_max as f32)?;
        let ng = V3::from(h.ng).cast::<f64>();
        let len = ng.length();
        // Embree's Ng is not normalised and may face either way: make it a unit normal facing
        // the ray (the entry side), and fall back to −d where it vanishes.
        let mut n = if len > 0.0 && len.is_finite() { ng.scale(1.0 / len) } else { -ray.d.normalize_or_zero() };
        if n.dot(ray.d) > 0.0 {
            n = -n;
        }
        self.prims.get(h.prim as usize)?;
        Some(Hit { t: f64::from(h.t), n, u: f64::from(h.u), id: h.prim, entering: true })
    }

    /// Every surface Embree reports along `ray` in `[t_min, t_max]`, nearest first, appended
    /// to `out`: the closest hit, then the ray cast again from just past it (by a thousandth
    /// of the hit segment's radius, or 2⁻²⁰·|t| where that is larger, at least 8 `f32` ulps of
    /// `t`, so every cast starts strictly further) until a cast misses. At most
    /// `4·segments + 16` casts, so a pathological answer cannot loop.
    pub fn surfaces(&self, ray: &Ray<f64>, out: &mut Vec<Hit>) {
        let mut t_near = ray.t_min;
        for _ in 0..4 * self.prims.len() + 16 {
            let Some(h) = self.hit_from(ray, t_near) else { return };
            let r = self.prims[h.id as usize].max_radius() as f64;
            let next = (h.t + (1e-3 * r).max(h.t.abs() * 2f64.powi(-20))) as f32;
            t_near = f64::from(if next > h.t as f32 { next } else { next_up(h.t as f32) });
            out.push(h);
        }
    }
}

/// The next `f32` above finite `x` (`f32::next_up`, stable only since Rust 1.86; MSRV 1.80).
fn next_up(x: f32) -> f32 {
    match x {
        0.0 => f32::from_bits(1),
        x if x > 0.0 => f32::from_bits(x.to_bits() + 1),
        x => f32::from_bits(x.to_bits() - 1),
    }
}

fn to32(v: V3<f64>) -> [f32; 3] {
    v.cast::<f32>().to_array()
}

impl Tracer for EmbreeTracer {
    fn prim(&self, id: u32) -> Prim {
        self.prims[id as usize]
    }
    fn prim_count(&self) -> usize {
        self.prims.len()
    }

    fn closest_hit(&self, ray: &Ray<f64>) -> Option<Hit> {
        self.hit_from(ray, ray.t_min)
    }

    fn any_hit(&self, ray: &Ray<f64>) -> bool {
        self.scene.occluded(to32(ray.o), to32(ray.d), ray.t_min as f32, ray.t_max as f32)
    }

    /// Every surface Embree reports along the ray within its range, each as an entry-only
    /// interval (exit `−∞`); see the module docs.
    fn line_intervals(&self, ray: &Ray<f64>, out: &mut Vec<Tagged<f64>>) {
        let mut hits = Vec::new();
        self.surfaces(ray, &mut hits);
        out.extend(hits.into_iter().map(|h| Tagged {
            iv: Interval::new(
                Crossing { t: h.t, n: h.n, u: h.u },
                Crossing { t: f64::NEG_INFINITY, n: h.n, u: h.u },
                true,
            ),
            id: h.id,
        }));
    }

    fn memory_bytes(&self) -> usize {
        self.bytes + std::mem::size_of_val(self.prims.as_slice())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use tubecast_render::accel::Bvh;
    use tubecast_render::io::Polyline;
    use tubecast_render::scene::Scene as TScene;

    #[test]
    fn embree_tracer_finds_the_bvh_hits_within_f32_rounding() {
        // Tube of radius 0.5 along x from 0 to 4 at y = z = 0 (4 links). A ray down −y from
        // y = 3 over x = 1.3 enters at t = 2.5 exactly (both tracers); Embree's f32 answer is
        // within a few ulps of 3 (|t| ≤ 3, so 1e-5 is > 20 ulps). A ray that passes at z = 0.6
        // misses both. The shadow query agrees with the hit.
        let line = Polyline { points: (0..5).map(|k| [k as f64, 0.0, 0.0]).collect(), radii: vec![] };
        let scene = TScene::from_polylines(&[line], 0.5, "tube").unwrap();
        let dev = Device::with_threads(1).unwrap();
        let e = EmbreeTracer::build(&dev, scene.primitives()).unwrap();
        let b = Bvh::build(scene.primitives());
        let hit_ray = Ray::new(V3::new(1.3, 3.0, 0.0), V3::new(0.0, -1.0, 0.0));
        let (he, hb) = (e.closest_hit(&hit_ray).unwrap(), b.closest_hit(&hit_ray).unwrap());
        assert!((he.t - 2.5).abs() < 1e-5 && (hb.t - 2.5).abs() < 1e-12, "{he:?} {hb:?}");
        assert!((he.n - V3::new(0.0, 1.0, 0.0)).length() < 1e-5, "{he:?}");
        assert_eq!(e.prim(he.id).link, 1, "x = 1.3 lies on link 1");
        assert!(e.any_hit(&hit_ray));
        let miss = Ray::new(V3::new(1.3, 3.0, 0.6), V3::new(0.0, -1.0, 0.0));
        assert!(e.closest_hit(&miss).is_none() && b.closest_hit(&miss).is_none() && !e.any_hit(&miss));
        assert!(e.memory_bytes() > 0);
    }

    #[test]
    fn transparent_surfaces_are_every_crossing_overlaps_included() {
        // Two single-link tubes of radius 0.5 along x, at y = 0 and y = −2. A ray down −y from
        // y = 3 over x = 1.3 enters them at t = 2.5 and 4.5 and leaves at 3.5 and 5.5 (exact in
        // f64; Embree's f32 within 1e-5 of each, > 20 ulps at |t| ≤ 6): re-cast from inside,
        // Embree reports the exits too, and each surface is a boundary of its own.
        let line = |y: f64, x1: f64| Polyline { points: vec![[0.0, y, 0.0], [x1, y, 0.0]], radii: vec![] };
        let scene = TScene::from_polylines(&[line(0.0, 4.0), line(-2.0, 4.0)], 0.5, "two").unwrap();
        let dev = Device::with_threads(1).unwrap();
        let e = EmbreeTracer::build(&dev, scene.primitives()).unwrap();
        let b = Bvh::build(scene.primitives());
        let ray = Ray::new(V3::new(1.3, 3.0, 0.0), V3::new(0.0, -1.0, 0.0));
        let near = |got: &[f64], want: &[f64]| {
            got.len() == want.len() && got.iter().zip(want).all(|(g, w)| (g - w).abs() < 1e-5)
        };
        let mut hits = Vec::new();
        e.surfaces(&ray, &mut hits);
        let ts: Vec<f64> = hits.iter().map(|h| h.t).collect();
        assert!(near(&ts, &[2.5, 3.5, 4.5, 5.5]), "{ts:?}");
        let bounds = |t: &dyn Tracer, ray: &Ray<f64>| {
            let mut ivs = Vec::new();
            t.line_intervals(ray, &mut ivs);
            let mut out = Vec::new();
            tubecast::csg::union(&mut ivs, ray.t_min, ray.t_max, |b| out.push((b.t, b.entering)));
            out
        };
        let eb: Vec<f64> = bounds(&e, &ray).iter().map(|b| b.0).collect();
        assert!(near(&eb, &[2.5, 3.5, 4.5, 5.5]), "{eb:?}");
        assert_eq!(bounds(&b, &ray), [(2.5, true), (3.5, false), (4.5, true), (5.5, false)]);
        // One polyline of two links, 0→2→4: over x = 1.9 the ray crosses link 0's side (2.5,
        // 3.5) and link 1's start sphere (centre x = 2, 0.1 away: 3 ∓ √(0.25 − 0.01) =
        // 2.51010, 3.48990), inside link 0. Our union has two boundaries; Embree's four.
        let joint = TScene::from_polylines(
            &[Polyline { points: vec![[0.0; 3], [2.0, 0.0, 0.0], [4.0, 0.0, 0.0]], radii: vec![] }],
            0.5,
            "joint",
        )
        .unwrap();
        let (ej, bj) = (EmbreeTracer::build(&dev, joint.primitives()).unwrap(), Bvh::build(joint.primitives()));
        let over = Ray::new(V3::new(1.9, 3.0, 0.0), V3::new(0.0, -1.0, 0.0));
        let s = 0.24f64.sqrt();
        let ej: Vec<f64> = bounds(&ej, &over).iter().map(|b| b.0).collect();
        assert!(near(&ej, &[2.5, 3.0 - s, 3.0 + s, 3.5]), "{ej:?}");
        assert_eq!(bounds(&bj, &over).len(), 2);
        let miss = Ray::new(V3::new(1.3, 3.0, 0.6), V3::new(0.0, -1.0, 0.0));
        assert!(bounds(&e, &miss).is_empty());
    }
}
