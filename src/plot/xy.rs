//! x-y figures: the [`XyPlot`] description and the single-figure writer [`write_xy`].

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::prelude::*;

use super::output::{msg, write_figure, DrawResult, Figure};
use super::range::{finite_extent, resolve};
use super::series::Series;
use super::style::Sizes;
use super::xy_draw::{draw_xy, Ranges};
use crate::error::Result;

/// An x-y figure: series of points with axis labels, optional fixed ranges, marked vertical lines
/// and shaded x-intervals.
#[derive(Debug, Clone, PartialEq)]
pub struct XyPlot {
    /// Figure title (empty for none).
    pub title: String,
    /// Optional small second line under the title, e.g. the parameters of the run.
    pub caption: Option<String>,
    /// Label of the x axis.
    pub x_label: String,
    /// Label of the y axis.
    pub y_label: String,
    /// Data sets, drawn in order (later ones on top).
    pub series: Vec<Series>,
    /// Fixed x range; `None` fits the finite data with 5 % padding.
    pub x_range: Option<(f64, f64)>,
    /// Fixed y range; `None` fits the finite data (inside a fixed x range) with 5 % padding.
    pub y_range: Option<(f64, f64)>,
    /// Marked vertical lines at x with a label, e.g. the edges of an Omega = 1/2 window.
    pub vlines: Vec<(f64, String)>,
    /// Shaded x-intervals (lo, hi).
    pub bands: Vec<(f64, f64)>,
    /// Whether to draw a legend of the labelled series.
    pub legend: bool,
}

impl Default for XyPlot {
    fn default() -> Self {
        XyPlot {
            title: String::new(),
            caption: None,
            x_label: String::new(),
            y_label: String::new(),
            series: Vec::new(),
            x_range: None,
            y_range: None,
            vlines: Vec::new(),
            bands: Vec::new(),
            legend: true,
        }
    }
}

impl XyPlot {
    /// An empty plot with a title and axis labels; legend on, automatic ranges.
    pub fn new(
        title: impl Into<String>,
        x_label: impl Into<String>,
        y_label: impl Into<String>,
    ) -> Self {
        XyPlot {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            ..Self::default()
        }
    }

    /// Adds a series.
    pub fn with_series(mut self, s: Series) -> Self {
        self.series.push(s);
        self
    }

    /// Sets the caption line.
    pub fn with_caption(mut self, caption: impl Into<String>) -> Self {
        self.caption = Some(caption.into());
        self
    }

    /// Fixes the x range.
    pub fn with_x_range(mut self, lo: f64, hi: f64) -> Self {
        self.x_range = Some((lo, hi));
        self
    }

    /// Fixes the y range.
    pub fn with_y_range(mut self, lo: f64, hi: f64) -> Self {
        self.y_range = Some((lo, hi));
        self
    }

    /// Adds a marked vertical line.
    pub fn with_vline(mut self, x: f64, label: impl Into<String>) -> Self {
        self.vlines.push((x, label.into()));
        self
    }

    /// Adds a shaded x-interval.
    pub fn with_band(mut self, lo: f64, hi: f64) -> Self {
        self.bands.push((lo, hi));
        self
    }

    /// The plot with the paper's symbols in every text (see [`symbols`](super::symbols)).
    pub(crate) fn with_symbols(&self) -> XyPlot {
        let mut p = self.clone();
        p.title = super::symbols(&p.title);
        p.caption = p.caption.as_deref().map(super::symbols);
        p.x_label = super::symbols(&p.x_label);
        p.y_label = super::symbols(&p.y_label);
        for s in &mut p.series {
            s.label = super::symbols(&s.label);
        }
        for v in &mut p.vlines {
            v.1 = super::symbols(&v.1);
        }
        p
    }

    /// Axis ranges actually drawn: fixed ranges validated, the others fitted to finite data.
    pub fn resolved_ranges(&self) -> Result<((f64, f64), (f64, f64))> {
        let inside = |v: f64, r: Option<(f64, f64)>| r.is_none_or(|(lo, hi)| v >= lo && v <= hi);
        let pts = || {
            self.series
                .iter()
                .filter(|s| !s.outside_range)
                .flat_map(Series::finite_points)
        };
        let xs = pts().filter(|p| inside(p.1, self.y_range)).map(|p| p.0);
        let x = resolve("x_range", self.x_range, finite_extent(xs))?;
        let ys = pts().filter(|p| inside(p.0, self.x_range)).map(|p| p.1);
        let y = resolve("y_range", self.y_range, finite_extent(ys))?;
        Ok((x, y))
    }
}

/// Writes `plot` to `stem.png` (1000 x 700) and `stem.svg`, with the paper's symbols in its
/// text; returns both paths.
pub fn write_xy(plot: &XyPlot, stem: &Path) -> Result<Vec<PathBuf>> {
    let ranges = plot.resolved_ranges()?;
    let plot = &plot.with_symbols();
    write_figure(&Single { plot, ranges }, stem)
}

struct Single<'a> {
    plot: &'a XyPlot,
    ranges: Ranges,
}

impl Figure for Single<'_> {
    fn size(&self) -> (u32, u32) {
        (1000, 700)
    }
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>, raster: bool) -> DrawResult {
        root.fill(&WHITE).map_err(msg)?;
        let sz = Sizes::scaled(1.0);
        draw_xy(
            &root.margin(8, 8, 8, 8),
            self.plot,
            self.ranges,
            &sz,
            raster,
        )
    }
}
