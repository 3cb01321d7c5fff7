//! Layout helpers shared by the figure kinds.

use plotters::coord::Shift;
use plotters::prelude::{DrawingArea, DrawingBackend, IntoFont, RGBColor, TextStyle};

use super::output::msg;
use super::style::{Sizes, FONT};

/// Colour of secondary text (captions, marked lines).
pub(crate) const MUTED: RGBColor = RGBColor(0x50, 0x50, 0x50);

/// Draws the title and the optional caption line at the top of `area`; returns the rest.
pub(crate) fn headed<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    title: &str,
    caption: Option<&str>,
    sz: &Sizes,
) -> Result<DrawingArea<DB, Shift>, String> {
    let mut rest = area.clone();
    if !title.trim().is_empty() {
        rest = rest.titled(title, (FONT, sz.title)).map_err(msg)?;
    }
    if let Some(c) = caption.filter(|c| !c.trim().is_empty()) {
        let style = TextStyle::from((FONT, sz.caption).into_font()).color(&MUTED);
        rest = rest.titled(c, style).map_err(msg)?;
    }
    Ok(rest)
}
