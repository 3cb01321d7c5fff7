//! Model parameters: eq. 3a with the excitation of eq. 20 and an optional mesh-stiffness variation.

use crate::error::{GearError, Result};
use serde::{Deserialize, Serialize};

/// Largest force the model accepts, in units of the half backlash (F_m is the static deflection
/// over b). Beyond it b is, to any gear, zero, and the closed form's derivative bounds in the
/// exact solver approach overflow (a fit that let b drift to b e^-667 reached F_m ~ 1e289).
pub const MAX_FORCE: f64 = 1e9;

/// Smallest excitation frequency Omega accepted (a forcing period of 6e6 natural periods).
pub const MIN_OMEGA: f64 = 1e-6;
/// Largest excitation frequency Omega accepted.
pub const MAX_OMEGA: f64 = 1e6;

const TOO_LARGE: &str =
    "force beyond 1e9 half backlashes of deflection: the backlash is negligible, use a linear model";

/// One harmonic term `amplitude * sin(order * Omega * t + phase)` (or `cos` for stiffness terms),
/// at an integer multiple `order` of the fundamental frequency Omega of [`GearPair`].
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Term {
    /// Multiple of the fundamental frequency (j in eq. 20), >= 1.
    pub order: u32,
    /// Amplitude: F_ahj for STE terms, F_aTj for torque terms, eps_j for stiffness terms.
    pub amplitude: f64,
    /// Phase in radians (phi_hj, phi_Tj or psi_j).
    pub phase: f64,
}

impl Term {
    /// A term of the given order and amplitude with zero phase.
    pub fn new(order: u32, amplitude: f64) -> Self {
        Term {
            order,
            amplitude,
            phase: 0.0,
        }
    }
}

/// Dimensionless spur gear pair with backlash (design.md section 1):
///
/// q'' + 2 zeta q' + k(t) f(q) = F(t),
/// F(t) = F_m + sum F_aT sin(n Omega t + phi) + sum (n Omega)^2 F_ah sin(n Omega t + phi),
/// k(t) = 1 + sum eps cos(n Omega t + psi).
///
/// Every excitation is a harmonic of one fundamental frequency `omega`, whose period 2 pi / omega
/// is the stroboscopic (Poincare) period. The paper's eq. 5 is one STE term of order 1; Fig. 29's
/// Omega_h = 2 Omega_T is `omega = Omega_T`, a torque term of order 1 and an STE term of order 2.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GearPair {
    /// Damping ratio zeta of the mesh, 0 < zeta < 1.
    pub zeta: f64,
    /// Dimensionless mean load F_m = F_bar_m / (b k_h), >= 0.
    pub mean_force: f64,
    /// Fundamental excitation frequency Omega (dimensionless, omega_n = 1).
    pub omega: f64,
    /// Static transmission error terms e/b = sum F_ahj sin(j Omega t + phi_hj) (eq. 20).
    pub ste: Vec<Term>,
    /// External torque terms F_aTj sin(j Omega t + phi_Tj) (eq. 20).
    pub torque: Vec<Term>,
    /// Mesh-stiffness variation k(t) = 1 + sum eps_j cos(j Omega t + psi_j).
    pub stiffness: Vec<Term>,
}

impl GearPair {
    /// The paper's model, eq. 5: one STE harmonic F_ah at Omega_h = `omega`, phase 0.
    pub fn paper(mean_force: f64, ste_amplitude: f64, zeta: f64, omega: f64) -> Result<Self> {
        GearPair {
            zeta,
            mean_force,
            omega,
            ste: vec![Term::new(1, ste_amplitude)],
            torque: Vec::new(),
            stiffness: Vec::new(),
        }
        .validated()
    }

    /// The STE excitation of eq. 5 (F_ah, phase 0) together with an external torque of eq. 4
    /// (F_aT sin(Omega t), the same frequency, Omega_h = Omega_T as in Sec. 8.1); `fat = 0` is
    /// [`GearPair::paper`], `fah = 0` eq. 4 alone.
    pub fn excited(
        mean_force: f64,
        ste_amplitude: f64,
        torque_amplitude: f64,
        zeta: f64,
        omega: f64,
    ) -> Result<Self> {
        let mut m = GearPair::paper(mean_force, ste_amplitude, zeta, omega)?;
        if torque_amplitude != 0.0 {
            m.torque = vec![Term::new(1, torque_amplitude)];
        }
        m.validated()
    }

    /// ", F_aT = .." for a caption when an external torque of eq. 4 acts, else nothing.
    pub fn torque_caption(torque_amplitude: f64) -> String {
        if torque_amplitude > 0.0 {
            format!(", F_aT = {torque_amplitude}")
        } else {
            String::new()
        }
    }

    /// Return the same model at another fundamental frequency (used by sweeps).
    pub fn at_omega(&self, omega: f64) -> Result<Self> {
        GearPair {
            omega,
            ..self.clone()
        }
        .validated()
    }

    /// Check every parameter; the solvers assume a validated model.
    pub fn validated(self) -> Result<Self> {
        if !(self.zeta.is_finite() && self.zeta > 0.0 && self.zeta < 1.0) {
            return Err(GearError::param(
                "zeta",
                self.zeta,
                "damping ratio must satisfy 0 < zeta < 1 (the mesh is underdamped)",
            ));
        }
        if !(self.omega.is_finite() && self.omega > 0.0) {
            return Err(GearError::param(
                "omega",
                self.omega,
                "excitation frequency must be finite and > 0",
            ));
        }
        if !(MIN_OMEGA..=MAX_OMEGA).contains(&self.omega) {
            return Err(GearError::param(
                "omega",
                self.omega,
                "excitation frequency over the natural frequency must be in [1e-6, 1e6] \
                 (further out the time of one forcing period under- or overflows the solvers)",
            ));
        }
        if !(self.mean_force.is_finite() && self.mean_force >= 0.0) {
            return Err(GearError::param(
                "F_m",
                self.mean_force,
                "mean load must be finite and >= 0 (the model is symmetric under q -> -q)",
            ));
        }
        if self.mean_force > MAX_FORCE {
            return Err(GearError::param("F_m", self.mean_force, TOO_LARGE));
        }
        for (name, terms) in [
            ("F_ah", &self.ste),
            ("F_aT", &self.torque),
            ("eps", &self.stiffness),
        ] {
            for t in terms {
                if t.order == 0 {
                    return Err(GearError::param(name, 0.0, "harmonic order must be >= 1"));
                }
                if !(t.amplitude.is_finite() && t.amplitude >= 0.0) {
                    return Err(GearError::param(
                        name,
                        t.amplitude,
                        "harmonic amplitude must be finite and >= 0 (use the phase for the sign)",
                    ));
                }
                if t.amplitude > MAX_FORCE {
                    return Err(GearError::param(name, t.amplitude, TOO_LARGE));
                }
                if !t.phase.is_finite() {
                    return Err(GearError::param(name, t.phase, "phase must be finite"));
                }
            }
        }
        let eps_sum: f64 = self.stiffness.iter().map(|t| t.amplitude).sum();
        if eps_sum >= 1.0 {
            return Err(GearError::param(
                "eps",
                eps_sum,
                "sum of stiffness-variation amplitudes must be < 1 so that k(t) > 0",
            ));
        }
        Ok(self)
    }

    /// Forcing period 2 pi / Omega.
    pub fn period(&self) -> f64 {
        2.0 * std::f64::consts::PI / self.omega
    }

    /// Force ratio F_hat = F_m / F_ah of the first STE term (Sec. 2.2); infinite without STE.
    pub fn force_ratio(&self) -> f64 {
        match self.ste.first() {
            Some(t) if t.amplitude > 0.0 => self.mean_force / t.amplitude,
            _ => f64::INFINITY,
        }
    }

    /// True when k(t) is not identically 1 (the exact piecewise solver then does not apply).
    pub fn has_stiffness_variation(&self) -> bool {
        self.stiffness.iter().any(|t| t.amplitude != 0.0)
    }

    /// Highest harmonic order of any excitation term (0 when unforced).
    pub fn max_order(&self) -> u32 {
        self.ste
            .iter()
            .chain(&self.torque)
            .chain(&self.stiffness)
            .filter(|t| t.amplitude != 0.0)
            .map(|t| t.order)
            .max()
            .unwrap_or(0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn validation_rejects_bad_values() {
        assert!(GearPair::paper(0.1, 0.2, 0.02, 0.5).is_ok());
        assert!(GearPair::paper(0.1, 0.2, -0.02, 0.5).is_err());
        assert!(GearPair::paper(0.1, 0.2, 0.0, 0.5).is_err());
        assert!(GearPair::paper(0.1, 0.2, 0.02, 0.0).is_err());
        assert!(GearPair::paper(f64::NAN, 0.2, 0.02, 0.5).is_err());
        assert!(GearPair::paper(0.1, f64::INFINITY, 0.02, 0.5).is_err());
        let mut m = GearPair::paper(0.1, 0.2, 0.02, 0.5).unwrap();
        m.stiffness = vec![Term::new(1, 1.0)];
        assert!(m.validated().is_err());
        // Forces of more than MAX_FORCE backlashes: b is negligible, and the exact solver's
        // bounds would approach overflow.
        assert!(GearPair::paper(1e9, 0.2, 0.02, 0.5).is_ok());
        assert!(GearPair::paper(2e9, 0.2, 0.02, 0.5).is_err());
        assert!(GearPair::paper(0.1, 2e9, 0.02, 0.5).is_err());
    }

    #[test]
    fn force_ratio_is_fm_over_fah() {
        let m = GearPair::paper(0.1, 0.2, 0.02, 0.5).unwrap();
        assert!((m.force_ratio() - 0.5).abs() < 1e-15);
    }
}
