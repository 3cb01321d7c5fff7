//! CSV table and q_a / q_m plot of a set of frequency-response points (sweeps).

use super::model_args::{num, Model};
use geardyn::model::{Impact, OperatingPoint};
use geardyn::plot::{write_panels, Marker, Series, XyPlot};
use geardyn::sim::{Branch, SetKind, SweepPoint};
use std::path::{Path, PathBuf};

/// The sweep CSV (columns in docs/output-columns.md): `omega,qa,qm,case,period,impact,...`,
/// and with the rig's units `speed_rpm,mesh_freq_hz` before `omega` and `qa_um`, `qm_um`,
/// `dte_pp_um`, `mesh_force_max_n` beside their dimensionless values.
pub fn sweep_csv(points: &[SweepPoint], model: &Model) -> anyhow::Result<String> {
    let units = model.rig.as_ref();
    let mut header: Vec<&str> = Vec::new();
    if units.is_some() {
        header.extend(["speed_rpm", "mesh_freq_hz"]);
    }
    header.extend([
        "omega", "qa", "qm", "case", "period", "impact", "motion", "branch",
    ]);
    header.extend([
        "basin_fraction",
        "q_min",
        "q_max",
        "dte_pp",
        "dl_max",
        "lyapunov",
        "kind",
        "escape_rate_per_period",
    ]);
    if units.is_some() {
        header.extend(["qa_um", "qm_um", "dte_pp_um", "mesh_force_max_n"]);
    }
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record(&header)?;
    let opt = |v: Option<f64>| v.map_or(String::new(), |x| format!("{x:.10}"));
    for p in points {
        let s = &p.steady;
        let mut row = Vec::with_capacity(header.len());
        if let Some(op) = units {
            row.push(num(op.speed_rpm(p.omega)));
            row.push(num(op.mesh_frequency_hz(p.omega)));
        }
        row.extend([
            num(p.omega),
            format!("{:.10}", s.qa),
            format!("{:.10}", s.qm),
            s.impact.case().to_string(),
            s.period.map_or(String::new(), |k| k.to_string()),
            s.impact.name().to_string(),
            s.motion.name().to_string(),
            p.branch.name().to_string(),
            opt(p.basin_fraction),
            format!("{:.10}", s.q_min),
            format!("{:.10}", s.q_max),
            format!("{:.10}", s.dte_pp),
            opt(s.dl_max),
            opt(s.lyapunov),
            p.kind.map_or("", |k| k.name()).to_string(),
            p.escape_rate.map_or(String::new(), |r| format!("{r:.4e}")),
        ]);
        if let Some(op) = units {
            let um = |x: f64| format!("{:.6}", op.micrometres(x));
            row.extend([um(s.qa), um(s.qm), um(s.dte_pp)]);
            row.push(
                s.dl_max
                    .map_or(String::new(), |d| format!("{:.4}", op.mesh_force_n(d))),
            );
        }
        w.write_record(&row)?;
    }
    Ok(String::from_utf8(w.into_inner()?)?)
}

/// A series of points apart from the impact cases: label, which rows, colour, marker.
type ApartSeries = (&'static str, fn(&ResponseRow) -> bool, usize, Marker);

/// One point of a frequency response, whatever method produced it.
pub struct ResponseRow {
    pub omega: f64,
    pub qa: f64,
    pub qm: f64,
    pub impact: Impact,
    /// Known stability (None: not assessed).
    pub stable: Option<bool>,
    /// The carried sweep the point belongs to (None: not from a carried sweep).
    pub branch: Option<Branch>,
    /// A set that trajectories leave (transient chaos, or a slow approach), found by an
    /// all-attractor search: not a steady state a measurement would see.
    pub transient: bool,
}

impl From<&SweepPoint> for ResponseRow {
    fn from(p: &SweepPoint) -> Self {
        ResponseRow {
            omega: p.omega,
            qa: p.steady.qa,
            qm: p.steady.qm,
            impact: p.steady.impact,
            stable: Some(true),
            branch: Some(p.branch),
            transient: p.kind.is_some_and(|k| k != SetKind::Attractor),
        }
    }
}

/// Two panels, q_a and q_m versus Omega, one marker series per impact case (as Fig. 10), sets
/// that trajectories leave as rings of their own; with the rig's units (`units`), b q_a and
/// b q_m in µm versus the pinion speed in rpm.
pub fn write_response_plot(
    rows: &[ResponseRow],
    units: Option<&OperatingPoint>,
    title: &str,
    caption: &str,
    stem: &Path,
) -> anyhow::Result<Vec<PathBuf>> {
    let x = |p: &ResponseRow| units.map_or(p.omega, |op| op.speed_rpm(p.omega));
    let y = |v: f64| units.map_or(v, |op| op.micrometres(v));
    let panel = |label: &str, pick: fn(&ResponseRow) -> f64| {
        let mut series: Vec<Series> = [Impact::None, Impact::Single, Impact::Double]
            .iter()
            .enumerate()
            .map(|(i, &imp)| {
                let pts = rows
                    .iter()
                    .filter(|p| p.impact == imp && p.stable != Some(false) && !p.transient)
                    .map(|p| (x(p), y(pick(p))))
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
        // Up and down sweeps in one figure: a line through each, in sweep order, tells the
        // branches apart where they differ (the markers give the impact case).
        let path = |b: Branch| -> Vec<(f64, f64)> {
            rows.iter()
                .filter(|p| p.branch == Some(b))
                .map(|p| (x(p), y(pick(p))))
                .collect()
        };
        let (up, down) = (path(Branch::Up), path(Branch::Down));
        if !up.is_empty() && !down.is_empty() {
            let lines = [
                Series::line("speed up", up).with_color(4),
                Series::dashed("speed down", down).with_color(6),
            ];
            series.splice(0..0, lines);
        }
        // Points that are not the impact cases' steady states, each kind its own marker.
        let apart: [ApartSeries; 2] = [
            (
                "transient set (trajectories leave it)",
                |p| p.transient,
                5,
                Marker::Ring,
            ),
            ("unstable", |p| p.stable == Some(false), 7, Marker::Cross),
        ];
        for (label, is, color, marker) in apart {
            let pts: Vec<(f64, f64)> = rows
                .iter()
                .filter(|p| is(p))
                .map(|p| (x(p), y(pick(p))))
                .collect();
            if !pts.is_empty() {
                series.push(
                    Series::markers(label, pts)
                        .with_color(color)
                        .with_marker(marker),
                );
            }
        }
        XyPlot {
            title: label.to_string(),
            caption: Some(caption.to_string()),
            x_label: match units {
                Some(_) => "pinion speed n (rpm)".into(),
                None => "Ω_h (dimensionless)".into(),
            },
            y_label: match units {
                Some(_) => format!("{label} (µm)"),
                None => format!("{label} (dimensionless)"),
            },
            series,
            ..XyPlot::default()
        }
    };
    let panels = [panel("q_a", |p| p.qa), panel("q_m", |p| p.qm)];
    Ok(write_panels(title, &panels, 2, stem)?)
}
