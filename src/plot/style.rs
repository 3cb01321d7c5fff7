//! Visual vocabulary shared by all figures: palette, markers, line styles, fonts and sizes.

use std::sync::OnceLock;

use plotters::style::{register_font, FontStyle, RGBColor};

/// Font family used for every piece of text. It is backed by the DejaVu Sans file shipped in
/// `src/plot/font`, so rendering never depends on fonts installed on the machine.
pub(crate) const FONT: &str = "sans-serif";

pub(crate) static FONT_BYTES: &[u8] = include_bytes!("font/DejaVuSans.ttf");
static FONT_REGISTERED: OnceLock<bool> = OnceLock::new();

/// Registers the shipped font under [`FONT`] once per process; returns whether it is usable.
pub(crate) fn ensure_font() -> bool {
    *FONT_REGISTERED.get_or_init(|| register_font(FONT, FontStyle::Normal, FONT_BYTES).is_ok())
}

/// Colour-blind-friendly palette after Okabe-Ito, every colour at least 3:1 in contrast on white
/// (WCAG 2 relative luminance): Okabe-Ito blue, vermillion and bluish green as they are, their
/// orange, reddish purple and sky blue darkened to pass, black, an olive for their yellow (1.3:1),
/// Tableau's brown and a dark purple. Index with [`palette_color`].
pub const PALETTE: [RGBColor; 10] = [
    RGBColor(0x00, 0x72, 0xB2), // blue 5.2:1
    RGBColor(0xD5, 0x5E, 0x00), // vermillion 3.9:1
    RGBColor(0x00, 0x9E, 0x73), // bluish green 3.4:1
    RGBColor(0xB9, 0x77, 0x00), // dark orange 3.7:1
    RGBColor(0xC0, 0x67, 0x9A), // reddish purple 3.7:1
    RGBColor(0x3A, 0x93, 0xC3), // sky blue 3.4:1
    RGBColor(0x00, 0x00, 0x00), // black 21:1
    RGBColor(0x8F, 0x8A, 0x00), // olive 3.6:1
    RGBColor(0x9C, 0x75, 0x5F), // brown 4.1:1
    RGBColor(0x6A, 0x3D, 0x9A), // dark purple 8.8:1
];

/// WCAG 2 contrast ratio of `c` against white: (1.05) / (L + 0.05) with L the relative
/// luminance of the sRGB colour.
#[cfg(test)]
pub(crate) fn contrast_on_white(c: RGBColor) -> f64 {
    let lin = |v: u8| {
        let v = f64::from(v) / 255.0;
        if v <= 0.03928 {
            v / 12.92
        } else {
            ((v + 0.055) / 1.055).powf(2.4)
        }
    };
    let l = 0.2126 * lin(c.0) + 0.7152 * lin(c.1) + 0.0722 * lin(c.2);
    1.05 / (l + 0.05)
}

/// Colour for palette index `i`; indices beyond the palette wrap around.
pub fn palette_color(i: usize) -> RGBColor {
    PALETTE[i % PALETTE.len()]
}

/// How a [`Series`](super::Series) is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SeriesStyle {
    /// Solid polyline through the points (broken at non-finite points).
    #[default]
    Line,
    /// One marker per point, no line (e.g. Poincaré sections, sampled amplitudes).
    Markers,
    /// Solid polyline with a marker on every point.
    LineMarkers,
    /// Dashed polyline (e.g. unstable branches, reference curves).
    Dashed,
    /// Dotted polyline, a third line style beside solid and dashed (e.g. one edge of a band
    /// whose other edge is dashed).
    Dotted,
}

impl SeriesStyle {
    /// Dash and gap lengths in pixels of a broken line style, `None` for solid lines.
    pub(crate) fn dash(self) -> Option<(u32, u32)> {
        match self {
            SeriesStyle::Dashed => Some((9, 6)),
            SeriesStyle::Dotted => Some((2, 4)),
            _ => None,
        }
    }
}

/// Marker shape used by [`SeriesStyle::Markers`] and [`SeriesStyle::LineMarkers`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Marker {
    /// Filled circle.
    #[default]
    Circle,
    /// Filled square.
    Square,
    /// Filled upward triangle.
    Triangle,
    /// Diagonal cross (x).
    Cross,
    /// Tiny filled dot, for dense point clouds.
    Dot,
    /// Open circle (a ring): what is not a filled marker's kind, e.g. a set trajectories leave.
    Ring,
}

/// Pixel sizes of one figure, scaled together so that panels stay proportionate.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Sizes {
    pub title: f64,
    pub caption: f64,
    pub axis: f64,
    pub tick: f64,
    pub legend: f64,
    pub marker: i32,
    pub line: u32,
}

impl Sizes {
    /// Sizes for a stand-alone 1000 x 700 figure multiplied by `scale`.
    pub fn scaled(scale: f64) -> Self {
        Sizes {
            title: 26.0 * scale,
            caption: 17.0 * scale,
            axis: 20.0 * scale,
            tick: 16.0 * scale,
            legend: 16.0 * scale,
            marker: ((4.0 * scale).round() as i32).max(2),
            line: 2,
        }
    }
}
