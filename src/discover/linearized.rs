//! Test statistics of the discovery workflow and their parametric bootstrap under the fitted M0
//! (Davison & Hinkley 1997, ch. 4). Replicate data y* = f0 + sigma z are generated at the fitted
//! M0 curves; the refit of M0 to y* is linearised (the residual is projected off the span of the
//! M0 Jacobian, the Gauss-Newton step from the fitted parameters) and sigma is re-estimated from
//! y* exactly as from the data. The same function computes every statistic on the data and on
//! each replicate, so the Monte Carlo p-values are calibrated for the fit's degrees of freedom,
//! the noise estimate, the boundary of amplitude parameters and the non-smooth pp response.

use super::forward::CurvePrediction;
use super::stats::{noise_from_differences, runs_z};
use super::windows::{windows, Window};
use crate::validate::Rng;
use nalgebra::{DMatrix, DVector};
use rayon::prelude::*;

/// Everything fixed under the null: fitted M0 curves, mask, projections, probe curves.
#[derive(Clone)]
pub struct Linearized {
    /// M0 predictions per curve (um), every curve.
    pub f0: Vec<Vec<f64>>,
    pub mask: Vec<Vec<bool>>,
    /// Indices of the training curves (their masked points, in order, make the training rows).
    pub train: Vec<usize>,
    /// Orthonormal basis of the M0 Jacobian's column space on the training rows.
    pub q_train: DMatrix<f64>,
    /// Unit vector of each held-out curve's STE sensitivity on its masked points.
    pub q_held: Vec<(usize, DVector<f64>)>,
    /// Omega of each point (at the M0 omega_n).
    pub omega: Vec<Vec<f64>>,
    pub windows: Vec<Window>,
    /// Per candidate: projected probe curves f(theta0, delta_k) - f0 on the training rows (um).
    pub probes: Vec<Vec<DVector<f64>>>,
    /// Points whose residual is set to zero (kept rows, so the null distribution still applies):
    /// where a refitted model has a jump or a non-period-1 state that M0 did not have.
    pub zero: Option<Vec<Vec<bool>>>,
    /// Use this noise level instead of the difference estimate (stated noise).
    pub fixed_sigma: Option<f64>,
}

/// Statistics of one data set (observed or replicate).
#[derive(Clone, Debug)]
pub struct Statistics {
    pub sigma: f64,
    /// chi2 training, chi2 held-out, -runs z, then one energy per window (NaN if empty).
    pub detection: Vec<f64>,
    /// Per candidate: likelihood-ratio statistic (RSS0 - min_k RSS1_k) / sigma^2, and the index
    /// of the minimising probe.
    pub lr: Vec<(f64, usize)>,
    /// Per candidate: largest one-direction score (r . d)^2 / |d|^2 over its probes.
    pub score: Vec<f64>,
}

/// Names of the detection statistics, in [`Statistics::detection`] order.
pub fn detection_names(windows: &[Window]) -> Vec<String> {
    let mut n = vec![
        "chi_square_training".to_string(),
        "chi_square_held_out".to_string(),
        "runs_along_frequency".to_string(),
    ];
    n.extend(windows.iter().map(|w| format!("window_omega_{}", w.label)));
    n
}

impl Linearized {
    /// At a fit: its predictions `f0` of every curve, the mask, the training Jacobian (rows: the
    /// training curves' kept points in order) and each held-out curve's STE sensitivity column.
    pub fn at_fit(
        f0: &[CurvePrediction],
        mask: &[Vec<bool>],
        train: &[usize],
        jacobian: &DMatrix<f64>,
        held: &[(usize, f64, DVector<f64>)],
        omega: &[Vec<f64>],
        fixed_sigma: Option<f64>,
    ) -> Self {
        let q = jacobian.clone().qr().q();
        let q_train = q
            .columns(0, jacobian.ncols().min(jacobian.nrows()))
            .into_owned();
        Linearized {
            f0: f0.iter().map(|p| p.dte_pp_um.clone()).collect(),
            mask: mask.to_vec(),
            train: train.to_vec(),
            q_train,
            q_held: held.iter().map(|(i, _, c)| (*i, c.normalize())).collect(),
            omega: omega.to_vec(),
            windows: windows(),
            probes: Vec::new(),
            zero: None,
            fixed_sigma,
        }
    }

    fn project_out(q: &DMatrix<f64>, v: &DVector<f64>) -> DVector<f64> {
        v - q * (q.transpose() * v)
    }

    /// One replicate data set under the fitted curves: y* = f0 + sigma z, z standard normal.
    pub fn replicate(&self, sigma: f64, rng: &mut Rng) -> Vec<Vec<f64>> {
        self.f0
            .iter()
            .map(|c| c.iter().map(|v| v + sigma * rng.normal()).collect())
            .collect()
    }

    /// Statistics of `n` replicates (replicate b seeded from `seed` and b), in parallel: the
    /// parametric bootstrap under the fitted curves.
    pub fn bootstrap(&self, sigma: f64, n: usize, seed: u64) -> Vec<Statistics> {
        (0..n)
            .into_par_iter()
            .map(|b| {
                let mut rng = Rng::new(seed.wrapping_mul(1_000_003).wrapping_add(b as u64));
                self.statistics(&self.replicate(sigma, &mut rng))
            })
            .collect()
    }

    /// Compute every statistic on curves `y` (all curves, full length).
    pub fn statistics(&self, y: &[Vec<f64>]) -> Statistics {
        let sigma = self
            .fixed_sigma
            .or_else(|| noise_from_differences(y))
            .unwrap_or(1.0)
            .max(1e-12);
        let raw: Vec<Vec<f64>> = y
            .iter()
            .enumerate()
            .map(|(i, c)| {
                c.iter()
                    .enumerate()
                    .filter(|(j, _)| self.mask[i][*j])
                    .map(|(j, v)| {
                        if self.zero.as_ref().is_some_and(|z| z[i][j]) {
                            0.0
                        } else {
                            (v - self.f0[i][j]) / sigma
                        }
                    })
                    .collect()
            })
            .collect();
        let mut residuals = raw.clone();
        // Training rows: project off the M0 Jacobian.
        let rt: Vec<f64> = self.train.iter().flat_map(|&i| raw[i].clone()).collect();
        let rt = Self::project_out(&self.q_train, &DVector::from_vec(rt));
        let mut k = 0;
        for &i in &self.train {
            let n = residuals[i].len();
            residuals[i] = rt.as_slice()[k..k + n].to_vec();
            k += n;
        }
        let mut chi_held = 0.0;
        for (i, u) in &self.q_held {
            let v = DVector::from_vec(raw[*i].clone());
            let p = &v - u * u.dot(&v);
            chi_held += p.norm_squared();
            residuals[*i] = p.as_slice().to_vec();
        }
        let chi_train = rt.norm_squared();
        let runs = -runs_z(&residuals);
        let mut detection = vec![chi_train, chi_held, runs];
        for w in &self.windows {
            let mut e = 0.0;
            let mut m = 0;
            for (i, r) in residuals.iter().enumerate() {
                let om: Vec<f64> = self.omega[i]
                    .iter()
                    .enumerate()
                    .filter(|(j, _)| self.mask[i][*j])
                    .map(|(_, o)| *o)
                    .collect();
                for (o, v) in om.iter().zip(r) {
                    if w.contains(*o) {
                        e += v * v;
                        m += 1;
                    }
                }
            }
            detection.push(if m >= 3 { e } else { f64::NAN });
        }
        let mut lr = Vec::new();
        let mut score = Vec::new();
        for probes in &self.probes {
            let mut best = (f64::NEG_INFINITY, 0);
            let mut sc: f64 = 0.0;
            for (k, d) in probes.iter().enumerate() {
                let d = d / sigma;
                let dd = d.norm_squared();
                let rd = rt.dot(&d);
                // RSS0 - RSS1 = 2 r.d - |d|^2 for the linearised refit at this probe.
                let gain = 2.0 * rd - dd;
                if gain > best.0 {
                    best = (gain, k);
                }
                if dd > 0.0 {
                    sc = sc.max(rd * rd / dd);
                }
            }
            lr.push((best.0.max(0.0), best.1));
            score.push(sc);
        }
        Statistics {
            sigma,
            detection,
            lr,
            score,
        }
    }
}
