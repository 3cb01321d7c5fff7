//! The computation behind `geardyn compare`: every method at the same parameters.

use super::matching::{gaps, Gaps};
use super::{ComparePoint, Source};
use crate::error::{GearError, Result};
use crate::hb::{
    branch_at, branch_from_start, df_response_forced, AftOptions, ContinuationOptions, DfForcing,
    DfMethod,
};
use crate::model::{GearPair, OperatingPoint};
use crate::numeric::to_significant;
use crate::progress::{NoProgress, Progress};
use crate::sim::{
    find_attractors, sweep, Branch, ExactFlow, IcGrid, PeriodFlow, SteadyOptions, SweepPlan,
    SweepPoint,
};
use rayon::prelude::*;

/// Lowest frequency at which the AFT continuation starts (below the first grid frequency when
/// that is higher).
const AFT_START: f64 = 0.2;

/// The AFT continuation runs this far beyond the last grid frequency, so that a branch folding
/// back above the grid (the upper branch of a jump, Figs 11-12) returns into it.
const AFT_OVERSHOOT: f64 = 0.5;

/// Parameters of a comparison of harmonic balance and simulation for eq. 5 (with an external
/// torque of eq. 4 when `fat` > 0).
#[derive(Clone, Debug)]
pub struct CompareSettings {
    /// Mean load F_m.
    pub fm: f64,
    /// STE amplitude F_ah.
    pub fah: f64,
    /// External torque amplitude F_aT of eq. 4, at the mesh frequency (0: eq. 5 alone).
    pub fat: f64,
    /// Damping ratio zeta.
    pub zeta: f64,
    /// Frequency grid (increasing) shared by the sweeps, the df-exact solution and the AFT grid.
    pub omegas: Vec<f64>,
    /// Initial conditions of the all-attractor search at each Omega.
    pub grid: IcGrid,
    /// Harmonics H of the AFT ansatz.
    pub harmonics: usize,
    /// Relative q_a tolerance of a match (0.01 = 1%).
    pub tolerance: f64,
}

/// Every point of every method, and the disagreements.
#[derive(Clone, Debug)]
pub struct Comparison {
    /// The parameters.
    pub settings: CompareSettings,
    /// Points of all sources (see [`Source`]).
    pub points: Vec<ComparePoint>,
    /// Where the methods disagree.
    pub gaps: Gaps,
}

fn sim_point(p: &SweepPoint, source: Source) -> ComparePoint {
    let s = &p.steady;
    ComparePoint {
        source,
        omega: p.omega,
        qa: s.qa,
        qm: s.qm,
        case: s.impact,
        stable: Some(true),
        period: s.period,
        motion: Some(s.motion),
        basin_fraction: p.basin_fraction,
    }
}

/// Run df-exact, the AFT continuation (stability by Floquet multipliers) and the three
/// simulation sweeps for eq. 5 at `settings`, and detect gaps (Figs 11-13 overlaid).
pub fn compare(settings: &CompareSettings, progress: &dyn Progress) -> Result<Comparison> {
    let omegas = &settings.omegas;
    let (Some(&first), Some(&last)) = (omegas.first(), omegas.last()) else {
        return Err(GearError::param(
            "omega",
            0.0,
            "need at least one frequency",
        ));
    };
    if !(settings.tolerance.is_finite() && settings.tolerance > 0.0) {
        return Err(GearError::param(
            "tolerance",
            settings.tolerance,
            "match tolerance must be finite and > 0",
        ));
    }
    let model = GearPair::excited(
        settings.fm,
        settings.fah,
        settings.fat,
        settings.zeta,
        first,
    )?;
    let mut points = Vec::new();
    let forcing = DfForcing {
        ste: settings.fah,
        torque: settings.fat,
    };
    for s in df_response_forced(settings.fm, forcing, settings.zeta, omegas, DfMethod::Exact)? {
        points.push(ComparePoint::hb(
            Source::DfExact,
            s.omega,
            s.qa,
            s.qm,
            s.stable,
        ));
    }
    let opts = AftOptions {
        harmonics: settings.harmonics,
        ..AftOptions::default()
    };
    // Start where the teeth stay in contact (eq. 13 exact; eq. 5 always has case I at low
    // Omega, Sec. 8.1), so that the continuation begins on the physical lower branch.
    let branch = branch_from_start(
        &model,
        first.min(AFT_START),
        last + AFT_OVERSHOOT,
        &opts,
        &ContinuationOptions::default(),
    )?;
    for p in &branch {
        points.push(ComparePoint::hb(Source::Aft, p.omega, p.qa, p.qm, p.stable));
    }
    for list in branch_at(&model, &branch, omegas, &opts) {
        for p in list {
            points.push(ComparePoint::hb(
                Source::AftGrid,
                p.omega,
                p.qa,
                p.qm,
                p.stable,
            ));
        }
    }
    let factory =
        |m: &GearPair| -> Result<Box<dyn PeriodFlow>> { Ok(Box::new(ExactFlow::new(m)?)) };
    let sopts = SteadyOptions::default();
    let carried: Vec<Result<Vec<SweepPoint>>> = [Branch::Up, Branch::Down]
        .par_iter()
        .map(|&b| {
            let plan = SweepPlan {
                omegas: omegas.clone(),
                branch: b,
                x0: [1.0 + settings.fm, 0.0],
                grid: settings.grid,
                opts: sopts.clone(),
            };
            sweep(&factory, &model, &plan, &NoProgress)
        })
        .collect();
    for (pts, source) in carried
        .into_iter()
        .zip([Source::SweepUp, Source::SweepDown])
    {
        points.extend(pts?.iter().map(|p| sim_point(p, source)));
    }
    progress.start(omegas.len() as u64, "frequencies (attractors)");
    let all: Vec<Result<Vec<ComparePoint>>> = omegas
        .par_iter()
        .map(|&w| {
            let flow = ExactFlow::new(&model.at_omega(w)?)?;
            let map = find_attractors(&flow, &settings.grid, &sopts, &NoProgress)?;
            progress.advance(1);
            Ok(map
                .attractors
                .into_iter()
                .map(|a| sim_point(&SweepPoint::from_attractor(w, a), Source::Attractors))
                .collect())
        })
        .collect();
    progress.finish();
    for a in all {
        points.extend(a?);
    }
    let gaps = gaps(&points, settings.tolerance);
    Ok(Comparison {
        settings: settings.clone(),
        points,
        gaps,
    })
}

impl Comparison {
    /// CSV of every point with a `source` column (columns in docs/output-columns.md); with the
    /// rig's units `units`, also the speed, the mesh frequency and q_a, q_m in µm.
    pub fn csv(&self, units: Option<&OperatingPoint>) -> Result<String> {
        let mut w = csv::Writer::from_writer(Vec::new());
        let io = |e: csv::Error| GearError::Numerical(format!("CSV: {e}"));
        let mut header = vec!["source"];
        if units.is_some() {
            header.extend(["speed_rpm", "mesh_freq_hz"]);
        }
        header.extend([
            "omega", "qa", "qm", "case", "impact", "stable", "period", "motion",
        ]);
        header.push("basin_fraction");
        if units.is_some() {
            header.extend(["qa_um", "qm_um"]);
        }
        w.write_record(&header).map_err(io)?;
        let num = |x: f64| format!("{}", to_significant(x, 10));
        for p in &self.points {
            let mut row = vec![p.source.name().to_string()];
            if let Some(op) = units {
                row.extend([
                    num(op.speed_rpm(p.omega)),
                    num(op.mesh_frequency_hz(p.omega)),
                ]);
            }
            row.extend([
                num(p.omega),
                format!("{:.10}", p.qa),
                format!("{:.10}", p.qm),
                p.case.case().to_string(),
                p.case.name().to_string(),
                p.stable.map_or(String::new(), |b| b.to_string()),
                p.period.map_or(String::new(), |k| k.to_string()),
                p.motion.map_or(String::new(), |m| m.name().to_string()),
                p.basin_fraction
                    .map_or(String::new(), |f| format!("{f:.6}")),
            ]);
            if let Some(op) = units {
                row.extend([
                    format!("{:.6}", op.micrometres(p.qa)),
                    format!("{:.6}", op.micrometres(p.qm)),
                ]);
            }
            w.write_record(&row).map_err(io)?;
        }
        let bytes = w
            .into_inner()
            .map_err(|e| GearError::Numerical(format!("CSV: {e}")))?;
        String::from_utf8(bytes).map_err(|e| GearError::Numerical(format!("CSV: {e}")))
    }

    /// JSON report: parameters, counts per source and the gaps.
    pub fn json(&self) -> serde_json::Value {
        let s = &self.settings;
        let count = |src: Source| self.points.iter().filter(|p| p.source == src).count();
        serde_json::json!({
            "parameters": {
                "fm": s.fm, "fah": s.fah, "fat": s.fat, "zeta": s.zeta,
                "force_ratio": s.fm / s.fah,
                "omega_first": s.omegas.first(), "omega_last": s.omegas.last(),
                "omega_count": s.omegas.len(),
                "ic_grid": s.grid, "harmonics": s.harmonics, "tolerance": s.tolerance,
            },
            "counts": {
                "df-exact": count(Source::DfExact), "aft": count(Source::Aft),
                "aft-grid": count(Source::AftGrid), "sweep-up": count(Source::SweepUp),
                "sweep-down": count(Source::SweepDown), "attractors": count(Source::Attractors),
            },
            "summary": self.gaps.summary_lines(),
            "gaps": self.gaps,
        })
    }
}
