//! A candidate's refit on the training curves, in stages ([`refit_candidate`]): the design load
//! alone, then the other training loads' STE, then everything, from starts that profiles over
//! the candidate's delta choose (a polar profile over amplitude and phase for an effect with a
//! phase, one over the probes otherwise); finally once more with the points around the
//! refitted model's own jumps dropped and the noise estimated about the refit.

use super::ambiguity::CHI2_95_1DF;
use super::effects::{Candidate, Effect};
use super::fit::{fit_model, fit_ste, relinearized, residuals_of, EffectInFit, Mask, ModelFit};
use super::forward::{
    fitted_damping_admissible, predict, predict_many, CurvePrediction, Globals, Setup, MIN_ZETA,
};
use super::interval::{wald_ci, wald_phase_arc, RefitNoise};
use super::noise::{DiscoveryNoise, NoiseSpec, Scales};
use super::run::{make_mask, noise_about, row_scales, OtherStart};
use crate::error::{GearError, Result};
use crate::fit::{log_likelihood, rss, Distribution, LmFit, Stop};
use rayon::prelude::*;

/// What the stages of one candidate's refit share.
struct Refit<'a> {
    setup: &'a Setup,
    train: &'a [usize],
    mask: &'a Mask,
    w: RunNoise<'a>,
    cand: Candidate,
    m0: &'a ModelFit,
    iters: usize,
}

impl Refit<'_> {
    /// The design-load stage from M0's values: zeta, omega_n and the design-load STE, with the
    /// candidate's delta fitted from `delta` (`EffectInFit::Fitted`) or held at it. Returns its
    /// globals, design-load STE and effect.
    fn design_stage(&self, delta: &[f64], fit_delta: bool) -> Result<(Globals, f64, Effect)> {
        let held = Effect::of(self.cand, delta.to_vec());
        let mut start = vec![
            self.m0.globals.zeta,
            self.m0.globals.omega_n_hz,
            self.m0.ste_um[0],
        ];
        let how = if fit_delta {
            start.extend_from_slice(delta);
            EffectInFit::Fitted(self.cand)
        } else {
            EffectInFit::Held(&held)
        };
        let f = fit_model(
            self.setup,
            &self.train[..1],
            self.mask,
            self.w.scales,
            how,
            &start,
            Stop::near(self.iters),
        )?;
        Ok((f.globals, f.ste_um[0], f.effect))
    }

    /// The other training loads' STE fitted alone at globals `g` with the effect `effect`,
    /// once its damping is admissible at every training load.
    fn fitted_others(&self, g: Globals, effect: &Effect) -> Result<Vec<f64>> {
        fitted_damping_admissible(self.setup, self.train, g, effect)?;
        self.train[1..]
            .par_iter()
            .zip(&self.m0.ste_um[1..])
            .map(|(&i, &e)| Ok(fit_ste(self.setup, i, self.mask, self.w.scales, g, effect, e)?.0))
            .collect()
    }

    /// The all-load stage's start (globals `g`, design-load STE `ste1`, the other loads' STE
    /// `others`, `effect`'s delta) and its residual sum of squares (sigma^2) on the training
    /// curves `on`, a tail of the training curves.
    fn scored_on(
        &self,
        on: &[usize],
        g: Globals,
        ste1: f64,
        effect: &Effect,
        others: &[f64],
    ) -> Result<ScoredStart> {
        let n = self.train.len();
        let mut start = vec![g.zeta, g.omega_n_hz, ste1];
        start.extend_from_slice(others);
        let preds = predict_many(self.setup, on, g, &start[2 + n - on.len()..2 + n], effect)?;
        let r = rss(&residuals_of(
            self.setup,
            on,
            &preds,
            self.mask,
            self.w.scales,
        ));
        start.extend_from_slice(&effect.delta);
        Ok((start, r))
    }

    /// The all-load stage's start with `effect` at globals `g` and design-load STE `ste1`, the
    /// other loads' STE fitted for it, scored on all training loads.
    fn start_at(&self, g: Globals, ste1: f64, effect: &Effect) -> Result<ScoredStart> {
        let others = self.fitted_others(g, effect)?;
        self.scored_on(self.train, g, ste1, effect, &others)
    }

    /// The all-load stage's start at globals `g` with `effect` and each training load's STE
    /// matched to it: the STE that, with the effect's first-order part at the mesh frequency
    /// ([`Effect::mesh_frequency_equivalent_um`]), keeps M0's fitted amplitude at that load. Of
    /// the STEs that come locally closest to it ([`ste_roots`]: the roots, and zero where the
    /// lower root is negative), the one with the lower residual sum of squares at that load.
    /// Scored on all training loads.
    ///
    /// Without the matching, a profile over the effect at M0's STE scores how much the effect
    /// changes M0's first-order response, which the STE alone would absorb: on an eps 0.2 set
    /// at -92 degrees (relative noise, seed 1) that profile's best was at -30 degrees and the
    /// refit ended at eps 0.146 and a training residual sum of squares of 87 sigma^2, while
    /// from the truth the same fit ends at 17 sigma^2. Fitting each STE alone at every profile
    /// value finds the truth's basin too, at eight times the cost.
    fn matched_start(&self, g: Globals, effect: &Effect) -> Result<ScoredStart> {
        fitted_damping_admissible(self.setup, self.train, g, effect)?;
        let per_load: Vec<(f64, f64)> = self
            .train
            .par_iter()
            .zip(&self.m0.ste_um)
            .map(|(&i, &m0_ste)| {
                matched_stes(self.setup, i, m0_ste, effect)
                    .unwrap_or_else(|| vec![m0_ste])
                    .into_par_iter()
                    .map(|ste| {
                        let pred = predict(self.setup, i, g, ste, effect)?;
                        let r = residuals_of(self.setup, &[i], &[pred], self.mask, self.w.scales);
                        Ok((ste, rss(&r)))
                    })
                    .collect::<Result<Vec<_>>>()?
                    .into_iter()
                    .min_by(|a, b| a.1.total_cmp(&b.1))
                    .ok_or_else(|| GearError::Numerical("no STE matches the effect".into()))
            })
            .collect::<Result<_>>()?;
        let mut start = vec![g.zeta, g.omega_n_hz];
        start.extend(per_load.iter().map(|p| p.0));
        start.extend_from_slice(&effect.delta);
        Ok((start, per_load.iter().map(|p| p.1).sum()))
    }

    /// The all-load stage: everything fitted on all training loads from `start`.
    fn all_loads(&self, start: &[f64]) -> Result<ModelFit> {
        fit_model(
            self.setup,
            self.train,
            self.mask,
            self.w.scales,
            EffectInFit::Fitted(self.cand),
            start,
            Stop::near(self.iters),
        )
    }

    /// All-load fits of a phase-carrying candidate, one per phase basin of the polar profile
    /// ([`polar_profile`]) at M0's fit. An effect with a first-order part at the mesh
    /// frequency (stiffness variation, torque ripple) is scored on all training loads with
    /// each load's STE matched to it ([`Refit::matched_start`]), and the all-load stage starts
    /// there. Otherwise (a second STE harmonic) it is scored on the lighter training loads at
    /// M0's STE, and each start goes through the design-load stage with the effect held (it
    /// fits zeta, omega_n and the design-load STE to it) and the other loads' STE fitted for it.
    ///
    /// The profile is taken at M0's fit and not after a design-load stage with the delta free:
    /// from the dictionary's best probe that stage can end anywhere (on an eps 0.2 set with
    /// relative noise, seed 1, it ended at zeta 0.0034 and a design-load STE of 2.3 um, truth
    /// 0.3 um, and the profile at its fit was meaningless). It scores the lighter training loads
    /// alone (the design load where it is the only one): the design load's misfit at a phase
    /// depends on zeta more than on the phase (on the same set its RMS at the true phase and
    /// amplitude is 0.57 um at the true zeta 0.0175 and 3.6-3.9 um at zeta 0.025-0.035, 1.6 um
    /// 90 degrees off), while 1890 N gives 0.35-0.81 um at the true phase for any of these zeta
    /// and 1.1-10.7 um at every other phase.
    fn phase_basins(&self, delta0: &[f64]) -> Vec<Result<ModelFit>> {
        let matched = Effect::of(self.cand, delta0.to_vec())
            .mesh_frequency_equivalent_um(1.0, 1.0)
            .is_some();
        let light = if self.train.len() > 1 {
            &self.train[1..]
        } else {
            self.train
        };
        let others0 = &self.m0.ste_um[1..];
        let profile_at = |zeta_factor: f64| {
            let mut g = self.m0.globals;
            g.zeta = (g.zeta * zeta_factor).max(MIN_ZETA);
            polar_profile(self.cand, delta0, &|e: &Effect| {
                if matched {
                    self.matched_start(g, e)
                } else {
                    self.scored_on(light, g, self.m0.ste_um[0], e, others0)
                }
            })
        };
        let profiles: Vec<_> = PROFILE_ZETA_FACTORS
            .par_iter()
            .map(|&(f, n)| (profile_at(f), n))
            .collect();
        let mut first_error = None;
        let mut starts: Vec<Scored> = Vec::new();
        for (p, n) in profiles {
            match p {
                Ok(s) => starts.extend(s.into_iter().take(n)),
                Err(e) => {
                    first_error.get_or_insert(e);
                }
            }
        }
        if starts.is_empty() {
            return vec![Err(first_error.unwrap_or_else(|| {
                GearError::Numerical("no profile value gives a finite residual".into())
            }))];
        }
        starts
            .par_iter()
            .map(|s| {
                // A matched profile value is already the all-load stage's start.
                if matched {
                    return self.all_loads(&s.start);
                }
                let (g1, ste1, effect) = self.design_stage(&s.delta, false)?;
                self.all_loads(&self.start_at(g1, ste1, &effect)?.0)
            })
            .collect()
    }

    /// All-load fits of a candidate without a phase: from the design-load stage with the delta
    /// fitted from the best probe `delta0` when the design load sees the effect; otherwise
    /// (the backlash while the teeth stay in contact) the design-load stage fits M0 and the
    /// all-load stage starts from the best of a profile over the delta ([`profile_start`]).
    /// Left free at the design load, such a delta followed the forward model's own last bits
    /// (1e-6 um at one point of the rattle-regime set's design load, a forward-difference slope
    /// of 0.15 sigma per unit beta) to b = e^37 b_stated.
    fn plain(&self, delta0: &[f64], seen_at_design: bool) -> Result<ModelFit> {
        if seen_at_design {
            let (g1, ste1, effect) = self.design_stage(delta0, true)?;
            return self.all_loads(&self.start_at(g1, ste1, &effect)?.0);
        }
        let start = vec![
            self.m0.globals.zeta,
            self.m0.globals.omega_n_hz,
            self.m0.ste_um[0],
        ];
        let f = fit_model(
            self.setup,
            &self.train[..1],
            self.mask,
            self.w.scales,
            EffectInFit::None,
            &start,
            Stop::near(self.iters),
        )?;
        let (g1, ste1) = (f.globals, f.ste_um[0]);
        let start = profile_start(self.cand, &|e: &Effect| self.start_at(g1, ste1, e))?;
        self.all_loads(&start)
    }

    /// An all-load fit from the contact twin ([`Candidate::contact_twin`]) of the best of
    /// `converged` (sorted, best first), unless one of them already ended within 45 degrees of
    /// the twin's phase and within chi2(0.95; 1) of the best, or the fit fails. The twin fits
    /// the in-contact points as well as the best does, so the training loads may not tell the
    /// two apart; the polar profile, scored at M0's globals, need not have a basin there, and
    /// a fit from its start need not reach the twin's minimum. On an r2 0.4 set (Student-t
    /// noise, study seed 2, truth 191 deg) the refit ended at 33 deg (20.0 sigma^2), the fit
    /// from the profile's start at 180 deg at r2 0.23 and 117 sigma^2.
    fn contact_twin_fit(&self, converged: &[ModelFit]) -> Option<ModelFit> {
        let best = converged.first()?;
        let twin = self.cand.contact_twin(&best.effect.delta)?;
        let near = |f: &ModelFit| {
            Candidate::phase_distance(&f.effect.delta, &twin) < std::f64::consts::FRAC_PI_4
                && f.lm.rss <= best.lm.rss + CHI2_95_1DF
        };
        if converged.iter().any(near) {
            return None;
        }
        let mut start = best.lm.params.clone();
        let p0 = start.len() - twin.len();
        start[p0..].copy_from_slice(&twin);
        self.all_loads(&start).ok()
    }

    /// The last stage: from the better all-load fit `f2`, once more with the points around its
    /// own jumps dropped and the noise estimated about it ([`refit_scales`]). Returns the fit,
    /// its mask, the best distinct minimum among the other all-load fits `rest`
    /// ([`Refit::other_basin`], with its interval under the new scales) and the scales.
    ///
    /// `f2` is the best under the run's scales, M0's noise inflated by its misfit. Where under
    /// the last stage's noise another basin fits better than `f2` ([`Refit::other_basin`]), the
    /// last stage is run once more from that basin, and of the two the one whose other basin
    /// lies higher above it is kept: a negative increase is a contradiction, the kept fit not
    /// the best of its basins under its own noise.
    fn last_stage(&self, f2: ModelFit, rest: Vec<ModelFit>) -> Result<RefitOutcome> {
        let increase =
            |o: &RefitOutcome| o.2.as_ref().map_or(f64::INFINITY, |b| b.deviance_increase);
        from_the_better_basin(f2, rest, |f, r| self.last_stage_from(f, r), increase)
    }

    /// [`Refit::last_stage`] from `f2` alone; with the index in `rest` of the other basin
    /// when it fits better than `f2` under the last stage's noise.
    fn last_stage_from(
        &self,
        f2: &ModelFit,
        rest: &[ModelFit],
    ) -> Result<(RefitOutcome, Option<usize>)> {
        let (setup, train) = (self.setup, self.train);
        let preds = predict_many(setup, train, f2.globals, &f2.ste_um, &f2.effect)?;
        let mut m2 = self.mask.clone();
        for (k, &i) in train.iter().enumerate() {
            let own = make_mask(setup, std::slice::from_ref(&preds[k]), &[i], self.w.noise)?;
            for (j, keep) in own[0].iter().enumerate() {
                m2[i][j] = m2[i][j] && *keep;
            }
        }
        let (scales3, noise3) = refit_scales(setup, self.w, train, &preds, &m2)?;
        let f3 = fit_model(
            setup,
            train,
            &m2,
            &scales3,
            EffectInFit::Fitted(self.cand),
            &f2.lm.params.clone(),
            Stop::converged(self.iters / 2 + 1),
        )?;
        let q = noise3.quantile(self.cand, &f3.lm, train, &m2);
        let f3 = relinearized(
            setup,
            train,
            &m2,
            &scales3,
            EffectInFit::Fitted(self.cand),
            f3,
            q,
        );
        let other = self.other_basin(f2, rest, (&f3, q), (&scales3, &noise3));
        let better = other
            .as_ref()
            .filter(|(_, o)| o.deviance_increase < 0.0)
            .map(|(k, _)| *k);
        Ok(((f3, m2, other.map(|(_, o)| o), (scales3, noise3)), better))
    }

    /// The best of the other all-load fits `rest` that is a distinct minimum from the kept fit
    /// (`kept`, its quantile; [`distinct_minima`]), with its index in `rest`, its interval and
    /// its -2 log-likelihood above `f2`'s (the kept fit before the last stage, on the same
    /// points), each under the last stage's noise (`last`: its scales and noise) evaluated at
    /// its own level ([`deviance_under`]). That difference is held against chi2(0.95; 1).
    ///
    /// Under the run's scales, inflated by M0's misfit, it was a fraction of itself: on an eps
    /// 0.2 set (relative noise, study seed 4) two minima 55 deg apart differed by 1.0 there and
    /// by 4.8 under the refit's noise. And both fits weighed by the scales at the kept fit's
    /// level favoured the other: on the bench's eps 0.2 set (relative noise, seed 3) the 2nd
    /// STE harmonic's basin at 89 deg scored 16.1 sigma^2 below the kept one at 269 deg, and
    /// the kept one 178 sigma^2 below it under the scales at the other's level; each weighed by
    /// its own level, the kept fit is the better by 291 and by 173.
    fn other_basin(
        &self,
        f2: &ModelFit,
        rest: &[ModelFit],
        kept: (&ModelFit, f64),
        last: (&Scales, &RefitNoise),
    ) -> Option<(usize, OtherStart)> {
        let (train, mask, old) = (self.train, self.mask, self.w.scales);
        let kept_arc = wald_phase_arc(self.cand, &kept.0.lm, kept.1);
        let deviance = |lm: &LmFit| deviance_under(self.setup, lm, train, mask, old, &last.1.noise);
        let base = deviance(&f2.lm);
        rest.iter()
            .enumerate()
            .filter_map(|(k, o)| {
                let lm = restandardized(&o.lm, train, mask, old, last.0);
                let q = last.1.quantile(self.cand, &lm, train, mask);
                let arc = wald_phase_arc(self.cand, &lm, q);
                distinct_minima((&o.effect.delta, arc), (&kept.0.effect.delta, kept_arc)).then(
                    || {
                        (
                            k,
                            OtherStart {
                                deviance_increase: deviance(&o.lm) - base,
                                ci95: wald_ci(self.cand, &lm, q),
                                phase_wald95_deg: arc,
                                delta: o.effect.delta.clone(),
                            },
                        )
                    },
                )
            })
            .min_by(|a, b| a.1.deviance_increase.total_cmp(&b.1.deviance_increase))
    }
}

/// The swap of [`Refit::last_stage`], apart from the fits: `stage(from, others)` runs the last
/// stage from one fit with the others as its rivals, and says which rival (an index into
/// `others`) fits better under its noise. When one does, the stage is run again from that rival
/// with `from` among the rivals in its place, and of the two outcomes the one whose best rival
/// lies higher above it (`increase`; infinite without a rival) is kept, the first on a tie.
fn from_the_better_basin<F, O>(
    from: F,
    mut others: Vec<F>,
    stage: impl Fn(&F, &[F]) -> Result<(O, Option<usize>)>,
    increase: impl Fn(&O) -> f64,
) -> Result<O> {
    let (first, better) = stage(&from, &others)?;
    let Some(k) = better else {
        return Ok(first);
    };
    let rival = others.remove(k);
    others.push(from);
    let (second, _) = stage(&rival, &others)?;
    Ok(if increase(&second) > increase(&first) {
        second
    } else {
        first
    })
}

/// Whether two fits of a phase-carrying candidate, each its delta and its 95% Wald arc of the
/// phase (degrees, [`wald_phase_arc`]), are distinct minima: each phase lies outside the
/// other's arc, so neither fit's linearised confidence set holds the other. Without an arc,
/// more than 90 deg apart. A fixed 90 deg missed distinct minima nearer: on an eps 0.2 set
/// (relative noise, study seed 4, truth 301 deg) the refit kept 248 deg (arc 244-253) while a
/// fit at 304 deg ended 4.8 sigma^2 worse.
pub(super) fn distinct_minima(
    a: (&[f64], Option<(f64, f64)>),
    b: (&[f64], Option<(f64, f64)>),
) -> bool {
    let apart = Candidate::phase_distance(a.0, b.0).to_degrees();
    let half = |arc: Option<(f64, f64)>| arc.map(|(lo, hi)| 0.5 * (hi - lo));
    match (half(a.1), half(b.1)) {
        (Some(ha), Some(hb)) => apart > ha.max(hb),
        _ => apart > 90.0,
    }
}

/// The other phase basin once a profile's better refit `new` replaced the kept fit `old` of
/// a phase-carrying candidate `cand` (each with its 95% quantile), `gain` the fall of -2 log L
/// from `old` to `new` (both on the same points and noise,
/// [`super::interval::profiled_refit`]; [`deviance_gain`]). The earlier other basin `other` was
/// measured against `old`, and the better refit may lie in it: `old` becomes another basin
/// where it is a distinct minimum from `new`, `gain` above it, and `other` stays one where it
/// is distinct from `new`, that much further above (its increase was over `old` before the last
/// stage, so the sum is as near as the refit's own comparison); the nearer of the two.
pub(super) fn rebased_other(
    cand: Candidate,
    old: (&ModelFit, f64),
    other: Option<OtherStart>,
    new: (&ModelFit, f64),
    gain: f64,
) -> Option<OtherStart> {
    if !cand.has_phase() {
        return other;
    }
    let old_basin = OtherStart {
        delta: old.0.effect.delta.clone(),
        deviance_increase: gain,
        ci95: wald_ci(cand, &old.0.lm, old.1),
        phase_wald95_deg: wald_phase_arc(cand, &old.0.lm, old.1),
    };
    let new_basin = (
        new.0.effect.delta.as_slice(),
        wald_phase_arc(cand, &new.0.lm, new.1),
    );
    nearest_distinct_basin(old_basin, other, gain, new_basin)
}

/// [`rebased_other`] on the basins themselves: of `old` (its increase over the new fit given)
/// and `other` (its increase over `old`, so `gain` more over the new fit), the nearer of those
/// that are distinct minima from the new fit (its delta and Wald arc).
fn nearest_distinct_basin(
    old: OtherStart,
    other: Option<OtherStart>,
    gain: f64,
    new: (&[f64], Option<(f64, f64)>),
) -> Option<OtherStart> {
    let moved = other.map(|o| OtherStart {
        deviance_increase: o.deviance_increase + gain,
        ..o
    });
    [Some(old), moved]
        .into_iter()
        .flatten()
        .filter(|o| distinct_minima((&o.delta, o.phase_wald95_deg), new))
        .min_by(|a, b| a.deviance_increase.total_cmp(&b.deviance_increase))
}

/// The STEs of curve `i` that, with `effect`'s first-order part at the mesh frequency
/// ([`Effect::mesh_frequency_equivalent_um`] at the curve's and the design load's static
/// deflections), keep the amplitude `ste_um` ([`ste_roots`]); None for an effect without that
/// part.
pub(super) fn matched_stes(
    setup: &Setup,
    i: usize,
    ste_um: f64,
    effect: &Effect,
) -> Option<Vec<f64>> {
    let dim = &setup.dim;
    let deflection = |load_n: f64| dim.ste_um(dim.mean_force(load_n));
    effect
        .mesh_frequency_equivalent_um(
            deflection(setup.curves[i].load_n),
            deflection(setup.design_load_n),
        )
        .map(|w| ste_roots(ste_um.abs(), w))
}

/// The STE amplitudes (um, >= 0, phase 0) whose sum with the complex amplitude `w` (um) comes
/// locally closest to the magnitude `a`: the roots of |ste + w| = a, ste = -Re w +-
/// sqrt(a^2 - (Im w)^2), that are not negative, lower first; where the lower root is
/// negative while |ste + w| still falls with ste at zero (Re w < 0), also zero, the closest
/// that branch comes (the model takes |ste|, so a negative root is no STE of phase 0); where no
/// root exists, the amplitude that comes closest, max(-Re w, 0).
///
/// Without the zero a matched start could only take the upper root on that branch: on an eps
/// 0.2 set at 212 deg (relative noise, study seed 9) M0's design-load STE of 3.02 um and
/// w = (-1.52, 2.39) um gave the roots -0.32 and 3.36 um; the truth's 0.3 um lies on the
/// lower root's branch (|0.3 + w| = 2.69 um). From 3.36 um the polar profile's truth-phase
/// value scored 166 sigma^2 (17.5 with the true STE), every all-load fit ended at least 20
/// sigma^2 above the one from the truth, and the refit (eps 0.18 [0.172, 0.191]) failed the
/// training chi-square.
pub(super) fn ste_roots(a: f64, w: (f64, f64)) -> Vec<f64> {
    let disc = a * a - w.1 * w.1;
    if disc < 0.0 {
        return vec![(-w.0).max(0.0)];
    }
    let (lower, upper) = (-w.0 - disc.sqrt(), -w.0 + disc.sqrt());
    let mut roots: Vec<f64> = [lower, upper].into_iter().filter(|r| *r >= 0.0).collect();
    roots.dedup();
    // Zero where the lower branch still falls there (the closest it comes), or where both
    // roots are negative (|ste + w| rises from zero, already above a).
    if (lower < 0.0 && -w.0 > 0.0) || roots.is_empty() {
        roots.push(0.0);
    }
    roots
}

/// A refit's last fit, its mask, the start not kept and its scales.
type RefitOutcome = (ModelFit, Mask, Option<OtherStart>, (Scales, RefitNoise));

/// Refit M0 + `cand` on the training curves in stages: the highest load alone first (the
/// design load, usually in contact, where the fit is smooth), then the other training loads'
/// STE alone, then everything; finally once more with the points around the refitted model's
/// own jumps also dropped, with the noise estimated about the refit ([`refit_scales`]).
///
/// A phase-carrying effect is refitted from two phase basins ([`Refit::phase_basins`]) and the
/// lower residual sum of squares goes on to the last stage; the other is reported. The pp
/// response jumps with the phase (a jump moves by a grid step), so Levenberg-Marquardt stops
/// within a few degrees of where it starts: on an r2 0.4 set (true phase 0, 50 rpm grid, seed
/// 3) twelve starts 30 deg apart ended within 30 deg of their own phase. Psi and psi + pi can
/// fit the in-contact points alike (at eps 0.1, seed 7, both of two starts ended in the psi =
/// pi basin, 7.6 sigma^2 above the true minimum), and where the two basins end within the LR
/// threshold the phase is reported undetermined.
#[allow(clippy::too_many_arguments)]
pub(super) fn refit_candidate(
    setup: &Setup,
    train: &[usize],
    mask: &Mask,
    w: RunNoise,
    cand: Candidate,
    m0: &ModelFit,
    delta0: &[f64],
    seen_at_design: bool,
    iters: usize,
) -> Result<RefitOutcome> {
    let r = Refit {
        setup,
        train,
        mask,
        w,
        cand,
        m0,
        iters,
    };
    let fits = if cand.has_phase() {
        r.phase_basins(delta0)
    } else {
        vec![r.plain(delta0, seen_at_design)]
    };
    let mut converged = Vec::new();
    let mut first_error = None;
    for f in fits {
        match f {
            Ok(f) => converged.push(f),
            Err(e) => {
                first_error.get_or_insert(e);
            }
        }
    }
    // Stable: on a tie the profile's best basin is kept.
    converged.sort_by(|a, b| a.lm.rss.total_cmp(&b.lm.rss));
    if converged.is_empty() {
        return Err(
            first_error.unwrap_or_else(|| GearError::Numerical("a refit needs a start".into()))
        );
    }
    if let Some(twin) = r.contact_twin_fit(&converged) {
        converged.push(twin);
        converged.sort_by(|a, b| a.lm.rss.total_cmp(&b.lm.rss));
    }
    let f2 = converged.remove(0);
    // The other fits are looked at for a distinct minimum, which is reported.
    let rest = if cand.has_phase() {
        converged
    } else {
        Vec::new()
    };
    r.last_stage(f2, rest)
}

/// A stage-two start (parameter layout of [`ModelFit::lm`]) and the residual sum of squares
/// (sigma^2) that scored it.
type ScoredStart = (Vec<f64>, f64);

/// Steps of the profile's refinement around its best probe, in units of the candidate's scale
/// (the probes are 2-10 scales apart).
const PROFILE_REFINE: [f64; 4] = [-2.0, -1.0, 1.0, 2.0];

/// Phases of [`polar_profile`]: shifts of the design-load fit's phase 30 deg apart (the
/// all-load fit moves a phase by less than that)...
const PHASE_PROFILE_STEP_DEG: f64 = 30.0;
/// ...then these steps around the best (the coarse shifts leave a phase up to 15 deg from the
/// nearest; with the steps, 5 deg).
const PHASE_REFINE_DEG: [f64; 2] = [-10.0, 10.0];

/// The all-load stage's start of a candidate the design load does not see (the backlash while
/// the teeth stay in contact, a load-dependent damping law): the start `start_at` builds at the
/// best delta of a profile over the candidate's probe values, then over steps of
/// [`PROFILE_REFINE`] around the best, each scored by the residual sum of squares `start_at`
/// returns (all training loads, the other loads' STE fitted alone at the design-load fit).
/// Values `start_at` rejects (a damping law below the floor at some load) are skipped.
///
/// The design-load stage cannot move such a delta, so without the profile the start is the
/// dictionary's best probe, chosen at M0's parameters. Where M0 is far off that is a blind
/// guess: on a rattle-regime set (true b x 0.7, seed 16) M0 settled at zeta 0.066 and
/// omega_n 1821 Hz, its best probe was b x 1.65, the wrong direction, and from there the light
/// training load had no back contact, so b was unseen and the refit stayed at 1.65. At the
/// design-load fit (zeta 0.0171, 1599.5 Hz: the design load alone is M0's own regime) the same
/// profile has one sharp minimum, at b x 0.70.
fn profile_start(
    cand: Candidate,
    start_at: &(dyn Fn(&Effect) -> Result<ScoredStart> + Sync),
) -> Result<Vec<f64>> {
    let refine = |best: &[f64]| -> Vec<Vec<f64>> {
        (0..cand.dim())
            .flat_map(|k| {
                PROFILE_REFINE.iter().map(move |s| {
                    let mut d = best.to_vec();
                    d[k] += s * cand.scale();
                    d
                })
            })
            .collect()
    };
    Ok(best_of_profile(cand, cand.probes(), &refine, start_at)?.1)
}

/// The starts of a phase-carrying candidate's all-load stage: a profile over the amplitude and
/// the phase of its first (cos, sin) pair at the design-load fit, each value scored by `score`
/// (the residual sum of squares of all training loads, the other loads' STE held): the
/// amplitudes [`Candidate::profile_amplitudes`] and the design-load fit's own, times phases
/// [`PHASE_PROFILE_STEP_DEG`] apart, then steps of [`PHASE_REFINE_DEG`] and
/// [`AMPLITUDE_REFINE`] around the best. Returns the best, then the other local minima over
/// the phase ([`phase_minima`], refined the same way), lowest first, up to [`PROFILE_BASINS`]
/// in all; where the profile has one minimum, the best at a phase more than 90 degrees from
/// it, the start of the other basin. Each with its score.
///
/// The phase alone at the design-load fit's amplitude is not enough: the response is far from
/// linear in the amplitude. On a set with eps 0.2 at 191 degrees (relative noise, seed 2) the
/// training RMS at the true globals is 0.44 um at the true phase and amplitude, 0.77-4.6 um at
/// amplitude 0.2 and other phases, and 6.1-8.2 um at every phase at amplitude 0.1; the
/// design-load fit's amplitude (0.09) and its best phase led to eps 0.09 at -3 degrees.
fn polar_profile(
    cand: Candidate,
    delta1: &[f64],
    score: &(dyn Fn(&Effect) -> Result<ScoredStart> + Sync),
) -> Result<Vec<Scored>> {
    let steps = (360.0 / PHASE_PROFILE_STEP_DEG).round() as usize;
    let a1 = delta1[0].hypot(delta1[1]);
    let mut amps = cand.profile_amplitudes().to_vec();
    if a1 > 0.0 {
        amps.push(a1);
    }
    let coarse: Vec<Vec<f64>> = amps
        .iter()
        .flat_map(|&a| {
            (0..steps).map(move |k| {
                let deg = k as f64 * PHASE_PROFILE_STEP_DEG;
                Candidate::with_first_amplitude(
                    &Candidate::phase_shifted(delta1, deg.to_radians()),
                    a,
                )
            })
        })
        .collect();
    let scored = scored_deltas(cand, coarse, score)?;
    let refine = |d: &[f64]| -> Vec<Vec<f64>> {
        let a = d[0].hypot(d[1]);
        let mut v: Vec<Vec<f64>> = PHASE_REFINE_DEG
            .iter()
            .map(|deg| Candidate::phase_shifted(d, deg.to_radians()))
            .collect();
        v.extend(
            AMPLITUDE_REFINE
                .iter()
                .map(|f| Candidate::with_first_amplitude(d, f * a)),
        );
        v
    };
    let refined = |start: &Scored| -> Scored {
        scored_deltas(cand, refine(&start.delta), score)
            .ok()
            .and_then(|r| r.into_iter().min_by(|a, b| a.rss.total_cmp(&b.rss)))
            .filter(|r| r.rss < start.rss)
            .unwrap_or_else(|| start.clone())
    };
    let best = lowest(scored.iter())
        .ok_or_else(|| GearError::Numerical("no profile value gives a finite residual".into()))?;
    let best = refined(best);
    let best_delta = best.delta.clone();
    let from_best = |d: &[f64]| Candidate::phase_distance(d, &best_delta);
    let mut starts = vec![best];
    let bin_width = PHASE_PROFILE_STEP_DEG.to_radians();
    for m in phase_minima(&scored, Candidate::first_phase(delta1), steps) {
        if starts.len() == PROFILE_BASINS {
            break;
        }
        // A minimum beside the best one is the best one's basin.
        if from_best(&m.delta) > 1.5 * bin_width {
            starts.push(refined(m));
        }
    }
    if starts.len() == 1 {
        let apart = |d: &[f64]| from_best(d) > std::f64::consts::FRAC_PI_2;
        starts.extend(lowest(scored.iter().filter(|s| apart(&s.delta))).map(refined));
    }
    Ok(starts)
}

/// Damping ratios of the polar profile, as factors of M0's, and the starts taken from each
/// (its best phase basins). M0 absorbs a missing effect partly into its damping (0.028-0.037
/// on eps 0.2 sets made at 0.0175), and at M0's own value the profile can miss the true
/// phase: on an eps 0.2 set at 191 degrees (relative noise, seed 2) its best was at -50
/// degrees and the refit ended 16 sigma^2 above the fit from the truth; at 0.6 x M0's the
/// best profile value lies in the truth's basin. Neither profile's score tells which is right
/// (on seed 4 the lower-damping profile scored lower and its starts all ended 150-220
/// sigma^2 above the other's): the all-load fits decide. Three basins of each: with two, an
/// eps 0.2 set at -86 degrees (relative noise, seed 14) ended at 132 degrees and eps 0.149;
/// the third basin of the profile at M0's damping led to -70 degrees and eps 0.189.
///
/// The best basin of a profile at twice M0's damping too: on the eps 0.2 study with relative
/// noise, seed 17 (M0 at zeta 0.0175, the truth's) had named a 2nd STE harmonic; with it, eps
/// 0.192 [0.183, 0.203]. One seed of twenty, at about 2.5 s a run for one start (7.4 s for
/// three, which changed nothing more on that study).
const PROFILE_ZETA_FACTORS: [(f64, usize); 3] = [(1.0, 3), (0.6, 3), (2.0, 1)];

/// Phase basins a phase-carrying refit starts from: the profile's best and up to two more.
const PROFILE_BASINS: usize = 3;

/// The local minima over the phase of a polar profile's `scored` values (each phase bin's
/// lowest over the amplitudes; bins of [`PHASE_PROFILE_STEP_DEG`] from `phase0`, `steps` of
/// them around the circle), lowest first.
fn phase_minima(scored: &[Scored], phase0: f64, steps: usize) -> Vec<&Scored> {
    let bin_width = std::f64::consts::TAU / steps as f64;
    let mut bins: Vec<Option<&Scored>> = vec![None; steps];
    for v in scored {
        let k = ((Candidate::first_phase(&v.delta) - phase0) / bin_width)
            .round()
            .rem_euclid(steps as f64) as usize
            % steps;
        if bins[k].is_none_or(|b| v.rss < b.rss) {
            bins[k] = Some(v);
        }
    }
    let at = |k: usize| bins[k % steps].map_or(f64::INFINITY, |b| b.rss);
    let mut minima: Vec<&Scored> = (0..steps)
        .filter_map(|k| {
            let here = bins[k]?;
            (here.rss <= at(k + steps - 1) && here.rss <= at(k + 1)).then_some(here)
        })
        .collect();
    minima.sort_by(|a, b| a.rss.total_cmp(&b.rss));
    minima
}

/// Steps of the amplitude around the polar profile's best value, as factors.
const AMPLITUDE_REFINE: [f64; 2] = [0.85, 1.15];

/// A profile value: the delta, the all-load start its score built, and the residual sum of
/// squares (sigma^2) that scored it.
#[derive(Clone, Debug)]
struct Scored {
    delta: Vec<f64>,
    start: Vec<f64>,
    rss: f64,
}

/// `score` at every delta of `deltas` (in parallel); values it rejects or scores as
/// non-finite are left out, and it fails only when every value is.
fn scored_deltas(
    cand: Candidate,
    deltas: Vec<Vec<f64>>,
    score: &(dyn Fn(&Effect) -> Result<ScoredStart> + Sync),
) -> Result<Vec<Scored>> {
    let all: Vec<(Vec<f64>, Result<ScoredStart>)> = deltas
        .into_par_iter()
        .map(|d| {
            let r = score(&Effect::of(cand, d.clone()));
            (d, r)
        })
        .collect();
    let mut first_error = None;
    let mut out = Vec::new();
    for (delta, r) in all {
        match r {
            Ok((start, rss)) if rss.is_finite() => out.push(Scored { delta, start, rss }),
            Ok(_) => {}
            Err(e) => {
                first_error.get_or_insert(e);
            }
        }
    }
    if out.is_empty() {
        return Err(first_error.unwrap_or_else(|| {
            GearError::Numerical("no profile value gives a finite residual".into())
        }));
    }
    Ok(out)
}

/// The lowest of `scored` (the first of equals, in scan order).
fn lowest<'a>(scored: impl Iterator<Item = &'a Scored>) -> Option<&'a Scored> {
    scored.min_by(|a, b| a.rss.total_cmp(&b.rss))
}

/// The (delta, start) with the lowest score of `start_at` over `coarse`, then over
/// `refine(best)` when a refinement scores lower. Ties keep the earlier value (scan order);
/// values `start_at` rejects are skipped, and the profile fails only when it rejects them all.
fn best_of_profile(
    cand: Candidate,
    coarse: Vec<Vec<f64>>,
    refine: &dyn Fn(&[f64]) -> Vec<Vec<f64>>,
    start_at: &(dyn Fn(&Effect) -> Result<ScoredStart> + Sync),
) -> Result<(Vec<f64>, Vec<f64>)> {
    let best_of = |deltas: Vec<Vec<f64>>| -> Result<Scored> {
        let scored = scored_deltas(cand, deltas, start_at)?;
        Ok(lowest(scored.iter())
            .cloned()
            .expect("scored_deltas is not empty"))
    };
    let coarse = best_of(coarse)?;
    let best = match best_of(refine(&coarse.delta)) {
        Ok(fine) if fine.rss < coarse.rss => fine,
        _ => coarse,
    };
    Ok((best.delta, best.start))
}

/// The noise of a run as the refits use it: the scales at M0's levels, the noise model that
/// gave them, and what was known of it before any fit.
#[derive(Clone, Copy)]
pub(super) struct RunNoise<'a> {
    pub scales: &'a Scales,
    pub noise: &'a DiscoveryNoise,
    pub spec: &'a NoiseSpec,
}

/// The scales of a refit's last stage: on the training curves, the noise estimated anew about
/// the refit's predictions `preds` on the points `fitted` keeps (stated noise: its scales at
/// the refit's levels); elsewhere the run's. About M0, a missing effect's misfit at the
/// resonances inflates the estimate (eps 0.2 hidden in Gaussian noise of floor 0.15 um: floor
/// 0.21 um and Student-t tails of 3 dof, standard deviations 2.4 times the true ones), which
/// would widen the refit's interval by as much. Returns the scales and the noise behind them.
fn refit_scales(
    setup: &Setup,
    w: RunNoise,
    train: &[usize],
    preds: &[CurvePrediction],
    fitted: &Mask,
) -> Result<(Scales, RefitNoise)> {
    let mut levels: Vec<Vec<f64>> = setup.curves.iter().map(|c| c.dte_pp_um.clone()).collect();
    let mut mask: Mask = levels.iter().map(|l| vec![false; l.len()]).collect();
    let mut full: Vec<CurvePrediction> = setup
        .curves
        .iter()
        .map(|c| {
            let n = c.dte_pp_um.len();
            CurvePrediction {
                dte_pp_um: c.dte_pp_um.clone(),
                period1: vec![true; n],
                separated: vec![false; n],
                back_contact: vec![false; n],
                aperiodic_start: vec![None; n],
                neighbour_starts: Vec::new(),
                sweep_model: None,
            }
        })
        .collect();
    for (k, &i) in train.iter().enumerate() {
        levels[i] = preds[k].dte_pp_um.clone();
        mask[i] = fitted[i].clone();
        full[i] = preds[k].clone();
    }
    let noise = noise_about(setup, w.spec, &full, &mask)?;
    let fresh = noise.scales(&levels);
    let mut scales = w.scales.clone();
    for &i in train {
        scales[i] = fresh[i].clone();
    }
    Ok((scales, RefitNoise { noise, levels }))
}

/// How much -2 log L falls from fit `old` to fit `new` ([`deviance_under`]), both standardized
/// by `scales` on the points `mask` keeps of the curves `train`, the noise `noise` taken at each
/// fit's own level: the measure [`Refit::other_basin`] compares basins by.
pub(super) fn deviance_gain(
    setup: &Setup,
    train: &[usize],
    mask: &Mask,
    scales: &Scales,
    noise: &DiscoveryNoise,
    old: &LmFit,
    new: &LmFit,
) -> f64 {
    deviance_under(setup, old, train, mask, scales, noise)
        - deviance_under(setup, new, train, mask, scales, noise)
}

/// -2 log L of a fit (Gaussian errors, the constant dropped) on the points `mask` keeps of the
/// curves `idx`: sum z_i^2 + 2 sum ln sigma_i, with the noise `noise` evaluated at the fit's own
/// predictions (recovered from its residuals, standardized by `old`). Each fit is weighed by
/// the noise its own curve implies: the weighted sum of squares alone, with the scales of one
/// fit's level, favours whichever fit those scales were not taken about.
fn deviance_under(
    setup: &Setup,
    lm: &LmFit,
    idx: &[usize],
    mask: &Mask,
    old: &Scales,
    noise: &DiscoveryNoise,
) -> f64 {
    let mut levels: Scales = setup.curves.iter().map(|c| c.dte_pp_um.clone()).collect();
    let mut raw = Vec::with_capacity(lm.residuals.len());
    let mut z = lm.residuals.iter();
    for &i in idx {
        for j in 0..mask[i].len() {
            if mask[i][j] {
                let r = z.next().copied().unwrap_or(f64::NAN) * old[i][j];
                levels[i][j] -= r;
                raw.push(r);
            }
        }
    }
    let scales = row_scales(idx, mask, &noise.scales(&levels));
    let ln_2pi = (2.0 * std::f64::consts::PI).ln();
    -2.0 * log_likelihood(Distribution::Gaussian, &raw, &scales) - raw.len() as f64 * ln_2pi
}

/// A fit's standardized residuals, their sum of squares and Jacobian with each row r
/// re-standardized from scale `old[r]` to `new[r]` (rows: the points `mask` keeps of the
/// curves `idx`, in order).
fn restandardized(lm: &LmFit, idx: &[usize], mask: &Mask, old: &Scales, new: &Scales) -> LmFit {
    let (o, n) = (row_scales(idx, mask, old), row_scales(idx, mask, new));
    let mut out = lm.clone();
    for (r, (a, b)) in o.iter().zip(&n).enumerate() {
        if let Some(x) = out.residuals.get_mut(r) {
            *x *= a / b;
        }
        if r < out.jacobian.nrows() {
            out.jacobian.row_mut(r).scale_mut(a / b);
        }
        if let Some(sec) = out.secant_jacobian.as_mut().filter(|j| r < j.nrows()) {
            sec.row_mut(r).scale_mut(a / b);
        }
    }
    out.rss = rss(&out.residuals);
    out
}

#[cfg(test)]
mod tests {
    use super::{
        deviance_under, distinct_minima, from_the_better_basin, nearest_distinct_basin,
        polar_profile, profile_start, ste_roots,
    };
    use crate::discover::effects::{Candidate, Effect};
    use crate::discover::run::OtherStart;
    use crate::error::{GearError, Result};

    /// A fit's -2 log L weighs it by the noise at its own level: data 2, 10, 4 um (the middle
    /// point masked out), a fit predicting 1 and 6 um on the kept points (standardized residuals
    /// under scales 0.5 and 2 um), the noise 0.2 um + 10% of the level: sigma = hypot(0.2, 0.1)
    /// and hypot(0.2, 0.6) um at the predictions 1 and 6 um, residuals 1 and -2 um, in closed
    /// form. A second fit, predicting 4 um exactly at the third point, is scored with the
    /// scales at its own levels, not the first fit's.
    #[test]
    fn the_deviance_takes_each_fits_noise_at_its_own_level() {
        use crate::discover::forward::{Curve, Setup};
        use crate::discover::noise::{DiscoveryNoise, NoiseOrigin};
        use crate::fit::{LmFit, NoiseModel};
        use crate::validate::MunroNoise;
        let dim = crate::data::munro_rig().dimensional().unwrap();
        let curve = Curve {
            load_n: 3780.0,
            speeds_rpm: vec![1000.0, 2000.0, 3000.0],
            dte_pp_um: vec![2.0, 10.0, 4.0],
            sd_um: None,
        };
        let setup = Setup::new(
            dim,
            3780.0,
            vec![curve],
            MunroNoise::Estimate { floor_min: 0.0 },
        );
        let mask = vec![vec![true, false, true]];
        let old = vec![vec![0.5, 1.0, 2.0]];
        let noise = DiscoveryNoise::stated(
            NoiseOrigin::StatedOption,
            NoiseModel {
                floor: 0.2,
                relative: 0.1,
                ..NoiseModel::constant(0.2)
            },
        );
        let fit = |z: Vec<f64>| LmFit {
            params: Vec::new(),
            rss: 0.0,
            residuals: z,
            jacobian: nalgebra::DMatrix::zeros(0, 0),
            secant_jacobian: None,
            evaluations: 0,
        };
        let expected = |r: &[f64], sigma: &[f64]| -> f64 {
            r.iter()
                .zip(sigma)
                .map(|(r, s)| (r / s).powi(2) + 2.0 * s.ln())
                .sum()
        };
        let a = deviance_under(&setup, &fit(vec![2.0, -1.0]), &[0], &mask, &old, &noise);
        let sa = [0.2f64.hypot(0.1), 0.2f64.hypot(0.6)];
        assert!((a - expected(&[1.0, -2.0], &sa)).abs() < 1e-12, "{a}");
        // Its residuals sqrt(2) and 0 under the scales 0.5 and 2 um: predictions
        // 2 - 0.5 sqrt(2) and 4 um.
        let b = deviance_under(
            &setup,
            &fit(vec![2f64.sqrt(), 0.0]),
            &[0],
            &mask,
            &old,
            &noise,
        );
        let mu0 = 2.0 - 0.5 * 2f64.sqrt();
        let sb = [0.2f64.hypot(0.1 * mu0), 0.2f64.hypot(0.4)];
        assert!(
            (b - expected(&[0.5 * 2f64.sqrt(), 0.0], &sb)).abs() < 1e-12,
            "{b}"
        );
        assert!(b < a - 10.0, "{a} {b}");
    }

    /// Two fits are distinct minima when each phase lies outside the other's Wald arc (study
    /// seed 4's pair, 55 deg apart with arcs of +-4 deg, is); the same minimum reached twice,
    /// or a fit inside a wide arc, is not; without arcs, more than 90 deg apart. The phase
    /// difference wraps at +-180 deg.
    /// The last stage's swap on stand-in fits (numbers for their -2 log L): from the kept fit
    /// 10 with rivals 7 and 12, rival 7 fits better; the stage runs again from 7 with 12 and
    /// 10 as rivals, and the outcome whose best rival lies higher above it is kept.
    #[test]
    fn the_last_stage_is_rerun_from_a_better_rival_and_the_consistent_outcome_kept() {
        use std::cell::RefCell;
        let calls = RefCell::new(Vec::new());
        // An outcome: (the fit it started from, its best rival's increase).
        let stage = |from: &i32, others: &[i32]| -> Result<((i32, f64), Option<usize>)> {
            calls.borrow_mut().push((*from, others.to_vec()));
            let (k, best) = others
                .iter()
                .enumerate()
                .min_by_key(|(_, o)| **o)
                .map(|(k, o)| (k, *o))
                .unwrap();
            let increase = f64::from(best - from);
            Ok(((*from, increase), (increase < 0.0).then_some(k)))
        };
        let increase = |o: &(i32, f64)| o.1;
        let kept = from_the_better_basin(10, vec![7, 12], stage, increase).unwrap();
        assert_eq!(kept, (7, 3.0));
        assert_eq!(*calls.borrow(), vec![(10, vec![7, 12]), (7, vec![12, 10])]);

        // No better rival: one stage, its outcome kept.
        calls.borrow_mut().clear();
        let kept = from_the_better_basin(7, vec![10, 12], stage, increase).unwrap();
        assert_eq!(kept, (7, 3.0));
        assert_eq!(calls.borrow().len(), 1);

        // A second stage no more consistent than the first (its rival as far below): the first
        // is kept.
        let flat = |from: &i32, _: &[i32]| -> Result<((i32, f64), Option<usize>)> {
            Ok(((*from, -1.0), Some(0)))
        };
        let kept = from_the_better_basin(10, vec![7], flat, increase).unwrap();
        assert_eq!(kept, (10, -1.0));

        // A failing second stage fails the whole.
        let failing = |from: &i32, _: &[i32]| -> Result<((i32, f64), Option<usize>)> {
            if *from == 10 {
                Ok(((10, -2.0), Some(0)))
            } else {
                Err(GearError::Numerical("no start converged".into()))
            }
        };
        assert!(from_the_better_basin(10, vec![7], failing, increase).is_err());
    }

    #[test]
    fn distinct_minima_lie_outside_each_others_arcs() {
        let at = |deg: f64| {
            let r = deg.to_radians();
            vec![0.2 * r.cos(), 0.2 * r.sin()]
        };
        let arc = |deg: f64, half: f64| Some((deg - half, deg + half));
        let (kept, other) = (at(248.0), at(303.0));
        assert!(distinct_minima(
            (&other, arc(303.0, 6.0)),
            (&kept, arc(248.0, 4.2))
        ));
        assert!(!distinct_minima(
            (&at(250.0), arc(250.0, 4.0)),
            (&kept, arc(248.0, 4.2))
        ));
        // Inside the other fit's wide arc, though outside the kept one's.
        assert!(!distinct_minima(
            (&other, arc(303.0, 70.0)),
            (&kept, arc(248.0, 4.2))
        ));
        assert!(!distinct_minima((&other, None), (&kept, None)));
        assert!(distinct_minima((&at(68.0), None), (&kept, None)));
        // 170 and -170 deg are 20 deg apart, not 340.
        assert!(distinct_minima(
            (&at(-170.0), arc(-170.0, 5.0)),
            (&at(170.0), arc(170.0, 5.0))
        ));
        assert!(!distinct_minima(
            (&at(-170.0), arc(-170.0, 25.0)),
            (&at(170.0), arc(170.0, 5.0))
        ));
    }

    /// After a profile's better refit: where it moved into the other basin, that basin is no
    /// longer "other" and the old kept fit becomes it; where it stayed in the kept basin, the
    /// other basin stays, further above by what the better refit gained; where both are
    /// distinct from it, the nearer.
    #[test]
    fn the_other_basin_is_rebased_on_a_better_refit() {
        let basin = |deg: f64, half: f64, increase: f64| {
            let r = deg.to_radians();
            OtherStart {
                delta: vec![0.2 * r.cos(), 0.2 * r.sin()],
                deviance_increase: increase,
                ci95: Some((0.15, 0.25)),
                phase_wald95_deg: Some((deg - half, deg + half)),
            }
        };
        // Kept 248 deg, other 303 deg 2.0 above; the better refit, 1.5 lower, at `deg`.
        let rebase = |deg: f64| {
            let r = deg.to_radians();
            let d = vec![0.2 * r.cos(), 0.2 * r.sin()];
            nearest_distinct_basin(
                basin(248.0, 4.0, 1.5),
                Some(basin(303.0, 5.0, 2.0)),
                1.5,
                (&d, Some((deg - 4.0, deg + 4.0))),
            )
        };
        // The other basin found (its phase, deg) and its increase over the better refit.
        let found = |o: Option<OtherStart>| {
            o.map(|o| {
                let deg = o.delta[1].atan2(o.delta[0]).to_degrees().rem_euclid(360.0);
                (
                    (deg * 1e6).round() / 1e6,
                    (o.deviance_increase * 1e9).round() / 1e9,
                )
            })
        };
        // In the other basin (302 deg): the old kept fit is the other basin now.
        assert_eq!(found(rebase(302.0)), Some((248.0, 1.5)));
        // In the kept basin (250 deg): the other basin, 2.0 + 1.5 above.
        assert_eq!(found(rebase(250.0)), Some((303.0, 3.5)));
        // A third basin (150 deg): both are distinct from it, the old kept fit is nearer.
        assert_eq!(found(rebase(150.0)), Some((248.0, 1.5)));
        // No other basin before, and the better refit in the kept basin: none.
        let d = basin(250.0, 4.0, 0.0);
        assert!(nearest_distinct_basin(
            basin(248.0, 4.0, 0.7),
            None,
            0.7,
            (&d.delta, d.phase_wald95_deg)
        )
        .is_none());
    }

    /// The admissible STEs closest to M0's amplitude: both roots where both are positive; the
    /// upper root and zero where the lower root is negative and |ste + w| falls at zero (study
    /// seed 9's design load: a 3.02 um, w (-1.52, 2.39) um, roots -0.32 and 3.36 um); the upper
    /// root alone where it rises there; the vertex where no root exists.
    #[test]
    fn ste_roots_are_the_admissible_local_best_matches() {
        let close = |got: &[f64], want: &[f64]| {
            got.len() == want.len() && got.iter().zip(want).all(|(g, w)| (g - w).abs() < 1e-12)
        };
        // |ste + (-2, 1)| = 2: ste = 2 -+ sqrt(3).
        let both = ste_roots(2.0, (-2.0, 1.0));
        assert!(
            close(&both, &[2.0 - 3f64.sqrt(), 2.0 + 3f64.sqrt()]),
            "{both:?}"
        );
        let (a, w): (f64, (f64, f64)) = (3.02, (-1.52, 2.39));
        let upper = -w.0 + (a * a - w.1 * w.1).sqrt();
        assert!((upper - 3.36).abs() < 0.01);
        let seed9 = ste_roots(a, w);
        assert!(close(&seed9, &[upper, 0.0]), "{seed9:?}");
        // At zero |ste + w| = 2.83 um < a: the lower branch's best admissible STE.
        assert!(w.0.hypot(w.1) < a);
        // Re w > 0: |ste + w| rises from zero, which is no local best.
        let rising = ste_roots(a, (1.52, 2.39));
        assert!(
            close(&rising, &[-1.52 + (a * a - 2.39 * 2.39).sqrt()]),
            "{rising:?}"
        );
        // No root: the vertex, or zero when the vertex is negative.
        assert!(close(&ste_roots(1.0, (-2.0, 3.0)), &[2.0]));
        assert!(close(&ste_roots(1.0, (2.0, 3.0)), &[0.0]));
    }

    /// The profile takes the best probe, then the best refinement step around it, skips the
    /// values its scorer rejects, and fails only when every value is rejected.
    #[test]
    fn profile_start_refines_around_the_best_probe_and_skips_rejected_values() {
        // Backlash probes are beta = +-0.1, 0.25, 0.5; the minimum at -0.36 is closest to the
        // probe -0.25 (0.11 away; -0.5 is 0.14 away) and then to the step -0.25 - 2 x 0.05.
        // The start is the scorer's own, here (STE, delta).
        let sharp = |e: &Effect| -> crate::error::Result<(Vec<f64>, f64)> {
            assert_eq!(e.candidate, Some(Candidate::Backlash));
            let d = e.delta[0];
            if d > 0.0 {
                return Err(GearError::Numerical("rejected".into()));
            }
            Ok((vec![10.0, d], (d + 0.36).powi(2)))
        };
        let start = profile_start(Candidate::Backlash, &sharp).unwrap();
        assert_eq!(start.len(), 2);
        assert!((start[1] + 0.35).abs() < 1e-12, "{start:?}");
        let none = |_: &Effect| -> crate::error::Result<(Vec<f64>, f64)> {
            Err(GearError::Numerical("rejected".into()))
        };
        assert!(profile_start(Candidate::Backlash, &none).is_err());
    }

    /// The polar profile scans the first pair's amplitude and phase (every pair turned alike,
    /// the others' amplitudes kept): with a minimum at amplitude 0.35 and 100 degrees from the
    /// design-load phase it takes the grid's 0.35 at the coarse shift of 90 degrees (120 is 20
    /// away), then the step of 10 degrees on; the other basin is the best value more than 90
    /// degrees from that (the shift 0, 100 degrees away; 180 is only 80 away), refined by its
    /// step of 10 degrees toward the minimum.
    #[test]
    fn polar_profile_finds_amplitude_and_phase_and_the_other_basin() {
        let d1 = [0.1, 0.0, 0.0, 0.1];
        let target = 100f64.to_radians();
        let score = |e: &Effect| -> crate::error::Result<(Vec<f64>, f64)> {
            let a = e.delta[0].hypot(e.delta[1]);
            let off = 1.0 - (Candidate::first_phase(&e.delta) - target).cos() + (a - 0.35).powi(2);
            Ok((e.delta.clone(), off))
        };
        let starts: Vec<Vec<f64>> = polar_profile(Candidate::SteHarmonics, &d1, &score)
            .unwrap()
            .into_iter()
            .map(|s| s.delta)
            .collect();
        let best = &starts[0];
        let deg = |x: f64, y: f64| y.atan2(x).to_degrees();
        assert!((deg(best[0], best[1]) - 100.0).abs() < 1e-9, "{best:?}");
        assert!((best[0].hypot(best[1]) - 0.35).abs() < 1e-12, "{best:?}");
        // The third harmonic's pair (phase 90) turned by the same 100 degrees, its amplitude kept.
        assert!(
            (deg(best[2], best[3]) - 190.0 + 360.0).abs() < 1e-9,
            "{best:?}"
        );
        assert!((best[2].hypot(best[3]) - 0.1).abs() < 1e-12);
        // One minimum: the other start is the best more than 90 degrees away.
        assert_eq!(starts.len(), 2, "{starts:?}");
        let other = &starts[1];
        assert!((deg(other[0], other[1]) - 10.0).abs() < 1e-9, "{other:?}");
        assert!((other[0].hypot(other[1]) - 0.35).abs() < 1e-12, "{other:?}");
    }

    /// Three local minima over the phase (100, -110 and 10 degrees, in that order of depth):
    /// all three are starts, lowest first, each at its own phase.
    #[test]
    fn polar_profile_starts_from_each_phase_minimum() {
        let d1 = [0.1, 0.0];
        let well = |phase: f64, centre: f64, depth: f64| {
            let diff = (phase - centre.to_radians()).rem_euclid(std::f64::consts::TAU);
            let diff = diff.min(std::f64::consts::TAU - diff);
            depth + diff * diff
        };
        let score = |e: &Effect| -> crate::error::Result<(Vec<f64>, f64)> {
            let ph = Candidate::first_phase(&e.delta);
            let a = e.delta[0].hypot(e.delta[1]);
            let off = well(ph, 100.0, 0.0)
                .min(well(ph, -110.0, 0.2))
                .min(well(ph, 10.0, 0.3));
            Ok((e.delta.clone(), off + (a - 0.2).powi(2)))
        };
        let starts = polar_profile(Candidate::MeshStiffnessVariation, &d1, &score).unwrap();
        let deg: Vec<f64> = starts
            .iter()
            .map(|s| s.delta[1].atan2(s.delta[0]).to_degrees())
            .collect();
        assert_eq!(deg.len(), 3, "{deg:?}");
        for (got, want) in deg.iter().zip([100.0, -110.0, 10.0]) {
            assert!((got - want).abs() < 1e-9, "{deg:?}");
        }
    }
}
