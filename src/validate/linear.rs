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

/// H_x(Omega) as (modulus, argument): the DTE per unit STE of one harmonic at Omega (eq. 13),
/// (1 + 2 i zeta W) / (1 - W^2 + 2 i zeta W).
fn dte_response(zeta: f64, omega: f64) -> (f64, f64) {
    let c = 2.0 * zeta * omega;
    (
        dte_gain(zeta, omega),
        c.atan2(1.0) - c.atan2(1.0 - omega * omega),
    )
}

/// Samples per period of the multi-harmonic peak-to-peak (each extreme refined by a parabola).
const PP_SAMPLES: usize = 256;

/// Peak-to-peak DTE in micrometres in contact for an STE of several harmonics,
/// e(t) = sum_j e_j sin(j W t + phi_j), given as (j, e_j in um, phi_j): eq. 3a is linear in
/// contact, so by superposition of eq. 13 x(t) = sum_j |H_x(j W)| e_j sin(j W t + phi_j +
/// arg H_x(j W)). Its pp is taken over 256 samples of a period, each extreme refined by the
/// parabola through its neighbours (relative error ~1e-6 for 5 harmonics). One harmonic gives
/// [`dte_pp_um`] exactly.
pub fn dte_pp_um_harmonics(ste: &[(u32, f64, f64)], zeta: f64, omega: f64) -> f64 {
    if let [(1, e, _)] = ste {
        return dte_pp_um(*e, zeta, omega);
    }
    let terms: Vec<(f64, f64, f64)> = ste
        .iter()
        .map(|&(j, e, phi)| {
            let (g, arg) = dte_response(zeta, j as f64 * omega);
            (j as f64, e * g, phi + arg)
        })
        .collect();
    let n = PP_SAMPLES;
    let y: Vec<f64> = (0..n)
        .map(|i| {
            let th = 2.0 * std::f64::consts::PI * i as f64 / n as f64;
            terms.iter().map(|(j, a, p)| a * (j * th + p).sin()).sum()
        })
        .collect();
    let refine = |i: usize| {
        let (a, b, c) = (y[(i + n - 1) % n], y[i], y[(i + 1) % n]);
        let curv = a - 2.0 * b + c;
        if curv.abs() > 1e-300 {
            b - (c - a).powi(2) / (8.0 * curv)
        } else {
            b
        }
    };
    let imax = (0..n).max_by(|&i, &j| y[i].total_cmp(&y[j])).unwrap_or(0);
    let imin = (0..n).min_by(|&i, &j| y[i].total_cmp(&y[j])).unwrap_or(0);
    refine(imax) - refine(imin)
}

/// True when the linear solution for an STE of several harmonics (j, F_ahj dimensionless)
/// keeps the teeth in contact by the triangle-inequality bound on the mesh force:
/// 1 + sum_j F_ahj (j W)^2 |H_x(j W)| / F_m < 2 (sufficient; [`stays_in_contact`] for one).
pub fn stays_in_contact_harmonics(
    mean_force: f64,
    ste: &[(u32, f64)],
    zeta: f64,
    omega: f64,
) -> bool {
    let excess: f64 = ste
        .iter()
        .map(|&(j, a)| load_factor_max(mean_force, a, zeta, j as f64 * omega) - 1.0)
        .sum();
    1.0 + excess < 2.0
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

    /// The multi-harmonic closed form agrees with the exact simulation of an STE with three
    /// harmonics in contact, and reduces to the one-harmonic form.
    #[test]
    fn multi_harmonic_closed_form_matches_simulation() {
        let (fm, zeta, b) = (3.0, 0.04, 50.0);
        let ste_um = [(1u32, 0.6, -0.5), (2, 0.35, -2.6), (3, 0.2, 2.7)];
        for om in [0.3, 0.45, 0.8, 1.2] {
            let m = GearPair {
                ste: ste_um
                    .iter()
                    .map(|&(j, e, phi)| crate::model::Term {
                        order: j,
                        amplitude: e / b,
                        phase: phi,
                    })
                    .collect(),
                ..GearPair::paper(fm, 0.0, zeta, om).unwrap()
            }
            .validated()
            .unwrap();
            let s = steady_state(
                &ExactFlow::new(&m).unwrap(),
                [1.0 + fm, 0.0],
                &SteadyOptions::default(),
            )
            .unwrap();
            let closed = dte_pp_um_harmonics(&ste_um, zeta, om);
            assert!(
                (b * s.dte_pp - closed).abs() < 1e-4 * closed,
                "Omega {om}: simulated {} um, closed form {closed} um",
                b * s.dte_pp
            );
            let amps: Vec<(u32, f64)> = ste_um.iter().map(|t| (t.0, t.1 / b)).collect();
            assert!(stays_in_contact_harmonics(fm, &amps, zeta, om));
        }
        assert_eq!(
            dte_pp_um_harmonics(&[(1, 0.7, 1.0)], 0.05, 0.9),
            dte_pp_um(0.7, 0.05, 0.9)
        );
    }
}
