//! Newton's method on the multi-harmonic balance equations R(x, Omega) = 0 at a fixed frequency,
//! with the exact AFT Jacobian, nalgebra LU solves and a backtracking line search (the sampled
//! residual is piecewise linear in x, so a full step can overshoot a change of contact pattern).

use super::aft::{Aft, AftOptions};
use super::aft_point::HbPoint;
use crate::error::{GearError, Result};
use crate::model::GearPair;
use nalgebra::DVector;

/// A model with its AFT evaluator, shared by the fixed-frequency solver and the continuation.
pub(crate) struct Context {
    pub(crate) aft: Aft,
    pub(crate) model: GearPair,
    pub(crate) opts: AftOptions,
}

impl Context {
    /// Validate the model and options and plan the transforms.
    pub(crate) fn new(model: &GearPair, opts: &AftOptions) -> Result<Self> {
        let model = model.clone().validated()?;
        Ok(Context {
            aft: Aft::new(&model, opts)?,
            model,
            opts: opts.clone(),
        })
    }

    /// Absolute residual tolerance at Omega.
    pub(crate) fn tolerance(&self, omega: f64) -> f64 {
        self.opts.tolerance * self.aft.scale(omega)
    }

    /// Check a coefficient vector supplied by the caller.
    pub(crate) fn check_coeffs(&self, x: &[f64]) -> Result<()> {
        if x.len() != self.aft.dim() {
            return Err(GearError::param(
                "guess",
                x.len() as f64,
                "the coefficient vector must have 2H + 1 entries (H = AftOptions::harmonics)",
            ));
        }
        if let Some(v) = x.iter().find(|v| !v.is_finite()) {
            return Err(GearError::param("guess", *v, "coefficients must be finite"));
        }
        Ok(())
    }

    /// Newton iteration at fixed Omega from `x0`; returns the solution and its residual max |R|.
    pub(crate) fn newton(&mut self, x0: &[f64], omega: f64) -> Result<(Vec<f64>, f64)> {
        let tol = self.tolerance(omega);
        let mut x = DVector::from_column_slice(x0);
        let mut lin = self.aft.linearise(x.as_slice(), omega)?;
        let mut rn = lin.r.amax();
        for _ in 0..self.opts.max_iterations {
            if rn <= tol {
                return Ok((x.as_slice().to_vec(), rn));
            }
            let dx = lin
                .jx
                .clone()
                .lu()
                .solve(&(-&lin.r))
                .filter(|d| d.iter().all(|v| v.is_finite()))
                .ok_or_else(|| {
                    GearError::Numerical(format!(
                        "singular harmonic balance Jacobian at Omega = {omega}"
                    ))
                })?;
            // Backtracking: halve the step until the residual decreases (at most 1/64 of it).
            let mut lambda = 1.0;
            let mut trial = &x + &dx;
            loop {
                let rt = self.aft.residual(trial.as_slice(), omega)?.amax();
                if rt < (1.0 - 1e-4 * lambda) * rn || lambda <= 1.0 / 64.0 {
                    break;
                }
                lambda *= 0.5;
                trial = &x + lambda * &dx;
            }
            x = trial;
            lin = self.aft.linearise(x.as_slice(), omega)?;
            rn = lin.r.amax();
            if !rn.is_finite() {
                break;
            }
        }
        if rn <= tol {
            return Ok((x.as_slice().to_vec(), rn));
        }
        Err(GearError::Numerical(format!(
            "harmonic balance Newton did not converge at Omega = {omega}: residual {rn:.3e} > {tol:.3e} after {} iterations",
            self.opts.max_iterations
        )))
    }

    /// Build the solution record for converged coefficients.
    pub(crate) fn point(&self, x: Vec<f64>, omega: f64, residual: f64) -> HbPoint {
        HbPoint::build(
            &self.model,
            x,
            omega,
            self.opts.subharmonic,
            residual,
            self.opts.stability,
        )
    }
}

/// Solve the multi-harmonic balance equations of eq. 3a (generalised: several STE and torque
/// harmonics of eq. 20, mesh stiffness k(t)) at the model's frequency `model.omega`, by Newton's
/// method with the exact AFT Jacobian from the coefficient vector `guess`
/// (`[a_0, a_1, b_1, ..., a_H, b_H]`, see [`super::linear_guess`] and [`super::guess_from_state`]).
/// Fails with [`GearError::Numerical`] when Newton does not converge.
pub fn solve_at(model: &GearPair, guess: &[f64], opts: &AftOptions) -> Result<HbPoint> {
    let mut ctx = Context::new(model, opts)?;
    ctx.check_coeffs(guess)?;
    let omega = ctx.model.omega;
    let (x, res) = ctx.newton(guess, omega)?;
    Ok(ctx.point(x, omega, res))
}
