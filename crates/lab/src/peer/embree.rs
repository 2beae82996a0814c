//! A small hand-written FFI to Embree 3 (`libembree3`), enough to build a scene of round
//! linear or round Hermite curves and shoot single rays at it.
//!
//! Layouts follow the installed `embree3/rtcore_*.h` (3.13, `RTC_MAX_INSTANCE_LEVEL_COUNT = 1`,
//! `RTC_MIN_WIDTH = 0`): `RTCRay` 48 bytes and `RTCHit` 32 bytes, both 16-byte aligned;
//! `RTCIntersectContext` = `{flags: u32, filter: fn ptr, instID: [u32; 1]}`. The size checks in
//! the tests guard them.
//!
//! Embree asks callers to set flush-to-zero and denormals-are-zero in MXCSR; every entry point
//! here sets both for the duration of the call and restores the caller's MXCSR afterwards, so
//! the crate's own kernels never run with them.

use tubecast::RoundCone;

use std::ffi::c_void;
use std::os::raw::c_char;

type RtcDevice = *mut c_void;
type RtcScene = *mut c_void;
type RtcGeometry = *mut c_void;

const GEOMETRY_ROUND_LINEAR_CURVE: u32 = 16;
const GEOMETRY_ROUND_HERMITE_CURVE: u32 = 40;
const BUFFER_INDEX: u32 = 0;
const BUFFER_VERTEX: u32 = 1;
const BUFFER_TANGENT: u32 = 4;
const BUFFER_FLAGS: u32 = 32;
const FORMAT_UCHAR: u32 = 0x1001;
const FORMAT_UINT: u32 = 0x5001;
const FORMAT_FLOAT4: u32 = 0x9004;
const BUILD_QUALITY_HIGH: u32 = 2;
const SCENE_FLAG_ROBUST: u32 = 1 << 2;
const INVALID_ID: u32 = u32::MAX;

#[repr(C, align(16))]
#[derive(Clone, Copy, Debug, Default)]
struct RtcRay {
    org: [f32; 3],
    tnear: f32,
    dir: [f32; 3],
    time: f32,
    tfar: f32,
    mask: u32,
    id: u32,
    flags: u32,
}

#[repr(C, align(16))]
#[derive(Clone, Copy, Debug, Default)]
struct RtcHit {
    ng: [f32; 3],
    u: f32,
    v: f32,
    prim_id: u32,
    geom_id: u32,
    inst_id: [u32; 1],
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
struct RtcRayHit {
    ray: RtcRay,
    hit: RtcHit,
}

#[repr(C)]
struct RtcIntersectContext {
    flags: u32,
    filter: Option<unsafe extern "C" fn(*const c_void)>,
    inst_id: [u32; 1],
}

#[link(name = "embree3")]
extern "C" {
    fn rtcNewDevice(config: *const c_char) -> RtcDevice;
    fn rtcReleaseDevice(device: RtcDevice);
    fn rtcGetDeviceError(device: RtcDevice) -> u32;
    fn rtcNewScene(device: RtcDevice) -> RtcScene;
    fn rtcReleaseScene(scene: RtcScene);
    fn rtcSetSceneBuildQuality(scene: RtcScene, quality: u32);
    fn rtcSetSceneFlags(scene: RtcScene, flags: u32);
    fn rtcCommitScene(scene: RtcScene);
    fn rtcNewGeometry(device: RtcDevice, kind: u32) -> RtcGeometry;
    fn rtcSetNewGeometryBuffer(
        geometry: RtcGeometry,
        kind: u32,
        slot: u32,
        format: u32,
        byte_stride: usize,
        item_count: usize,
    ) -> *mut c_void;
    fn rtcCommitGeometry(geometry: RtcGeometry);
    fn rtcAttachGeometry(scene: RtcScene, geometry: RtcGeometry) -> u32;
    fn rtcReleaseGeometry(geometry: RtcGeometry);
    fn rtcIntersect1(scene: RtcScene, context: *mut RtcIntersectContext, rayhit: *mut RtcRayHit);
    fn rtcOccluded1(scene: RtcScene, context: *mut RtcIntersectContext, ray: *mut RtcRay);
    fn rtcSetDeviceMemoryMonitorFunction(
        device: RtcDevice,
        monitor: Option<unsafe extern "C" fn(*mut c_void, isize, bool) -> bool>,
        user: *mut c_void,
    );
}

/// Embree's memory monitor callback (`RTCMemoryMonitorFunction`): adds `bytes` (negative on a
/// free) to the counter `user` points to and lets the allocation proceed.
unsafe extern "C" fn count_bytes(user: *mut c_void, bytes: isize, _post: bool) -> bool {
    // SAFETY: `user` is the `AtomicIsize` owned by the `Device` that registered this callback;
    // Embree calls it only while the device lives (it is unregistered before release).
    let counter = unsafe { &*(user as *const std::sync::atomic::AtomicIsize) };
    counter.fetch_add(bytes, std::sync::atomic::Ordering::Relaxed);
    true
}

/// One `ROUND_HERMITE_CURVE` segment: `([p0, r0], [m0, dr0], [p1, r1], [m1, dr1])`.
pub type HermiteSegment = ([f32; 4], [f32; 4], [f32; 4], [f32; 4]);

/// An Embree call failed.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct EmbreeError(pub String);

impl std::fmt::Display for EmbreeError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "embree: {}", self.0)
    }
}
impl std::error::Error for EmbreeError {}

/// Sets FTZ and DAZ for its lifetime (x86-64), restoring the previous MXCSR on drop.
struct FlushDenormals {
    #[cfg(target_arch = "x86_64")]
    saved: u32,
}

impl FlushDenormals {
    #[allow(deprecated)]
    fn new() -> Self {
        #[cfg(target_arch = "x86_64")]
        {
            // SAFETY: reading and writing MXCSR only changes how this thread's SSE arithmetic
            // treats denormals (bits 15 FTZ and 6 DAZ); it touches no memory. Rust code does not
            // rely on denormal behaviour for soundness, and the old value is restored on drop.
            let saved = unsafe { core::arch::x86_64::_mm_getcsr() };
            unsafe { core::arch::x86_64::_mm_setcsr(saved | 0x8040) };
            Self { saved }
        }
        #[cfg(not(target_arch = "x86_64"))]
        Self {}
    }
}

impl Drop for FlushDenormals {
    #[allow(deprecated)]
    fn drop(&mut self) {
        #[cfg(target_arch = "x86_64")]
        // SAFETY: restores the MXCSR value read in `new` (see there).
        unsafe {
            core::arch::x86_64::_mm_setcsr(self.saved)
        };
    }
}

/// An Embree device (shared by the scenes built on it), with its memory monitor: the bytes
/// Embree has allocated on it (scene buffers, BVH, build scratch not yet freed).
pub struct Device(RtcDevice, Box<std::sync::atomic::AtomicIsize>);

// SAFETY: an Embree device handle may be used from any thread (the API is thread-safe for
// scene creation and queries on distinct scenes).
unsafe impl Send for Device {}
// SAFETY: see `Send`.
unsafe impl Sync for Device {}

impl Device {
    /// A device with the default configuration.
    pub fn new() -> Result<std::sync::Arc<Self>, EmbreeError> {
        Self::with_config(None)
    }

    /// A device whose builds use at most `threads` worker threads (Embree's `threads=N`
    /// configuration), so that a build can be timed against one on as many rayon threads.
    pub fn with_threads(threads: usize) -> Result<std::sync::Arc<Self>, EmbreeError> {
        Self::with_config(Some(format!("threads={}", threads.max(1))))
    }

    fn with_config(config: Option<String>) -> Result<std::sync::Arc<Self>, EmbreeError> {
        let config = config
            .map(|c| std::ffi::CString::new(c).map_err(|_| EmbreeError("config string holds a NUL".into())))
            .transpose()?;
        let ptr = config.as_ref().map_or(std::ptr::null(), |c| c.as_ptr());
        // SAFETY: `ptr` is null (default configuration) or a NUL-terminated string that lives
        // until the call returns (`config` is dropped at the end of this function).
        let device = unsafe { rtcNewDevice(ptr) };
        if device.is_null() {
            return Err(EmbreeError("rtcNewDevice failed (is libembree3 installed and the CPU supported?)".into()));
        }
        let counter = Box::new(std::sync::atomic::AtomicIsize::new(0));
        // SAFETY: `device` is valid; the counter is boxed (a stable address) and lives as long
        // as the device (both in `Self`; the monitor is removed before the device is released).
        unsafe { rtcSetDeviceMemoryMonitorFunction(device, Some(count_bytes), &*counter as *const _ as *mut c_void) };
        Ok(std::sync::Arc::new(Self(device, counter)))
    }

    /// Bytes Embree currently holds on this device, by its memory monitor callback
    /// (`rtcSetDeviceMemoryMonitorFunction`).
    pub fn memory_bytes(&self) -> isize {
        self.1.load(std::sync::atomic::Ordering::Relaxed)
    }
}

impl Drop for Device {
    fn drop(&mut self) {
        // SAFETY: the handle was created by `Device::new` and is released exactly once, after
        // every scene holding this device (they hold an `Arc`) was released; the monitor is
        // removed first so Embree never calls it with a freed counter.
        unsafe {
            rtcSetDeviceMemoryMonitorFunction(self.0, None, std::ptr::null_mut());
            rtcReleaseDevice(self.0)
        };
    }
}

/// One committed Embree scene (geometry id 0) on a [`Device`].
pub struct Scene {
    device: std::sync::Arc<Device>,
    scene: RtcScene,
    prims: usize,
}

// SAFETY: Embree devices and committed scenes may be used from any thread; `intersect` only
// reads the scene (rtcIntersect1 is thread-safe on a committed scene, per the Embree API docs).
unsafe impl Send for Scene {}
// SAFETY: see `Send`; no method mutates the scene after construction.
unsafe impl Sync for Scene {}

/// The first hit Embree reports.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EmbreeHit {
    /// Ray parameter.
    pub t: f32,
    /// Primitive (segment) index.
    pub prim: u32,
    /// Unnormalised geometric normal.
    pub ng: [f32; 3],
    /// Curve parameter.
    pub u: f32,
}

impl Scene {
    /// An empty scene and a new geometry of `kind` on `device`.
    fn start(device: &std::sync::Arc<Device>, kind: u32) -> Result<(Self, RtcGeometry), EmbreeError> {
        // SAFETY: `device.0` is a valid device handle.
        let scene = unsafe { rtcNewScene(device.0) };
        if scene.is_null() {
            return Err(EmbreeError("rtcNewScene failed".into()));
        }
        let s = Self { device: device.clone(), scene, prims: 0 };
        // SAFETY: `scene` is a valid scene handle; the enum values are from rtcore_common.h.
        unsafe {
            rtcSetSceneBuildQuality(scene, BUILD_QUALITY_HIGH);
            rtcSetSceneFlags(scene, SCENE_FLAG_ROBUST);
        }
        // SAFETY: `device.0` is valid; the type constants are from rtcore_geometry.h.
        let geom = unsafe { rtcNewGeometry(device.0, kind) };
        if geom.is_null() {
            return Err(EmbreeError("rtcNewGeometry failed".into()));
        }
        Ok((s, geom))
    }

    fn finish(mut self, geom: RtcGeometry, filled: Result<(), EmbreeError>, prims: usize) -> Result<Self, EmbreeError> {
        let _ftz = FlushDenormals::new();
        if let Err(e) = filled {
            // SAFETY: releases the geometry created in `start` (not attached).
            unsafe { rtcReleaseGeometry(geom) };
            return Err(e);
        }
        // SAFETY: all handles are valid; the geometry's buffers were filled by the caller; the
        // scene keeps its own reference to the geometry after attach, so releasing ours is fine.
        let err = unsafe {
            rtcCommitGeometry(geom);
            rtcAttachGeometry(self.scene, geom);
            rtcReleaseGeometry(geom);
            rtcCommitScene(self.scene);
            rtcGetDeviceError(self.device.0)
        };
        if err != 0 {
            return Err(EmbreeError(format!("scene build failed with RTCError {err}")));
        }
        self.prims = prims;
        Ok(self)
    }

    /// Allocate an Embree buffer of `n` items of `stride` bytes and fill it from `data`.
    ///
    /// # Safety
    /// `geom` must be a valid geometry handle; `T` must be a plain-old-data type of exactly
    /// `stride` bytes matching `format`.
    unsafe fn buffer<T: Copy>(
        geom: RtcGeometry,
        kind: u32,
        slot: u32,
        format: u32,
        data: &[T],
    ) -> Result<(), EmbreeError> {
        let stride = std::mem::size_of::<T>();
        // SAFETY: guaranteed by the caller (valid handle, matching format and stride).
        let p = unsafe { rtcSetNewGeometryBuffer(geom, kind, slot, format, stride, data.len()) } as *mut T;
        if p.is_null() {
            return Err(EmbreeError("rtcSetNewGeometryBuffer failed".into()));
        }
        // SAFETY: Embree returned a writable buffer of `data.len()` items of `stride` bytes
        // (16-byte aligned, padded); it does not overlap `data`.
        unsafe { std::ptr::copy_nonoverlapping(data.as_ptr(), p, data.len()) };
        Ok(())
    }

    /// A scene of `ROUND_LINEAR_CURVE` segments, one per link, each with flags 0 (no
    /// neighbours): start sphere + tangent cone + end sphere, i.e. the same solid as the link.
    /// Errors: no links, a non-finite value, or an Embree failure.
    pub fn round_linear(device: &std::sync::Arc<Device>, links: &[RoundCone<f32>]) -> Result<Self, EmbreeError> {
        if links.is_empty() {
            return Err(EmbreeError("no links".into()));
        }
        if links.len() > (u32::MAX / 2) as usize {
            return Err(EmbreeError("too many links".into()));
        }
        let mut verts = Vec::with_capacity(links.len() * 2);
        for l in links {
            let v = [l.a.x, l.a.y, l.a.z, l.ra, l.b.x, l.b.y, l.b.z, l.rb];
            if v.iter().any(|x| !x.is_finite()) {
                return Err(EmbreeError("non-finite link".into()));
            }
            verts.push([l.a.x, l.a.y, l.a.z, l.ra]);
            verts.push([l.b.x, l.b.y, l.b.z, l.rb]);
        }
        let index: Vec<u32> = (0..links.len() as u32).map(|k| 2 * k).collect();
        let flags = vec![0u8; links.len()];
        let (s, geom) = Self::start(device, GEOMETRY_ROUND_LINEAR_CURVE)?;
        // SAFETY: `geom` is valid; [f32; 4] is FLOAT4 (16 bytes), u32 is UINT, u8 is UCHAR.
        let filled = unsafe {
            Self::buffer(geom, BUFFER_VERTEX, 0, FORMAT_FLOAT4, &verts)
                .and_then(|_| Self::buffer(geom, BUFFER_INDEX, 0, FORMAT_UINT, &index))
                .and_then(|_| Self::buffer(geom, BUFFER_FLAGS, 0, FORMAT_UCHAR, &flags))
        };
        s.finish(geom, filled, links.len())
    }

    /// A scene of `ROUND_HERMITE_CURVE` segments (a swept **circle**, not our sphere sweep):
    /// `(p0, r0, m0, dr0, p1, r1, m1, dr1)` per segment, tangents per unit parameter.
    pub fn round_hermite(device: &std::sync::Arc<Device>, segments: &[HermiteSegment]) -> Result<Self, EmbreeError> {
        if segments.is_empty() || segments.len() > (u32::MAX / 2) as usize {
            return Err(EmbreeError("segment count out of range".into()));
        }
        let mut verts = Vec::with_capacity(segments.len() * 2);
        let mut tans = Vec::with_capacity(segments.len() * 2);
        for (p0, t0, p1, t1) in segments {
            if [p0, t0, p1, t1].iter().any(|v| v.iter().any(|x| !x.is_finite())) {
                return Err(EmbreeError("non-finite segment".into()));
            }
            verts.extend([*p0, *p1]);
            tans.extend([*t0, *t1]);
        }
        let index: Vec<u32> = (0..segments.len() as u32).map(|k| 2 * k).collect();
        let (s, geom) = Self::start(device, GEOMETRY_ROUND_HERMITE_CURVE)?;
        // SAFETY: `geom` is valid; [f32; 4] is FLOAT4, u32 is UINT.
        let filled = unsafe {
            Self::buffer(geom, BUFFER_VERTEX, 0, FORMAT_FLOAT4, &verts)
                .and_then(|_| Self::buffer(geom, BUFFER_TANGENT, 0, FORMAT_FLOAT4, &tans))
                .and_then(|_| Self::buffer(geom, BUFFER_INDEX, 0, FORMAT_UINT, &index))
        };
        s.finish(geom, filled, segments.len())
    }

    /// Number of primitives.
    pub fn len(&self) -> usize {
        self.prims
    }

    /// True when the scene has no primitives (never, for a built scene).
    pub fn is_empty(&self) -> bool {
        self.prims == 0
    }

    /// Closest hit of the ray `o + t·d`, `t ∈ [t_near, t_far]`, or `None`.
    pub fn intersect(&self, o: [f32; 3], d: [f32; 3], t_near: f32, t_far: f32) -> Option<EmbreeHit> {
        let _ftz = FlushDenormals::new();
        self.intersect_raw(o, d, t_near, t_far)
    }

    /// Closest hits of many rays `(o, d)` with `t ∈ [0, ∞)` (FTZ/DAZ set once for the batch).
    pub fn intersect_all(&self, rays: &[([f32; 3], [f32; 3])], out: &mut Vec<Option<EmbreeHit>>) {
        let _ftz = FlushDenormals::new();
        out.clear();
        out.extend(rays.iter().map(|(o, d)| self.intersect_raw(*o, *d, 0.0, f32::INFINITY)));
    }

    /// Number of hits among many rays `(o, d)`, `t ∈ [0, ∞)`: the timing loop of the reports.
    pub fn count_hits(&self, rays: &[([f32; 3], [f32; 3])]) -> usize {
        let _ftz = FlushDenormals::new();
        rays.iter().filter(|(o, d)| self.intersect_raw(*o, *d, 0.0, f32::INFINITY).is_some()).count()
    }

    /// True when the ray `o + t·d` meets any segment with `t ∈ [t_near, t_far]`
    /// (`rtcOccluded1`: the first hit found, not the closest).
    pub fn occluded(&self, o: [f32; 3], d: [f32; 3], t_near: f32, t_far: f32) -> bool {
        let _ftz = FlushDenormals::new();
        let mut ctx = RtcIntersectContext { flags: 0, filter: None, inst_id: [INVALID_ID] };
        let mut ray = RtcRay { org: o, tnear: t_near, dir: d, time: 0.0, tfar: t_far, mask: u32::MAX, id: 0, flags: 0 };
        // SAFETY: as in `intersect_raw`; `ray` has the C layout of RTCRay (layout test) and
        // lives for the call. Embree sets `tfar` to -inf when it finds a hit.
        unsafe { rtcOccluded1(self.scene, &mut ctx, &mut ray) };
        ray.tfar == f32::NEG_INFINITY
    }

    #[inline]
    fn intersect_raw(&self, o: [f32; 3], d: [f32; 3], t_near: f32, t_far: f32) -> Option<EmbreeHit> {
        let mut ctx = RtcIntersectContext { flags: 0, filter: None, inst_id: [INVALID_ID] };
        let mut rh = RtcRayHit {
            ray: RtcRay { org: o, tnear: t_near, dir: d, time: 0.0, tfar: t_far, mask: u32::MAX, id: 0, flags: 0 },
            hit: RtcHit { geom_id: INVALID_ID, prim_id: INVALID_ID, inst_id: [INVALID_ID], ..RtcHit::default() },
        };
        // SAFETY: `self.scene` is a committed scene owned by `self`; `ctx` and `rh` are
        // initialised values with the C layouts of RTCIntersectContext and RTCRayHit (checked
        // by the layout test) and live for the duration of the call.
        unsafe { rtcIntersect1(self.scene, &mut ctx, &mut rh) };
        if rh.hit.geom_id == INVALID_ID {
            return None;
        }
        Some(EmbreeHit { t: rh.ray.tfar, prim: rh.hit.prim_id, ng: rh.hit.ng, u: rh.hit.u })
    }
}

impl Drop for Scene {
    fn drop(&mut self) {
        // SAFETY: the scene handle was created by this value and is released exactly once
        // (the device outlives it: `self.device` is dropped after this).
        unsafe { rtcReleaseScene(self.scene) };
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use tubecast::{Primitive, V3};

    #[test]
    fn layouts_match_rtcore_headers() {
        assert_eq!(std::mem::size_of::<RtcRay>(), 48);
        assert_eq!(std::mem::size_of::<RtcHit>(), 32);
        assert_eq!(std::mem::size_of::<RtcRayHit>(), 80);
        assert_eq!(std::mem::align_of::<RtcRayHit>(), 16);
        assert_eq!(std::mem::size_of::<RtcIntersectContext>(), 24);
    }

    #[test]
    fn isolated_round_linear_segment_is_the_convex_hull_of_its_spheres() {
        // Hand-derived: spheres (0,0,0) r=1 and (4,0,0) r=0.5. A ray along +x from x=-10 enters
        // the start sphere at t=9 (Embree renders it because the segment has no left
        // neighbour); one along -x from x=14 enters the end sphere at t=9.5. A ray across the
        // cone is compared with our stable kernel (itself checked against the oracle by
        // tests/kernels/link/properties.rs), within f32 rounding of both.
        let l = RoundCone::new(V3::new(0.0f32, 0.0, 0.0), 1.0, V3::new(4.0, 0.0, 0.0), 0.5).unwrap();
        let dev = Device::new().unwrap();
        let s = Scene::round_linear(&dev, &[l]).unwrap();
        let h = s.intersect([-10.0, 0.0, 0.0], [1.0, 0.0, 0.0], 0.0, f32::INFINITY).expect("hits start sphere");
        assert!((h.t - 9.0).abs() < 1e-5, "{h:?}");
        let h = s.intersect([14.0, 0.0, 0.0], [-1.0, 0.0, 0.0], 0.0, f32::INFINITY).expect("hits end sphere");
        assert!((h.t - 9.5).abs() < 1e-5, "{h:?}");
        let r = tubecast::Ray::new(V3::new(2.0f32, -10.0, 0.3), V3::new(0.0, 1.0, 0.0));
        let ours = l.intersect(&r);
        let h = s.intersect([2.0, -10.0, 0.3], [0.0, 1.0, 0.0], 0.0, f32::INFINITY).expect("hits cone");
        assert!((h.t - ours.entry.t).abs() < 1e-4, "embree {h:?} vs ours {}", ours.entry.t);
        assert!(s.intersect([2.0, -10.0, 3.0], [0.0, 1.0, 0.0], 0.0, f32::INFINITY).is_none());
        assert!(Scene::round_linear(&dev, &[]).is_err());
    }

    #[test]
    fn the_memory_monitor_counts_a_scene_and_its_release() {
        // A scene of 1000 segments holds at least its own vertex buffer (2 × 16 B per segment)
        // and index buffer (4 B per segment); releasing it returns the count to where it was.
        let dev = Device::new().unwrap();
        let before = dev.memory_bytes();
        let l = RoundCone::new(V3::new(0.0f32, 0.0, 0.0), 0.1, V3::new(1.0, 0.0, 0.0), 0.1).unwrap();
        let s = Scene::round_linear(&dev, &vec![l; 1000]).unwrap();
        let held = dev.memory_bytes() - before;
        assert!(held >= 36_000, "{held} B");
        drop(s);
        assert!(dev.memory_bytes() - before < held, "{} B after release", dev.memory_bytes() - before);
    }
}
