//! `validate kubo` (Sec. 7, Fig. 23): the dynamic load factor D_L = max (2 zeta q' + k f(q)) / F_m
//! over a period versus speed, against the envelope of Kubo's measured dynamic factors. zeta and
//! omega_n come from rig.toml when given, else they are fitted (with the STE amplitude when not
//! given) to the envelope midline where the teeth stay in contact.
//!
//! Which points are "in contact" is decided by the model, not by each point's measured value:
//! selecting on the measured D_L (< 1.8) keeps the points whose tooth-pair scatter happens to be
//! low near the threshold, a selection on the response that biased zeta up by ~15% on synthetic
//! sets with known truth. So a first fit on the measured selection only starts an iteration in
//! which the points are those where the fitted linear model has D_L < 1.8 (it separates at 2)
//! and, above the resonance, the describing-function solution has contact as the only steady
//! state; refit until the selection repeats.

use super::curve_metrics::{location_error, location_error_text, rms, transition_location};
use super::design_fit::CorrelationChoice;
use super::fit_check::{fit_failed, fit_failure, FITTED_ZETA};
use super::kubo_midline::{measured_peak_rpm, midline, ste_of, MidlineFit, MidlineSetting};
use super::kubo_swept::fit_whole_curve;
use super::linear::load_factor_max;
use super::test_run::TestRun;
use crate::data::{rig_key_error, KuboData, KuboPoint};
use crate::error::{GearError, Result};
use crate::fit::{Estimate, ProfileInterval, Stop};
use crate::model::{Dimensional, GearPair};
use crate::progress::{NoProgress, Progress};
use crate::sim::{Branch, SteadyOptions, SweepPoint};
use serde::Serialize;

/// The Runge-Kutta tolerance the sweeps ([`TestRun::sweep`]) ask for: unused, as the model's
/// mesh stiffness is constant and its flow the exact solver's.
pub(super) const UNUSED_RK_RTOL: f64 = 1e-9;

/// D_L below which the teeth are taken to stay in contact for the fit (the linear model
/// separates at 2; the margin keeps the points off the separation).
pub const CONTACT_LIMIT: f64 = 1.8;
/// Refits with a model-based point selection before giving up on a fixed point.
const SELECTION_ROUNDS: usize = 6;

/// The points where the model with (zeta, omega_n) keeps the teeth in contact: linear D_L below
/// [`CONTACT_LIMIT`], and above the resonance (Omega > 1, where the separated branch can persist
/// on an up-sweep) the describing-function solution's only steady state is contact (case I).
fn contact_points<'a>(
    points: &[&'a KuboPoint],
    dim: &Dimensional,
    fm: f64,
    fah: f64,
    zeta: f64,
    omega_n_hz: f64,
) -> Result<Vec<&'a KuboPoint>> {
    let mut out = Vec::new();
    for &p in points {
        let om = dim.omega(p.speed_rpm, omega_n_hz);
        if load_factor_max(fm, fah, zeta, om) >= CONTACT_LIMIT {
            continue;
        }
        if om > 1.0 {
            let sols = crate::hb::df_solutions(fm, fah, zeta, om, crate::hb::DfMethod::Exact)?;
            if !(sols.len() == 1 && sols[0].case == crate::model::Impact::None) {
                continue;
            }
        }
        out.push(p);
    }
    Ok(out)
}

/// Which part of the measured envelope zeta and omega_n are fitted to (when rig.toml does not
/// give them).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum KuboFitPath {
    /// The contact part, and the whole curve when the contact part does not determine zeta.
    #[default]
    Auto,
    /// The contact part only (closed form of the linear model; an error when it does not
    /// determine zeta). Depends least on how the model treats separation.
    ContactPart,
    /// The whole curve through simulated up-sweeps, separation and jump included: the most
    /// information (the peak), about 10 s on 2 cores instead of hundredths.
    WholeCurve,
}

/// Settings of the Kubo pipeline.
#[derive(Clone, Debug)]
pub struct KuboOptions {
    /// Points of the dense speed grid on which the model curves are drawn.
    pub dense_points: usize,
    /// What the parameters are fitted to.
    pub fit_path: KuboFitPath,
    /// Hold the STE amplitude at rig.toml's value instead of fitting it from there. A stated
    /// STE is a nominal value: on independently made envelopes (each tooth pair with its own
    /// STE) holding it made zeta's intervals cover 74% instead of 94% (docs/validation.md).
    pub hold_ste: bool,
    /// The errors' correlation along speed (`--correlation`, docs/correlated-errors.md).
    /// Independent by default: estimated on a whole-curve fit through simulated sweeps (a
    /// synthetic envelope of independent errors whose teeth separate at nearly every speed),
    /// the correlation took the misfit at the jump for drift and zeta ended thousands of
    /// standard errors from the truth; the Kubo fits' correlation awaits its coverage study.
    pub correlation: CorrelationChoice,
}

impl Default for KuboOptions {
    fn default() -> Self {
        KuboOptions {
            dense_points: 161,
            fit_path: KuboFitPath::Auto,
            hold_ste: false,
            correlation: CorrelationChoice::Off,
        }
    }
}

/// Everything `validate kubo` computed.
#[derive(Clone, Debug, Serialize)]
pub struct KuboValidation {
    /// The fit, when zeta and omega_n were not given in rig.toml.
    pub fit: Option<Estimate>,
    pub ci95_profile: Vec<ProfileInterval>,
    /// "fitted to the contact part of the curve" or "given in rig.toml".
    pub parameter_source: String,
    pub zeta: f64,
    pub omega_n_hz: f64,
    pub ste_um: f64,
    pub ste_source: String,
    pub load_n: f64,
    pub mean_force: f64,
    pub ste_amplitude: f64,
    pub points_used_in_fit: usize,
    /// (speed, min, max) of the measured envelope.
    pub envelope: Vec<(f64, f64, f64)>,
    /// (speed, D_L, case) carried up and down.
    pub up: Vec<(f64, f64, u8)>,
    pub down: Vec<(f64, f64, u8)>,
    /// Share of measured speeds where the up-branch D_L lies inside the envelope.
    pub inside_fraction: f64,
    /// RMS distance of the up branch outside the envelope at the measured speeds (0 inside).
    pub outside_rms: f64,
    pub jump_measured_rpm: Option<f64>,
    pub jump_up_rpm: Option<f64>,
    pub jump_error_rpm: Option<f64>,
    /// How finely the grids place that error, rpm: half the envelope's speed step at its
    /// transition plus half the model sweep's at its own.
    pub jump_error_resolution_rpm: Option<f64>,
}

impl KuboValidation {
    /// The transition error as "-125 ± 75" followed by `unit` (rpm, with the grids'
    /// resolution), or "-" when the envelope or the model has no transition.
    pub fn transition_error_text(&self, unit: &str) -> String {
        self.jump_error_rpm.map_or("-".to_string(), |e| {
            location_error_text(e, self.jump_error_resolution_rpm, unit)
        })
    }
}

struct ContactFit<'a> {
    dim: &'a Dimensional,
    fm: f64,
    points: Vec<&'a KuboPoint>,
    ste: MidlineSetting,
}

impl ContactFit<'_> {
    /// The model's D_L at each point for (zeta, omega_n[, STE]).
    fn curve(&self, p: &[f64]) -> Result<Vec<f64>> {
        let fah = self.dim.ste_amplitude(ste_of(self.ste.held, p));
        Ok(self
            .points
            .iter()
            .map(|k| load_factor_max(self.fm, fah, p[0], self.dim.omega(k.speed_rpm, p[1])))
            .collect())
    }

    fn problem(&self) -> MidlineFit {
        // The closed form is smooth: the fit and its profiles run to convergence.
        let stop = Stop::converged(100).central();
        MidlineFit::new(
            (
                self.points.iter().map(|k| k.speed_rpm).collect(),
                midline(self.points.iter().copied()),
            ),
            self.ste,
            // In contact D_L - 1 is proportional to the STE amplitude, so the mean of two
            // pairs' D_L is one pair's at their mean STE: the spread does not enter.
            None,
            (stop, stop),
        )
    }

    fn fit(&self, starts: &[Vec<f64>]) -> Result<Estimate> {
        self.problem().fit(&|p: &[f64]| self.curve(p), None, starts)
    }

    fn profile(&self, est: &Estimate) -> Result<Vec<ProfileInterval>> {
        self.problem().profile(&|p: &[f64]| self.curve(p), est)
    }
}

/// zeta, omega_n and the STE amplitude the model curves are drawn with, and where they came
/// from.
pub(super) struct ModelParameters {
    /// The fit, when zeta and omega_n were not given in rig.toml.
    pub fit: Option<Estimate>,
    pub profile: Vec<ProfileInterval>,
    pub zeta: f64,
    pub omega_n_hz: f64,
    pub ste_um: f64,
    pub source: String,
    pub points_used: usize,
    /// Whether the STE amplitude was held (given with zeta and omega_n, or held in the fit).
    pub ste_held: bool,
}

/// Run the Kubo validation on a loaded data set.
pub fn validate_kubo(
    data: &KuboData,
    opts: &KuboOptions,
    progress: &dyn Progress,
) -> Result<KuboValidation> {
    let rig = &data.rig.rig;
    let dim = rig.dimensional()?;
    let load = rig.test_load_n.unwrap_or(rig.design_load_n);
    let fm = dim.mean_force(load);
    let ste_stated = data.rig.ste.as_ref().and_then(|t| t.amplitude_at(load));
    let ste_sd = data.rig.ste.as_ref().and_then(|t| t.sd_at(load));
    if opts.hold_ste && ste_stated.is_none() {
        return Err(GearError::Unsupported(format!(
            "--hold-ste: rig.toml's [ste] table gives no STE amplitude at the test load {load} N to hold; add it there, or leave --hold-ste out to fit it"
        )));
    }
    if let (true, Some(sd)) = (opts.hold_ste, ste_sd) {
        return Err(GearError::Unsupported(format!(
            "--hold-ste: rig.toml's [ste] states the STE at the test load {load} N with an uncertainty (sd_um = {sd}), so it is weighed against the curve as a measurement; holding it exact would throw that uncertainty away. Leave --hold-ste out, or remove sd_um to hold the stated value"
        )));
    }
    let ste = MidlineSetting {
        held: ste_stated.filter(|_| opts.hold_ste),
        start: ste_stated.unwrap_or(1.0),
        stated_sd: ste_stated.and(ste_sd),
        correlation: opts.correlation,
    };
    let par = match (rig.zeta, rig.omega_n_hz) {
        (Some(z), Some(w)) => given_parameters(data, z, w, ste_stated)?,
        (None, None) => fit_parameters(data, &dim, fm, ste, opts.fit_path, progress)?,
        (Some(_), None) | (None, Some(_)) => {
            let key = if rig.zeta.is_some() {
                "zeta"
            } else {
                "omega_n_hz"
            };
            return Err(rig_key_error(
                &data.dir,
                "rig",
                key,
                "validate kubo takes zeta and omega_n_hz as fixed values only when both are given \
                 (else it fits both): give the other one too, or remove this one",
            ));
        }
    };
    let fah = dim.ste_amplitude(par.ste_um);
    let ste_source = ste_source(ste_stated, ste_sd, par.ste_held);
    let model = GearPair::paper(fm, fah, par.zeta, 1.0)?;
    let speeds = drawing_speeds(&data.points, opts.dense_points);
    progress.start(2, "branches");
    let carried = |branch| -> Result<Vec<(f64, f64, u8)>> {
        let pts = TestRun {
            dim: &dim,
            model: &model,
            omega_n_hz: par.omega_n_hz,
            speeds: &speeds,
            opts: &SteadyOptions::default(),
        }
        .sweep(branch, UNUSED_RK_RTOL, &NoProgress)?;
        Ok(branch_points(&dim, par.omega_n_hz, &pts))
    };
    let up = carried(Branch::Up)?;
    progress.advance(1);
    let down = carried(Branch::Down)?;
    progress.advance(1);
    progress.finish();
    let outside = outside_envelope(&data.points, &up);
    let inside = outside.iter().filter(|d| **d == 0.0).count();
    let mid: Vec<(f64, f64)> = data
        .points
        .iter()
        .map(|p| {
            (
                p.speed_rpm,
                0.5 * (p.dynamic_factor_min + p.dynamic_factor_max),
            )
        })
        .collect();
    let jump_measured = transition_location(&mid, 6.0);
    let up_curve: Vec<(f64, f64)> = up.iter().map(|u| (u.0, u.1)).collect();
    let jump_up = transition_location(&up_curve, 6.0);
    let (jump_error_rpm, jump_error_resolution_rpm) =
        location_error((&mid, jump_measured), (&up_curve, jump_up));
    Ok(KuboValidation {
        fit: par.fit,
        ci95_profile: par.profile,
        parameter_source: par.source,
        zeta: par.zeta,
        omega_n_hz: par.omega_n_hz,
        ste_um: par.ste_um,
        ste_source,
        load_n: load,
        mean_force: fm,
        ste_amplitude: fah,
        points_used_in_fit: par.points_used,
        envelope: data
            .points
            .iter()
            .map(|p| (p.speed_rpm, p.dynamic_factor_min, p.dynamic_factor_max))
            .collect(),
        inside_fraction: inside as f64 / data.points.len().max(1) as f64,
        outside_rms: rms(&outside),
        jump_error_rpm,
        jump_error_resolution_rpm,
        jump_measured_rpm: jump_measured,
        jump_up_rpm: jump_up,
        up,
        down,
    })
}

/// zeta and omega_n as rig.toml gives them, which then has to give the STE amplitude too.
fn given_parameters(
    data: &KuboData,
    zeta: f64,
    omega_n_hz: f64,
    ste_given: Option<f64>,
) -> Result<ModelParameters> {
    let ste_um = ste_given.ok_or_else(|| {
        rig_key_error(
            &data.dir,
            "ste",
            "amplitude_um",
            "zeta and omega_n_hz are given, so the STE amplitude at the test load must be given too",
        )
    })?;
    Ok(ModelParameters {
        fit: None,
        profile: Vec::new(),
        zeta,
        omega_n_hz,
        ste_um,
        source: "given in rig.toml".into(),
        points_used: 0,
        ste_held: true,
    })
}

/// What the contact-part fit gave: usable parameters, or why not with the values it reached
/// (empty when it could not be fitted at all).
enum ContactOutcome {
    Usable(Box<ModelParameters>),
    Undetermined { reason: String, reached: Vec<f64> },
}

/// zeta, omega_n (and the STE amplitude when rig.toml does not give it) fitted to the
/// contact part of the envelope ([`fit_contact_part`]), or to the whole curve
/// ([`fit_whole_curve`]) as `path` says. The whole-curve fit starts from the values the
/// contact fit reached (a few hundredths of a second).
fn fit_parameters(
    data: &KuboData,
    dim: &Dimensional,
    fm: f64,
    ste: MidlineSetting,
    path: KuboFitPath,
    progress: &dyn Progress,
) -> Result<ModelParameters> {
    let contact = fit_contact_part(data, dim, fm, ste);
    match path {
        KuboFitPath::WholeCurve => {
            // The contact fit only gives starts here; what stopped it does not stop this fit.
            let reached = match contact {
                Ok(ContactOutcome::Usable(p)) => p.fit.map(|f| f.params).unwrap_or_default(),
                Ok(ContactOutcome::Undetermined { reached, .. }) => reached,
                Err(_) => Vec::new(),
            };
            fit_whole_curve(data, dim, fm, ste, &reached, WHOLE_AS_ASKED, progress)
        }
        KuboFitPath::Auto => match contact? {
            ContactOutcome::Usable(p) => Ok(*p),
            ContactOutcome::Undetermined { reason, reached } => {
                fit_whole_curve(data, dim, fm, ste, &reached, WHOLE_AS_FALLBACK, progress)
                    .map_err(|e| whole_curve_failed(data, reason, e))
            }
        },
        KuboFitPath::ContactPart => match contact? {
            ContactOutcome::Usable(p) => Ok(*p),
            ContactOutcome::Undetermined { reason, .. } => Err(fit_failed(
                &data.dir,
                "fit to the contact part",
                format!(
                    "{reason}; fit the whole curve instead (--fit whole), or give zeta and \
                     omega_n_hz (and the STE) in rig.toml"
                ),
            )),
        },
    }
}

/// The parameter source of a whole-curve fit taken because the contact part did not
/// determine zeta.
const WHOLE_AS_FALLBACK: &str =
    "fitted to the whole curve by simulated up-sweeps, the contact part not determining zeta";
/// The parameter source of a whole-curve fit asked for (`--fit whole`).
const WHOLE_AS_ASKED: &str = "fitted to the whole curve by simulated up-sweeps";

/// zeta, omega_n (and the STE amplitude when rig.toml does not give it) fitted to the envelope
/// midline where the model keeps the teeth in contact (see the module's doc): a first fit to
/// the points below the resonance whose measured D_L is under [`CONTACT_LIMIT`], then refits
/// on the model's own selection until it repeats.
fn fit_contact_part(
    data: &KuboData,
    dim: &Dimensional,
    fm: f64,
    ste: MidlineSetting,
) -> Result<ContactOutcome> {
    let contact: Vec<&KuboPoint> = data
        .points
        .iter()
        .filter(|p| p.dynamic_factor_max < CONTACT_LIMIT)
        .collect();
    let k = 2 + usize::from(ste.held.is_none());
    if contact.len() < k + 3 {
        return Ok(ContactOutcome::Undetermined {
            reason: format!(
                "only {} points have D_L < {CONTACT_LIMIT} (teeth in contact)",
                contact.len()
            ),
            reached: Vec::new(),
        });
    }
    // Below the resonance the up-sweep is on the contact branch while D_L < limit; above
    // it the separated branch can persist, so those points join only where the
    // describing-function solution says contact is the unique steady state.
    let peak_speed = measured_peak_rpm(&data.points).unwrap_or(f64::INFINITY);
    let below: Vec<&KuboPoint> = contact
        .iter()
        .copied()
        .filter(|p| p.speed_rpm < peak_speed)
        .collect();
    let mut starts = first_starts(dim.mesh_frequency_hz(peak_speed), ste);
    let problem_on = |points| ContactFit {
        dim,
        fm,
        points,
        ste,
    };
    let mut r = match problem_on(below.clone()).fit(&starts) {
        Ok(r) => r,
        Err(e) => {
            return Ok(ContactOutcome::Undetermined {
                reason: e.to_string(),
                reached: Vec::new(),
            })
        }
    };
    let all: Vec<&KuboPoint> = data.points.iter().collect();
    let mut selected: Vec<f64> = Vec::new();
    let mut problem = None;
    for _ in 0..SELECTION_ROUNDS {
        // A fit that ran zeta out of what the model admits (an underdamped mesh, 0 < zeta < 1:
        // `GearPair::validated`) selects nothing, the describing function refusing it; it is
        // refused below and the whole curve fitted instead. A first fit that ran zeta towards
        // 0 but not to it still selects, and the refits on that selection usually recover
        // (17 of 200 sets with 4 tooth pairs and 8% scatter).
        let zeta = r.params[0];
        if !(zeta > 0.0 && zeta < 1.0) {
            break;
        }
        let e = ste_of(ste.held, &r.params);
        let used = contact_points(
            &all,
            dim,
            fm,
            dim.ste_amplitude(e),
            r.params[0],
            r.params[1],
        )?;
        let speeds: Vec<f64> = used.iter().map(|p| p.speed_rpm).collect();
        if speeds == selected || used.len() < k + 3 {
            break;
        }
        selected = speeds;
        let pr = problem_on(used);
        starts.push(r.params.clone());
        r = match pr.fit(&starts) {
            Ok(refit) => refit,
            Err(e) => {
                return Ok(ContactOutcome::Undetermined {
                    reason: e.to_string(),
                    reached: r.params,
                })
            }
        };
        problem = Some(pr);
    }
    let problem = problem.unwrap_or_else(|| problem_on(below));
    let profile = problem.profile(&r)?;
    if let Some(reason) = fit_failure(&r, &profile, FITTED_ZETA) {
        return Ok(ContactOutcome::Undetermined {
            reason,
            reached: r.params,
        });
    }
    Ok(ContactOutcome::Usable(Box::new(ModelParameters {
        ste_um: ste_of(ste.held, &r.params),
        zeta: r.params[0],
        omega_n_hz: r.params[1],
        fit: Some(r),
        profile,
        source: "fitted to the contact part of the curve".into(),
        points_used: problem.points.len(),
        ste_held: ste.held.is_some(),
    })))
}

/// Where the STE amplitude of the model curves came from: the value `stated` in rig.toml,
/// held there, weighed against the curve as a measurement with its uncertainty `sd`, or
/// fitted (from the stated value when there is one).
fn ste_source(stated: Option<f64>, sd: Option<f64>, held: bool) -> String {
    // Six digits: a set written by a program states the STE to full double precision, which
    // the reports' source column would otherwise print as 17 digits.
    let six = |v: f64| crate::numeric::to_significant(v, 6);
    match (stated, held, sd) {
        (Some(_), true, _) => "rig.toml".into(),
        (Some(s), false, Some(sd)) => format!(
            "fitted with rig.toml's {} ± {} um weighed in as a measurement",
            six(s),
            six(sd)
        ),
        (Some(s), false, None) => format!(
            "fitted (rig.toml states {} um, the fit's start; --hold-ste holds it)",
            six(s)
        ),
        (None, _, _) => "fitted".into(),
    }
}

/// The error when neither the contact part (`contact`, why it could not be used) nor the whole
/// curve (`whole`) gave a usable fit.
fn whole_curve_failed(data: &KuboData, contact: String, whole: GearError) -> GearError {
    // A failed fit's reason already names the whole-curve fit; another error does not.
    let whole = match whole {
        GearError::FitFailed { reason, .. } => reason,
        e => format!("fit to the whole curve: {e}"),
    };
    fit_failed(
        &data.dir,
        "fit to the contact part",
        format!(
            "{contact}; and the {whole}; give zeta and omega_n_hz (and the STE) in rig.toml \
             to draw the model without a fit"
        ),
    )
}

/// Starts of the first contact fit: zeta over a decade, omega_n about the mesh frequency of
/// the measured peak (the resonance), the STE amplitude at its start when it is fitted.
fn first_starts(peak_mesh_hz: f64, ste: MidlineSetting) -> Vec<Vec<f64>> {
    let mut starts = Vec::new();
    for z in [0.03, 0.1, 0.2] {
        for f in [0.8, 1.0, 1.2] {
            let mut s = vec![z, peak_mesh_hz * f];
            if ste.held.is_none() {
                s.push(ste.start);
            }
            starts.push(s);
        }
    }
    starts
}

/// The speeds the model curves are drawn at: a dense grid over the measured range, with the
/// measured speeds themselves (where the envelope is compared).
fn drawing_speeds(points: &[KuboPoint], dense_points: usize) -> Vec<f64> {
    let measured: Vec<f64> = points.iter().map(|p| p.speed_rpm).collect();
    let (lo, hi) = (measured[0], measured[measured.len() - 1]);
    let n = dense_points.max(2);
    let mut speeds: Vec<f64> = (0..n)
        .map(|i| lo + (hi - lo) * i as f64 / (n - 1) as f64)
        .collect();
    speeds.extend(&measured);
    speeds.sort_by(f64::total_cmp);
    speeds.dedup_by(|a, b| (*a - *b).abs() <= 1e-9 * b.abs());
    speeds
}

/// (speed, D_L, impact case) at each point of a sweep `pts` (see [`TestRun::sweep`]).
fn branch_points(dim: &Dimensional, omega_n_hz: f64, pts: &[SweepPoint]) -> Vec<(f64, f64, u8)> {
    pts.iter()
        .map(|p| {
            (
                dim.speed_rpm(p.omega, omega_n_hz),
                p.steady.dl_max.unwrap_or(f64::NAN),
                p.steady.impact.case(),
            )
        })
        .collect()
}

/// At each measured speed, how far the up branch's D_L lies outside the measured envelope
/// (0 inside it, and where the branch has no point at that speed: such a speed is counted
/// as inside).
fn outside_envelope(points: &[KuboPoint], up: &[(f64, f64, u8)]) -> Vec<f64> {
    points
        .iter()
        .map(|p| {
            let m = up
                .iter()
                .find(|u| (u.0 - p.speed_rpm).abs() <= 1e-6 * p.speed_rpm)
                .map_or(f64::NAN, |u| u.1);
            if m < p.dynamic_factor_min {
                p.dynamic_factor_min - m
            } else if m > p.dynamic_factor_max {
                m - p.dynamic_factor_max
            } else {
                0.0
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::ste_source;

    #[test]
    fn a_stated_ste_is_quoted_to_six_digits() {
        let s = ste_source(Some(2.990_954_998_206_589_3), None, false);
        assert!(s.contains("states 2.99095 um"), "{s}");
        assert!(ste_source(Some(3.0), None, false).contains("states 3 um"));
        let m = ste_source(Some(3.0), Some(0.050_000_000_000_001), false);
        assert!(m.contains("3 ± 0.05 um weighed in"), "{m}");
    }
}
