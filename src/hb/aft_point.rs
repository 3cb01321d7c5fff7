//! One multi-harmonic balance solution with its response measures (q_a, q_m, impact regime of
//! Fig. 9, defined as in the simulation) and its Floquet stability.

use super::aft_floquet::monodromy;
use super::aft_series::{eval_theta, extremes, harmonics_of};
use crate::model::{GearPair, Impact};
use crate::sim::{eigenvalues2, State};
use serde::Serialize;

/// A periodic solution of eq. 3a (generalised) from the multi-harmonic balance with AFT:
///
/// q(t) = a_0 + sum_{k=1..H} (a_k cos(k Omega t / nu) + b_k sin(k Omega t / nu)).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct HbPoint {
    /// Excitation frequency Omega (the fundamental of [`GearPair`]).
    pub omega: f64,
    /// Subharmonic order nu: the orbit repeats after nu forcing periods.
    pub subharmonic: u32,
    /// Fourier coefficients `[a_0, a_1, b_1, ..., a_H, b_H]`.
    pub coeffs: Vec<f64>,
    /// Half range of q over the orbit, q_a = (max q - min q) / 2 (as in the simulation).
    pub qa: f64,
    /// Mid range of q over the orbit, q_m = (max q + min q) / 2 (as in the simulation).
    pub qm: f64,
    /// Smallest q over the orbit.
    pub q_min: f64,
    /// Largest q over the orbit.
    pub q_max: f64,
    /// Impact regime (case I, II, III of Sec. 4) from q_min.
    pub case: Impact,
    /// All Floquet multipliers inside the unit circle; `None` when stability was not computed.
    pub stable: Option<bool>,
    /// Floquet multipliers (re, im) of the variational equation about this solution over one
    /// orbit period; `None` when not computed.
    pub multipliers: Option<[(f64, f64); 2]>,
    /// A fold (turning point, saddle-node) of the branch: the Omega-component of the
    /// continuation tangent changes sign here.
    pub fold: bool,
    /// A real multiplier crossed -1 between the previous branch point and this one.
    pub period_doubling: bool,
    /// Final max |R| of the harmonic balance residual.
    pub residual: f64,
}

impl HbPoint {
    /// Assemble a solution from converged coefficients (computes extremes and, optionally, the
    /// Floquet multipliers).
    pub(crate) fn build(
        model: &GearPair,
        coeffs: Vec<f64>,
        omega: f64,
        subharmonic: u32,
        residual: f64,
        stability: bool,
    ) -> HbPoint {
        let (q_min, q_max) = extremes(&coeffs);
        let multipliers =
            stability.then(|| eigenvalues2(&monodromy(model, &coeffs, omega, subharmonic)));
        HbPoint {
            omega,
            subharmonic,
            qa: 0.5 * (q_max - q_min),
            qm: 0.5 * (q_max + q_min),
            q_min,
            q_max,
            case: Impact::from_range(q_min),
            stable: multipliers.map(|m| m.iter().all(|(re, im)| re.hypot(*im) < 1.0)),
            multipliers,
            fold: false,
            period_doubling: false,
            residual,
            coeffs,
        }
    }

    /// Number of harmonics H of the series.
    pub fn harmonics(&self) -> usize {
        harmonics_of(&self.coeffs)
    }

    /// Displacement q(t) of the series at time t (t = 0 is forcing phase 0).
    pub fn q(&self, t: f64) -> f64 {
        eval_theta(&self.coeffs, self.theta(t))[0]
    }

    /// State (q, q') of the series at time t, e.g. as an initial condition for the simulation.
    pub fn state(&self, t: f64) -> State {
        let v = eval_theta(&self.coeffs, self.theta(t));
        [v[0], v[1] * self.omega / self.subharmonic as f64]
    }

    /// Largest multiplier modulus, when computed.
    pub fn spectral_radius(&self) -> Option<f64> {
        self.multipliers
            .map(|m| m.iter().map(|(re, im)| re.hypot(*im)).fold(0.0, f64::max))
    }

    fn theta(&self, t: f64) -> f64 {
        self.omega * t / self.subharmonic as f64
    }
}
