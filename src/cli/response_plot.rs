//! CSV table and q_a / q_m plot of a set of frequency-response points (sweeps).

use geardyn::model::Impact;
use geardyn::plot::{write_panels, Marker, Series, XyPlot};
use geardyn::sim::SweepPoint;
use std::path::{Path, PathBuf};

/// The sweep CSV: `omega,qa,qm,case,period,impact,...` (design.md section 3).
pub fn sweep_csv(points: &[SweepPoint]) -> anyhow::Result<String> {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record([
        "omega",
        "qa",
        "qm",
        "case",
        "period",
        "impact",
        "motion",
        "branch",
        "basin_fraction",
        "q_min",
        "q_max",
        "dte_pp",
        "dl_max",
        "lyapunov",
        "kind",
        "escape_rate_per_period",
    ])?;
    let opt = |v: Option<f64>| v.map_or(String::new(), |x| format!("{x:.10}"));
    for p in points {
        let s = &p.steady;
        w.write_record([
            format!("{}", p.omega),
            format!("{:.10}", s.qa),
            format!("{:.10}", s.qm),
            s.impact.case().to_string(),
            s.period.map_or(String::new(), |k| k.to_string()),
            s.impact.name().to_string(),
            format!("{:?}", s.motion).to_lowercase(),
            p.branch.name().to_string(),
            opt(p.basin_fraction),
            format!("{:.10}", s.q_min),
            format!("{:.10}", s.q_max),
            format!("{:.10}", s.dte_pp),
            opt(s.dl_max),
            opt(s.lyapunov),
            p.kind.map_or("", |k| k.name()).to_string(),
            p.escape_rate.map_or(String::new(), |r| format!("{r:.4e}")),
        ])?;
    }
    Ok(String::from_utf8(w.into_inner()?)?)
}

/// One point of a frequency response, whatever method produced it.
pub struct ResponseRow {
    pub omega: f64,
    pub qa: f64,
    pub qm: f64,
    pub impact: Impact,
    /// Known stability (None: not assessed).
    pub stable: Option<bool>,
}

impl From<&SweepPoint> for ResponseRow {
    fn from(p: &SweepPoint) -> Self {
        ResponseRow {
            omega: p.omega,
            qa: p.steady.qa,
            qm: p.steady.qm,
            impact: p.steady.impact,
            stable: Some(true),
        }
    }
}

/// Two panels, q_a and q_m versus Omega, one marker series per impact case (as Fig. 10).
pub fn write_response_plot(
    rows: &[ResponseRow],
    title: &str,
    caption: &str,
    stem: &Path,
) -> anyhow::Result<Vec<PathBuf>> {
    let panel = |label: &str, pick: fn(&ResponseRow) -> f64| {
        let mut series: Vec<Series> = [Impact::None, Impact::Single, Impact::Double]
            .iter()
            .enumerate()
            .map(|(i, &imp)| {
                let pts = rows
                    .iter()
                    .filter(|p| p.impact == imp && p.stable != Some(false))
                    .map(|p| (p.omega, pick(p)))
                    .collect();
                let label = [
                    "case I (no impact)",
                    "case II (single-sided impact)",
                    "case III (double-sided impact)",
                ][i];
                Series::markers(label, pts)
                    .with_color(i)
                    .with_marker([Marker::Square, Marker::Triangle, Marker::Circle][i])
            })
            .collect();
        let unstable: Vec<(f64, f64)> = rows
            .iter()
            .filter(|p| p.stable == Some(false))
            .map(|p| (p.omega, pick(p)))
            .collect();
        if !unstable.is_empty() {
            series.push(
                Series::markers("unstable", unstable)
                    .with_color(7)
                    .with_marker(Marker::Cross),
            );
        }
        XyPlot {
            title: label.to_string(),
            caption: Some(caption.to_string()),
            x_label: "Omega_h".into(),
            y_label: label.into(),
            series,
            ..XyPlot::default()
        }
    };
    let panels = [panel("q_a", |p| p.qa), panel("q_m", |p| p.qm)];
    Ok(write_panels(title, &panels, 2, stem)?)
}
