//! Fourier coefficients of the STE and mesh stiffness over one mesh period, in the conventions
//! of the model (design.md section 1, eq. 20 of the paper):
//!
//! ```text
//! e(t) - mean(e) = sum_j e_j sin(j Omega_h t + phi_hj),   F_ahj = e_j / b
//! k(t) / k_mean  = 1 + sum_j eps_j cos(j Omega_h t + psi_j)
//! ```
//!
//! with Omega_h t = 2 pi tau / p_b (t = 0 when a new pair enters contact). For samples f_i at
//! theta_i = 2 pi i / N, a_j = (2/N) sum f_i cos(j theta_i), b_j = (2/N) sum f_i sin(j theta_i)
//! (j < N/2); then e_j = sqrt(a_j^2 + b_j^2), phi_j = atan2(a_j, b_j) and, for k, eps_j =
//! sqrt(a_j^2 + b_j^2) / k_mean, psi_j = atan2(-b_j, a_j).

use super::ste::{mean, SteWaveform};
use crate::error::{GearError, Result};
use serde::Serialize;
use std::f64::consts::PI;

/// One harmonic order of the STE and of the mesh stiffness.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct MeshHarmonic {
    /// Order j (multiple of the mesh frequency).
    pub order: u32,
    /// STE amplitude e_j, um.
    pub ste_amplitude_um: f64,
    /// STE phase phi_hj of the sine form, radians.
    pub ste_phase_rad: f64,
    /// Relative stiffness amplitude eps_j (of k / k_mean).
    pub stiffness_eps: f64,
    /// Stiffness phase psi_j of the cosine form, radians.
    pub stiffness_phase_rad: f64,
}

/// Cosine and sine coefficients (a_j, b_j) of uniformly sampled one-period data, j = 1..=orders.
pub fn fourier(samples: &[f64], orders: u32) -> Vec<(f64, f64)> {
    let n = samples.len() as f64;
    (1..=orders)
        .map(|j| {
            samples
                .iter()
                .enumerate()
                .fold((0.0, 0.0), |(a, b), (i, &f)| {
                    let th = 2.0 * PI * j as f64 * i as f64 / n;
                    (a + f * th.cos(), b + f * th.sin())
                })
        })
        .map(|(a, b)| (2.0 * a / n, 2.0 * b / n))
        .collect()
}

/// The first `orders` harmonics of `w`'s STE and loaded mesh stiffness (orders < N/2).
pub fn mesh_harmonics(w: &SteWaveform, orders: u32) -> Result<Vec<MeshHarmonic>> {
    let n = w.ste_um.len();
    if orders == 0 || 2 * orders as usize >= n {
        return Err(GearError::param(
            "harmonics",
            orders as f64,
            "need 1 <= orders < samples / 2",
        ));
    }
    let k_mean = mean(&w.stiffness_n_per_um);
    let e = fourier(&w.ste_um, orders);
    let k = fourier(&w.stiffness_n_per_um, orders);
    Ok(e.iter()
        .zip(&k)
        .enumerate()
        .map(|(i, (&(ea, eb), &(ka, kb)))| MeshHarmonic {
            order: i as u32 + 1,
            ste_amplitude_um: ea.hypot(eb),
            ste_phase_rad: ea.atan2(eb),
            stiffness_eps: ka.hypot(kb) / k_mean,
            stiffness_phase_rad: (-kb).atan2(ka),
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn recovers_a_known_series_in_the_model_conventions() {
        let n = 64;
        let th = |i: usize| 2.0 * PI * i as f64 / n as f64;
        // e = 3 + 2 sin(th + 0.4) + 0.5 sin(3 th - 1.0); k = 10 (1 + 0.2 cos(th + 0.7))
        let ste: Vec<f64> = (0..n)
            .map(|i| 3.0 + 2.0 * (th(i) + 0.4).sin() + 0.5 * (3.0 * th(i) - 1.0).sin())
            .collect();
        let k: Vec<f64> = (0..n)
            .map(|i| 10.0 * (1.0 + 0.2 * (th(i) + 0.7).cos()))
            .collect();
        let w = SteWaveform {
            load_n: 1.0,
            position: (0..n).map(|i| i as f64 / n as f64).collect(),
            ste_um: ste,
            stiffness_n_per_um: k.clone(),
            geometric_stiffness_n_per_um: k,
            pairs: vec![],
        };
        let h = mesh_harmonics(&w, 3).unwrap();
        assert!((h[0].ste_amplitude_um - 2.0).abs() < 1e-12);
        assert!((h[0].ste_phase_rad - 0.4).abs() < 1e-12);
        assert!(h[1].ste_amplitude_um < 1e-12);
        assert!((h[2].ste_amplitude_um - 0.5).abs() < 1e-12);
        assert!((h[2].ste_phase_rad + 1.0).abs() < 1e-12);
        assert!((h[0].stiffness_eps - 0.2).abs() < 1e-12);
        assert!((h[0].stiffness_phase_rad - 0.7).abs() < 1e-12);
        assert!(mesh_harmonics(&w, 32).is_err());
    }
}
