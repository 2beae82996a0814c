//! Lane packets: the links (cylinders and cones) of a BVH leaf tested together by one call of
//! the lane kernel `RoundCone::<WideF32x8>::intersect`, eight links per call.
//!
//! A packet holds up to [`LANES`] consecutive links of one leaf (the builder moves a leaf's
//! links to its front), each stored exactly as the scalar path stores it: `f32` centres and
//! radii relative to the link's own `f64` local origin. A query moves the ray to each lane's
//! local origin in `f64` with the very operations of the scalar path
//! ([`Prim::local_origin`]), so each lane sees the same `f32` ray as the scalar kernel would;
//! the lane kernel equals the scalar one bit for bit (`tests/kernels/link/properties.rs`,
//! `lanes_equal_scalar_bitwise`), and each lane's interval is mapped back to the world ray by
//! the scalar path's [`Prim::to_world`]. A packet's result per link is therefore
//! bit-identical to [`Prim::intersect`]. Unused lanes repeat the packet's first link (a valid
//! link, so no lane computes on garbage) and their results are never read.

use crate::scene::Prim;
use tubecast::{Interval, Primitive, Ray};
use tubecast::{Mask, Real, WideF32x8};
use tubecast::{RoundCone, V3};

/// Links per packet.
pub(crate) const LANES: usize = 8;

/// Up to [`LANES`] links in SoA lanes.
pub(crate) struct Packet {
    cone: RoundCone<WideF32x8>,
    /// Number of used lanes (`1..=LANES`).
    pub n: usize,
}

impl Packet {
    /// A packet of the round cones of `1..=LANES` link primitives, in order.
    pub fn new(cones: &[RoundCone<f32>]) -> Self {
        debug_assert!(!cones.is_empty() && cones.len() <= LANES);
        let cone = RoundCone::from_lanes(|i| cones[if i < cones.len() { i } else { 0 }]);
        Self { cone, n: cones.len() }
    }

    /// Each link's interval with `ray`'s line, hit mask clipped to its range, exactly as
    /// [`Prim::intersect`] gives it: `emit(lane, interval)` for every used lane whose
    /// interval is a hit, in lane order. `links` are the packet's primitives; `dn`, `len`:
    /// the ray's unit direction and length, computed as [`Prim::intersect`] does.
    #[inline]
    pub fn intersect(
        &self,
        links: &[Prim],
        ray: &Ray<f64>,
        dn: V3<f64>,
        len: f64,
        mut emit: impl FnMut(usize, Interval<f64>),
    ) {
        let mut tc = [0.0f64; LANES];
        let mut o = [V3::<f32>::default(); LANES];
        for (i, p) in links.iter().enumerate().take(self.n) {
            (o[i], tc[i]) = p.local_origin(ray.o, dn);
        }
        let (o0, tc0) = (o[0], tc[0]);
        o[self.n..].fill(o0);
        tc[self.n..].fill(tc0);
        let inf = WideF32x8::splat(f32::INFINITY);
        let rl = Ray::with_range(V3::from_fn(|i| o[i]), V3::broadcast(dn.cast::<f32>()), -inf, inf);
        let iv = self.cone.intersect(&rl);
        if !iv.hit.any() {
            return;
        }
        for (i, &tci) in tc.iter().enumerate().take(self.n) {
            if iv.hit.lane(i) {
                let w = Prim::to_world(&iv.lane(i), tci, len, ray);
                if w.hit {
                    emit(i, w);
                }
            }
        }
    }

    /// Bytes held by one packet.
    pub const BYTES: usize = std::mem::size_of::<Self>();
}
