//! Text on raster (PNG) figures. plotters' ab_glyph renderer places every glyph at its pen
//! position without the glyph's left side bearing, so a decimal point sits against the digit
//! before it ("0 5" for "0.5") and a combining mark (the circumflex of F̂) lands beside its base
//! letter. [`GlyphPlaced`] wraps a backend and draws text with the bearings, and puts combining
//! marks above the letter they follow. Everything else goes to the wrapped backend unchanged;
//! SVG output keeps its `<text>` elements and needs none of this.

use ab_glyph::{point, Font, FontRef, Glyph, OutlinedGlyph, PxScale, Rect, ScaleFont};
use plotters::prelude::DrawingBackend;
use plotters_backend::text_anchor::{HPos, VPos};
use plotters_backend::{
    BackendColor, BackendCoord, BackendStyle, BackendTextStyle, DrawingErrorKind,
};

use super::style::FONT_BYTES;

/// A drawing backend whose text is drawn glyph by glyph with proper placement.
pub(crate) struct GlyphPlaced<B> {
    inner: B,
    font: Option<FontRef<'static>>,
}

impl<B> GlyphPlaced<B> {
    pub fn new(inner: B) -> Self {
        GlyphPlaced {
            inner,
            font: FontRef::try_from_slice(FONT_BYTES).ok(),
        }
    }
}

/// Combining diacritical marks (U+0300-U+036F): drawn above the preceding letter.
fn is_combining(c: char) -> bool {
    ('\u{0300}'..='\u{036F}').contains(&c)
}

/// One glyph's outline and where its pixels go, relative to the text's layout origin.
struct Placed {
    glyph: OutlinedGlyph,
    dx: f32,
    dy: f32,
}

/// Outlines of `text` at pixel `size`, with the vertical convention of plotters (the baseline at
/// half the size below the layout box's top) so that PNG and SVG text sit alike.
fn layout(font: &FontRef<'static>, size: f32, text: &str) -> Vec<Placed> {
    let scaled = font.as_scaled(PxScale::from(size));
    let mut out: Vec<Placed> = Vec::new();
    let mut pen = 0f32;
    let mut prev_id = None;
    let mut base: Option<Rect> = None;
    for c in text.chars() {
        let id = scaled.glyph_id(c);
        if let Some(p) = prev_id {
            pen += scaled.kern(p, id);
        }
        prev_id = Some(id);
        let glyph: Glyph = id.with_scale_and_position(PxScale::from(size), point(pen, 0.0));
        pen += scaled.h_advance(id);
        let Some(og) = font.outline_glyph(glyph) else {
            continue;
        };
        let b = og.px_bounds();
        let (mut dx, mut dy) = (b.min.x, b.min.y);
        match (is_combining(c), base) {
            (true, Some(under)) => {
                // Centre the mark on its letter and lift it clear of the letter's top.
                dx = 0.5 * (under.min.x + under.max.x - b.width()).round();
                let gap = (0.06 * size).max(1.0);
                dy = dy.min(under.min.y - gap - b.height());
            }
            _ => base = Some(b),
        }
        out.push(Placed {
            glyph: og,
            dx,
            dy: dy + 0.5 * size,
        });
    }
    out
}

impl<B: DrawingBackend> DrawingBackend for GlyphPlaced<B> {
    type ErrorType = B::ErrorType;

    fn get_size(&self) -> (u32, u32) {
        self.inner.get_size()
    }
    fn ensure_prepared(&mut self) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.ensure_prepared()
    }
    fn present(&mut self) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.present()
    }
    fn draw_pixel(
        &mut self,
        point: BackendCoord,
        color: BackendColor,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.draw_pixel(point, color)
    }
    fn draw_line<S: BackendStyle>(
        &mut self,
        from: BackendCoord,
        to: BackendCoord,
        style: &S,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.draw_line(from, to, style)
    }
    fn draw_rect<S: BackendStyle>(
        &mut self,
        upper_left: BackendCoord,
        bottom_right: BackendCoord,
        style: &S,
        fill: bool,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.draw_rect(upper_left, bottom_right, style, fill)
    }
    fn draw_path<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        path: I,
        style: &S,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.draw_path(path, style)
    }
    fn draw_circle<S: BackendStyle>(
        &mut self,
        center: BackendCoord,
        radius: u32,
        style: &S,
        fill: bool,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.draw_circle(center, radius, style, fill)
    }
    fn fill_polygon<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        vert: I,
        style: &S,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.fill_polygon(vert, style)
    }
    fn blit_bitmap(
        &mut self,
        pos: BackendCoord,
        size: (u32, u32),
        src: &[u8],
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.blit_bitmap(pos, size, src)
    }

    /// The anchor and rotation handling of plotters' default `draw_text`, with glyphs placed by
    /// [`layout`].
    fn draw_text<S: BackendTextStyle>(
        &mut self,
        text: &str,
        style: &S,
        pos: BackendCoord,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        let color = style.color();
        let Some(font) = self.font.as_ref() else {
            return self.inner.draw_text(text, style, pos);
        };
        if color.alpha == 0.0 {
            return Ok(());
        }
        let ((min_x, min_y), (max_x, max_y)) = style
            .layout_box(text)
            .map_err(|e| DrawingErrorKind::FontError(Box::new(e)))?;
        let (width, height) = (max_x - min_x, max_y - min_y);
        let ax = match style.anchor().h_pos {
            HPos::Left => 0,
            HPos::Right => -width,
            HPos::Center => -width / 2,
        };
        let ay = match style.anchor().v_pos {
            VPos::Top => 0,
            VPos::Center => -height / 2,
            VPos::Bottom => -height,
        };
        let trans = style.transform();
        let (w, h) = self.inner.get_size();
        let mut pixels = Vec::new();
        for p in layout(font, style.size() as f32, text) {
            p.glyph.draw(|x, y, a| {
                let gx = (p.dx + x as f32).round() as i32;
                let gy = (p.dy + y as f32).round() as i32;
                pixels.push((gx, gy, a));
            });
        }
        for (x, y, a) in pixels {
            let (x, y) = trans.transform(x + ax - min_x, y + ay - min_y);
            let (x, y) = (pos.0 + x, pos.1 + y);
            if x >= 0 && x < w as i32 && y >= 0 && y < h as i32 && a > 0.0 {
                let c = BackendColor {
                    alpha: color.alpha * f64::from(a.min(1.0)),
                    rgb: color.rgb,
                };
                self.inner.draw_pixel((x, y), c)?;
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn font() -> FontRef<'static> {
        FontRef::try_from_slice(FONT_BYTES).unwrap()
    }

    /// Pixel columns (x) covered by each glyph of `text`.
    fn columns(text: &str) -> Vec<(f32, f32)> {
        layout(&font(), 16.0, text)
            .iter()
            .map(|p| (p.dx, p.dx + p.glyph.px_bounds().width()))
            .collect()
    }

    #[test]
    fn decimal_point_sits_between_its_digits_with_space_around() {
        // DejaVu's '.' has a left bearing of about a third of its advance: drawn at the pen
        // position (plotters) it touches the '0'; placed, it has a gap on both sides.
        let c = columns("0.5");
        assert_eq!(c.len(), 3);
        let (zero, dot, five) = (c[0], c[1], c[2]);
        assert!(dot.0 - zero.1 >= 1.0, "gap before the point: {c:?}");
        assert!(five.0 - dot.1 >= 1.0, "gap after the point: {c:?}");
    }

    #[test]
    fn combining_circumflex_sits_above_its_capital() {
        let placed = layout(&font(), 20.0, "F\u{0302}");
        assert_eq!(placed.len(), 2);
        let (f, hat) = (&placed[0], &placed[1]);
        let fb = f.glyph.px_bounds();
        let hb = hat.glyph.px_bounds();
        // Horizontally within the letter, vertically wholly above its top.
        assert!(hat.dx >= f.dx - 1.0 && hat.dx + hb.width() <= f.dx + fb.width() + 1.0);
        assert!(hat.dy + hb.height() < f.dy, "mark above the letter");
    }
}
