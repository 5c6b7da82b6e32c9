//! Colours, fonts and sizes shared by all plots.

use plotters::prelude::*;

/// Font family (DejaVu is installed; plotters resolves the family through the system).
pub const FONT: &str = "sans-serif";

/// Caption font size (px).
pub const CAPTION_SIZE: u32 = 26;

/// Axis label font size (px).
pub const LABEL_SIZE: u32 = 20;

/// Series colours (colour-blind friendly, Okabe-Ito).
pub const PALETTE: [RGBColor; 7] = [
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(230, 159, 0),
    RGBColor(86, 180, 233),
    RGBColor(0, 0, 0),
];

/// Colour of series `i`.
pub fn series_color(i: usize) -> RGBColor {
    PALETTE[i % PALETTE.len()]
}

/// Crack colour.
pub const CRACK: RGBColor = RGBColor(200, 0, 0);

/// Viridis stops (matplotlib's default colour map).
const VIRIDIS: [(u8, u8, u8); 8] = [
    (68, 1, 84),
    (70, 50, 127),
    (54, 92, 141),
    (39, 127, 143),
    (31, 162, 136),
    (74, 194, 110),
    (160, 219, 57),
    (254, 232, 37),
];

/// Viridis colour of `t` in [0, 1] (clamped; NaN gives grey).
pub fn viridis(t: f64) -> RGBColor {
    if !t.is_finite() {
        return RGBColor(128, 128, 128);
    }
    let x = t.clamp(0.0, 1.0) * (VIRIDIS.len() - 1) as f64;
    let i = (x.floor() as usize).min(VIRIDIS.len() - 2);
    let f = x - i as f64;
    let lerp = |a: u8, b: u8| (a as f64 + f * (b as f64 - a as f64)).round() as u8;
    let (a, b) = (VIRIDIS[i], VIRIDIS[i + 1]);
    RGBColor(lerp(a.0, b.0), lerp(a.1, b.1), lerp(a.2, b.2))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn viridis_ends() {
        assert_eq!(viridis(0.0), RGBColor(68, 1, 84));
        assert_eq!(viridis(1.0), RGBColor(254, 232, 37));
        assert_eq!(viridis(2.0), RGBColor(254, 232, 37));
        assert_eq!(viridis(f64::NAN), RGBColor(128, 128, 128));
    }
}
