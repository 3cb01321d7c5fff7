//! Which pixels belong to the curve: those within a colour distance of the target colour,
//! inside an optional crop box.

use std::str::FromStr;

use super::image::RgbImage;
use crate::error::{GearError, Result};

/// An 8-bit RGB colour, written `RRGGBB` in hexadecimal (optionally with a leading `#`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Rgb(pub u8, pub u8, pub u8);

impl Rgb {
    /// Euclidean distance in RGB space (0 to about 441.7).
    pub fn distance(self, px: [u8; 3]) -> f64 {
        let d = |a: u8, b: u8| f64::from(i32::from(a) - i32::from(b));
        let (r, g, b) = (d(self.0, px[0]), d(self.1, px[1]), d(self.2, px[2]));
        (r * r + g * g + b * b).sqrt()
    }
}

impl std::fmt::Display for Rgb {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "#{:02x}{:02x}{:02x}", self.0, self.1, self.2)
    }
}

impl FromStr for Rgb {
    type Err = GearError;

    fn from_str(s: &str) -> Result<Self> {
        let hex = s.trim().trim_start_matches('#');
        let byte = |i: usize| {
            hex.get(i..i + 2)
                .and_then(|h| u8::from_str_radix(h, 16).ok())
        };
        let digits = hex.len() == 6 && hex.bytes().all(|c| c.is_ascii_hexdigit());
        match (digits, byte(0), byte(2), byte(4)) {
            (true, Some(r), Some(g), Some(b)) => Ok(Rgb(r, g, b)),
            _ => Err(GearError::Digitize(format!(
                "colour '{s}' is not of the form RRGGBB (six hexadecimal digits, e.g. 0072b2)"
            ))),
        }
    }
}

/// A pixel rectangle from corner (`x0`, `y0`) to corner (`x1`, `y1`), both included; the
/// corners may be given in any order.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PixelBox {
    /// Column of one corner.
    pub x0: u32,
    /// Row of one corner.
    pub y0: u32,
    /// Column of the opposite corner.
    pub x1: u32,
    /// Row of the opposite corner.
    pub y1: u32,
}

/// Column and row ranges (half-open) that are searched.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Region {
    pub x: (u32, u32),
    pub y: (u32, u32),
}

impl Region {
    /// The crop box checked against the image, or the whole image.
    pub fn new(img: &RgbImage, crop: Option<PixelBox>) -> Result<Self> {
        let Some(b) = crop else {
            return Ok(Region {
                x: (0, img.width),
                y: (0, img.height),
            });
        };
        let (x0, x1) = (b.x0.min(b.x1), b.x0.max(b.x1));
        let (y0, y1) = (b.y0.min(b.y1), b.y0.max(b.y1));
        if x1 >= img.width || y1 >= img.height {
            return Err(GearError::Digitize(format!(
                "crop box {}:{}:{}:{} reaches outside the image of {} x {} pixels \
                 (columns 0 to {}, rows 0 to {})",
                b.x0,
                b.y0,
                b.x1,
                b.y1,
                img.width,
                img.height,
                img.width.saturating_sub(1),
                img.height.saturating_sub(1)
            )));
        }
        Ok(Region {
            x: (x0, x1 + 1),
            y: (y0, y1 + 1),
        })
    }

    pub fn width(&self) -> usize {
        (self.x.1 - self.x.0) as usize
    }

    pub fn height(&self) -> usize {
        (self.y.1 - self.y.0) as usize
    }
}

/// Matching pixels of a region: `on[r * width + c]` for region column c and row r.
#[derive(Debug, Clone)]
pub(crate) struct Mask {
    pub region: Region,
    pub on: Vec<bool>,
}

impl Mask {
    /// Pixels of `region` within `tolerance` of `color`; an error naming the closest colour
    /// present when none matches.
    pub fn new(img: &RgbImage, region: Region, color: Rgb, tolerance: f64) -> Result<Self> {
        if !(tolerance.is_finite() && tolerance >= 0.0) {
            return Err(GearError::param(
                "tolerance",
                tolerance,
                "the colour tolerance must be a finite distance >= 0",
            ));
        }
        let mut on = Vec::with_capacity(region.width() * region.height());
        let mut closest: Option<(f64, [u8; 3])> = None;
        for y in region.y.0..region.y.1 {
            for x in region.x.0..region.x.1 {
                let px = img.get(x, y);
                let d = color.distance(px);
                if closest.is_none_or(|(best, _)| d < best) {
                    closest = Some((d, px));
                }
                on.push(d <= tolerance);
            }
        }
        if !on.contains(&true) {
            let near = closest.map_or(String::new(), |(d, px)| {
                format!(
                    "; the closest colour there is {} at distance {d:.1}",
                    Rgb(px[0], px[1], px[2])
                )
            });
            return Err(GearError::Digitize(format!(
                "no pixel of colour {color} within tolerance {tolerance} in columns {}..{}, \
                 rows {}..{}{near}",
                region.x.0,
                region.x.1 - 1,
                region.y.0,
                region.y.1 - 1
            )));
        }
        Ok(Mask { region, on })
    }

    pub fn width(&self) -> usize {
        self.region.width()
    }

    pub fn height(&self) -> usize {
        self.region.height()
    }

    /// Whether region pixel (c, r) matches.
    pub fn at(&self, c: usize, r: usize) -> bool {
        self.on[r * self.width() + c]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image() -> RgbImage {
        // 4 x 3, white with one blue pixel at (2, 1).
        let mut pixels = vec![[255u8; 3]; 12];
        pixels[6] = [0, 114, 178];
        RgbImage {
            width: 4,
            height: 3,
            pixels,
        }
    }

    #[test]
    fn colours_parse_and_print() {
        assert_eq!("0072B2".parse::<Rgb>().unwrap(), Rgb(0, 114, 178));
        assert_eq!("#d55e00".parse::<Rgb>().unwrap().to_string(), "#d55e00");
        for bad in ["", "12345", "1234567", "gg0000", "+12345", "é1234"] {
            assert!(bad.parse::<Rgb>().is_err(), "{bad}");
        }
        assert_eq!(Rgb(0, 0, 0).distance([3, 4, 0]), 5.0);
    }

    #[test]
    fn mask_finds_the_colour_inside_the_crop_only() {
        let img = image();
        let blue = Rgb(0, 114, 178);
        let m = Mask::new(&img, Region::new(&img, None).unwrap(), blue, 10.0).unwrap();
        assert!(m.at(2, 1));
        assert_eq!(m.on.iter().filter(|&&b| b).count(), 1);

        let crop = PixelBox {
            x0: 1,
            y0: 2,
            x1: 0,
            y1: 0,
        };
        let r = Region::new(&img, Some(crop)).unwrap();
        assert_eq!((r.x, r.y), ((0, 2), (0, 3)));
        let err = Mask::new(&img, r, blue, 10.0).unwrap_err().to_string();
        assert!(err.contains("no pixel of colour #0072b2"), "{err}");
        assert!(err.contains("closest colour there is #ffffff"), "{err}");

        let outside = PixelBox {
            x0: 0,
            y0: 0,
            x1: 4,
            y1: 1,
        };
        let err = Region::new(&img, Some(outside)).unwrap_err().to_string();
        assert!(err.contains("outside the image of 4 x 3"), "{err}");
        assert!(Mask::new(&img, r, blue, f64::NAN).is_err());
    }
}
