//! Grids of x-y panels in one figure: [`write_panels`].

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::prelude::*;

use super::layout::headed;
use super::output::{msg, write_figure, DrawResult, Figure};
use super::style::Sizes;
use super::xy::XyPlot;
use super::xy_draw::{draw_xy, Ranges};
use crate::error::{GearError, Result};

/// Writes a grid of `panels` with `cols` columns under a common `title` (empty for none) to
/// `stem.png` and `stem.svg`; returns both paths.
///
/// Panels fill the grid row by row; each is 600 x 430 pixels with proportionally smaller text,
/// and has its own title, caption, ranges and legend. Fails if `cols` is 0 or `panels` is empty.
pub fn write_panels(
    title: &str,
    panels: &[XyPlot],
    cols: usize,
    stem: &Path,
) -> Result<Vec<PathBuf>> {
    if cols == 0 {
        return Err(GearError::param("cols", 0.0, "need at least one column"));
    }
    if panels.is_empty() {
        return Err(GearError::Unsupported(
            "write_panels: no panels to draw".into(),
        ));
    }
    let ranges = panels
        .iter()
        .map(XyPlot::resolved_ranges)
        .collect::<Result<Vec<_>>>()?;
    let cols = cols.min(panels.len());
    let panels: &[XyPlot] = &panels.iter().map(XyPlot::with_symbols).collect::<Vec<_>>();
    let title = &super::symbols(title);
    let fig = Grid {
        title,
        panels,
        ranges,
        cols,
        rows: panels.len().div_ceil(cols),
    };
    write_figure(&fig, stem)
}

/// Panel size in pixels and the text scale used inside panels.
const PANEL: (u32, u32) = (600, 430);
const PANEL_SCALE: f64 = 0.8;
const GRID_TITLE_H: u32 = 50;

struct Grid<'a> {
    title: &'a str,
    panels: &'a [XyPlot],
    ranges: Vec<Ranges>,
    cols: usize,
    rows: usize,
}

impl Figure for Grid<'_> {
    fn size(&self) -> (u32, u32) {
        let cols = u32::try_from(self.cols).unwrap_or(u32::MAX);
        let rows = u32::try_from(self.rows).unwrap_or(u32::MAX);
        (
            PANEL.0.saturating_mul(cols),
            PANEL
                .1
                .saturating_mul(rows)
                .saturating_add(if self.title.trim().is_empty() {
                    0
                } else {
                    GRID_TITLE_H
                }),
        )
    }
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>, raster: bool) -> DrawResult {
        root.fill(&WHITE).map_err(msg)?;
        let body = headed(
            &root.margin(6, 0, 0, 0),
            self.title,
            None,
            &Sizes::scaled(1.0),
        )?;
        let cells = body.split_evenly((self.rows, self.cols));
        let sz = Sizes::scaled(PANEL_SCALE);
        for ((cell, plot), ranges) in cells.iter().zip(self.panels).zip(&self.ranges) {
            draw_xy(&cell.margin(6, 6, 6, 6), plot, *ranges, &sz, raster)?;
        }
        Ok(())
    }
}
