//! `validate-study`: how often the 95% intervals of `validate munro` contain the truth, on
//! seeded synthetic design-load curves made by another integrator than the fit's (DOP853 by
//! default) with a chosen noise family, on a uniform or a non-uniform speed grid, at Munro's
//! four loads (the design-load fit takes the low-speed parts of the others). Each seed's
//! set goes through the same files and the same fit as `validate munro` (rig.toml and dte.csv
//! written, loaded, fitted by [`fit_munro_design_load`]); only the expensive noise-free curve
//! is simulated once and shared by the seeds.

use super::munro::{fit_munro_design_load, usable_design_fit};
use super::synth::{clean_munro_curves, write_munro_set, MunroTruth, SynthNoise};
use crate::data::load_munro;
use crate::error::{GearError, Result};
use crate::fit::{Distribution, Robust};
use crate::numeric::{wilson95, Rng};
use crate::progress::Progress;
use serde::Serialize;
use std::path::Path;

/// The speed grid of the study's sets.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(rename_all = "snake_case", tag = "kind")]
pub enum SpeedGrid {
    /// 1000 to 5000 rpm in steps of `step_rpm` (Munro's figures: 50).
    Uniform { step_rpm: f64 },
    /// `points` speeds drawn uniformly at random in 1000-5000 rpm (seed `seed`), sorted: gaps
    /// and clusters, as a test log's speeds are.
    NonUniform { points: usize, seed: u64 },
}

/// Speeds of the study grids, rpm.
const GRID_RPM: (f64, f64) = (1000.0, 5000.0);

impl SpeedGrid {
    /// The speeds, ascending; a non-uniform draw keeps its speeds at least 1 rpm apart.
    pub fn speeds(self) -> Result<Vec<f64>> {
        match self {
            SpeedGrid::Uniform { step_rpm } => {
                crate::sim::frequency_range(GRID_RPM.0, GRID_RPM.1, step_rpm).map_err(|_| {
                    GearError::param("speed_step", step_rpm, "the speed step must be positive")
                })
            }
            SpeedGrid::NonUniform { points, seed } => {
                if !(5..=2000).contains(&points) {
                    return Err(GearError::param(
                        "points",
                        points as f64,
                        "a non-uniform grid needs 5 to 2000 speeds",
                    ));
                }
                let mut rng = Rng::new(seed);
                let mut s: Vec<f64> = (0..points)
                    .map(|_| {
                        let v = GRID_RPM.0 + (GRID_RPM.1 - GRID_RPM.0) * rng.uniform();
                        (v * 10.0).round() / 10.0
                    })
                    .collect();
                s.sort_by(f64::total_cmp);
                s.dedup_by(|a, b| *a - *b < 1.0);
                Ok(s)
            }
        }
    }
}

/// Settings of a validation study.
#[derive(Clone, Debug)]
pub struct ValidateStudyOptions {
    pub first_seed: u64,
    pub seeds: usize,
    pub noise: SynthNoise,
    pub grid: SpeedGrid,
    /// DOP853 tolerance of the sets (None: the exact solver, the fit's own).
    pub dop853_rtol: Option<f64>,
    /// True zeta, omega_n (Hz) and design-load STE amplitude (um).
    pub zeta: f64,
    pub omega_n_hz: f64,
    pub ste_um: f64,
    /// Every load's STE stated in rig.toml as a measurement of the truth with this standard
    /// uncertainty (um; [`MunroTruth::ste_sd_um`]); None: not stated.
    pub ste_sd_um: Option<f64>,
    pub robust: Robust,
}

impl Default for ValidateStudyOptions {
    fn default() -> Self {
        ValidateStudyOptions {
            first_seed: 1,
            seeds: 200,
            noise: super::synth::NoiseFamily::Relative.noise(0.15),
            grid: SpeedGrid::Uniform { step_rpm: 50.0 },
            dop853_rtol: Some(1e-9),
            zeta: 0.0175,
            omega_n_hz: 1600.0,
            ste_um: 0.3,
            ste_sd_um: None,
            robust: Robust::Auto,
        }
    }
}

/// Whether each kind of interval of one parameter contained the truth.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Covered {
    pub fisher: bool,
    pub sandwich: bool,
    /// An unbounded side counts as containing the truth; None for the other loads' STE,
    /// which have no profile interval.
    pub profile: Option<bool>,
}

/// One seed's fit.
#[derive(Clone, Debug, Serialize)]
pub struct ValidateSeed {
    pub seed: u64,
    /// Why the fit was refused as `validate munro` refuses it (a zeta the curve does not
    /// determine, see `validate::munro::usable`); the other fields are then empty.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub refused: Option<String>,
    /// Estimates of zeta, omega_n_hz, ste_um.
    pub estimates: Vec<f64>,
    pub std_errors: Vec<f64>,
    /// Degrees of freedom of each interval's t quantile.
    pub interval_dof: Vec<f64>,
    pub covered: Vec<Covered>,
    pub noise_floor_um: f64,
    pub noise_relative: f64,
    pub student_t: bool,
    pub outliers: usize,
    /// The errors' correlation length along speed the fit kept (rpm; 0: independent errors).
    pub correlation_rpm: f64,
}

impl ValidateSeed {
    /// The record of a seed whose fit was refused for `reason`.
    fn refused(seed: u64, reason: String) -> Self {
        ValidateSeed {
            seed,
            refused: Some(reason),
            estimates: Vec::new(),
            std_errors: Vec::new(),
            interval_dof: Vec::new(),
            covered: Vec::new(),
            noise_floor_um: f64::NAN,
            noise_relative: f64::NAN,
            student_t: false,
            outliers: 0,
            correlation_rpm: f64::NAN,
        }
    }
}

/// Coverage of one parameter's intervals over the seeds.
#[derive(Clone, Debug, Serialize)]
pub struct ParameterCoverage {
    pub name: String,
    pub truth: f64,
    /// Seeds whose interval contained the truth, the rate and its Wilson 95% interval.
    pub fisher: (usize, f64, (f64, f64)),
    pub sandwich: (usize, f64, (f64, f64)),
    pub profile: Option<(usize, f64, (f64, f64))>,
    /// Mean and standard deviation of the estimates, and the mean reported standard error
    /// (Fisher): a calibrated error bar has sd ~ mean standard error.
    pub mean: f64,
    pub sd: f64,
    pub mean_std_error: f64,
}

/// Summary of a validation study.
#[derive(Clone, Debug, Serialize)]
pub struct ValidateStudySummary {
    /// Seeds whose fit was used: the coverage is over them.
    pub seeds: usize,
    /// Seeds whose fit `validate munro` refuses (zeta not determined).
    pub refused: usize,
    pub noise_family: &'static str,
    pub noise_floor_um: f64,
    pub noise_relative: f64,
    pub noise_distribution: Distribution,
    pub noise_quantum_um: Option<f64>,
    /// Correlation of neighbouring errors at the median step (the correlated family).
    pub noise_rho: Option<f64>,
    pub grid: SpeedGrid,
    pub grid_points: usize,
    pub data_dop853_rtol: Option<f64>,
    pub robust: Robust,
    pub coverage: Vec<ParameterCoverage>,
    /// Seeds on which the fit chose Student-t errors, and the mean count of outliers listed.
    pub student_t_chosen: usize,
    pub mean_outliers: f64,
    /// Seeds on which the fit kept errors correlated along speed, and the median length it
    /// kept there (rpm; NaN where none).
    pub correlation_kept: usize,
    pub median_correlation_rpm: f64,
}

fn covered(truth: f64, ci: (f64, f64)) -> bool {
    ci.0 <= truth && truth <= ci.1
}

/// Run a validation study: one set per seed in `scratch` (replaced by the next), `on_seed`
/// called with each seed's fit as soon as it is known.
pub fn run_validate_study(
    opts: &ValidateStudyOptions,
    scratch: &Path,
    progress: &dyn Progress,
    on_seed: &mut dyn FnMut(&ValidateSeed) -> Result<()>,
) -> Result<ValidateStudySummary> {
    if !(1..=100_000).contains(&opts.seeds) {
        return Err(GearError::param(
            "seeds",
            opts.seeds as f64,
            "a study needs 1 to 100000 seeds",
        ));
    }
    let mut t = MunroTruth::default_munro();
    t.zeta = opts.zeta;
    t.omega_n_hz = opts.omega_n_hz;
    // Munro's four loads: the design load's STE is the study's, the others' low-speed parts
    // join the fit (they carry the noise model's relative part).
    t.ste_um[0].1 = opts.ste_um;
    t.speed_list = Some(opts.grid.speeds()?);
    t.noise = opts.noise;
    t.dop853_rtol = opts.dop853_rtol;
    t.publish_ste = opts.ste_sd_um.is_some();
    t.ste_sd_um = opts.ste_sd_um;
    let clean = clean_munro_curves(&t, &crate::progress::NoProgress)?;
    let grid_points = clean.curves.first().map_or(0, |c| c.1.len());
    // zeta, omega_n, the design load's STE, then the other loads' STE in the fit's order
    // (loads descending, as `MunroData::loads` and the default table list them).
    let truth: Vec<f64> = [opts.zeta, opts.omega_n_hz]
        .into_iter()
        .chain(t.ste_um.iter().map(|x| x.1))
        .collect();
    let mut names: Vec<String> = Vec::new();
    let dir = scratch.join("set");
    let mut seeds = Vec::with_capacity(opts.seeds);
    let mut refused = 0;
    progress.start(opts.seeds as u64, "seeds");
    for k in 0..opts.seeds {
        t.seed = opts.first_seed + k as u64;
        write_munro_set(&t, &clean, &dir)?;
        let data = load_munro(&dir)?;
        let fitted = fit_munro_design_load(&data, (opts.robust, None))
            .and_then(|(fit, _)| usable_design_fit(&data, fit));
        let fit = match fitted {
            Ok(f) => f,
            Err(GearError::FitFailed { reason, .. }) => {
                on_seed(&ValidateSeed::refused(t.seed, reason))?;
                refused += 1;
                progress.advance(1);
                continue;
            }
            Err(e) => return Err(e),
        };
        let e = &fit.estimate;
        if e.params.len() != truth.len() {
            return Err(GearError::Numerical(format!(
                "seed {}: the fit has {} parameters where the truth has {} (a load's low-speed part was left out)",
                t.seed,
                e.params.len(),
                truth.len()
            )));
        }
        names.clone_from(&e.names);
        let s = ValidateSeed {
            seed: t.seed,
            refused: None,
            estimates: e.params.clone(),
            std_errors: e.std_errors.clone(),
            interval_dof: e.dof.clone(),
            covered: (0..e.params.len())
                .map(|i| Covered {
                    fisher: covered(truth[i], e.ci95[i]),
                    sandwich: covered(truth[i], e.ci95_sandwich[i]),
                    profile: fit.ci95_profile.get(i).map(|c| c.covers(truth[i])),
                })
                .collect(),
            noise_floor_um: e.noise.model.floor,
            noise_relative: e.noise.model.relative,
            student_t: matches!(e.noise.model.distribution, Distribution::StudentT { .. }),
            outliers: e.noise.outliers.len(),
            correlation_rpm: e.noise.correlation.as_ref().map_or(0.0, |c| c.length_rpm),
        };
        on_seed(&s)?;
        seeds.push(s);
        progress.advance(1);
    }
    progress.finish();
    let n = seeds.len();
    if n == 0 {
        return Err(GearError::Numerical(format!(
            "every one of the {refused} seeds' fits was refused (see the per-seed records)"
        )));
    }
    let rate = |k: usize| (k, k as f64 / n as f64, wilson95(k, n));
    let coverage = (0..names.len())
        .map(|i| {
            let est: Vec<f64> = seeds.iter().map(|s| s.estimates[i]).collect();
            let mean = est.iter().sum::<f64>() / n as f64;
            let sd = (est.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n.max(2) - 1) as f64)
                .sqrt();
            let count =
                |f: &dyn Fn(&Covered) -> bool| seeds.iter().filter(|s| f(&s.covered[i])).count();
            ParameterCoverage {
                name: names[i].clone(),
                truth: truth[i],
                fisher: rate(count(&|c| c.fisher)),
                sandwich: rate(count(&|c| c.sandwich)),
                profile: seeds
                    .iter()
                    .all(|s| s.covered[i].profile.is_some())
                    .then(|| rate(count(&|c| c.profile == Some(true)))),
                mean,
                sd,
                mean_std_error: seeds.iter().map(|s| s.std_errors[i]).sum::<f64>() / n as f64,
            }
        })
        .collect();
    let mut kept: Vec<f64> = seeds
        .iter()
        .map(|s| s.correlation_rpm)
        .filter(|l| *l > 0.0)
        .collect();
    kept.sort_by(f64::total_cmp);
    Ok(ValidateStudySummary {
        seeds: n,
        refused,
        noise_family: opts.noise.family.name(),
        noise_floor_um: opts.noise.model.floor,
        noise_relative: opts.noise.model.relative,
        noise_distribution: opts.noise.model.distribution,
        noise_quantum_um: opts.noise.quantum_um,
        noise_rho: opts.noise.rho_on_grid,
        grid: opts.grid,
        grid_points,
        data_dop853_rtol: opts.dop853_rtol,
        robust: opts.robust,
        coverage,
        student_t_chosen: seeds.iter().filter(|s| s.student_t).count(),
        mean_outliers: seeds.iter().map(|s| s.outliers as f64).sum::<f64>() / n as f64,
        correlation_kept: kept.len(),
        median_correlation_rpm: kept.get(kept.len() / 2).copied().unwrap_or(f64::NAN),
    })
}
