//! Layout helpers shared by the figure kinds.

use plotters::coord::Shift;
use plotters::prelude::{DrawingArea, DrawingBackend, IntoFont, RGBColor, TextStyle};
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::output::msg;
use super::style::{Sizes, FONT};

/// Colour of secondary text (captions, marked lines).
pub(crate) const MUTED: RGBColor = RGBColor(0x50, 0x50, 0x50);

/// Smallest font scale a title or caption is shrunk to before it is wrapped.
const MIN_SHRINK: f64 = 0.8;

/// Lines and font size that fit `text` into `width` pixels: the text on one line at `size` if it
/// fits, else at a smaller size down to [`MIN_SHRINK`] of it, else wrapped at spaces into as many
/// lines of that smallest size as needed (a single word longer than the width stays whole).
pub(crate) fn fit_lines<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    text: &str,
    size: f64,
    width: u32,
) -> Result<(Vec<String>, f64), String> {
    let w = |t: &str, s: f64| -> Result<u32, String> {
        let style = TextStyle::from((FONT, s).into_font());
        Ok(area.estimate_text_size(t, &style).map_err(msg)?.0)
    };
    let full = w(text, size)?;
    if full <= width {
        return Ok((vec![text.to_string()], size));
    }
    let shrunk = size * (f64::from(width) / f64::from(full)).max(MIN_SHRINK);
    if w(text, shrunk)? <= width {
        return Ok((vec![text.to_string()], shrunk));
    }
    Ok((wrap(area, text, shrunk, width)?, shrunk))
}

/// `text` broken at spaces into lines no wider than `width` pixels at font `size` (a single word
/// longer than the width stays whole).
pub(crate) fn wrap<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    text: &str,
    size: f64,
    width: u32,
) -> Result<Vec<String>, String> {
    let style = TextStyle::from((FONT, size).into_font());
    let mut lines: Vec<String> = Vec::new();
    let mut line = String::new();
    for word in text.split(' ') {
        let candidate = if line.is_empty() {
            word.to_string()
        } else {
            format!("{line} {word}")
        };
        let too_wide = area.estimate_text_size(&candidate, &style).map_err(msg)?.0 > width;
        if !line.is_empty() && too_wide {
            lines.push(std::mem::replace(&mut line, word.to_string()));
        } else {
            line = candidate;
        }
    }
    lines.push(line);
    Ok(lines)
}

/// Draws `text` centred in lines at the top of `area` (shrunk or wrapped to fit its width, see
/// [`fit_lines`]); returns the rest of the area below it.
fn banner<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    text: &str,
    size: f64,
    color: RGBColor,
) -> Result<DrawingArea<DB, Shift>, String> {
    let (w, _) = area.dim_in_pixel();
    let (lines, size) = fit_lines(area, text, size, w.saturating_sub(8))?;
    let row = (size * 1.25).ceil() as u32;
    let style = TextStyle::from((FONT, size).into_font())
        .color(&color)
        .pos(Pos::new(HPos::Center, VPos::Top));
    for (k, line) in lines.iter().enumerate() {
        let y = (row * k as u32 + (size * 0.25) as u32) as i32;
        area.draw_text(line, &style, (w as i32 / 2, y))
            .map_err(msg)?;
    }
    let used = row * lines.len() as u32 + (size * 0.35) as u32;
    Ok(area.split_vertically(used).1)
}

/// Draws the title and the optional caption line at the top of `area`; returns the rest.
/// Both are shrunk or wrapped to fit the width, never clipped.
pub(crate) fn headed<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    title: &str,
    caption: Option<&str>,
    sz: &Sizes,
) -> Result<DrawingArea<DB, Shift>, String> {
    let mut rest = area.clone();
    if !title.trim().is_empty() {
        rest = banner(&rest, title, sz.title, RGBColor(0, 0, 0))?;
    }
    if let Some(c) = caption.filter(|c| !c.trim().is_empty()) {
        rest = banner(&rest, c, sz.caption, MUTED)?;
    }
    Ok(rest)
}
