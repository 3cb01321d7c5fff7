//! Figures of `geardyn simulate --out DIR`: time history, phase plane and Poincare map of the
//! steady state (as the paper's Figs 2, 4, 5, 7, 8), with the sampled history as CSV.

use super::common::write_text;
use geardyn::plot::{write_xy, Series, XyPlot};
use geardyn::sim::{sample_trajectory, PeriodFlow, SteadyState};
use std::path::{Path, PathBuf};

/// Write the steady state's figures and CSV into `dir`; returns the files written.
pub fn write(
    flow: &dyn PeriodFlow,
    s: &SteadyState,
    caption: &str,
    dir: &Path,
) -> anyhow::Result<Vec<PathBuf>> {
    let start = s.poincare.first().copied().unwrap_or([0.0, 0.0]);
    // Enough periods to show a period-p orbit several times, or the irregularity of chaos.
    let periods = s.period.map_or(40, |p| (4 * p as usize).max(4));
    let (samples, _) = sample_trajectory(flow, start, periods, 200)?;
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record(["t", "q", "v", "dte", "mesh_force"])?;
    for x in &samples {
        w.write_record([x.t, x.q, x.v, x.dte, x.mesh_force].map(|v| format!("{v:.10}")))?;
    }
    let csv_text = String::from_utf8(w.into_inner()?)?;
    let section: Vec<(f64, f64)> = if s.cloud.is_empty() {
        &s.poincare
    } else {
        &s.cloud
    }
    .iter()
    .map(|p| (p[0], p[1]))
    .collect();
    let base = |title: &str, x: &str, y: &str, series: Vec<Series>| XyPlot {
        title: title.to_string(),
        caption: Some(caption.to_string()),
        x_label: x.into(),
        y_label: y.into(),
        series,
        vlines: Vec::new(),
        ..XyPlot::default()
    };
    let history = base(
        "Time history of q",
        "t (dimensionless)",
        "q",
        vec![Series::line(
            "q(t)",
            samples.iter().map(|x| (x.t, x.q)).collect(),
        )],
    );
    let phase = base(
        "Phase plane",
        "q",
        "q'",
        vec![
            Series::line("trajectory", samples.iter().map(|x| (x.q, x.v)).collect()),
            Series::markers(
                "Poincare points",
                s.poincare.iter().map(|p| (p[0], p[1])).collect(),
            ),
        ],
    );
    let poincare = base(
        "Poincare map (stroboscopic, phase 0)",
        "q",
        "q'",
        vec![Series::markers("section points", section)],
    );
    let mut written = Vec::new();
    written.extend(write_xy(&history, &dir.join("time_history"))?);
    written.extend(write_xy(&phase, &dir.join("phase_plane"))?);
    written.extend(write_xy(&poincare, &dir.join("poincare"))?);
    write_text(&dir.join("time_history.csv"), &csv_text)?;
    written.push(dir.join("time_history.csv"));
    Ok(written)
}
