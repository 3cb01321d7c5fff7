//! Drawing one [`XyPlot`] into an area: axes, bands, marked lines, series and legend.

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::axis::LinAxis;
use super::clip::{polylines, visible_points, View};
use super::glyph::{draw_markers, Chart, LegendSample};
use super::layout::{headed, MUTED};
use super::legend::{draw_legend, occupancy};
use super::output::{msg, DrawResult};
use super::style::{palette_color, Marker, SeriesStyle, Sizes, FONT};
use super::xy::XyPlot;

/// Resolved (x, y) axis ranges.
pub(crate) type Ranges = ((f64, f64), (f64, f64));

/// What one series puts on the canvas after clipping and thinning.
struct Visible {
    color: RGBColor,
    lines: Vec<Vec<(f64, f64)>>,
    dots: Vec<(f64, f64)>,
}

fn visible(plot: &XyPlot, view: &View) -> Vec<Visible> {
    let mut auto = 0;
    plot.series
        .iter()
        .map(|s| {
            let ci = s.color.unwrap_or_else(|| {
                auto += 1;
                auto - 1
            });
            let lines = match s.style {
                SeriesStyle::Markers => Vec::new(),
                _ => polylines(&s.points, view),
            };
            let dots = match s.style {
                SeriesStyle::Markers | SeriesStyle::LineMarkers => visible_points(&s.points, view),
                _ => Vec::new(),
            };
            Visible {
                color: palette_color(ci),
                lines,
                dots,
            }
        })
        .collect()
}

/// Draws one x-y plot (title block, axes, bands, marked lines, series, legend) into `area`.
pub(crate) fn draw_xy<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    plot: &XyPlot,
    (xr, yr): Ranges,
    sz: &Sizes,
    raster: bool,
) -> DrawResult {
    let area = headed(area, &plot.title, plot.caption.as_deref(), sz)?;
    let (w, h) = area.dim_in_pixel();
    let nx = ((w / 110) as usize).clamp(3, 10);
    let ny = ((h / 70) as usize).clamp(3, 10);
    let (ax, ay) = (LinAxis::new(xr, nx), LinAxis::new(yr, ny));
    let tick_style = TextStyle::from((FONT, sz.tick).into_font());
    let widest_y = ay.widest_label(&area, &tick_style)?;
    let axis_h = (sz.axis * 1.2) as u32;
    let tick_h = (sz.tick * 1.2) as u32;

    let mut chart = ChartBuilder::on(&area)
        .margin_top((sz.tick * 0.6) as u32 + 4)
        .margin_right((sz.tick * 2.0) as u32)
        .margin_left(4)
        .x_label_area_size(tick_h + axis_h + 16)
        .y_label_area_size(widest_y + axis_h + 18)
        .build_cartesian_2d(ax, ay)
        .map_err(msg)?;

    let band = RGBColor(0x80, 0x80, 0x80).mix(0.18).filled();
    let bands = plot.bands.iter().filter_map(|&(a, b)| {
        let (a, b) = (a.min(b).max(xr.0), a.max(b).min(xr.1));
        (a < b).then(|| Rectangle::new([(a, yr.0), (b, yr.1)], band))
    });
    chart.draw_series(bands).map_err(msg)?;

    chart
        .configure_mesh()
        .x_desc(plot.x_label.as_str())
        .y_desc(plot.y_label.as_str())
        .label_style(tick_style.clone())
        .axis_desc_style((FONT, sz.axis))
        .bold_line_style(RGBColor(0xDD, 0xDD, 0xDD).stroke_width(1))
        .light_line_style(TRANSPARENT)
        .axis_style(RGBColor(0x40, 0x40, 0x40).stroke_width(1))
        .x_labels(nx)
        .y_labels(ny)
        .draw()
        .map_err(msg)?;

    let view = View {
        x: xr,
        y: yr,
        px: chart.plotting_area().dim_in_pixel(),
    };
    let labels = draw_vlines(&mut chart, plot, &view, sz)?;
    let vis = visible(plot, &view);
    for (s, v) in plot.series.iter().zip(&vis) {
        let st = v.color.stroke_width(sz.line);
        for line in v.lines.iter().filter(|l| l.len() >= 2) {
            draw_line(&mut chart, line, s.style == SeriesStyle::Dashed, st, raster)?;
        }
        // Isolated points of pure line styles would be invisible: mark them with a circle.
        let lone: Vec<_> = v
            .lines
            .iter()
            .filter(|l| l.len() == 1 && s.style != SeriesStyle::LineMarkers)
            .map(|l| l[0])
            .collect();
        draw_markers(&mut chart, &lone, Marker::Circle, sz.marker, v.color, &view)?;
        draw_markers(&mut chart, &v.dots, s.marker, sz.marker, v.color, &view)?;
    }

    if !plot.legend {
        return Ok(());
    }
    let entries: Vec<_> = plot
        .series
        .iter()
        .zip(&vis)
        .filter(|(s, _)| !s.label.is_empty())
        .map(|(s, v)| {
            let sample = LegendSample {
                width: (sz.legend * 2.2) as i32,
                style: s.style,
                marker: s.marker,
                size: sz.marker,
                line: sz.line,
                color: v.color,
            };
            (s.label.as_str(), sample)
        })
        .collect();
    let drawn = occupancy(
        vis.iter().flat_map(|v| &v.lines),
        vis.iter().flat_map(|v| &v.dots).chain(&labels),
    );
    let area = chart.plotting_area().strip_coord_spec();
    draw_legend(&area, &entries, &drawn, &view, sz)
}

/// Draws one polyline. The bitmap backend fills a wide polyline as a single polygon, which
/// leaves holes where the line crosses itself (phase-plane orbits), so on rasters solid lines go
/// segment by segment; vector output keeps one path per polyline.
fn draw_line<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    line: &[(f64, f64)],
    dashed: bool,
    st: ShapeStyle,
    raster: bool,
) -> DrawResult {
    let pts = line.iter().copied();
    match (dashed, raster) {
        (true, _) => chart.draw_series(DashedLineSeries::new(pts, 9, 6, st)),
        (false, true) => {
            let segs = line
                .windows(2)
                .map(|w| PathElement::new(vec![w[0], w[1]], st));
            chart.draw_series(segs)
        }
        (false, false) => chart.draw_series(LineSeries::new(pts, st)),
    }
    .map(|_| ())
    .map_err(msg)
}

/// Dashed grey vertical lines with their labels near the top, alternating between two rows.
/// Returns points covering the labels, so the legend can avoid them.
fn draw_vlines<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    plot: &XyPlot,
    view: &View,
    sz: &Sizes,
) -> Result<Vec<(f64, f64)>, String> {
    let ((x0, x1), (y0, y1)) = (view.x, view.y);
    let (px, py) = view.pixel();
    let st = MUTED.stroke_width(1);
    let lines = plot
        .vlines
        .iter()
        .filter(|(x, _)| x.is_finite() && *x >= x0 && *x <= x1);
    let row_h = (sz.legend * 1.2) as i32;
    let mut covered = Vec::new();
    for (k, (x, label)) in lines.enumerate() {
        chart
            .draw_series(DashedLineSeries::new([(*x, y0), (*x, y1)], 6, 4, st))
            .map_err(msg)?;
        if label.is_empty() {
            continue;
        }
        let right_side = (x - x0) / (x1 - x0) > 0.85;
        let hpos = if right_side { HPos::Right } else { HPos::Left };
        let style = TextStyle::from((FONT, sz.legend * 0.9).into_font())
            .color(&MUTED)
            .pos(Pos::new(hpos, VPos::Top));
        let dx = if right_side { -4 } else { 4 };
        let dy = 4 + (k as i32 % 2) * row_h;
        let (w, h) = chart
            .plotting_area()
            .estimate_text_size(label, &style)
            .map_err(msg)?;
        let text = EmptyElement::at((*x, y1)) + Text::new(label.clone(), (dx, dy), style);
        chart.draw_series(std::iter::once(text)).map_err(msg)?;
        let sign = if right_side { -1.0 } else { 1.0 };
        for i in 0..=4 {
            for j in 0..=1 {
                let u = f64::from(dx) + sign * f64::from(w) * f64::from(i) / 4.0;
                let v = f64::from(dy) + f64::from(h) * f64::from(j);
                covered.push((x + u * px, y1 - v * py));
            }
        }
    }
    Ok(covered)
}
