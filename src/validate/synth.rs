//! Synthetic data sets in the layout of design.md section 4, made by simulating the model from
//! stated truth parameters and adding seeded noise. They stand in for Munro's and Kubo's curves
//! until digitized ones are added, and they are labelled `kind = "synthetic"` with their truth.

use super::test_run::{up_sweep_start, TestRun};
use crate::data::{
    munro_rig, write_rig, DataKind, Rig, RigFile, Source, SteTable, SteUncertainty,
    MAX_DYNAMIC_FACTOR,
};
use crate::error::{GearError, Result};
use crate::fit::{Axis, Correlation, Distribution, NoiseModel};
use crate::model::{Dimensional, GearPair, Term, MAX_DTE_UM};
use crate::numeric::Rng;
use crate::progress::Progress;
use crate::sim::{Branch, ExactFlow, PeriodFlow, RkFlow, SteadyOptions, SweepPoint};
use std::path::Path;

/// Physical effects that can be hidden in synthetic data (absent from the paper's model).
#[derive(Clone, Debug, Default)]
pub struct HiddenEffects {
    /// Mesh-stiffness variation amplitude eps of k(t) = 1 + eps cos(Omega t + psi).
    pub stiffness_eps: f64,
    /// Phase psi of the stiffness variation (rad).
    pub stiffness_phase: f64,
    /// Second STE harmonic amplitude as a fraction of the first.
    pub ste2_ratio: f64,
    /// Phase of the second STE harmonic (rad).
    pub ste2_phase: f64,
    /// Third STE harmonic amplitude as a fraction of the first.
    pub ste3_ratio: f64,
    /// Phase of the third STE harmonic (rad).
    pub ste3_phase: f64,
    /// Load-dependent damping zeta(W) = zeta (W / W_design)^gamma: the exponent gamma (0: none).
    pub damping_exponent: f64,
    /// True half backlash over the one stated in rig.toml (0 or 1: the stated one).
    pub backlash_factor: f64,
    /// External torque ripple at mesh frequency, F_aT sin(Omega t + phi), as a fraction of the
    /// design-load mean force (the same newtons at every load).
    pub torque_ripple_ratio: f64,
    /// Phase phi of the torque ripple (rad).
    pub torque_ripple_phase: f64,
    /// An effect outside the discovery library: a lightly damped resonance of the measuring chain
    /// at this mesh frequency (Hz) multiplies the pp DTE by 1 + g / (1 + ((f - f_s) / (0.03 f_s))^2)
    /// (0: none).
    pub sensor_peak_hz: f64,
    /// Relative height g of that transducer peak.
    pub sensor_peak_gain: f64,
}

impl HiddenEffects {
    fn is_none(&self) -> bool {
        self.stiffness_eps == 0.0
            && self.ste2_ratio == 0.0
            && self.ste3_ratio == 0.0
            && self.damping_exponent == 0.0
            && (self.backlash_factor == 0.0 || self.backlash_factor == 1.0)
            && self.torque_ripple_ratio == 0.0
            && (self.sensor_peak_hz == 0.0 || self.sensor_peak_gain == 0.0)
    }

    /// The true dimensional scales: the stated ones with the hidden backlash factor applied.
    pub fn true_dimensional(&self, dim: &Dimensional) -> Dimensional {
        let mut d = dim.clone();
        if self.backlash_factor > 0.0 {
            d.half_backlash_m *= self.backlash_factor;
        }
        d
    }

    /// Apply the effects that depend on the load: [`HiddenEffects::apply`], then the damping law
    /// at `load_ratio` = W / W_design and the torque ripple relative to `design_mean_force`.
    pub fn apply_at_load(
        &self,
        model: GearPair,
        load_ratio: f64,
        design_mean_force: f64,
    ) -> Result<GearPair> {
        let mut model = self.apply(model)?;
        if self.damping_exponent != 0.0 {
            model.zeta *= load_ratio.powf(self.damping_exponent);
        }
        if self.torque_ripple_ratio != 0.0 {
            model.torque.push(Term {
                order: 1,
                amplitude: self.torque_ripple_ratio * design_mean_force,
                phase: self.torque_ripple_phase,
            });
        }
        model.validated()
    }

    /// Gain of the measuring chain at mesh frequency `f_hz` (1 without a sensor peak).
    pub fn sensor_gain(&self, f_hz: f64) -> f64 {
        if self.sensor_peak_hz > 0.0 && self.sensor_peak_gain != 0.0 {
            let x = (f_hz - self.sensor_peak_hz) / (0.03 * self.sensor_peak_hz);
            1.0 + self.sensor_peak_gain / (1.0 + x * x)
        } else {
            1.0
        }
    }

    /// Apply the effects to a model of the paper's form.
    pub fn apply(&self, mut model: GearPair) -> Result<GearPair> {
        if self.stiffness_eps != 0.0 {
            model.stiffness = vec![Term {
                order: 1,
                amplitude: self.stiffness_eps,
                phase: self.stiffness_phase,
            }];
        }
        if self.ste2_ratio != 0.0 {
            let a1 = model.ste.first().map_or(0.0, |t| t.amplitude);
            model.ste.push(Term {
                order: 2,
                amplitude: self.ste2_ratio * a1,
                phase: self.ste2_phase,
            });
        }
        if self.ste3_ratio != 0.0 {
            let a1 = model.ste.first().map_or(0.0, |t| t.amplitude);
            model.ste.push(Term {
                order: 3,
                amplitude: self.ste3_ratio * a1,
                phase: self.ste3_phase,
            });
        }
        model.validated()
    }
}

/// Truth and measurement settings of a synthetic Munro-style set (pp DTE versus speed per load).
#[derive(Clone, Debug)]
pub struct MunroTruth {
    /// The rig (geometry, design load, backlash).
    pub rig: Rig,
    /// Damping ratio.
    pub zeta: f64,
    /// Natural frequency of the mesh mode, Hz.
    pub omega_n_hz: f64,
    /// (load N, STE amplitude um) per load; the first is taken as the design load's.
    pub ste_um: Vec<(f64, f64)>,
    /// Speeds: start, stop, step in rpm.
    pub speeds_rpm: (f64, f64, f64),
    /// Speeds in rpm, ascending, in place of `speeds_rpm` (a non-uniform grid).
    pub speed_list: Option<Vec<f64>>,
    /// The measurement noise added to the simulated curves.
    pub noise: SynthNoise,
    /// Seed of the noise.
    pub seed: u64,
    /// Write the STE amplitudes into rig.toml (else the pipeline estimates them from the curves).
    pub publish_ste: bool,
    /// With `publish_ste`: the stated amplitudes are measurements of the true ones with this
    /// standard deviation (um), each drawn after the curves' noise, and rig.toml states it as
    /// `[ste] sd_um` (None: the true amplitudes, no uncertainty stated, which `validate munro`
    /// and `discover` refuse).
    pub ste_sd_um: Option<f64>,
    /// Effects hidden in the data.
    pub hidden: HiddenEffects,
    /// Make every curve with DOP853 at this relative tolerance, even with k = 1 (`None`: the
    /// exact solver for k = 1). Periodic points agree with the exact solver's to ~1e-5 um;
    /// chaotic ones are a different window of the attractor, as in data the fitting solver
    /// did not make (measurements, or sets made by an older build).
    pub dop853_rtol: Option<f64>,
}

/// The measurement noise of a synthetic set: errors drawn from a [`NoiseModel`] (the same
/// type the fits estimate) at the true level of the curve, then optionally read to a grid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SynthNoise {
    pub family: NoiseFamily,
    pub model: NoiseModel,
    /// Values read to this grid (um), as off a digitized figure; None: written to 1e-5 um.
    pub quantum_um: Option<f64>,
    /// Correlation of the standardized errors of neighbouring speeds at the curve's median
    /// step: an Ornstein-Uhlenbeck process in speed within each curve, corr = exp(-|ds| / L)
    /// with L = -median step / ln rho (on an even grid the AR(1) of lag-one correlation rho; a
    /// drawn line's reading error, a rig's drift); None: independent errors.
    pub rho_on_grid: Option<f64>,
}

impl SynthNoise {
    /// A noisy reading of the true value `y` (never negative: a pp value).
    pub fn read(&self, y: f64, rng: &mut Rng) -> f64 {
        self.quantized((y + self.model.draw(y, rng)).max(0.0))
    }

    /// Noisy readings of one curve's true values `ys` at increasing speeds `speeds` (rpm):
    /// independent draws (in the order of the points, as [`SynthNoise::read`] makes them), or
    /// with `rho_on_grid` standardized errors z_1 ~ N(0, 1), z_k = phi_k z_{k-1} +
    /// sqrt(1 - phi_k^2) N(0, 1), phi_k = rho^(step_k / median step), each scaled by its
    /// point's sigma.
    pub fn read_curve(&self, speeds: &[f64], ys: &[f64], rng: &mut Rng) -> Vec<f64> {
        let Some(rho) = self.rho_on_grid else {
            return ys.iter().map(|y| self.read(*y, rng)).collect();
        };
        let e: Vec<f64> = ys.iter().map(|_| rng.normal()).collect();
        let z = match Axis::new(vec![0; speeds.len()], speeds.to_vec()) {
            Ok(axis) => {
                let length = axis
                    .median_step()
                    .filter(|_| rho > 0.0)
                    .map_or(0.0, |h| -h / rho.ln());
                Correlation {
                    axis: &axis,
                    length,
                }
                .correlate(&e)
            }
            // A curve's speeds are distinct (checked when its grid is made).
            Err(_) => e,
        };
        ys.iter()
            .zip(&z)
            .map(|(y, z)| self.quantized((y + self.model.scale(*y) * z).max(0.0)))
            .collect()
    }

    fn quantized(&self, v: f64) -> f64 {
        match self.quantum_um {
            Some(q) if q > 0.0 => (v / q).round() * q,
            _ => v,
        }
    }

    /// Its parameters, for the truth recorded in rig.toml.
    fn record(&self, t: &mut toml::Table) {
        t.insert("noise_family".into(), self.family.name().into());
        t.insert("noise_um".into(), self.model.floor.into());
        t.insert("noise_relative".into(), self.model.relative.into());
        if let Distribution::StudentT { dof } = self.model.distribution {
            t.insert("noise_student_t_dof".into(), dof.into());
            // noise_um and noise_relative are the t scale's parts; the standard deviation is
            // sqrt(dof / (dof - 2)) times larger, and that is what rig.toml's [noise] states.
            let k = self.model.distribution.sd_factor();
            t.insert("noise_sd_floor_um".into(), (k * self.model.floor).into());
            t.insert("noise_sd_relative".into(), (k * self.model.relative).into());
        }
        if let Some(q) = self.quantum_um {
            t.insert("noise_quantum_um".into(), q.into());
        }
        if let Some(rho) = self.rho_on_grid {
            t.insert("noise_rho_on_grid".into(), rho.into());
        }
    }
}

/// The noise families of the studies: what real measurements and digitized figures look like
/// besides geardyn's own constant Gaussian noise.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NoiseFamily {
    /// Gaussian, one standard deviation everywhere.
    Constant,
    /// Gaussian with a floor plus 3% of the level (scatter grows near resonance).
    Relative,
    /// Student-t with 3 degrees of freedom, floor plus 3% of the level (heavy-tailed scatter,
    /// the odd outlier).
    StudentT,
    /// Floor plus 3% of the level, read to a 0.25 um grid (a digitized figure: about a pixel
    /// of a 60 um axis 240 pixels high).
    Quantized,
    /// Gaussian, floor plus 3% of the level, correlated along speed within each curve: an
    /// Ornstein-Uhlenbeck process in speed whose neighbours at the median step correlate by
    /// 0.6 (a digitized line's smooth reading error, a rig's slow drift;
    /// docs/correlated-errors.md).
    Correlated,
}

/// Relative part of the level-dependent families.
pub const FAMILY_RELATIVE: f64 = 0.03;
/// Degrees of freedom of the Student-t family.
pub const FAMILY_T_DOF: f64 = 3.0;
/// Reading grid of the quantized family, um.
pub const FAMILY_QUANTUM_UM: f64 = 0.25;
/// Lag-one correlation on the grid of the correlated family.
pub const FAMILY_RHO: f64 = 0.6;

impl NoiseFamily {
    /// All families, in the order of the studies' tables.
    pub const ALL: [NoiseFamily; 5] = [
        NoiseFamily::Constant,
        NoiseFamily::Relative,
        NoiseFamily::StudentT,
        NoiseFamily::Quantized,
        NoiseFamily::Correlated,
    ];

    /// Name on the command line and in rig.toml.
    pub fn name(self) -> &'static str {
        match self {
            NoiseFamily::Constant => "constant",
            NoiseFamily::Relative => "relative",
            NoiseFamily::StudentT => "student-t",
            NoiseFamily::Quantized => "quantized",
            NoiseFamily::Correlated => "correlated",
        }
    }

    /// The family of a name.
    pub fn parse(s: &str) -> Option<NoiseFamily> {
        NoiseFamily::ALL.into_iter().find(|f| f.name() == s)
    }

    /// The family's noise with floor `floor_um`.
    pub fn noise(self, floor_um: f64) -> SynthNoise {
        let (relative, distribution, quantum_um) = match self {
            NoiseFamily::Constant => (0.0, Distribution::Gaussian, None),
            NoiseFamily::Relative => (FAMILY_RELATIVE, Distribution::Gaussian, None),
            NoiseFamily::StudentT => (
                FAMILY_RELATIVE,
                Distribution::StudentT { dof: FAMILY_T_DOF },
                None,
            ),
            NoiseFamily::Quantized => (
                FAMILY_RELATIVE,
                Distribution::Gaussian,
                Some(FAMILY_QUANTUM_UM),
            ),
            NoiseFamily::Correlated => (FAMILY_RELATIVE, Distribution::Gaussian, None),
        };
        SynthNoise {
            family: self,
            model: NoiseModel {
                floor: floor_um,
                relative,
                distribution,
                correlation_length: 0.0,
            },
            quantum_um,
            rho_on_grid: (self == NoiseFamily::Correlated).then_some(FAMILY_RHO),
        }
    }
}

/// Check a synthetic noise: finite, non-negative, a reading grid > 0, dof > 2 (finite variance).
fn check_noise(n: &SynthNoise) -> Result<()> {
    let m = &n.model;
    if !(m.floor >= 0.0 && m.floor.is_finite() && m.floor < 1e3) {
        return Err(GearError::param(
            "noise_um",
            m.floor,
            "the noise floor must be in [0, 1000) um",
        ));
    }
    if !(m.relative >= 0.0 && m.relative < 1.0) {
        return Err(GearError::param(
            "noise_relative",
            m.relative,
            "the relative noise must be in [0, 1)",
        ));
    }
    if let Distribution::StudentT { dof } = m.distribution {
        if !(dof > 2.0 && dof <= 1e3) {
            return Err(GearError::param(
                "noise_dof",
                dof,
                "Student-t noise needs 2 < dof <= 1000 (a finite variance)",
            ));
        }
    }
    if let Some(rho) = n.rho_on_grid {
        if !(0.0..=0.999).contains(&rho) {
            return Err(GearError::param(
                "noise_rho",
                rho,
                "the lag-one correlation of the errors along speed must be in [0, 0.999]",
            ));
        }
    }
    if let Some(q) = n.quantum_um {
        if !(q > 0.0 && q < 1e3) {
            return Err(GearError::param(
                "noise_quantum_um",
                q,
                "the reading grid must be in (0, 1000) um",
            ));
        }
    }
    Ok(())
}

impl MunroTruth {
    /// The default stand-in for Munro's Figs 19-22: the paper's zeta = 0.0175, a resonance inside
    /// the speed range, an STE that is smallest at the design load (profile modification) so the
    /// force ratio there is about 50 as the paper says, and loads 1, 3/4, 1/2, 1/4 of design.
    pub fn default_munro() -> Self {
        let d = 3780.0;
        MunroTruth {
            rig: munro_rig(),
            zeta: 0.0175,
            omega_n_hz: 1600.0,
            ste_um: vec![(d, 0.3), (0.75 * d, 1.5), (0.5 * d, 2.5), (0.25 * d, 3.5)],
            speeds_rpm: (1000.0, 5000.0, 50.0),
            speed_list: None,
            noise: NoiseFamily::Constant.noise(0.15),
            seed: 1,
            publish_ste: false,
            ste_sd_um: None,
            hidden: HiddenEffects::default(),
            dop853_rtol: None,
        }
    }
}

/// Relative tolerance of the Runge-Kutta flow used when k(t) varies.
const RK_RTOL: f64 = 1e-9;

/// Exact flow for k = 1, DOP853 at relative tolerance `rtol` when k(t) varies.
pub(crate) fn flow_with_rtol(m: &GearPair, rtol: f64) -> Result<Box<dyn PeriodFlow>> {
    if m.has_stiffness_variation() {
        Ok(Box::new(RkFlow::new(m, rtol)?))
    } else {
        Ok(Box::new(ExactFlow::new(m)?))
    }
}

/// The flow a synthetic set is made with: DOP853 at `dop853_rtol` throughout when given (another
/// solver than the exact one the fits use, so chaotic points are another window of the
/// attractor, as in data the fitting solver did not make), else [`flow_with_rtol`] at
/// [`RK_RTOL`].
fn synth_flow(m: &GearPair, dop853_rtol: Option<f64>) -> Result<Box<dyn PeriodFlow>> {
    match dop853_rtol {
        None => flow_with_rtol(m, RK_RTOL),
        Some(rtol) => Ok(Box::new(RkFlow::new(m, rtol)?)),
    }
}

/// The up-sweep of a synthetic set's test run `run`, made with the set's flow ([`synth_flow`]).
fn synth_up_sweep(
    run: &TestRun,
    dop853_rtol: Option<f64>,
    progress: &dyn Progress,
) -> Result<Vec<SweepPoint>> {
    let flow = |m: &GearPair| synth_flow(m, dop853_rtol);
    run.carried(Branch::Up, &flow, up_sweep_start(run.model), progress)
}

/// What rig.toml's truth says of the solver a set was made with ([`synth_flow`]).
fn integrator_note(dop853_rtol: Option<f64>) -> String {
    match dop853_rtol {
        None => format!("exact for k = 1, DOP853 (rtol {RK_RTOL:e}) when k(t) varies"),
        Some(rtol) => format!("DOP853 (rtol {rtol:e}) throughout"),
    }
}

/// Simulated up-sweep (speed increasing, as a test run) of pp DTE in um at one load.
pub fn simulate_dte_curve(
    dim: &Dimensional,
    model: &GearPair,
    omega_n_hz: f64,
    speeds: &[f64],
    progress: &dyn Progress,
) -> Result<Vec<f64>> {
    let run = TestRun {
        dim,
        model,
        omega_n_hz,
        speeds,
        opts: &SteadyOptions::default(),
    };
    let pts = run.up_sweep(RK_RTOL, progress)?;
    Ok(pts.iter().map(|p| dim.dte_um(p.steady.dte_pp)).collect())
}

fn speed_grid((start, stop, step): (f64, f64, f64)) -> Result<Vec<f64>> {
    crate::sim::frequency_range(start, stop, step).map_err(|_| {
        GearError::param(
            "speeds_rpm",
            step,
            "speed range must be start > 0, stop >= start, step > 0",
        )
    })
}

/// The (load, STE) table must name distinct positive loads with finite non-negative STE.
fn check_loads(ste_um: &[(f64, f64)]) -> Result<()> {
    if ste_um.is_empty() {
        return Err(GearError::param(
            "loads",
            0.0,
            "at least one load is needed",
        ));
    }
    for (k, &(load, ste)) in ste_um.iter().enumerate() {
        if !(load > 0.0 && load.is_finite()) {
            return Err(GearError::param(
                "load_n",
                load,
                "loads must be positive and finite",
            ));
        }
        if !(ste >= 0.0 && ste.is_finite()) {
            return Err(GearError::param(
                "ste_um",
                ste,
                "STE amplitudes must be finite and non-negative",
            ));
        }
        if ste_um[..k]
            .iter()
            .any(|(l, _)| crate::data::same_load(*l, load))
        {
            return Err(GearError::param(
                "load_n",
                load,
                "each load may appear once",
            ));
        }
    }
    Ok(())
}

/// The noise-free curves of a synthetic Munro-style set: (load, speeds, pp DTE in um) per
/// load, simulated up-sweeps with the hidden effects (before the sensor's gain).
pub struct CleanCurves {
    pub curves: Vec<(f64, Vec<f64>, Vec<f64>)>,
}

/// The speeds of a truth: its list, or its range.
fn speeds_of(truth: &MunroTruth) -> Result<Vec<f64>> {
    match &truth.speed_list {
        Some(list) => {
            let ok = !list.is_empty()
                && list.iter().all(|s| *s > 0.0 && s.is_finite())
                && list.windows(2).all(|w| w[1] > w[0]);
            if !ok {
                return Err(GearError::param(
                    "speeds_rpm",
                    list.first().copied().unwrap_or(0.0),
                    "a speed list must be positive, finite and increasing",
                ));
            }
            Ok(list.clone())
        }
        None => speed_grid(truth.speeds_rpm),
    }
}

/// Simulate the noise-free curves of `truth` (the expensive part of [`synth_munro`], shared by
/// studies that draw many noise seeds on one truth).
pub fn clean_munro_curves(truth: &MunroTruth, progress: &dyn Progress) -> Result<CleanCurves> {
    let dim = truth.rig.dimensional()?;
    let speeds = speeds_of(truth)?;
    check_loads(&truth.ste_um)?;
    // Hidden backlash: the data come from the true b; rig.toml states the nominal one.
    let true_dim = truth.hidden.true_dimensional(&dim);
    let design_fm = true_dim.mean_force(truth.rig.design_load_n);
    let mut curves = Vec::new();
    for &(load, ste) in &truth.ste_um {
        let model = GearPair::paper(
            true_dim.mean_force(load),
            true_dim.ste_amplitude(ste),
            truth.zeta,
            1.0,
        )?;
        let model = truth
            .hidden
            .apply_at_load(model, load / truth.rig.design_load_n, design_fm)?;
        let run = TestRun {
            dim: &true_dim,
            model: &model,
            omega_n_hz: truth.omega_n_hz,
            speeds: &speeds,
            opts: &SteadyOptions::default(),
        };
        let clean: Vec<f64> = synth_up_sweep(&run, truth.dop853_rtol, progress)?
            .iter()
            .map(|p| true_dim.dte_um(p.steady.dte_pp))
            .collect();
        curves.push((load, speeds.clone(), clean));
    }
    Ok(CleanCurves { curves })
}

/// Write a synthetic Munro-style data set (rig.toml with its truth, dte.csv) into `dir`.
pub fn synth_munro(truth: &MunroTruth, dir: &Path, progress: &dyn Progress) -> Result<()> {
    // Checked again by `write_munro_set`; here so that bad noise fails before the simulation.
    check_noise(&truth.noise)?;
    let clean = clean_munro_curves(truth, progress)?;
    write_munro_set(truth, &clean, dir)
}

/// Write the set of `truth` from its noise-free curves: the sensor's gain, then the noise of
/// `truth.noise` drawn with `truth.seed`. Nothing is written when a value leaves the data's
/// plausible range ([`MAX_DTE_UM`]): `load_munro` would refuse the set.
pub fn write_munro_set(truth: &MunroTruth, clean: &CleanCurves, dir: &Path) -> Result<()> {
    check_noise(&truth.noise)?;
    let dim = truth.rig.dimensional()?;
    let mut rng = Rng::new(truth.seed);
    let mut rows = String::from("load_n,speed_rpm,dte_pp_um\n");
    for (load, speeds, ys) in &clean.curves {
        let seen: Vec<f64> = speeds
            .iter()
            .zip(ys)
            .map(|(s, y)| y * truth.hidden.sensor_gain(dim.mesh_frequency_hz(*s)))
            .collect();
        let noisy = truth.noise.read_curve(speeds, &seen, &mut rng);
        for (s, noisy) in speeds.iter().zip(noisy) {
            if noisy > MAX_DTE_UM {
                return Err(GearError::Unsupported(format!(
                    "the synthetic curve at {load} N reaches {noisy:.1} um at {s} rpm, beyond \
                     the data's plausible range [0, {MAX_DTE_UM}] um of dte_pp_um (geardyn \
                     would not load the set): lower that load's STE amplitude"
                )));
            }
            rows.push_str(&format!("{load},{s},{noisy:.5}\n"));
        }
    }
    let mut t = toml::Table::new();
    t.insert("zeta".into(), truth.zeta.into());
    t.insert("omega_n_hz".into(), truth.omega_n_hz.into());
    t.insert(
        "load_n".into(),
        truth
            .ste_um
            .iter()
            .map(|x| toml::Value::from(x.0))
            .collect::<Vec<_>>()
            .into(),
    );
    t.insert(
        "ste_um".into(),
        truth
            .ste_um
            .iter()
            .map(|x| toml::Value::from(x.1))
            .collect::<Vec<_>>()
            .into(),
    );
    truth.noise.record(&mut t);
    t.insert("seed".into(), (truth.seed as i64).into());
    t.insert(
        "integrator".into(),
        integrator_note(truth.dop853_rtol).into(),
    );
    if truth.speed_list.is_some() {
        t.insert("speed_grid".into(), "non-uniform list (see dte.csv)".into());
    }
    t.insert(
        "branch".into(),
        "up (speed increasing, state carried)".into(),
    );
    insert_hidden(&mut t, &truth.hidden);
    // Drawn after the curves' noise, so that the curves are the same with or without them.
    let stated: Vec<f64> = truth
        .ste_um
        .iter()
        .map(|x| x.1 + truth.ste_sd_um.map_or(0.0, |sd| sd * rng.normal()))
        .collect();
    let drawn_below_zero = truth
        .ste_sd_um
        .and_then(|_| stated.iter().enumerate().find(|(_, e)| **e <= 0.0));
    if let Some((k, e)) = drawn_below_zero {
        return Err(GearError::Unsupported(format!(
            "the stated STE drawn at {} N is {e:.4} um: an STE uncertainty this large against \
             the amplitude {} um can state a negative amplitude; give a smaller one",
            truth.ste_um[k].0, truth.ste_um[k].1
        )));
    }
    let ste = truth.publish_ste.then(|| SteTable {
        load_n: truth.ste_um.iter().map(|x| x.0).collect(),
        amplitude_um: stated,
        sd_um: truth.ste_sd_um.map(SteUncertainty::Every),
    });
    let rig = RigFile {
        rig: truth.rig.clone(),
        ste,
        noise: None,
        source: synthetic_source(
            "Synthetic stand-in for Munro (1962) as shown in Kahraman & Singh (1990) Figs 19-22: \
                       simulated from the truth below, not measured",
            "layout of Figs 19-22 (loads 1, 3/4, 1/2, 1/4 of design)",
            t,
        ),
    };
    write_set(dir, &rig, "dte.csv", &rows)
}

fn insert_hidden(t: &mut toml::Table, h: &HiddenEffects) {
    let mut e = toml::Table::new();
    e.insert("stiffness_eps".into(), h.stiffness_eps.into());
    e.insert("stiffness_phase".into(), h.stiffness_phase.into());
    e.insert("ste2_ratio".into(), h.ste2_ratio.into());
    e.insert("ste2_phase".into(), h.ste2_phase.into());
    e.insert("ste3_ratio".into(), h.ste3_ratio.into());
    e.insert("ste3_phase".into(), h.ste3_phase.into());
    e.insert("damping_exponent".into(), h.damping_exponent.into());
    e.insert("backlash_factor".into(), h.backlash_factor.into());
    e.insert("torque_ripple_ratio".into(), h.torque_ripple_ratio.into());
    e.insert("torque_ripple_phase".into(), h.torque_ripple_phase.into());
    e.insert("sensor_peak_hz".into(), h.sensor_peak_hz.into());
    e.insert("sensor_peak_gain".into(), h.sensor_peak_gain.into());
    e.insert("none".into(), h.is_none().into());
    t.insert("hidden_effects".into(), e.into());
}

/// Provenance of a synthetic set: labelled synthetic, with its generator and truth.
fn synthetic_source(citation: &str, figure: &str, truth: toml::Table) -> Source {
    Source {
        kind: DataKind::Synthetic,
        citation: citation.into(),
        figure: Some(figure.into()),
        method: None,
        uncertainty: None,
        instrument: None,
        date: None,
        generator: Some(format!("geardyn synth {}", env!("CARGO_PKG_VERSION"))),
        truth: Some(truth),
    }
}

/// Write rig.toml and one CSV, replacing any previous set in `dir` only once both are ready.
fn write_set(dir: &Path, rig: &RigFile, csv_name: &str, rows: &str) -> Result<()> {
    std::fs::create_dir_all(dir).map_err(GearError::io(dir))?;
    write_rig(&dir.join("rig.toml"), rig)?;
    let csv = dir.join(csv_name);
    std::fs::write(&csv, rows).map_err(GearError::io(&csv))
}

/// Truth of a synthetic Kubo-style set: the dynamic-factor envelope of several tooth pairs.
#[derive(Clone, Debug)]
pub struct KuboTruth {
    /// The rig (placeholder geometry; the load the curve is measured at is `test_load_n`).
    pub rig: Rig,
    /// Damping ratio (Kubo's rig is heavily damped, about 0.1).
    pub zeta: f64,
    /// Natural frequency, Hz.
    pub omega_n_hz: f64,
    /// STE amplitude at the test load, um.
    pub ste_um: f64,
    /// Speeds: start, stop, step in rpm.
    pub speeds_rpm: (f64, f64, f64),
    /// Tooth pairs whose dynamic factors make the envelope.
    pub tooth_pairs: usize,
    /// Relative scatter between tooth pairs (standard deviation).
    pub pair_scatter: f64,
    /// Seed.
    pub seed: u64,
    /// Publish the STE amplitude in rig.toml.
    pub publish_ste: bool,
    /// Effects hidden in the data.
    pub hidden: HiddenEffects,
    /// Make the curve with DOP853 at this relative tolerance instead of the exact solver
    /// ([`MunroTruth::dop853_rtol`]).
    pub dop853_rtol: Option<f64>,
}

impl KuboTruth {
    /// Default stand-in for Fig. 23: zeta 0.1, a resonance inside the speed range and an STE
    /// that separates the teeth near resonance. The geometry is a placeholder, not Kubo's.
    pub fn default_kubo() -> Self {
        KuboTruth {
            rig: Rig {
                name: "Heavily damped four-square rig (placeholder geometry, Kubo-like damping)"
                    .into(),
                pinion_teeth: 25,
                gear_teeth: 25,
                module_mm: 4.0,
                pressure_angle_deg: 20.0,
                face_width_mm: 10.0,
                design_load_n: 2000.0,
                backlash_mm: 0.1,
                mesh_stiffness_n_per_um: None,
                contact_ratio: None,
                zeta: None,
                omega_n_hz: None,
                test_load_n: Some(2000.0),
            },
            zeta: 0.1,
            omega_n_hz: 2500.0,
            ste_um: 3.0,
            speeds_rpm: (2000.0, 10000.0, 100.0),
            tooth_pairs: 8,
            pair_scatter: 0.04,
            seed: 2,
            publish_ste: true,
            hidden: HiddenEffects::default(),
            dop853_rtol: None,
        }
    }
}

/// Write a synthetic Kubo-style set (rig.toml with its truth, dynamic_factor.csv) into `dir`.
pub fn synth_kubo(truth: &KuboTruth, dir: &Path, progress: &dyn Progress) -> Result<()> {
    let dim = truth.rig.dimensional()?;
    let load = truth.rig.test_load_n.unwrap_or(truth.rig.design_load_n);
    let speeds = speed_grid(truth.speeds_rpm)?;
    let model = GearPair::paper(
        dim.mean_force(load),
        dim.ste_amplitude(truth.ste_um),
        truth.zeta,
        1.0,
    )?;
    let model = truth.hidden.apply(model)?;
    let run = TestRun {
        dim: &dim,
        model: &model,
        omega_n_hz: truth.omega_n_hz,
        speeds: &speeds,
        opts: &SteadyOptions::default(),
    };
    let pts = synth_up_sweep(&run, truth.dop853_rtol, progress)?;
    let mut rng = Rng::new(truth.seed);
    let mut rows = String::from("speed_rpm,dynamic_factor_min,dynamic_factor_max\n");
    for (s, p) in speeds.iter().zip(&pts) {
        let d = p.steady.dl_max.unwrap_or(f64::NAN);
        let pairs: Vec<f64> = (0..truth.tooth_pairs.max(1))
            .map(|_| d * (1.0 + truth.pair_scatter * rng.normal()))
            .collect();
        let lo = pairs.iter().copied().fold(f64::INFINITY, f64::min).max(0.0);
        let hi = pairs
            .iter()
            .copied()
            .fold(f64::NEG_INFINITY, f64::max)
            .max(lo);
        if !(hi.is_finite() && hi <= MAX_DYNAMIC_FACTOR) {
            return Err(GearError::Unsupported(format!(
                "the synthetic envelope reaches a dynamic factor of {hi:.3} at {s} rpm, beyond \
                 the data's plausible range [0, {MAX_DYNAMIC_FACTOR}] (geardyn would not load \
                 the set)"
            )));
        }
        rows.push_str(&format!("{s},{lo:.5},{hi:.5}\n"));
    }
    let mut t = toml::Table::new();
    t.insert("zeta".into(), truth.zeta.into());
    t.insert("omega_n_hz".into(), truth.omega_n_hz.into());
    t.insert("ste_um".into(), truth.ste_um.into());
    t.insert("load_n".into(), load.into());
    t.insert("tooth_pairs".into(), (truth.tooth_pairs as i64).into());
    t.insert("pair_scatter".into(), truth.pair_scatter.into());
    t.insert("seed".into(), (truth.seed as i64).into());
    t.insert(
        "integrator".into(),
        integrator_note(truth.dop853_rtol).into(),
    );
    t.insert(
        "branch".into(),
        "up (speed increasing, state carried)".into(),
    );
    insert_hidden(&mut t, &truth.hidden);
    let rig = RigFile {
        rig: truth.rig.clone(),
        ste: truth.publish_ste.then(|| SteTable {
            load_n: vec![load],
            amplitude_um: vec![truth.ste_um],
            sd_um: None,
        }),
        noise: None,
        source: synthetic_source("Synthetic stand-in for Kubo's dynamic-factor envelope (Kahraman & Singh 1990 Fig. 23, \
                       from Ozguven & Houser 1988): simulated from the truth below, not measured", "layout of Fig. 23 (envelope of tooth pairs)", t),
    };
    write_set(dir, &rig, "dynamic_factor.csv", &rows)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An envelope the Kubo loader would refuse (a dynamic factor over its plausible 100, from
    /// an STE of 1000 um on a 3 um-scale rig) is refused and nothing is written.
    #[test]
    fn an_envelope_beyond_the_loaders_range_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let mut t = KuboTruth::default_kubo();
        t.ste_um = 1000.0;
        t.speeds_rpm = (5000.0, 6000.0, 500.0);
        let out = dir.path().join("set");
        let e = synth_kubo(&t, &out, &crate::progress::NoProgress);
        match e {
            Err(GearError::Unsupported(m)) => assert!(m.contains("dynamic factor of"), "{m}"),
            other => panic!("{other:?}"),
        }
        assert!(!out.exists());
    }

    /// A Student-t family's truth records the standard deviation beside the t scale, and it is
    /// the draws' standard deviation: t5 (finite kurtosis 9, so the sample variance of 400000
    /// draws has relative standard error sqrt(8 / 400000) = 0.45%, the SD half that) at floor
    /// 1 um, level 0, against sqrt(5 / 3) = 1.291 um, to 1.5% (about 7 standard errors).
    #[test]
    fn a_student_t_truth_records_its_standard_deviation() {
        let mut noise = NoiseFamily::StudentT.noise(1.0);
        noise.model.distribution = Distribution::StudentT { dof: 5.0 };
        let mut t = toml::Table::new();
        noise.record(&mut t);
        let sd = t["noise_sd_floor_um"].as_float().unwrap();
        assert!((sd - (5.0f64 / 3.0).sqrt()).abs() < 1e-12, "{sd}");
        let rel = t["noise_sd_relative"].as_float().unwrap();
        assert!((rel - FAMILY_RELATIVE * sd).abs() < 1e-12, "{rel}");
        let mut rng = Rng::new(7);
        let n = 400_000;
        let draws: Vec<f64> = (0..n).map(|_| noise.model.draw(0.0, &mut rng)).collect();
        let var = draws.iter().map(|d| d * d).sum::<f64>() / n as f64;
        assert!(
            (var.sqrt() / sd - 1.0).abs() < 0.015,
            "{} vs {sd}",
            var.sqrt()
        );
        let mut gauss = toml::Table::new();
        NoiseFamily::Relative.noise(1.0).record(&mut gauss);
        assert!(!gauss.contains_key("noise_sd_floor_um"));
    }

    /// A load table with a repeated, negative or NaN entry is refused before anything is
    /// simulated or written.
    #[test]
    fn bad_load_tables_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        for bad in [
            vec![],
            vec![(3780.0, 0.3), (3780.0, 1.0)],
            vec![(-945.0, 3.5)],
            vec![(945.0, f64::NAN)],
            vec![(945.0, -1.0)],
        ] {
            let mut t = MunroTruth::default_munro();
            t.ste_um = bad.clone();
            let out = dir.path().join("set");
            let e = synth_munro(&t, &out, &crate::progress::NoProgress);
            assert!(
                matches!(e, Err(GearError::InvalidParameter { .. })),
                "{bad:?}"
            );
            assert!(!out.exists(), "{bad:?}");
        }
    }

    /// Rows (load, speed, pp) of a set's dte.csv.
    fn rows(dir: &Path) -> Vec<(f64, f64, f64)> {
        std::fs::read_to_string(dir.join("dte.csv"))
            .unwrap()
            .lines()
            .skip(1)
            .map(|l| {
                let v: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
                (v[0], v[1], v[2])
            })
            .collect()
    }

    /// A set made by DOP853 has the exact solver's periodic points (the same seed gives the
    /// same noise, so the rows differ by the clean curves' difference: below 1e-4 um at the
    /// design load, all period-1 in contact) and other chaotic ones (945 N, 4300-4500 rpm,
    /// where M0's pp over observation windows spans 35-84 um: some point moves by more than
    /// 1 um); rig.toml says which integrator made it.
    #[test]
    fn dop853_sets_keep_periodic_points_and_draw_other_chaotic_ones() {
        let dir = tempfile::tempdir().unwrap();
        let make = |name: &str, loads: Vec<(f64, f64)>, speeds, rtol| {
            let mut t = MunroTruth::default_munro();
            t.ste_um = loads;
            t.speeds_rpm = speeds;
            t.dop853_rtol = rtol;
            let out = dir.path().join(name);
            synth_munro(&t, &out, &crate::progress::NoProgress).unwrap();
            out
        };
        let design = vec![(3780.0, 0.3)];
        let quarter = vec![(945.0, 3.5)];
        let slow = (1000.0, 2000.0, 100.0);
        let chaos = (4300.0, 4500.0, 50.0);
        let (a, b) = (
            rows(&make("a", design.clone(), slow, None)),
            rows(&make("b", design, slow, Some(1e-9))),
        );
        assert_eq!(a.len(), 11);
        for (x, y) in a.iter().zip(&b) {
            assert_eq!((x.0, x.1), (y.0, y.1));
            assert!((x.2 - y.2).abs() < 1e-4, "{x:?} vs {y:?}");
        }
        let (c, d) = (
            make("c", quarter.clone(), chaos, None),
            make("d", quarter, chaos, Some(1e-9)),
        );
        let moved = rows(&c)
            .iter()
            .zip(rows(&d))
            .map(|(x, y)| (x.2 - y.2).abs())
            .fold(0.0, f64::max);
        assert!(moved > 1.0, "largest change {moved} um");
        let rig = std::fs::read_to_string(d.join("rig.toml")).unwrap();
        assert!(
            rig.contains("integrator = \"DOP853 (rtol 1e-9) throughout\""),
            "{rig}"
        );
        let rig = std::fs::read_to_string(c.join("rig.toml")).unwrap();
        assert!(rig.contains("integrator = \"exact for k = 1"), "{rig}");
    }
}
