//! `geardyn digitize` on a figure another tool drew in its own style (matplotlib's defaults: a
//! box frame, outward ticks, a legend inside the plot), made by
//! tests/data/digitize/make_matplotlib_figure.py with its truth beside it. Only the tick values
//! are typed: the frame and tick marks are found in the image.

mod common;

use std::path::{Path, PathBuf};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/digitize")
        .join(name)
}

/// The curve the figure draws (see the script).
fn curve(x: f64) -> f64 {
    let r = x / 3400.0;
    2.0 + 6.0 / ((1.0 - r * r).powi(2) + (0.25 * r).powi(2)).sqrt()
}

/// Data units per pixel on the figure's axes: x 4000 rpm over 564 px, y 30 um over 361 px
/// (the tick marks' spacing).
const X_PX: f64 = 4000.0 / 564.0;
const Y_PX: f64 = 30.0 / 361.0;

fn run(out: &Path, extra: &[&str]) -> std::process::Output {
    run_ticks(out, "1500:5500:500", extra)
}

fn run_ticks(out: &Path, x_ticks: &str, extra: &[&str]) -> std::process::Output {
    let image = data("matplotlib_resonance.png");
    let mut args = vec![
        "digitize",
        "--image",
        image.to_str().unwrap(),
        "--x-ticks",
        x_ticks,
        "--y-ticks",
        "0:30:5",
        "--columns",
        "speed_rpm,dte_pp_um",
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend(extra);
    common::geardyn(&args)
}

#[test]
fn markers_with_tick_values_only_match_the_truth_and_the_legend_marker_is_caught() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("dte.csv");
    // The legend's sample marker lies beside its text: an error, and nothing written.
    let r = run(&out, &["--color", "1f77b4", "--mode", "markers"]);
    let err = String::from_utf8_lossy(&r.stderr);
    assert!(!r.status.success(), "{err}");
    assert!(
        err.contains("1 of 22 points") && err.contains("beside text"),
        "{err}"
    );
    assert!(
        err.contains("marker sizes found") && err.contains("9 px: 22"),
        "{err}"
    );
    assert!(!out.exists());

    let r = run(
        &out,
        &["--color", "1f77b4", "--mode", "markers", "--allow-suspect"],
    );
    let stdout = String::from_utf8_lossy(&r.stdout);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    assert!(stdout.contains("x axis: 9 tick marks") && stdout.contains("y axis: 7 tick marks"));
    let got = common::read_xy_csv(&out);
    let truth = common::read_xy_csv(&data("matplotlib_truth.csv"));
    assert_eq!(got.len(), 22, "21 markers and the legend's");
    // Every true marker is found within 0.6 px on both axes (matplotlib snaps markers to whole
    // pixels: up to half a pixel, plus the centroid of an anti-aliased edge).
    for &(x, y) in &truth {
        let best = got
            .iter()
            .map(|&(gx, gy)| ((gx - x) / X_PX).abs().max(((gy - y) / Y_PX).abs()))
            .fold(f64::INFINITY, f64::min);
        assert!(best <= 0.6, "marker at {x} rpm found {best:.2} px off");
    }
    for f in ["dte_check.png", "dte_plot.png", "dte_plot.svg"] {
        assert!(dir.path().join(f).is_file(), "{f}");
    }
}

#[test]
fn line_with_tick_values_only_follows_the_curve() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("line.csv");
    // Searched inside the frame by default, the legend's red sample line is caught...
    let r = run(&out, &["--color", "d62728"]);
    let err = String::from_utf8_lossy(&r.stderr);
    assert!(!r.status.success() && err.contains("beside text"), "{err}");
    // ...and a crop below the legend leaves the curve alone.
    let r = run(&out, &["--color", "d62728", "--crop", "102:114:718:443"]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let got = common::read_xy_csv(&out);
    assert!(got.len() > 400, "{} points", got.len());
    // Within 1.2 px of the true curve, along y plus the slope's share of a 1.2 px x error:
    // matplotlib snaps tick marks to whole pixels but not the line (the ticks lie up to 0.43 px
    // off a straight line, and the line reads 0.57 px above the ticks' calibration on average),
    // and the 2 px anti-aliased line is read at its run's middle (half a pixel).
    let mut mean_offset = 0.0;
    for &(x, y) in &got {
        let slope = (curve(x + 1.0) - curve(x - 1.0)) / 2.0;
        let tol = 1.2 * Y_PX + (slope * 1.2 * X_PX).abs();
        mean_offset += (y - curve(x)) / Y_PX / got.len() as f64;
        assert!(
            (y - curve(x)).abs() <= tol,
            "at {x} rpm: {y} vs {}",
            curve(x)
        );
    }
    assert!(mean_offset.abs() < 0.8, "mean offset {mean_offset:.2} px");
}

#[test]
fn wrong_tick_count_names_the_marks_found() {
    let dir = tempfile::tempdir().unwrap();
    let r = run_ticks(
        &dir.path().join("x.csv"),
        "1500:5000:500",
        &["--color", "d62728"],
    );
    let err = String::from_utf8_lossy(&r.stderr);
    assert!(!r.status.success());
    assert!(
        err.contains("8 tick values given but 9 tick marks found") && err.contains("128.0"),
        "{err}"
    );
}
