//! The spline model of a scene: chains, finite-difference derivatives (checked against hand
//! computations), the radius-derivative limit, the straight-run rule, counts and errors.

use tubecast::HermiteSegment;
use tubecast::QuadTube;
use tubecast::{GeometryError, V3};
use tubecast_render::io::swc::SwcNode;
use tubecast_render::io::Polyline;
use tubecast_render::scene::{Chain, Node, Prim, PrimKind, Radii, Scene, SPLINE_MAX_DEPTH, SPLINE_TOLERANCE};

/// Pieces of the certified split over the scene's spline segments (all curved here).
fn pieces(s: &Scene) -> usize {
    let split = |g: &tubecast_render::scene::SplineSegment| g.seg.split_adaptive(SPLINE_TOLERANCE, SPLINE_MAX_DEPTH);
    s.spline_segments().iter().map(|g| split(g).unwrap().quads.len()).sum()
}

fn line(points: &[[f64; 3]], radii: &[f64]) -> Polyline {
    Polyline { points: points.to_vec(), radii: radii.to_vec() }
}

#[test]
fn chains_split_at_bifurcations_and_loops_are_closed() {
    // Trunk 1–2–3–4, branches 4–5–6–7 and 4–8–9–10, and an isolated node 11.
    let parents = [-1, 1, 2, 3, 4, 5, 6, 4, 8, 9, -1];
    let rows: Vec<SwcNode> = (0..11)
        .map(|i| SwcNode {
            id: i + 1,
            kind: 3,
            pos: [i as f64, (i * i) as f64 * 0.1, 0.0],
            radius: 0.3,
            parent: parents[i as usize],
        })
        .collect();
    let s = Scene::from_swc(&rows, "y").unwrap();
    let c = s.chains();
    let open = |nodes: Vec<u32>, links: Vec<u32>| Chain { nodes, links, closed: false };
    // Links in SWC order: 0:[0,1] 1:[1,2] 2:[2,3] 3:[3,4] 4:[4,5] 5:[5,6] 6:[3,7] 7:[7,8]
    // 8:[8,9], then the isolated node's zero-length link 9:[10,10] (in no chain).
    assert_eq!(
        c,
        vec![
            open(vec![0, 1, 2, 3], vec![0, 1, 2]),
            open(vec![3, 4, 5, 6], vec![3, 4, 5]),
            open(vec![3, 7, 8, 9], vec![6, 7, 8])
        ]
    );
    // The isolated node stays a sphere primitive; the 9 chain links are curved splines.
    let st = s.stats_of(&s.spline_primitives().unwrap());
    assert_eq!((st.splines, st.spheres, st.cylinders, st.cones), (9, 1, 0, 0));

    // A closed loop (a square): one periodic chain.
    let node = |x: f64, y: f64| Node { pos: [x, y, 0.0] };
    let sq = Scene {
        values: Vec::new(),
        coverage: Vec::new(),
        nodes: vec![node(0.0, 0.0), node(1.0, 0.0), node(1.0, 1.0), node(0.0, 1.0)],
        links: vec![[0, 1], [1, 2], [2, 3], [3, 0]].into(),
        radii: Radii::uniform(0.2),
        kinds: Vec::new(),
    };
    assert_eq!(sq.chains(), vec![Chain { nodes: vec![0, 1, 2, 3, 0], links: vec![0, 1, 2, 3], closed: true }]);
    // Central differences wrap around: at node 0, (p₁ − p₃)/2 = (½, −½, 0), on both sides.
    let segs = sq.spline_segments();
    assert_eq!(segs[0].seg.m0, V3::new(0.5, -0.5, 0.0));
    assert_eq!(segs[3].seg.m1, V3::new(0.5, -0.5, 0.0));
    assert_eq!(segs[1].seg.m0, V3::new(0.5, 0.5, 0.0), "(p₂ − p₀)/2 at node 1");
}

#[test]
fn derivatives_are_catmull_rom_with_one_sided_ends() {
    let s = Scene::from_polylines(
        &[line(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [3.0, 1.0, 0.0], [4.0, 4.0, 0.0]], &[1.0, 0.8, 0.7, 0.2])],
        1.0,
        "p",
    )
    .unwrap();
    let g = s.spline_segments();
    assert_eq!(g.len(), 3);
    let close = |a: V3<f64>, b: [f64; 3]| (a - V3::from(b)).max_abs() < 1e-15;
    // Hand-computed: ends one-sided (p₁ − p₀, p₃ − p₂), interior central (pᵢ₊₁ − pᵢ₋₁)/2.
    assert!(close(g[0].seg.m0, [1.0, 0.0, 0.0]));
    assert!(close(g[0].seg.m1, [1.5, 0.5, 0.0]));
    assert!(close(g[1].seg.m1, [1.5, 2.0, 0.0]));
    assert!(close(g[2].seg.m1, [1.0, 3.0, 0.0]));
    // Radius derivatives: −0.2, (0.7 − 1)/2 = −0.15, (0.2 − 0.8)/2 = −0.3, and the end's
    // one-sided −0.5 limited to −2·0.2 = −0.4.
    let d = [g[0].seg.dr0, g[0].seg.dr1, g[1].seg.dr1, g[2].seg.dr1];
    for (got, want) in d.iter().zip([-0.2, -0.15, -0.3, -0.4]) {
        assert!((got - want).abs() < 1e-15, "{d:?}");
    }
    // C¹: both segments at a node share position, tangent, radius and radius derivative.
    for w in g.windows(2) {
        let (a, b) = (w[0].seg, w[1].seg);
        assert_eq!((a.p1, a.m1, a.r1, a.dr1), (b.p0, b.m0, b.r0, b.dr0));
    }
}

#[test]
fn radius_derivative_limit_keeps_every_sub_segment_valid() {
    // A bent chain tapering to a point: radii 1, 0.05, 0.
    let pts = [[0.0, 0.0, 0.0], [1.0, 0.5, 0.0], [2.0, 0.0, 0.0]];
    let s = Scene::from_polylines(&[line(&pts, &[1.0, 0.05, 0.0])], 1.0, "tip").unwrap();
    // Without the limit, node 1 would have r' = (0 − 1)/2 = −0.5 and the tip r' = −0.05:
    // the second segment's first control radius 0.05 − 0.5/3 < 0 makes the split invalid.
    let p = |i: usize| V3::from(pts[i]);
    let raw = HermiteSegment::new(p(1), (p(2) - p(0)) * 0.5, 0.05, -0.5, p(2), p(2) - p(1), 0.0, -0.05);
    assert_eq!(raw.split().unwrap_err(), GeometryError::NegativeRadius);
    // With it (|r'| ≤ 2r: −0.1 and 0), every sub-segment is valid and keeps a positive radius.
    let g = s.spline_segments();
    assert_eq!((g[1].seg.dr0, g[1].seg.dr1), (-0.1, 0.0));
    let prims = s.spline_primitives().unwrap();
    // Both links are curved: each split into its certified split's pieces (the segments' own
    // derivatives are checked just above).
    assert_eq!(prims.len(), pieces(&s));
    assert!(prims.len() >= 4, "the taper needs more than one piece per segment ({})", prims.len());
    for q in prims.iter().map(|p| p.quad().expect("both links are curved: spline pieces only")) {
        assert!(q.min_radius() >= 0.0 && q.r.iter().any(|&r| r > 0.0), "{q:?}");
    }
}

#[test]
fn straight_runs_stay_links_and_curved_ones_do_not() {
    let pts = |dy: f64| -> Vec<[f64; 3]> { (0..6).map(|k| [k as f64, if k == 3 { dy } else { 0.0 }, 0.0]).collect() };
    let count = |dy: f64| {
        let s = Scene::from_polylines(&[line(&pts(dy), &[0.5; 6])], 1.0, "s").unwrap();
        let st = s.stats_of(&s.spline_primitives().unwrap());
        (st.cylinders, st.splines)
    };
    // Evenly spaced and collinear: every derivative is the chord, the sweep is the links'.
    assert_eq!(count(0.0), (5, 0));
    // Node 3 moved by 1e-3: its derivative and its neighbours' are no longer the chord, so the
    // four segments touching nodes 2, 3, 4 become splines (the defect ~1e-3 ≫ the threshold
    // 2⁻²²·(½ + ½) ≈ 2.4e-7).
    assert_eq!(count(1e-3), (1, 4));
    // Moved by 1e-12 (defect ≲ 1e-12 < 2.4e-7): indistinguishable in f32, still links.
    assert_eq!(count(1e-12), (5, 0));
    let s = Scene::from_polylines(&[line(&pts(1e-3), &[0.5; 6])], 1.0, "s").unwrap();
    let g = s.spline_segments();
    assert!(g[0].is_straight() && !g[1].is_straight());
    // The defect bounds the deviation: segment 1's controls leave the chord by ≤ 1e-3·(the
    // largest Hermite weight on node 3's displacement, ≤ 1), and are not on it.
    assert!(g[1].chord_defect() > 1e-5 && g[1].chord_defect() <= 1e-3, "{}", g[1].chord_defect());
}

#[test]
fn link_model_counts_match_and_f32_storage_is_guarded() {
    // The link model through stats_of counts what stats counts.
    let s = Scene::from_polylines(
        &[line(&[[0.0; 3], [2.0, 0.0, 0.0], [4.0, 0.0, 0.0], [4.1, 0.0, 0.0]], &[0.5, 0.5, 0.3, 0.1])],
        1.0,
        "t",
    )
    .unwrap();
    let (a, b) = (s.stats(), s.stats_of(&s.primitives()));
    assert_eq!((a.cylinders, a.cones, a.spheres, a.splines), (b.cylinders, b.cones, b.spheres, b.splines));
    assert!(s.primitives().iter().all(|p| p.kind() != PrimKind::Spline));

    // Far and huge (extents 1e9, radius 1): a valid f32 spline model, every box finite.
    let big =
        Scene::from_polylines(&[line(&[[0.0; 3], [1e9, 0.0, 0.0], [2e9, 1e9, 0.0]], &[1.0; 3])], 1.0, "big").unwrap();
    let prims = big.spline_primitives().unwrap();
    // L/r ~ 1e9: the split stops at its maximal depth, 2⁷ pieces per segment.
    assert_eq!(prims.len(), pieces(&big));
    assert_eq!(prims.len(), 2 << SPLINE_MAX_DEPTH);
    assert!(prims.iter().all(|p| {
        let (a, b) = p.aabb();
        a.iter().chain(&b).all(|v| v.is_finite())
    }));
    // The f32 guard: a segment whose extent squared overflows f32 (1e20) is an error, not a
    // primitive that would make the kernel return NaN.
    let q = QuadTube::new([V3::zero(), V3::new(1e20, 1e20, 0.0), V3::new(2e20, 0.0, 0.0)], [1.0; 3]).unwrap();
    assert!(matches!(Prim::from_quad(&q, 0, 0), Err(GeometryError::NonFinite { .. })));
}
