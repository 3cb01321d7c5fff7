//! Drawing one [`XyPlot`] into an area: axes, bands, marked lines, series and legend.

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::axis::LinAxis;
use super::clip::{polylines, visible_points, View};
use super::glyph::{draw_markers, Chart, LegendSample};
use super::layout::{headed, MUTED};
use super::legend::{occupancy, Legend, Placement};
use super::output::{msg, DrawResult};
use super::overlap::{coincidence_notes, Drawn};
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

/// Colour of each series: its own palette index, or the next unused one in order.
fn colors(plot: &XyPlot) -> Vec<RGBColor> {
    let mut auto = 0;
    plot.series
        .iter()
        .map(|s| {
            palette_color(s.color.unwrap_or_else(|| {
                auto += 1;
                auto - 1
            }))
        })
        .collect()
}

fn visible(plot: &XyPlot, view: &View) -> Vec<Visible> {
    plot.series
        .iter()
        .zip(colors(plot))
        .map(|(s, color)| {
            let lines = match s.style {
                SeriesStyle::Markers => Vec::new(),
                _ => polylines(&s.points, view),
            };
            let dots = match s.style {
                SeriesStyle::Markers | SeriesStyle::LineMarkers => visible_points(&s.points, view),
                _ => Vec::new(),
            };
            Visible { color, lines, dots }
        })
        .collect()
}

/// Points of the series kept out of the automatic range that lie above or below the y range
/// (within the x range), per series.
fn beyond(plot: &XyPlot, view: &View) -> Vec<(usize, Vec<(f64, f64)>)> {
    plot.series
        .iter()
        .enumerate()
        .filter(|(_, s)| s.outside_range)
        .map(|(i, s)| {
            let pts: Vec<_> = s
                .finite_points()
                .filter(|p| p.0 >= view.x.0 && p.0 <= view.x.1)
                .filter(|p| p.1 > view.y.1 || p.1 < view.y.0)
                .collect();
            (i, pts)
        })
        .filter(|(_, p)| !p.is_empty())
        .collect()
}

/// Pixel sizes of the axis label areas and margins around the plotting area.
struct Frame {
    top: u32,
    right: u32,
    left: u32,
    x_labels: u32,
    y_labels: u32,
}

impl Frame {
    /// Plotting-area size inside an area of `(w, h)` pixels.
    fn inner(&self, (w, h): (u32, u32)) -> (u32, u32) {
        (
            w.saturating_sub(self.left + self.right + self.y_labels)
                .max(1),
            h.saturating_sub(self.top + self.x_labels).max(1),
        )
    }
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
    let axis_h = (sz.axis * 1.2) as u32;
    let frame = Frame {
        top: (sz.tick * 0.6) as u32 + 4,
        right: (sz.tick * 2.0) as u32,
        left: 4,
        x_labels: (sz.tick * 1.2) as u32 + axis_h + 16,
        y_labels: ay.widest_label(&area, &tick_style)? + axis_h + 18,
    };

    // The legend is measured and placed on the plot's expected size before the chart is built,
    // since a legend that fits nowhere inside takes a strip beside the plot.
    let guess = View {
        x: xr,
        y: yr,
        px: frame.inner((w, h)),
    };
    let legend = build_legend(&area, plot, &guess, (&ax, &ay), sz)?;
    let placement = legend.as_ref().map(|l| {
        let vis = visible(plot, &guess);
        let drawn = occupancy(
            vis.iter().flat_map(|v| &v.lines),
            vis.iter().flat_map(|v| &v.dots),
            &guess,
            2.0,
        );
        let mut drawn = drawn;
        drawn.extend(vline_label_cover(&area, plot, &guess, sz).unwrap_or_default());
        l.place(&drawn, &guess)
    });
    // Outside: a strip to the right of the plot (one column) or below it (as many columns as
    // the width holds), whichever leaves the larger plot (a strip may take at most half the
    // width or height).
    let wide = match (&legend, placement) {
        (Some(l), Some(Placement::Outside)) => Some(l.widened(&area, sz, w as i32 - 16)?),
        _ => None,
    };
    let below = legend.as_ref().zip(wide.as_ref()).is_some_and(|(l, wl)| {
        let (lw, lh) = (f64::from(l.size.0 + 12), f64::from(wl.size.1 + 8));
        let (w, h) = (f64::from(w), f64::from(h));
        let right = (w - lw.min(w / 2.0)) * h * if lw > w / 2.0 { 0.5 } else { 1.0 };
        let under = w * (h - lh.min(h / 2.0)) * if lh > h / 2.0 { 0.5 } else { 1.0 };
        under > right
    });
    let legend = if below { wide } else { legend };
    let (chart_area, side) = match (&legend, placement) {
        (Some(l), Some(Placement::Outside)) if below => {
            let strip = (l.size.1 + 8).min(h as i32 / 2);
            let (a, b) = area.split_vertically(h as i32 - strip);
            (a, Some(b))
        }
        (Some(l), Some(Placement::Outside)) => {
            let strip = (l.size.0 + 12).min(w as i32 / 2);
            let (a, b) = area.split_horizontally(w as i32 - strip);
            (a, Some(b))
        }
        _ => (area.clone(), None),
    };

    let mut chart = ChartBuilder::on(&chart_area)
        .margin_top(frame.top)
        .margin_right(if side.is_some() && !below {
            8
        } else {
            frame.right
        })
        .margin_left(frame.left)
        .x_label_area_size(frame.x_labels)
        .y_label_area_size(frame.y_labels)
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
    draw_vlines(&mut chart, plot, &view, sz)?;
    draw_series(&mut chart, plot, &view, sz, raster)?;

    match (legend, placement, side) {
        (Some(l), Some(Placement::Inside(fx, fy)), _) => {
            l.draw_inside(&chart.plotting_area().strip_coord_spec(), (fx, fy))
        }
        (Some(l), Some(Placement::Outside), Some(side)) if below => {
            let x0 = (side.dim_in_pixel().0 as i32 - l.size.0).max(0) / 2;
            l.draw_at(&side, (x0, 2))
        }
        (Some(l), Some(Placement::Outside), Some(side)) => l.draw_at(&side, (4, frame.top as i32)),
        _ => Ok(()),
    }
}

/// Lines, markers and the frame arrows of far points, series by series.
fn draw_series<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    plot: &XyPlot,
    view: &View,
    sz: &Sizes,
    raster: bool,
) -> DrawResult {
    let vis = visible(plot, view);
    for (s, v) in plot.series.iter().zip(&vis) {
        let st = v.color.stroke_width(sz.line);
        for line in v.lines.iter().filter(|l| l.len() >= 2) {
            draw_line(chart, line, s.style.dash(), st, raster)?;
        }
        // Isolated points of pure line styles would be invisible: mark them with a circle.
        let lone: Vec<_> = v
            .lines
            .iter()
            .filter(|l| l.len() == 1 && s.style != SeriesStyle::LineMarkers)
            .map(|l| l[0])
            .collect();
        draw_markers(chart, &lone, Marker::Circle, sz.marker, v.color, view)?;
        draw_markers(chart, &v.dots, s.marker, sz.marker, v.color, view)?;
    }
    // Far points of series kept out of the range: a small arrow on the frame at their x.
    let (_, py) = view.pixel();
    let len = f64::from(sz.marker * 3) * py;
    for (i, pts) in beyond(plot, view) {
        let color = vis[i].color.stroke_width(2);
        let arrows = pts.iter().map(|&(x, y)| {
            let (tip, tail) = if y > view.y.1 {
                (view.y.1, view.y.1 - len)
            } else {
                (view.y.0, view.y.0 + len)
            };
            PathElement::new(vec![(x, tail), (x, tip)], color)
        });
        chart.draw_series(arrows).map_err(msg)?;
    }
    Ok(())
}

/// The legend of `plot` (labelled series, then notes on coinciding lines and on far points), or
/// `None` when it is switched off or empty.
fn build_legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    plot: &XyPlot,
    view: &View,
    (ax, ay): (&LinAxis, &LinAxis),
    sz: &Sizes,
) -> Result<Option<Legend>, String> {
    if !plot.legend {
        return Ok(None);
    }
    let vis = visible(plot, view);
    // A listed series with nothing on the canvas says so, rather than look hidden.
    let labels: Vec<String> = plot
        .series
        .iter()
        .zip(&vis)
        .map(|(s, v)| {
            let beyond = s.outside_range && !s.points.is_empty();
            if v.lines.is_empty() && v.dots.is_empty() && !beyond {
                format!("{}: none", s.label)
            } else {
                s.label.clone()
            }
        })
        .collect();
    let entries: Vec<_> = plot
        .series
        .iter()
        .zip(colors(plot))
        .zip(&labels)
        .filter(|((s, _), _)| !s.label.is_empty())
        .map(|((s, color), label)| {
            let sample = LegendSample {
                width: (sz.legend * 2.2) as i32,
                style: s.style,
                marker: s.marker,
                size: sz.marker,
                line: sz.line,
                color,
            };
            (label.clone(), sample)
        })
        .collect();
    let drawn: Vec<Drawn> = plot
        .series
        .iter()
        .zip(&vis)
        .filter(|(s, _)| !s.label.is_empty())
        .map(|(s, v)| Drawn {
            label: &s.label,
            lines: &v.lines,
            dots: &v.dots,
        })
        .collect();
    let mut notes = coincidence_notes(
        &drawn,
        view,
        |x| ax.format_between(x),
        label_unit(&plot.x_label),
    );
    for (i, pts) in beyond(plot, view) {
        let above = pts.iter().filter(|p| p.1 > view.y.1).count();
        let below = pts.len() - above;
        let mid = 0.5 * (view.y.0 + view.y.1);
        let far = pts
            .iter()
            .map(|p| p.1)
            .max_by(|a, b| (a - mid).abs().total_cmp(&(b - mid).abs()))
            .unwrap_or(mid);
        let where_ = match (above, below) {
            (_, 0) => format!("{above} above the plot"),
            (0, _) => format!("{below} below the plot"),
            _ => format!("{above} above and {below} below the plot"),
        };
        notes.push(format!(
            "{}: {where_} (arrows on the frame; farthest at {})",
            plot.series[i].label,
            ay.format_between(far)
        ));
    }
    let legend = Legend::measure(area, entries, &notes, sz)?;
    Ok((!legend.is_empty()).then_some(legend))
}

/// Draws one polyline, solid or broken into `dash` (dash, gap) pixels. The bitmap backend fills
/// a wide polyline as a single polygon, which leaves holes where the line crosses itself
/// (phase-plane orbits), so on rasters solid lines go segment by segment; vector output keeps
/// one path per polyline.
fn draw_line<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    line: &[(f64, f64)],
    dash: Option<(u32, u32)>,
    st: ShapeStyle,
    raster: bool,
) -> DrawResult {
    let pts = line.iter().copied();
    match (dash, raster) {
        (Some((d, g)), _) => chart.draw_series(DashedLineSeries::new(pts, d, g, st)),
        (None, true) => {
            let segs = line
                .windows(2)
                .map(|w| PathElement::new(vec![w[0], w[1]], st));
            chart.draw_series(segs)
        }
        (None, false) => chart.draw_series(LineSeries::new(pts, st)),
    }
    .map(|_| ())
    .map_err(msg)
}

/// Where a marked line's label goes: its text style, pixel offset from the top of the line,
/// and size.
struct VLabel<'a> {
    x: f64,
    text: &'a str,
    style: TextStyle<'static>,
    offset: (i32, i32),
    size: (u32, u32),
    right_side: bool,
}

/// Labels of the marked lines inside the x range, near the top, alternating between two rows.
fn vline_labels<'a, DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    plot: &'a XyPlot,
    view: &View,
    sz: &Sizes,
) -> Result<Vec<VLabel<'a>>, String> {
    let (x0, x1) = view.x;
    let row_h = (sz.legend * 1.2) as i32;
    let mut out = Vec::new();
    let lines = plot
        .vlines
        .iter()
        .filter(|(x, _)| x.is_finite() && *x >= x0 && *x <= x1);
    let mut sorted: Vec<&(f64, String)> = lines.filter(|(_, l)| !l.is_empty()).collect();
    sorted.sort_by(|a, b| a.0.total_cmp(&b.0));
    // Pixel extents of the labels in each row so far: a label goes to the first row where it
    // clears the last one by 4 pixels (the least crowded row when none does).
    let mut row_ends: Vec<f64> = Vec::new();
    let px_per_x = f64::from(view.px.0) / (x1 - x0);
    for (x, label) in sorted {
        let right_side = (x - x0) / (x1 - x0) > 0.85;
        let hpos = if right_side { HPos::Right } else { HPos::Left };
        let style = TextStyle::from((FONT, sz.legend * 0.9).into_font())
            .color(&MUTED)
            .pos(Pos::new(hpos, VPos::Top));
        let size = area.estimate_text_size(label, &style).map_err(msg)?;
        let at = (x - x0) * px_per_x;
        let (left, right) = if right_side {
            (at - 4.0 - f64::from(size.0), at - 4.0)
        } else {
            (at + 4.0, at + 4.0 + f64::from(size.0))
        };
        let row = match row_ends.iter().position(|&end| left > end + 4.0) {
            Some(r) => r,
            None if row_ends.len() < MAX_VLINE_ROWS => {
                row_ends.push(f64::NEG_INFINITY);
                row_ends.len() - 1
            }
            None => (0..row_ends.len())
                .min_by(|&a, &b| row_ends[a].total_cmp(&row_ends[b]))
                .unwrap_or(0),
        };
        row_ends[row] = row_ends[row].max(right);
        out.push(VLabel {
            x: *x,
            text: label,
            style,
            offset: (if right_side { -4 } else { 4 }, 4 + row as i32 * row_h),
            size,
            right_side,
        });
    }
    Ok(out)
}

/// Rows of marked-line labels stacked at the top of a plot before labels may overlap.
const MAX_VLINE_ROWS: usize = 4;

/// Data points covering the marked lines' labels, so the legend can avoid them.
fn vline_label_cover<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    plot: &XyPlot,
    view: &View,
    sz: &Sizes,
) -> Result<Vec<(f64, f64)>, String> {
    let (px, py) = view.pixel();
    let mut covered = Vec::new();
    for l in vline_labels(area, plot, view, sz)? {
        let sign = if l.right_side { -1.0 } else { 1.0 };
        for i in 0..=8 {
            for j in 0..=2 {
                let u = f64::from(l.offset.0) + sign * f64::from(l.size.0) * f64::from(i) / 8.0;
                let v = f64::from(l.offset.1) + f64::from(l.size.1) * f64::from(j) / 2.0;
                covered.push((l.x + u * px, view.y.1 - v * py));
            }
        }
    }
    Ok(covered)
}

/// Dashed grey vertical lines with their labels near the top.
fn draw_vlines<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    plot: &XyPlot,
    view: &View,
    sz: &Sizes,
) -> DrawResult {
    let ((x0, x1), (y0, y1)) = (view.x, view.y);
    let st = MUTED.stroke_width(1);
    let xs = plot
        .vlines
        .iter()
        .filter(|(x, _)| x.is_finite() && *x >= x0 && *x <= x1);
    for (x, _) in xs {
        chart
            .draw_series(DashedLineSeries::new([(*x, y0), (*x, y1)], 6, 4, st))
            .map_err(msg)?;
    }
    let area = chart.plotting_area().strip_coord_spec();
    for l in vline_labels(&area, plot, view, sz)? {
        let text = EmptyElement::at((l.x, y1)) + Text::new(l.text.to_string(), l.offset, l.style);
        chart.draw_series(std::iter::once(text)).map_err(msg)?;
    }
    Ok(())
}

/// The unit an axis label states in its closing parentheses ("speed (rpm)" gives "rpm"), for
/// the values a note quotes from that axis.
fn label_unit(label: &str) -> Option<&str> {
    let inner = label.trim_end().strip_suffix(')')?;
    let (_, unit) = inner.rsplit_once('(')?;
    let unit = unit.trim();
    (!unit.is_empty() && unit != "dimensionless").then_some(unit)
}

#[cfg(test)]
mod unit_tests {
    use super::label_unit;

    #[test]
    fn a_label_states_its_unit_in_parentheses() {
        assert_eq!(label_unit("speed (rpm)"), Some("rpm"));
        assert_eq!(label_unit("pp DTE (µm) "), Some("µm"));
        assert_eq!(label_unit("Ω"), None);
        assert_eq!(label_unit("()"), None);
    }
}
