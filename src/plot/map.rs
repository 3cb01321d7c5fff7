//! Category maps on a regular grid, e.g. basins of attraction: one coloured cell per initial
//! condition, coloured by the attractor it reaches, with a legend beside the map.

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::axis::LinAxis;
use super::layout::headed;
use super::output::{msg, write_figure, DrawResult, Figure};
use super::range::resolve;
use super::style::{palette_color, Sizes, FONT};
use crate::error::{GearError, Result};

/// Colour of unclassified (`None`) cells: a mid grey, 3.2:1 on white like the palette.
pub(crate) const UNCLASSIFIED: RGBColor = RGBColor(0x90, 0x90, 0x90);

/// A grid of cells, each belonging to a category (or none), drawn as a coloured map.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct CategoryMap {
    /// Figure title (empty for none).
    pub title: String,
    /// Optional small second line under the title.
    pub caption: Option<String>,
    /// Label of the x axis.
    pub x_label: String,
    /// Label of the y axis.
    pub y_label: String,
    /// Cell centres along x: (first, last, count), evenly spaced.
    pub x: (f64, f64, usize),
    /// Cell centres along y: (first, last, count), evenly spaced.
    pub y: (f64, f64, usize),
    /// Category per cell, row-major: y index outer (row 0 = lowest y), x index inner.
    /// `None` marks an unclassified cell.
    pub cells: Vec<Option<usize>>,
    /// Legend label per category index; indices without a label are shown as "category k".
    pub legend: Vec<String>,
}

/// Writes `map` to `stem.png` (760 pixels high, as wide as its equal-aspect map needs) and
/// `stem.svg`; returns both paths.
///
/// Fails if `cells.len()` differs from `x.2 * y.2` or an axis is malformed.
pub fn write_category_map(map: &CategoryMap, stem: &Path) -> Result<Vec<PathBuf>> {
    let xe = cell_edges("x", map.x)?;
    let ye = cell_edges("y", map.y)?;
    let expected = map.x.2.checked_mul(map.y.2);
    if expected != Some(map.cells.len()) {
        return Err(GearError::param(
            "cells",
            map.cells.len() as f64,
            "number of cells must equal x count times y count",
        ));
    }
    let map = &CategoryMap {
        title: super::symbols(&map.title),
        caption: map.caption.as_deref().map(super::symbols),
        x_label: super::symbols(&map.x_label),
        y_label: super::symbols(&map.y_label),
        legend: map.legend.iter().map(|l| super::symbols(l)).collect(),
        ..map.clone()
    };
    write_figure(&MapFigure { map, xe, ye }, stem)
}

/// The `n + 1` cell edges of an axis with `n` evenly spaced cell centres from `lo` to `hi`.
fn cell_edges(name: &'static str, (lo, hi, n): (f64, f64, usize)) -> Result<Vec<f64>> {
    if n == 0 {
        return Err(GearError::param(name, 0.0, "need at least one cell"));
    }
    if n == 1 {
        let (a, b) = resolve(name, Some((lo, hi)), None)?;
        return Ok(vec![a, b]);
    }
    let (a, b) = resolve(name, Some((lo, hi)), None)?;
    if lo == hi {
        return Err(GearError::param(
            name,
            lo,
            "several cells need first < last",
        ));
    }
    let d = (b - a) / (n - 1) as f64;
    Ok((0..=n).map(|i| a - 0.5 * d + i as f64 * d).collect())
}

struct MapFigure<'a> {
    map: &'a CategoryMap,
    xe: Vec<f64>,
    ye: Vec<f64>,
}

impl MapFigure<'_> {
    /// Legend entries: every labelled or used category, then "unclassified" if present.
    fn entries(&self) -> Vec<(String, RGBColor)> {
        let used = self.map.cells.iter().flatten().max().map_or(0, |m| m + 1);
        let mut out: Vec<_> = (0..used.max(self.map.legend.len()))
            .map(|k| {
                let label = self.map.legend.get(k).cloned();
                (
                    label.unwrap_or_else(|| format!("category {k}")),
                    palette_color(k),
                )
            })
            .collect();
        if self.map.cells.iter().any(Option::is_none) {
            out.push(("unclassified".to_string(), UNCLASSIFIED));
        }
        out
    }
}

/// Height of a map figure in pixels; its width follows from the map's aspect (see
/// [`MapFigure::aspect`]) so that little of the canvas is left empty.
const MAP_HEIGHT: u32 = 760;
/// Pixels of a map figure outside the map itself: title block and x-axis labels (vertical),
/// y-axis labels and margins (horizontal), as laid out in `draw`.
const MAP_CHROME: (u32, u32) = (150, 130);

impl MapFigure<'_> {
    /// Width over height of the map's plotting area: equal scales on both axes (one unit of x as
    /// long as one of y, so a square domain is drawn square), kept between 1:3 and 3:1.
    fn aspect(&self) -> f64 {
        let (n, m) = (self.map.x.2, self.map.y.2);
        let (sx, sy) = (self.xe[n] - self.xe[0], self.ye[m] - self.ye[0]);
        (sx / sy).clamp(1.0 / 3.0, 3.0)
    }

    /// Width of the legend column for the entries' longest label (an estimate from the font's
    /// advance widths, as the drawing measures it).
    fn legend_width(&self, sz: &Sizes) -> u32 {
        let font = (FONT, sz.legend).into_font();
        let text_w = self
            .entries()
            .iter()
            .filter_map(|(label, _)| font.box_size(label).ok())
            .map(|b| b.0)
            .max()
            .unwrap_or(0);
        (text_w + (sz.legend * 1.1) as u32 + 40).clamp(140, 420)
    }
}

impl Figure for MapFigure<'_> {
    fn size(&self) -> (u32, u32) {
        let inner_h = f64::from(MAP_HEIGHT - MAP_CHROME.0);
        let inner_w = (inner_h * self.aspect()).round() as u32;
        let legend = self.legend_width(&Sizes::scaled(1.0));
        (
            (inner_w + MAP_CHROME.1 + legend).clamp(640, 2400),
            MAP_HEIGHT,
        )
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>, _: bool) -> DrawResult {
        let map = self.map;
        let sz = Sizes::scaled(1.0);
        root.fill(&WHITE).map_err(msg)?;
        let body = headed(
            &root.margin(8, 8, 8, 8),
            &map.title,
            map.caption.as_deref(),
            &sz,
        )?;

        let entries = self.entries();
        let font = TextStyle::from((FONT, sz.legend).into_font());
        let swatch = (sz.legend * 1.1) as i32;
        let legend_w = self.legend_width(&sz) as i32;
        let (plot_area, legend_area) =
            body.split_horizontally(body.dim_in_pixel().0 as i32 - legend_w);

        let (n, m) = (map.x.2, map.y.2);
        let xr = (self.xe[0], self.xe[n]);
        let yr = (self.ye[0], self.ye[m]);
        let (ax, ay) = (LinAxis::new(xr, 10), LinAxis::new(yr, 10));
        let tick_style = TextStyle::from((FONT, sz.tick).into_font());
        let widest_y = ay.widest_label(&plot_area, &tick_style)?;
        let x_labels = (sz.tick * 1.2 + sz.axis * 1.2 + 16.0) as u32;
        let y_labels = widest_y + (sz.axis * 1.2) as u32 + 18;
        let margin_right = (sz.tick * 1.2) as u32;
        // Equal aspect: the spare width (or height) of the area goes to the right (or bottom)
        // margin, so the map's cells are as long as they are high in data units.
        let (aw, ah) = plot_area.dim_in_pixel();
        let free_w = f64::from(aw.saturating_sub(y_labels + margin_right).max(1));
        let free_h = f64::from(ah.saturating_sub(x_labels + 10).max(1));
        let a = self.aspect();
        let (extra_w, extra_h) = if free_w / free_h > a {
            ((free_w - free_h * a).round() as u32, 0)
        } else {
            (0, (free_h - free_w / a).round() as u32)
        };
        let margin_top: i32 = 10;
        let mut chart = ChartBuilder::on(&plot_area)
            .margin_top(margin_top as u32)
            .margin_right(margin_right + extra_w)
            .margin_bottom(extra_h)
            .x_label_area_size(x_labels)
            .y_label_area_size(y_labels)
            .build_cartesian_2d(ax, ay)
            .map_err(msg)?;

        let rects = (0..m).flat_map(|j| {
            let row = &map.cells[j * n..(j + 1) * n];
            runs(row).map(move |(i0, i1, c)| {
                let color = c.map_or(UNCLASSIFIED, palette_color);
                Rectangle::new(
                    [(self.xe[i0], self.ye[j]), (self.xe[i1], self.ye[j + 1])],
                    color.filled(),
                )
            })
        });
        chart.draw_series(rects).map_err(msg)?;

        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc(map.x_label.as_str())
            .y_desc(map.y_label.as_str())
            .label_style(tick_style)
            .axis_desc_style((FONT, sz.axis))
            .x_labels(10)
            .y_labels(10)
            .draw()
            .map_err(msg)?;
        let frame = RGBColor(0x40, 0x40, 0x40).stroke_width(1);
        chart
            .draw_series(std::iter::once(Rectangle::new(
                [(xr.0, yr.0), (xr.1, yr.1)],
                frame,
            )))
            .map_err(msg)?;

        let row_h = (sz.legend * 1.6) as i32;
        let line_h = (sz.legend * 1.25) as i32;
        let text = font.pos(Pos::new(HPos::Left, VPos::Center));
        // A label wider than the legend column (at most 420 px) continues on further lines.
        let text_w = (legend_w - 28 - swatch).max(40) as u32;
        let mut y = margin_top;
        for (label, color) in &entries {
            let lines = super::layout::wrap(&legend_area, label, sz.legend, text_w)?;
            let corners = [(12, y), (12 + swatch, y + swatch)];
            legend_area
                .draw(&Rectangle::new(corners, color.filled()))
                .map_err(msg)?;
            legend_area
                .draw(&Rectangle::new(
                    corners,
                    RGBColor(0x60, 0x60, 0x60).stroke_width(1),
                ))
                .map_err(msg)?;
            for (i, line) in lines.iter().enumerate() {
                legend_area
                    .draw_text(
                        line,
                        &text,
                        (20 + swatch, y + swatch / 2 + i as i32 * line_h),
                    )
                    .map_err(msg)?;
            }
            y += row_h + (lines.len() as i32 - 1) * line_h;
        }
        Ok(())
    }
}

/// Maximal runs of equal cells in a row: (first index, one past last index, category).
fn runs(row: &[Option<usize>]) -> impl Iterator<Item = (usize, usize, Option<usize>)> + '_ {
    let mut start = 0;
    std::iter::from_fn(move || {
        let first = *row.get(start)?;
        let len = row[start..].iter().take_while(|&&c| c == first).count();
        let run = (start, start + len, first);
        start += len;
        Some(run)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn runs_merge_equal_neighbours() {
        let row = [Some(1), Some(1), None, Some(0), Some(0), Some(0)];
        let r: Vec<_> = runs(&row).collect();
        assert_eq!(r, vec![(0, 2, Some(1)), (2, 3, None), (3, 6, Some(0))]);
        assert_eq!(runs(&[]).count(), 0);
    }

    #[test]
    fn edges_surround_cell_centres() {
        let e = cell_edges("x", (0.0, 1.0, 3)).unwrap();
        assert_eq!(e, vec![-0.25, 0.25, 0.75, 1.25]);
        assert_eq!(cell_edges("x", (2.0, 3.0, 1)).unwrap(), vec![2.0, 3.0]);
        assert!(cell_edges("x", (2.0, 2.0, 1)).is_ok());
        assert!(cell_edges("x", (2.0, 2.0, 3)).is_err());
        assert!(cell_edges("x", (0.0, 1.0, 0)).is_err());
        assert!(cell_edges("x", (f64::NAN, 1.0, 4)).is_err());
    }
}
