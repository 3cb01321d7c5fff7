//! Null-rate and recovery studies of the discovery workflow: many seeded synthetic Munro-style
//! sets with one effect hidden (or none), each run through [`discover`] exactly as a user would
//! (the generated rig.toml records the truth; the workflow does not read it, the study compares
//! afterwards). Rates come with Wilson 95% intervals.

use crate::data::load_munro;
use crate::discover::{discover, Candidate, DiscoverOptions, Discovery, Effect};
use crate::error::{GearError, Result};
use crate::numeric::{clopper_pearson_upper95, ks_from_uniform, wilson95, Rng};
use crate::progress::Progress;
use crate::validate::{synth_munro, HiddenEffects, MunroTruth, NoiseFamily, SpeedGrid, SynthNoise};
use serde::Serialize;
use std::path::Path;

/// What a study hides in its data sets.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Hidden {
    /// M0 plus noise: the null case (expected effect "none").
    None,
    /// One library effect at the study's moderate strength.
    Library(Candidate),
    /// A measuring-chain resonance at 2300 Hz, +50% (outside the library: expected "unexplained").
    SensorPeak,
}

impl Hidden {
    /// Parse "none", "sensor_peak" or a candidate name.
    pub fn parse(s: &str) -> Option<Hidden> {
        match s {
            "none" => Some(Hidden::None),
            "sensor_peak" => Some(Hidden::SensorPeak),
            _ => crate::discover::LIBRARY
                .iter()
                .find(|c| c.name() == s)
                .map(|c| Hidden::Library(*c)),
        }
    }

    /// The name `parse` reads: "none", "sensor_peak" or the candidate's.
    pub fn name(self) -> &'static str {
        match self {
            Hidden::None => "none",
            Hidden::SensorPeak => "sensor_peak",
            Hidden::Library(c) => c.name(),
        }
    }

    /// The discovery answer that counts as correct.
    pub fn expected(self) -> &'static str {
        match self {
            Hidden::None => "none",
            Hidden::SensorPeak => "unexplained",
            Hidden::Library(c) => c.name(),
        }
    }

    /// The study's moderate strength of the hidden effect, in the units of the candidate's
    /// reported estimate (eps, r2, gamma, b / b_stated, F_aT / F_m(design)), or the sensor
    /// peak's relative height; None for the null case.
    pub fn default_strength(self) -> Option<f64> {
        match self {
            Hidden::None => None,
            Hidden::SensorPeak => Some(0.5),
            Hidden::Library(c) => Some(match c {
                Candidate::MeshStiffnessVariation => 0.2,
                Candidate::SteHarmonics => 0.4,
                Candidate::DampingLaw => 1.0,
                Candidate::Backlash => 1.5,
                Candidate::TorqueRipple => 0.03,
            }),
        }
    }

    /// Whether the hidden effect has a phase (stiffness variation, STE harmonic, torque ripple).
    pub fn has_phase(self) -> bool {
        matches!(self, Hidden::Library(c) if c.has_phase())
    }

    /// The hidden effects at `strength` (see [`Hidden::default_strength`]) with phase `phase`
    /// (rad; ignored by effects without one) and the true value of the candidate's reported
    /// estimate.
    pub fn effects(self, strength: f64, phase: f64) -> (HiddenEffects, Option<f64>) {
        let mut h = HiddenEffects::default();
        let truth = match self {
            Hidden::None => None,
            Hidden::SensorPeak => {
                h.sensor_peak_hz = 2300.0;
                h.sensor_peak_gain = strength;
                None
            }
            Hidden::Library(c) => {
                match c {
                    Candidate::MeshStiffnessVariation => {
                        h.stiffness_eps = strength;
                        h.stiffness_phase = phase;
                    }
                    Candidate::SteHarmonics => {
                        h.ste2_ratio = strength;
                        h.ste2_phase = phase;
                    }
                    Candidate::DampingLaw => h.damping_exponent = strength,
                    Candidate::Backlash => h.backlash_factor = strength,
                    Candidate::TorqueRipple => {
                        h.torque_ripple_ratio = strength;
                        h.torque_ripple_phase = phase;
                    }
                }
                Some(strength)
            }
        };
        (h, truth)
    }

    /// The hidden effect in the candidate's coordinates, for its power bound: the load
    /// exponent gamma of a damping law. The phase-carrying effects and the backlash are left
    /// out (their coordinates are not the synthetic set's).
    fn power_effect(self, truth: Option<f64>) -> Option<Effect> {
        match (self, truth) {
            (Hidden::Library(Candidate::DampingLaw), Some(gamma)) => {
                Some(Effect::of(Candidate::DampingLaw, vec![gamma]))
            }
            _ => None,
        }
    }
}

/// One seed's outcome (its default: nothing answered, nothing estimated).
#[derive(Clone, Debug, Default, Serialize)]
pub struct SeedOutcome {
    pub seed: u64,
    /// Phase of the hidden effect (rad), when it has one.
    pub true_phase: Option<f64>,
    pub effect: String,
    pub correct: bool,
    pub estimate: Option<f64>,
    pub ci95: Option<(f64, f64)>,
    pub covered: Option<bool>,
    /// The intervals behind `ci95` ([`crate::discover::CandidateResult`]), to compare their
    /// coverage.
    pub wald_ci95: Option<(f64, f64)>,
    pub profile_ci95: Option<(Option<f64>, Option<f64>)>,
    /// The named phase-carrying candidate's phase and its 95% Wald arc, degrees; whether the
    /// true phase lies on it, and how far it is from the estimate (degrees, 0 to 180).
    pub phase_deg: Option<f64>,
    pub phase_wald95_deg: Option<(f64, f64)>,
    pub phase_covered: Option<bool>,
    pub phase_error_deg: Option<f64>,
    pub held_out_rms_before_um: Option<f64>,
    pub held_out_rms_after_um: Option<f64>,
    /// Raw (unadjusted) bootstrap p-value of M0's goodness of fit and of every tested
    /// candidate's likelihood ratio, by name: under the null each should be uniform.
    pub p_values: Vec<(String, f64)>,
    /// The best candidate when the answer is unexplained or ambiguous.
    pub closest_candidate: Option<String>,
    /// Points left out of the likelihood whose measured pp lies far outside M0's range there
    /// (the run's warning; see `ExcludedPoints`).
    pub excluded_far_outside: usize,
    pub seconds: f64,
    /// The run's error, when `discover` failed on this set (`effect` is then "error" and the
    /// seed counts as not answered correctly).
    pub error: Option<String>,
    /// The first-order power of the hidden effect's test on this set, where stated.
    pub power_bound: Option<f64>,
}

/// How often one test's raw p-value fell below 0.05 and 0.01 over the seeds, with Wilson 95%
/// intervals, and the Kolmogorov-Smirnov distance of its p-values from uniform: under the null
/// a calibrated test gives 5% and 1% (the Monte Carlo p-value (1 + #{T* >= T}) / (B + 1) is
/// slightly conservative), so this shows which test, if any, a false-positive excess comes from.
#[derive(Clone, Debug, Serialize)]
pub struct TestCalibration {
    pub name: String,
    pub seeds: usize,
    pub below_5pct: (usize, (f64, f64)),
    pub below_1pct: (usize, (f64, f64)),
    pub ks_distance: f64,
}

/// Summary of a study.
#[derive(Clone, Debug, Serialize)]
pub struct StudySummary {
    pub hidden: Hidden,
    pub expected: &'static str,
    pub true_value: Option<f64>,
    /// DOP853 tolerance the sets were made with ([`StudyOptions::dop853_rtol`]); `None`: the
    /// exact solver, the same one that fits them.
    pub data_dop853_rtol: Option<f64>,
    /// The sets' speed grid.
    pub data_grid: String,
    /// Whether the hidden effect's phase was drawn at random per seed (else 0).
    pub random_phase: bool,
    /// The sets' noise family, floor (um) and relative part.
    pub data_noise_family: &'static str,
    pub data_noise_floor_um: f64,
    pub data_noise_relative: f64,
    /// The stated STEs' standard uncertainty (um; [`StudyOptions::ste_sd_um`]); None: not
    /// stated.
    pub data_ste_sd_um: Option<f64>,
    pub seeds: usize,
    pub correct: usize,
    pub correct_rate: f64,
    pub correct_ci95: (f64, f64),
    /// For the null study: any answer other than "none" (false positives) and its interval.
    pub false_positive_rate: Option<(f64, (f64, f64))>,
    /// For the null study: one-sided 95% upper bound of the false-positive rate
    /// (Clopper-Pearson), the number to hold against a "at most 5%" requirement.
    pub false_positive_upper95: Option<f64>,
    /// True value inside the 95% interval, over the correctly named seeds.
    pub coverage: Option<(usize, usize)>,
    /// Held-out RMS smaller after than before, over the correctly named seeds.
    pub held_out_shrunk: Option<(usize, usize)>,
    /// True phase on the 95% phase arc, over the correctly named seeds with a phase-carrying
    /// effect, and its Wilson 95% interval.
    pub phase_coverage: Option<(usize, usize, (f64, f64))>,
    /// Seeds whose run warned about excluded points far outside M0's range.
    pub warned: usize,
    /// Seeds on which `discover` failed, with the error (counted as not correct).
    pub failed: Vec<(u64, String)>,
    /// The mean over the seeds of the first-order power of the hidden effect's test
    /// ([`crate::discover::PowerBound`]), where the study states one: what a test of these data
    /// can reach, to first order, to compare `correct_rate` with.
    pub power_bound_mean: Option<f64>,
    /// Per test (detection and candidates), its raw p-values over the seeds.
    pub calibration: Vec<TestCalibration>,
    pub outcomes: Vec<SeedOutcome>,
}

/// Settings of the generated sets.
#[derive(Clone, Debug)]
pub struct StudyOptions {
    pub first_seed: u64,
    pub seeds: usize,
    /// Speed grid of the sets (uniform in 1000-5000 rpm, or a non-uniform draw); coarser grids
    /// run faster.
    pub grid: SpeedGrid,
    /// Draw the hidden effect's phase uniformly in [0, 2 pi) per seed (else 0): the method must
    /// find an effect at any phase, not only at the one it was developed on.
    pub random_phase: bool,
    /// The sets' measurement noise (family and floor).
    pub noise: SynthNoise,
    /// Strength of the hidden effect; None takes [`Hidden::default_strength`].
    pub strength: Option<f64>,
    /// (load N, STE um) of the sets; None takes Munro's four loads of
    /// [`MunroTruth::default_munro`].
    pub loads: Option<Vec<(f64, f64)>>,
    /// Make the sets with DOP853 at this tolerance ([`MunroTruth::dop853_rtol`]): their
    /// chaotic points are then not the fitting solver's, as with real data.
    pub dop853_rtol: Option<f64>,
    /// Keep each seed's set in `DIR/seed-N` (rig.toml + dte.csv) instead of replacing it with
    /// the next, so that a seed's answer can be looked at again with `geardyn discover`.
    pub keep_sets: Option<std::path::PathBuf>,
    /// State every load's STE in rig.toml as a measurement of the truth with this standard
    /// uncertainty (um; [`MunroTruth::ste_sd_um`]); None: not stated, every STE free.
    pub ste_sd_um: Option<f64>,
    pub discover: DiscoverOptions,
}

impl Default for StudyOptions {
    fn default() -> Self {
        StudyOptions {
            first_seed: 1,
            seeds: 100,
            grid: SpeedGrid::Uniform { step_rpm: 50.0 },
            random_phase: false,
            noise: NoiseFamily::Constant.noise(0.15),
            strength: None,
            loads: None,
            dop853_rtol: None,
            keep_sets: None,
            ste_sd_um: None,
            discover: DiscoverOptions::default(),
        }
    }
}

impl StudyOptions {
    /// The options a study cannot run with, refused before anything is made or written: no
    /// seed, or `discover` options on which every seed would fail (too few bootstrap
    /// replicates to ever detect, an alpha or a stated noise out of range).
    pub fn check(&self) -> Result<()> {
        if self.seeds == 0 {
            return Err(GearError::param(
                "seeds",
                0.0,
                "a study needs at least one seed",
            ));
        }
        crate::discover::check_options(&self.discover)
    }
}

/// Run one study; `scratch` is a folder for the generated sets (each replaced by the next).
/// `on_seed` gets each seed's outcome as soon as it is known, so that a long study stopped
/// part way keeps what it found (a 20-seed study on rattle-regime sets runs half an hour).
pub fn run_study(
    hidden: Hidden,
    opts: &StudyOptions,
    scratch: &Path,
    progress: &dyn Progress,
    on_seed: &mut dyn FnMut(&SeedOutcome) -> Result<()>,
) -> Result<StudySummary> {
    opts.check()?;
    let strength = study_strength(hidden, opts.strength)?;
    let speeds = opts.grid.speeds()?;
    let mut outcomes = Vec::new();
    let mut truth = None;
    progress.start(opts.seeds as u64, "seeds");
    for k in 0..opts.seeds {
        let seed = opts.first_seed + k as u64;
        let true_phase = hidden
            .has_phase()
            .then(|| true_phase(seed, opts.random_phase));
        let (effects, t_value) = hidden.effects(strength, true_phase.unwrap_or(0.0));
        truth = t_value;
        let t = seed_truth(opts, &speeds, seed, effects);
        let dir = match &opts.keep_sets {
            Some(keep) => keep.join(format!("seed-{seed}")),
            None => scratch.join("set"),
        };
        synth_munro(&t, &dir, &crate::progress::NoProgress).map_err(|e| {
            GearError::Unsupported(format!("the synthetic set of seed {seed}: {e}"))
        })?;
        let data = load_munro(&dir)?;
        let start = std::time::Instant::now();
        let mut dopts = opts.discover.clone();
        dopts.seed = opts.discover.seed.wrapping_add(seed);
        dopts.power_at = hidden.power_effect(truth);
        let truth_of_seed = SeedTruth {
            seed,
            hidden,
            value: truth,
            phase: true_phase,
        };
        // One set's failure is one seed's outcome: the study goes on, and says so.
        let outcome = match discover(&data, &dopts, &crate::progress::NoProgress) {
            Ok(d) => seed_outcome(&d, &truth_of_seed, start.elapsed().as_secs_f64()),
            Err(e) => failed_outcome(&truth_of_seed, &e, start.elapsed().as_secs_f64()),
        };
        on_seed(&outcome)?;
        outcomes.push(outcome);
        progress.advance(1);
    }
    progress.finish();
    Ok(summarise(hidden, opts, truth, outcomes))
}

/// The hidden effect's strength: the one asked for, or the study's default; none for the null
/// study, which refuses one.
fn study_strength(hidden: Hidden, asked: Option<f64>) -> Result<f64> {
    match (hidden, asked) {
        (Hidden::None, Some(s)) => Err(GearError::param(
            "strength",
            s,
            "the null study hides nothing: no strength to set",
        )),
        (_, Some(s)) => Ok(s),
        (_, None) => Ok(hidden.default_strength().unwrap_or(0.0)),
    }
}

/// The true phase of a phase-carrying effect in seed `seed` (rad): uniform on the circle when
/// `random`, else 0.
fn true_phase(seed: u64, random: bool) -> f64 {
    if random {
        // Its own stream, so that the noise of seed k is the same with or without it.
        2.0 * std::f64::consts::PI * Rng::new(seed ^ 0x005e_ed0f_9a5e).uniform()
    } else {
        0.0
    }
}

/// The synthetic set of one seed: Munro's rig and loads (or the study's), its noise, grid,
/// integrator and hidden effects.
fn seed_truth(
    opts: &StudyOptions,
    speeds: &[f64],
    seed: u64,
    effects: HiddenEffects,
) -> MunroTruth {
    let mut t = MunroTruth::default_munro();
    t.seed = seed;
    t.noise = opts.noise;
    match opts.grid {
        SpeedGrid::Uniform { step_rpm } => t.speeds_rpm = (1000.0, 5000.0, step_rpm),
        SpeedGrid::NonUniform { .. } => t.speed_list = Some(speeds.to_vec()),
    }
    t.hidden = effects;
    t.dop853_rtol = opts.dop853_rtol;
    if let Some(loads) = &opts.loads {
        t.ste_um = loads.clone();
    }
    t.publish_ste = opts.ste_sd_um.is_some();
    t.ste_sd_um = opts.ste_sd_um;
    t
}

/// What a seed hid: the effect, its strength in the candidate's units and its phase (rad).
struct SeedTruth {
    seed: u64,
    hidden: Hidden,
    value: Option<f64>,
    phase: Option<f64>,
}

/// The outcome of a seed on which `discover` failed with `error`: effect "error", nothing
/// estimated.
fn failed_outcome(truth: &SeedTruth, error: &GearError, seconds: f64) -> SeedOutcome {
    SeedOutcome {
        seed: truth.seed,
        true_phase: truth.phase,
        effect: "error".to_string(),
        seconds,
        error: Some(error.to_string()),
        ..SeedOutcome::default()
    }
}

/// Whether the phase `deg` (degrees, any turn) lies on the arc `(lo, hi)` (hi above lo, by at
/// most a turn).
fn on_phase_arc(deg: f64, (lo, hi): (f64, f64)) -> bool {
    (deg - lo).rem_euclid(360.0) <= hi - lo
}

/// One seed's discovery `d` scored against what it hid.
fn seed_outcome(d: &Discovery, truth: &SeedTruth, seconds: f64) -> SeedOutcome {
    let cand = d.named();
    let p_values = d
        .goodness_of_fit
        .p_value
        .map(|p| (d.goodness_of_fit.name.clone(), p))
        .into_iter()
        .chain(
            d.held_out_prediction
                .as_ref()
                .and_then(|h| Some((h.name.clone(), h.p_value?))),
        )
        .chain(
            d.candidates
                .iter()
                .filter_map(|c| c.p_value.map(|p| (format!("candidate_{}", c.name), p))),
        )
        .collect();
    let ci95 = cand.and_then(|c| c.ci95);
    let phase_deg = cand.and_then(|c| c.phase_deg);
    let phase_wald95_deg = cand.and_then(|c| c.phase_wald95_deg);
    let true_deg = truth.phase.map(f64::to_degrees);
    SeedOutcome {
        phase_covered: true_deg
            .zip(phase_wald95_deg)
            .map(|(t, arc)| on_phase_arc(t, arc)),
        phase_error_deg: truth
            .phase
            .zip(phase_deg)
            .map(|(t, e)| Candidate::angle_apart(e.to_radians(), t).to_degrees()),
        phase_deg,
        phase_wald95_deg,
        seed: truth.seed,
        true_phase: truth.phase,
        correct: d.effect == truth.hidden.expected(),
        covered: truth
            .value
            .zip(ci95)
            .map(|(v, (lo, hi))| v >= lo && v <= hi),
        estimate: cand.and_then(|c| c.estimate),
        ci95,
        wald_ci95: cand.and_then(|c| c.wald_ci95),
        profile_ci95: cand.and_then(|c| c.profile_ci95),
        held_out_rms_before_um: d.gap_before.held_out.as_ref().map(|g| g.rms_um),
        held_out_rms_after_um: d.gap_after.held_out.as_ref().map(|g| g.rms_um),
        excluded_far_outside: d.excluded_far_outside(),
        power_bound: d.power_bound.as_ref().map(|p| p.power),
        closest_candidate: d.closest_candidate.clone(),
        effect: d.effect.clone(),
        p_values,
        seconds,
        error: None,
    }
}

/// The study's rates over its seeds' outcomes, with Wilson 95% intervals; `truth` the hidden
/// effect's strength (None for the null study and the sensor peak).
fn summarise(
    hidden: Hidden,
    opts: &StudyOptions,
    truth: Option<f64>,
    outcomes: Vec<SeedOutcome>,
) -> StudySummary {
    let n = outcomes.len();
    let correct = outcomes.iter().filter(|o| o.correct).count();
    let good: Vec<&SeedOutcome> = outcomes.iter().filter(|o| o.correct).collect();
    let share =
        |flag: &dyn Fn(&SeedOutcome) -> bool| (good.iter().filter(|o| flag(o)).count(), good.len());
    let coverage = truth.map(|_| share(&|o| o.covered == Some(true)));
    let held_out_shrunk = truth.map(|_| {
        share(&|o| {
            o.held_out_rms_before_um
                .zip(o.held_out_rms_after_um)
                .is_some_and(|(b, a)| a < b)
        })
    });
    let rate = |flags: Vec<bool>| {
        (!flags.is_empty()).then(|| {
            let k = flags.iter().filter(|c| **c).count();
            (k, flags.len(), wilson95(k, flags.len()))
        })
    };
    let phase_coverage = rate(good.iter().filter_map(|o| o.phase_covered).collect());
    let null = hidden == Hidden::None;
    StudySummary {
        hidden,
        expected: hidden.expected(),
        true_value: truth,
        data_dop853_rtol: opts.dop853_rtol,
        data_grid: match opts.grid {
            SpeedGrid::Uniform { step_rpm } => format!("1000-5000 rpm in steps of {step_rpm} rpm"),
            SpeedGrid::NonUniform { points, seed } => {
                format!("{points} speeds drawn in 1000-5000 rpm (draw seed {seed})")
            }
        },
        random_phase: opts.random_phase,
        data_noise_family: opts.noise.family.name(),
        data_noise_floor_um: opts.noise.model.floor,
        data_noise_relative: opts.noise.model.relative,
        data_ste_sd_um: opts.ste_sd_um,
        seeds: n,
        correct,
        correct_rate: correct as f64 / n as f64,
        correct_ci95: wilson95(correct, n),
        false_positive_rate: null
            .then(|| ((n - correct) as f64 / n as f64, wilson95(n - correct, n))),
        false_positive_upper95: if null {
            clopper_pearson_upper95(n - correct, n)
        } else {
            None
        },
        coverage,
        held_out_shrunk,
        phase_coverage,
        warned: outcomes
            .iter()
            .filter(|o| o.excluded_far_outside > 0)
            .count(),
        failed: outcomes
            .iter()
            .filter_map(|o| o.error.clone().map(|e| (o.seed, e)))
            .collect(),
        calibration: calibration(&outcomes),
        power_bound_mean: {
            let powers: Vec<f64> = outcomes.iter().filter_map(|o| o.power_bound).collect();
            (!powers.is_empty()).then(|| powers.iter().sum::<f64>() / powers.len() as f64)
        },
        outcomes,
    }
}

/// [`TestCalibration`] of every test that has a p-value in some seed, in first-seen order.
fn calibration(outcomes: &[SeedOutcome]) -> Vec<TestCalibration> {
    let mut names: Vec<&str> = Vec::new();
    for (n, _) in outcomes.iter().flat_map(|o| &o.p_values) {
        if !names.contains(&n.as_str()) {
            names.push(n);
        }
    }
    names
        .into_iter()
        .map(|name| {
            let mut p: Vec<f64> = outcomes
                .iter()
                .flat_map(|o| &o.p_values)
                .filter(|(n, _)| n == name)
                .map(|(_, p)| *p)
                .collect();
            p.sort_by(f64::total_cmp);
            let n = p.len();
            let below = |a: f64| {
                let k = p.iter().filter(|x| **x < a).count();
                (k, wilson95(k, n))
            };
            TestCalibration {
                name: name.to_string(),
                seeds: n,
                below_5pct: below(0.05),
                below_1pct: below(0.01),
                ks_distance: ks_from_uniform(&p),
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_hidden_effect_reads_back_from_its_name() {
        let all = [Hidden::None, Hidden::SensorPeak]
            .into_iter()
            .chain(crate::discover::LIBRARY.iter().map(|c| Hidden::Library(*c)));
        for h in all {
            assert_eq!(Hidden::parse(h.name()), Some(h), "{}", h.name());
        }
        assert_eq!(Hidden::parse("None"), None);
    }

    /// A seed on which `discover` failed is an outcome of its own: listed with its error,
    /// counted as not correct (for the null study, not "none").
    #[test]
    fn a_failed_seed_is_listed_and_counted_as_not_correct() {
        let truth = |seed| SeedTruth {
            seed,
            hidden: Hidden::None,
            value: None,
            phase: None,
        };
        let e = GearError::Numerical("no start converged".into());
        let outcomes = vec![
            failed_outcome(&truth(3), &e, 0.1),
            failed_outcome(&truth(5), &e, 0.2),
        ];
        let s = summarise(Hidden::None, &StudyOptions::default(), None, outcomes);
        assert_eq!(s.correct, 0);
        assert_eq!(
            s.failed,
            [
                (3, "numerical failure: no start converged".to_string()),
                (5, "numerical failure: no start converged".to_string())
            ]
        );
        assert_eq!(s.false_positive_rate.map(|r| r.0), Some(1.0));
        assert_eq!(s.outcomes[0].effect, "error");
    }
}
