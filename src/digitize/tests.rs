//! End-to-end checks of [`digitize`] on hand-made rasters.

use super::*;

const BLUE: Rgb = Rgb(0, 114, 178);

/// 40 x 30 white image with a blue 2-pixel-thick line y = 5 + c / 2 (rows from the top) and
/// a 3 x 3 blue square centred at (30, 25).
fn image() -> RgbImage {
    let (w, h) = (40u32, 30u32);
    let mut pixels = vec![[255u8; 3]; (w * h) as usize];
    let mut set = |x: u32, y: u32| pixels[(y * w + x) as usize] = [0, 110, 180];
    for c in 0..20 {
        set(c, 5 + c / 2);
        set(c, 6 + c / 2);
    }
    for x in 29..=31 {
        for y in 24..=26 {
            set(x, y);
        }
    }
    RgbImage {
        width: w,
        height: h,
        pixels,
    }
}

fn options(mode: Mode) -> DigitizeOptions {
    DigitizeOptions {
        // column 0 -> x = 100, column 20 -> x = 0 (a reversed axis)
        x: AxisCalibration::new(0.0, 100.0, 20.0, 0.0, false).unwrap(),
        // row 0 -> 1000, row 20 -> 10 on a log axis
        y: AxisCalibration::new(0.0, 1000.0, 20.0, 10.0, true).unwrap(),
        color: BLUE,
        tolerance: 10.0,
        mode,
        crop: Some(PixelBox {
            x0: 0,
            y0: 0,
            x1: 25,
            y1: 29,
        }),
    }
}

#[test]
fn line_points_are_in_data_units_and_sorted() {
    let pts = digitize(&image(), &options(Mode::Line { multi: false })).unwrap();
    assert_eq!(pts.len(), 20);
    assert!(pts.windows(2).all(|p| p[0].0 < p[1].0));
    // The last point is column 0: x = 100, centroid row 5.5.
    let (x, y) = pts[19];
    assert_eq!(x, 100.0);
    assert!((y - 10f64.powf(3.0 - 5.5 / 10.0)).abs() < 1e-9);
}

#[test]
fn markers_and_their_filter() {
    let mut o = options(Mode::Markers(MarkerFilter {
        min_area: 9,
        ..MarkerFilter::default()
    }));
    o.crop = None;
    let pts = extract_pixels(&image(), &o).unwrap();
    // The line is one blob of 40 pixels, the square one of 9.
    assert_eq!(pts.len(), 2);
    o.mode = Mode::Markers(MarkerFilter {
        min_area: 9,
        max_area: Some(20),
        ..MarkerFilter::default()
    });
    assert_eq!(extract_pixels(&image(), &o).unwrap(), [(30.0, 25.0)]);
    o.mode = Mode::Markers(MarkerFilter {
        min_area: 100,
        ..MarkerFilter::default()
    });
    let err = extract_pixels(&image(), &o).unwrap_err().to_string();
    assert!(err.contains("2 blob(s)"), "{err}");
}

#[test]
fn bad_options_are_errors() {
    let mut o = options(Mode::Line { multi: true });
    o.x.p2 = o.x.p1;
    assert!(digitize(&image(), &o).is_err());
    let mut o = options(Mode::Line { multi: true });
    o.crop = Some(PixelBox {
        x0: 0,
        y0: 0,
        x1: 40,
        y1: 10,
    });
    assert!(digitize(&image(), &o).is_err());
    let mut o = options(Mode::Line { multi: true });
    o.color = Rgb(255, 0, 0);
    let err = digitize(&image(), &o).unwrap_err().to_string();
    assert!(err.contains("no pixel of colour #ff0000"), "{err}");
}
