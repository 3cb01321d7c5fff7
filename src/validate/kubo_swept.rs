//! The whole-curve fit of `validate kubo`: zeta, omega_n, the STE amplitude (unless held) and
//! the tooth pairs' STE half-spread fitted to the envelope midline at every measured speed, the
//! model's midline the mean of two pairs' D_L from simulated up-sweeps (exact solver, state
//! carried from one speed to the next, as a test run is measured), separation and jumps
//! included ([`SweptFit::curve`]).
//!
//! The contact-part fit ([`super::kubo`]) uses the closed form of the linear model and is exact
//! only where the teeth stay in contact. On a lightly damped rig the teeth separate over the
//! whole resonance, the contact part holds no peak, and zeta is not determined there (at zeta
//! 0.06, 2200 Hz, 114 of 200 seeded sets were refused). The peak is where the damping shows,
//! so this fit takes the whole curve through the nonlinear model.

use super::fit_check::{fit_failed, fit_failure, FITTED_ZETA};
use super::kubo::{ModelParameters, UNUSED_RK_RTOL};
use super::kubo_midline::{measured_peak_rpm, midline, ste_of, MidlineFit, MidlineSetting};
use super::test_run::{up_sweep_neighbour_starts, TestRun};
use crate::data::KuboData;
use crate::error::{GearError, Result};
use crate::fit::{Estimate, ProfileInterval, Stop};
use crate::model::{Dimensional, GearPair};
use crate::progress::{NoProgress, Progress};
use crate::sim::{State, SteadyOptions};
use quick_cache::sync::Cache;
use rayon::prelude::*;
use std::sync::Arc;

/// Jacobians at most in the fit (a simulated curve: 10-30 on the sets tried).
const SWEPT_JACOBIANS: usize = 60;

/// The fit stops once three Jacobians gained less than this (sigma^2 units; see
/// [`Stop::stall`]): within 0.01 standard errors of where it creeps to, far inside what the
/// report prints (the creep took half the fit's 11 s on a set whose optimum lies at a jump).
const FIT_STALL: f64 = 1e-4;
/// The profile intervals' inner fits stop once three Jacobians gained less than this: an
/// interval's end then lies within 0.01 / (2 x 1.96) = 0.003 standard errors. Creeping to
/// convergence, they took 100 s of 115 on that set (0.3-0.9 s a sweep at the saddle-node);
/// with this rule 15 s, the ends moving by less than 1e-5 of their values.
const PROFILE_STALL: f64 = 1e-2;

/// The least damping ratio the fit simulates. A sweep's transients last 30 / zeta forcing
/// periods at each speed: at zeta 0.01 a sweep of 81 speeds took 0.02 s, at 4e-4 26 s and
/// at 2e-5 129 s. Unbounded, the profile of a free STE on an independent envelope (set-035 of
/// batch 515) ran zeta there and took over 12 minutes; the paper's lightest damping (Munro's
/// rig, 0.0175) is 3.5 times the floor. A fit or profile end at the floor is reported as not
/// determined by the curve.
pub(super) const SWEPT_ZETA_MIN: f64 = 0.005;

/// Where the fit starts the pairs' relative STE half-spread h ([`SweptFit::curve`]).
const PAIR_SPREAD_START: f64 = 0.05;
/// Largest half-spread the fit takes: the extreme pairs' STE amplitudes within a factor of 3
/// of each other (the independent batches spread them by 3-30%).
const PAIR_SPREAD_MAX: f64 = 0.5;

/// Damping ratios the fit starts from, each at two natural frequencies: the light end of
/// what a rig whose contact part did not determine zeta may have, to Kubo's 0.1 and beyond.
const START_ZETAS: [f64; 3] = [0.03, 0.06, 0.12];

/// Natural frequencies of the coarse grid the starts are screened on (see
/// [`SweptFit::screened`]), and how many of its best points start fits.
const SCREEN_OMEGAS: usize = 12;
const SCREENED_STARTS: usize = 2;

/// zeta, omega_n (and the STE amplitude unless `ste` holds it) fitted to the whole curve of
/// `data`, at load `fm`, started about `near` (the values the contact-part fit reached, empty
/// when it reached none) and about the measured peak; `source` says why this path was taken.
///
/// The model is two tooth pairs ([`SweptFit::curve`]); where the curve does not tell their
/// spread from the damping (the fit is refused: on a rig whose teeth separate at nearly every
/// speed, zeta's profile ran to the floor with the spread widening), the nested model of one
/// pair is fitted instead and `parameter_source` says so.
pub(super) fn fit_whole_curve(
    data: &KuboData,
    dim: &Dimensional,
    fm: f64,
    ste: MidlineSetting,
    near: &[f64],
    source: &'static str,
    progress: &dyn Progress,
) -> Result<ModelParameters> {
    let fitted = |pairs| fit_with(data, dim, fm, ste, near, pairs, progress);
    let (fit, profile, source) = match fitted(true) {
        Ok((fit, profile)) => (fit, profile, source.to_string()),
        Err(GearError::FitFailed { .. }) => {
            let (fit, profile) = fitted(false)?;
            let source = format!(
                "{source}; one tooth pair (the whole-curve fit does not determine the pairs' \
                 STE spread)"
            );
            (fit, profile, source)
        }
        Err(e) => return Err(e),
    };
    Ok(ModelParameters {
        ste_um: ste_of(ste.held, &fit.params),
        zeta: fit.params[0],
        omega_n_hz: fit.params[1],
        fit: Some(fit),
        profile,
        source,
        points_used: data.points.len(),
        ste_held: ste.held.is_some(),
    })
}

/// Profile-likelihood 95% intervals per fitted parameter (None: unbounded on that side).
type ProfileIntervals = Vec<ProfileInterval>;

/// The whole-curve fit and its profile intervals, with two tooth pairs or one (`pairs`); an
/// error when [`fit_failure`] refuses it.
fn fit_with(
    data: &KuboData,
    dim: &Dimensional,
    fm: f64,
    ste: MidlineSetting,
    near: &[f64],
    pairs: bool,
    progress: &dyn Progress,
) -> Result<(Estimate, ProfileIntervals)> {
    let problem = SweptFit {
        dim,
        fm,
        speeds: data.points.iter().map(|k| k.speed_rpm).collect(),
        midline: midline(&data.points),
        ste,
        pair_spread: pairs.then_some(PAIR_SPREAD_START),
        sweeps: Cache::new(REMEMBERED_SWEEPS),
    };
    progress.start(2, "whole-curve fit (simulated up-sweeps)");
    let mut from = starts(data, dim, near, ste, problem.pair_spread);
    from.extend(problem.screened(ste));
    let mut fit = problem.fit(&from)?;
    progress.advance(1);
    let zeta_range = (SWEPT_ZETA_FLOOR, FITTED_ZETA.1);
    let refused =
        |fit: &Estimate, profile: &[ProfileInterval]| fit_failure(fit, profile, zeta_range);
    let mut refits = 0;
    let profile = loop {
        if refused(&fit, &[]).is_some() {
            break Vec::new();
        }
        let go_on = |so_far: &[ProfileInterval]| refused(&fit, so_far).is_none();
        match problem.profile_while(&fit, Some(BETTER_BY), go_on)? {
            (profile, None) => break profile,
            (_, Some(better)) if refits < MAX_REFITS => {
                refits += 1;
                // A refit from one start may fail where the first fit's many did not: that
                // refuses this model (the one-pair fit follows), it does not end the run.
                fit = problem.fit(&[better]).map_err(|e| {
                    let reason =
                        format!("the refit from a better point of its profile failed: {e}");
                    fit_failed(&data.dir, "fit to the whole curve", reason)
                })?;
            }
            (_, Some(_)) => {
                let reason = format!(
                    "its profile still found a better fit after {MAX_REFITS} refits: the \
                     curve's minima are too many to tell"
                );
                return Err(fit_failed(&data.dir, "fit to the whole curve", reason));
            }
        }
    };
    progress.advance(1);
    progress.finish();
    if let Some(reason) = refused(&fit, &profile) {
        return Err(fit_failed(&data.dir, "fit to the whole curve", reason));
    }
    Ok((fit, profile))
}

/// A profile point fitting better than the fit by more than this (sigma^2) is a minimum the
/// fit's starts missed, and the fit starts again from it: the height of a 95% interval (the
/// chi-square quantile of one degree of freedom), beyond which the fit lies outside the
/// likelihood region about the better point. Smaller differences are the steps a jump crossing
/// a speed puts in the sum of squares: at 0.1 the two-pair fit of the rig below walked down
/// them by 0.002 in zeta per refit and the refits ran out.
const BETTER_BY: f64 = 3.84;
/// Refits from better profile points at most (each costs a fit and the profiles before it).
const MAX_REFITS: usize = 3;

/// A zeta below this, 1.1 times [`SWEPT_ZETA_MIN`], lies at the floor: the fit could not go
/// below it (a curve that fails there counts as infinitely bad), so a fit or a profile's
/// lower end there is the floor's, not the data's. Profiles go no lower
/// ([`Param::profile_floor`](crate::fit::Param::profile_floor)): halving towards the floor
/// with sweeps ever slower took 135 s of a refused fit's 216.
pub(super) const SWEPT_ZETA_FLOOR: f64 = 1.1 * SWEPT_ZETA_MIN;

/// Starts of the whole-curve fit: each of [`START_ZETAS`] at the contact fit's natural
/// frequency (when it reached one) and at 1.05 times the mesh frequency of the measured peak
/// (backlash softens the resonance, so the peak lies below omega_n); the STE amplitude, when
/// fitted, at the contact fit's (the setting's start when it reached none that is finite and
/// positive).
fn starts(
    data: &KuboData,
    dim: &Dimensional,
    near: &[f64],
    ste: MidlineSetting,
    pair_spread: Option<f64>,
) -> Vec<Vec<f64>> {
    let peak_hz = measured_peak_rpm(&data.points).map(|rpm| dim.mesh_frequency_hz(rpm));
    let plausible = |v: &f64| v.is_finite() && *v > 0.0;
    let omegas: Vec<f64> = [near.get(1).copied(), peak_hz.map(|f| 1.05 * f)]
        .into_iter()
        .flatten()
        .filter(plausible)
        .collect();
    let ste_start = ste
        .held
        .is_none()
        .then(|| near.get(2).copied().filter(plausible).unwrap_or(ste.start));
    let mut out = Vec::new();
    for z in START_ZETAS {
        debug_assert!((FITTED_ZETA.0..FITTED_ZETA.1).contains(&z));
        for &w in &omegas {
            let mut s = vec![z, w];
            s.extend(ste_start);
            s.extend(pair_spread);
            out.push(s);
        }
    }
    out
}

/// The whole measured curve against the model's up-sweep.
struct SweptFit<'a> {
    dim: &'a Dimensional,
    fm: f64,
    /// The measured speeds, rpm: the sweep's grid at every evaluation.
    speeds: Vec<f64>,
    /// The envelope's midline at each of them: what is fitted.
    midline: Vec<f64>,
    ste: MidlineSetting,
    /// Where the pairs' STE half-spread h starts; None: one pair (h = 0, not fitted).
    pair_spread: Option<f64>,
    /// Where each speed of a tooth pair's up-sweep starts at nearby parameters
    /// ([`up_sweep_neighbour_starts`]), by the pair's parameters: the Jacobian columns start there
    /// ([`SweptFit::curve_near`]).
    sweeps: Cache<PairKey, Arc<Vec<State>>>,
}

/// Tooth-pair sweeps [`SweptFit`] remembers: the bases of the Jacobians in progress (a fit's,
/// the two sides of a profile, two pairs each) and many more.
const REMEMBERED_SWEEPS: usize = 256;

/// One tooth pair's model in the whole-curve fit: zeta, omega_n (Hz) and its STE amplitude
/// (um).
#[derive(Clone, Copy, Debug)]
struct Pair {
    zeta: f64,
    omega_n_hz: f64,
    ste_um: f64,
}

/// A [`Pair`] by the bits of its numbers.
type PairKey = [u64; 3];

impl Pair {
    fn key(&self) -> PairKey {
        [self.zeta, self.omega_n_hz, self.ste_um].map(f64::to_bits)
    }
}

impl SweptFit<'_> {
    /// The mean of two tooth pairs' D_L at each measured speed on the up-sweep for (zeta,
    /// omega_n[, STE], h): pairs with STE amplitudes STE (1 - h) and STE (1 + h).
    ///
    /// The envelope's edges are its extreme pairs: D_L grows with the STE amplitude at every
    /// speed on an up-sweep (so in the 9720 pair points of the independent batch 515), and
    /// the pair with the larger amplitude stays on the resonance branch to a higher speed. Over
    /// the jump the midline is the mean of a pair still on that branch and one already down,
    /// which no single pair's curve follows: fitted with one pair, the flatter two-step descent
    /// read as damping (zeta up to +17% on noise-free envelopes of that batch, the 95%
    /// intervals covering 84%). In contact D_L - 1 is proportional to the amplitude and h
    /// drops out.
    fn curve(&self, p: &[f64]) -> Result<Vec<f64>> {
        match self.pairs(p)?.as_slice() {
            [one] => Ok(self.pair_sweep(one)?.0),
            [low, high] => {
                let (low, high) = rayon::join(|| self.pair_sweep(low), || self.pair_sweep(high));
                Ok(mean_of(&low?.0, &high?.0))
            }
            _ => Err(GearError::Numerical(
                "internal: one or two tooth pairs".into(),
            )),
        }
    }

    /// [`SweptFit::curve`] at `p`, a finite-difference neighbour of `base`: each pair's speeds
    /// started from the steady states of base's pair ([`up_sweep_neighbour_starts`]), its periodic
    /// orbits without their transients. Equal to the curve at p at its period-1 points to the
    /// orbit's Newton tolerance, except where the step moves a jump across a measured speed:
    /// there the curve at p is on the other branch and this stays on base's, which is the
    /// derivative the fit's linearisation wants (the sum of squares steps at such a speed).
    /// The carried sweeps were 72% of the fit's time, mostly transients.
    fn curve_near(&self, p: &[f64], base: &[f64]) -> Result<Vec<f64>> {
        let (pairs, bases) = (self.pairs(p)?, self.pairs(base)?);
        let near = |i: usize| self.pair_near(&pairs[i], &bases[i]);
        match (pairs.len(), bases.len()) {
            (1, 1) => near(0),
            (2, 2) => {
                let (low, high) = rayon::join(|| near(0), || near(1));
                Ok(mean_of(&low?, &high?))
            }
            _ => self.curve(p),
        }
    }

    /// The tooth pairs of the parameters `p` (zeta, omega_n[, STE], h): one at the STE when
    /// h = 0, else two at STE (1 - h) and STE (1 + h).
    fn pairs(&self, p: &[f64]) -> Result<Vec<Pair>> {
        if p[0].is_nan() || p[0] < SWEPT_ZETA_MIN {
            return Err(GearError::Numerical(format!(
                "zeta = {} is below the least damping the whole-curve fit simulates ({SWEPT_ZETA_MIN})",
                p[0]
            )));
        }
        let ste = ste_of(self.ste.held, p);
        // The spread, when fitted, is the last parameter (MidlineFit::new).
        let h = match self.pair_spread {
            Some(_) => p.last().map_or(f64::NAN, |h| h.abs()),
            None => 0.0,
        };
        if h.is_nan() || h >= PAIR_SPREAD_MAX {
            return Err(GearError::Numerical(format!(
                "the pairs' STE half-spread {h} is outside [0, {PAIR_SPREAD_MAX})"
            )));
        }
        let pair = |ste_um| Pair {
            zeta: p[0],
            omega_n_hz: p[1],
            ste_um,
        };
        Ok(if h == 0.0 {
            vec![pair(ste)]
        } else {
            vec![pair(ste * (1.0 - h)), pair(ste * (1.0 + h))]
        })
    }

    /// The model of `pair` at Omega = 1 (the sweeps set Omega).
    fn model(&self, pair: &Pair) -> Result<GearPair> {
        GearPair::paper(self.fm, self.dim.ste_amplitude(pair.ste_um), pair.zeta, 1.0)
    }

    /// D_L of `pair` at each measured speed on its carried up-sweep, and where a sweep at
    /// nearby parameters starts each speed (remembered for [`SweptFit::pair_near`]).
    fn pair_sweep(&self, pair: &Pair) -> Result<(Vec<f64>, Arc<Vec<State>>)> {
        let model = self.model(pair)?;
        let pts = TestRun {
            dim: self.dim,
            model: &model,
            omega_n_hz: pair.omega_n_hz,
            speeds: &self.speeds,
            opts: &SteadyOptions::default(),
        }
        .up_sweep(UNUSED_RK_RTOL, &NoProgress)?;
        let dl = pts
            .iter()
            .map(|p| p.steady.dl_max.unwrap_or(f64::NAN))
            .collect();
        let starts = Arc::new(up_sweep_neighbour_starts(&model, &pts));
        self.sweeps.insert(pair.key(), Arc::clone(&starts));
        Ok((dl, starts))
    }

    /// D_L of `pair` at each measured speed, each started where `base`'s up-sweep puts it.
    fn pair_near(&self, pair: &Pair, base: &Pair) -> Result<Vec<f64>> {
        let starts = match self.sweeps.get(&base.key()) {
            Some(starts) => starts,
            None => self.pair_sweep(base)?.1,
        };
        let pts = TestRun {
            dim: self.dim,
            model: &self.model(pair)?,
            omega_n_hz: pair.omega_n_hz,
            speeds: &self.speeds,
            opts: &SteadyOptions::default(),
        }
        .near_up_sweep(UNUSED_RK_RTOL, &starts)?;
        Ok(pts
            .iter()
            .map(|p| p.steady.dl_max.unwrap_or(f64::NAN))
            .collect())
    }

    /// The [`SCREENED_STARTS`] best points of a coarse grid, [`START_ZETAS`] times
    /// [`SCREEN_OMEGAS`] natural frequencies log-spaced over the mesh frequencies of the
    /// measured speeds (0.8 to 1.2 times their range), the STE at its start, scored by the
    /// sum of squared relative residuals of one sweep each. The measured peak can lie far from
    /// omega_n: on a rig whose teeth separate at nearly every speed (zeta 0.05, 2200 Hz, STE
    /// 8 um at 2000 N) the separated branch grows to 8700 rpm (3625 Hz), and every start
    /// about it ended at 1100-1300 Hz, a fit the model's curve lay outside the envelope at 80%
    /// of the speeds.
    fn screened(&self, ste: MidlineSetting) -> Vec<Vec<f64>> {
        let (lo, hi) = self
            .speeds
            .iter()
            .fold((f64::INFINITY, 0.0_f64), |(a, b), s| (a.min(*s), b.max(*s)));
        let (f_lo, f_hi) = (
            0.8 * self.dim.mesh_frequency_hz(lo),
            1.2 * self.dim.mesh_frequency_hz(hi),
        );
        if !(f_lo > 0.0 && f_hi > f_lo) {
            return Vec::new();
        }
        let y = &self.midline;
        let grid: Vec<Vec<f64>> = START_ZETAS
            .iter()
            .flat_map(|&z| {
                (0..SCREEN_OMEGAS).map(move |k| {
                    let w = f_lo * (f_hi / f_lo).powf(k as f64 / (SCREEN_OMEGAS - 1) as f64);
                    let mut p = vec![z, w];
                    if ste.held.is_none() {
                        p.push(ste.start);
                    }
                    p.extend(self.pair_spread);
                    p
                })
            })
            .collect();
        let mut scored: Vec<(f64, Vec<f64>)> = grid
            .into_par_iter()
            .filter_map(|p| {
                let m = self.curve(&p).ok()?;
                let cost: f64 = y.iter().zip(&m).map(|(y, m)| ((y - m) / y).powi(2)).sum();
                cost.is_finite().then_some((cost, p))
            })
            .collect();
        scored.sort_by(|a, b| a.0.total_cmp(&b.0));
        scored
            .into_iter()
            .take(SCREENED_STARTS)
            .map(|(_, p)| p)
            .collect()
    }

    fn problem(&self) -> MidlineFit {
        let stop = Stop::converged(SWEPT_JACOBIANS).central();
        MidlineFit::new(
            (self.speeds.clone(), self.midline.clone()),
            self.ste,
            self.pair_spread,
            (stop.or_stalled(FIT_STALL), stop.or_stalled(PROFILE_STALL)),
        )
        .with_zeta_floor(SWEPT_ZETA_FLOOR)
    }

    fn fit(&self, starts: &[Vec<f64>]) -> Result<Estimate> {
        let near = |p: &[f64], base: &[f64]| self.curve_near(p, base);
        self.problem()
            .fit(&|p: &[f64]| self.curve(p), Some(&near), starts)
    }

    fn profile_while(
        &self,
        est: &Estimate,
        better_by: Option<f64>,
        go_on: impl Fn(&[ProfileInterval]) -> bool,
    ) -> Result<(ProfileIntervals, Option<Vec<f64>>)> {
        let near = |p: &[f64], base: &[f64]| self.curve_near(p, base);
        self.problem().profile_while(
            &|p: &[f64]| self.curve(p),
            Some(&near),
            est,
            better_by,
            go_on,
        )
    }
}

/// The mean of two pairs' curves, point by point.
fn mean_of(low: &[f64], high: &[f64]) -> Vec<f64> {
    low.iter().zip(high).map(|(a, b)| 0.5 * (a + b)).collect()
}
