//! # tubecast-render
//!
//! Everything between files and pixels, built on the [`tubecast`] kernels: readers and
//! writers for SWC, TrackVis `.trk`, MRtrix `.tck`, OBJ polylines and `.npy` ([`io`]); scenes
//! of links and spline tubes with per-segment primitive choice ([`scene`]); a BVH with
//! closest-hit, any-hit and all-intervals queries ([`accel`]); and a CPU renderer with opaque
//! and CSG-correct transparent compositing ([`render`]).
//!
//! A scene, its primitives in a BVH, a camera and a picture:
//!
//! ```
//! use tubecast_render::accel::Bvh;
//! use tubecast_render::render::{render, Options, View};
//! use tubecast_render::scene::{generate, Model, Scene};
//!
//! let scene = Scene::from_polylines(&generate::helix(40), 0.5, "helix")?;
//! let prims = scene.model_primitives(Model::Splines)?;
//! let bounds = scene.stats_of(&prims).bounds;
//! let bvh = Bvh::build(prims);
//! let cam = View { width: 64, height: 48, ..View::default() }.camera(bounds)?;
//! let img = render(&scene, &bvh, &cam, &Options { ao: 4, shadows: true, ..Options::default() })?;
//! assert!(img.depth.iter().any(|d| d.is_finite()));
//! // img.write_png(Path::new("helix.png"))?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![deny(missing_docs)]

pub mod accel;
pub mod estimate;
pub mod io;
pub mod mesh;
pub mod quantized;
pub mod render;
pub mod scene;
