//! One data set of an x-y figure.

use super::style::{Marker, SeriesStyle};

/// A labelled set of (x, y) points and how to draw them.
///
/// Non-finite points are never drawn: lines are broken at them and markers skipped.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Series {
    /// Legend text; an empty label keeps the series out of the legend.
    pub label: String,
    /// Data points in plot order.
    pub points: Vec<(f64, f64)>,
    /// Line, markers, both, or dashed.
    pub style: SeriesStyle,
    /// Palette index (see [`PALETTE`](super::PALETTE)); `None` takes the next colour in order
    /// among the series without an explicit colour.
    pub color: Option<usize>,
    /// Marker shape, used by the styles that draw markers.
    pub marker: Marker,
    /// Keeps the series out of the automatic axis ranges, so that a few far points (e.g. distant
    /// attractors) do not squeeze the rest; its points beyond the range are marked by arrows
    /// on the frame and counted in the legend.
    pub outside_range: bool,
}

impl Series {
    /// A series drawn with `style` and default colour and marker.
    pub fn new(label: impl Into<String>, points: Vec<(f64, f64)>, style: SeriesStyle) -> Self {
        Series {
            label: label.into(),
            points,
            style,
            color: None,
            marker: Marker::default(),
            outside_range: false,
        }
    }

    /// A solid line.
    pub fn line(label: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Self::new(label, points, SeriesStyle::Line)
    }

    /// Markers only.
    pub fn markers(label: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Self::new(label, points, SeriesStyle::Markers)
    }

    /// A solid line with a marker on every point.
    pub fn line_markers(label: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Self::new(label, points, SeriesStyle::LineMarkers)
    }

    /// A dashed line.
    pub fn dashed(label: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Self::new(label, points, SeriesStyle::Dashed)
    }

    /// A dotted line.
    pub fn dotted(label: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Self::new(label, points, SeriesStyle::Dotted)
    }

    /// Keeps the series out of the automatic ranges (see [`Series::outside_range`]).
    pub fn outside_range(mut self) -> Self {
        self.outside_range = true;
        self
    }

    /// Uses palette colour `i` (wrapping beyond the palette length).
    pub fn with_color(mut self, i: usize) -> Self {
        self.color = Some(i);
        self
    }

    /// Uses marker shape `m`.
    pub fn with_marker(mut self, m: Marker) -> Self {
        self.marker = m;
        self
    }

    /// Finite points only.
    pub(crate) fn finite_points(&self) -> impl Iterator<Item = (f64, f64)> + '_ {
        self.points
            .iter()
            .copied()
            .filter(|(x, y)| x.is_finite() && y.is_finite())
    }
}
