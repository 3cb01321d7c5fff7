//! Renders one figure of each kind with synthetic data, for eyeballing the plot module:
//! `cargo run --example plot_gallery -- [out_dir]` (default `target/plot-gallery`).

use std::path::PathBuf;

use geardyn::plot::{
    write_category_map, write_panels, write_xy, CategoryMap, Marker, Series, XyPlot,
};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = PathBuf::from(
        std::env::args()
            .nth(1)
            .unwrap_or_else(|| "target/plot-gallery".into()),
    );

    // Frequency response: a softening resonance with jump, an unstable branch, marked windows.
    let omega: Vec<f64> = (0..400).map(|i| 0.3 + 1.5 * i as f64 / 399.0).collect();
    let amp = |w: f64, shift: f64| 1.0 / ((1.0 - (w + shift).powi(2)).powi(2) + 0.01).sqrt();
    let upper: Vec<_> = omega
        .iter()
        .filter(|&&w| w < 1.05)
        .map(|&w| (w, amp(w, 0.0)))
        .collect();
    let lower: Vec<_> = omega
        .iter()
        .filter(|&&w| w > 0.85)
        .map(|&w| (w, amp(w, 0.3)))
        .collect();
    let unstable: Vec<_> = omega
        .iter()
        .filter(|&&w| (0.85..1.05).contains(&w))
        .map(|&w| (w, 0.5 * (amp(w, 0.0) + amp(w, 0.3))))
        .collect();
    let sim: Vec<_> = omega
        .iter()
        .step_by(12)
        .map(|&w| (w, amp(w, 0.02) * 0.98))
        .collect();
    let mut with_nan = sim.clone();
    with_nan[5].1 = f64::NAN;
    let fr = XyPlot::new("Frequency response", "Omega", "RMS of x")
        .with_caption("zeta = 0.05, Fm = 0.1, Fa = 0.2, b = 1")
        .with_series(Series::line("HBM stable", upper))
        .with_series(Series::line("HBM stable (lower)", lower).with_color(0))
        .with_series(Series::dashed("HBM unstable", unstable))
        .with_series(Series::markers("simulation", with_nan).with_marker(Marker::Triangle))
        .with_vline(0.5, "Omega = 1/2")
        .with_vline(1.0, "Omega = 1")
        .with_band(0.85, 1.05);
    report(write_xy(&fr, &dir.join("frequency_response"))?);

    // Panels: time history, phase plane, Poincaré section, empty panel.
    let t: Vec<f64> = (0..3000).map(|i| i as f64 * 0.02).collect();
    let x = |t: f64| (t).sin() + 0.3 * (2.7 * t).sin();
    let v = |t: f64| (t).cos() + 0.81 * (2.7 * t).cos();
    let history = XyPlot::new("Time history", "t", "x")
        .with_series(Series::line("x(t)", t.iter().map(|&t| (t, x(t))).collect()));
    let phase = XyPlot::new("Phase plane", "x", "x'")
        .with_caption("last 3000 samples")
        .with_series(Series::line("", t.iter().map(|&t| (x(t), v(t))).collect()).with_color(2));
    let poincare = XyPlot::new("Poincaré section", "x", "x'").with_series(
        Series::markers(
            "section",
            (0..2000)
                .map(|k| {
                    let t = k as f64 * 2.0 * std::f64::consts::PI / 1.3;
                    (x(t), v(t))
                })
                .collect(),
        )
        .with_marker(Marker::Dot)
        .with_color(1),
    );
    let spectrum = XyPlot::new("Spectrum", "frequency", "amplitude")
        .with_y_range(0.0, 1.2)
        .with_series(
            Series::line_markers(
                "|X|",
                vec![(1.0, 1.0), (2.0, 0.02), (2.7, 0.3), (3.0, 0.01)],
            )
            .with_marker(Marker::Square),
        )
        .with_series(Series::line("empty", vec![]));
    report(write_panels(
        "Response at Omega = 1.3",
        &[history, phase, poincare, spectrum],
        2,
        &dir.join("panels"),
    )?);

    // Basins of attraction on a 201 x 201 grid.
    let n = 201;
    let cells = (0..n * n)
        .map(|k| {
            let (i, j) = (k % n, k / n);
            let (px, py) = (-2.0 + 4.0 * i as f64 / 200.0, -1.5 + 3.0 * j as f64 / 200.0);
            let s = (3.0 * px).sin() + py * py - 0.5 * px * py;
            match () {
                _ if (px * px + py * py) < 0.05 => None,
                _ if s > 0.8 => Some(2),
                _ if s > 0.0 => Some(1),
                _ => Some(0),
            }
        })
        .collect();
    let map = CategoryMap {
        title: "Basins of attraction".into(),
        caption: Some("Omega = 1.2, 201 x 201 initial conditions".into()),
        x_label: "x(0)".into(),
        y_label: "x'(0)".into(),
        x: (-2.0, 2.0, n),
        y: (-1.5, 1.5, n),
        cells,
        legend: vec![
            "period 1, no impact".into(),
            "period 1, single-sided".into(),
            "chaos".into(),
        ],
    };
    let t0 = std::time::Instant::now();
    report(write_category_map(&map, &dir.join("basins"))?);
    println!("basins rendered in {:.3} s", t0.elapsed().as_secs_f64());
    Ok(())
}

fn report(files: Vec<PathBuf>) {
    for f in files {
        println!("{}", f.display());
    }
}
