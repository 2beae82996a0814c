//! The WGSL kernels' constants against the Rust kernels': each `const` of `shaders/link.wgsl`
//! and of the spline kernel's shaders (`spline.wgsl`, `ray_space.wgsl`, `roots.wgsl`) must
//! appear, with the same value, in the Rust expression it ports (or be one of the spline
//! shader's own function and start ids, which port no Rust constant).
//! A constant changed on either side, or a new WGSL constant without an entry here, fails.

const WGSL: &str = include_str!("../../shaders/link.wgsl");
const SPLINE_WGSL: &str = tubecast_gpu::kernel::SPLINE_WGSL;
const STABLE: &str = include_str!("../../../../src/kernel/link/stable.rs");
const QUADRIC: &str = include_str!("../../../../src/math/quadric.rs");
const ROOTS: &str = include_str!("../../../../src/math/roots.rs");
const RAY_SPACE: &str = include_str!("../../../../src/kernel/spline/ray_space.rs");
const DIRECT: &str = include_str!("../../../../src/kernel/spline/direct.rs");
const REJECT: &str = include_str!("../../../../src/kernel/spline/ray_space/reject.rs");
const CAPSULE: &str = include_str!("../../../../src/kernel/spline/capsule.rs");

/// The spline shader's ids of the functions its root finders solve and of their starts (the
/// Rust passes closures instead): they must be distinct within each kind.
const SHADER_IDS: [&str; 7] = ["FN_G1", "FN_GSQ", "FN_F1", "FN_POLY", "START_NONE", "START_G1", "START_G"];

/// `(name, value)` of every `const NAME: TYPE = VALUE;` line of `src` (a `u` or `i` suffix
/// dropped).
fn wgsl_constants(src: &str) -> Vec<(String, String)> {
    src.lines()
        .filter_map(|l| l.trim().strip_prefix("const "))
        .map(|rest| {
            let (name, rest) = rest.split_once(':').expect("const NAME: TYPE = VALUE;");
            let (_, value) = rest.split_once('=').expect("const NAME: TYPE = VALUE;");
            let value = value.trim().trim_end_matches(';').trim();
            let value = if value.starts_with("0x") { value } else { value.trim_end_matches(['u', 'i']) };
            (name.trim().to_string(), value.to_string())
        })
        .collect()
}

/// The Rust expression that holds each constant, with `{}` where the value goes (written as
/// Rust's `{:?}` writes the WGSL value).
fn rust_site(name: &str) -> Option<(&'static str, &'static str)> {
    Some(match name {
        "CONE_DROP" => (STABLE, "c2.ge(T::epsilon() * T::cst({}))"),
        "SKEW" => (STABLE, "q2.gt(T::cst({}))"),
        "STEP_LIM" => (STABLE, "T::epsilon().sqrt() * T::cst({}) * scale"),
        "TIGHT" => (STABLE, "T::epsilon() * T::cst({}) * scale.min(self.sd)"),
        "SETTLE_ROUNDS" => (STABLE, "for _ in 0..{} {"),
        "FAR_APART" => (QUADRIC, "(b * b).gt(T::cst({}) * (a * c).abs())"),
        "MAX_ITER" => (ROOTS, "pub const MAX_ITER: u32 = {};"),
        "TOL_ULPS" => (ROOTS, "T::epsilon() * T::cst({})\n"),
        "ITP_K1" => (ROOTS, "let k1 = T::cst({}) / T::select(w0.gt(zero), w0, one);"),
        "TINY_EXP" => (RAY_SPACE, "} else { ({}, "),
        "TINY_UP_EXP" => (RAY_SPACE, "} else { (-38, {}) };"),
        "TAU_ULPS" => (DIRECT, "T::epsilon() * T::cst({}) * (sw + sr)"),
        "HULL_REACH" => (REJECT, "rho + T::cst({}) * eps;"),
        "HULL_ORIENT" => (REJECT, "T::cst({}) * eps * (a.length2() + b.length2())"),
        "G_HULL_LIM" => (REJECT, "-(T::cst({}) * T::epsilon())"),
        "CAPSULE_ABS" => (CAPSULE, "T::cst({}) * eps + T::cst(64.0) * eps * n1(w)"),
        "CAPSULE_REL" => (CAPSULE, "T::cst(16384.0) * eps + T::cst({}) * eps * n1(w)"),
        _ => return None,
    })
}

#[test]
fn wgsl_constants_equal_the_rust_kernels() {
    let link = wgsl_constants(WGSL);
    assert!(link.len() >= 8, "parsed {link:?}");
    let spline = wgsl_constants(SPLINE_WGSL);
    assert!(spline.len() >= 18, "parsed {spline:?}");
    let ids: Vec<&(String, String)> = spline.iter().filter(|(n, _)| SHADER_IDS.contains(&n.as_str())).collect();
    assert_eq!(ids.len(), SHADER_IDS.len(), "{ids:?}");
    for kind in ["FN_", "START_"] {
        let mut values: Vec<&str> = ids.iter().filter(|(n, _)| n.starts_with(kind)).map(|(_, v)| v.as_str()).collect();
        let n = values.len();
        values.sort_unstable();
        values.dedup();
        assert_eq!(values.len(), n, "{kind} ids repeat: {ids:?}");
    }
    for (name, value) in link.iter().chain(spline.iter().filter(|(n, _)| !SHADER_IDS.contains(&n.as_str()))) {
        match name.as_str() {
            "EPS" => assert_eq!(value.parse::<f32>().unwrap(), f32::EPSILON, "EPS"),
            "INF_BITS" => assert_eq!(
                u32::from_str_radix(value.trim_start_matches("0x").trim_end_matches('u'), 16).unwrap(),
                f32::INFINITY.to_bits()
            ),
            _ => {
                let (src, site) = rust_site(name).unwrap_or_else(|| panic!("WGSL constant {name} has no Rust site"));
                let shown = match value.parse::<i64>() {
                    Ok(i) => i.to_string(),
                    Err(_) => format!("{:?}", value.trim_end_matches('f').parse::<f64>().unwrap()),
                };
                let want = site.replace("{}", &shown);
                assert!(src.contains(&want), "{name} = {value}: the Rust kernel has no `{want}`");
            }
        }
    }
}
