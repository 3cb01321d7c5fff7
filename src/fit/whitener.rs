//! The map from a fit's residuals to the vector whose sum of squares its least-squares steps
//! minimise: each residual divided by its scale sigma_i, turned into innovations along speed
//! where the errors are correlated ([`super::correlation`]), and multiplied by the square root
//! of its robust weight (Student-t errors, Lange, Little & Taylor 1989). With independent errors
//! this is the weighted least squares of r_i sqrt(w_i), w_i = robust weight / sigma_i^2
//! (generalized least squares in the correlated case, Carroll & Ruppert 1988, Sec. 2.3).

use super::correlation::{Axis, Correlation};
use nalgebra::DMatrix;

/// See the module's notes.
#[derive(Clone, Debug)]
pub struct Whitener {
    scales: Vec<f64>,
    /// Robust weight of each innovation (1 for Gaussian errors).
    robust: Vec<f64>,
    axis: Option<Axis>,
    length: f64,
}

impl Whitener {
    /// Scales `scales`, robust weights `robust`, and the errors' correlation (`axis`,
    /// `length`; None or length 0: independent).
    pub fn new(scales: Vec<f64>, robust: Vec<f64>, axis: Option<&Axis>, length: f64) -> Whitener {
        Whitener {
            scales,
            robust,
            axis: axis.filter(|_| length > 0.0).cloned(),
            length,
        }
    }

    /// Independent errors of scales `scales`, unit robust weights.
    pub fn independent(scales: Vec<f64>) -> Whitener {
        Whitener::unit(scales, None, 0.0)
    }

    /// Unit robust weights (Gaussian errors): the map whose innovations the likelihood, the
    /// Fisher information and the diagnostics read.
    pub fn unit(scales: Vec<f64>, axis: Option<&Axis>, length: f64) -> Whitener {
        let n = scales.len();
        Whitener::new(scales, vec![1.0; n], axis, length)
    }

    fn correlation(&self) -> Option<Correlation<'_>> {
        self.axis.as_ref().map(|axis| Correlation {
            axis,
            length: self.length,
        })
    }

    /// The innovations of residuals `r`: r_i / sigma_i, decorrelated along speed (the
    /// standardized residuals themselves with independent errors).
    pub fn innovations(&self, r: &[f64]) -> Vec<f64> {
        let z: Vec<f64> = r.iter().zip(&self.scales).map(|(r, s)| r / s).collect();
        match self.correlation() {
            Some(c) => c.innovations(&z),
            None => z,
        }
    }

    /// The least-squares vector of residuals `r`: innovations times sqrt(robust weight).
    pub fn apply(&self, r: &[f64]) -> Vec<f64> {
        match self.correlation() {
            // The product r sqrt(w) of the weighted fit, w = robust / sigma^2, as it always was.
            None => r
                .iter()
                .zip(&self.scales)
                .zip(&self.robust)
                .map(|((r, s), u)| r * (u / (s * s)).sqrt())
                .collect(),
            Some(_) => self
                .innovations(r)
                .iter()
                .zip(&self.robust)
                .map(|(e, u)| e * u.sqrt())
                .collect(),
        }
    }

    /// [`Whitener::innovations`] of each column of `m` (a Jacobian of the model's values): the
    /// whitened Jacobian G, whose G'G is the Fisher information under Gaussian errors.
    pub fn innovations_of_columns(&self, m: &DMatrix<f64>) -> DMatrix<f64> {
        let mut g = m.clone();
        for (i, s) in self.scales.iter().enumerate() {
            g.row_mut(i).scale_mut(1.0 / s);
        }
        match self.correlation() {
            Some(c) => c.innovations_of_columns(&g),
            None => g,
        }
    }

    /// The inverse of [`Whitener::apply`] on each column of `m`: the model's Jacobian from the
    /// least-squares vector's.
    pub fn unapply_columns(&self, m: &DMatrix<f64>) -> DMatrix<f64> {
        let mut g = m.clone();
        for (i, u) in self.robust.iter().enumerate() {
            g.row_mut(i).scale_mut(1.0 / u.sqrt());
        }
        let mut g = match self.correlation() {
            Some(c) => c.correlate_columns(&g),
            None => g,
        };
        for (i, s) in self.scales.iter().enumerate() {
            g.row_mut(i).scale_mut(*s);
        }
        g
    }

    /// The weight robust / sigma^2 of each point (its weight in the fit with independent
    /// errors).
    pub fn weights(&self) -> Vec<f64> {
        self.scales
            .iter()
            .zip(&self.robust)
            .map(|(s, u)| u / (s * s))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// With correlated errors, unapplying the applied columns gives them back, and the
    /// innovations of a column are the applied vector at unit robust weights.
    #[test]
    fn apply_and_unapply_are_inverse() {
        let axis = Axis::new(vec![0, 0, 1, 0, 1], vec![0.0, 20.0, 5.0, 45.0, 9.0]).unwrap();
        let w = Whitener::new(
            vec![0.5, 1.0, 2.0, 0.7, 1.3],
            vec![1.0, 0.4, 0.9, 1.0, 0.2],
            Some(&axis),
            30.0,
        );
        let m = DMatrix::from_fn(5, 2, |i, j| (i as f64 + 1.0) * (j as f64 - 0.5));
        let mut applied = m.clone();
        for j in 0..2 {
            let col: Vec<f64> = m.column(j).iter().copied().collect();
            for (i, v) in w.apply(&col).iter().enumerate() {
                applied[(i, j)] = *v;
            }
        }
        let back = w.unapply_columns(&applied);
        assert!((back - &m).norm() < 1e-12);
        let unit = Whitener::new(
            vec![0.5, 1.0, 2.0, 0.7, 1.3],
            vec![1.0; 5],
            Some(&axis),
            30.0,
        );
        let col: Vec<f64> = m.column(1).iter().copied().collect();
        let g = unit.innovations_of_columns(&m);
        for (i, v) in unit.apply(&col).iter().enumerate() {
            assert!((g[(i, 1)] - v).abs() < 1e-12);
        }
    }
}
