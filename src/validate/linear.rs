//! Closed-form responses of eq. 3a while the teeth stay in contact (eq. 13): the design-load
//! Munro curve and the contact part of Kubo's curve are fitted with these, and the fitted model
//! is then checked by simulation for tooth separation.

/// |H_x(Omega)|: amplitude of the dynamic transmission error x = q + e/b per unit STE amplitude,
/// (1 + 2 i zeta W) / (1 - W^2 + 2 i zeta W), from eq. 13 with x = q + F_ah sin(W t).
pub fn dte_gain(zeta: f64, omega: f64) -> f64 {
    let num = 1.0 + (2.0 * zeta * omega).powi(2);
    let den = (1.0 - omega * omega).powi(2) + (2.0 * zeta * omega).powi(2);
    (num / den).sqrt()
}

/// Peak-to-peak DTE in micrometres for an STE amplitude `ste_um` in contact: 2 e |H_x|.
pub fn dte_pp_um(ste_um: f64, zeta: f64, omega: f64) -> f64 {
    2.0 * ste_um * dte_gain(zeta, omega)
}

/// Largest dynamic load factor in contact: D_L = 1 + F_ah W^2 |1 + 2 i zeta W| / |1 - W^2 + 2 i zeta W| / F_m
/// (the mesh force 2 zeta q' + q - 1 is F_m plus the harmonic response to F_ah W^2 sin W t).
pub fn load_factor_max(mean_force: f64, ste_amplitude: f64, zeta: f64, omega: f64) -> f64 {
    1.0 + ste_amplitude * omega * omega * dte_gain(zeta, omega) / mean_force
}

/// True when the linear solution keeps the teeth in contact: mesh force amplitude below F_m.
pub fn stays_in_contact(mean_force: f64, ste_amplitude: f64, zeta: f64, omega: f64) -> bool {
    load_factor_max(mean_force, ste_amplitude, zeta, omega) < 2.0
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::GearPair;
    use crate::sim::{steady_state, ExactFlow, SteadyOptions};

    /// The closed forms agree with the exact simulation in the linear regime.
    #[test]
    fn closed_forms_match_simulation() {
        for om in [0.4, 0.9, 1.3] {
            let (fm, fah, zeta) = (2.0, 0.02, 0.05);
            let m = GearPair::paper(fm, fah, zeta, om).unwrap();
            let s = steady_state(
                &ExactFlow::new(&m).unwrap(),
                [1.0 + fm, 0.0],
                &SteadyOptions::default(),
            )
            .unwrap();
            assert!((s.dte_pp - 2.0 * fah * dte_gain(zeta, om)).abs() < 1e-9);
            let dl = load_factor_max(fm, fah, zeta, om);
            assert!(
                (s.dl_max.unwrap() - dl).abs() < 1e-8,
                "{} vs {dl}",
                s.dl_max.unwrap()
            );
        }
    }
}
