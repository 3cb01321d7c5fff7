//! The plot frame and its tick marks, found in the image so that the user types only the tick
//! values. Dark ink (luminance below [`DARK`]) that runs straight over a large part of the image
//! is an axis line; short dark runs leaving an axis line at right angles are tick marks.
//!
//! Pixel convention (as everywhere in `digitize`): pixel column c, row r covers [c - 0.5,
//! c + 0.5] x [r - 0.5, r + 0.5], so integer coordinates are pixel centres. Lines and ticks
//! several pixels wide, or anti-aliased, are located at their ink-weighted centre, to a fraction
//! of a pixel.

use super::calibration::AxisCalibration;
use super::image::RgbImage;
use crate::error::{GearError, Result};

/// Luminance (0-255) below which a pixel is ink of the frame, ticks or text.
pub const DARK: f64 = 110.0;
/// Share of the image width (height) an axis line must span.
const LINE_SPAN: f64 = 0.4;
/// Longest tick mark looked for, in pixels.
const MAX_TICK: usize = 15;
/// Widest tick mark, in pixels.
const MAX_TICK_WIDTH: usize = 5;

/// Luminance of a pixel (ITU-R BT.601 weights).
pub fn luminance(p: [u8; 3]) -> f64 {
    0.299 * f64::from(p[0]) + 0.587 * f64::from(p[1]) + 0.114 * f64::from(p[2])
}

/// Ink weight of a pixel: 0 for light pixels, up to 1 for black.
fn ink(p: [u8; 3]) -> f64 {
    let l = luminance(p);
    if l < DARK {
        1.0 - l / 255.0
    } else {
        0.0
    }
}

/// One axis line: its sub-pixel centre across the line, the pixel rows (columns) it covers, and
/// its extent along the line.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxisLine {
    /// Ink-weighted centre across the line (a row for a horizontal line).
    pub at: f64,
    /// First and last pixel across the line with ink.
    pub width: (usize, usize),
    /// First and last pixel along the line.
    pub span: (usize, usize),
}

/// The frame of a plot: the x axis (bottom) and y axis (left) lines, the top and right lines of
/// a box frame if drawn, and the tick marks on the two axes (sub-pixel positions along them).
#[derive(Debug, Clone, PartialEq)]
pub struct Frame {
    pub bottom: AxisLine,
    pub left: AxisLine,
    pub top: Option<AxisLine>,
    pub right: Option<AxisLine>,
    /// Tick columns on the x axis, increasing.
    pub x_ticks: Vec<f64>,
    /// Tick rows on the y axis, increasing (top to bottom).
    pub y_ticks: Vec<f64>,
    /// Longest tick mark found, in pixels (0 without ticks).
    pub tick_len: usize,
    /// Longest tick mark reaching into the plot, in pixels (0 for outward ticks).
    pub inward: usize,
}

impl Frame {
    /// The inside of the frame, clear of its lines and of inward ticks: (first column, first
    /// row, last column, last row).
    pub fn interior(&self) -> (u32, u32, u32, u32) {
        let clear = self.inward + 2;
        let x0 = self.left.width.1 + clear;
        let x1 = self
            .right
            .map_or(self.bottom.span.1, |r| r.width.0.saturating_sub(clear));
        let y0 = self.top.map_or(self.left.span.0, |t| t.width.1 + clear);
        let y1 = self.bottom.width.0.saturating_sub(clear);
        let c = |v: usize| u32::try_from(v).unwrap_or(u32::MAX);
        (c(x0), c(y0), c(x1.max(x0)), c(y1.max(y0)))
    }
}

/// Lines of ink along one direction: `len` lines of `n` pixels each, `get(i, k)` the ink of
/// pixel k on line i. Adjacent lines whose longest ink run reaches `min_run` form one
/// [`AxisLine`], centred at their ink-weighted mean.
fn lines(len: usize, n: usize, min_run: usize, get: &dyn Fn(usize, usize) -> f64) -> Vec<AxisLine> {
    // Longest run of ink on line i, and its ink.
    let longest = |i: usize| {
        let (mut best, mut start, mut span, mut run) = (0, 0, (0, 0), 0);
        for k in 0..n {
            if get(i, k) > 0.0 {
                if run == 0 {
                    start = k;
                }
                run += 1;
                if run > best {
                    (best, span) = (run, (start, k));
                }
            } else {
                run = 0;
            }
        }
        (best >= min_run).then(|| (span, (span.0..=span.1).map(|k| get(i, k)).sum::<f64>()))
    };
    let mut out = Vec::new();
    // (line, ink-weighted sum of line indices, ink) of the group being built.
    let mut cur: Option<(AxisLine, f64, f64)> = None;
    for i in 0..len {
        match (longest(i), cur.as_mut()) {
            (Some((span, ink)), Some((line, sum, total))) => {
                line.width.1 = i;
                line.span = (line.span.0.min(span.0), line.span.1.max(span.1));
                *sum += ink * i as f64;
                *total += ink;
            }
            (Some((span, ink)), None) => {
                let line = AxisLine {
                    at: 0.0,
                    width: (i, i),
                    span,
                };
                cur = Some((line, ink * i as f64, ink));
            }
            (None, _) => out.extend(cur.take()),
        }
    }
    out.extend(cur);
    out.into_iter()
        .map(|(line, sum, total)| AxisLine {
            at: sum / total,
            ..line
        })
        .collect()
}

/// Tick marks leaving an axis line: for each position k along the line (inside `range`), the
/// length of the ink run that starts next to the line on either side; positions whose run is at
/// least 2 pixels are grouped, and each group (at most [`MAX_TICK_WIDTH`] wide) is one tick at
/// its ink-weighted centre. `get(k, d)` is the ink at position k and signed distance d from the
/// line's edge (d > 0 outwards from `outer`, d < 0 inwards from `inner`).
fn ticks(range: (usize, usize), get: &dyn Fn(usize, i64) -> f64) -> (Vec<f64>, usize, usize) {
    let run = |k: usize, sign: i64| {
        (1..=MAX_TICK as i64)
            .take_while(|&d| get(k, sign * d) > 0.0)
            .count()
    };
    let mut out = Vec::new();
    let (mut longest, mut inward) = (0, 0);
    let mut group: Vec<(usize, f64)> = Vec::new();
    let mut flush = |group: &mut Vec<(usize, f64)>| {
        let w: f64 = group.iter().map(|g| g.1).sum();
        if !group.is_empty() && group.len() <= MAX_TICK_WIDTH && w > 0.0 {
            out.push(group.iter().map(|g| g.0 as f64 * g.1).sum::<f64>() / w);
        }
        group.clear();
    };
    for k in range.0..=range.1 {
        let (outer, inner) = (run(k, 1), run(k, -1));
        let len = outer.max(inner);
        if (2..MAX_TICK).contains(&len) {
            let sign = if outer >= inner { 1 } else { -1 };
            let weight: f64 = (1..=len as i64).map(|d| get(k, sign * d)).sum();
            group.push((k, weight));
            longest = longest.max(len);
            inward = inward.max(inner);
        } else {
            flush(&mut group);
        }
    }
    flush(&mut group);
    (out, longest, inward)
}

/// Finds the frame of the plot in `img`: the lowest long horizontal ink line is the x axis, the
/// leftmost long vertical one the y axis; `None` when either is missing.
pub fn find_frame(img: &RgbImage) -> Option<Frame> {
    let (w, h) = (img.width as usize, img.height as usize);
    let at = |x: usize, y: usize| ink(img.get(x as u32, y as u32));
    let min_w = ((w as f64) * LINE_SPAN).ceil() as usize;
    let min_h = ((h as f64) * LINE_SPAN).ceil() as usize;
    let rows = lines(h, w, min_w.max(2), &|y, x| at(x, y));
    let cols = lines(w, h, min_h.max(2), &|x, y| at(x, y));
    let bottom = *rows.last()?;
    let left = *cols.first()?;
    let top = (rows.len() > 1).then(|| rows[0]);
    let right = (cols.len() > 1).then(|| cols[cols.len() - 1]);
    // Ticks along the x axis, between the frame's vertical lines.
    let x_range = (
        left.width.1 + 1,
        right.map_or(bottom.span.1, |r| r.width.0.saturating_sub(1)),
    );
    let (x_ticks, lx, ix) = ticks(x_range, &|x, d| {
        let y = if d > 0 {
            bottom.width.1 as i64 + d
        } else {
            bottom.width.0 as i64 + d
        };
        if y < 0 || y >= h as i64 {
            0.0
        } else {
            at(x, y as usize)
        }
    });
    let y_range = (
        top.map_or(left.span.0, |t| t.width.1 + 1),
        bottom.width.0.saturating_sub(1),
    );
    let (y_ticks, ly, iy) = ticks(y_range, &|y, d| {
        // Outwards is to the left of the y axis.
        let x = if d > 0 {
            left.width.0 as i64 - d
        } else {
            left.width.1 as i64 - d
        };
        if x < 0 || x >= w as i64 {
            0.0
        } else {
            at(x as usize, y)
        }
    });
    Some(Frame {
        bottom,
        left,
        top,
        right,
        x_ticks,
        y_ticks,
        tick_len: lx.max(ly),
        inward: ix.max(iy),
    })
}

/// Tick values as typed: `FIRST:LAST:STEP` (e.g. 1500:5500:500) or a comma-separated list
/// (e.g. 1,10,100 on a log axis).
pub fn parse_tick_values(text: &str) -> Result<Vec<f64>> {
    let bad = |why: &str| {
        GearError::Digitize(format!(
            "tick values '{text}': {why}; expected FIRST:LAST:STEP (e.g. 1500:5500:500) or a list A,B,C"
        ))
    };
    let num = |s: &str| {
        s.trim()
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| bad(&format!("'{s}' is not a finite number")))
    };
    if text.contains(':') {
        let parts: Vec<&str> = text.split(':').collect();
        let [a, b, s] = parts.as_slice() else {
            return Err(bad("three numbers separated by ':' were expected"));
        };
        let (a, b, s) = (num(a)?, num(b)?, num(s)?);
        if s <= 0.0 || b <= a {
            return Err(bad("LAST must exceed FIRST and STEP be positive"));
        }
        let n = ((b - a) / s + 1e-9).floor();
        if n > 1000.0 {
            return Err(bad("more than 1000 ticks"));
        }
        Ok((0..=n as usize).map(|k| a + k as f64 * s).collect())
    } else {
        let v: Vec<f64> = text.split(',').map(num).collect::<Result<_>>()?;
        if v.len() < 2 || v.windows(2).any(|p| p[1] <= p[0]) {
            return Err(bad("at least two increasing values were expected"));
        }
        Ok(v)
    }
}

/// Calibration of one axis from its tick marks and the values they show: the least-squares line
/// through (pixel, value) pairs (value in log10 on a log axis), given as a two-point
/// [`AxisCalibration`] at the first and last tick; and the largest distance in pixels of a tick
/// from that line (a check that the ticks were read right). `axis` names the axis in errors.
pub fn calibrate_from_ticks(
    axis: &str,
    ticks: &[f64],
    values: &[f64],
    log: bool,
) -> Result<(AxisCalibration, f64)> {
    if ticks.len() != values.len() {
        let found: Vec<String> = ticks.iter().map(|t| format!("{t:.1}")).collect();
        return Err(GearError::Digitize(format!(
            "{axis} axis: {} tick values given but {} tick marks found (at pixels {}); give as many values as marks, or calibrate with two known pixels (--{axis}-cal)",
            values.len(),
            ticks.len(),
            if found.is_empty() { "none".into() } else { found.join(", ") }
        )));
    }
    if log && values.iter().any(|v| *v <= 0.0) {
        return Err(GearError::Digitize(format!(
            "{axis} axis: values on a log axis must be positive"
        )));
    }
    let v: Vec<f64> = values
        .iter()
        .map(|&v| if log { v.log10() } else { v })
        .collect();
    let n = ticks.len() as f64;
    let (mp, mv) = (ticks.iter().sum::<f64>() / n, v.iter().sum::<f64>() / n);
    let sxx: f64 = ticks.iter().map(|p| (p - mp).powi(2)).sum();
    let sxy: f64 = ticks.iter().zip(&v).map(|(p, v)| (p - mp) * (v - mv)).sum();
    let slope = sxy / sxx;
    let pixel_of = |v: f64| mp + (v - mv) / slope;
    let worst = ticks
        .iter()
        .zip(&v)
        .map(|(p, v)| (p - pixel_of(*v)).abs())
        .fold(0.0, f64::max);
    let (first, last) = (v[0], v[v.len() - 1]);
    let value = |t: f64| if log { 10f64.powf(t) } else { t };
    let cal = AxisCalibration::new(
        pixel_of(first),
        value(first),
        pixel_of(last),
        value(last),
        log,
    )?;
    Ok((cal, worst))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A white image with a box frame 2 px wide, outward ticks 5 px long, 1 px wide.
    fn framed() -> RgbImage {
        let (w, h) = (200u32, 120u32);
        let mut img = RgbImage {
            width: w,
            height: h,
            pixels: vec![[255; 3]; (w * h) as usize],
        };
        let mut set = |x: u32, y: u32| img.pixels[(y * w + x) as usize] = [0, 0, 0];
        for x in 20..=180 {
            for y in [99, 100, 10, 11] {
                set(x, y);
            }
        }
        for y in 10..=100 {
            for x in [20, 21, 179, 180] {
                set(x, y);
            }
        }
        for d in 1..=5 {
            for k in 0..5 {
                set(40 + 30 * k, 100 + d); // x ticks at columns 40, 70, .., 160
            }
            for k in 0..4 {
                set(20 - d, 20 + 20 * k); // y ticks at rows 20, 40, 60, 80
            }
        }
        img
    }

    #[test]
    fn frame_and_ticks_are_found_at_their_centres() {
        let f = find_frame(&framed()).unwrap();
        assert!((f.bottom.at - 99.5).abs() < 1e-9, "{:?}", f.bottom);
        assert!((f.left.at - 20.5).abs() < 1e-9, "{:?}", f.left);
        assert!((f.top.unwrap().at - 10.5).abs() < 1e-9);
        assert!((f.right.unwrap().at - 179.5).abs() < 1e-9);
        assert_eq!(f.x_ticks, [40.0, 70.0, 100.0, 130.0, 160.0]);
        assert_eq!(f.y_ticks, [20.0, 40.0, 60.0, 80.0]);
        assert_eq!((f.tick_len, f.inward), (5, 0));
        assert_eq!(f.interior(), (23, 13, 177, 97));
    }

    #[test]
    fn ticks_calibrate_the_axis() {
        let (c, worst) =
            calibrate_from_ticks("x", &[40.0, 70.0, 100.0], &[0.0, 5.0, 10.0], false).unwrap();
        assert!(worst < 1e-12);
        assert!((c.to_value(55.0) - 2.5).abs() < 1e-12);
        let (c, _) = calibrate_from_ticks("y", &[10.0, 60.0], &[1.0, 100.0], true).unwrap();
        assert!((c.to_value(35.0) - 10.0).abs() < 1e-9);
        let e = calibrate_from_ticks("x", &[40.0, 70.0], &[0.0, 5.0, 10.0], false).unwrap_err();
        assert!(
            e.to_string()
                .contains("3 tick values given but 2 tick marks found"),
            "{e}"
        );
    }

    #[test]
    fn tick_values_parse() {
        assert_eq!(
            parse_tick_values("1500:5500:500").unwrap(),
            (0..9)
                .map(|k| 1500.0 + 500.0 * k as f64)
                .collect::<Vec<_>>()
        );
        assert_eq!(parse_tick_values("0:30:5").unwrap().len(), 7);
        assert_eq!(parse_tick_values("1,10,100").unwrap(), [1.0, 10.0, 100.0]);
        for bad in ["1:2", "5:1:1", "0:1:0", "1", "3,2", "a,b", "0:1e9:1"] {
            assert!(parse_tick_values(bad).is_err(), "{bad}");
        }
    }
}
