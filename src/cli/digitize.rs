//! `geardyn digitize`: a curve of one colour in a figure image (PNG) becomes a CSV data set.

use super::common::{check_out_file, commit, print_text, stage, write_text};
use super::digitize_parse::{check_stem, columns, constants, number, numbers, pixel};
use super::limits::real;
use anyhow::{bail, Context};
use clap::{Args as ClapArgs, ValueEnum};
use geardyn::digitize::{
    digitize, read_png, AxisCalibration, DigitizeOptions, MarkerFilter, Mode, PixelBox, Rgb,
};
use geardyn::plot::{write_xy, Marker, Series, XyPlot};
use std::path::{Path, PathBuf};

#[derive(ClapArgs, Debug)]
pub struct Args {
    /// Figure image (PNG of any colour type).
    #[arg(long)]
    image: PathBuf,
    /// x-axis calibration PX1:VAL1:PX2:VAL2 (two pixel columns and the values they show).
    #[arg(long, allow_hyphen_values = true)]
    x_cal: String,
    /// Logarithmic x axis.
    #[arg(long)]
    x_log: bool,
    /// y-axis calibration PY1:VAL1:PY2:VAL2 (two pixel rows, counted from the top).
    #[arg(long, allow_hyphen_values = true)]
    y_cal: String,
    /// Logarithmic y axis.
    #[arg(long)]
    y_log: bool,
    /// Colour of the curve, RRGGBB in hexadecimal.
    #[arg(long, alias = "colour")]
    color: String,
    /// Largest RGB distance from --color that still counts as the curve, in [0, 442].
    #[arg(long, default_value_t = 60.0, allow_hyphen_values = true, value_parser = real(0.0, 442.0, false))]
    tolerance: f64,
    /// line: one point per pixel column; markers: one point per blob (marker) of the colour.
    #[arg(long, value_enum, default_value_t = CliMode::Line)]
    mode: CliMode,
    /// Line mode: one point per separate vertical run of the colour (multivalued jump regions).
    #[arg(long)]
    multi: bool,
    /// Marker mode: blobs with fewer pixels are ignored.
    #[arg(long, default_value_t = 4)]
    min_area: usize,
    /// Marker mode: blobs with more pixels are ignored.
    #[arg(long)]
    max_area: Option<usize>,
    /// Marker mode: MIN:MAX bounds (pixels) on both sides of a marker's bounding box.
    #[arg(long)]
    marker_size: Option<String>,
    /// Marker mode: erosion radius (pixels) that detaches filled markers from thin lines.
    #[arg(long, default_value_t = 0)]
    erode: u32,
    /// Pixel box X0:Y0:X1:Y1 searched (corners included), to leave out legend, labels and axes.
    #[arg(long)]
    crop: Option<String>,
    /// Names of the x and y columns, e.g. speed_rpm,dte_pp_um.
    #[arg(long)]
    columns: String,
    /// Constant column NAME=VALUE written first on every row (repeatable), e.g. load_n=1890.
    #[arg(long = "const", value_name = "NAME=VALUE")]
    constants: Vec<String>,
    /// Output CSV; a check plot goes next to it as <stem>_check.png / .svg.
    #[arg(long)]
    out: PathBuf,
}

#[derive(ValueEnum, Debug, Clone, Copy, PartialEq, Eq)]
enum CliMode {
    Line,
    Markers,
}

pub fn run(a: Args) -> anyhow::Result<()> {
    check_out_file("--out", &a.out)?;
    if a.out.file_name().is_none() {
        bail!("--out {}: a CSV file name was expected", a.out.display());
    }
    let calibration = |flag: &str, text: &str, log: bool| -> anyhow::Result<AxisCalibration> {
        let [p1, v1, p2, v2] = numbers::<4>(flag, text, "PX1:VAL1:PX2:VAL2")?;
        AxisCalibration::new(p1, v1, p2, v2, log).with_context(|| format!("{flag} '{text}'"))
    };
    let x = calibration("--x-cal", &a.x_cal, a.x_log)?;
    let y = calibration("--y-cal", &a.y_cal, a.y_log)?;
    let color: Rgb = a.color.parse().context("--color")?;
    let crop = match &a.crop {
        Some(t) => {
            let [x0, y0, x1, y1] = numbers::<4>("--crop", t, "X0:Y0:X1:Y1")?.map(pixel);
            let ctx = || format!("--crop '{t}'");
            Some(PixelBox {
                x0: x0.with_context(ctx)?,
                y0: y0.with_context(ctx)?,
                x1: x1.with_context(ctx)?,
                y1: y1.with_context(ctx)?,
            })
        }
        None => None,
    };
    let size = match &a.marker_size {
        Some(t) => {
            let [lo, hi] = numbers::<2>("--marker-size", t, "MIN:MAX")?.map(pixel);
            let ctx = || format!("--marker-size '{t}'");
            let (lo, hi) = (lo.with_context(ctx)?, hi.with_context(ctx)?);
            if lo > hi {
                bail!("--marker-size '{t}': MIN is larger than MAX");
            }
            Some((lo, hi))
        }
        None => None,
    };
    let marker_opts = a.max_area.is_some() || a.marker_size.is_some() || a.erode > 0;
    if a.mode == CliMode::Markers && a.multi {
        bail!("--multi applies to --mode line only");
    }
    if a.mode == CliMode::Line && marker_opts {
        bail!("--max-area, --marker-size and --erode apply to --mode markers only");
    }
    let mode = match a.mode {
        CliMode::Line => Mode::Line { multi: a.multi },
        CliMode::Markers => Mode::Markers(MarkerFilter {
            min_area: a.min_area,
            max_area: a.max_area,
            size,
            erode: a.erode,
        }),
    };
    let (x_name, y_name) = columns(&a.columns)?;
    let constants = constants(&a.constants, [&x_name, &y_name])?;
    let opts = DigitizeOptions {
        x,
        y,
        color,
        tolerance: a.tolerance,
        mode,
        crop,
    };

    let img = read_png(&a.image)?;
    let points = digitize(&img, &opts)?;

    let mut w = csv::Writer::from_writer(Vec::new());
    let header: Vec<&str> = constants.iter().map(|(n, _)| n.as_str()).collect();
    w.write_record(
        header
            .iter()
            .copied()
            .chain([x_name.as_str(), y_name.as_str()]),
    )?;
    for &(px, py) in &points {
        let row = constants.iter().map(|(_, v)| number(*v));
        w.write_record(row.chain([number(px), number(py)]))?;
    }
    let csv_text = String::from_utf8(w.into_inner()?)?;

    let mode_text = match a.mode {
        CliMode::Line if a.multi => "line (multi)",
        CliMode::Line => "line",
        CliMode::Markers => "markers",
    };
    let names = (x_name, y_name);
    let plot = check_plot(
        &a.image,
        names,
        &opts,
        &points,
        (img.width, img.height),
        mode_text,
    );
    // Everything is computed before the first file is written; the CSV and its check plot are
    // staged beside the output folder and moved into it together.
    let folder = a
        .out
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let file_name = a.out.file_name().unwrap_or_default();
    let stage = stage("--out", folder)?;
    let staged_out = stage.dir().join(file_name);
    let mut written = write_xy(&plot, &check_stem(&staged_out))?;
    write_text(&staged_out, &csv_text)?;
    written.insert(0, staged_out);
    let written = commit(stage, &written)?;
    let mut text = format!(
        "extracted {} points from {} (colour {color}, tolerance {}, mode {mode_text})\n",
        points.len(),
        a.image.display(),
        a.tolerance
    );
    for p in written {
        text.push_str(&format!("wrote {}\n", p.display()));
    }
    print_text(&text)
}

/// The extracted points over the searched box in data units, log axes as log10, so that the
/// plot can be laid over the figure by eye.
fn check_plot(
    image: &Path,
    (x_name, y_name): (String, String),
    opts: &DigitizeOptions,
    points: &[(f64, f64)],
    (w, h): (u32, u32),
    mode_text: &str,
) -> XyPlot {
    let b = opts.crop.unwrap_or(PixelBox {
        x0: 0,
        y0: 0,
        x1: w.saturating_sub(1),
        y1: h.saturating_sub(1),
    });
    let axis = |c: AxisCalibration, p0: u32, p1: u32, name: String| {
        let shown = move |v: f64| if c.log { v.log10() } else { v };
        let (v0, v1) = (
            shown(c.to_value(f64::from(p0))),
            shown(c.to_value(f64::from(p1))),
        );
        let label = if c.log { format!("log10 {name}") } else { name };
        (shown, (v0.min(v1), v0.max(v1)), label)
    };
    let (fx, xr, x_label) = axis(opts.x, b.x0, b.x1, x_name);
    let (fy, yr, y_label) = axis(opts.y, b.y0, b.y1, y_name);
    let shown: Vec<(f64, f64)> = points.iter().map(|&(x, y)| (fx(x), fy(y))).collect();
    let marker = match opts.mode {
        Mode::Line { .. } => Marker::Dot,
        Mode::Markers(_) => Marker::Square,
    };
    let image_name = image.file_name().map_or_else(
        || image.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    );
    let mut plot = XyPlot::new(format!("Digitized from {image_name}"), x_label, y_label)
        .with_caption(format!(
            "{} points, colour {}, tolerance {}, mode {mode_text}; axes span the searched box",
            points.len(),
            opts.color,
            opts.tolerance
        ))
        .with_series(Series::markers("digitized", shown).with_marker(marker));
    if xr.0 < xr.1 && yr.0 < yr.1 {
        plot = plot.with_x_range(xr.0, xr.1).with_y_range(yr.0, yr.1);
    }
    plot
}
