//! Writing one figure to `stem.png` and `stem.svg`.

use std::ffi::OsString;
use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::prelude::{BitMapBackend, DrawingArea, DrawingBackend, IntoDrawingArea, SVGBackend};

use super::raster_text::GlyphPlaced;
use super::style::ensure_font;
use crate::error::{GearError, Result};

/// Largest figure area in pixels (the raster is held in memory while drawing).
const MAX_PIXELS: u64 = 80_000_000;

/// Error message of a failed drawing step.
pub(crate) type DrawResult = std::result::Result<(), String>;

/// Converts any displayable backend error into a message.
pub(crate) fn msg<E: std::fmt::Display>(e: E) -> String {
    e.to_string()
}

/// Something that can draw itself on a drawing area of any backend.
pub(crate) trait Figure {
    /// Size of the whole figure in pixels.
    fn size(&self) -> (u32, u32);
    /// Draws the figure on `root`, which covers [`Figure::size`]; `raster` tells whether the
    /// backend is a bitmap (whose wide polylines need special care, see `xy::draw_line`).
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>, raster: bool) -> DrawResult;
}

/// `stem` with `.ext` appended (not substituted, so `a.v2` becomes `a.v2.png`).
fn with_suffix(stem: &Path, ext: &str) -> PathBuf {
    let mut s = OsString::from(stem.as_os_str());
    s.push(".");
    s.push(ext);
    PathBuf::from(s)
}

fn plot_err(path: &Path, message: String) -> GearError {
    GearError::Plot {
        path: path.to_path_buf(),
        message,
    }
}

/// Renders `fig` to `stem.png` and `stem.svg`, creating the parent directory if needed.
pub(crate) fn write_figure(fig: &impl Figure, stem: &Path) -> Result<Vec<PathBuf>> {
    let png = with_suffix(stem, "png");
    let svg = with_suffix(stem, "svg");
    if !ensure_font() {
        return Err(plot_err(
            &png,
            "the bundled font could not be loaded".into(),
        ));
    }
    if let Some(dir) = stem.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(GearError::io(dir))?;
    }
    let size = fig.size();
    if u64::from(size.0) * u64::from(size.1) > MAX_PIXELS {
        let m = format!("figure of {} x {} pixels is too large", size.0, size.1);
        return Err(plot_err(&png, m));
    }

    let mut text = String::new();
    {
        let root = SVGBackend::with_string(&mut text, size).into_drawing_area();
        fig.draw(&root, false)
            .and_then(|()| root.present().map_err(msg))
            .map_err(|m| plot_err(&svg, m))?;
    }
    std::fs::write(&svg, text).map_err(GearError::io(&svg))?;

    // Drawn into memory and encoded with the `png` crate: plotters' own file output goes
    // through the `image` crate, which was about 25 s of CPU in every clean build for nothing
    // the `png` crate does not do.
    let mut pixels = vec![0u8; 3 * size.0 as usize * size.1 as usize];
    {
        let backend = BitMapBackend::with_buffer(&mut pixels, size);
        let root = GlyphPlaced::new(backend).into_drawing_area();
        fig.draw(&root, true)
            .and_then(|()| root.present().map_err(msg))
            .map_err(|m| plot_err(&png, m))?;
    }
    write_rgb_png(&png, size, &pixels)?;
    Ok(vec![png, svg])
}

/// Writes packed 8-bit RGB pixels (3 bytes each, row-major from the top left) of an image of
/// `(width, height)` as a PNG file.
pub(crate) fn write_rgb_png(path: &Path, (width, height): (u32, u32), rgb: &[u8]) -> Result<()> {
    let file = std::fs::File::create(path).map_err(GearError::io(path))?;
    let mut enc = png::Encoder::new(std::io::BufWriter::new(file), width, height);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    // Per-row choice of filter, as the `image` crate did: files about a third smaller.
    enc.set_adaptive_filter(png::AdaptiveFilterType::Adaptive);
    let png_err = |e: png::EncodingError| GearError::io(path)(std::io::Error::other(e.to_string()));
    let mut writer = enc.write_header().map_err(png_err)?;
    writer.write_image_data(rgb).map_err(png_err)?;
    writer.finish().map_err(png_err)
}
