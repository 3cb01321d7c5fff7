//! The probe dictionary at M0's fit: each candidate's finite probes, their change of the
//! training curves, for the score ranking and the likelihood-ratio statistic of
//! [`super::linearized`].

use super::effects::{Effect, LIBRARY};
use super::fit::{Mask, ModelFit};
use super::forward::{predict, CurvePrediction, Setup};
use super::noise::Scales;
use super::refit::matched_stes;
use super::run::row_scales;
use crate::error::{GearError, Result};
use crate::progress::Progress;
use nalgebra::DVector;
use rayon::prelude::*;

/// Every probe of the candidate library: (candidate index in [`LIBRARY`], delta).
pub(super) fn library_probes() -> Vec<(usize, Vec<f64>)> {
    LIBRARY
        .iter()
        .enumerate()
        .flat_map(|(c, cand)| cand.probes().into_iter().map(move |d| (c, d)))
        .collect()
}

/// The probe dictionary at M0's fit, by candidate ([`LIBRARY`] order): each probe's change of
/// the training curves on their kept points, its delta, and whether some probe moves the
/// design-load curve by the noise (the identifiability rule on the refit's first stage of a
/// candidate without a phase; a phase-carrying one's refit starts from a polar profile).
/// A candidate one of whose probes cannot be simulated at M0's fit has no probes and the
/// reason in `failed`.
pub(super) struct ProbeDictionary {
    pub raw: Vec<Vec<DVector<f64>>>,
    pub deltas: Vec<Vec<Vec<f64>>>,
    pub seen_at_design: [bool; LIBRARY.len()],
    pub failed: Vec<Option<String>>,
}

/// What every probe's curves are taken against: M0's fit, its curves and their kept points.
struct AtM0<'a> {
    setup: &'a Setup,
    train: &'a [usize],
    m0: &'a ModelFit,
    mask: &'a Mask,
    f0: &'a [CurvePrediction],
    scales: &'a Scales,
}

impl AtM0<'_> {
    /// The kept points of training load `i` (its position `k` in the training loads) under
    /// `effect`, as differences from M0's curve; at M0's STE, or, for an effect with a
    /// first-order part at the mesh frequency, at the STE matched to it ([`matched_stes`]).
    ///
    /// A probe at M0's STE drives the in-contact response at |STE + w| instead of M0's
    /// amplitude: the linear projection off M0's Jacobian removes that change where the teeth
    /// stay in contact, but not where they separate, so an unmatched probe's change of the
    /// curves there is not the effect's. Every eps 0.15 set the workflow missed (phases 5, 100,
    /// 123, 254 and 268 deg, relative and quantized noise) had the stiffness variation's own
    /// test at p 0.011-0.248 and the second STE harmonic's at 0.001, while its information
    /// bound on the same curves is lambda >= 36 sigma^2 at every phase. Of the roots, the
    /// one whose curve comes closest to M0's is taken: a choice made by M0's fit alone, so the
    /// bootstrap under M0 still calibrates the statistic (the refit's choice among them by
    /// the data's residual would not be).
    fn probe_rows(&self, k: usize, effect: &Effect) -> Result<Vec<f64>> {
        let i = self.train[k];
        let g = self.m0.globals;
        let ste = self.m0.ste_um[k];
        let rows = |ste: f64| -> Result<Vec<f64>> {
            let p = predict(self.setup, i, g, ste, effect)?;
            Ok(self.mask[i]
                .iter()
                .enumerate()
                .filter(|(_, keep)| **keep)
                .map(|(j, _)| p.dte_pp_um[j] - self.f0[i].dte_pp_um[j])
                .collect())
        };
        match matched_stes(self.setup, i, ste, effect) {
            None => rows(ste),
            Some(roots) => {
                let candidates = roots
                    .into_par_iter()
                    .map(|s| {
                        let r = rows(s)?;
                        Ok((self.standardized_norm(i, &r), r))
                    })
                    .collect::<Result<Vec<_>>>()?;
                candidates
                    .into_iter()
                    .min_by(|a, b| a.0.total_cmp(&b.0))
                    .map(|(_, r)| r)
                    .ok_or_else(|| GearError::Numerical("no STE matches the probe".into()))
            }
        }
    }

    /// Squared norm of the kept-point differences `rows` of load `i`, in units of the noise.
    fn standardized_norm(&self, i: usize, rows: &[f64]) -> f64 {
        rows.iter()
            .zip(row_scales(&[i], self.mask, self.scales))
            .map(|(x, s)| (x / s).powi(2))
            .sum()
    }

    /// One probe's change of every training curve on its kept points, in training order.
    fn probe(&self, effect: &Effect) -> Result<Vec<f64>> {
        let per_load = (0..self.train.len())
            .into_par_iter()
            .map(|k| self.probe_rows(k, effect))
            .collect::<Result<Vec<_>>>()?;
        Ok(per_load.concat())
    }
}

/// [`ProbeDictionary`] of M0's fit `m0` (globals and training STEs; its curves `f0`) on the
/// training curves `train`, one step of `progress` a probe. A probe that fails is the failure
/// of its candidate, not of the run: the probes are the candidate's own model at M0's fit,
/// and a damping law's gamma -1 at M0's zeta 0.64 asks for zeta 1.27 at half the design load
/// (an independent set with a 2nd STE harmonic of 40% whose M0 ended there, and the whole run
/// stopped).
pub(super) fn probe_dictionary(
    setup: &Setup,
    train: &[usize],
    m0: &ModelFit,
    mask: &Mask,
    f0: &[CurvePrediction],
    scales: &Scales,
    progress: &dyn Progress,
) -> ProbeDictionary {
    let at = AtM0 {
        setup,
        train,
        m0,
        mask,
        f0,
        scales,
    };
    let probes = library_probes();
    let probe_rows: Vec<Result<Vec<f64>>> = probes
        .par_iter()
        .map(|(c, d)| {
            let v = at.probe(&Effect::of(LIBRARY[*c], d.clone()));
            progress.advance(1);
            v
        })
        .collect();
    let mut raw: Vec<Vec<DVector<f64>>> = vec![Vec::new(); LIBRARY.len()];
    let mut deltas: Vec<Vec<Vec<f64>>> = vec![Vec::new(); LIBRARY.len()];
    // The design-load curve's rows are the first kept points of each probe's differences.
    let design_rows = mask[train[0]].iter().filter(|keep| **keep).count();
    let mut seen_at_design = [false; LIBRARY.len()];
    let mut failed: Vec<Option<String>> = vec![None; LIBRARY.len()];
    for (v, (c, d)) in probe_rows.into_iter().zip(&probes) {
        match v {
            Ok(v) => {
                seen_at_design[*c] |= at.standardized_norm(train[0], &v[..design_rows]) >= 1.0;
                raw[*c].push(DVector::from_vec(v));
                deltas[*c].push(d.clone());
            }
            Err(e) => {
                failed[*c].get_or_insert_with(|| {
                    format!("its probe delta = {d:?} could not be simulated at M0's fit: {e}")
                });
            }
        }
    }
    for c in (0..LIBRARY.len()).filter(|&c| failed[c].is_some()) {
        raw[c].clear();
        deltas[c].clear();
        seen_at_design[c] = false;
    }
    ProbeDictionary {
        raw,
        deltas,
        seen_at_design,
        failed,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::data::munro_rig;
    use crate::discover::effects::Candidate;
    use crate::discover::forward::{Curve, Globals};
    use crate::fit::LmFit;
    use crate::progress::NoProgress;
    use crate::validate::MunroNoise;

    /// Munro's rig with a curve at each load of `loads` over `speeds` (measured values 1 um:
    /// the probes do not read them).
    fn setup_at(loads: &[f64], speeds: &[f64]) -> Setup {
        let curves = loads
            .iter()
            .map(|&load_n| Curve {
                load_n,
                speeds_rpm: speeds.to_vec(),
                dte_pp_um: vec![1.0; speeds.len()],
                sd_um: None,
            })
            .collect();
        Setup::new(
            munro_rig().dimensional().unwrap(),
            3780.0,
            curves,
            MunroNoise::Estimate { floor_min: 0.0 },
        )
    }

    /// M0's fit at `globals` with the training STEs `ste_um` (the probes read no more of it).
    fn m0_at(globals: Globals, ste_um: Vec<f64>) -> ModelFit {
        ModelFit {
            globals,
            ste_um,
            effect: Effect::none(),
            lm: LmFit {
                params: Vec::new(),
                rss: 0.0,
                residuals: Vec::new(),
                jacobian: nalgebra::DMatrix::zeros(0, 0),
                secant_jacobian: None,
                evaluations: 0,
            },
        }
    }

    /// The design load alone, in contact across the resonance (zeta 0.02, 1600 Hz, STE 0.3 um),
    /// with M0's fit at those values, its curve, every point kept and a noise scale of 0.05 um.
    fn at_m0_parts() -> (Setup, ModelFit, Mask, Vec<CurvePrediction>, Scales) {
        let speeds = [1500.0, 2200.0, 2700.0, 2950.0, 3100.0, 3500.0, 4500.0];
        let n = speeds.len();
        let setup = setup_at(&[3780.0], &speeds);
        let globals = Globals {
            zeta: 0.02,
            omega_n_hz: 1600.0,
        };
        let f0 = vec![predict(&setup, 0, globals, 0.3, &Effect::none()).unwrap()];
        let m0 = m0_at(globals, vec![0.3]);
        (setup, m0, vec![vec![true; n]], f0, vec![vec![0.05; n]])
    }

    /// M0's fit at zeta 0.64 (as on an independent set with a 2nd STE harmonic of 40%, 64
    /// speeds at Omega 0.4-1.45, whose M0 ended at zeta 0.636 and 1282 Hz): the damping law's
    /// probe gamma = -1 asks for zeta 1.28 at half the design load, outside 0 < zeta < 1. The
    /// dictionary is still made: the damping law has failed, with the probe and the reason,
    /// and has no probes; every other candidate has all of its own. (The run used to end
    /// there with the bare "invalid parameter zeta".)
    #[test]
    fn a_probe_outside_the_models_range_fails_its_candidate_not_the_dictionary() {
        let speeds = [1600.0, 2400.0, 3200.0, 4000.0, 5600.0];
        let n = speeds.len();
        let setup = setup_at(&[3780.0, 1890.0], &speeds);
        let globals = Globals {
            zeta: 0.64,
            omega_n_hz: 1282.0,
        };
        let ste = vec![0.8, 6.0];
        let f0: Vec<CurvePrediction> = (0..2)
            .map(|i| predict(&setup, i, globals, ste[i], &Effect::none()).unwrap())
            .collect();
        let m0 = m0_at(globals, ste);
        let (mask, scales) = (vec![vec![true; n]; 2], vec![vec![0.05; n]; 2]);
        let dict = probe_dictionary(&setup, &[0, 1], &m0, &mask, &f0, &scales, &NoProgress);
        let damping = LIBRARY
            .iter()
            .position(|&c| c == Candidate::DampingLaw)
            .unwrap();
        let why = dict.failed[damping]
            .as_deref()
            .expect("the damping law failed");
        assert!(
            why.contains("[-1.0]") && why.contains("invalid parameter zeta = 1.28"),
            "{why}"
        );
        assert!(dict.raw[damping].is_empty() && dict.deltas[damping].is_empty());
        assert!(!dict.seen_at_design[damping]);
        for (c, cand) in LIBRARY.iter().enumerate().filter(|(c, _)| *c != damping) {
            assert!(
                dict.failed[c].is_none(),
                "{}: {:?}",
                cand.name(),
                dict.failed[c]
            );
            assert_eq!(dict.raw[c].len(), cand.probes().len(), "{}", cand.name());
        }
    }

    /// A stiffness variation whose first-order part is w = -0.5 um (eps 0.5 um / the static
    /// deflection, psi -90 deg) has two matched STEs for M0's 0.3 um, 0.2 and 0.8 um, both in
    /// contact. The probe takes the one whose curve comes closer to M0's, and there the change
    /// is the rest the first order neglects, within 4% of the pp (see the forward model's
    /// `matched_ste_reproduces_m0_to_first_order`): in the noise's norm under a seventh of the
    /// probe at M0's STE, which drives the response at |0.3 - 0.5| = 0.2 um instead of 0.3 um,
    /// a third less (found: 22 against 9100 sigma^2, a twentieth). A second STE harmonic has no
    /// part at the mesh frequency and is taken at M0's STE.
    #[test]
    fn probes_match_the_ste_to_the_first_order_part_and_take_the_closer_root() {
        let (setup, m0, mask, f0, scales) = at_m0_parts();
        let at = AtM0 {
            setup: &setup,
            train: &[0],
            m0: &m0,
            mask: &mask,
            f0: &f0,
            scales: &scales,
        };
        let dim = &setup.dim;
        let eps = 0.5 / dim.ste_um(dim.mean_force(3780.0));
        let e = Effect::of(Candidate::MeshStiffnessVariation, vec![0.0, -eps]);
        let roots = matched_stes(&setup, 0, 0.3, &e).unwrap();
        assert_eq!(roots.len(), 2, "{roots:?}");
        assert!((roots[0] - 0.2).abs() < 1e-9 && (roots[1] - 0.8).abs() < 1e-9);
        let rows_at = |ste: f64, e: &Effect| -> Vec<f64> {
            let p = predict(&setup, 0, m0.globals, ste, e).unwrap();
            assert!(p.separated.iter().all(|s| !s), "left contact at {ste} um");
            p.dte_pp_um
                .iter()
                .zip(&f0[0].dte_pp_um)
                .map(|(p, q)| p - q)
                .collect()
        };
        let norms: Vec<f64> = roots
            .iter()
            .map(|&s| at.standardized_norm(0, &rows_at(s, &e)))
            .collect();
        let closer = if norms[0] <= norms[1] {
            roots[0]
        } else {
            roots[1]
        };
        let probe = at.probe(&e).unwrap();
        assert_eq!(probe, rows_at(closer, &e));
        let unmatched = at.standardized_norm(0, &rows_at(0.3, &e));
        assert!(
            at.standardized_norm(0, &probe) < unmatched / 49.0,
            "matched {norms:?}, unmatched {unmatched}"
        );

        let harmonic = Effect::of(Candidate::SteHarmonics, vec![0.15, 0.0, 0.0, 0.0]);
        assert!(matched_stes(&setup, 0, 0.3, &harmonic).is_none());
        assert_eq!(at.probe(&harmonic).unwrap(), rows_at(0.3, &harmonic));
    }
}
