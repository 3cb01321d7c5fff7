//! The check image: the source figure, lightened, with what was found drawn over it — the frame
//! lines and tick marks (green), every extracted point (magenta) and the suspect ones (orange
//! squares) — so that a look shows whether the digitizer read the figure right.

use std::path::Path;

use super::frame::Frame;
use super::image::RgbImage;
use crate::error::Result;
use crate::plot::write_rgb_png;

const FRAME: [u8; 3] = [0, 150, 0];
const POINT: [u8; 3] = [200, 0, 200];
const SUSPECT: [u8; 3] = [255, 120, 0];

fn put(img: &mut RgbImage, x: i64, y: i64, c: [u8; 3]) {
    if x >= 0 && y >= 0 && x < i64::from(img.width) && y < i64::from(img.height) {
        let i = y as usize * img.width as usize + x as usize;
        img.pixels[i] = c;
    }
}

/// The check image of `points` (pixel column, row) and `suspects` read from `img` within
/// `frame` (if found).
pub fn check_image(
    img: &RgbImage,
    frame: Option<&Frame>,
    points: &[(f64, f64)],
    suspects: &[(f64, f64)],
) -> RgbImage {
    let mut out = img.clone();
    for p in &mut out.pixels {
        for v in p.iter_mut() {
            *v = (f64::from(*v) * 0.4 + 255.0 * 0.6).round() as u8;
        }
    }
    if let Some(f) = frame {
        let (w, h) = (i64::from(img.width), i64::from(img.height));
        for l in [Some(f.bottom), f.top].into_iter().flatten() {
            let y = l.at.round() as i64;
            for x in l.span.0 as i64..=l.span.1 as i64 {
                put(&mut out, x, y, FRAME);
            }
        }
        for l in [Some(f.left), f.right].into_iter().flatten() {
            let x = l.at.round() as i64;
            for y in l.span.0 as i64..=l.span.1 as i64 {
                put(&mut out, x, y, FRAME);
            }
        }
        let reach = f.tick_len as i64 + 3;
        let yb = f.bottom.at.round() as i64;
        for t in &f.x_ticks {
            for d in -reach..=reach {
                put(&mut out, t.round() as i64, (yb + d).clamp(0, h - 1), FRAME);
            }
        }
        let xl = f.left.at.round() as i64;
        for t in &f.y_ticks {
            for d in -reach..=reach {
                put(&mut out, (xl + d).clamp(0, w - 1), t.round() as i64, FRAME);
            }
        }
    }
    for &(x, y) in points {
        let (x, y) = (x.round() as i64, y.round() as i64);
        for d in -2..=2 {
            put(&mut out, x + d, y, POINT);
            put(&mut out, x, y + d, POINT);
        }
    }
    for &(x, y) in suspects {
        let (x, y) = (x.round() as i64, y.round() as i64);
        for d in -6..=6 {
            for (dx, dy) in [
                (d, -6),
                (d, 6),
                (-6, d),
                (6, d),
                (d, -7),
                (d, 7),
                (-7, d),
                (7, d),
            ] {
                put(&mut out, x + dx, y + dy, SUSPECT);
            }
        }
    }
    out
}

/// Writes `img` as an 8-bit RGB PNG.
pub fn write_png(img: &RgbImage, path: &Path) -> Result<()> {
    let data: Vec<u8> = img.pixels.iter().flatten().copied().collect();
    write_rgb_png(path, (img.width, img.height), &data)
}
