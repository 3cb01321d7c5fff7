//! Data markers and legend samples. Markers keep a fixed pixel size whatever the axis scales.
//!
//! Elements are drawn one kind per call: plotters' composable elements carry the backend type,
//! which would force `'static` backends on the writers.

use plotters::coord::Shift;
use plotters::prelude::*;

use super::axis::LinAxis;
use super::clip::View;
use super::output::{msg, DrawResult};
use super::style::{Marker, SeriesStyle};

/// Chart with linear f64 axes, as used by every figure.
pub(crate) type Chart<'a, DB> = ChartContext<'a, DB, Cartesian2d<LinAxis, LinAxis>>;

/// Radius of a [`Marker::Dot`] for marker half-size `s`.
fn dot_radius(s: i32) -> i32 {
    ((s + 1) / 2).max(1)
}

/// Half side of a [`Marker::Square`], chosen so it looks as heavy as a circle of radius `s`.
fn square_half(s: i32) -> i32 {
    (s * 9 + 5) / 10
}

/// Draws marker `m` of half-size `s` pixels at each data point of `pts`.
pub(crate) fn draw_markers<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    pts: &[(f64, f64)],
    m: Marker,
    s: i32,
    color: RGBColor,
    view: &View,
) -> DrawResult {
    let fill = color.filled();
    let it = pts.iter().copied();
    match m {
        Marker::Circle => chart.draw_series(it.map(|p| Circle::new(p, s, fill))),
        Marker::Dot => chart.draw_series(it.map(|p| Circle::new(p, dot_radius(s), fill))),
        Marker::Ring => {
            let st = color.stroke_width(2);
            chart.draw_series(it.map(|p| Circle::new(p, s, st)))
        }
        Marker::Triangle => chart.draw_series(it.map(|p| TriangleMarker::new(p, s + 1, fill))),
        Marker::Cross => {
            let st = color.stroke_width(2);
            chart.draw_series(it.map(|p| Cross::new(p, s, st)))
        }
        Marker::Square => {
            let h = f64::from(square_half(s));
            let (dx, dy) = (h * view.pixel().0, h * view.pixel().1);
            let sq =
                |(x, y): (f64, f64)| Rectangle::new([(x - dx, y - dy), (x + dx, y + dy)], fill);
            chart.draw_series(it.map(sq))
        }
    }
    .map(|_| ())
    .map_err(msg)
}

/// Legend sample of a series: a line (solid or dashed) and/or a marker.
#[derive(Debug, Clone, Copy)]
pub(crate) struct LegendSample {
    pub width: i32,
    pub style: SeriesStyle,
    pub marker: Marker,
    pub size: i32,
    pub line: u32,
    pub color: RGBColor,
}

impl LegendSample {
    /// Draws the sample on `area` with its left end at pixel `(x, y)`.
    pub fn draw<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        (x, y): (i32, i32),
    ) -> DrawResult {
        let (w, st) = (self.width, self.color.stroke_width(self.line));
        match self.style {
            SeriesStyle::Line | SeriesStyle::LineMarkers => {
                area.draw(&PathElement::new(vec![(x, y), (x + w, y)], st))
                    .map_err(msg)?;
            }
            SeriesStyle::Dashed | SeriesStyle::Dotted => {
                let (dash, gap) = match self.style.dash() {
                    Some((d, g)) => (d as i32, g as i32),
                    None => (w, 0),
                };
                let mut x0 = x;
                while x0 < x + w {
                    let x1 = (x0 + dash).min(x + w);
                    area.draw(&PathElement::new(vec![(x0, y), (x1, y)], st))
                        .map_err(msg)?;
                    x0 = x1 + gap;
                }
            }
            SeriesStyle::Markers => {}
        }
        if !matches!(self.style, SeriesStyle::Markers | SeriesStyle::LineMarkers) {
            return Ok(());
        }
        let c = (x + w / 2, y);
        let s = self.size;
        let fill = self.color.filled();
        match self.marker {
            Marker::Circle => area.draw(&Circle::new(c, s, fill)),
            Marker::Dot => area.draw(&Circle::new(c, dot_radius(s), fill)),
            Marker::Ring => area.draw(&Circle::new(c, s, self.color.stroke_width(2))),
            Marker::Triangle => area.draw(&TriangleMarker::new(c, s + 1, fill)),
            Marker::Cross => area.draw(&Cross::new(c, s, self.color.stroke_width(2))),
            Marker::Square => {
                let h = square_half(s);
                area.draw(&Rectangle::new(
                    [(c.0 - h, c.1 - h), (c.0 + h, c.1 + h)],
                    fill,
                ))
            }
        }
        .map_err(msg)
    }
}
