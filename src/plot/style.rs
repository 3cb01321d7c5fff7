//! Visual vocabulary shared by all figures: palette, markers, line styles, fonts and sizes.

use std::sync::OnceLock;

use plotters::style::{register_font, FontStyle, RGBColor};

/// Font family used for every piece of text. It is backed by the DejaVu Sans file shipped in
/// `src/plot/font`, so rendering never depends on fonts installed on the machine.
pub(crate) const FONT: &str = "sans-serif";

static FONT_BYTES: &[u8] = include_bytes!("font/DejaVuSans.ttf");
static FONT_REGISTERED: OnceLock<bool> = OnceLock::new();

/// Registers the shipped font under [`FONT`] once per process; returns whether it is usable.
pub(crate) fn ensure_font() -> bool {
    *FONT_REGISTERED.get_or_init(|| register_font(FONT, FontStyle::Normal, FONT_BYTES).is_ok())
}

/// Colour-blind-friendly palette: the eight Okabe-Ito colours (yellow moved back, as it is faint
/// on white) followed by two Tableau-10 colours. Index with [`palette_color`].
pub const PALETTE: [RGBColor; 10] = [
    RGBColor(0x00, 0x72, 0xB2), // blue
    RGBColor(0xD5, 0x5E, 0x00), // vermillion
    RGBColor(0x00, 0x9E, 0x73), // bluish green
    RGBColor(0xE6, 0x9F, 0x00), // orange
    RGBColor(0xCC, 0x79, 0xA7), // reddish purple
    RGBColor(0x56, 0xB4, 0xE9), // sky blue
    RGBColor(0x00, 0x00, 0x00), // black
    RGBColor(0xF0, 0xE4, 0x42), // yellow
    RGBColor(0x9C, 0x75, 0x5F), // brown (Tableau)
    RGBColor(0xBA, 0xB0, 0xAC), // grey (Tableau)
];

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
