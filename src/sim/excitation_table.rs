//! The forcing F(s) and mesh stiffness k(s) of eq. 20 for the Runge-Kutta right-hand side,
//! tabulated once per flow.
//!
//! DOP853 evaluates them twelve times a step, and with one `sin`/`cos` call per term
//! ([`GearPair::forcing`], [`GearPair::stiffness_at`]) the standard library's trigonometry was
//! 38% of a `discover` run that refits a time-varying mesh stiffness (perf, `geardyn bench
//! --discover-refit`). Here one reduction-free `sin_cos` of the fundamental's angle serves every
//! order: sin((j+1) theta) and cos((j+1) theta) follow from the j-th by the angle-addition
//! recurrence, whose rounding grows about linearly with j (below 1e-14 for the 64 orders a
//! geometry excitation may carry, far under the integrator's tolerance); each term's phase is
//! folded into its (sin, cos) coefficients.

use crate::fast_math::sin_cos;
use crate::model::GearPair;

/// F(s) and k(s) of a [`GearPair`] as Fourier coefficients by order (index j - 1 for order j).
#[derive(Clone, Debug)]
pub(crate) struct ExcitationTable {
    omega: f64,
    mean_force: f64,
    /// (coefficient of sin j theta, coefficient of cos j theta) of F - F_m.
    forcing: Vec<(f64, f64)>,
    /// (coefficient of sin j theta, coefficient of cos j theta) of k - 1; empty when k = 1,
    /// which [`ExcitationTable::at`] then returns exactly.
    stiffness: Vec<(f64, f64)>,
}

impl ExcitationTable {
    /// The table of `model`: its combined STE and torque harmonics
    /// ([`GearPair::forcing_harmonics`]) and its stiffness terms eps_j cos(j theta + psi_j) =
    /// eps_j cos psi_j cos j theta - eps_j sin psi_j sin j theta.
    pub(crate) fn new(model: &GearPair) -> Self {
        let orders = model.max_order() as usize;
        let mut forcing = vec![(0.0, 0.0); orders];
        for h in model.forcing_harmonics() {
            let slot = &mut forcing[h.order as usize - 1];
            slot.0 += h.sin_coef;
            slot.1 += h.cos_coef;
        }
        let mut stiffness = vec![(0.0, 0.0); orders];
        for t in model.stiffness.iter().filter(|t| t.amplitude != 0.0) {
            let (s, c) = t.phase.sin_cos();
            let slot = &mut stiffness[t.order as usize - 1];
            slot.0 -= t.amplitude * s;
            slot.1 += t.amplitude * c;
        }
        // Drop trailing orders with nothing in them (max_order counts every kind of term).
        let used = |v: &[(f64, f64)]| v.iter().rposition(|&(a, b)| a != 0.0 || b != 0.0);
        forcing.truncate(used(&forcing).map_or(0, |k| k + 1));
        stiffness.truncate(used(&stiffness).map_or(0, |k| k + 1));
        ExcitationTable {
            omega: model.omega,
            mean_force: model.mean_force,
            forcing,
            stiffness,
        }
    }

    /// (F(s), k(s)) of eq. 20 at dimensionless time `s`.
    #[inline]
    pub(crate) fn at(&self, s: f64) -> (f64, f64) {
        let orders = self.forcing.len().max(self.stiffness.len());
        if orders == 0 {
            return (self.mean_force, 1.0);
        }
        let (s1, c1) = sin_cos(self.omega * s);
        let (mut sj, mut cj) = (s1, c1);
        let (mut f, mut k) = (self.mean_force, 1.0);
        for j in 0..orders {
            if let Some(&(a, b)) = self.forcing.get(j) {
                f += a * sj + b * cj;
            }
            if let Some(&(a, b)) = self.stiffness.get(j) {
                k += a * sj + b * cj;
            }
            (sj, cj) = (sj * c1 + cj * s1, cj * c1 - sj * s1);
        }
        (f, k)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Term;

    /// Against the model's own term-by-term evaluation (standard-library trigonometry) over
    /// several periods: a single order-1 model, and one with STE, torque and stiffness terms of
    /// mixed orders and phases up to order 64, as a geometry excitation carries.
    #[test]
    fn matches_the_models_term_by_term_evaluation() {
        let simple = GearPair::paper(0.1, 0.2, 0.02, 0.7).unwrap();
        let mut rich = GearPair::paper(0.4, 0.05, 0.03, 1.3).unwrap();
        rich.ste = (1..=64)
            .map(|j| Term {
                order: j,
                amplitude: 0.05 / j as f64,
                phase: 0.37 * j as f64,
            })
            .collect();
        rich.torque = vec![Term {
            order: 1,
            amplitude: 0.01,
            phase: -2.0,
        }];
        rich.stiffness = vec![
            Term {
                order: 1,
                amplitude: 0.2,
                phase: 1.1,
            },
            Term {
                order: 3,
                amplitude: 0.05,
                phase: -0.4,
            },
        ];
        for model in [simple, rich] {
            let table = ExcitationTable::new(&model);
            let scale = 1.0
                + model
                    .forcing_harmonics()
                    .iter()
                    .map(|h| h.sin_coef.abs() + h.cos_coef.abs())
                    .sum::<f64>();
            for i in 0..=4000 {
                let s = 3.0 * model.period() * i as f64 / 4000.0;
                let (f, k) = table.at(s);
                assert!((f - model.forcing(s)).abs() < 1e-13 * scale, "F at {s}");
                assert!((k - model.stiffness_at(s)).abs() < 1e-13, "k at {s}");
            }
        }
    }

    /// A model with no stiffness terms gets exactly 1, as the flow's constant-stiffness path
    /// did before the table.
    #[test]
    fn constant_stiffness_is_exactly_one() {
        let model = GearPair::paper(0.1, 0.2, 0.02, 0.7).unwrap();
        let table = ExcitationTable::new(&model);
        assert!((0..100).all(|i| table.at(0.37 * i as f64).1 == 1.0));
    }
}
