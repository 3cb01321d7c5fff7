//! Legend box of x-y plots, placed in the corner of the plot where it hides the least data.

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::clip::View;
use super::glyph::LegendSample;
use super::output::{msg, DrawResult};
use super::style::{Sizes, FONT};

/// Gap between the legend box and the plot frame, and inner padding of the box, in pixels.
const INSET: i32 = 6;
const PAD: i32 = 8;

/// Draws a legend of `entries` on `area` (the plotting area, pixel coordinates), in the corner
/// where it covers the fewest points of `drawn` (data coordinates within `view`).
pub(crate) fn draw_legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    entries: &[(&str, LegendSample)],
    drawn: &[(f64, f64)],
    view: &View,
    sz: &Sizes,
) -> DrawResult {
    if entries.is_empty() {
        return Ok(());
    }
    let font = TextStyle::from((FONT, sz.legend).into_font());
    let mut text_w = 0;
    for (label, _) in entries {
        text_w = text_w.max(area.estimate_text_size(label, &font).map_err(msg)?.0 as i32);
    }
    let glyph_w = entries[0].1.width;
    let row_h = (sz.legend * 1.35) as i32;
    let size = (
        2 * PAD + glyph_w + 8 + text_w,
        2 * PAD + row_h * entries.len() as i32,
    );
    let (aw, ah) = area.dim_in_pixel();
    let (right, upper) = best_corner(drawn, view, size);
    let x0 = if right {
        aw as i32 - size.0 - INSET
    } else {
        INSET
    };
    let y0 = if upper {
        INSET
    } else {
        ah as i32 - size.1 - INSET
    };
    let corners = [(x0, y0), (x0 + size.0, y0 + size.1)];
    area.draw(&Rectangle::new(corners, WHITE.mix(0.88).filled()))
        .map_err(msg)?;
    area.draw(&Rectangle::new(
        corners,
        RGBColor(0xA0, 0xA0, 0xA0).stroke_width(1),
    ))
    .map_err(msg)?;
    let text = font.pos(Pos::new(HPos::Left, VPos::Center));
    for (k, (label, sample)) in entries.iter().enumerate() {
        let y = y0 + PAD + row_h * k as i32 + row_h / 2;
        sample.draw(area, (x0 + PAD, y))?;
        area.draw_text(label, &text, (x0 + PAD + glyph_w + 8, y))
            .map_err(msg)?;
    }
    Ok(())
}

/// (right, upper) of the corner whose legend-sized box holds the fewest of `pts`; ties go to
/// upper right, upper left, lower right, lower left in that order.
fn best_corner(pts: &[(f64, f64)], view: &View, size: (i32, i32)) -> (bool, bool) {
    let fx = (f64::from(size.0 + INSET) / f64::from(view.px.0.max(1))).min(1.0);
    let fy = (f64::from(size.1 + INSET) / f64::from(view.px.1.max(1))).min(1.0);
    let (xs, ys) = (view.x.1 - view.x.0, view.y.1 - view.y.0);
    let near = |u: f64, high: bool, f: f64| if high { u >= 1.0 - f } else { u <= f };
    let count = |right: bool, upper: bool| {
        pts.iter()
            .filter(|p| {
                near((p.0 - view.x.0) / xs, right, fx) && near((p.1 - view.y.0) / ys, upper, fy)
            })
            .count()
    };
    [(true, true), (false, true), (true, false), (false, false)]
        .into_iter()
        .min_by_key(|&(r, u)| count(r, u))
        .unwrap_or((true, true))
}

/// Points along the drawn lines (sampled inside each segment so long straight pieces count)
/// and markers, used to place the legend.
pub(crate) fn occupancy<'a>(
    lines: impl Iterator<Item = &'a Vec<(f64, f64)>>,
    dots: impl Iterator<Item = &'a (f64, f64)>,
) -> Vec<(f64, f64)> {
    let mut out: Vec<(f64, f64)> = dots.copied().collect();
    for l in lines {
        for s in l.windows(2) {
            out.extend((0..8).map(|k| {
                let t = f64::from(k) / 8.0;
                (
                    s[0].0 + t * (s[1].0 - s[0].0),
                    s[0].1 + t * (s[1].1 - s[0].1),
                )
            }));
        }
        out.extend(l.last());
    }
    out
}
