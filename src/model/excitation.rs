//! Evaluation of the excitation of eq. 20 and the derived outputs of design.md section 1
//! (dynamic transmission error, dynamic load factor).

use super::mesh::dead_zone;
use super::params::GearPair;
use crate::fast_math::sin_cos;

/// One Fourier component `sin_coef sin(w t) + cos_coef cos(w t)` of the total forcing F(t),
/// at w = order * Omega. Terms of equal order from STE and torque are combined.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Harmonic {
    /// Multiple of the fundamental frequency.
    pub order: u32,
    /// Coefficient of sin(order Omega t).
    pub sin_coef: f64,
    /// Coefficient of cos(order Omega t).
    pub cos_coef: f64,
}

impl GearPair {
    /// Fourier components of F(t) - F_m (eq. 20): the STE terms carry the factor (j Omega)^2.
    pub fn forcing_harmonics(&self) -> Vec<Harmonic> {
        let mut out: Vec<Harmonic> = Vec::new();
        let mut add = |order: u32, amp: f64, phase: f64| {
            if amp == 0.0 {
                return;
            }
            let (s, c) = phase.sin_cos();
            match out.iter_mut().find(|h| h.order == order) {
                Some(h) => {
                    h.sin_coef += amp * c;
                    h.cos_coef += amp * s;
                }
                None => out.push(Harmonic {
                    order,
                    sin_coef: amp * c,
                    cos_coef: amp * s,
                }),
            }
        };
        for t in &self.ste {
            let w = t.order as f64 * self.omega;
            add(t.order, w * w * t.amplitude, t.phase);
        }
        for t in &self.torque {
            add(t.order, t.amplitude, t.phase);
        }
        out.sort_by_key(|h| h.order);
        out
    }

    /// Total forcing F(t) of eq. 20.
    pub fn forcing(&self, t: f64) -> f64 {
        let mut f = self.mean_force;
        for t_ in &self.ste {
            let w = t_.order as f64 * self.omega;
            f += w * w * t_.amplitude * (w * t + t_.phase).sin();
        }
        for t_ in &self.torque {
            f += t_.amplitude * (t_.order as f64 * self.omega * t + t_.phase).sin();
        }
        f
    }

    /// Static transmission error over half backlash, e(t)/b = sum F_ahj sin(j Omega t + phi_hj).
    pub fn ste_over_b(&self, t: f64) -> f64 {
        self.ste
            .iter()
            .map(|s| s.amplitude * sin_cos(s.order as f64 * self.omega * t + s.phase).0)
            .sum()
    }

    /// Mesh stiffness k(t) = 1 + sum eps_j cos(j Omega t + psi_j).
    pub fn stiffness_at(&self, t: f64) -> f64 {
        1.0 + self
            .stiffness
            .iter()
            .map(|s| s.amplitude * sin_cos(s.order as f64 * self.omega * t + s.phase).1)
            .sum::<f64>()
    }

    /// Dynamic transmission error x = q + e/b (design.md section 1; what Munro measured).
    pub fn dte(&self, t: f64, q: f64) -> f64 {
        q + self.ste_over_b(t)
    }

    /// Dynamic mesh force 2 zeta q' + k(t) f(q), the numerator of D_L (Sec. 7).
    pub fn mesh_force(&self, t: f64, q: f64, v: f64) -> f64 {
        2.0 * self.zeta * v + self.stiffness_at(t) * dead_zone(q)
    }

    /// Acceleration q'' from eq. 3a.
    pub fn acceleration(&self, t: f64, q: f64, v: f64) -> f64 {
        self.forcing(t) - self.mesh_force(t, q, v)
    }
}

#[cfg(test)]
mod tests {
    use crate::model::{GearPair, Term};

    #[test]
    fn harmonics_reproduce_forcing() {
        let mut m = GearPair::paper(0.1, 0.05, 0.05, 0.7).unwrap();
        m.ste.push(Term {
            order: 2,
            amplitude: 0.02,
            phase: 0.4,
        });
        m.torque.push(Term {
            order: 2,
            amplitude: 0.03,
            phase: -1.0,
        });
        let hs = m.forcing_harmonics();
        assert_eq!(hs.len(), 2);
        for &t in &[0.0, 0.37, 2.9, 11.0] {
            let mut f = m.mean_force;
            for h in &hs {
                let w = h.order as f64 * m.omega;
                f += h.sin_coef * (w * t).sin() + h.cos_coef * (w * t).cos();
            }
            assert!((f - m.forcing(t)).abs() < 1e-14);
        }
    }
}
