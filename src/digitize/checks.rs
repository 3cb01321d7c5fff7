//! Points that are probably not the curve: on the plot frame, on a tick mark, outside the frame
//! (where tick labels and axis titles are), or beside dark text (a legend entry).

use super::frame::{luminance, Frame};
use super::image::RgbImage;
use super::mask::Rgb;

/// Luminance below which a pixel counts as the core of dark text.
const TEXT_DARK: f64 = 70.0;
/// Dark pixels (not of the curve's colour) in a point's window that make it "beside text".
const TEXT_PIXELS: usize = 8;
/// Pixels around a frame line or tick mark that still count as on it.
const NEAR: f64 = 2.0;

/// Why a point is suspect. Points on the frame or a tick mark count only when the frame's ink is
/// of the curve's colour (a coloured curve may cross the black frame).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Suspicion {
    /// On an axis line of the frame.
    Frame,
    /// On a tick mark.
    Tick,
    /// Outside the frame, where tick labels and axis titles are.
    OutsideFrame,
    /// Beside dark text of another colour, such as a legend entry.
    BesideText,
}

impl Suspicion {
    /// Human wording.
    pub fn text(self) -> &'static str {
        match self {
            Suspicion::Frame => "on the plot frame",
            Suspicion::Tick => "on a tick mark",
            Suspicion::OutsideFrame => "outside the plot frame (tick labels, axis titles)",
            Suspicion::BesideText => "beside text (a legend entry or label)",
        }
    }
}

/// The suspect points among `pixels` (column, row), with the reason. `frame` comes from
/// [`find_frame`](super::find_frame); `color`/`tolerance` are the curve's, whose own pixels are
/// never text; `size` is the half-height in pixels of the window searched for text (about a
/// marker's size).
pub fn suspect_points(
    img: &RgbImage,
    pixels: &[(f64, f64)],
    frame: Option<&Frame>,
    color: Rgb,
    tolerance: f64,
    size: u32,
) -> Vec<((f64, f64), Suspicion)> {
    pixels
        .iter()
        .filter_map(|&p| {
            let why = frame
                .and_then(|f| on_frame(f, p))
                .filter(|w| {
                    *w == Suspicion::OutsideFrame || frame_ink_matches(img, frame, color, tolerance)
                })
                .or_else(|| {
                    beside_text(img, p, frame, color, tolerance, size)
                        .then_some(Suspicion::BesideText)
                });
            why.map(|w| (p, w))
        })
        .collect()
}

/// Whether the frame's own ink is of the curve's colour (dark curves): only then can a point on
/// the frame or a tick mark be the frame's ink rather than the curve crossing it.
fn frame_ink_matches(img: &RgbImage, frame: Option<&Frame>, color: Rgb, tolerance: f64) -> bool {
    frame.is_some_and(|f| {
        let y = 0.5 * (f.left.span.0 + f.left.span.1) as f64;
        let px = img.get(f.left.at.round() as u32, y.round() as u32);
        color.distance(px) <= tolerance
    })
}

/// Whether `v` lies within [`NEAR`] pixels of the pixel range `w` (inclusive).
fn within(v: f64, w: (usize, usize)) -> bool {
    v >= w.0 as f64 - NEAR && v <= w.1 as f64 + NEAR
}

fn on_frame(f: &Frame, (x, y): (f64, f64)) -> Option<Suspicion> {
    let outside = x < f.left.width.0 as f64
        || y > f.bottom.width.1 as f64
        || f.top.is_some_and(|t| y < t.width.0 as f64)
        || f.right.is_some_and(|r| x > r.width.1 as f64);
    if outside {
        return Some(Suspicion::OutsideFrame);
    }
    let lines_h = [Some(f.bottom), f.top];
    let lines_v = [Some(f.left), f.right];
    if lines_h.iter().flatten().any(|l| within(y, l.width))
        || lines_v.iter().flatten().any(|l| within(x, l.width))
    {
        return Some(Suspicion::Frame);
    }
    let reach = f.tick_len;
    let near_tick = |t: &f64, v: f64| (v - t).abs() <= NEAR;
    let on_x_tick = within(
        y,
        (
            f.bottom.width.0.saturating_sub(reach),
            f.bottom.width.1 + reach,
        ),
    ) && f.x_ticks.iter().any(|t| near_tick(t, x));
    let on_y_tick = within(
        x,
        (f.left.width.0.saturating_sub(reach), f.left.width.1 + reach),
    ) && f.y_ticks.iter().any(|t| near_tick(t, y));
    (on_x_tick || on_y_tick).then_some(Suspicion::Tick)
}

/// Dark pixels inside the frame and not of the curve's colour in a window eight sizes to
/// either side of the point (a legend's sample line and its gap to the text are about seven
/// marker sizes long) and one size above and below.
fn beside_text(
    img: &RgbImage,
    (x, y): (f64, f64),
    frame: Option<&Frame>,
    color: Rgb,
    tolerance: f64,
    size: u32,
) -> bool {
    let (w, h) = (i64::from(img.width), i64::from(img.height));
    let s = i64::from(size.max(2));
    let (cx, cy) = (x.round() as i64, y.round() as i64);
    // Only ink inside the frame counts: tick labels outside it are expected text.
    let on_line = |c: i64, r: i64| {
        frame.is_some_and(|f| {
            let (x0, y0, x1, y1) = f.interior();
            c < i64::from(x0) || c > i64::from(x1) || r < i64::from(y0) || r > i64::from(y1)
        })
    };
    let mut count = 0;
    for r in (cy - s).max(0)..=(cy + s).min(h - 1) {
        for c in (cx - 8 * s).max(0)..=(cx + 8 * s).min(w - 1) {
            let px = img.get(c as u32, r as u32);
            if luminance(px) < TEXT_DARK && color.distance(px) > tolerance && !on_line(c, r) {
                count += 1;
            }
        }
    }
    count >= TEXT_PIXELS
}

#[cfg(test)]
mod tests {
    use super::super::{find_frame, read_png};
    use super::*;

    #[test]
    fn legend_sample_of_a_matplotlib_figure_is_beside_text() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/data/digitize/matplotlib_resonance.png");
        let img = read_png(&path).unwrap();
        let frame = find_frame(&img);
        // The legend's red sample line ends at column 625, row 78.5; its text starts at 637.
        let red = Rgb(0xd6, 0x27, 0x28);
        let pts = [(598.0, 78.5), (625.0, 78.5), (300.0, 300.0)];
        let s = suspect_points(&img, &pts, frame.as_ref(), red, 60.0, 6);
        let beside = |p| (p, Suspicion::BesideText);
        assert_eq!(s, [beside((598.0, 78.5)), beside((625.0, 78.5))]);
    }
}
