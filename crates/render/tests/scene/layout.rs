//! The scene's memory layout: 24-byte nodes, radii kept per node only when they differ
//! ([`Radii`]), chains of links stored implicitly ([`Links`]), node kinds kept only when some
//! are not 0; the link lists and the answers are the ones an
//! explicit list of pairs gives.

use tubecast::V3;
use tubecast_render::io::swc::SwcNode;
use tubecast_render::render::{clamp_thin, Camera};
use tubecast_render::scene::generate::{self, Rng};
use tubecast_render::scene::{Links, Node, Radii, Scene};

#[test]
fn a_node_is_24_bytes() {
    // Position 3 × 8 = 24 (the SWC type, 4 bytes plus 4 of padding, left every node first:
    // 40 → 32; then the radius, 8: 32 → 24).
    assert_eq!(std::mem::size_of::<Node>(), 24);
}

#[test]
fn a_tractogram_costs_its_nodes_and_a_few_bytes_per_streamline() {
    // 50 streamlines of 84 links (85 nodes): 85 nodes × 24 B, one shared radius (no bytes
    // per node) and one 12-byte run per streamline, per link (85·24 + 12)/84 = 24.43 B
    // (before: (85·32 + 12)/84 = 32.52 B with the radius in each node, 85·40/84 + 8 = 48.48 B
    // with explicit pairs).
    let scene = Scene::from_polylines(&generate::bundle(50, 84, 7), 0.1, "bundle").unwrap();
    assert_eq!((scene.nodes.len(), scene.links.len()), (50 * 85, 50 * 84));
    assert_eq!(scene.links.stretches(), 50);
    assert!(scene.kinds.is_empty(), "every kind is 0: none kept");
    assert!(scene.radii.is_uniform() && scene.radii.memory_bytes() == 0, "one radius: none per node");
    let per_link = scene.memory_bytes() as f64 / scene.links.len() as f64;
    assert!(per_link <= (85.0 * 24.0 + 12.0) / 84.0 + 1e-9, "{per_link} B per link");
}

/// Random link lists: chains of random lengths, broken by explicit pairs (reversed links,
/// jumps, zero-length links), as SWC files and mixed inputs give them.
fn random_links(rng: &mut Rng, n: usize) -> Vec<[u32; 2]> {
    let mut out = Vec::with_capacity(n);
    let mut at = 0u32;
    while out.len() < n {
        match (rng.uniform() * 5.0) as u32 {
            0 | 1 => {
                let len = 1 + (rng.uniform() * 6.0) as u32;
                out.extend((0..len).map(|j| [at + j, at + j + 1]));
                at += len;
            }
            2 => out.push([at + 1, at]),
            3 => out.push([at, at]),
            _ => at += 1 + (rng.uniform() * 3.0) as u32,
        }
    }
    out.truncate(n);
    out
}

#[test]
fn runs_and_explicit_pairs_give_the_same_link_lists() {
    let mut rng = Rng::new(15);
    for case in 0..200 {
        let n = (rng.uniform() * 60.0) as usize;
        let want = random_links(&mut rng, n);
        let got = Links::from(want.clone());
        assert_eq!(got.len(), want.len(), "case {case}");
        assert_eq!(got.iter().len(), want.len());
        assert_eq!(got.to_vec(), want, "case {case}: iter");
        for (k, l) in want.iter().enumerate() {
            assert_eq!(got.get(k), *l, "case {case}: link {k}");
        }
        // Pushed one by one (the same canonical form), and as extended in two halves.
        let mut pushed = Links::default();
        want.iter().for_each(|&l| pushed.push(l));
        let mut halves: Links = want[..n / 2].iter().copied().collect();
        halves.extend(want[n / 2..].iter().copied());
        assert!(pushed == got && halves == got && got == want, "case {case}");
        // Never more than explicit pairs cost: each stretch of explicit pairs is ≥ 1 link and
        // each run ≥ 2, so 12 B per stretch is ≤ 12 B per link; pairs 8 B each.
        assert!(got.stretches() <= n);
    }
}

#[test]
fn a_chain_costs_one_stretch_and_a_break_costs_one_more() {
    let chain: Links = (0..100u32).map(|i| [i, i + 1]).collect();
    assert_eq!((chain.len(), chain.stretches(), chain.get(99)), (100, 1, [99, 100]));
    // Two chains that do not join (the second starts at node 102, not 101): two runs.
    let two: Links = (0..100u32).map(|i| [i, i + 1]).chain((102..110).map(|i| [i, i + 1])).collect();
    assert_eq!((two.stretches(), two.get(100), two.get(99)), (2, [102, 103], [99, 100]));
    // A lone chain link and a reversed one are explicit pairs: one stretch.
    let lone = Links::from(vec![[4, 5], [9, 8]]);
    assert_eq!((lone.stretches(), lone.to_vec()), (1, vec![[4, 5], [9, 8]]));
    assert_ne!(lone, Links::from(vec![[4, 5], [8, 9]]));
}

#[test]
#[should_panic(expected = "link 3 of 3")]
fn a_link_past_the_end_panics_like_an_index() {
    let l = Links::from(vec![[0, 1], [1, 2], [2, 3]]);
    let _ = l.get(3);
}

#[test]
fn a_polyline_scene_links_the_nodes_an_explicit_list_names() {
    // The reference: the links of each streamline written out as explicit pairs; the scene's
    // runs must give the same list, and each link's round cone the nodes that list names.
    let lines = generate::furball(20, 12, 3);
    let a = Scene::from_polylines(&lines, 0.05, "runs").unwrap();
    let mut explicit = Vec::new();
    let mut base = 0u32;
    for l in &lines {
        let n = l.points.len() as u32;
        explicit.extend((1..n).map(|i| [base + i - 1, base + i]));
        base += n;
    }
    assert_eq!(a.links, explicit);
    assert_eq!(a.links.stretches(), 20);
    let b = Scene { links: explicit.clone().into(), ..a.clone() };
    assert_eq!((&a, a.primitives()), (&b, b.primitives()));
    for (k, &[i, j]) in explicit.iter().enumerate() {
        let (i, j) = (i as usize, j as usize);
        let (l, (p, q)) = (a.link(k), (a.nodes[i].pos, a.nodes[j].pos));
        assert_eq!((l.a.to_array(), l.ra, l.b.to_array(), l.rb), (p, a.radius(i), q, a.radius(j)), "link {k}");
    }
}

#[test]
fn swc_kinds_are_kept_per_node_and_polyline_kinds_are_zero() {
    let row = |id: i64, kind: i32, x: f64, parent: i64| SwcNode { id, kind, pos: [x, 0.0, 0.0], radius: 0.5, parent };
    let s = Scene::from_swc(&[row(1, 1, 0.0, -1), row(2, 3, 1.0, 1), row(3, 3, 2.0, 2)], "n").unwrap();
    assert_eq!((s.kind(0), s.kind(1), s.kind(2)), (1, 3, 3));
    assert_eq!(s.kinds, vec![1, 3, 3]);
    // SWC links are [parent, child]: here a chain 0 → 1 → 2, one run.
    assert_eq!((s.links.to_vec(), s.links.stretches()), (vec![[0, 1], [1, 2]], 1));
    let zero = Scene::from_swc(&[row(1, 0, 0.0, -1), row(2, 0, 1.0, 1)], "z").unwrap();
    assert!(zero.kinds.is_empty() && zero.kind(1) == 0);
}

#[test]
fn an_swc_with_varying_radii_keeps_every_radius_bit_for_bit() {
    // A base neuron (901 rows: soma 6, tapering dendrites): every radius read back is the
    // row's, bit for bit, and each node costs 24 (position) + 8 (radius) + 4 (type) bytes.
    let rows = generate::base_neuron(1);
    let s = Scene::from_swc(&rows, "neuron").unwrap();
    assert!(!s.radii.is_uniform());
    for (i, r) in rows.iter().enumerate() {
        assert_eq!(s.radius(i).to_bits(), r.radius.to_bits(), "node {i}");
    }
    let n = rows.len();
    assert_eq!(s.memory_bytes(), n * (24 + 8 + 4) + s.links.memory_bytes());
    // The links' round cones carry the same radii.
    for (k, [a, b]) in s.links.iter().enumerate() {
        let l = s.link(k);
        let want = [rows[a as usize].radius.to_bits(), rows[b as usize].radius.to_bits()];
        assert_eq!([l.ra.to_bits(), l.rb.to_bits()], want, "link {k}");
    }
}

#[test]
fn a_uniform_scene_stores_no_radius_per_node() {
    // Polylines without radii (all get the default), and an SWC whose rows share one radius.
    let s = Scene::from_polylines(&generate::bundle(4, 10, 3), 0.12, "b").unwrap();
    assert!(s.radii.is_uniform() && (0..s.nodes.len()).all(|i| s.radius(i) == 0.12));
    assert_eq!(s.memory_bytes(), s.nodes.len() * 24 + s.links.memory_bytes());
    let row = |id: i64, x: f64, parent: i64| SwcNode { id, kind: 0, pos: [x, 0.0, 0.0], radius: 0.5, parent };
    let swc = Scene::from_swc(&[row(1, 0.0, -1), row(2, 1.0, 1), row(3, 2.0, 2)], "u").unwrap();
    assert!(swc.radii.is_uniform() && swc.radius(2) == 0.5 && swc.radii.memory_bytes() == 0);
    // Setting a radius to the shared one keeps it shared; another value keeps one per node.
    let mut t = swc.clone();
    t.set_radius(1, 0.5);
    assert!(t.radii.is_uniform() && t == swc);
    t.set_radius(1, 0.25);
    assert_eq!((t.radius(0), t.radius(1), t.radius(2)), (0.5, 0.25, 0.5));
    assert!(t.radii.memory_bytes() >= 3 * 8);
    // A list of equal radii is stored once; -0.0 and 0.0 differ in their bits and are kept.
    assert!(Radii::from_vec(vec![0.3; 5]).is_uniform());
    let signed = Radii::from_vec(vec![0.0, -0.0]);
    assert_eq!((signed.get(0).to_bits(), signed.get(1).to_bits()), (0.0f64.to_bits(), (-0.0f64).to_bits()));
}

#[test]
fn thin_clamping_gives_each_node_its_own_radius() {
    // A line of radius 0.001 receding from the eye at z = 10 (depths 10, 14, 18), 90° field
    // of view, 100 rows: a pixel at depth d is 2·d·tan 45°/100 = d/50 wide, so a 2-pixel
    // footprint asks r = ½·2·d/50 = d/50: 0.2, 0.28, 0.36 — three radii from one shared one.
    let cam = Camera::look_at(V3::new(0.0, 0.0, 10.0), V3::zero(), V3::new(0.0, 1.0, 0.0), 90.0, 100, 100).unwrap();
    let nodes = [0.0, -4.0, -8.0].map(|z| Node { pos: [0.0, 0.0, z] }).to_vec();
    let links = vec![[0, 1], [1, 2]].into();
    let mut s = Scene { nodes, links, radii: Radii::uniform(0.001), ..Scene::default() };
    assert!(s.radii.is_uniform());
    assert_eq!(clamp_thin(&mut s, &cam, 2.0), 3);
    assert!(!s.radii.is_uniform());
    for (i, want) in [0.2, 0.28, 0.36].into_iter().enumerate() {
        // The depth is (eye − p)·forward, exact here; the rest a few roundings of ~1e-16.
        assert!((s.radius(i) - want).abs() < 1e-12, "node {i}: {}", s.radius(i));
    }
    assert_eq!((s.link(1).ra, s.link(1).rb), (s.radius(1), s.radius(2)));
}
