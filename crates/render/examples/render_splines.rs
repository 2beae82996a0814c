//! Render one scene as links and as spline tubes, opaque and transparent, to four PNGs.
//!
//! `cargo run --release --example render_splines [-- IN OUT_DIR]` (default: a generated
//! helix of 24 segments per strand into `target/render_splines/`). `IN` is any scene the CLI
//! reads (.swc, .trk, .tck, .obj; default radius 0.2).

fn main() -> Result<(), Box<dyn std::error::Error>> {
    use tubecast_render::accel::Bvh;
    use tubecast_render::render::{render, Camera, Options};
    use tubecast_render::scene::{generate, Scene};

    let args: Vec<String> = std::env::args().skip(1).collect();
    let scene = match args.first() {
        Some(p) => Scene::load(std::path::Path::new(p), 0.2)?,
        None => Scene::from_polylines(&generate::helix(24), 0.2, "helix")?,
    };
    let dir = std::path::PathBuf::from(args.get(1).map_or("target/render_splines", |s| s.as_str()));
    std::fs::create_dir_all(&dir)?;
    let spline_prims = scene.spline_primitives()?;
    let st = scene.stats_of(&spline_prims);
    println!(
        "{} links → {} spline segments, {} links kept",
        st.links,
        st.splines,
        st.cylinders + st.cones + st.spheres
    );
    // One camera for both models (fitted to the spline model's bounds, which contain the
    // curves' bulges).
    let cam = Camera::fit(st.bounds.0, st.bounds.1, 40.0, 480, 360)?;
    for (model, prims) in [("links", scene.primitives()), ("splines", spline_prims)] {
        let bvh = Bvh::build(prims);
        for (mode, opacity) in [("opaque", 1.0), ("transparent", 0.4)] {
            let img = render(&scene, &bvh, &cam, &Options { opacity, ..Options::default() })?;
            let out = dir.join(format!("{model}_{mode}.png"));
            img.write_png(&out)?;
            println!("wrote {}", out.display());
        }
    }
    Ok(())
}
