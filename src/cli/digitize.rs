//! `geardyn digitize`: a curve of one colour in a figure image (PNG) becomes a CSV data set.

use super::common::{check_out_file, commit, print_text, stage, write_text};
use super::digitize_parse::{
    columns, constants, crop_box, marker_size, number, numbers, stem_with,
};
use super::limits::real;
use anyhow::{bail, Context};
use clap::{Args as ClapArgs, ValueEnum};
use geardyn::digitize::{
    calibrate_from_ticks, check_image, extract, find_frame, marker_sizes, parse_tick_values,
    read_png, suspect_points, to_data, write_png, AxisCalibration, DigitizeOptions, Extraction,
    Frame, MarkerCensus, MarkerFilter, MarkerSizes, Mode, PixelBox, Rgb, RgbImage, Suspicion,
};
use geardyn::plot::{write_xy, Marker, Series, XyPlot};
use std::path::{Path, PathBuf};

#[derive(ClapArgs, Debug)]
pub struct Args {
    /// Figure image (PNG of any colour type).
    #[arg(long)]
    image: PathBuf,
    /// x-axis tick values, FIRST:LAST:STEP (e.g. 1500:5500:500) or A,B,C: the plot frame and
    /// its tick marks are found in the image and their sub-pixel centres fitted to these values.
    /// Give as many values as there are tick marks on the axis.
    #[arg(long, allow_hyphen_values = true)]
    x_ticks: Option<String>,
    /// y-axis tick values, bottom to top, as for --x-ticks (e.g. 0:30:5).
    #[arg(long, allow_hyphen_values = true)]
    y_ticks: Option<String>,
    /// x-axis calibration PX1:VAL1:PX2:VAL2 instead of --x-ticks: two pixel columns and the
    /// values they show. Whole numbers are pixel centres (as an image viewer shows the pixel
    /// under the cursor); fractions are allowed and half a pixel matters on a steep curve.
    #[arg(long, allow_hyphen_values = true)]
    x_cal: Option<String>,
    /// Logarithmic x axis.
    #[arg(long)]
    x_log: bool,
    /// y-axis calibration PY1:VAL1:PY2:VAL2 instead of --y-ticks (rows counted from the top).
    #[arg(long, allow_hyphen_values = true)]
    y_cal: Option<String>,
    /// Logarithmic y axis.
    #[arg(long)]
    y_log: bool,
    /// Keep points that lie on the plot frame, a tick mark, outside the frame or beside text
    /// (by default they are listed and nothing is written).
    #[arg(long)]
    allow_suspect: bool,
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
    /// Marker mode: MIN:MAX bounds (pixels) on both sides of a marker's bounding box. Default:
    /// the blob sizes are measured and the most common one (+-1 or 2 px) is taken; the size
    /// histogram is printed either way.
    #[arg(long)]
    marker_size: Option<String>,
    /// Marker mode: erosion radius (pixels) that detaches filled markers from thin lines.
    #[arg(long, default_value_t = 0)]
    erode: u32,
    /// Pixel box X0:Y0:X1:Y1 searched (corners included), to leave out legend, labels and axes.
    /// Default: the inside of the plot frame when one is found, else the whole image.
    #[arg(long)]
    crop: Option<String>,
    /// Names of the x and y columns, e.g. speed_rpm,dte_pp_um.
    #[arg(long)]
    columns: String,
    /// Constant column NAME=VALUE written first on every row (repeatable), e.g. load_n=1890.
    #[arg(long = "const", value_name = "NAME=VALUE")]
    constants: Vec<String>,
    /// Output CSV; beside it <stem>_check.png (the figure with the frame, ticks and points
    /// found drawn over it) and <stem>_plot.png / .svg (the points in data units).
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
    let img = read_png(&a.image)?;
    let frame = find_frame(&img);
    let mut report = String::new();
    let (x, y) = axes(&a, frame.as_ref(), &mut report)?;
    let color: Rgb = a.color.parse().context("--color")?;
    let crop = search_box(&a, frame.as_ref(), &mut report)?;
    let size = a.marker_size.as_deref().map(marker_size).transpose()?;
    check_mode_flags(&a)?;
    let (x_name, y_name) = columns(&a.columns)?;
    let constants = constants(&a.constants, [&x_name, &y_name])?;
    let mut opts = DigitizeOptions {
        x,
        y,
        color,
        tolerance: a.tolerance,
        mode: Mode::Line { multi: a.multi },
        crop,
    };
    // Half-height of the window searched for text beside a point: about a marker's half size.
    let mut text_window = 6;
    if a.mode == CliMode::Markers {
        let picked;
        (opts.mode, picked) = markers_mode(&a, size, &img, &opts, &mut report)?;
        text_window = picked.map_or(6, |p| p.1 / 2 + 1);
    }

    // The report so far (calibration, marker sizes) explains most failures: it goes with the error.
    let Extraction { pixels, census } = match extract(&img, &opts) {
        Ok(found) => found,
        Err(e) => bail!("{report}{e}"),
    };
    if let Some(c) = &census {
        report.push_str(&census_report(c));
    }
    let points = to_data(&opts, &pixels);
    let suspects = suspect_points(
        &img,
        &pixels,
        frame.as_ref(),
        color,
        a.tolerance,
        text_window,
    );
    if !suspects.is_empty() {
        let text = suspect_text(&suspects, pixels.len());
        if !a.allow_suspect {
            bail!("{report}{text}\nnothing written: narrow the search with --crop X0:Y0:X1:Y1 (or check --color), or pass --allow-suspect to keep these points (the check image marks them)");
        }
        report.push_str(&format!("warning: {text}\n"));
    }

    let csv_text = csv_text(&constants, (&x_name, &y_name), &points)?;
    let mode_text = match a.mode {
        CliMode::Line if a.multi => "line (multi)",
        CliMode::Line => "line",
        CliMode::Markers => "markers",
    };
    let plot = check_plot(
        &a.image,
        (x_name, y_name),
        &opts,
        &points,
        (img.width, img.height),
        mode_text,
    );
    let marked: Vec<(f64, f64)> = suspects.iter().map(|s| s.0).collect();
    let check = check_image(&img, frame.as_ref(), &pixels, &marked);
    let written = write_outputs(&a.out, &csv_text, &check, &plot)?;
    let mut text = format!(
        "{report}extracted {} points from {} (colour {color}, tolerance {}, mode {mode_text})\n",
        points.len(),
        a.image.display(),
        a.tolerance
    );
    for p in written {
        text.push_str(&format!("wrote {}\n", p.display()));
    }
    print_text(&text)
}

/// Both axes' calibrations (--A-cal or --A-ticks against the tick marks found); what was done
/// is added to `report`.
fn axes(
    a: &Args,
    frame: Option<&Frame>,
    report: &mut String,
) -> anyhow::Result<(AxisCalibration, AxisCalibration)> {
    let x = calibration(
        "x",
        (a.x_cal.as_deref(), a.x_ticks.as_deref()),
        a.x_log,
        frame.map(|f| f.x_ticks.clone()),
        report,
    )?;
    // Rows grow downwards and the y values upwards: the bottom tick takes the first value.
    let y = calibration(
        "y",
        (a.y_cal.as_deref(), a.y_ticks.as_deref()),
        a.y_log,
        frame.map(|f| f.y_ticks.iter().rev().copied().collect()),
        report,
    )?;
    Ok((x, y))
}

/// The pixel box searched: --crop, else the inside of the plot frame found (said in `report`),
/// else the whole image.
fn search_box(
    a: &Args,
    frame: Option<&Frame>,
    report: &mut String,
) -> anyhow::Result<Option<PixelBox>> {
    Ok(match &a.crop {
        Some(t) => Some(crop_box(t)?),
        None => frame.map(|f| {
            let (x0, y0, x1, y1) = f.interior();
            report.push_str(&format!(
                "searched inside the plot frame: columns {x0}..{x1}, rows {y0}..{y1} (--crop to change)\n"
            ));
            PixelBox { x0, y0, x1, y1 }
        }),
    })
}

/// Options of one mode given with the other are refused.
fn check_mode_flags(a: &Args) -> anyhow::Result<()> {
    let marker_opts = a.max_area.is_some() || a.marker_size.is_some() || a.erode > 0;
    if a.mode == CliMode::Markers && a.multi {
        bail!("--multi applies to --mode line only");
    }
    if a.mode == CliMode::Line && marker_opts {
        bail!("--max-area, --marker-size and --erode apply to --mode markers only");
    }
    Ok(())
}

/// Marker mode with its filter: the size given (`size`), or the most common blob size measured (the
/// histogram goes to `report` either way); also the size range used.
fn markers_mode(
    a: &Args,
    size: Option<(u32, u32)>,
    img: &RgbImage,
    opts: &DigitizeOptions,
    report: &mut String,
) -> anyhow::Result<(Mode, Option<(u32, u32)>)> {
    let mut filter = MarkerFilter {
        min_area: a.min_area,
        max_area: a.max_area,
        size,
        erode: a.erode,
    };
    let sizes = marker_sizes(img, opts, &filter)?;
    let picked = size.or(sizes.picked);
    report.push_str(&size_report(&sizes, picked, size.is_none()));
    filter.size = picked;
    Ok((Mode::Markers(filter), picked))
}

/// Writes the CSV, its check image and its plot beside each other. Everything is computed
/// before the first file is written; the files are staged beside the output folder and moved
/// into it together.
fn write_outputs(
    out: &Path,
    csv_text: &str,
    check: &RgbImage,
    plot: &XyPlot,
) -> anyhow::Result<Vec<PathBuf>> {
    let folder = out
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let file_name = out.file_name().unwrap_or_default();
    let stage = stage("--out", folder)?;
    let staged_out = stage.dir().join(file_name);
    let check_path = stem_with(&staged_out, "_check").with_extension("png");
    write_png(check, &check_path)?;
    let mut written = vec![staged_out.clone(), check_path];
    written.extend(write_xy(plot, &stem_with(&staged_out, "_plot"))?);
    write_text(&staged_out, csv_text)?;
    commit(stage, &written)
}

/// The CSV of the extracted points: the `constants` columns, then x and y.
fn csv_text(
    constants: &[(String, f64)],
    (x_name, y_name): (&str, &str),
    points: &[(f64, f64)],
) -> anyhow::Result<String> {
    let mut w = csv::Writer::from_writer(Vec::new());
    let header = constants.iter().map(|(n, _)| n.as_str());
    w.write_record(header.chain([x_name, y_name]))?;
    for &(px, py) in points {
        let row = constants.iter().map(|(_, v)| number(*v));
        w.write_record(row.chain([number(px), number(py)]))?;
    }
    Ok(String::from_utf8(w.into_inner()?)?)
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

/// One axis's calibration from `--A-cal` (two known pixels) or `--A-ticks` (tick values fitted
/// to the tick marks `found` in the image, first value to first mark); what was done is added to
/// `report`.
fn calibration(
    axis: &str,
    (cal, ticks): (Option<&str>, Option<&str>),
    log: bool,
    found: Option<Vec<f64>>,
    report: &mut String,
) -> anyhow::Result<AxisCalibration> {
    match (cal, ticks) {
        (Some(_), Some(_)) => bail!("give --{axis}-ticks or --{axis}-cal, not both"),
        (None, None) => bail!(
            "give --{axis}-ticks (the tick values; the frame and tick marks are found in the image), or --{axis}-cal with two known pixels"
        ),
        (Some(text), None) => {
            let flag = format!("--{axis}-cal");
            let [p1, v1, p2, v2] = numbers::<4>(&flag, text, "PX1:VAL1:PX2:VAL2")?;
            AxisCalibration::new(p1, v1, p2, v2, log).with_context(|| format!("{flag} '{text}'"))
        }
        (None, Some(text)) => {
            let flag = format!("--{axis}-ticks");
            let values = parse_tick_values(text).with_context(|| flag.clone())?;
            let Some(found) = found else {
                bail!("{flag}: no plot frame (long dark axis lines) found in the image; calibrate with --{axis}-cal");
            };
            let (c, worst) = calibrate_from_ticks(axis, &found, &values, log).with_context(|| flag.clone())?;
            if worst > 1.0 {
                bail!("{flag} '{text}': the tick marks found lie up to {worst:.1} px off a straight line through these values; check the values, or calibrate with --{axis}-cal");
            }
            let (first, last) = (found[0], found[found.len() - 1]);
            report.push_str(&format!(
                "{axis} axis: {} tick marks at pixels {first:.2} .. {last:.2} fitted to {} .. {} (largest tick residual {worst:.2} px)\n",
                found.len(),
                values[0],
                values[values.len() - 1]
            ));
            Ok(c)
        }
    }
}

/// The marker-size histogram and the size range used.
fn size_report(sizes: &MarkerSizes, used: Option<(u32, u32)>, measured: bool) -> String {
    let hist: Vec<String> = sizes
        .histogram
        .iter()
        .map(|(s, n)| format!("{s} px: {n}"))
        .collect();
    let range = used.map_or("none".to_string(), |(lo, hi)| format!("{lo}:{hi} px"));
    format!(
        "marker sizes found (blobs by the longer side of their bounding box): {}\nmarker size {} {range} (both sides of a marker must lie within it)\n",
        if hist.is_empty() { "none".into() } else { hist.join(", ") },
        if measured { "measured:" } else { "given:" },
    )
}

/// How many markers were found, how many were put back together from pieces, and what was left
/// out and why.
fn census_report(c: &MarkerCensus) -> String {
    format!(
        "{} marker(s) from {} blob(s), {} of them put back together from pieces cut by another curve; {}\n",
        c.points.len(),
        c.blobs,
        c.rejoined,
        c.left_out_text()
    )
}

/// A summary of the suspect points: counts per reason and the first few pixels.
fn suspect_text(suspects: &[((f64, f64), Suspicion)], total: usize) -> String {
    let mut s = format!(
        "{} of {total} points look like they are not the curve:",
        suspects.len()
    );
    for why in [
        Suspicion::Frame,
        Suspicion::Tick,
        Suspicion::OutsideFrame,
        Suspicion::BesideText,
    ] {
        let at: Vec<String> = suspects
            .iter()
            .filter(|s| s.1 == why)
            .map(|s| format!("({:.0}, {:.0})", s.0 .0, s.0 .1))
            .collect();
        if !at.is_empty() {
            let more = if at.len() > 4 { ", ..." } else { "" };
            s.push_str(&format!(
                "\n  {} {}: pixels {}{more}",
                at.len(),
                why.text(),
                at[..at.len().min(4)].join(", ")
            ));
        }
    }
    s
}
