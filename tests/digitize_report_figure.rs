//! `geardyn digitize` on a figure where the measured markers lie under other curves: geardyn's
//! own report figure for Munro's 1890 N curve (tests/data/digitize/geardyn_report_1890.png, a
//! copy of reports/munro/load_1890.png), whose model lines cross every square of the set's
//! 81 points (the truth: the 1890 N rows of data/munro/dte.csv). Each square is cut into pieces
//! that only a rejoining step puts back together.

mod common;

use std::path::{Path, PathBuf};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/digitize")
        .join(name)
}

/// Pixels per data unit: the x ticks 1000..5000 rpm span 808 px, the y ticks 0..70 um 347 px.
const X_PER_RPM: f64 = 808.0 / 4000.0;
const Y_PER_UM: f64 = 347.0 / 70.0;

#[test]
fn markers_cut_by_model_lines_are_put_back_together() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("d.csv");
    let image = data("geardyn_report_1890.png");
    let r = common::geardyn(&[
        "digitize",
        "--image",
        image.to_str().unwrap(),
        "--color",
        "0072B2",
        "--x-ticks",
        "1000:5000:1000",
        "--y-ticks",
        "0:70:10",
        "--mode",
        "markers",
        "--columns",
        "speed_rpm,dte_pp_um",
        "--out",
        out.to_str().unwrap(),
    ]);
    let stdout = String::from_utf8_lossy(&r.stdout);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    assert!(stdout.contains("put back together"), "{stdout}");
    let got = common::read_xy_csv(&out);
    let truth = common::read_xy_csv(&data("geardyn_report_1890_truth.csv"));
    assert_eq!(got.len(), truth.len(), "every marker found once");
    // Sorted by speed, the i-th point is the i-th marker. A marker whose edge lies under a
    // 3 px line loses up to half of that from its bounding box, so a point may be off by up to
    // 2 px; on average the points are within a pixel.
    let mut sum = 0.0;
    for (g, t) in got.iter().zip(&truth) {
        let (dx, dy) = ((g.0 - t.0) * X_PER_RPM, (g.1 - t.1) * Y_PER_UM);
        assert!(dx.abs() < 2.0 && dy.abs() < 2.0, "{g:?} vs {t:?}");
        sum += dx.hypot(dy);
    }
    assert!(
        sum / (got.len() as f64) < 1.0,
        "mean {} px",
        sum / got.len() as f64
    );
}
