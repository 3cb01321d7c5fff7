//! Figures for the analyses: x-y plots (time histories, phase planes, Poincaré sections,
//! frequency responses), grids of such panels, and category maps (basins of attraction).
//!
//! Every writer takes a path *stem* and writes `stem.png` (raster) and `stem.svg` (vector, with
//! real text), creating the parent directory if needed, and returns both paths. All text uses
//! the DejaVu Sans font bundled with the crate, so no system fonts are needed.
//!
//! User data never makes the writers panic: non-finite points are skipped (lines are broken at
//! them), empty series are allowed, degenerate ranges are widened, and malformed inputs give a
//! [`GearError`](crate::GearError).
//!
//! ```no_run
//! use geardyn::plot::{write_xy, Series, XyPlot};
//! let pts: Vec<(f64, f64)> = (0..100).map(|i| (i as f64 * 0.1, (i as f64 * 0.1).sin())).collect();
//! let plot = XyPlot::new("Response", "t", "x(t)").with_series(Series::line("x", pts));
//! let files = write_xy(&plot, std::path::Path::new("out/response"))?;
//! # Ok::<(), geardyn::GearError>(())
//! ```

mod axis;
mod clip;
mod glyph;
mod layout;
mod legend;
mod map;
mod notation;
mod output;
mod overlap;
mod panels;
mod range;
mod raster_text;
mod series;
mod style;
mod xy;
mod xy_draw;

#[cfg(test)]
mod tests;

pub use map::{write_category_map, CategoryMap};
pub use notation::symbols;
pub(crate) use output::write_rgb_png;
pub use panels::write_panels;
pub use series::Series;
pub use style::{palette_color, Marker, SeriesStyle, PALETTE};
pub use xy::{write_xy, XyPlot};
