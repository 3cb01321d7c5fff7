//! Figures of one steady state (the paper's Figs 2, 4, 5, 7, 8): time history, phase plane and
//! Poincare map, with the sampled history as CSV text. Used by `geardyn simulate --out` and by
//! the reproduction.

use crate::error::Result;
use crate::plot::{Series, XyPlot};
use crate::sim::{sample_trajectory, PeriodFlow, Sample, SteadyState};

/// Samples per forcing period of the drawn trajectories.
pub const SAMPLES_PER_PERIOD: usize = 200;

/// The three figures of a steady state and its sampled history.
#[derive(Clone, Debug)]
pub struct SteadyFigures {
    /// q versus t.
    pub history: XyPlot,
    /// q' versus q with the Poincare points.
    pub phase: XyPlot,
    /// Stroboscopic section (phase 0).
    pub poincare: XyPlot,
    /// `t,q,v,dte,mesh_force` with a header line.
    pub csv: String,
}

/// Forcing periods drawn for a steady state: a period-p orbit several times (at least 4
/// periods), non-periodic motion over 40 periods.
pub fn periods_to_draw(s: &SteadyState) -> usize {
    s.period.map_or(40, |p| (4 * p as usize).max(4))
}

/// Sample `periods` forcing periods of the steady state from its first section point.
pub fn orbit_samples(
    flow: &dyn PeriodFlow,
    s: &SteadyState,
    periods: usize,
) -> Result<Vec<Sample>> {
    let start = s.poincare.first().copied().unwrap_or([0.0, 0.0]);
    Ok(sample_trajectory(flow, start, periods, SAMPLES_PER_PERIOD)?.0)
}

/// Build the time history, phase plane and Poincare figures of `s`.
pub fn steady_figures(
    flow: &dyn PeriodFlow,
    s: &SteadyState,
    caption: &str,
) -> Result<SteadyFigures> {
    let samples = orbit_samples(flow, s, periods_to_draw(s))?;
    let mut csv = String::from("t,q,v,dte,mesh_force\n");
    for x in &samples {
        csv.push_str(&format!(
            "{:.10},{:.10},{:.10},{:.10},{:.10}\n",
            x.t, x.q, x.v, x.dte, x.mesh_force
        ));
    }
    let section: Vec<(f64, f64)> = if s.cloud.is_empty() {
        &s.poincare
    } else {
        &s.cloud
    }
    .iter()
    .map(|p| (p[0], p[1]))
    .collect();
    // A single curve is named by its axis label: no legend box for it.
    let base = |title: &str, x: &str, y: &str, series: Vec<Series>| XyPlot {
        title: title.to_string(),
        caption: Some(caption.to_string()),
        x_label: x.into(),
        y_label: y.into(),
        legend: series.len() > 1,
        series,
        ..XyPlot::default()
    };
    // The drawn orbit starts where the transient from the caption's initial conditions ended.
    let t_label = format!(
        "t after a transient of {} forcing periods (dimensionless)",
        s.transient_periods
    );
    Ok(SteadyFigures {
        history: base(
            "Time history of q",
            &t_label,
            "q (dimensionless)",
            vec![Series::line(
                "q(t)",
                samples.iter().map(|x| (x.t, x.q)).collect(),
            )],
        ),
        phase: base(
            "Phase plane",
            "q (dimensionless)",
            "q' (dimensionless)",
            vec![
                Series::line("trajectory", samples.iter().map(|x| (x.q, x.v)).collect()),
                Series::markers(
                    "Poincaré points",
                    s.poincare.iter().map(|p| (p[0], p[1])).collect(),
                ),
            ],
        ),
        poincare: base(
            "Poincaré map (stroboscopic, phase 0)",
            "q (dimensionless)",
            "q' (dimensionless)",
            vec![Series::markers("section points", section)],
        ),
        csv,
    })
}
