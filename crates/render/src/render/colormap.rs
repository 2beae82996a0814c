//! Named colour maps for colouring by data, from the `colorous` crate (d3-scale-chromatic's
//! maps), and the value range they span.

/// A named colour map.
///
/// ```
/// use tubecast_render::render::Colormap;
/// let m: Colormap = "viridis".parse().unwrap();
/// assert_eq!(m, Colormap::Viridis);
/// // Ends of viridis: dark purple at 0, yellow at 1 (sRGB 0x440154 → 0xfde725).
/// let (lo, hi) = (m.srgb8(0.0), m.srgb8(1.0));
/// assert!(lo[2] > lo[1] && hi[0] > hi[2]);
/// assert!("nope".parse::<Colormap>().is_err());
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Colormap {
    /// Perceptually uniform, blue → green → yellow (the default).
    #[default]
    Viridis,
    /// Black → purple → cream.
    Magma,
    /// Black → red → yellow.
    Inferno,
    /// Blue → magenta → yellow.
    Plasma,
    /// Colour-blind safe blue → yellow.
    Cividis,
    /// Rainbow-like, improved jet.
    Turbo,
    /// Grey ramp, black → white.
    Greys,
    /// Diverging red → yellow → blue.
    RdYlBu,
}

impl Colormap {
    /// Every map with its name.
    pub const ALL: [(Colormap, &'static str); 8] = [
        (Colormap::Viridis, "viridis"),
        (Colormap::Magma, "magma"),
        (Colormap::Inferno, "inferno"),
        (Colormap::Plasma, "plasma"),
        (Colormap::Cividis, "cividis"),
        (Colormap::Turbo, "turbo"),
        (Colormap::Greys, "greys"),
        (Colormap::RdYlBu, "rdylbu"),
    ];

    fn gradient(self) -> colorous::Gradient {
        match self {
            Colormap::Viridis => colorous::VIRIDIS,
            Colormap::Magma => colorous::MAGMA,
            Colormap::Inferno => colorous::INFERNO,
            Colormap::Plasma => colorous::PLASMA,
            Colormap::Cividis => colorous::CIVIDIS,
            Colormap::Turbo => colorous::TURBO,
            Colormap::Greys => colorous::GREYS,
            Colormap::RdYlBu => colorous::RED_YELLOW_BLUE,
        }
    }

    /// The sRGB colour at `x ∈ [0, 1]` (clamped; NaN reads as 0).
    pub fn srgb8(self, x: f64) -> [u8; 3] {
        let x = if x.is_nan() { 0.0 } else { x.clamp(0.0, 1.0) };
        let c = self.gradient().eval_continuous(x);
        [c.r, c.g, c.b]
    }

    /// The linear-RGB colour at `x ∈ [0, 1]` (the renderer works in linear RGB).
    pub fn linear(self, x: f64) -> [f32; 3] {
        self.srgb8(x).map(|v| {
            let s = v as f32 / 255.0;
            if s <= 0.04045 {
                s / 12.92
            } else {
                ((s + 0.055) / 1.055).powf(2.4)
            }
        })
    }
}

impl std::str::FromStr for Colormap {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        let low = s.to_ascii_lowercase();
        Self::ALL.iter().find(|(_, n)| *n == low).map(|(m, _)| *m).ok_or_else(|| {
            let names: Vec<&str> = Self::ALL.iter().map(|(_, n)| *n).collect();
            format!("unknown colour map {s:?} (one of {})", names.join(", "))
        })
    }
}

/// The finite range of `values`: `None` when none is finite.
pub fn value_range(values: &[f64]) -> Option<(f64, f64)> {
    let mut it = values.iter().copied().filter(|v| v.is_finite());
    let first = it.next()?;
    Some(it.fold((first, first), |(lo, hi), v| (lo.min(v), hi.max(v))))
}
