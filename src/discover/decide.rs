//! Refit rounds and the decision they lead to: the candidates refitted, the one a name would
//! rest on (with its profile interval), and whether the curves name it, leave it ambiguous or
//! unexplained (see [discover-method.md](../../docs/discover-method.md#the-answer)).

use super::ambiguity::{ambiguous_with as ambiguous_partners, Contender};
use super::effects::LIBRARY;
use super::fit::{Mask, ModelFit};
use super::forward::{predict_many, CurvePrediction, Setup};
use super::interval::{over_both_basins, profiled_refit, wald_ci, IntervalFound, RefitNoise};
use super::linearized::{Linearized, Statistics, CHI_SQUARE_HELD_OUT, CHI_SQUARE_TRAINING};
use super::noise::{DiscoveryNoise, NoiseSpec, Scales};
use super::refit::{deviance_gain, rebased_other, refit_candidate, RunNoise};
use super::run::{
    detection_tests, make_mask, model_jacobian, noise_about, predict_all, rival, row_scales,
    significant, CandidateResult, DiscoverOptions, HeldFit, OtherStart, TestResult,
};
use crate::error::{GearError, Result};
use nalgebra::{DMatrix, DVector};
use rayon::prelude::*;

/// The decision from the refits so far, and what the report shows of it.
pub(super) struct Decision {
    pub effect: String,
    pub ambiguous_with: Vec<String>,
    pub closest: Option<String>,
    /// Detection tests after the best refit (empty without one).
    pub post_fit: Vec<TestResult>,
    /// Curves shown as "after": the best refit's when it explains the data, else M0's.
    pub after_preds: Vec<CurvePrediction>,
    /// Points both M0 and the best refit compare (M0's mask without one).
    pub compare_mask: Mask,
    /// The best refit's curves and held-out STE fits, even when it does not explain the data.
    pub refit_preds: Option<Vec<CurvePrediction>>,
    pub refit_held: Option<Vec<HeldFit>>,
    /// The interval of the candidate the decision rests on, and how it was found (see
    /// [`profiled_refit`]).
    pub named_ci: Option<(usize, IntervalFound)>,
    /// A better refit of that candidate, found by its profile.
    pub better_refit: Option<Refitted>,
    /// The refitted candidate the decision rests on (None without a refit).
    pub rests_on: Option<usize>,
    /// The held-out loads' preference when the training loads' differs ([`Rounds::held_out_split`]):
    /// the candidate whose refit predicts the held-out loads while the leading one's does not.
    pub held_out_prefers: Option<String>,
}

/// A refitted candidate.
pub(super) struct Refitted {
    /// Its index in [`LIBRARY`].
    pub cand: usize,
    pub fit: ModelFit,
    /// The points it was fitted on: M0's with the points around its own jumps dropped.
    pub mask: Mask,
    /// Its predictions of the training curves.
    pub train_preds: Vec<CurvePrediction>,
    /// The noise scales of its last stage (the noise estimated about the refit, see
    /// [`super::refit::refit_scales`]).
    pub scales: Scales,
    /// The noise model behind `scales`, for its intervals' quantile.
    pub noise: RefitNoise,
}

impl Refitted {
    /// The 97.5% quantile of its intervals ([`RefitNoise::quantile`]) on the training curves
    /// `train`.
    pub fn quantile(&self, train: &[usize]) -> f64 {
        self.noise
            .quantile(LIBRARY[self.cand], &self.fit.lm, train, &self.mask)
    }
}

/// A failure inside candidate `cand` (its index in [`LIBRARY`]) while a decision checked it:
/// the candidate fails `because` ([`CandidateResult::fail`]), and the decision is made again
/// without it ([`Rounds::decided`]).
struct CandidateFailed {
    cand: usize,
    because: String,
}

impl CandidateFailed {
    /// For `map_err`: in candidate `cand`, `what` ("its profile interval") failed.
    fn of(cand: usize, what: &'static str) -> impl Fn(GearError) -> CandidateFailed {
        move |e| CandidateFailed {
            cand,
            because: format!("{what} failed: {e}"),
        }
    }
}

/// The p-value of the test `name` among `tests` (None: absent, or not computed).
fn p_value_of(tests: &[TestResult], name: &str) -> Option<f64> {
    tests
        .iter()
        .find(|t| t.name == name)
        .and_then(|t| t.p_value)
}

/// A candidate's drop from M0: its refit's on the common points, else its dictionary LR.
fn drop_of(c: &CandidateResult) -> f64 {
    c.refit_lr.unwrap_or(c.lr)
}

/// The refits of candidates that can be named (significant after Holm's correction), not the
/// rivals refitted for the held-out split alone ([`Rounds::held_out_rivals`]).
fn namable<'a>(
    cands: &'a [CandidateResult],
    refits: &'a [Refitted],
    alpha: f64,
) -> impl Iterator<Item = &'a Refitted> {
    refits
        .iter()
        .filter(move |r| significant(&cands[r.cand], alpha))
}

/// The namable refitted candidate with the largest drop from M0.
fn largest_drop(cands: &[CandidateResult], refits: &[Refitted], alpha: f64) -> Option<usize> {
    namable(cands, refits, alpha)
        .map(|r| r.cand)
        .max_by(|&a, &b| drop_of(&cands[a]).total_cmp(&drop_of(&cands[b])))
}

/// Each refit's drop in the residual sum of squares from M0 (standardized residuals), on the
/// training points that every refit and M0 keep. Refits are compared on the same points: each
/// refit drops the points around its own jumps, and an effect that brings jumps (the stiffness
/// variation opens instability regions) would otherwise be compared on fewer points than one
/// that does not, and lose to a worse fit (eps 0.2, relative noise, seed 1: a drop of 1458 on
/// its own points against 7803 for a second STE harmonic with the wrong damping on its own).
fn common_drops(
    setup: &Setup,
    train: &[usize],
    f0: &[CurvePrediction],
    scales: &Scales,
    refits: &[&Refitted],
) -> Vec<(usize, f64)> {
    let kept = |i: usize, j: usize| refits.iter().all(|r| r.mask[i][j]);
    let rss_of = |preds: &dyn Fn(usize) -> f64, i: usize| -> f64 {
        let c = &setup.curves[i];
        (0..c.dte_pp_um.len())
            .filter(|&j| kept(i, j))
            .map(|j| ((c.dte_pp_um[j] - preds(j)) / scales[i][j]).powi(2))
            .sum()
    };
    let rss0: f64 = train
        .iter()
        .map(|&i| rss_of(&|j| f0[i].dte_pp_um[j], i))
        .sum();
    refits
        .iter()
        .map(|r| {
            let rss: f64 = train
                .iter()
                .enumerate()
                .map(|(k, &i)| rss_of(&|j| r.train_preds[k].dte_pp_um[j], i))
                .sum();
            (r.cand, rss0 - rss)
        })
        .collect()
}

/// The model Jacobian (um per parameter) of refit `f`, fitted on the points `fitted` keeps, on
/// the rows of M0's `mask` (the training curves' kept points in order): a row the refit did not
/// fit is zero.
fn refit_jacobian(
    f: &ModelFit,
    train: &[usize],
    mask: &Mask,
    fitted: &Mask,
    scales: &Scales,
) -> DMatrix<f64> {
    let j = model_jacobian(&f.lm, &row_scales(train, fitted, scales));
    let rows: Vec<bool> = train
        .iter()
        .flat_map(|&i| {
            (0..mask[i].len())
                .filter(move |&k| mask[i][k])
                .map(move |k| fitted[i][k])
        })
        .collect();
    let mut out = DMatrix::zeros(rows.len(), j.ncols());
    let mut next = 0;
    for (r, fit_row) in rows.iter().enumerate() {
        if *fit_row && next < j.nrows() {
            out.row_mut(r).copy_from(&j.row(next));
            next += 1;
        }
    }
    out
}

/// What every refit round and decision of one run reads: M0's fit on the training curves and
/// everything its tests fixed under the null.
pub(super) struct Rounds<'a> {
    pub setup: &'a Setup,
    pub opts: &'a DiscoverOptions,
    pub train: &'a [usize],
    pub held: &'a [usize],
    pub measured: &'a [Vec<f64>],
    pub m0: &'a ModelFit,
    pub mask: &'a Mask,
    pub f0: &'a [CurvePrediction],
    pub held0: &'a [HeldFit],
    pub noise: &'a DiscoveryNoise,
    pub scales: &'a Scales,
    pub spec: &'a NoiseSpec,
    /// The linearised statistics at M0 (its probes included).
    pub lin: &'a Linearized,
    /// Each candidate's probes standardized and projected off M0's Jacobian, and their deltas.
    pub dict: &'a [Vec<DVector<f64>>],
    pub dict_delta: &'a [Vec<Vec<f64>>],
    /// Whether a candidate's probes move the design-load curve by the noise.
    pub seen_at_design: &'a [bool],
    pub observed: &'a Statistics,
    /// The detection tests' names.
    pub names: &'a [String],
    /// Whether a discrepancy is detected (see `run::detection_tests`).
    pub detected: bool,
}

impl Rounds<'_> {
    /// The decision after refitting the candidates `first`. Before a discrepancy is called
    /// unexplained, every significant candidate is refitted: where M0 is far off, its local
    /// statistics can rank the right one low (on rattle-regime sets, b x 0.7, M0 sometimes
    /// settled at zeta 0.058 and omega_n 1815 Hz, true 0.0175 and 1600 Hz, where the backlash
    /// probes ranked third by score and by LR). And where a name fails the held-out test, its
    /// rivals, significant only before Holm's correction, are refitted
    /// ([`Rounds::held_out_rivals`]).
    pub fn settle(
        &self,
        first: &[usize],
        cands: &mut [CandidateResult],
        refits: &mut Vec<Refitted>,
    ) -> Decision {
        let alpha = self.opts.alpha;
        self.refit(first, cands, refits);
        let mut decision = self.decision(cands, refits);
        let rest: Vec<usize> = (0..cands.len())
            .filter(|&c| significant(&cands[c], alpha) && !first.contains(&c))
            .collect();
        if decision.effect == "unexplained" && !rest.is_empty() {
            self.refit(&rest, cands, refits);
            decision = self.decision(cands, refits);
        }
        let rivals: Vec<usize> = (0..cands.len())
            .filter(|&c| rival(&cands[c], alpha))
            .collect();
        if self.held_out_rivals(&decision) && !rivals.is_empty() {
            self.refit(&rivals, cands, refits);
            decision = self.decision(cands, refits);
        }
        // Say why a significant candidate has no estimate (a failed one says so already).
        for c in cands.iter_mut() {
            if significant(c, alpha)
                && c.estimate.is_none()
                && c.note.is_none()
                && c.failed.is_none()
            {
                c.note = Some(format!(
                    "not refitted: its score statistic {:.1} ranks below the {} significant \
                     candidates refitted first (by score, and the largest LR), and the answer \
                     ({}) needed no further refit",
                    c.score,
                    self.opts.refit_top.max(1),
                    decision.effect
                ));
            }
        }
        decision
    }

    /// Refit the candidates `list` (in parallel; those failed already are not tried again)
    /// and record each converged refit in `cands` and `refits`, then every refit's drop on the
    /// points all of them and M0 keep.
    pub fn refit(&self, list: &[usize], cands: &mut [CandidateResult], refits: &mut Vec<Refitted>) {
        let list: Vec<usize> = list
            .iter()
            .copied()
            .filter(|&c| cands[c].failed.is_none())
            .collect();
        let fits: Vec<Result<(Refitted, Option<OtherStart>)>> =
            list.par_iter().map(|&c| self.refit_one(c)).collect();
        // A refit that failed fails its candidate; the others go on.
        for (&c, fit) in list.iter().zip(fits) {
            let (r, other) = match fit {
                Ok(f) => f,
                Err(e) => {
                    cands[c].fail(format!("its refit failed: {e}"));
                    continue;
                }
            };
            let cand = LIBRARY[c];
            let delta = &r.fit.effect.delta;
            cands[c].other_start = other;
            cands[c].estimate = Some(cand.estimate(delta).0);
            // Two basins within chi2(0.95; 1) of each other: the interval spans both.
            let q = r.quantile(self.train);
            cands[c].interval_quantile = Some(q);
            cands[c].ci95 = over_both_basins(wald_ci(cand, &r.fit.lm, q), &cands[c]);
            cands[c].set_phase(&r.fit.lm, delta, q);
            cands[c].delta = Some(delta.clone());
            cands[c].refit_zeta = Some(r.fit.globals.zeta);
            cands[c].refit_omega_n_hz = Some(r.fit.globals.omega_n_hz);
            refits.push(r);
        }
        self.record_drops(cands, refits);
    }

    /// Candidate `c` refitted from its largest-LR probe, with its training predictions, and
    /// the other phase basin's fit when it has one.
    fn refit_one(&self, c: usize) -> Result<(Refitted, Option<OtherStart>)> {
        let k = self.observed.lr[c].1;
        let (fit, mask, other, (scales, noise)) = refit_candidate(
            self.setup,
            self.train,
            self.mask,
            RunNoise {
                scales: self.scales,
                noise: self.noise,
                spec: self.spec,
            },
            LIBRARY[c],
            self.m0,
            &self.dict_delta[c][k],
            self.seen_at_design[c],
            self.opts.refit_iterations,
        )?;
        let train_preds = predict_many(
            self.setup,
            self.train,
            fit.globals,
            &fit.ste_um,
            &fit.effect,
        )?;
        let refitted = Refitted {
            cand: c,
            fit,
            mask,
            train_preds,
            scales,
            noise,
        };
        Ok((refitted, other))
    }

    /// Every namable refit's drop from M0 on the points all of them and M0 keep
    /// ([`common_drops`]): a rival's refit, which cannot be named, does not move the points
    /// the others are compared on.
    fn record_drops(&self, cands: &mut [CandidateResult], refits: &[Refitted]) {
        let alpha = self.opts.alpha;
        let compared: Vec<&Refitted> = namable(cands, refits, alpha).collect();
        for (c, d) in common_drops(self.setup, self.train, self.f0, self.scales, &compared) {
            cands[c].refit_lr = Some(d);
        }
    }

    /// Whether decision `d` names an effect whose refit fails the held-out chi-square: then
    /// the candidates significant on their own tests before Holm's correction but not after
    /// are refitted as rivals for the held-out split ([`Rounds::held_out_split`]), never to be
    /// named themselves. On eps sets at 250-270 and 357 deg the stiffness variation's own test
    /// (p 0.012-0.015) did not survive Holm's correction while the 2nd STE harmonic's did;
    /// the harmonic was named with a held-out chi-square at p 0.001, and the stiffness
    /// variation, never refitted, could not be the rival the split turns to.
    pub fn held_out_rivals(&self, d: &Decision) -> bool {
        let named = d.rests_on.is_some_and(|b| d.effect == LIBRARY[b].name());
        named && self.fails_held_out(d)
    }

    /// Whether the refit decision `d` rests on fails the held-out chi-square at alpha / 2.
    fn fails_held_out(&self, d: &Decision) -> bool {
        p_value_of(&d.post_fit, CHI_SQUARE_HELD_OUT).is_some_and(|p| p < self.opts.alpha / 2.0)
    }

    /// The decision from the refits so far ([`Rounds::decide`]), with what it found kept
    /// ([`Rounds::keep_profile`]). The profile of the candidate a decision rests on may
    /// replace its refit with a better one, whose drop on the points every refit keeps can
    /// then be smaller than another candidate's: the decision is made again on the candidate
    /// with the largest drop, at most once per refit. On an eps 0.2 set (Student-t noise,
    /// study seed 13) a 2nd STE harmonic led by 755 against 740, its profile's better refit
    /// fell to 719, and the harmonic, with zeta 0.0045 against a true 0.0175, was named. (Since
    /// a matched start also scores zero STE, [`super::refit::ste_roots`], the stiffness
    /// variation leads there from the first decision; no study seed since has needed a second.)
    pub fn decision(&self, cands: &mut [CandidateResult], refits: &mut Vec<Refitted>) -> Decision {
        let mut d = self.decided(cands, refits);
        self.keep_profile(cands, refits, &mut d);
        for _ in 0..refits.len() {
            if largest_drop(cands, refits, self.opts.alpha) == d.rests_on {
                break;
            }
            d = self.decided(cands, refits);
            self.keep_profile(cands, refits, &mut d);
        }
        d
    }

    /// [`Rounds::decide`], where a candidate that fails inside it (its profile, the check of
    /// its refit) is recorded as failed and its refit dropped, and the decision is made again
    /// without it. Each failure is of a candidate in `refits` and removes it, so this ends.
    fn decided(&self, cands: &mut [CandidateResult], refits: &mut Vec<Refitted>) -> Decision {
        loop {
            match self.decide(cands, refits) {
                Ok(d) => return d,
                Err(CandidateFailed { cand, because }) => {
                    cands[cand].fail(because);
                    refits.retain(|r| r.cand != cand);
                    self.record_drops(cands, refits);
                }
            }
        }
    }

    /// The decision from the refits so far: the candidate with the largest drop, ambiguous
    /// with those the data cannot tell apart from it, its profile interval, the detection
    /// tests after its refit, and its verdict ([`Rounds::verdict`]). Anything that fails in
    /// it fails a candidate: M0's part of the run is done.
    fn decide(
        &self,
        cands: &[CandidateResult],
        refits: &[Refitted],
    ) -> std::result::Result<Decision, CandidateFailed> {
        let mut d = Decision {
            effect: if self.detected { "unexplained" } else { "none" }.to_string(),
            ambiguous_with: Vec::new(),
            closest: None,
            post_fit: Vec::new(),
            after_preds: self.f0.to_vec(),
            compare_mask: self.mask.clone(),
            refit_preds: None,
            refit_held: None,
            named_ci: None,
            better_refit: None,
            rests_on: None,
            held_out_prefers: None,
        };
        let sig: Vec<usize> = namable(cands, refits, self.opts.alpha)
            .map(|r| r.cand)
            .collect();
        let drop = |c: usize| drop_of(&cands[c]);
        let Some(best) = largest_drop(cands, refits, self.opts.alpha) else {
            return Ok(d);
        };
        d.rests_on = Some(best);
        // Two refitted candidates are ambiguous when the data cannot tell their fits apart
        // (see `ambiguity`); the coarse dictionary LR is not used.
        let contender = |c: usize| Contender {
            index: c,
            drop: drop(c),
            direction: &self.dict[c][self.observed.lr[c].1],
        };
        let others: Vec<Contender> = sig.iter().map(|&c| contender(c)).collect();
        d.ambiguous_with = ambiguous_partners(&contender(best), &others, self.opts.collinear_cos)
            .into_iter()
            .map(|c| cands[c].name.to_string())
            .collect();
        let Some(chosen) = refits.iter().find(|r| r.cand == best) else {
            return Ok(d);
        };
        self.profile_chosen(&mut d, best, chosen, cands)
            .map_err(CandidateFailed::of(best, "its profile interval"))?;
        let chosen = d.better_refit.as_ref().unwrap_or(chosen);
        let checked = self
            .check_refit(chosen)
            .map_err(CandidateFailed::of(best, "the check of its refit"))?;
        d.post_fit = checked.post_fit;
        d.compare_mask = checked.compare_mask;
        d.refit_held = Some(checked.held);
        d.refit_preds = Some(checked.preds.clone());
        d.after_preds = checked.preds;
        self.verdict(&mut d, &cands[best]);
        if d.effect == cands[best].name {
            self.held_out_split(&mut d, best, cands, refits)?;
        }
        Ok(d)
    }

    /// A name whose refit fails the held-out chi-square while another refit passes both the
    /// training and the held-out one is "ambiguous": the training loads prefer one candidate,
    /// the held-out loads the other. On eps 0.2 sets at phases near 250 deg (and 330 deg) the
    /// training loads let a 2nd STE harmonic with a wrong damping (zeta 0.005-0.007 against a
    /// true 0.0175) fit better than the stiffness variation: seven of 160 sets named it, each
    /// failing the held-out test at p 0.001. The held-out test alone is no veto: it also
    /// fails on 22 of 224 correct names (the 945 N curve's chaotic and multi-stable points).
    /// The split turned 2 of the 10 wrong names that failed it in the studies into
    /// "ambiguous" (the others' rival refits fail it too) and changed no correct name.
    fn held_out_split(
        &self,
        d: &mut Decision,
        best: usize,
        cands: &[CandidateResult],
        refits: &[Refitted],
    ) -> std::result::Result<(), CandidateFailed> {
        let half = self.opts.alpha / 2.0;
        if !self.fails_held_out(d) {
            return Ok(());
        }
        let mut others: Vec<&Refitted> = refits.iter().filter(|r| r.cand != best).collect();
        others.sort_by(|a, b| drop_of(&cands[b.cand]).total_cmp(&drop_of(&cands[a.cand])));
        for r in others {
            let check = self
                .check_refit(r)
                .map_err(CandidateFailed::of(r.cand, "the check of its refit"))?;
            let passes = |name| p_value_of(&check.post_fit, name).is_some_and(|p| p >= half);
            if passes(CHI_SQUARE_TRAINING) && passes(CHI_SQUARE_HELD_OUT) {
                let other = cands[r.cand].name.to_string();
                d.ambiguous_with = vec![cands[best].name.to_string(), other.clone()];
                d.effect = "ambiguous".into();
                d.held_out_prefers = Some(other);
                return Ok(());
            }
        }
        Ok(())
    }

    /// The refit a name would rest on gets its profile interval, and continues from a better
    /// point the profile finds (`d.better_refit`), before anything is predicted from it. A
    /// second decision (after every significant candidate was refitted) reuses the first
    /// one's profile of a refit that settled: `refits` already holds that refit, and its
    /// profile would come out the same. An ambiguous decision takes no profile.
    fn profile_chosen(
        &self,
        d: &mut Decision,
        best: usize,
        chosen: &Refitted,
        cands: &[CandidateResult],
    ) -> Result<()> {
        if !d.ambiguous_with.is_empty() {
            return Ok(());
        }
        let settled_before = cands[best].profile_ci95.map(|profile| IntervalFound {
            ci: cands[best].ci95,
            profile: Some(profile),
            phase_arc: cands[best].phase_profile95_deg,
            method: cands[best].ci95_method,
        });
        if let Some(found) = settled_before {
            d.named_ci = Some((best, found));
            return Ok(());
        }
        let (better, ci) = profiled_refit(
            self.setup,
            self.train,
            chosen,
            &cands[best],
            self.opts.refit_iterations,
            self.opts.phase_profile,
        )?;
        d.named_ci = Some((best, ci));
        d.better_refit = better;
        Ok(())
    }

    /// Refit `chosen`'s predictions of every curve and the detection tests after it, on the
    /// points both it and M0 keep.
    fn check_refit(&self, chosen: &Refitted) -> Result<RefitCheck> {
        let f = &chosen.fit;
        let (preds, held1) = predict_all(
            self.setup,
            f,
            self.train,
            self.held,
            self.mask,
            self.scales,
            Some(self.held0),
        )?;
        let every: Vec<usize> = (0..preds.len()).collect();
        let m1 = make_mask(self.setup, &preds, &every, self.noise)?;
        let zero: Mask = self
            .mask
            .iter()
            .zip(&m1)
            .map(|(a, b)| a.iter().zip(b).map(|(a, b)| *a && !*b).collect())
            .collect();
        let compare_mask: Mask = m1
            .iter()
            .zip(self.mask)
            .map(|(a, b)| a.iter().zip(b).map(|(a, b)| *a && *b).collect())
            .collect();
        let lin1 = Linearized {
            f0: preds.iter().map(|p| p.dte_pp_um.clone()).collect(),
            zero: Some(zero),
            jac_train: refit_jacobian(f, self.train, self.mask, &chosen.mask, &chosen.scales),
            held_sens: held1.iter().map(|(i, _, s)| (*i, s.clone())).collect(),
            held_globals: Vec::new(),
            probes: Vec::new(),
            // The noise about the refit: its tails and relative part chosen anew, where M0's
            // misfit no longer inflates them.
            noise: noise_about(self.setup, self.spec, &preds, &compare_mask)?,
            ..self.lin.clone()
        };
        let post = lin1.statistics(self.measured);
        // Its null is the bootstrap under the refitted curves, not under M0: the noise is
        // re-estimated from second differences of each replicate, which also see the
        // curves' own jumps and chaotic scatter. On a rattle-regime set (M0 24 um off) a
        // refit at the noise (training RMS 0.151 um against a true 0.15 um, data sigma
        // 0.267 um) failed this test at p = 0.02 under M0's bootstrap: a statistic of 29
        // on 94 rows that M0's replicates exceeded only 2% of the time, whose noise
        // re-estimate must have come out near twice the data's.
        let post_reps = lin1.bootstrap(self.opts.bootstrap, self.opts.seed);
        Ok(RefitCheck {
            post_fit: detection_tests(self.names, &post, &post_reps, &[]).0,
            compare_mask,
            preds,
            held: held1,
        })
    }

    /// The verdict on the best refit `best` (see discover-method.md, "The answer").
    fn verdict(&self, d: &mut Decision, best: &CandidateResult) {
        let alpha = self.opts.alpha;
        if !d.ambiguous_with.is_empty() {
            d.ambiguous_with.insert(0, best.name.to_string());
            d.effect = "ambiguous".into();
        } else if d.named_ci.is_some_and(|(_, found)| !found.settled()) {
            // Its profile found a better fit after every restart: an estimate still moving is
            // not named. On an eps 0.2 set (relative noise, study seed 13) a 2nd STE harmonic
            // refit, 1.18 um RMS off the training curves, improved at each of its restarts
            // and would have been named in place of the stiffness variation.
            d.effect = "unexplained".into();
            d.closest = Some(best.name.to_string());
        } else if p_value_of(&d.post_fit, CHI_SQUARE_TRAINING).is_some_and(|p| p < alpha / 2.0) {
            // The training chi-square after the refit (its null from the refit's bootstrap): the
            // held-out loads are predictions and their multi-stable branches are reported as
            // the held-out gap, not used to reject the name.
            d.effect = "unexplained".into();
            d.closest = Some(best.name.to_string());
        } else if !d
            .named_ci
            .and_then(|(_, found)| found.ci)
            .is_some_and(|ci| best.candidate.excludes_nested(ci))
        {
            // The refit explains the curves, but its size is not told apart from M0's
            // (delta = 0): the effect is not named. What remains is what the tests said.
            d.closest = Some(best.name.to_string());
        } else {
            d.effect = best.name.to_string();
        }
    }

    /// Keep what the decision `d` found of the candidate it rests on: a better refit its
    /// profile reached (replacing the earlier refit) and its interval.
    fn keep_profile(
        &self,
        cands: &mut [CandidateResult],
        refits: &mut Vec<Refitted>,
        d: &mut Decision,
    ) {
        if let Some(b) = d.better_refit.take() {
            if let Some(old) = refits.iter().find(|r| r.cand == b.cand) {
                let cand = LIBRARY[b.cand];
                let other = cands[b.cand].other_start.take();
                let gain = deviance_gain(
                    self.setup,
                    self.train,
                    &b.mask,
                    &b.scales,
                    &b.noise.noise,
                    &old.fit.lm,
                    &b.fit.lm,
                );
                cands[b.cand].other_start = rebased_other(
                    cand,
                    (&old.fit, old.quantile(self.train)),
                    other,
                    (&b.fit, b.quantile(self.train)),
                    gain,
                );
            }
            let c = &mut cands[b.cand];
            c.estimate = Some(c.candidate.estimate(&b.fit.effect.delta).0);
            let q = b.quantile(self.train);
            c.interval_quantile = Some(q);
            c.set_phase(&b.fit.lm, &b.fit.effect.delta, q);
            c.delta = Some(b.fit.effect.delta.clone());
            c.refit_zeta = Some(b.fit.globals.zeta);
            c.refit_omega_n_hz = Some(b.fit.globals.omega_n_hz);
            refits.retain(|r| r.cand != b.cand);
            refits.push(b);
            self.record_drops(cands, refits);
        }
        if let Some((c, found)) = d.named_ci.take() {
            // From the refit itself: on a second decision `ci95` is already a hull.
            let wald = refits.iter().find(|r| r.cand == c).and_then(|r| {
                let w = wald_ci(cands[c].candidate, &r.fit.lm, r.quantile(self.train));
                over_both_basins(w, &cands[c])
            });
            cands[c].wald_ci95 = wald;
            cands[c].ci95 = found.ci;
            cands[c].profile_ci95 = found.profile;
            cands[c].phase_profile95_deg = found.phase_arc;
            cands[c].ci95_method = found.method;
        }
    }
}

/// The best refit's curves and the detection tests after it.
struct RefitCheck {
    post_fit: Vec<TestResult>,
    /// Points both M0 and the refit keep.
    compare_mask: Mask,
    preds: Vec<CurvePrediction>,
    held: Vec<HeldFit>,
}
