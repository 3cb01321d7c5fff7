//! Stability of a harmonic balance solution: Floquet multipliers of the variational equation
//!
//! z'' + 2 zeta z' + k(t) f'(q_hb(t)) z = 0
//!
//! (eq. 3a linearised about the harmonic balance approximation q_hb) over one orbit period
//! nu 2 pi / Omega. f' is 1 in contact and 0 in the gap (eq. 3c), so the period splits at the
//! crossings of q_hb = +-1 into intervals with a smooth coefficient. With k = 1 each interval is
//! a constant-coefficient system whose transition matrix is a closed-form exponential (exact);
//! with a time-varying k(t) each interval is integrated by fixed-step RK4.

use super::aft_series::{boundary_crossings, eval_theta};
use crate::model::GearPair;
use nalgebra::Matrix2;
use std::f64::consts::TAU;

/// Monodromy matrix of the variational equation about the series `coeffs` (orbit phase
/// theta = Omega t / nu), mapping (z, z') at t = 0 to t = nu 2 pi / Omega.
pub(crate) fn monodromy(model: &GearPair, coeffs: &[f64], omega: f64, nu: u32) -> Matrix2<f64> {
    let to_t = nu as f64 / omega;
    let mut cuts = vec![0.0];
    cuts.extend(
        boundary_crossings(coeffs)
            .into_iter()
            .filter(|&c| c > 0.0 && c < TAU),
    );
    cuts.push(TAU);
    let varying = model.has_stiffness_variation();
    let mut phi = Matrix2::identity();
    for w in cuts.windows(2) {
        let (a, b) = (w[0], w[1]);
        if b <= a {
            continue;
        }
        let q_mid = eval_theta(coeffs, 0.5 * (a + b))[0];
        let kappa = if q_mid.abs() > 1.0 { 1.0 } else { 0.0 };
        let (ta, tb) = (a * to_t, b * to_t);
        let step = if varying && kappa != 0.0 {
            rk4_interval(model, omega, model.zeta, ta, tb)
        } else {
            constant_exp(kappa, model.zeta, tb - ta)
        };
        phi = step * phi;
    }
    phi
}

/// exp(A h) for A = [[0, 1], [-s, -2 zeta]] by Cayley-Hamilton: with mu = -zeta and
/// delta^2 = zeta^2 - s, exp(A h) = e^{mu h} (C I + S (A - mu I)), C = cosh(delta h),
/// S = sinh(delta h) / delta (circular functions when delta^2 < 0).
fn constant_exp(s: f64, zeta: f64, h: f64) -> Matrix2<f64> {
    let d2 = zeta * zeta - s;
    let (c, sn) = if d2 > 0.0 {
        let d = d2.sqrt();
        ((d * h).cosh(), (d * h).sinh() / d)
    } else if d2 < 0.0 {
        let w = (-d2).sqrt();
        ((w * h).cos(), (w * h).sin() / w)
    } else {
        (1.0, h)
    };
    let n = Matrix2::new(zeta, 1.0, -s, -zeta);
    (-zeta * h).exp() * (Matrix2::identity() * c + n * sn)
}

/// Largest RK4 step, short against the free oscillation (period ~ 2 pi) and the stiffness
/// harmonics: the error of the multipliers is then far below the harmonic-balance truncation.
const RK4_STEPS_PER_UNIT_TIME: f64 = 50.0;

/// Transition matrix over [ta, tb] of z'' + 2 zeta z' + k(t) z = 0 by fixed-step RK4.
fn rk4_interval(model: &GearPair, omega: f64, zeta: f64, ta: f64, tb: f64) -> Matrix2<f64> {
    let max_order = model
        .stiffness
        .iter()
        .map(|t| t.order)
        .max()
        .unwrap_or(1)
        .max(1) as f64;
    let per_unit = RK4_STEPS_PER_UNIT_TIME * (max_order * omega).max(1.0);
    let n = ((tb - ta) * per_unit).ceil().max(1.0) as usize;
    let h = (tb - ta) / n as f64;
    let k = |t: f64| {
        1.0 + model
            .stiffness
            .iter()
            .map(|s| s.amplitude * (s.order as f64 * omega * t + s.phase).cos())
            .sum::<f64>()
    };
    let a = |t: f64| Matrix2::new(0.0, 1.0, -k(t), -2.0 * zeta);
    let mut phi = Matrix2::identity();
    for i in 0..n {
        let t = ta + i as f64 * h;
        let (a0, a1, a2) = (a(t), a(t + 0.5 * h), a(t + h));
        let k1 = a0 * phi;
        let k2 = a1 * (phi + 0.5 * h * k1);
        let k3 = a1 * (phi + 0.5 * h * k2);
        let k4 = a2 * (phi + h * k3);
        phi += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
    }
    phi
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Term;

    /// In permanent contact (q > 1) with k = 1 the multipliers have modulus e^{-zeta T}.
    #[test]
    fn linear_multipliers() {
        let m = GearPair::paper(2.0, 0.05, 0.05, 0.8).unwrap();
        let phi = monodromy(&m, &[3.0, 0.1, 0.0], 0.8, 1);
        let det = phi.determinant();
        let expect = (-2.0 * 0.05 * TAU / 0.8).exp();
        assert!((det - expect).abs() < 1e-13);
        // The RK4 path (h = 0.02, global error ~ h^4 T / 120 ~ 1e-8) agrees with the exponential.
        let mut mv = m.clone();
        mv.stiffness.push(Term::new(1, 1e-300));
        let phi_rk = monodromy(&mv, &[3.0, 0.1, 0.0], 0.8, 1);
        assert!((phi_rk - phi).amax() < 1e-7, "{}", (phi_rk - phi).amax());
    }
}
