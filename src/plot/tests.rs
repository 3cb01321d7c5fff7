//! Writer-level tests: every figure kind produces a PNG and an SVG, and hostile data is handled.

use std::path::{Path, PathBuf};

use super::*;
use crate::error::GearError;

const PNG_SIGNATURE: &[u8] = b"\x89PNG\r\n\x1a\n";

fn check_outputs(files: &[PathBuf], stem: &Path) -> String {
    assert_eq!(files.len(), 2);
    assert_eq!(files[0], PathBuf::from(format!("{}.png", stem.display())));
    assert_eq!(files[1], PathBuf::from(format!("{}.svg", stem.display())));
    let png = std::fs::read(&files[0]).unwrap();
    assert!(png.len() > 1000, "png too small");
    assert!(png.starts_with(PNG_SIGNATURE));
    let svg = std::fs::read_to_string(&files[1]).unwrap();
    assert!(svg.contains("<svg"));
    svg
}

fn sine(n: usize) -> Vec<(f64, f64)> {
    (0..n)
        .map(|i| {
            let t = i as f64 * 0.05;
            (t, t.sin())
        })
        .collect()
}

fn sample_plot() -> XyPlot {
    XyPlot::new("Sine", "t", "x")
        .with_caption("zeta = 0.05")
        .with_series(Series::line("sin", sine(200)))
        .with_series(Series::markers("samples", sine(20)).with_marker(Marker::Square))
        .with_series(Series::dashed("ref", vec![(0.0, 0.0), (10.0, 0.0)]).with_color(6))
        .with_vline(3.0, "a")
        .with_band(5.0, 6.0)
}

#[test]
fn xy_writes_png_and_svg_with_real_text() {
    let dir = tempfile::tempdir().unwrap();
    let stem = dir.path().join("nested/deeper/sine");
    let files = write_xy(&sample_plot(), &stem).unwrap();
    let svg = check_outputs(&files, &stem);
    assert!(svg.contains("<text"));
    assert!(svg.contains("Sine") && svg.contains("ζ = 0.05") && svg.contains("samples"));
}

#[test]
fn stem_with_dot_keeps_its_name() {
    let dir = tempfile::tempdir().unwrap();
    let stem = dir.path().join("run.v2");
    let files = write_xy(&sample_plot(), &stem).unwrap();
    check_outputs(&files, &stem);
}

#[test]
fn hostile_series_do_not_panic() {
    let dir = tempfile::tempdir().unwrap();
    let nan = f64::NAN;
    let inf = f64::INFINITY;
    let cases = vec![
        vec![Series::line("empty", vec![])],
        vec![Series::line(
            "nan",
            vec![(nan, nan), (1.0, nan), (inf, 2.0)],
        )],
        vec![Series::line(
            "mixed",
            vec![(0.0, 1.0), (nan, 2.0), (2.0, 3.0), (3.0, inf)],
        )],
        vec![Series::markers("one", vec![(1.0, 1.0)])],
        vec![Series::line("one", vec![(1.0, 1.0)])],
        vec![Series::line_markers("flat", vec![(1.0, 5.0), (1.0, 5.0)])],
        vec![Series::line("big", vec![(-1e300, 1e-300), (1e300, 2e-300)])],
        vec![],
    ];
    for (k, series) in cases.into_iter().enumerate() {
        let plot = XyPlot {
            series,
            ..XyPlot::new("t", "x", "y")
        };
        let stem = dir.path().join(format!("case{k}"));
        let files = write_xy(&plot, &stem).unwrap();
        check_outputs(&files, &stem);
    }
}

#[test]
fn fixed_ranges_clip_and_bad_ranges_error() {
    let dir = tempfile::tempdir().unwrap();
    let plot = sample_plot().with_x_range(2.0, 4.0).with_y_range(-0.5, 0.5);
    check_outputs(
        &write_xy(&plot, &dir.path().join("zoom")).unwrap(),
        &dir.path().join("zoom"),
    );
    let bad = sample_plot().with_x_range(4.0, 2.0);
    assert!(matches!(
        write_xy(&bad, &dir.path().join("bad")),
        Err(GearError::InvalidParameter { .. })
    ));
    let bad = sample_plot().with_y_range(f64::NAN, 1.0);
    assert!(write_xy(&bad, &dir.path().join("bad")).is_err());
}

#[test]
fn panels_write_a_grid() {
    let dir = tempfile::tempdir().unwrap();
    let panels = vec![sample_plot(), XyPlot::new("empty", "a", "b"), sample_plot()];
    let stem = dir.path().join("grid");
    let svg = check_outputs(
        &write_panels("Three panels", &panels, 2, &stem).unwrap(),
        &stem,
    );
    assert!(svg.contains("Three panels"));
    assert!(write_panels("x", &panels, 0, &stem).is_err());
    assert!(write_panels("x", &[], 2, &stem).is_err());
}

fn sample_map(nx: usize, ny: usize) -> CategoryMap {
    let cells = (0..nx * ny)
        .map(|k| {
            let (i, j) = ((k % nx) as f64 / nx as f64, (k / nx) as f64 / ny as f64);
            let r = (i - 0.5).hypot(j - 0.5);
            match () {
                _ if r < 0.2 => Some(0),
                _ if r < 0.3 => None,
                _ if i > j => Some(1),
                _ => Some(3),
            }
        })
        .collect();
    CategoryMap {
        title: "Basins".into(),
        caption: Some("Omega = 1.2".into()),
        x_label: "x(0)".into(),
        y_label: "x'(0)".into(),
        x: (-2.0, 2.0, nx),
        y: (-1.0, 1.0, ny),
        cells,
        legend: vec!["period 1".into(), "period 2".into()],
    }
}

#[test]
fn category_map_writes_both_files() {
    let dir = tempfile::tempdir().unwrap();
    let stem = dir.path().join("basins");
    let svg = check_outputs(
        &write_category_map(&sample_map(201, 201), &stem).unwrap(),
        &stem,
    );
    assert!(svg.contains("period 2") && svg.contains("category 3") && svg.contains("unclassified"));
    let one = CategoryMap {
        x: (1.0, 1.0, 1),
        y: (0.0, 0.0, 1),
        cells: vec![Some(0)],
        ..CategoryMap::default()
    };
    check_outputs(&write_category_map(&one, &stem).unwrap(), &stem);
}

#[test]
fn mismatched_category_map_errors() {
    let dir = tempfile::tempdir().unwrap();
    let mut map = sample_map(10, 10);
    map.cells.pop();
    let stem = dir.path().join("bad");
    assert!(matches!(
        write_category_map(&map, &stem),
        Err(GearError::InvalidParameter { name: "cells", .. })
    ));
    assert!(!stem.with_extension("png").exists());
    map.x.2 = 0;
    map.cells.clear();
    assert!(write_category_map(&map, &stem).is_err());
}

#[test]
fn every_colour_has_3_to_1_contrast_on_white() {
    use super::style::contrast_on_white;
    use plotters::style::RGBColor;
    // WCAG reference values: black 21:1, white 1:1, #767676 4.54:1 (the lightest grey at 4.5:1).
    assert!((contrast_on_white(RGBColor(0, 0, 0)) - 21.0).abs() < 1e-9);
    assert!((contrast_on_white(RGBColor(255, 255, 255)) - 1.0).abs() < 1e-9);
    assert!((contrast_on_white(RGBColor(0x76, 0x76, 0x76)) - 4.54).abs() < 0.01);
    for (i, c) in PALETTE
        .iter()
        .chain([&super::map::UNCLASSIFIED])
        .enumerate()
    {
        assert!(contrast_on_white(*c) >= 3.0, "colour {i} {c:?}");
    }
}
