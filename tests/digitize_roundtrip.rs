//! Round trip of `digitize`: plotters draws known curves at a known pixel geometry, the
//! digitizer reads them back, and every recovered point must lie on the true curve to within
//! the pixel quantisation of the drawing.
//!
//! Tolerance, per axis, in data units: 1.5 x (axis data range / plot-area size in pixels).
//! Plotters places each vertex at the floor of its exact pixel position (up to 1 px off), and
//! a 2-px stroke is rasterised from vertex +- 1 px truncated to whole pixels, which can move the
//! centroid of a column's pixels by up to another 0.5 px; 1 + 0.5 = 1.5 px. The x coordinate of a
//! line point is its pixel column, exact; on a steep stretch the column's centroid lies on the
//! curve within the same 1.5 px measured along x, so a point passes when the true curve comes
//! within 1.5 px in y of it somewhere within 1.5 px in x of it.

mod common;

use geardyn::digitize::{
    digitize, AxisCalibration, DigitizeOptions, MarkerFilter, Mode, PixelBox, Rgb, RgbImage,
};
use plotters::coord::ranged1d::Ranged;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use std::path::Path;

const W: u32 = 900;
const H: u32 = 600;
const X_RANGE: (f64, f64) = (0.0, 10.0);
const LINE: RGBColor = RGBColor(0x00, 0x72, 0xB2);
const MARK: RGBColor = RGBColor(0xD5, 0x5E, 0x00);
const HOLLOW: RGBColor = RGBColor(0x00, 0x9E, 0x73);
/// Marker abscissae: 10 filled squares, 10 hollow ones.
const MARKER_X: [f64; 10] = [0.5, 1.5, 2.5, 3.5, 4.5, 5.5, 6.5, 7.5, 8.5, 9.5];

/// The true curves of one figure (y values in data units), kept apart by at least 25 px so
/// that no curve covers another's pixels.
struct Truth {
    log: bool,
    y_range: (f64, f64),
    line: fn(f64) -> f64,
    filled: fn(f64) -> f64,
    hollow: fn(f64) -> f64,
}

const LINEAR: Truth = Truth {
    log: false,
    y_range: (-2.0, 2.0),
    line: |x| 0.7 * (0.8 * x).sin() + 0.25 * (2.3 * x).cos() + 0.9,
    filled: |x| 0.3 * (0.6 * x).cos() - 0.9,
    hollow: |x| 0.2 * (0.5 * x).sin() - 1.65,
};

const LOG_Y: Truth = Truth {
    log: true,
    y_range: (0.01, 100.0),
    line: |x| 10f64.powf(0.8 * (0.7 * x).sin() + 0.6),
    filled: |x| 10f64.powf(-0.8 + 0.2 * (0.5 * x).cos()),
    hollow: |x| 10f64.powf(-1.6 + 0.2 * x / 10.0),
};

/// A drawn figure: the raster, the calibration read off the chart and the plot-area box.
struct Figure {
    img: RgbImage,
    x: AxisCalibration,
    y: AxisCalibration,
    plot: PixelBox,
}

/// Draws the three curves of `t` plus a black frame and a legend sample of the line colour
/// outside the plot area.
fn draw(t: &Truth) -> Figure {
    let mut buf = vec![0u8; (W * H * 3) as usize];
    let (x, y, plot) = {
        let root = BitMapBackend::with_buffer(&mut buf, (W, H)).into_drawing_area();
        root.fill(&WHITE).unwrap();
        let builder = || {
            let mut b = ChartBuilder::on(&root);
            b.margin(30).x_label_area_size(50).y_label_area_size(70);
            b
        };
        let x_axis = X_RANGE.0..X_RANGE.1;
        let (y_lo, y_hi) = t.y_range;
        if t.log {
            let mut chart = builder()
                .build_cartesian_2d(x_axis, (y_lo..y_hi).log_scale())
                .unwrap();
            content(&mut chart, t)
        } else {
            let mut chart = builder().build_cartesian_2d(x_axis, y_lo..y_hi).unwrap();
            content(&mut chart, t)
        }
    };
    // Legend sample in the top margin, in the line colour (must be cropped away).
    for y in 8..11 {
        for x in 700..760 {
            let i = ((y * W + x) * 3) as usize;
            buf[i..i + 3].copy_from_slice(&[LINE.0, LINE.1, LINE.2]);
        }
    }
    Figure {
        img: RgbImage::from_rgb_bytes(W, H, &buf).unwrap(),
        x,
        y,
        plot,
    }
}

type Chart<'a, 'b, Y> = ChartContext<'a, BitMapBackend<'b>, Cartesian2d<RangedCoordf64, Y>>;

fn content<Y: Ranged<ValueType = f64>>(
    chart: &mut Chart<'_, '_, Y>,
    t: &Truth,
) -> (AxisCalibration, AxisCalibration, PixelBox) {
    let (y_lo, y_hi) = t.y_range;
    let n = 3000;
    let line = (0..=n).map(|i| {
        let x = X_RANGE.0 + (X_RANGE.1 - X_RANGE.0) * i as f64 / n as f64;
        (x, (t.line)(x))
    });
    chart
        .draw_series(LineSeries::new(line, LINE.stroke_width(2)))
        .unwrap();
    // Filled squares joined by a thin line of their colour ("-[]-"): erosion separates them.
    let filled: Vec<(f64, f64)> = MARKER_X.iter().map(|&x| (x, (t.filled)(x))).collect();
    chart
        .draw_series(LineSeries::new(filled.clone(), MARK.stroke_width(1)))
        .unwrap();
    chart
        .draw_series(
            filled
                .iter()
                .map(|&p| EmptyElement::at(p) + Rectangle::new([(-5, -5), (5, 5)], MARK.filled())),
        )
        .unwrap();
    // Hollow squares, as the paper's Munro data.
    chart
        .draw_series(MARKER_X.iter().map(|&x| {
            EmptyElement::at((x, (t.hollow)(x)))
                + Rectangle::new([(-5, -5), (5, 5)], HOLLOW.stroke_width(1))
        }))
        .unwrap();
    let (px0, py0) = chart.backend_coord(&(X_RANGE.0, y_lo));
    let (px1, py1) = chart.backend_coord(&(X_RANGE.1, y_hi));
    let (xr, yr) = chart.plotting_area().get_pixel_range();
    // Axis frame in black.
    let frame = [(xr.start, yr.start), (xr.end - 1, yr.end - 1)];
    chart
        .plotting_area()
        .strip_coord_spec()
        .draw(&Rectangle::new(
            [(0, 0), (frame[1].0 - frame[0].0, frame[1].1 - frame[0].1)],
            BLACK.stroke_width(1),
        ))
        .unwrap();
    let cal = |p1: i32, v1: f64, p2: i32, v2: f64, log: bool| {
        AxisCalibration::new(f64::from(p1), v1, f64::from(p2), v2, log).unwrap()
    };
    (
        cal(px0, X_RANGE.0, px1, X_RANGE.1, false),
        cal(py0, y_lo, py1, y_hi, t.log),
        PixelBox {
            x0: xr.start as u32,
            y0: yr.start as u32,
            x1: (xr.end - 1) as u32,
            y1: (yr.end - 1) as u32,
        },
    )
}

/// Tolerances (x in data units, y in data units or decades on a log axis), see the file header.
fn tolerances(f: &Figure, t: &Truth) -> (f64, f64) {
    let y_span = if t.log {
        (t.y_range.1 / t.y_range.0).log10()
    } else {
        t.y_range.1 - t.y_range.0
    };
    (
        1.5 * (X_RANGE.1 - X_RANGE.0) / (f.x.p2 - f.x.p1).abs(),
        1.5 * y_span / (f.y.p2 - f.y.p1).abs(),
    )
}

fn y_gap(t: &Truth, a: f64, b: f64) -> f64 {
    if t.log {
        (a.log10() - b.log10()).abs()
    } else {
        (a - b).abs()
    }
}

fn options(f: &Figure, color: RGBColor, mode: Mode, crop: bool) -> DigitizeOptions {
    DigitizeOptions {
        x: f.x,
        y: f.y,
        color: Rgb(color.0, color.1, color.2),
        tolerance: 60.0,
        mode,
        crop: crop.then_some(f.plot),
    }
}

/// Every point lies on `curve` within the tolerances; returns the largest miss in pixels.
fn check_line(f: &Figure, t: &Truth, pts: &[(f64, f64)]) -> Result<f64, String> {
    let (tx, ty) = tolerances(f, t);
    let mut worst = 0.0f64;
    for &(x, y) in pts {
        let gap = (0..=60)
            .map(|k| x - tx + 2.0 * tx * k as f64 / 60.0)
            .map(|s| y_gap(t, (t.line)(s), y))
            .fold(f64::INFINITY, f64::min);
        worst = worst.max(1.5 * gap / ty);
        if gap > ty {
            return Err(format!(
                "point ({x}, {y}) is {gap} from the curve (tol {ty})"
            ));
        }
    }
    Ok(worst)
}

fn check_markers(f: &Figure, t: &Truth, pts: &[(f64, f64)], curve: fn(f64) -> f64) {
    let (tx, ty) = tolerances(f, t);
    assert_eq!(pts.len(), MARKER_X.len(), "marker count: {pts:?}");
    for (&(x, y), &x_true) in pts.iter().zip(&MARKER_X) {
        assert!((x - x_true).abs() <= tx, "marker x {x} vs {x_true}");
        let gap = y_gap(t, y, curve(x_true));
        assert!(
            gap <= ty,
            "marker at x {x_true}: y {y} vs {}",
            curve(x_true)
        );
    }
}

fn roundtrip(t: &Truth) {
    let f = draw(t);
    let line = digitize(
        &f.img,
        &options(&f, LINE, Mode::Line { multi: false }, true),
    )
    .unwrap();
    let width = f.plot.x1 - f.plot.x0 + 1;
    assert!(
        line.len() as f64 >= 0.95 * f64::from(width),
        "{} points",
        line.len()
    );
    let worst = check_line(&f, t, &line).unwrap();
    assert!(worst <= 1.5, "worst miss {worst} px");

    // Without the crop the legend sample in the margin shares columns with the curve: each
    // column keeps the run nearest the previous point, so the curve's own columns stay on it.
    let all = digitize(
        &f.img,
        &options(&f, LINE, Mode::Line { multi: false }, false),
    )
    .unwrap();
    let shared: Vec<(f64, f64)> = all
        .iter()
        .copied()
        .filter(|p| line.iter().any(|q| q.0 == p.0))
        .collect();
    assert!(shared.len() >= line.len() * 9 / 10);
    assert!(check_line(&f, t, &shared).unwrap() <= 1.5);

    let filled = Mode::Markers(MarkerFilter {
        min_area: 20,
        erode: 1,
        ..MarkerFilter::default()
    });
    let pts = digitize(&f.img, &options(&f, MARK, filled, true)).unwrap();
    check_markers(&f, t, &pts, t.filled);

    let hollow = Mode::Markers(MarkerFilter {
        min_area: 20,
        size: Some((8, 14)),
        ..MarkerFilter::default()
    });
    let pts = digitize(&f.img, &options(&f, HOLLOW, hollow, true)).unwrap();
    check_markers(&f, t, &pts, t.hollow);
}

#[test]
fn linear_axes_roundtrip() {
    roundtrip(&LINEAR);
}

#[test]
fn log_y_axis_roundtrip() {
    roundtrip(&LOG_Y);
}

/// Writes the figure as an RGBA PNG (exercising the alpha path of the reader).
fn write_png(f: &Figure, path: &Path) {
    let file = std::fs::File::create(path).unwrap();
    let mut enc = png::Encoder::new(std::io::BufWriter::new(file), W, H);
    enc.set_color(png::ColorType::Rgba);
    enc.set_depth(png::BitDepth::Eight);
    let data: Vec<u8> = f
        .img
        .pixels
        .iter()
        .flat_map(|p| [p[0], p[1], p[2], 255])
        .collect();
    enc.write_header().unwrap().write_image_data(&data).unwrap();
}

fn cal_arg(c: &AxisCalibration) -> String {
    format!("{}:{}:{}:{}", c.p1, c.v1, c.p2, c.v2)
}

#[test]
fn cli_writes_csv_and_check_plot() {
    let dir = tempfile::tempdir().unwrap();
    let f = draw(&LINEAR);
    let image = dir.path().join("fig.png");
    write_png(&f, &image);
    let out = dir.path().join("munro").join("load_1890.csv");
    let crop = format!("{}:{}:{}:{}", f.plot.x0, f.plot.y0, f.plot.x1, f.plot.y1);
    let (x_cal, y_cal) = (cal_arg(&f.x), cal_arg(&f.y));
    let (image_s, out_s) = (image.to_str().unwrap(), out.to_str().unwrap());
    let base = [
        "digitize",
        "--image",
        image_s,
        "--x-cal",
        &x_cal,
        "--y-cal",
        &y_cal,
        "--crop",
        &crop,
        "--columns",
        "speed_rpm,dte_pp_um",
        "--const",
        "load_n=1890",
        "--out",
        out_s,
    ];

    let mut args = base.to_vec();
    args.extend(["--color", "d55e00", "--mode", "markers", "--erode", "1"]);
    args.extend(["--min-area", "20"]);
    let run = common::geardyn(&args);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(stdout.contains("extracted 10 points"), "{stdout}");
    let csv = std::fs::read_to_string(&out).unwrap();
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some("load_n,speed_rpm,dte_pp_um"));
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 10);
    let pts: Vec<(f64, f64)> = rows.iter().map(|r| (r[1], r[2])).collect();
    assert!(rows.iter().all(|r| r[0] == 1890.0));
    check_markers(&f, &LINEAR, &pts, LINEAR.filled);
    for file in [
        "load_1890_check.png",
        "load_1890_plot.png",
        "load_1890_plot.svg",
    ] {
        assert!(dir.path().join("munro").join(file).is_file(), "{file}");
    }

    let mut args = base.to_vec();
    args.extend(["--color", "#0072B2"]);
    let run = common::geardyn(&args);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let csv = std::fs::read_to_string(&out).unwrap();
    let pts: Vec<(f64, f64)> = csv
        .lines()
        .skip(1)
        .map(|l| {
            let v: Vec<f64> = l.split(',').map(|v| v.parse().unwrap()).collect();
            (v[1], v[2])
        })
        .collect();
    assert!(pts.len() > 700);
    check_line(&f, &LINEAR, &pts).unwrap();
}

#[test]
fn cli_bad_input_leaves_no_output() {
    let dir = tempfile::tempdir().unwrap();
    let f = draw(&LINEAR);
    let image = dir.path().join("fig.png");
    write_png(&f, &image);
    std::fs::write(dir.path().join("junk.png"), b"not an image").unwrap();
    let out = dir.path().join("out").join("curve.csv");
    let (x_cal, y_cal) = (cal_arg(&f.x), cal_arg(&f.y));
    let run = |image: &str, extra: &[&str], needle: &str| {
        let image = dir.path().join(image);
        let mut args = vec![
            "digitize",
            "--image",
            image.to_str().unwrap(),
            "--columns",
            "x_hz,y_um",
            "--out",
            out.to_str().unwrap(),
        ];
        for flag in [["--x-cal", x_cal.as_str()], ["--y-cal", y_cal.as_str()]] {
            if !extra.contains(&flag[0]) {
                args.extend(flag);
            }
        }
        if !extra.contains(&"--color") {
            args.extend(["--color", "0072b2"]);
        }
        args.extend(extra);
        let o = common::geardyn(&args);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{extra:?} should fail");
        assert!(!err.contains("panicked"), "{err}");
        assert!(err.contains(needle), "{extra:?}: '{err}' lacks '{needle}'");
        assert!(o.stdout.is_empty());
        assert!(!dir.path().join("out").exists(), "{extra:?} left output");
    };
    run(
        "fig.png",
        &["--crop", "0:0:900:10"],
        "outside the image of 900 x 600",
    );
    run(
        "fig.png",
        &["--x-cal", "100:0:100:10"],
        "calibration pixels must differ",
    );
    run("fig.png", &["--y-cal", "1:2:3"], "PX1:VAL1:PX2:VAL2");
    run(
        "fig.png",
        &["--y-cal", "500:0:100:10", "--y-log"],
        "log axis",
    );
    run(
        "fig.png",
        &["--color", "ff00ff"],
        "no pixel of colour #ff00ff",
    );
    run("fig.png", &["--color", "blue"], "RRGGBB");
    run("junk.png", &[], "not a readable PNG");
    run("missing.png", &[], "missing.png");
    run("fig.png", &["--const", "load_n=-"], "not a finite number");
    run("fig.png", &["--erode", "1"], "--mode markers only");
}
