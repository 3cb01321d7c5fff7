//! Legend box of x-y plots: entries (sample and label) and notes, placed inside the plot where
//! it covers no drawn data, or beside the plot when every place inside would.

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::clip::View;
use super::glyph::LegendSample;
use super::layout::{wrap, MUTED};
use super::output::{msg, DrawResult};
use super::style::{Sizes, FONT};

/// Gap between the legend box and the plot frame, and inner padding of the box, in pixels.
const INSET: i32 = 6;
const PAD: i32 = 8;
/// Clearance in pixels kept between the box and any drawn point (lines are 2 px wide).
const CLEAR: f64 = 3.0;
/// Gap between the columns of a widened legend, pixels.
const COLUMN_GAP: i32 = 16;
/// Font scale of the notes under the entries.
const NOTE_SCALE: f64 = 0.85;

/// A measured legend: its entries, its notes wrapped to the box, and the box size in pixels.
#[derive(Clone)]
pub(crate) struct Legend {
    entries: Vec<(String, LegendSample)>,
    notes: Vec<String>,
    /// The notes before wrapping, for another box width.
    raw_notes: Vec<String>,
    glyph_w: i32,
    /// Width of the widest entry (sample and label), pixels.
    entry_w: i32,
    /// Entries per column (all of them in one column unless [`Legend::widened`]).
    rows: usize,
    row_h: i32,
    note_h: i32,
    text: TextStyle<'static>,
    note: TextStyle<'static>,
    pub size: (i32, i32),
}

/// Where the legend goes: inside the plot with its box anchored at fractions (0, 0.5 or 1 of the
/// free width and height, from the left and from the top), or beside the plot.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Placement {
    Inside(f64, f64),
    Outside,
}

impl Legend {
    /// Measures the legend of `entries` and `notes`, one column of entries with the notes
    /// wrapped to their width (at least 16 font sizes).
    pub fn measure<DB: DrawingBackend>(
        area: &DrawingArea<DB, Shift>,
        entries: Vec<(String, LegendSample)>,
        notes: &[String],
        sz: &Sizes,
    ) -> Result<Self, String> {
        let text = TextStyle::from((FONT, sz.legend).into_font());
        let note = TextStyle::from((FONT, sz.legend * NOTE_SCALE).into_font()).color(&MUTED);
        let glyph_w = entries.first().map_or(0, |e| e.1.width);
        let mut text_w = 0;
        for (label, _) in &entries {
            text_w = text_w.max(area.estimate_text_size(label, &text).map_err(msg)?.0 as i32);
        }
        let entry_w = if entries.is_empty() {
            0
        } else {
            glyph_w + 8 + text_w
        };
        let rows = entries.len();
        let legend = Legend {
            entries,
            notes: Vec::new(),
            raw_notes: notes.to_vec(),
            glyph_w,
            entry_w,
            rows,
            row_h: (sz.legend * 1.35) as i32,
            note_h: (sz.legend * NOTE_SCALE * 1.3) as i32,
            text: text.pos(Pos::new(HPos::Left, VPos::Center)),
            note: note.pos(Pos::new(HPos::Left, VPos::Center)),
            size: (0, 0),
        };
        let note_w = entry_w.max((sz.legend * 16.0) as i32);
        legend.arranged(area, sz, rows, note_w)
    }

    /// The legend laid out in as many columns (filled top to bottom) as fit in `max_w` pixels,
    /// its notes wrapped to the box's width: for a strip below a plot, where one tall column
    /// would take height the plot needs.
    pub fn widened<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        sz: &Sizes,
        max_w: i32,
    ) -> Result<Legend, String> {
        let n = self.entries.len();
        let fit = (max_w - 2 * PAD + COLUMN_GAP) / (self.entry_w + COLUMN_GAP).max(1);
        let rows = n.div_ceil((fit.max(1) as usize).min(n.max(1)));
        let note_w = self
            .entries_width(rows)
            .max((sz.legend * 16.0) as i32)
            .min(max_w - 2 * PAD);
        self.clone().arranged(area, sz, rows, note_w)
    }

    /// Width of the entries in columns of `rows` (as few columns as hold them all).
    fn entries_width(&self, rows: usize) -> i32 {
        let cols = if rows == 0 {
            1
        } else {
            self.entries.len().div_ceil(rows) as i32
        };
        cols * self.entry_w + (cols - 1) * COLUMN_GAP
    }

    /// This legend with its entries in columns of `rows` and its notes wrapped to `note_w`
    /// pixels, and the box size that makes.
    fn arranged<DB: DrawingBackend>(
        mut self,
        area: &DrawingArea<DB, Shift>,
        sz: &Sizes,
        rows: usize,
        note_w: i32,
    ) -> Result<Legend, String> {
        let mut notes = Vec::new();
        for raw in &self.raw_notes {
            notes.extend(wrap(
                area,
                raw,
                sz.legend * NOTE_SCALE,
                note_w.max(1) as u32,
            )?);
        }
        let mut widest_note = 0;
        for t in &notes {
            widest_note =
                widest_note.max(area.estimate_text_size(t, &self.note).map_err(msg)?.0 as i32);
        }
        self.size = (
            2 * PAD + self.entries_width(rows).max(widest_note),
            2 * PAD + self.row_h * rows as i32 + self.note_h * notes.len() as i32,
        );
        self.rows = rows;
        self.notes = notes;
        Ok(self)
    }

    pub fn is_empty(&self) -> bool {
        self.entries.is_empty() && self.notes.is_empty()
    }

    /// The first place inside the plot, in the order upper right, upper left, lower right, lower
    /// left, then the middles of the edges, whose box keeps clear of every point of `drawn`
    /// (data coordinates within `view`); `Outside` when there is none.
    pub fn place(&self, drawn: &[(f64, f64)], view: &View) -> Placement {
        let (pw, ph) = (f64::from(view.px.0), f64::from(view.px.1));
        let (bw, bh) = (f64::from(self.size.0), f64::from(self.size.1));
        let inset = f64::from(INSET);
        if bw + 2.0 * inset > pw || bh + 2.0 * inset > ph {
            return Placement::Outside;
        }
        let px: Vec<(f64, f64)> = drawn
            .iter()
            .map(|p| {
                (
                    (p.0 - view.x.0) / (view.x.1 - view.x.0) * pw,
                    (view.y.1 - p.1) / (view.y.1 - view.y.0) * ph,
                )
            })
            .collect();
        let free = |fx: f64, fy: f64| {
            let left = inset + fx * (pw - bw - 2.0 * inset);
            let top = inset + fy * (ph - bh - 2.0 * inset);
            !px.iter().any(|&(x, y)| {
                x >= left - CLEAR
                    && x <= left + bw + CLEAR
                    && y >= top - CLEAR
                    && y <= top + bh + CLEAR
            })
        };
        [
            (1.0, 0.0),
            (0.0, 0.0),
            (1.0, 1.0),
            (0.0, 1.0),
            (0.5, 0.0),
            (0.5, 1.0),
            (0.0, 0.5),
            (1.0, 0.5),
        ]
        .into_iter()
        .find(|&(fx, fy)| free(fx, fy))
        .map_or(Placement::Outside, |(fx, fy)| Placement::Inside(fx, fy))
    }

    /// Draws the box with its top left corner at pixel `(x0, y0)` of `area`.
    pub fn draw_at<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        (x0, y0): (i32, i32),
    ) -> DrawResult {
        let corners = [(x0, y0), (x0 + self.size.0, y0 + self.size.1)];
        area.draw(&Rectangle::new(corners, WHITE.mix(0.92).filled()))
            .map_err(msg)?;
        area.draw(&Rectangle::new(
            corners,
            RGBColor(0xA0, 0xA0, 0xA0).stroke_width(1),
        ))
        .map_err(msg)?;
        let rows = self.rows.max(1);
        for (i, (label, sample)) in self.entries.iter().enumerate() {
            let (col, row) = ((i / rows) as i32, (i % rows) as i32);
            let x = x0 + PAD + col * (self.entry_w + COLUMN_GAP);
            let mid = y0 + PAD + row * self.row_h + self.row_h / 2;
            sample.draw(area, (x, mid))?;
            area.draw_text(label, &self.text, (x + self.glyph_w + 8, mid))
                .map_err(msg)?;
        }
        let mut y = y0 + PAD + self.row_h * rows.min(self.entries.len()) as i32;
        for n in &self.notes {
            area.draw_text(n, &self.note, (x0 + PAD, y + self.note_h / 2))
                .map_err(msg)?;
            y += self.note_h;
        }
        Ok(())
    }

    /// Draws the box inside `plot_area` (the plotting area, pixel coordinates) at `(fx, fy)`.
    pub fn draw_inside<DB: DrawingBackend>(
        &self,
        plot_area: &DrawingArea<DB, Shift>,
        (fx, fy): (f64, f64),
    ) -> DrawResult {
        let (aw, ah) = plot_area.dim_in_pixel();
        let free_w = f64::from(aw as i32 - self.size.0 - 2 * INSET);
        let free_h = f64::from(ah as i32 - self.size.1 - 2 * INSET);
        let x0 = INSET + (fx * free_w).round() as i32;
        let y0 = INSET + (fy * free_h).round() as i32;
        self.draw_at(plot_area, (x0, y0))
    }
}

/// Points along the drawn lines, every `step` pixels or closer, and the markers; used to place
/// the legend where it hides nothing.
pub(crate) fn occupancy<'a>(
    lines: impl Iterator<Item = &'a Vec<(f64, f64)>>,
    dots: impl Iterator<Item = &'a (f64, f64)>,
    view: &View,
    step: f64,
) -> Vec<(f64, f64)> {
    let (px, py) = view.pixel();
    let mut out: Vec<(f64, f64)> = dots.copied().collect();
    for l in lines {
        for s in l.windows(2) {
            let len = ((s[1].0 - s[0].0) / px).hypot((s[1].1 - s[0].1) / py);
            let n = (len / step).ceil().clamp(1.0, 10_000.0) as usize;
            out.extend((0..n).map(|k| {
                let t = k as f64 / n as f64;
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plot::style::{Marker, SeriesStyle};

    fn legend(area: &DrawingArea<SVGBackend<'_>, Shift>, n: usize) -> Legend {
        let sz = Sizes::scaled(1.0);
        let entries = (0..n)
            .map(|i| {
                let sample = LegendSample {
                    width: 35,
                    style: SeriesStyle::Line,
                    marker: Marker::Circle,
                    size: 4,
                    line: 2,
                    color: RGBColor(0, 0, 0),
                };
                (format!("series number {i}"), sample)
            })
            .collect();
        let notes = [
            "a note long enough to be wrapped to several lines in a narrow legend box \
                      but to fewer in a wide one"
                .to_string(),
        ];
        Legend::measure(area, entries, &notes, &sz).unwrap()
    }

    #[test]
    fn a_widened_legend_keeps_every_entry_in_fewer_rows_and_no_more_height() {
        assert!(crate::plot::style::ensure_font());
        let mut svg = String::new();
        let area = SVGBackend::with_string(&mut svg, (1200, 800)).into_drawing_area();
        let sz = Sizes::scaled(1.0);
        let one = legend(&area, 7);
        assert_eq!(one.rows, 7);
        let wide = one.widened(&area, &sz, 1000).unwrap();
        assert_eq!(wide.entries.len(), 7);
        // Columns of the widest entry fit side by side; 7 entries in 4 rows at most.
        let cols = 7usize.div_ceil(wide.rows);
        assert!(cols >= 2 && wide.rows <= 4, "{} rows", wide.rows);
        assert!(wide.size.0 <= 1000 && wide.size.1 < one.size.1);
        assert!(wide.notes.len() <= one.notes.len());
        // Too narrow for two columns: one column, as measured.
        let narrow = one.widened(&area, &sz, one.size.0).unwrap();
        assert_eq!(narrow.rows, 7);
    }
}
