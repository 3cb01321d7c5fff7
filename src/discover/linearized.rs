//! Test statistics of the discovery workflow and their parametric bootstrap under the fitted M0
//! (Davison & Hinkley 1997, ch. 4). Replicate data y*_ij = f0_ij + sigma_ij e_ij are drawn at
//! the fitted M0 curves from the fitted noise model (its scale at each point's level, its
//! distribution: Gaussian or Student-t); on each replicate the noise is re-estimated exactly as on
//! the data, and the weighted refit of M0 is linearised (the standardized residual is projected
//! off the span of the weighted M0 Jacobian: the Gauss-Newton step from the fitted parameters).
//! The same function computes every statistic on the data and on each replicate, so the Monte
//! Carlo p-values are calibrated for the fit's degrees of freedom, the noise estimate, the
//! boundary of amplitude parameters and the non-smooth pp response.

use super::noise::{DiscoveryNoise, PseudoInput, Scales};
use super::stats::runs_z;
use super::windows::Window;
use crate::numeric::Rng;
use nalgebra::{DMatrix, DVector};
use rayon::prelude::*;

/// Standardized residuals are clipped at +-HUBER_C before any statistic (Huber's psi, Huber
/// 1964): a Gaussian residual exceeds 3 with probability 0.0027, so the statistics of Gaussian
/// data hardly change, while one outlier of heavy-tailed noise (a Student-t draw of 15 scales)
/// adds at most 9 to a chi-square instead of 225. The bootstrap computes the same clipped
/// statistics on its replicates, so the p-values stay calibrated; a missing effect moves many
/// points by several scales and is seen through the clip.
pub const HUBER_C: f64 = 3.0;

/// Huber's loss in units of a squared standardized residual: v^2 within +-HUBER_C, then
/// linear (2 c |v| - c^2), so that its differences are residual-sum-of-squares differences for
/// Gaussian residuals and an outlier's weight is bounded.
fn huber_loss(v: f64) -> f64 {
    let a = v.abs();
    if a <= HUBER_C {
        v * v
    } else {
        2.0 * HUBER_C * a - HUBER_C * HUBER_C
    }
}

/// Everything fixed under the null: fitted M0 curves, mask, model Jacobian, probe curves and
/// the data's noise.
#[derive(Clone)]
pub struct Linearized {
    /// M0 predictions per curve (um), every curve: the null curves and the noise levels.
    pub f0: Vec<Vec<f64>>,
    pub mask: Vec<Vec<bool>>,
    /// Speeds of every point (rpm), for the pseudo-residuals of the noise estimate.
    pub speeds: Vec<Vec<f64>>,
    /// Indices of the training curves (their masked points, in order, make the training rows).
    pub train: Vec<usize>,
    /// Jacobian of M0's training curves (um per parameter) on the training rows.
    pub jac_train: DMatrix<f64>,
    /// Each held-out curve's STE sensitivity (um per um) on its masked points.
    pub held_sens: Vec<(usize, DVector<f64>)>,
    /// Each held-out curve's sensitivity to the shared parameters (zeta, omega_n: um per unit,
    /// um per Hz) on its masked points: a refit on the training loads moves them, and with them
    /// the held-out predictions. Empty: not accounted for.
    pub held_globals: Vec<(usize, DMatrix<f64>)>,
    /// Omega of each point (at the M0 omega_n).
    pub omega: Vec<Vec<f64>>,
    pub windows: Vec<Window>,
    /// Per candidate: probe curves f(theta0, delta_k) - f0 on the training rows (um).
    pub probes: Vec<Vec<DVector<f64>>>,
    /// Points whose residual is set to zero (kept rows, so the null distribution still applies):
    /// where a refitted model has a jump or a non-period-1 state that M0 did not have.
    pub zero: Option<Vec<Vec<bool>>>,
    /// The data's noise: the scales replicates are drawn with, and the rule by which each data
    /// set's own noise is found (re-estimated when estimated, as stated otherwise).
    pub noise: DiscoveryNoise,
}

/// Whether a linearised refit of M0 on the training loads moves the held-out curves by what its
/// step of the shared parameters (zeta, omega_n) does to them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum HeldOutShift {
    /// Moved, to first order: the held-out chi-square's null.
    Propagated,
    /// Only their own STE refitted: the residuals the noise is re-estimated from.
    OwnSteOnly,
}

/// Statistics of one data set (observed or replicate).
#[derive(Clone, Debug)]
pub struct Statistics {
    /// chi2 training, chi2 held-out (NaN without a held-out point), -runs z, then one energy per
    /// window (NaN if empty).
    pub detection: Vec<f64>,
    /// Per candidate: likelihood-ratio statistic RSS0 - min_k RSS1_k (standardized residuals),
    /// and the index of the minimising probe.
    pub lr: Vec<(f64, usize)>,
    /// Per candidate: largest one-direction score (r . d)^2 / |d|^2 over its probes.
    pub score: Vec<f64>,
}

/// The chi-square of the training curves' normalised residuals (the first detection test).
pub const CHI_SQUARE_TRAINING: &str = "chi_square_training";
/// The chi-square of the held-out curves' residuals about their predictions.
pub const CHI_SQUARE_HELD_OUT: &str = "chi_square_held_out";

/// Names of the detection statistics, in [`Statistics::detection`] order.
pub fn detection_names(windows: &[Window]) -> Vec<String> {
    let mut n = vec![
        CHI_SQUARE_TRAINING.to_string(),
        CHI_SQUARE_HELD_OUT.to_string(),
        "runs_along_frequency".to_string(),
    ];
    n.extend(windows.iter().map(|w| format!("window_omega_{}", w.label)));
    n
}

/// Orthonormal basis of the column space of `a` (thin QR; `a` has at least as many rows as
/// columns in every use here).
fn column_basis(a: &DMatrix<f64>) -> DMatrix<f64> {
    let k = a.ncols().min(a.nrows());
    a.clone().qr().q().columns(0, k).into_owned()
}

fn project_out(q: &DMatrix<f64>, v: &DVector<f64>) -> DVector<f64> {
    v - q * (q.transpose() * v)
}

/// What one data set's weights make of the fixed pieces: the standardized, projected residuals
/// and the weighted basis they were projected with.
struct Weighted {
    /// The weighted Jacobian and an orthonormal basis of its columns.
    jw: DMatrix<f64>,
    basis: DMatrix<f64>,
    /// Training-row scales, in row order.
    train_scales: Vec<f64>,
}

/// The linearised refit of the null model to one data set: per curve, the standardized
/// residual of its kept points after the refit, and the training rows' as one vector.
struct Refit {
    residuals: Vec<Vec<f64>>,
    train: DVector<f64>,
}

impl Linearized {
    /// Scales of the training rows, in row order, from per-point scales.
    fn train_row_scales(&self, scales: &Scales) -> Vec<f64> {
        self.train
            .iter()
            .flat_map(|&i| {
                (0..self.mask[i].len())
                    .filter(move |&j| self.mask[i][j])
                    .map(move |j| scales[i][j])
            })
            .collect()
    }

    fn weighted(&self, scales: &Scales) -> Weighted {
        let train_scales = self.train_row_scales(scales);
        let mut jw = self.jac_train.clone();
        for (r, s) in train_scales.iter().enumerate() {
            jw.row_mut(r).unscale_mut(*s);
        }
        Weighted {
            basis: column_basis(&jw),
            jw,
            train_scales,
        }
    }

    /// Per candidate, its probe curves standardized by `scales` and projected off the weighted
    /// M0 Jacobian: the directions the linearised refit of M0 + candidate can move the
    /// standardized residual in.
    pub fn weighted_probes(&self, scales: &Scales) -> Vec<Vec<DVector<f64>>> {
        let w = self.weighted(scales);
        self.project_probes(&w)
    }

    fn project_probes(&self, w: &Weighted) -> Vec<Vec<DVector<f64>>> {
        self.probes
            .iter()
            .map(|ps| {
                ps.iter()
                    .map(|d| {
                        let dw = DVector::from_iterator(
                            d.len(),
                            d.iter().zip(&w.train_scales).map(|(x, s)| x / s),
                        );
                        project_out(&w.basis, &dw)
                    })
                    .collect()
            })
            .collect()
    }

    /// One replicate data set under the null curves: y* = f0 + sigma_ij e, e drawn from the
    /// data's noise model (with its relative part free, [`DiscoveryNoise::replicate_model`]).
    pub fn replicate(&self, rng: &mut Rng) -> Vec<Vec<f64>> {
        let noise = self.noise.replicates();
        let scales = noise.scales(&self.f0);
        self.f0
            .iter()
            .zip(&scales)
            .map(|(c, s)| {
                c.iter()
                    .zip(s)
                    .map(|(v, s)| v + noise.draw(*s, rng))
                    .collect()
            })
            .collect()
    }

    /// Statistics of `n` replicates (replicate b seeded from `seed` and b), in parallel: the
    /// parametric bootstrap under the null curves.
    pub fn bootstrap(&self, n: usize, seed: u64) -> Vec<Statistics> {
        (0..n)
            .into_par_iter()
            .map(|b| {
                let mut rng = Rng::new(seed.wrapping_mul(1_000_003).wrapping_add(b as u64));
                self.statistics(&self.replicate(&mut rng))
            })
            .collect()
    }

    /// The linearised refit of the null model to standardized residuals `z` (kept points of
    /// every curve, weights `w`, scales `scales`): the training rows projected off the weighted
    /// Jacobian (the Gauss-Newton step); each held-out curve shifted by what that step's zeta
    /// and omega_n do to it when `held` says so, then projected off its own STE sensitivity
    /// (its STE is fitted alone).
    fn linear_refit(
        &self,
        z: &[Vec<f64>],
        w: &Weighted,
        scales: &Scales,
        held: HeldOutShift,
    ) -> Refit {
        let mut residuals = z.to_vec();
        let zt: Vec<f64> = self.train.iter().flat_map(|&i| z[i].clone()).collect();
        let zt = DVector::from_vec(zt);
        let rt = project_out(&w.basis, &zt);
        let mut k = 0;
        for &i in &self.train {
            let n = residuals[i].len();
            residuals[i] = rt.as_slice()[k..k + n].to_vec();
            k += n;
        }
        // The step of the shared parameters (the first two columns).
        let step = (held == HeldOutShift::Propagated && !self.held_globals.is_empty())
            .then(|| w.jw.clone().svd(true, true).solve(&zt, 1e-12).ok())
            .flatten();
        for (i, sens) in &self.held_sens {
            let kept: Vec<usize> = (0..self.mask[*i].len())
                .filter(|&j| self.mask[*i][j])
                .collect();
            let mut v = DVector::from_vec(z[*i].clone());
            if let (Some(step), Some((_, g))) =
                (&step, self.held_globals.iter().find(|(h, _)| h == i))
            {
                let shift = g * step.rows(0, g.ncols());
                for (r, &j) in kept.iter().enumerate() {
                    v[r] -= shift[r] / scales[*i][j];
                }
            }
            let u = DVector::from_iterator(
                kept.len(),
                kept.iter()
                    .zip(sens.iter())
                    .map(|(&j, d)| d / scales[*i][j]),
            );
            let p = if u.norm() > 0.0 {
                let u = u.normalize();
                &v - &u * u.dot(&v)
            } else {
                v
            };
            residuals[*i] = p.as_slice().to_vec();
        }
        Refit {
            residuals,
            train: rt,
        }
    }

    /// Residuals (um) of data set `y` about the linearised refit of the null model to it,
    /// weighted by the data's noise, at every point (kept or not): what a full refit would
    /// leave, to first order, but with the held-out curves only refitted in their own STE.
    ///
    /// Why not moved by the refit's zeta and omega_n: the projections shrink a residual, the
    /// shift does not. On a coarse grid, where the training loads hardly fix omega_n and zeta,
    /// the Gauss-Newton step of a replicate moved a held-out resonance by a linear extrapolation
    /// of several um, far beyond what the model's curves can do; the pseudo-residuals took it
    /// for noise, and the replicates' re-estimated noise came out several times the one they
    /// were drawn with (relative part 0.16 drawn at 0.05, floor 4 um drawn at 0.25 um). The
    /// replicates' training chi-square then fell to half its degrees of freedom and the data's
    /// was judged against it: 13/100 rejections on null sets with Student-t noise on a 300 rpm
    /// grid (docs/discover-studies.md, "The null rate and its calibration").
    fn refit_residuals(&self, y: &[Vec<f64>]) -> Vec<Vec<f64>> {
        let scales = self.noise.scales(&self.f0);
        let w = self.weighted(&scales);
        let z = self.standardized(y, &scales, f64::INFINITY);
        let fit = self.linear_refit(&z, &w, &scales, HeldOutShift::OwnSteOnly);
        y.iter()
            .enumerate()
            .map(|(i, c)| {
                let mut kept = fit.residuals[i].iter();
                c.iter()
                    .enumerate()
                    .map(|(j, v)| match self.mask[i][j] {
                        true => kept.next().copied().unwrap_or(0.0) * scales[i][j],
                        false => v - self.f0[i][j],
                    })
                    .collect()
            })
            .collect()
    }

    /// The noise of data set `y`: re-estimated from the pseudo-residuals of its residuals about
    /// the linearised refit ([`Linearized::refit_residuals`]) when the data's noise was
    /// estimated (the points zeroed after a refit left out), as stated otherwise.
    pub fn noise_of(&self, y: &[Vec<f64>]) -> DiscoveryNoise {
        if !self.noise.is_estimated() {
            return self.noise.clone();
        }
        let residuals = self.refit_residuals(y);
        let mask: Vec<Vec<bool>> = match &self.zero {
            None => self.mask.clone(),
            Some(z) => self
                .mask
                .iter()
                .zip(z)
                .map(|(m, z)| m.iter().zip(z).map(|(m, z)| *m && !*z).collect())
                .collect(),
        };
        self.noise.for_replicate(&PseudoInput {
            speeds: &self.speeds,
            residuals: &residuals,
            levels: &self.f0,
            mask: &mask,
        })
    }

    /// Standardized residuals of the kept points of every curve, clipped at `clip` (zero where
    /// `zero` says).
    fn standardized(&self, y: &[Vec<f64>], scales: &Scales, clip: f64) -> Vec<Vec<f64>> {
        y.iter()
            .enumerate()
            .map(|(i, c)| {
                c.iter()
                    .enumerate()
                    .filter(|(j, _)| self.mask[i][*j])
                    .map(|(j, v)| {
                        if self.zero.as_ref().is_some_and(|z| z[i][j]) {
                            0.0
                        } else {
                            ((v - self.f0[i][j]) / scales[i][j]).clamp(-clip, clip)
                        }
                    })
                    .collect()
            })
            .collect()
    }

    /// Compute every statistic on curves `y` (all curves, full length).
    pub fn statistics(&self, y: &[Vec<f64>]) -> Statistics {
        let noise = self.noise_of(y);
        let scales = noise.scales(&self.f0);
        let w = self.weighted(&scales);
        let z = self.standardized(y, &scales, HUBER_C);
        let Refit {
            residuals,
            train: rt,
        } = self.linear_refit(&z, &w, &scales, HeldOutShift::Propagated);
        let chi_train = rt.norm_squared();
        // No held-out point (a single load, or nothing kept off the training loads): the test
        // is not run, rather than a zero statistic with p 1 in the family.
        let held_points: usize = self
            .held_sens
            .iter()
            .map(|(i, _)| residuals[*i].len())
            .sum();
        let chi_held: f64 = if held_points == 0 {
            f64::NAN
        } else {
            self.held_sens
                .iter()
                .map(|(i, _)| residuals[*i].iter().map(|v| v * v).sum::<f64>())
                .sum()
        };
        let runs = -runs_z(&residuals);
        let mut detection = vec![chi_train, chi_held, runs];
        for win in &self.windows {
            let mut e = 0.0;
            let mut m = 0;
            for (i, r) in residuals.iter().enumerate() {
                let om = (0..self.omega[i].len())
                    .filter(|&j| self.mask[i][j])
                    .map(|j| self.omega[i][j]);
                for (o, v) in om.zip(r) {
                    if win.contains(o) {
                        e += v * v;
                        m += 1;
                    }
                }
            }
            detection.push(if m >= 3 { e } else { f64::NAN });
        }
        // The probes' gains are Huber losses of the unclipped residuals: with the clipped ones
        // a probe that moves the curves by tens of scales, toward a missing effect of that
        // size, gained 2 r.d - |d|^2 < 0 (a 2nd STE harmonic of 40% on Munro's 50 rpm grid
        // with constant noise: LR 0, not detected; 34,000 before the clip).
        let raw = self
            .linear_refit(
                &self.standardized(y, &scales, f64::INFINITY),
                &w,
                &scales,
                HeldOutShift::Propagated,
            )
            .train;
        let loss0: f64 = raw.iter().map(|&v| huber_loss(v)).sum();
        let mut lr = Vec::new();
        let mut score = Vec::new();
        for probes in self.project_probes(&w) {
            let mut best = (f64::NEG_INFINITY, 0);
            let mut sc: f64 = 0.0;
            for (k, d) in probes.iter().enumerate() {
                let dd = d.norm_squared();
                let rd = rt.dot(d);
                // The loss M0 loses to the linearised refit at this probe: RSS0 - RSS1 =
                // 2 r.d - |d|^2 for Gaussian residuals, Huber's loss beyond HUBER_C.
                let gain = loss0
                    - raw
                        .iter()
                        .zip(d.iter())
                        .map(|(r, d)| huber_loss(r - d))
                        .sum::<f64>();
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
            detection,
            lr,
            score,
        }
    }
}
