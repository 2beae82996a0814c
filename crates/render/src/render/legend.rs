//! A colour bar with its value range, drawn into a rendered image (`--legend`).

use super::{Colormap, Image};

/// 3×5 pixel glyphs (rows top to bottom, 3 bits each, high bit left) for the characters a
/// number needs.
fn glyph(c: char) -> Option<[u8; 5]> {
    Some(match c {
        '0' => [7, 5, 5, 5, 7],
        '1' => [2, 6, 2, 2, 7],
        '2' => [7, 1, 7, 4, 7],
        '3' => [7, 1, 7, 1, 7],
        '4' => [5, 5, 7, 1, 1],
        '5' => [7, 4, 7, 1, 7],
        '6' => [7, 4, 7, 5, 7],
        '7' => [7, 1, 1, 1, 1],
        '8' => [7, 5, 7, 5, 7],
        '9' => [7, 5, 7, 1, 7],
        '.' => [0, 0, 0, 0, 2],
        '-' => [0, 0, 7, 0, 0],
        '+' => [0, 2, 7, 2, 0],
        'e' => [0, 7, 7, 4, 7],
        _ => return None,
    })
}

/// A value as at most 4 significant digits (`1.234`, `-0.5`, `1.2e-5`).
pub fn label(v: f64) -> String {
    let a = v.abs();
    if a != 0.0 && !(1e-3..1e5).contains(&a) {
        format!("{v:.2e}")
    } else {
        let s = format!("{v:.4}");
        let s = s.trim_end_matches('0').trim_end_matches('.');
        if s.is_empty() || s == "-" {
            "0".into()
        } else {
            s.into()
        }
    }
}

/// WCAG relative luminance of a linear RGB colour.
fn luminance(c: [f32; 3]) -> f32 {
    0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]
}

/// WCAG contrast ratio of two linear RGB colours, `(L₁ + 0.05) / (L₂ + 0.05)` with `L₁ ≥ L₂`:
/// from 1 (the same luminance) to 21 (black on white).
pub fn contrast_ratio(a: [f32; 3], b: [f32; 3]) -> f32 {
    let (la, lb) = (luminance(a), luminance(b));
    (la.max(lb) + 0.05) / (la.min(lb) + 0.05)
}

/// Black or white, whichever contrasts more with `background` (linear RGB). The two ratios
/// multiply to 21 (`(1.05 / (L + 0.05)) · ((L + 0.05) / 0.05)`), so the larger is at least
/// √21 ≈ 4.58 on any background: above WCAG's 4.5 for text.
///
/// ```
/// use tubecast_render::render::contrasting_ink;
/// assert_eq!(contrasting_ink([0.0; 3]), [1.0; 3]);
/// assert_eq!(contrasting_ink([1.0; 3]), [0.0; 3]);
/// ```
pub fn contrasting_ink(background: [f32; 3]) -> [f32; 3] {
    let (black, white) = ([0.0; 3], [1.0; 3]);
    if contrast_ratio(white, background) > contrast_ratio(black, background) {
        white
    } else {
        black
    }
}

/// Text at `(x, y)` (top left), each glyph pixel an `s × s` block of `color`, over a halo one
/// block wide in the colour that contrasts with it, so the text reads over tubes as well as
/// over the background (and over whatever shows through a transparent one).
fn text(img: &mut Image, x: i64, y: i64, s: i64, t: &str, color: [f32; 3]) {
    let halo = contrasting_ink(color);
    for (ink, grow) in [(halo, s), (color, 0)] {
        for (k, c) in t.chars().enumerate() {
            let Some(g) = glyph(c) else { continue };
            for (row, bits) in g.iter().enumerate() {
                for col in 0..3 {
                    if bits >> (2 - col) & 1 == 1 {
                        let (px, py) = (x + (4 * k as i64 + col) * s, y + row as i64 * s);
                        fill(img, px - grow, py - grow, s + 2 * grow, s + 2 * grow, ink);
                    }
                }
            }
        }
    }
}

fn fill(img: &mut Image, x: i64, y: i64, w: i64, h: i64, color: [f32; 3]) {
    for yy in y.max(0)..(y + h).min(img.height as i64) {
        for xx in x.max(0)..(x + w).min(img.width as i64) {
            let i = (yy as u32 * img.width + xx as u32) as usize;
            img.rgb[i] = color;
            if let Some(a) = img.alpha.get_mut(i) {
                *a = 1.0;
            }
        }
    }
}

impl Image {
    /// Draw a vertical colour bar of `map` at the right edge, `lo` at its bottom and `hi` at
    /// its top, with both values written beside it in `ink` (linear RGB; [`contrasting_ink`]
    /// of the background reads on any background), each glyph haloed in the colour that
    /// contrasts with `ink`. The bar spans the
    /// middle 60 % of the height, is `max(6, width/40)` pixels wide, framed in `ink`; text is
    /// scaled with the image (3×5 glyphs, `max(1, height/200)` pixels each).
    ///
    /// ```
    /// use tubecast_render::render::{Colormap, Image};
    /// let n = 20_000;
    /// let (rgb, alpha, depth) = (vec![[1.0; 3]; n], vec![0.0; n], vec![f64::INFINITY; n]);
    /// let mut img = Image { width: 200, height: 100, rgb, alpha, depth, background: [1.0; 3] };
    /// img.draw_legend(Colormap::Viridis, 0.0, 1.0, [0.0; 3]);
    /// assert!(img.rgb.iter().any(|p| *p != [1.0; 3]));
    /// // The bar is opaque in an RGBA image.
    /// assert!(img.alpha.iter().any(|a| *a == 1.0));
    /// ```
    pub fn draw_legend(&mut self, map: Colormap, lo: f64, hi: f64, ink: [f32; 3]) {
        let (w, h) = (self.width as i64, self.height as i64);
        let s = (h / 200).max(1);
        let bw = (w / 40).max(6);
        let (top, bottom) = (h / 5, h - h / 5);
        let (lo_t, hi_t) = (label(lo), label(hi));
        let tw = 4 * s * lo_t.len().max(hi_t.len()) as i64;
        let x0 = w - bw - tw - 3 * s - 2;
        fill(self, x0 - 1, top - 1, bw + 2, bottom - top + 2, ink);
        for y in top..bottom {
            let f = if bottom - top > 1 { (bottom - 1 - y) as f64 / (bottom - top - 1) as f64 } else { 0.5 };
            fill(self, x0, y, bw, 1, map.linear(f));
        }
        let tx = x0 + bw + 2 * s + 1;
        text(self, tx, top, s, &hi_t, ink);
        text(self, tx, bottom - 5 * s, s, &lo_t, ink);
    }
}
