//! The candidate library: physical effects missing from the paper's model (M0), each with
//! parameters delta such that delta = 0 gives M0 back exactly (nested models, so that a
//! likelihood-ratio test between M0 and M0 + effect is meaningful).

use crate::error::{GearError, Result};
use crate::model::{Dimensional, GearPair, Term};
use serde::Serialize;

/// One candidate effect of the library.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Candidate {
    /// k(t) = 1 + eps cos(Omega t + psi) (design.md 1; the effect the paper names for the Kubo
    /// mismatch, Sec. 7 and 9). delta = (eps cos psi, eps sin psi).
    MeshStiffnessVariation,
    /// 2nd and 3rd STE harmonics F_ahj sin(j Omega t + phi_j), j = 2, 3 (eq. 20) as fractions
    /// r_j of the first: delta = (r2 cos phi2, r2 sin phi2, r3 cos phi3, r3 sin phi3).
    SteHarmonics,
    /// Load-dependent damping zeta(W) = zeta (W / W_design)^gamma. delta = (gamma).
    DampingLaw,
    /// Half backlash b free: b = b_stated exp(beta) (Sec. 2.1 scales F_m, F_ah and the DTE in
    /// um by b). delta = (beta).
    Backlash,
    /// External torque ripple at mesh frequency F_aT sin(Omega t + phi) (eq. 20's F_aT term),
    /// the same newtons at every load, F_aT = a F_m(design). delta = (a cos phi, a sin phi).
    TorqueRipple,
}

/// Every candidate, in report order.
pub const LIBRARY: [Candidate; 5] = [
    Candidate::MeshStiffnessVariation,
    Candidate::SteHarmonics,
    Candidate::DampingLaw,
    Candidate::Backlash,
    Candidate::TorqueRipple,
];

impl Candidate {
    /// The name used in discovery.json.
    pub fn name(self) -> &'static str {
        match self {
            Candidate::MeshStiffnessVariation => "mesh_stiffness_variation",
            Candidate::SteHarmonics => "ste_harmonics",
            Candidate::DampingLaw => "damping_law",
            Candidate::Backlash => "backlash",
            Candidate::TorqueRipple => "torque_ripple",
        }
    }

    /// Number of parameters delta.
    pub fn dim(self) -> usize {
        match self {
            Candidate::SteHarmonics => 4,
            Candidate::MeshStiffnessVariation | Candidate::TorqueRipple => 2,
            Candidate::DampingLaw | Candidate::Backlash => 1,
        }
    }

    /// What the reported estimate is (the profile coordinate of [`Candidate::profiled`], as
    /// [`Candidate::estimate_of_profiled`] maps it).
    pub fn estimate_name(self) -> &'static str {
        match self {
            Candidate::MeshStiffnessVariation => "eps",
            Candidate::SteHarmonics => "r2 (2nd harmonic / 1st)",
            Candidate::DampingLaw => "gamma",
            Candidate::Backlash => "b / b_stated",
            Candidate::TorqueRipple => "F_aT / F_m(design)",
        }
    }

    /// Whether delta holds (cos, sin) pairs of an amplitude and a phase, so that -delta is the
    /// same amplitude at the opposite phase (and the profile coordinate is an amplitude, which
    /// cannot go below zero).
    pub fn has_phase(self) -> bool {
        matches!(
            self,
            Candidate::MeshStiffnessVariation | Candidate::SteHarmonics | Candidate::TorqueRipple
        )
    }

    /// Phase (rad) of the first (cos, sin) pair of a phase-carrying candidate's delta, which
    /// holds (A cos psi, A sin psi): psi for the stiffness variation and the torque ripple, the
    /// 2nd harmonic's phase for the STE harmonics.
    pub fn first_phase(delta: &[f64]) -> f64 {
        delta[1].atan2(delta[0])
    }

    /// Angle (rad, 0 to pi) between the first phases of two deltas, wrapped: 170 and -170
    /// degrees are 20 degrees apart.
    pub fn phase_distance(a: &[f64], b: &[f64]) -> f64 {
        Self::angle_apart(Self::first_phase(a), Self::first_phase(b))
    }

    /// Angle (rad, 0 to pi) between two phases (rad, any turn), wrapped.
    pub fn angle_apart(a: f64, b: f64) -> f64 {
        let diff = (a - b).rem_euclid(std::f64::consts::TAU);
        diff.min(std::f64::consts::TAU - diff)
    }

    /// The coordinate a profile-likelihood interval holds and the rest of delta, free while it
    /// is held: a phase-carrying candidate's first amplitude, and its first phase (rad) and
    /// other pairs; gamma and nothing; beta (b = b_stated e^beta, the Wald interval's too).
    pub fn profiled(self, delta: &[f64]) -> (f64, Vec<f64>) {
        if self.has_phase() {
            let mut free = vec![Candidate::first_phase(delta)];
            free.extend_from_slice(&delta[2..]);
            (delta[0].hypot(delta[1]), free)
        } else {
            (delta[0], Vec::new())
        }
    }

    /// The delta of [`Candidate::profiled`]'s coordinate `u` and free part `free`.
    pub fn unprofiled(self, u: f64, free: &[f64]) -> Vec<f64> {
        if self.has_phase() {
            let (s, c) = free[0].sin_cos();
            let mut d = vec![u * c, u * s];
            d.extend_from_slice(&free[1..]);
            d
        } else {
            vec![u]
        }
    }

    /// The estimate at profile coordinate `u`: u, or exp(u) for the backlash.
    pub fn estimate_of_profiled(self, u: f64) -> f64 {
        match self {
            Candidate::Backlash => u.exp(),
            _ => u,
        }
    }

    /// Probe points delta, the starts of the candidate's fit and its identifiability check:
    /// amplitudes (smallest first) times phases for the phase-carrying effects, else signed steps.
    pub fn probes(self) -> Vec<Vec<f64>> {
        let polar = |amps: &[f64], phases: usize, slot: usize, dim: usize| {
            let mut v = Vec::new();
            for &a in amps {
                for k in 0..phases {
                    let ph = 2.0 * std::f64::consts::PI * k as f64 / phases as f64;
                    let mut d = vec![0.0; dim];
                    d[slot] = a * ph.cos();
                    d[slot + 1] = a * ph.sin();
                    v.push(d);
                }
            }
            v
        };
        let steps = |v: &[f64]| v.iter().map(|x| vec![*x]).collect();
        match self {
            Candidate::MeshStiffnessVariation => polar(&[0.05, 0.15, 0.3], 6, 0, 2),
            Candidate::SteHarmonics => {
                let mut v = polar(&[0.15, 0.35, 0.6], 6, 0, 4);
                v.extend(polar(&[0.15, 0.35], 6, 2, 4));
                v
            }
            Candidate::DampingLaw => steps(&[-1.0, -0.5, -0.2, 0.2, 0.5, 1.0]),
            Candidate::Backlash => steps(&[-0.5, -0.25, -0.1, 0.1, 0.25, 0.5]),
            Candidate::TorqueRipple => polar(&[0.01, 0.03, 0.08], 6, 0, 2),
        }
    }

    /// Typical size of one component of delta (the Levenberg-Marquardt parameter scale).
    pub fn scale(self) -> f64 {
        match self {
            Candidate::TorqueRipple => 0.01,
            _ => 0.05,
        }
    }
}

/// Largest factor between the fitted and the stated backlash, either way. A stated backlash is
/// measured (a feeler gauge, or rocking one gear against the other); one off by more than a
/// factor five describes another gear pair.
pub const MAX_BACKLASH_FACTOR: f64 = 5.0;

/// A candidate with its parameters (or M0 when `candidate` is None).
#[derive(Clone, Debug, PartialEq)]
pub struct Effect {
    pub candidate: Option<Candidate>,
    pub delta: Vec<f64>,
}

impl Effect {
    /// The paper's model.
    pub fn none() -> Self {
        Effect {
            candidate: None,
            delta: Vec::new(),
        }
    }

    /// A candidate at parameters `delta`.
    pub fn of(candidate: Candidate, delta: Vec<f64>) -> Self {
        Effect {
            candidate: Some(candidate),
            delta,
        }
    }

    /// The dimensional scales under the effect (only the backlash changes them). The backlash
    /// stays within a factor `MAX_BACKLASH_FACTOR` of the stated one, a fit step beyond it
    /// rejected: where the teeth stay in contact the data do not bound it, and at an enormous
    /// backlash every force is near rounding and the exact solver's crossing search stalls.
    pub fn dimensional(&self, dim: &Dimensional) -> Result<Dimensional> {
        let mut d = dim.clone();
        if self.candidate == Some(Candidate::Backlash) {
            let factor = self.delta[0].exp();
            if !(1.0 / MAX_BACKLASH_FACTOR..=MAX_BACKLASH_FACTOR).contains(&factor) {
                return Err(GearError::param(
                    "backlash_factor",
                    factor,
                    "a discovery fit keeps the backlash within a factor 5 of the stated one",
                ));
            }
            d.half_backlash_m *= factor;
        }
        Ok(d)
    }

    /// Damping ratio at a load W / W_design = `load_ratio`: zeta (W / W_design)^gamma under the
    /// damping law, zeta otherwise.
    pub fn zeta_at(&self, zeta: f64, load_ratio: f64) -> f64 {
        match self.candidate {
            Some(Candidate::DampingLaw) => zeta * load_ratio.powf(self.delta[0]),
            _ => zeta,
        }
    }

    /// The model at one load: M0 (zeta, F_m, F_ah) with the effect added. `load_ratio` is
    /// W / W_design and `design_fm` the design-load F_m (both under the effect's scales).
    pub fn model(
        &self,
        zeta: f64,
        fm: f64,
        fah: f64,
        load_ratio: f64,
        design_fm: f64,
    ) -> Result<GearPair> {
        let mut m = GearPair::paper(fm, fah, self.zeta_at(zeta, load_ratio), 1.0)?;
        let d = &self.delta;
        // The (cos, sin) pair at `slot` as a term of `order`, its amplitude times `scale`; none
        // at zero amplitude.
        let term = |order: u32, slot: usize, scale: f64| {
            let a = d[slot].hypot(d[slot + 1]);
            (a > 0.0).then(|| Term {
                order,
                amplitude: a * scale,
                phase: d[slot + 1].atan2(d[slot]),
            })
        };
        match self.candidate {
            None | Some(Candidate::Backlash) | Some(Candidate::DampingLaw) => {}
            Some(Candidate::MeshStiffnessVariation) => m.stiffness.extend(term(1, 0, 1.0)),
            Some(Candidate::SteHarmonics) => m
                .ste
                .extend([term(2, 0, fah), term(3, 2, fah)].into_iter().flatten()),
            Some(Candidate::TorqueRipple) => m.torque.extend(term(1, 0, design_fm)),
        }
        m.validated()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Nesting: every candidate at delta = 0 is the paper's model itself.
    #[test]
    fn zero_delta_gives_the_paper_model() {
        let m0 = GearPair::paper(0.3, 0.01, 0.02, 1.0).unwrap();
        for c in LIBRARY {
            let e = Effect::of(c, vec![0.0; c.dim()]);
            assert_eq!(
                e.model(0.02, 0.3, 0.01, 0.5, 0.6).unwrap(),
                m0,
                "{}",
                c.name()
            );
        }
        let dim = crate::data::munro_rig().dimensional().unwrap();
        let e = Effect::of(Candidate::Backlash, vec![0.0]);
        assert_eq!(e.dimensional(&dim).unwrap(), dim);
    }

    /// The probes stay inside the models' admissible ranges (eps < 1, zeta > 0, b within a
    /// factor 5 of the stated one).
    #[test]
    fn probes_build_valid_models() {
        let dim = crate::data::munro_rig().dimensional().unwrap();
        for c in LIBRARY {
            for d in c.probes() {
                assert_eq!(d.len(), c.dim());
                let e = Effect::of(c, d);
                e.model(0.02, 0.3, 0.01, 0.25, 0.6).unwrap();
                e.dimensional(&dim).unwrap();
            }
        }
    }

    /// The backlash bound: b x 4.9 and b / 4.9 are fitted, b x 5.1, b / 5.1, e^37 and a NaN
    /// are refused.
    #[test]
    fn backlash_stays_within_a_factor_five_of_the_stated_one() {
        let dim = crate::data::munro_rig().dimensional().unwrap();
        let at = |factor: f64| Effect::of(Candidate::Backlash, vec![factor.ln()]).dimensional(&dim);
        let b = at(4.9).unwrap().half_backlash_m / dim.half_backlash_m;
        assert!((b - 4.9).abs() < 1e-12, "{b}");
        assert!(at(1.0 / 4.9).is_ok());
        for factor in [5.1, 1.0 / 5.1, 37f64.exp(), f64::NAN] {
            assert!(at(factor).is_err(), "{factor}");
        }
    }
}
