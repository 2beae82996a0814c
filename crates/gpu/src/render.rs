//! `render --device gpu`: the CPU renderer's own shading ([`tubecast_render::render::render`]),
//! with every ray it casts (primary, shadow, ambient-occlusion, union boundaries) answered on
//! the GPU.
//!
//! The renderer asks one ray at a time through [`Tracer`]; a GPU answers batches. So the frame
//! is rendered in rounds: each round runs the renderer against the answers known so far,
//! records the rays it asked that have no answer yet (answering them "miss", or "no
//! intervals", for the moment), and sends them to the GPU as one batch. Round 1 gathers the
//! primary rays, round 2 the shadow and AO rays from the surface points they found, round 3
//! finds every ray answered and is the image. A transparent render asks each primary ray's
//! line intervals in round 1 and is done in round 2; a faded thin tube asks its ray's in
//! round 2 and the shadow and AO rays of the layers behind it in round 3. The renderer is
//! deterministic (AO seeds by pixel), so each round asks the same rays as the last plus those
//! that its new answers open.

use crate::device::GpuError;
use crate::scene::{GpuScene, Walk};
use std::collections::HashMap;
use std::sync::Mutex;
use tubecast::csg::Tagged;
use tubecast::{Hit, Ray};
use tubecast_render::accel::{closest_table, crossings_table, Tracer, WideBvh, HIT_COLUMNS};
use tubecast_render::render::{render, Camera, Image, Options};
use tubecast_render::scene::{Prim, Scene};

/// Rounds before giving up: primary; secondary (shadow and AO rays, a faded thin tube's union
/// boundaries); the shadow and AO rays of the layers behind a faded tube; final; one spare.
const ROUNDS: usize = 5;

/// A ray as a hash key: its bits.
type Key = [u64; 8];

fn key(r: &Ray<f64>) -> Key {
    [r.o.x, r.o.y, r.o.z, r.d.x, r.d.y, r.d.z, r.t_min, r.t_max].map(f64::to_bits)
}

/// A [`Tracer`] answering from the GPU's answers, recording the rays it cannot answer yet.
struct Answers<'a> {
    bvh: &'a WideBvh,
    closest: HashMap<Key, Option<Hit<f64>>>,
    any: HashMap<Key, bool>,
    lines: HashMap<Key, Vec<Tagged<f64>>>,
    ask_closest: Mutex<Vec<Ray<f64>>>,
    ask_any: Mutex<Vec<Ray<f64>>>,
    ask_lines: Mutex<Vec<Ray<f64>>>,
}

impl<'a> Answers<'a> {
    fn new(bvh: &'a WideBvh) -> Self {
        Self {
            bvh,
            closest: HashMap::new(),
            any: HashMap::new(),
            lines: HashMap::new(),
            ask_closest: Mutex::new(Vec::new()),
            ask_any: Mutex::new(Vec::new()),
            ask_lines: Mutex::new(Vec::new()),
        }
    }
}

impl Answers<'_> {
    /// `table` of `rays` from the answers so far; an error where it asked a ray they lack (a
    /// table is answered in one batch, so that would be a bug, not a round to run).
    fn table(&self, rays: &[Ray<f64>], table: Table) -> Result<Vec<[f64; HIT_COLUMNS]>, GpuError> {
        let rows = table(self, rays);
        let asked = [&self.ask_closest, &self.ask_any, &self.ask_lines]
            .iter()
            .any(|log| !log.lock().expect("ray log").is_empty());
        if asked {
            return Err(GpuError::Dispatch("a ray of the table went unanswered".into()));
        }
        Ok(rows)
    }
}

/// A table of the `tubecast_render::accel` kind.
type Table = fn(&dyn Tracer, &[Ray<f64>]) -> Vec<[f64; HIT_COLUMNS]>;

impl Tracer for Answers<'_> {
    fn prim(&self, id: u32) -> Prim {
        self.bvh.prim(id)
    }
    fn prim_count(&self) -> usize {
        self.bvh.prim_count()
    }
    fn closest_hit(&self, ray: &Ray<f64>) -> Option<Hit<f64>> {
        match self.closest.get(&key(ray)) {
            Some(h) => *h,
            None => {
                self.ask_closest.lock().expect("ray log").push(*ray);
                None
            }
        }
    }
    fn any_hit(&self, ray: &Ray<f64>) -> bool {
        match self.any.get(&key(ray)) {
            Some(h) => *h,
            None => {
                self.ask_any.lock().expect("ray log").push(*ray);
                false
            }
        }
    }
    /// The intervals reaching `[t_min, t_max]` only ([`GpuScene::line_intervals`]): enough for
    /// the union's boundaries within the range (all that the renderer and the `all` table
    /// take), not for a component's entry before `t_min`.
    fn line_intervals(&self, ray: &Ray<f64>, out: &mut Vec<Tagged<f64>>) {
        match self.lines.get(&key(ray)) {
            Some(ivs) => out.extend_from_slice(ivs),
            None => self.ask_lines.lock().expect("ray log").push(*ray),
        }
    }
    fn memory_bytes(&self) -> usize {
        self.bvh.memory_bytes()
    }
}

/// Render `scene` through `cam` as [`render`] does, every ray answered by `gpu_scene` (uploaded
/// from `bvh`): closest hits, shadow and AO rays, and the union boundaries of transparent
/// renders (`opacity < 1`) and faded thin tubes. Errors: the GPU's; render-option errors are
/// returned as [`GpuError::Unsupported`] with their message.
pub fn render_gpu(
    gpu_scene: &GpuScene<'_>,
    scene: &Scene,
    bvh: &WideBvh,
    cam: &Camera,
    opts: &Options,
) -> Result<Image, GpuError> {
    let mut ans = Answers::new(bvh);
    let quiet = Options { progress: false, ..*opts };
    for _ in 0..ROUNDS {
        let img = render(scene, &ans, cam, &quiet).map_err(|e| GpuError::Unsupported(e.to_string()))?;
        let mut closest = std::mem::take(&mut *ans.ask_closest.lock().expect("ray log"));
        let mut any = std::mem::take(&mut *ans.ask_any.lock().expect("ray log"));
        let mut lines = std::mem::take(&mut *ans.ask_lines.lock().expect("ray log"));
        if closest.is_empty() && any.is_empty() && lines.is_empty() {
            return Ok(img);
        }
        // Rows run in parallel: the same ray may be logged twice, in any order.
        for rays in [&mut closest, &mut any, &mut lines] {
            rays.sort_unstable_by_key(key);
            rays.dedup_by_key(|r| key(r));
        }
        let hits = gpu_scene.closest_hits(&closest, Walk::Tree)?;
        ans.closest.extend(closest.iter().map(key).zip(hits));
        let hits = gpu_scene.any_hits(&any)?;
        ans.any.extend(any.iter().map(key).zip(hits));
        let ivs = gpu_scene.line_intervals(&lines)?;
        ans.lines.extend(lines.iter().map(key).zip(ivs));
    }
    Err(GpuError::Dispatch(format!("rays still unanswered after {ROUNDS} rounds")))
}

/// The `intersect --query hit` table of `rays` ([`closest_table`]) with every closest hit found
/// on the GPU by `gpu_scene` (uploaded from `bvh`); the exit column is the CPU kernel's exit of
/// the primitive hit, as on the CPU path.
pub fn closest_table_gpu(
    gpu_scene: &GpuScene<'_>,
    bvh: &WideBvh,
    rays: &[Ray<f64>],
) -> Result<Vec<[f64; HIT_COLUMNS]>, GpuError> {
    let mut ans = Answers::new(bvh);
    let hits = gpu_scene.closest_hits(rays, Walk::Tree)?;
    ans.closest.extend(rays.iter().map(key).zip(hits));
    ans.table(rays, closest_table)
}

/// The `intersect --query piece` table of `rays` ([`tubecast_render::accel::hit_table`]'s rows:
/// entry `t`, exit `t`, entry normal, entry link, entry `u`, 1; a miss is
/// [`MISS_ROW`](tubecast_render::accel::MISS_ROW)) with the first union components found on
/// the GPU ([`GpuScene::first_pieces`]).
pub fn piece_table_gpu(
    gpu_scene: &GpuScene<'_>,
    bvh: &WideBvh,
    rays: &[Ray<f64>],
) -> Result<Vec<[f64; HIT_COLUMNS]>, GpuError> {
    Ok(gpu_scene
        .first_pieces(rays)?
        .iter()
        .map(|p| match p {
            Some((e, x)) => [e.t, x.t, e.n.x, e.n.y, e.n.z, f64::from(bvh.prim(e.id).link), e.u, 1.0],
            None => tubecast_render::accel::MISS_ROW,
        })
        .collect())
}

/// The `intersect --query all` table of `rays` ([`crossings_table`]'s rows: every exterior
/// boundary of the union within each ray's `[t_min, t_max]`, in ray order and increasing `t`)
/// with the line intervals found on the GPU ([`GpuScene::line_intervals`]) and the union taken
/// on the CPU by the same [`crossings_table`].
pub fn crossings_table_gpu(
    gpu_scene: &GpuScene<'_>,
    bvh: &WideBvh,
    rays: &[Ray<f64>],
) -> Result<Vec<[f64; HIT_COLUMNS]>, GpuError> {
    let mut ans = Answers::new(bvh);
    let lines = gpu_scene.line_intervals(rays)?;
    ans.lines.extend(rays.iter().map(key).zip(lines));
    ans.table(rays, crossings_table)
}
