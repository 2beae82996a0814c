//! The WGSL kernel's constants against the Rust kernel's: each `const` of `shaders/link.wgsl`
//! must appear, with the same value, in the Rust expression it ports. A constant changed on
//! either side, or a new WGSL constant without an entry here, fails.

const WGSL: &str = include_str!("../../shaders/link.wgsl");
const STABLE: &str = include_str!("../../../../src/kernel/link/stable.rs");
const QUADRIC: &str = include_str!("../../../../src/math/quadric.rs");

/// `(name, value)` of every `const NAME: TYPE = VALUE;` line.
fn wgsl_constants() -> Vec<(String, String)> {
    WGSL.lines()
        .filter_map(|l| l.trim().strip_prefix("const "))
        .map(|rest| {
            let (name, rest) = rest.split_once(':').expect("const NAME: TYPE = VALUE;");
            let (_, value) = rest.split_once('=').expect("const NAME: TYPE = VALUE;");
            (name.trim().to_string(), value.trim().trim_end_matches(';').trim().to_string())
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
        _ => return None,
    })
}

#[test]
fn wgsl_constants_equal_the_rust_kernels() {
    let consts = wgsl_constants();
    assert!(consts.len() >= 8, "parsed {consts:?}");
    for (name, value) in &consts {
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
