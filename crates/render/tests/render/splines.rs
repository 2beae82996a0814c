//! Spline-tube renders checked against direct kernel calls and the cubic itself: the depth
//! buffer against f64 spline-kernel calls on the certified split of independently built
//! Hermite segments and against the cubic Hermite sweep sampled by the oracle (within the
//! certified distance), a straight polyline against its link rendering, and transparent
//! compositing without interior surfaces at joints.

use crate::common::{self, compare_depth, flat};
use tubecast::csg::{union, Tagged};
use tubecast::{HermiteSegment, Primitive, QuadTube, Ray, V3};
use tubecast_oracle::{golden_min, line_dist, sphere_crossing, Line, Vec3};
use tubecast_render::accel::{first_component, Bvh};
use tubecast_render::io::Polyline;
use tubecast_render::render::{render, Camera, ColorBy};
use tubecast_render::scene::{generate, PrimKind, Scene, SPLINE_MAX_DEPTH, SPLINE_TOLERANCE};

/// Hermite segments of one open polyline, written out here from the documented rule (not
/// the scene code): uniform Catmull–Rom central differences inside, one-sided at the ends,
/// radius derivatives limited to `|r'| ≤ 2r`.
fn catmull_rom(l: &Polyline) -> Vec<HermiteSegment<f64>> {
    let n = l.points.len() - 1;
    let p = |i: usize| V3::from(l.points[i]);
    let d = |i: usize| {
        let (a, b) = (i.saturating_sub(1), (i + 1).min(n));
        let w = (b - a) as f64;
        let dr = (l.radii[b] - l.radii[a]) / w;
        ((p(b) - p(a)) * (1.0 / w), dr.clamp(-2.0 * l.radii[i], 2.0 * l.radii[i]))
    };
    (0..n)
        .map(|j| {
            let ((m0, dr0), (m1, dr1)) = (d(j), d(j + 1));
            HermiteSegment::new(p(j), m0, l.radii[j], dr0, p(j + 1), m1, l.radii[j + 1], dr1)
        })
        .collect()
}

/// The pieces the faithful model traces, computed here from the independently built segments
/// with the kernel's certified split (tested against the cubic in `tests/splines/hermite.rs`),
/// in `f64`, and the greatest certified distance to the cubic's sweep among them.
fn pieces(segs: &[HermiteSegment<f64>]) -> (Vec<QuadTube<f64>>, f64) {
    let mut out = Vec::new();
    let mut dist: f64 = 0.0;
    for s in segs {
        let split = s.split_adaptive(SPLINE_TOLERANCE, SPLINE_MAX_DEPTH).unwrap();
        assert!(split.relative <= SPLINE_TOLERANCE, "the helix needs no more than the maximal depth");
        dist = dist.max(split.distance);
        out.extend(split.quads);
    }
    (out, dist)
}

/// First entry along `ray` (t ≥ 0) over all pieces, by the f64 spline kernel (no BVH, no
/// f32), with the normal there.
fn reference_hit(pieces: &[QuadTube<f64>], ray: &Ray<f64>) -> Option<(f64, V3<f64>)> {
    let mut best: Option<(f64, V3<f64>)> = None;
    for q in pieces {
        if let Some(tubecast::Hit { t, n, .. }) = q.intersect(ray).first_hit(0.0, f64::INFINITY) {
            if best.map_or(true, |b| t < b.0) {
                best = Some((t, n));
            }
        }
    }
    best
}

/// The cubic Hermite segment's centre and radius at `u`, from the Hermite basis written out
/// here (`h₀₀ = 2u³ − 3u² + 1`, `h₁₀ = u³ − 2u² + u`, `h₀₁ = 3u² − 2u³`, `h₁₁ = u³ − u²`).
fn hermite_at(s: &HermiteSegment<f64>, u: f64) -> (Vec3, f64) {
    let (u2, u3) = (u * u, u * u * u);
    let (h00, h10, h01, h11) = (2.0 * u3 - 3.0 * u2 + 1.0, u3 - 2.0 * u2 + u, 3.0 * u2 - 2.0 * u3, u3 - u2);
    let o = |v: V3<f64>| Vec3::from(v.to_array());
    let c = o(s.p0) * h00 + o(s.m0) * h10 + o(s.p1) * h01 + o(s.m1) * h11;
    (c, s.r0 * h00 + s.dr0 * h10 + s.r1 * h01 + s.dr1 * h11)
}

/// Samples per segment of the cubic oracle ([`cubic_hit`]).
const CUBIC_SAMPLES: usize = 1024;

/// First entry (t ≥ 0) of the ray into the **cubic** Hermite sweeps themselves, independent of
/// the kernel: per segment (culled by the sphere around its Bézier control polygon, which holds
/// the curve) the oracle's sphere crossings at `CUBIC_SAMPLES + 1` parameters, the best
/// refined by golden section over the two neighbouring spacings; the normal is the entry
/// sphere's (the sweep's envelope is tangent to it there).
fn cubic_hit(segs: &[HermiteSegment<f64>], ray: &Ray<f64>) -> Option<(f64, V3<f64>)> {
    let o = |v: V3<f64>| Vec3::from(v.to_array());
    let line = Line { o: o(ray.o), d: o(ray.d) };
    let mut best: Option<(f64, V3<f64>)> = None;
    for s in segs {
        let ctrl = [s.p0, s.p0 + s.m0 * (1.0 / 3.0), s.p1 - s.m1 * (1.0 / 3.0), s.p1];
        let rad = [s.r0, s.r0 + s.dr0 / 3.0, s.r1 - s.dr1 / 3.0, s.r1];
        let mid = (ctrl[0] + ctrl[3]) * 0.5;
        let reach =
            ctrl.iter().map(|c| (*c - mid).length()).fold(0.0, f64::max) + rad.iter().fold(0.0f64, |a, b| a.max(*b));
        if line_dist(&line, o(mid)) > reach {
            continue;
        }
        let entry = |u: f64| {
            let (c, r) = hermite_at(s, u.clamp(0.0, 1.0));
            sphere_crossing(&line, c, r).map_or(f64::INFINITY, |x| if x.0 >= 0.0 { x.0 } else { f64::INFINITY })
        };
        let n = CUBIC_SAMPLES;
        let (k, v) =
            (0..=n)
                .map(|k| (k, entry(k as f64 / n as f64)))
                .fold((0, f64::INFINITY), |a, b| if b.1 < a.1 { b } else { a });
        if !v.is_finite() {
            continue;
        }
        let (lo, hi) = ((k as f64 - 1.0) / n as f64, (k as f64 + 1.0) / n as f64);
        let (u, t) = match golden_min(entry, lo.max(0.0), hi.min(1.0)) {
            (u, t) if t < v => (u, t),
            _ => (k as f64 / n as f64, v),
        };
        if best.map_or(true, |b| t < b.0) {
            let (c, _) = hermite_at(s, u.clamp(0.0, 1.0));
            let nrm = (line.at(t) - c).normalize_or_zero();
            best = Some((t, V3::new(nrm.x, nrm.y, nrm.z)));
        }
    }
    best
}

/// Tolerance on the depth (ray parameter, |d| ≥ 1 for camera rays) of a non-grazing hit of
/// an `f32` spline primitive, against the exact surface.
///
/// * Storing the controls in `f32` relative to the sub-segment midpoint and moving the ray
///   there: offsets ≤ `s` are rounded by ≤ `ε·s` (ε = 2⁻²³, generous for round-to-nearest),
///   moving the surface by a few `ε·s`.
/// * The `f32` kernel (bound of `tests/splines/kernel.rs`): `g(t*)` carries an absolute error
///   ≤ 64ε·s², `h` ≤ 8ε·s. At an entry with `|n·d̂| ≥ c`, `√g = r(t*)·|n·d̂| ≥ r_min·c` (the
///   half chord of the entry sphere), so `√g` errs by ≤ 64ε·s²/(2·r_min·c).
///
/// Sum: `64ε·s²/(2·r_min·c) + 8ε·s + 4ε·s` (the last term for the rounding of the inputs).
fn depth_tol(s: f64, r_min: f64, c: f64) -> f64 {
    let eps = f32::EPSILON as f64;
    64.0 * eps * s * s / (2.0 * r_min * c) + 12.0 * eps * s
}

/// The depth tolerance against the **cubic** (the oracle [`cubic_hit`]) on top of `tol`
/// against the traced pieces: the pieces' sweep lies between the cubic's sweeps with radii
/// `r ∓ D` (`D` the certified distance, [`HermiteSegment::split_adaptive`]), and the sweep
/// with `r ± D` is the cubic's offset by `D`, whose entry a non-grazing ray (`|n·d̂| ≥ c`,
/// `|d| ≥ 1`) reaches within `D/c` of the cubic's to first order; the second order is
/// `≲ D/(ρ c²)` of it (ρ ≥ r_min the surface's curvature radius: ≤ 0.1 relative for
/// `D ≤ 1e-3`, `ρ ≥ 0.25`, `c = 0.1`), so a factor 2 covers it. The oracle's own error is the
/// rounding of its f64 sphere crossings, refined by golden section to the value's rounding.
fn cubic_tol(tol: f64, dist: f64, c: f64) -> f64 {
    tol + 2.0 * dist / c
}

#[test]
fn spline_depth_buffer_equals_direct_f64_spline_kernel_calls() {
    let lines = generate::helix(24);
    let scene = Scene::from_polylines(&lines, 1.0, "helix").unwrap();
    let prims = scene.spline_primitives().unwrap();
    let segs: Vec<_> = lines.iter().flat_map(catmull_rom).collect();
    let (quads, dist) = pieces(&segs);
    // Every helix segment is curved (2 strands × 24 segments), each split into the certified
    // split's pieces, more than Russig's two (the pair is off the cubic by ~1e-2 R here).
    assert_eq!(prims.iter().filter(|p| p.kind() == PrimKind::Spline).count(), quads.len());
    assert!(quads.len() > 96, "{}", quads.len());
    let st = scene.stats_of(&prims);
    assert_eq!(st.splines, 48);
    let bvh = Bvh::build(prims);
    let cam = Camera::fit(st.bounds.0, st.bounds.1, 40.0, 32, 32).unwrap();
    let img = render(&scene, &bvh, &cam, &flat(ColorBy::Direction, 1.0)).unwrap();
    // Piece size: a helix segment spans 3 turns·2π·4/24 ≈ 3.14 of arc, so a piece (at most a
    // half) is ≤ 1.6 long and lies within 0.8 of its midpoint; plus the radius ≤ 0.6: s = 1.4.
    // Radii ≥ 0.25; non-grazing means |n·d̂| ≥ 0.1.
    let tol = depth_tol(1.4, 0.25, 0.1);
    let depth = compare_depth(&img, &cam, 0.1, tol, |_, _, r| reference_hit(&quads, r));
    depth.assert_covers("helix splines", tol, 100, 4);
    // Against the cubic sweep itself, by the oracle: within the certified distance.
    assert!(dist <= SPLINE_TOLERANCE * 0.6, "certified distance {dist:e}");
    let tol_c = cubic_tol(tol, dist, 0.1);
    let cubic = compare_depth(&img, &cam, 0.1, tol_c, |_, _, r| cubic_hit(&segs, r));
    cubic.assert_covers("helix splines vs the cubic", tol_c, 100, 4);
}

#[test]
fn bifurcation_splits_chains_and_matches_per_branch_splines() {
    use tubecast_render::io::swc::SwcNode;
    // A trunk 1–4 (uneven spacing), branches 5–7 and 8–10 from node 4.
    let pts: [[f64; 3]; 10] = [
        [0.0, -6.0, 0.0],
        [0.3, -4.0, 0.2],
        [0.2, -1.5, -0.3],
        [0.0, 0.0, 0.0],
        [1.5, 1.2, 0.4],
        [3.5, 2.0, 0.1],
        [5.0, 3.8, -0.5],
        [-1.2, 1.6, -0.2],
        [-2.0, 3.5, 0.6],
        [-4.0, 4.5, 0.0],
    ];
    let radii = [0.9, 0.8, 0.75, 0.7, 0.6, 0.5, 0.45, 0.55, 0.5, 0.35];
    let parents = [-1, 1, 2, 3, 4, 5, 6, 4, 8, 9];
    let rows: Vec<SwcNode> = (0..10)
        .map(|i| SwcNode { id: i as i64 + 1, kind: 3, pos: pts[i], radius: radii[i], parent: parents[i] })
        .collect();
    let scene = Scene::from_swc(&rows, "y").unwrap();
    let prims = scene.spline_primitives().unwrap();
    let st = scene.stats_of(&prims);
    assert_eq!(st.splines, 9, "every link is a curved spline segment");
    // The three chains as polylines (each branch starts at the bifurcation node 4).
    let chain = |ids: &[usize]| Polyline {
        points: ids.iter().map(|&i| pts[i - 1]).collect(),
        radii: ids.iter().map(|&i| radii[i - 1]).collect(),
    };
    let segs: Vec<_> =
        [chain(&[1, 2, 3, 4]), chain(&[4, 5, 6, 7]), chain(&[4, 8, 9, 10])].iter().flat_map(catmull_rom).collect();
    let (quads, dist) = pieces(&segs);
    assert_eq!(prims.iter().filter(|p| p.kind() == PrimKind::Spline).count(), quads.len());
    let bvh = Bvh::build(prims);
    let cam = Camera::fit(st.bounds.0, st.bounds.1, 40.0, 32, 32).unwrap();
    let img = render(&scene, &bvh, &cam, &flat(ColorBy::Type, 1.0)).unwrap();
    // Pieces (at most half segments) ≤ 1.3 from their midpoints plus radius ≤ 0.9: s = 2.2;
    // radii ≥ 0.35.
    let tol = depth_tol(2.2, 0.35, 0.1);
    let depth = compare_depth(&img, &cam, 0.1, tol, |_, _, r| reference_hit(&quads, r));
    depth.assert_covers("bifurcation", tol, 60, 4);
    assert!(dist <= SPLINE_TOLERANCE * 0.9, "certified distance {dist:e}");
    let tol_c = cubic_tol(tol, dist, 0.1);
    let cubic = compare_depth(&img, &cam, 0.1, tol_c, |_, _, r| cubic_hit(&segs, r));
    cubic.assert_covers("bifurcation vs the cubic", tol_c, 60, 4);
}

#[test]
fn straight_polyline_with_splines_matches_links() {
    // Uneven spacing along a line, radius affine in the position: the Catmull–Rom spline's
    // centre moves along the line at an uneven speed but covers exactly [s₀, s_N], and its
    // radius is the same affine function of position (derivatives are linear in the data),
    // so the sweep is exactly the links' surface (one long round cone).
    let u = V3::new(1.0, 2.0, 2.0) * (1.0 / 3.0);
    let c = V3::new(3.0, -1.0, 2.0);
    let ss = [0.0, 1.0, 2.5, 3.5, 5.0, 5.6, 7.0];
    let line = Polyline {
        points: ss.iter().map(|&s| (c + u * s).to_array()).collect(),
        radii: ss.iter().map(|&s| 0.3 + 0.05 * s).collect(),
    };
    let scene = Scene::from_polylines(std::slice::from_ref(&line), 1.0, "straight").unwrap();
    let links = scene.primitives();
    // The default rule keeps them links (the sweep is the same); forcing splines must not.
    let kept = scene.spline_primitives().unwrap();
    assert_eq!(kept, links, "straight segments stay links");
    let forced = scene.spline_primitives_with(false).unwrap();
    // Six segments, each split into the certified split's pieces (at least one each).
    let (quads, _) = pieces(&catmull_rom(&line));
    assert!(quads.len() >= 6);
    assert_eq!(forced.iter().filter(|p| p.kind() == PrimKind::Spline).count(), quads.len());

    let side = V3::new(2.0, -1.0, 0.0).normalize_or_zero();
    let cam = Camera::look_at(c + u * 3.5 + side * 4.5, c + u * 3.5, V3::new(0.0, 0.0, 1.0), 50.0, 48, 32).unwrap();
    let opts = flat(ColorBy::Direction, 1.0);
    let link_img = render(&scene, &Bvh::build(links), &cam, &opts).unwrap();
    let spline_img = render(&scene, &Bvh::build(forced), &cam, &opts).unwrap();
    // Reference normals (to skip grazing pixels): the f64 link kernels.
    let link_ref = |r: &Ray<f64>| {
        (0..scene.links.len())
            .filter_map(|k| scene.link(k).intersect(r).first_hit(0.0, f64::INFINITY))
            .min_by(|a, b| a.t.total_cmp(&b.t))
            .map(|h| (h.t, h.n))
    };
    // Both renders are within their rounding of the exact (same) surface: the link path by
    // a few ε·s (ε = 2⁻²³, s ≤ 1.4: half a link ≤ 0.75 plus radius ≤ 0.65), head-on or not,
    // ≤ 1/c times that; the spline path by `depth_tol` with r_min = 0.3, c = 0.1.
    let tol = depth_tol(1.4, 0.3, 0.1) + 8.0 * f32::EPSILON as f64 * 1.4 / 0.1;
    let w = cam.width;
    let common::DepthCheck { hits, grazing, worst } = compare_depth(&spline_img, &cam, 0.1, tol, |x, y, r| {
        link_ref(r).map(|(_, n)| (link_img.depth[(y * w + x) as usize], n))
    });
    eprintln!("straight: {hits} hits, {grazing} grazing skipped, worst |Δt| spline vs link {worst:e} (tol {tol:e})");
    assert!(hits > 150, "the line must cover part of the image ({hits})");
    assert!(grazing * 4 < hits, "too many grazing pixels ({grazing} of {hits})");
}

/// A "J": an evenly spaced straight run of constant radius (kept as links by the straight
/// rule) continuing into a half circle of varying radius (splines), in the plane z = 0.
fn j_shape() -> Polyline {
    let mut points: Vec<[f64; 3]> = (0..7).map(|k| [k as f64 - 6.0, 0.0, 0.0]).collect();
    let mut radii = vec![0.5; 7];
    for k in 1..=10 {
        let a = k as f64 * std::f64::consts::PI / 10.0;
        points.push([4.0 * a.sin(), 4.0 - 4.0 * a.cos(), 0.0]);
        radii.push(0.5 + 0.2 * (0.7 * k as f64).sin());
    }
    Polyline { points, radii }
}

#[test]
fn transparent_splines_show_no_interior_surfaces_at_joints() {
    let scene = Scene::from_polylines(&[j_shape()], 1.0, "j").unwrap();
    let prims = scene.spline_primitives().unwrap();
    let st = scene.stats_of(&prims);
    // Segments 0–4 have chord derivatives at both ends (evenly spaced collinear neighbours):
    // links. Segment 5 ends at the first arc node's neighbour: a spline, like the arc's 10.
    assert_eq!((st.cylinders, st.splines), (5, 11));
    let bvh = Bvh::build(prims);

    // Vertical lines through the plane of the tube meet it in one interval (every ball of the
    // sweep is centred in the plane, so each meets the line in an interval centred at z = 0),
    // so the union has exactly 0 or 2 boundaries. Sub-segment and segment joints inside the
    // interval must add none.
    let (lo, hi) = st.bounds;
    let (mut crossing_joints, mut hit_rays) = (0, 0);
    for i in 0..90 {
        for j in 0..60 {
            let x = lo[0] + (hi[0] - lo[0]) * (i as f64 + 0.5) / 90.0;
            let y = lo[1] + (hi[1] - lo[1]) * (j as f64 + 0.5) / 60.0;
            let ray = Ray::new(V3::new(x, y, 10.0), V3::new(0.0, 0.0, -1.0));
            let mut ivs: Vec<Tagged<f64>> = Vec::new();
            bvh.line_intervals(&ray, &mut ivs);
            crossing_joints += (ivs.len() >= 2) as usize;
            let mut b = Vec::new();
            union(&mut ivs, 0.0, f64::INFINITY, |x| b.push(x));
            assert!(b.is_empty() || b.len() == 2, "ray at ({x}, {y}): {} boundaries: {b:?}", b.len());
            if b.len() == 2 {
                hit_rays += 1;
                assert!(b[0].entering && !b[1].entering);
                // Symmetric about the plane: entry at 10 − z_top, exit at 10 + z_top (each
                // end within the f32 kernel's error, ≪ 1e-3 here even for grazing lines).
                assert!((b[0].t + b[1].t - 20.0).abs() < 1e-3, "{b:?}");
                let fc = first_component(&bvh, &ray).unwrap();
                assert_eq!((fc.0.t, fc.1.t), (b[0].t, b[1].t));
            }
        }
    }
    eprintln!("joints: {hit_rays} rays through the tube, {crossing_joints} through ≥ 2 primitives");
    assert!(hit_rays > 600, "{hit_rays}");
    assert!(crossing_joints * 2 > hit_rays, "most rays must cross overlapping primitives ({crossing_joints})");

    // The same through the renderer: seen from above with a flat colour, a pixel is the
    // background or exactly two layers of opacity α over it.
    let cen = V3::new(0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.0);
    let cam = Camera::look_at(cen + V3::new(0.0, 0.0, 40.0), cen, V3::new(0.0, 1.0, 0.0), 15.0, 64, 48).unwrap();
    let (alpha, col) = (0.5f64, [0.2f64, 0.4, 0.8]);
    let img = render(&scene, &bvh, &cam, &flat(ColorBy::Solid([0.2, 0.4, 0.8]), alpha)).unwrap();
    let two: [f64; 3] = std::array::from_fn(|k| alpha * col[k] * (2.0 - alpha) + (1.0 - alpha).powi(2));
    let (mut n_bg, mut n_two) = (0, 0);
    for y in 0..48 {
        for x in 0..64 {
            let p = img.at(x, y);
            // f32 accumulation of ≤ 2 terms in [0, 1] plus the background: ≤ 4 ulps of 1.
            let is = |e: [f64; 3]| (0..3).all(|k| (p[k] as f64 - e[k]).abs() < 1e-6);
            if is([1.0; 3]) {
                n_bg += 1;
            } else {
                assert!(is(two), "pixel ({x},{y}) = {p:?}: not background {:?} nor two layers {two:?}", [1.0; 3]);
                n_two += 1;
            }
        }
    }
    assert!(n_two > 200 && n_bg > 200, "{n_two} tube pixels, {n_bg} background");
}

#[test]
fn far_from_origin_spline_render_keeps_its_depth() {
    // The same helix and camera at the origin and shifted by ~10⁶: spline primitives are
    // stored in f32 relative to their midpoints, so both renders are within `depth_tol` of
    // the same surface. (World f32 at 10⁶ has a spacing of 1/16, a quarter of the radius.)
    let shift = V3::new(1.0e6 + 0.3, -1.0e6 + 0.7, 1.0e6 + 0.1);
    let render_at = |off: V3<f64>| {
        let lines: Vec<Polyline> = generate::helix(24)
            .into_iter()
            .map(|l| Polyline {
                points: l.points.iter().map(|p| (V3::from(*p) + off).to_array()).collect(),
                radii: l.radii,
            })
            .collect();
        let scene = Scene::from_polylines(&lines, 1.0, "helix").unwrap();
        let bvh = Bvh::build(scene.spline_primitives().unwrap());
        let cam = Camera::look_at(off + V3::new(8.0, 12.0, 30.0), off, V3::new(0.0, 1.0, 0.0), 40.0, 24, 24).unwrap();
        (render(&scene, &bvh, &cam, &flat(ColorBy::Direction, 1.0)).unwrap(), cam)
    };
    let (near, cam) = render_at(V3::zero());
    let (far, _) = render_at(shift);
    // Each within depth_tol(1.4, 0.25, c) of the surface on non-grazing pixels (s, radii as
    // in the helix depth test); the shifted inputs and camera rays carry f64 rounding of
    // ~10⁶·2⁻⁵³ ≈ 1e-10, negligible. Grazing pixels (|n·d̂| < 0.1 by the f64 kernels) skipped.
    let segs: Vec<_> = generate::helix(24).iter().flat_map(catmull_rom).collect();
    let (quads, _) = pieces(&segs);
    let tol = 2.0 * depth_tol(1.4, 0.25, 0.1) + 1e-9;
    let w = cam.width;
    let common::DepthCheck { hits, worst, .. } = compare_depth(&far, &cam, 0.1, tol, |x, y, r| {
        reference_hit(&quads, r).map(|(_, n)| (near.depth[(y * w + x) as usize], n))
    });
    eprintln!("far: {hits} hits, worst |Δt| far vs near {worst:e} (tol {tol:e})");
    assert!(hits > 60, "{hits}");
}
