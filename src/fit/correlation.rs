//! Errors correlated along speed within a curve (docs/correlated-errors.md): the standardized
//! errors z_i = e_i / sigma_i of one curve follow a stationary Ornstein-Uhlenbeck process in
//! speed, corr(z_i, z_j) = exp(-|s_i - s_j| / L), and different curves are independent. It is
//! Markov in speed, so with the points of a curve in increasing speed and
//! phi_k = exp(-(s_k - s_{k-1}) / L) the innovations
//!
//! ```text
//! e_1 = z_1,    e_k = (z_k - phi_k z_{k-1}) / sqrt(1 - phi_k^2)
//! ```
//!
//! are independent with unit variance, and the log-likelihood is that of the e_k less
//! 1/2 sum log(1 - phi_k^2) (the exact AR(1) likelihood, Box, Jenkins & Reinsel, Time Series
//! Analysis, Sec. 7.1, on an uneven grid). L = 0 is independent errors.

use crate::error::{GearError, Result};
use nalgebra::DMatrix;
use statrs::distribution::{ChiSquared, ContinuousCDF};

/// Where each point of a fit lies: its curve (one load's pp-DTE curve, one Kubo envelope) and
/// its position along the speed axis (rpm), with each point's predecessor in its curve.
#[derive(Clone, Debug, PartialEq)]
pub struct Axis {
    curve: Vec<usize>,
    position: Vec<f64>,
    /// The point before each point in its curve (in increasing speed) and the gap to it.
    previous: Vec<Option<(usize, f64)>>,
    /// Points in curve order, each curve in increasing speed: predecessors come first.
    order: Vec<usize>,
}

impl Axis {
    /// The axis of points in curves `curve` at speeds `position` (rpm). Two points of one curve
    /// at the same speed are refused: their errors would be one error (correlation 1).
    pub fn new(curve: Vec<usize>, position: Vec<f64>) -> Result<Axis> {
        if curve.len() != position.len() {
            return Err(GearError::Numerical(
                "the speed axis has another length than its curve labels".into(),
            ));
        }
        if let Some(s) = position.iter().find(|s| !s.is_finite()) {
            return Err(GearError::Numerical(format!(
                "a speed of the correlation axis is not finite ({s})"
            )));
        }
        let mut order: Vec<usize> = (0..curve.len()).collect();
        order.sort_by(|&a, &b| {
            curve[a]
                .cmp(&curve[b])
                .then(position[a].total_cmp(&position[b]))
        });
        let mut previous = vec![None; curve.len()];
        for w in order.windows(2) {
            let (j, k) = (w[0], w[1]);
            if curve[j] == curve[k] {
                let gap = position[k] - position[j];
                if gap <= 0.0 {
                    return Err(GearError::Numerical(format!(
                        "two points of one curve at the same speed ({} rpm): errors correlated \
                         along speed need distinct speeds within a curve",
                        position[k]
                    )));
                }
                previous[k] = Some((j, gap));
            }
        }
        Ok(Axis {
            curve,
            position,
            previous,
            order,
        })
    }

    pub fn len(&self) -> usize {
        self.curve.len()
    }

    pub fn is_empty(&self) -> bool {
        self.curve.is_empty()
    }

    /// The median gap between neighbouring points of a curve (rpm); None with no such pair.
    pub fn median_step(&self) -> Option<f64> {
        let mut gaps: Vec<f64> = self.previous.iter().flatten().map(|p| p.1).collect();
        if gaps.is_empty() {
            return None;
        }
        gaps.sort_by(f64::total_cmp);
        Some(gaps[gaps.len() / 2])
    }

    /// The least and the largest extent of the axis a correlation length can be told on: the
    /// least gap, and the widest curve's span.
    fn length_range(&self) -> Option<(f64, f64)> {
        let least = self
            .previous
            .iter()
            .flatten()
            .map(|p| p.1)
            .fold(f64::INFINITY, f64::min);
        if !least.is_finite() {
            return None;
        }
        let span = self
            .curves()
            .iter()
            .map(|c| self.position[c[c.len() - 1]] - self.position[c[0]])
            .fold(0.0, f64::max);
        Some((least, span.max(least)))
    }

    /// The widest curve's extent in speed (rpm).
    pub fn span(&self) -> f64 {
        self.length_range().map_or(0.0, |(_, span)| span)
    }

    /// The points of each curve in increasing speed, curves in order of their labels.
    pub fn curves(&self) -> Vec<Vec<usize>> {
        let mut out: Vec<Vec<usize>> = Vec::new();
        for &i in &self.order {
            match out.last_mut() {
                Some(c) if self.curve[c[0]] == self.curve[i] => c.push(i),
                _ => out.push(vec![i]),
            }
        }
        out
    }

    /// The curve label of each curve of [`Axis::curves`].
    pub fn curve_label(&self, point: usize) -> usize {
        self.curve[point]
    }

    /// Point k's predecessor j, the lag-one correlation phi = exp(-gap / length) of their
    /// errors and 1 - phi^2 (as -expm1(-2 gap / length), exact where phi is near 1); None for a
    /// curve's first point and for independent errors.
    fn phi(&self, k: usize, length: f64) -> Option<(usize, f64, f64)> {
        if length <= 0.0 {
            return None;
        }
        self.previous[k].map(|(j, gap)| {
            let x = gap / length;
            (j, (-x).exp(), -(-2.0 * x).exp_m1())
        })
    }
}

/// The correlation of one noise model on one axis: the map from standardized errors z to
/// innovations, and back.
#[derive(Clone, Copy, Debug)]
pub struct Correlation<'a> {
    pub axis: &'a Axis,
    /// Correlation length (rpm); 0 for independent errors.
    pub length: f64,
}

impl Correlation<'_> {
    /// The innovations e of standardized errors `z` (docs/correlated-errors.md).
    pub fn innovations(&self, z: &[f64]) -> Vec<f64> {
        (0..z.len())
            .map(|k| match self.axis.phi(k, self.length) {
                Some((j, phi, q)) => (z[k] - phi * z[j]) / q.sqrt(),
                None => z[k],
            })
            .collect()
    }

    /// The standardized errors z whose innovations are `e` (the inverse of
    /// [`Correlation::innovations`]): correlated draws from independent ones.
    pub fn correlate(&self, e: &[f64]) -> Vec<f64> {
        let mut z = vec![0.0; e.len()];
        for &k in &self.axis.order {
            z[k] = match self.axis.phi(k, self.length) {
                Some((j, phi, q)) => phi * z[j] + q.sqrt() * e[k],
                None => e[k],
            };
        }
        z
    }

    /// 1/2 sum log(1 - phi_k^2): the log-determinant part of -log L beyond the innovations'.
    pub fn half_log_det(&self) -> f64 {
        (0..self.axis.len())
            .filter_map(|k| self.axis.phi(k, self.length))
            .map(|(_, _, q)| 0.5 * q.ln())
            .sum()
    }

    /// [`Correlation::innovations`] applied to every column of `m`, whose rows are already
    /// standardized (divided by their scale).
    pub fn innovations_of_columns(&self, m: &DMatrix<f64>) -> DMatrix<f64> {
        let mut out = m.clone();
        for k in 0..m.nrows() {
            if let Some((j, phi, q)) = self.axis.phi(k, self.length) {
                let c = 1.0 / q.sqrt();
                for col in 0..m.ncols() {
                    out[(k, col)] = (m[(k, col)] - phi * m[(j, col)]) * c;
                }
            }
        }
        out
    }

    /// [`Correlation::correlate`] applied to every column of `m`.
    pub fn correlate_columns(&self, m: &DMatrix<f64>) -> DMatrix<f64> {
        let mut out = m.clone();
        for &k in &self.axis.order {
            if let Some((j, phi, q)) = self.axis.phi(k, self.length) {
                let c = q.sqrt();
                for col in 0..m.ncols() {
                    out[(k, col)] = phi * out[(j, col)] + c * m[(k, col)];
                }
            }
        }
        out
    }
}

/// Shortest and longest correlation length (rpm) the fit considers on an axis: a tenth of its
/// least gap (below that neighbouring errors correlate by less than e^-10, independent to every
/// purpose) and ten times its widest curve (beyond that a curve's error is one offset).
pub fn length_bounds(axis: &Axis) -> Option<(f64, f64)> {
    axis.length_range().map(|(a, b)| (0.1 * a, 10.0 * b))
}

/// The residual-correlation diagnostic of one curve (docs/correlated-errors.md).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct CurveCorrelation {
    /// The curve's label on the axis (the fit's order of curves).
    pub curve: usize,
    pub points: usize,
    /// Lag-one correlation of the standardized residuals r_i / sigma_i in speed order.
    pub lag1: f64,
    /// Ljung-Box statistic of the innovations under the fitted noise model, its lags, its
    /// degrees of freedom and p-value (None with fewer than 6 points).
    pub ljung_box: Option<(f64, usize, f64, f64)>,
}

/// Sample autocorrelations r_1..r_m of a series about its mean.
fn autocorrelations(x: &[f64], m: usize) -> Vec<f64> {
    let n = x.len() as f64;
    let mean = x.iter().sum::<f64>() / n;
    let d: Vec<f64> = x.iter().map(|v| v - mean).collect();
    let c0: f64 = d.iter().map(|v| v * v).sum();
    (1..=m)
        .map(|k| {
            if c0 <= 0.0 || k >= d.len() {
                return 0.0;
            }
            d.iter().zip(&d[k..]).map(|(a, b)| a * b).sum::<f64>() / c0
        })
        .collect()
}

/// Ljung-Box Q on m = min(10, n / 5) lags (Ljung & Box 1978), referred to chi^2 with m - fitted
/// degrees of freedom (at least 1; `fitted` may be a fraction, a curve's share of a correlation
/// estimated on several): (Q, m, dof, p).
pub fn ljung_box(x: &[f64], fitted: f64) -> Option<(f64, usize, f64, f64)> {
    let n = x.len();
    let m = (n / 5).min(10);
    if m < 1 || n < 6 {
        return None;
    }
    let r = autocorrelations(x, m);
    let nf = n as f64;
    let q = nf
        * (nf + 2.0)
        * r.iter()
            .enumerate()
            .map(|(k, rk)| rk * rk / (nf - (k + 1) as f64))
            .sum::<f64>();
    let dof = (m as f64 - fitted).max(1.0);
    let p = ChiSquared::new(dof).ok()?.sf(q);
    Some((q, m, dof, p))
}

/// The diagnostic of every curve of `axis`: lag-one correlations of the standardized
/// residuals `z`, Ljung-Box tests of the innovations `e` (`estimated`: the correlation length
/// was estimated, on all curves together, so each curve's test loses its share of a degree of
/// freedom, its points over all points).
pub fn curve_correlations(
    axis: &Axis,
    z: &[f64],
    e: &[f64],
    estimated: bool,
) -> Vec<CurveCorrelation> {
    let total = axis.len().max(1) as f64;
    axis.curves()
        .iter()
        .map(|c| {
            let fitted = if estimated {
                c.len() as f64 / total
            } else {
                0.0
            };
            let zc: Vec<f64> = c.iter().map(|&i| z[i]).collect();
            let ec: Vec<f64> = c.iter().map(|&i| e[i]).collect();
            CurveCorrelation {
                curve: axis.curve_label(c[0]),
                points: c.len(),
                lag1: if zc.len() > 2 {
                    autocorrelations(&zc, 1)[0]
                } else {
                    0.0
                },
                ljung_box: ljung_box(&ec, fitted),
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::numeric::Rng;

    /// Two curves on uneven grids, given out of order.
    fn axis() -> Axis {
        Axis::new(
            vec![1, 0, 0, 1, 0, 1, 0],
            vec![100.0, 30.0, 0.0, 0.0, 10.0, 35.0, 50.0],
        )
        .unwrap()
    }

    /// The innovations and their inverse undo each other, and with the exponential kernel's
    /// covariance R (formed densely) the likelihood by innovations equals the dense
    /// multivariate normal's: e'e = z' R^-1 z and sum log(1 - phi^2) = log det R.
    #[test]
    fn innovations_are_the_exact_factorization_of_the_kernel() {
        let a = axis();
        let c = Correlation {
            axis: &a,
            length: 25.0,
        };
        let z = vec![0.3, -1.2, 0.8, 2.0, -0.4, 0.1, 1.1];
        let e = c.innovations(&z);
        let back = c.correlate(&e);
        for (x, y) in z.iter().zip(&back) {
            assert!((x - y).abs() < 1e-12);
        }
        let pos: [f64; 7] = [100.0, 30.0, 0.0, 0.0, 10.0, 35.0, 50.0];
        let cur = [1, 0, 0, 1, 0, 1, 0];
        let r = DMatrix::from_fn(7, 7, |i, j| {
            if cur[i] == cur[j] {
                (-(pos[i] - pos[j]).abs() / 25.0).exp()
            } else {
                0.0
            }
        });
        let zv = nalgebra::DVector::from_vec(z.clone());
        let quad = (zv.transpose() * r.clone().try_inverse().unwrap() * &zv)[(0, 0)];
        let ee: f64 = e.iter().map(|v| v * v).sum();
        assert!((quad - ee).abs() < 1e-9, "{quad} {ee}");
        let log_det = r.determinant().ln();
        assert!((log_det - 2.0 * c.half_log_det()).abs() < 1e-9);
    }

    /// At length 0 the innovations are the standardized errors themselves.
    #[test]
    fn zero_length_is_independence() {
        let a = axis();
        let c = Correlation {
            axis: &a,
            length: 0.0,
        };
        let z = vec![0.3, -1.2, 0.8, 2.0, -0.4, 0.1, 1.1];
        assert_eq!(c.innovations(&z), z);
        assert_eq!(c.half_log_det(), 0.0);
    }

    /// Two points of one curve at one speed are refused; two curves may share speeds.
    #[test]
    fn a_repeated_speed_within_a_curve_is_refused() {
        assert!(Axis::new(vec![0, 0], vec![5.0, 5.0]).is_err());
        assert!(Axis::new(vec![0, 1], vec![5.0, 5.0]).is_ok());
    }

    /// White noise: the Ljung-Box p-value is uniform, so over 400 series of 100 points about
    /// 5% fall below 0.05 (binomial sd 1.1%: the band is 4 sd); an AR(1) series of rho 0.6
    /// is caught every time, and its lag-one correlation is 0.6 within 0.25 (3 standard errors
    /// of a lag-one correlation on 100 points, sqrt((1 - 0.36) / 100) = 0.08).
    #[test]
    fn ljung_box_is_calibrated_on_white_noise_and_catches_ar1() {
        let mut rng = Rng::new(17);
        let mut below = 0;
        for _ in 0..400 {
            let x: Vec<f64> = (0..100).map(|_| rng.normal()).collect();
            if ljung_box(&x, 0.0).unwrap().3 < 0.05 {
                below += 1;
            }
        }
        assert!((4..=36).contains(&below), "{below} of 400");
        let a = Axis::new(vec![0; 100], (0..100).map(|i| 10.0 * i as f64).collect()).unwrap();
        // rho 0.6 on a 10 rpm grid.
        let c = Correlation {
            axis: &a,
            length: -10.0 / 0.6_f64.ln(),
        };
        for _ in 0..20 {
            let e: Vec<f64> = (0..100).map(|_| rng.normal()).collect();
            let z = c.correlate(&e);
            assert!(ljung_box(&z, 0.0).unwrap().3 < 1e-3);
            let d = &curve_correlations(&a, &z, &e, true)[0];
            assert!((d.lag1 - 0.6).abs() < 0.25, "{}", d.lag1);
        }
    }
}
