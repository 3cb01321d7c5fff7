//! Transient chaos measured at one point (issue 23; by default Fig. 4's F_m 0.1, F_ah 0.2,
//! zeta 0.02, Omega 1.0): every initial condition of the grid is followed up to a long horizon,
//! by the exact flow and by the independent DOP853 flow, and the survival curve of each
//! non-periodic set, its escape rate (exact Poisson 95% interval), the check that the survival
//! is exponential, and the agreement of the two integrators are reported.
//!
//! A chaotic saddle loses its trajectories at a constant rate, so ln S(n) falls on a straight
//! line of slope -kappa after the trajectories have settled on it; the rate measured over the
//! first and the second half of the observation must agree, and so must the two integrators
//! (their trajectories separate within a few hundred periods, so they are independent samples of
//! the same saddle).

use super::figures::Figure;
use crate::error::{GearError, Result};
use crate::model::GearPair;
use crate::plot::{write_panels, Marker, Series, XyPlot};
use crate::progress::Progress;
use crate::sim::{
    escape_rate, find_attractors, Attractor, AttractorMap, EscapeBudget, EscapeRecord, ExactFlow,
    IcGrid, PeriodFlow, RkFlow, SetKind, SteadyOptions, MAX_EXPOSURE,
};
use serde_json::{json, Value};
use std::path::{Path, PathBuf};

/// What to compute.
#[derive(Clone, Debug)]
pub struct EscapeStudyOptions {
    /// Mean load F_m.
    pub fm: f64,
    /// STE amplitude F_ah.
    pub fah: f64,
    /// External torque amplitude F_aT of eq. 4 at the mesh frequency (0: eq. 5 alone).
    pub fat: f64,
    /// Damping ratio.
    pub zeta: f64,
    /// Mesh frequency Omega.
    pub omega: f64,
    /// Initial conditions.
    pub grid: IcGrid,
    /// Age, in forcing periods, to which every trajectory is followed.
    pub horizon: usize,
    /// Also follow the trajectories with DOP853 at this relative tolerance.
    pub dop853_rtol: Option<f64>,
}

impl EscapeStudyOptions {
    /// Fig. 4's point on the paper's 21x21 grid, 40,000 periods, DOP853 at rtol 1e-10.
    pub fn fig4() -> Result<Self> {
        Ok(EscapeStudyOptions {
            fm: 0.1,
            fah: 0.2,
            fat: 0.0,
            zeta: 0.02,
            omega: 1.0,
            grid: IcGrid::new(-2.0, 2.0, 21)?,
            horizon: 40_000,
            dop853_rtol: Some(1e-10),
        })
    }
}

/// The study's results.
#[derive(Clone, Debug)]
pub struct EscapeStudy {
    /// The attractor map of each integrator ("exact", "dop853").
    pub maps: Vec<(String, AttractorMap)>,
    /// Survival curves and their exponential fits.
    pub figure: Figure,
    /// `integrator,set,periods,alive,fraction` for every checkpoint.
    pub csv: String,
    /// Rates, intervals, checks (JSON).
    pub summary: Value,
}

/// Run the study.
pub fn escape_study(opts: &EscapeStudyOptions, progress: &dyn Progress) -> Result<EscapeStudy> {
    let model = GearPair::excited(opts.fm, opts.fah, opts.fat, opts.zeta, opts.omega)?;
    let steady = SteadyOptions {
        escape: EscapeBudget {
            horizon: opts.horizon,
            // Every trajectory is followed to the horizon: no early stop on escapes, and the
            // exposure limit is the largest accepted.
            target_escapes: usize::MAX,
            max_exposure: MAX_EXPOSURE,
            ..EscapeBudget::default()
        },
        ..SteadyOptions::default()
    };
    let mut maps = Vec::new();
    let exact = ExactFlow::new(&model)?;
    maps.push((
        "exact".to_string(),
        find_attractors(&exact, &opts.grid, &steady, progress)?,
    ));
    if let Some(rtol) = opts.dop853_rtol {
        let rk = RkFlow::new(&model, rtol)?;
        maps.push((
            format!("dop853 rtol {rtol:e}"),
            find_attractors(&rk as &dyn PeriodFlow, &opts.grid, &steady, progress)?,
        ));
    }
    let torque = GearPair::torque_caption(opts.fat);
    let caption = format!(
        "F_m = {}, F_ah = {} (F_hat = {}){torque}, ζ = {}, Ω = {}, {}x{} initial conditions",
        opts.fm,
        opts.fah,
        opts.fm / opts.fah,
        opts.zeta,
        opts.omega,
        opts.grid.n,
        opts.grid.n
    );
    Ok(EscapeStudy {
        figure: figure(&maps, &caption),
        csv: csv(&maps),
        summary: summary(opts, &maps),
        maps,
    })
}

impl EscapeStudy {
    /// Whether no integrator found a non-periodic set (every trajectory of the grid settled on
    /// a periodic attractor): the survival curves are then empty.
    pub fn found_none(&self) -> bool {
        none_followed(&self.maps)
    }
}

/// Whether no map followed a non-periodic set.
fn none_followed(maps: &[(String, AttractorMap)]) -> bool {
    maps.iter().all(|(_, m)| followed(m).next().is_none())
}

/// What the figure and the summary say when no set was followed.
const NONE_FOUND: &str = "no non-periodic set was found: every trajectory of the grid settled on a periodic attractor, so nothing escapes";

/// The non-periodic sets of a map with their escape records.
fn followed(m: &AttractorMap) -> impl Iterator<Item = (usize, &Attractor, &EscapeRecord)> {
    m.attractors
        .iter()
        .enumerate()
        .filter_map(|(i, a)| a.escape.as_ref().map(|r| (i, a, r)))
}

/// Escape rate of a record from the survival counts between ages `a` and `b` (checkpoints):
/// escapes over the exposure integrated by the trapezoid rule (exact within a block's
/// escapes), with its 95% interval.
fn rate_between(r: &EscapeRecord, a: usize, b: usize) -> Option<(f64, (f64, f64))> {
    let pts: Vec<_> = r
        .survival
        .iter()
        .filter(|p| p.periods >= a && p.periods <= b)
        .collect();
    let (first, last) = (pts.first()?, pts.last()?);
    let escapes = first.alive.checked_sub(last.alive)?;
    let exposure: f64 = pts
        .windows(2)
        .map(|w| 0.5 * (w[0].alive + w[1].alive) as f64 * (w[1].periods - w[0].periods) as f64)
        .sum();
    Some(escape_rate(escapes, exposure))
}

fn summary(opts: &EscapeStudyOptions, maps: &[(String, AttractorMap)]) -> Value {
    let mut per = Vec::new();
    for (name, m) in maps {
        for (i, a, r) in followed(m) {
            let mid = (r.start_periods + r.end_periods) / 2;
            let mid = r
                .survival
                .iter()
                .map(|p| p.periods)
                .min_by_key(|&p| p.abs_diff(mid))
                .unwrap_or(mid);
            let halves = [
                rate_between(r, r.start_periods, mid),
                rate_between(r, mid, r.end_periods),
            ];
            let alive_at = |n: usize| {
                r.survival
                    .iter()
                    .rev()
                    .find(|p| p.periods <= n)
                    .map(|p| json!({"periods": p.periods, "alive": p.alive}))
            };
            per.push(json!({
                "integrator": name,
                "set": i,
                "kind": a.kind,
                "motion": a.steady.motion,
                "impact": a.steady.impact,
                "lyapunov": a.steady.lyapunov,
                "entered": r.entered,
                "start_periods": r.start_periods,
                "end_periods": r.end_periods,
                "escapes": r.escapes,
                "exposure_periods": r.exposure,
                "escape_rate_per_period": r.rate,
                "escape_rate_ci95": [r.rate_ci95.0, r.rate_ci95.1],
                "mean_lifetime_periods": r.mean_lifetime(),
                "rate_first_half": halves[0].map(|h| json!({"rate": h.0, "ci95": [h.1 .0, h.1 .1]})),
                "rate_second_half": halves[1].map(|h| json!({"rate": h.0, "ci95": [h.1 .0, h.1 .1]})),
                "alive_at": [alive_at(10_000), alive_at(20_000), alive_at(40_000)],
                "destinations": r.destinations.iter().map(|&(k, n)| {
                    let d = &m.attractors[k].steady;
                    json!({"period": d.period, "impact": d.impact, "qa": d.qa, "escapes": n})
                }).collect::<Vec<_>>(),
            }));
        }
    }
    // The integrators' rates of their (first) chaotic transient, compared as two Poisson rates.
    let rates: Vec<(f64, usize)> = maps
        .iter()
        .filter_map(|(_, m)| {
            followed(m)
                .find(|(_, a, _)| a.kind == SetKind::ChaoticTransient)
                .map(|(_, _, r)| (r.rate, r.escapes))
        })
        .collect();
    let agreement = match rates.as_slice() {
        [(a, da), (b, db), ..] if *da > 0 && *db > 0 => {
            let z = (a - b) / (a * a / *da as f64 + b * b / *db as f64).sqrt();
            json!({"ratio": a / b, "z": z, "consistent": z.abs() < 2.0})
        }
        _ => Value::Null,
    };
    json!({
        "parameters": {"fm": opts.fm, "fah": opts.fah, "fat": opts.fat, "zeta": opts.zeta, "omega": opts.omega},
        "grid": {"lo": opts.grid.lo, "hi": opts.grid.hi, "n": opts.grid.n},
        "horizon_periods": opts.horizon,
        "note": none_followed(maps).then_some(NONE_FOUND),
        "sets": per,
        "integrators_agree": agreement,
    })
}

fn csv(maps: &[(String, AttractorMap)]) -> String {
    let mut s = String::from("integrator,set,periods,alive,fraction\n");
    for (name, m) in maps {
        for (i, _, r) in followed(m) {
            for p in &r.survival {
                s.push_str(&format!(
                    "{name},{i},{},{},{:.6}\n",
                    p.periods,
                    p.alive,
                    p.alive as f64 / r.entered.max(1) as f64
                ));
            }
        }
    }
    s
}

/// (a) ln S(n) with the fitted exp(-kappa (n - n0)); (b) S(n).
fn figure(maps: &[(String, AttractorMap)], caption: &str) -> Figure {
    let mut log_series = Vec::new();
    let mut lin_series = Vec::new();
    for (c, (name, m)) in maps.iter().enumerate() {
        for (_, _, r) in followed(m).filter(|(_, a, _)| a.kind != SetKind::Attractor) {
            let entered = r.entered.max(1) as f64;
            let pts: Vec<(f64, f64)> = r
                .survival
                .iter()
                .filter(|p| p.alive > 0)
                .map(|p| (p.periods as f64, p.alive as f64 / entered))
                .collect();
            let label = format!(
                "{name}: κ = {:.2e} (95% {:.2e}–{:.2e})",
                r.rate, r.rate_ci95.0, r.rate_ci95.1
            );
            log_series.push(
                Series::markers(
                    label.clone(),
                    pts.iter().map(|&(n, s)| (n, s.ln())).collect(),
                )
                .with_color(c)
                .with_marker(if c == 0 {
                    Marker::Circle
                } else {
                    Marker::Cross
                }),
            );
            let n0 = r.start_periods as f64;
            let n1 = r.end_periods as f64;
            // The fitted line is named in the panel's caption, so the legend keeps two entries
            // and fits inside the plot.
            log_series
                .push(Series::dashed("", vec![(n0, 0.0), (n1, -r.rate * (n1 - n0))]).with_color(c));
            lin_series.push(Series::line(name.clone(), pts).with_color(c));
        }
    }
    let none = if none_followed(maps) {
        format!("; {NONE_FOUND}")
    } else {
        String::new()
    };
    let panel = |title: &str, note: &str, y: &str, series: Vec<Series>| XyPlot {
        title: title.into(),
        caption: Some(format!("{caption}{note}{none}")),
        x_label: "forcing periods n".into(),
        y_label: y.into(),
        series,
        ..XyPlot::default()
    };
    Figure {
        name: "survival".into(),
        title: "Transient chaos: trajectories still on the chaotic set".into(),
        panels: vec![
            panel(
                "(a) ln S(n): a straight line of slope −κ",
                "; dashed: exp(−κ (n − n₀)) fitted",
                "ln S(n)",
                log_series,
            ),
            panel("(b) surviving fraction S(n)", "", "S(n)", lin_series),
        ],
        cols: 2,
    }
}

/// Write `survival.png`, `survival.svg`, `survival.csv` and `escape.json` into `dir`.
pub fn write_escape_study(s: &EscapeStudy, dir: &Path) -> Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir).map_err(GearError::io(dir))?;
    let f = &s.figure;
    let mut written = write_panels(&f.title, &f.panels, f.cols, &dir.join(&f.name))?;
    let csv = dir.join("survival.csv");
    std::fs::write(&csv, &s.csv).map_err(GearError::io(&csv))?;
    written.push(csv);
    let json = dir.join("escape.json");
    let text = serde_json::to_string_pretty(&s.summary)
        .map_err(|e| GearError::Numerical(format!("JSON: {e}")))?;
    std::fs::write(&json, format!("{text}\n")).map_err(GearError::io(&json))?;
    written.push(json);
    Ok(written)
}
