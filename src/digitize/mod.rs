//! Digitizing published figures: a curve of one colour in a PNG image becomes (x, y) data.
//!
//! The paper's measured curves (Munro's DTE in Figs 19-22, Kubo's dynamic factor in Fig. 23)
//! exist only as figures; this module turns such a figure into a data set:
//!
//! 1. [`read_png`] loads the image as 8-bit RGB (any PNG colour type and depth);
//! 2. pixels within a colour distance of the curve colour are selected, inside an optional
//!    [`PixelBox`] crop that leaves out legend, labels and axes;
//! 3. [`Mode::Line`] gives one point per pixel column (centroid row, or every vertical run),
//!    [`Mode::Markers`] one point per connected blob (e.g. the squares of "- - □ - -");
//! 4. two [`AxisCalibration`]s per figure (linear or log10) map pixels to data units, given
//!    as two known pixels per axis or fitted to the tick marks [`find_frame`] finds
//!    ([`calibrate_from_ticks`]);
//! 5. [`suspect_points`] flags points on the frame, on tick marks, outside the frame or beside
//!    text, and [`check_image`] draws everything found over the figure.
//!
//! Pixel convention: pixel column c, row r (rows from the top) covers [c - 0.5, c + 0.5] x
//! [r - 0.5, r + 0.5], so whole numbers are pixel centres, as an image viewer shows the pixel
//! under the cursor. Calibration pixels, line and tick centres and marker centroids are all in
//! this convention and fractional: the frame's lines and ticks are located at their ink-weighted
//! centre (sub-pixel), which is the default reading. (A half-pixel slip in a hand-typed
//! calibration shifts every value by half a pixel's worth: 0.7 um on a steep flank of a
//! 60 um / 90 px axis.)
//!
//! ```no_run
//! use geardyn::digitize::{digitize, read_png, AxisCalibration, DigitizeOptions, Mode};
//! let img = read_png(std::path::Path::new("fig21.png"))?;
//! let opts = DigitizeOptions {
//!     x: AxisCalibration::new(120.0, 0.0, 980.0, 4000.0, false)?,
//!     y: AxisCalibration::new(700.0, 0.0, 90.0, 60.0, false)?,
//!     color: "000000".parse()?,
//!     tolerance: 60.0,
//!     mode: Mode::Line { multi: false },
//!     crop: None,
//! };
//! let points = digitize(&img, &opts)?; // (speed, DTE) pairs sorted by speed
//! # Ok::<(), geardyn::GearError>(())
//! ```

mod calibration;
mod checks;
mod frame;
mod image;
mod line;
mod markers;
mod mask;
mod overlay;

pub use calibration::AxisCalibration;
pub use checks::{suspect_points, Suspicion};
pub use frame::{calibrate_from_ticks, find_frame, parse_tick_values, AxisLine, Frame};
pub use image::{decode_png, read_png, RgbImage};
pub use markers::{MarkerCensus, MarkerFilter, MarkerSizes};
pub use mask::{PixelBox, Rgb};
pub use overlay::{check_image, write_png};

use crate::error::{GearError, Result};
use mask::{Mask, Region};

/// How the curve is drawn in the figure.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    /// A line: one point per pixel column at the centroid row of the matching pixels, or with
    /// `multi` one point per separate vertical run (keeps both branches of a jump region).
    Line {
        /// One point per run instead of one per column.
        multi: bool,
    },
    /// Markers: one point per connected blob (4-connectivity) that passes the filter.
    Markers(MarkerFilter),
}

/// Everything [`digitize`] needs besides the image.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DigitizeOptions {
    /// Calibration of the x axis (pixel columns).
    pub x: AxisCalibration,
    /// Calibration of the y axis (pixel rows, counted from the top).
    pub y: AxisCalibration,
    /// Colour of the curve.
    pub color: Rgb,
    /// Largest RGB Euclidean distance from `color` that still counts as the curve (anti-aliased
    /// or scanned curves need some tens; 0 to about 442).
    pub tolerance: f64,
    /// Line or marker extraction.
    pub mode: Mode,
    /// Pixel box searched (corners included); `None` searches the whole image.
    pub crop: Option<PixelBox>,
}

/// Points of the curve in pixel coordinates (column, row), in the order found.
///
/// Errors when the crop box leaves the image, the tolerance is not a finite non-negative number,
/// no pixel of the colour is found, or (marker mode) no blob passes the filter.
pub fn extract_pixels(img: &RgbImage, opts: &DigitizeOptions) -> Result<Vec<(f64, f64)>> {
    Ok(extract(img, opts)?.pixels)
}

/// What [`extract`] found.
#[derive(Debug, Clone, PartialEq)]
pub struct Extraction {
    /// Points of the curve in pixel coordinates (column, row), in the order found.
    pub pixels: Vec<(f64, f64)>,
    /// In marker mode, the markers found, the blobs rejoined and those left out, by reason.
    pub census: Option<MarkerCensus>,
}

/// As [`extract_pixels`], with the marker census in marker mode, from the same one pass over
/// the image.
pub fn extract(img: &RgbImage, opts: &DigitizeOptions) -> Result<Extraction> {
    let mask = colour_mask(img, opts)?;
    match opts.mode {
        Mode::Line { multi } => Ok(Extraction {
            pixels: line::column_points(&mask, multi),
            census: None,
        }),
        Mode::Markers(filter) => {
            let census = markers::marker_census(&mask, &filter);
            if census.points.is_empty() {
                return Err(GearError::Digitize(format!(
                    "{} blob(s) of colour {} found, but none passes the marker filter \
                     (min area {} px, max area {}, size {}, erosion {} px): {}",
                    census.blobs,
                    opts.color,
                    filter.min_area,
                    filter.max_area.map_or("none".into(), |a| format!("{a} px")),
                    filter
                        .size
                        .map_or("any".into(), |(lo, hi)| format!("{lo} to {hi} px")),
                    filter.erode,
                    census.left_out_text()
                )));
            }
            Ok(Extraction {
                pixels: census.points.clone(),
                census: Some(census),
            })
        }
    }
}

/// The pixels of the curve's colour in the searched box.
fn colour_mask(img: &RgbImage, opts: &DigitizeOptions) -> Result<Mask> {
    let region = Region::new(img, opts.crop)?;
    Mask::new(img, region, opts.color, opts.tolerance)
}

/// The blob sizes of the marker colour in the searched box (see [`MarkerSizes`]), for choosing
/// or checking the marker filter's size bounds; `filter`'s own size bounds are ignored.
pub fn marker_sizes(
    img: &RgbImage,
    opts: &DigitizeOptions,
    filter: &MarkerFilter,
) -> Result<MarkerSizes> {
    let mask = colour_mask(img, opts)?;
    Ok(markers::marker_sizes(&mask, filter))
}

/// The curve in data units, sorted by x (then y).
///
/// Runs [`extract_pixels`] and maps each point through the two calibrations, which are
/// validated first.
pub fn digitize(img: &RgbImage, opts: &DigitizeOptions) -> Result<Vec<(f64, f64)>> {
    opts.x.validate()?;
    opts.y.validate()?;
    Ok(to_data(opts, &extract_pixels(img, opts)?))
}

/// Pixel points (column, row) in data units through the calibrations of `opts`, sorted by x
/// (then y).
pub fn to_data(opts: &DigitizeOptions, pixels: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let mut points: Vec<(f64, f64)> = pixels
        .iter()
        .map(|&(c, r)| (opts.x.to_value(c), opts.y.to_value(r)))
        .collect();
    points.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    points
}

#[cfg(test)]
mod tests;
