//! Alternating frequency-time (AFT) evaluation of the multi-harmonic balance residual of the full
//! model (design.md section 1, eq. 3a generalised by eq. 20 and k(t)):
//!
//! R(x, Omega) = harmonics of [ q'' + 2 zeta q' + k(t) f(q) - F(t) ],
//!
//! for the ansatz of [`super::aft_series`]. The linear terms are balanced in the frequency
//! domain; k(t) f(q(t)) is evaluated on N time samples of one orbit period (inverse real FFT of
//! the coefficients) and transformed back with a forward real FFT. The Jacobian is exact for the
//! sampled residual: d(k f(q))/dx_j = k(t) f'(q(t)) phi_j(t), whose harmonics follow from those of
//! c(t) = k(t) f'(q(t)) up to order 2H by the product formulas of cos and sin.

use crate::error::{GearError, Result};
use crate::model::{dead_zone, GearPair};
use crate::sim::MAX_PERIOD;
use nalgebra::{DMatrix, DVector};
use realfft::num_complex::Complex;
use realfft::{ComplexToReal, RealFftPlanner, RealToComplex};
use std::f64::consts::TAU;
use std::sync::Arc;

/// Options of the multi-harmonic balance with AFT.
#[derive(Clone, Debug, PartialEq)]
pub struct AftOptions {
    /// Number of harmonics H of the ansatz (of the orbit frequency Omega / nu), >= 1.
    pub harmonics: usize,
    /// Subharmonic order nu: the orbit period is nu forcing periods (1 for period-1 orbits).
    /// Forcing of order j sits at harmonic j nu of the ansatz, so H >= nu times the highest
    /// forcing order is required.
    pub subharmonic: u32,
    /// Time samples N per orbit period (a power of two, N >= 4H, and N / 2 > H + nu times the
    /// highest stiffness order); `None` chooses 32H rounded up to a power of two, at least 64.
    /// The dead zone is not smooth: the sampled residual is piecewise linear in the coefficients,
    /// with a kink whenever a sample crosses q = +-1 whose strength is about 2(2H + 1)/N. Generous
    /// oversampling keeps aliasing small and these kinks weak, so that Newton and the
    /// continuation do not stall on them (with N = 8H they visibly do near a fold).
    pub time_samples: Option<usize>,
    /// Newton stops when max |R| <= tolerance * (1 + max |F harmonic|).
    pub tolerance: f64,
    /// Newton iterations allowed.
    pub max_iterations: usize,
    /// Compute the Floquet multipliers (stability) of each solution.
    pub stability: bool,
}

impl Default for AftOptions {
    fn default() -> Self {
        AftOptions {
            harmonics: 15,
            subharmonic: 1,
            time_samples: None,
            tolerance: 1e-10,
            max_iterations: 50,
            stability: true,
        }
    }
}

/// Largest number of harmonics accepted: keeps the dense Jacobian small and the time bounded
/// (it grows about as H^2.8: 500 harmonics took 91 s, 128 take about 2 s a frequency).
pub const MAX_HARMONICS: usize = 128;
/// Largest number of time samples accepted (2^22).
const MAX_SAMPLES: usize = 1 << 22;

impl AftOptions {
    /// Validate the options against a model; return the number of time samples N.
    pub(crate) fn resolve(&self, model: &GearPair) -> Result<usize> {
        let h = self.harmonics;
        if h == 0 || h > MAX_HARMONICS {
            return Err(GearError::param(
                "harmonics",
                h as f64,
                "the number of harmonics must be between 1 and 128",
            ));
        }
        if self.subharmonic == 0 || self.subharmonic > MAX_PERIOD {
            return Err(GearError::param(
                "subharmonic",
                self.subharmonic as f64,
                "the subharmonic order must be between 1 and 32",
            ));
        }
        if !(self.tolerance.is_finite() && self.tolerance > 0.0) {
            return Err(GearError::param(
                "tolerance",
                self.tolerance,
                "the Newton tolerance must be finite and > 0",
            ));
        }
        let nu = self.subharmonic as usize;
        let forcing_order = model
            .ste
            .iter()
            .chain(&model.torque)
            .filter(|t| t.amplitude != 0.0)
            .map(|t| t.order as usize)
            .max()
            .unwrap_or(0);
        if forcing_order * nu > h {
            return Err(GearError::param(
                "harmonics",
                h as f64,
                "H must be at least the subharmonic order times the highest forcing order",
            ));
        }
        let stiff_order = model
            .stiffness
            .iter()
            .filter(|t| t.amplitude != 0.0)
            .map(|t| t.order as usize)
            .max()
            .unwrap_or(0);
        let need = (4 * h).max(2 * (h + nu * stiff_order) + 2);
        let n = match self.time_samples {
            Some(n) => {
                if !n.is_power_of_two() || n < need {
                    return Err(GearError::param(
                        "time_samples",
                        n as f64,
                        "N must be a power of two, >= 4H and > 2 (H + nu * stiffness order)",
                    ));
                }
                n
            }
            None => (32 * h).max(need).next_power_of_two().max(64),
        };
        if n > MAX_SAMPLES {
            return Err(GearError::param(
                "time_samples",
                n as f64,
                "at most 2^22 time samples (lower H or the stiffness harmonic order)",
            ));
        }
        Ok(n)
    }
}

/// The residual, its Jacobian in the coefficients and its derivative in Omega at one point.
pub(crate) struct Linearisation {
    /// R(x, Omega), in the coefficient layout.
    pub r: DVector<f64>,
    /// dR/dx.
    pub jx: DMatrix<f64>,
    /// dR/dOmega.
    pub jw: DVector<f64>,
}

/// AFT evaluator for one model (any Omega) and one set of options; owns FFT plans and buffers.
pub(crate) struct Aft {
    h: usize,
    nu: f64,
    n: usize,
    zeta: f64,
    fwd: Arc<dyn RealToComplex<f64>>,
    inv: Arc<dyn ComplexToReal<f64>>,
    /// k(theta_n) on the time samples (independent of Omega in the orbit phase).
    stiff: Vec<f64>,
    /// Mean load and external torque harmonics, in the coefficient layout.
    force_fixed: DVector<f64>,
    /// STE forcing per unit Omega^2 (eq. 20: (j Omega)^2 F_ahj sin(j Omega t + phi_hj)).
    force_ste: DVector<f64>,
    spec: Vec<Complex<f64>>,
    time: Vec<f64>,
    work: Vec<f64>,
    scratch_fwd: Vec<Complex<f64>>,
    scratch_inv: Vec<Complex<f64>>,
}

impl Aft {
    /// Plan the transforms and tabulate the excitation of `model` for the options `opts`.
    pub(crate) fn new(model: &GearPair, opts: &AftOptions) -> Result<Self> {
        let n = opts.resolve(model)?;
        let h = opts.harmonics;
        let nu = opts.subharmonic as usize;
        let mut planner = RealFftPlanner::<f64>::new();
        let fwd = planner.plan_fft_forward(n);
        let inv = planner.plan_fft_inverse(n);
        let stiff = (0..n)
            .map(|i| {
                let theta = TAU * i as f64 / n as f64;
                1.0 + model
                    .stiffness
                    .iter()
                    .map(|s| s.amplitude * ((s.order as usize * nu) as f64 * theta + s.phase).cos())
                    .sum::<f64>()
            })
            .collect();
        let dim = 2 * h + 1;
        let mut force_fixed = DVector::zeros(dim);
        let mut force_ste = DVector::zeros(dim);
        force_fixed[0] = model.mean_force;
        // amp sin(k theta + phi) = amp cos(phi) sin(k theta) + amp sin(phi) cos(k theta)
        let add = |v: &mut DVector<f64>, order: u32, amp: f64, phase: f64| {
            let k = order as usize * nu;
            if amp != 0.0 && k <= h {
                let (s, c) = phase.sin_cos();
                v[2 * k - 1] += amp * s;
                v[2 * k] += amp * c;
            }
        };
        for t in &model.ste {
            let j = t.order as f64;
            add(&mut force_ste, t.order, j * j * t.amplitude, t.phase);
        }
        for t in &model.torque {
            add(&mut force_fixed, t.order, t.amplitude, t.phase);
        }
        Ok(Aft {
            h,
            nu: nu as f64,
            n,
            zeta: model.zeta,
            spec: fwd.make_output_vec(),
            time: fwd.make_input_vec(),
            work: fwd.make_input_vec(),
            scratch_fwd: fwd.make_scratch_vec(),
            scratch_inv: inv.make_scratch_vec(),
            fwd,
            inv,
            stiff,
            force_fixed,
            force_ste,
        })
    }

    /// Number of unknown coefficients 2H + 1.
    pub(crate) fn dim(&self) -> usize {
        2 * self.h + 1
    }

    /// Harmonics of the forcing F(t) at Omega.
    pub(crate) fn forcing(&self, omega: f64) -> DVector<f64> {
        &self.force_fixed + omega * omega * &self.force_ste
    }

    /// Scale of the residual: 1 + the largest forcing harmonic.
    pub(crate) fn scale(&self, omega: f64) -> f64 {
        1.0 + self.forcing(omega).amax()
    }

    /// The residual R(x, Omega).
    pub(crate) fn residual(&mut self, x: &[f64], omega: f64) -> Result<DVector<f64>> {
        self.sample_time(x)?;
        let mut r = self.nonlinear()?;
        r -= self.forcing(omega);
        self.add_linear(x, omega, &mut r);
        Ok(r)
    }

    /// Residual, exact Jacobian dR/dx and dR/dOmega.
    pub(crate) fn linearise(&mut self, x: &[f64], omega: f64) -> Result<Linearisation> {
        let r = self.residual(x, omega)?;
        // self.time still holds q(theta_n): transform c = k f'(q).
        for (w, (&q, &k)) in self.work.iter_mut().zip(self.time.iter().zip(&self.stiff)) {
            *w = if q.abs() > 1.0 { k } else { 0.0 };
        }
        self.forward()?;
        let m = 2 * self.h;
        let cc: Vec<f64> = self.spec[..=m].iter().map(|z| z.re).collect();
        let cs: Vec<f64> = self.spec[..=m].iter().map(|z| -z.im).collect();
        let cs_signed = |d: isize| -> f64 {
            let v = cs[d.unsigned_abs()];
            if d < 0 {
                -v
            } else {
                v
            }
        };
        let dim = self.dim();
        let n = self.n as f64;
        let mut jx = DMatrix::zeros(dim, dim);
        for row in 0..dim {
            let (i, si) = kind(row);
            let w = if i == 0 { 1.0 / n } else { 2.0 / n };
            for col in 0..dim {
                let (j, sj) = kind(col);
                let d = i as isize - j as isize;
                let (lo, hi) = (cc[d.unsigned_abs()], cc[i + j]);
                let v = match (si, sj) {
                    (false, false) => 0.5 * (lo + hi),
                    (false, true) => 0.5 * (cs[i + j] - cs_signed(d)),
                    (true, false) => 0.5 * (cs[i + j] + cs_signed(d)),
                    (true, true) => 0.5 * (lo - hi),
                };
                jx[(row, col)] = w * v;
            }
        }
        let mut jw = DVector::zeros(dim);
        for k in 1..=self.h {
            let (kf, wv) = (k as f64, omega / self.nu);
            let (a, b) = (2 * k - 1, 2 * k);
            let (stiff, damp) = (-kf * kf * wv * wv, 2.0 * self.zeta * kf * wv);
            jx[(a, a)] += stiff;
            jx[(a, b)] += damp;
            jx[(b, a)] -= damp;
            jx[(b, b)] += stiff;
            let (dstiff, ddamp) = (
                -2.0 * kf * kf * wv / self.nu,
                2.0 * self.zeta * kf / self.nu,
            );
            jw[a] = dstiff * x[a] + ddamp * x[b];
            jw[b] = -ddamp * x[a] + dstiff * x[b];
        }
        jw -= 2.0 * omega * &self.force_ste;
        Ok(Linearisation { r, jx, jw })
    }

    /// Add the frequency-domain linear part (q'' + 2 zeta q') to `r`.
    fn add_linear(&self, x: &[f64], omega: f64, r: &mut DVector<f64>) {
        let wv = omega / self.nu;
        for k in 1..=self.h {
            let kf = k as f64;
            let (a, b) = (2 * k - 1, 2 * k);
            let (stiff, damp) = (-kf * kf * wv * wv, 2.0 * self.zeta * kf * wv);
            r[a] += stiff * x[a] + damp * x[b];
            r[b] += -damp * x[a] + stiff * x[b];
        }
    }

    /// q on the time samples (into `self.time`) by an inverse real FFT of the coefficients.
    fn sample_time(&mut self, x: &[f64]) -> Result<()> {
        if x.len() != self.dim() {
            return Err(GearError::param(
                "coefficients",
                x.len() as f64,
                "the coefficient vector must have 2H + 1 entries",
            ));
        }
        self.spec
            .iter_mut()
            .for_each(|z| *z = Complex::new(0.0, 0.0));
        self.spec[0] = Complex::new(x[0], 0.0);
        for k in 1..=self.h {
            self.spec[k] = Complex::new(0.5 * x[2 * k - 1], -0.5 * x[2 * k]);
        }
        // DC and Nyquist (index N/2 > H) have zero imaginary part, as the inverse requires.
        self.inv
            .process_with_scratch(&mut self.spec, &mut self.time, &mut self.scratch_inv)
            .map_err(|e| GearError::Numerical(format!("inverse FFT: {e}")))
    }

    /// Harmonics of k(t) f(q(t)) from the samples in `self.time`.
    fn nonlinear(&mut self) -> Result<DVector<f64>> {
        for (w, (&q, &k)) in self.work.iter_mut().zip(self.time.iter().zip(&self.stiff)) {
            *w = k * dead_zone(q);
        }
        self.forward()?;
        let n = self.n as f64;
        let mut out = DVector::zeros(self.dim());
        out[0] = self.spec[0].re / n;
        for k in 1..=self.h {
            out[2 * k - 1] = 2.0 * self.spec[k].re / n;
            out[2 * k] = -2.0 * self.spec[k].im / n;
        }
        Ok(out)
    }

    /// Forward real FFT of `self.work` into `self.spec` (unnormalised; `work` is used as scratch).
    fn forward(&mut self) -> Result<()> {
        self.fwd
            .process_with_scratch(&mut self.work, &mut self.spec, &mut self.scratch_fwd)
            .map_err(|e| GearError::Numerical(format!("forward FFT: {e}")))
    }
}

/// Harmonic index and kind (false: cos / DC, true: sin) of a coefficient position.
#[inline]
fn kind(pos: usize) -> (usize, bool) {
    if pos == 0 {
        (0, false)
    } else {
        (pos.div_ceil(2), pos.is_multiple_of(2))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Term;

    fn model() -> GearPair {
        let mut m = GearPair::paper(0.1, 0.05, 0.05, 0.8).unwrap();
        m.ste.push(Term {
            order: 2,
            amplitude: 0.02,
            phase: 0.3,
        });
        m.stiffness.push(Term {
            order: 1,
            amplitude: 0.2,
            phase: 0.5,
        });
        m
    }

    /// The analytic Jacobian equals central differences of the sampled residual away from
    /// samples sitting on a kink (the residual is piecewise linear in x, so differences with a
    /// small step are exact up to rounding unless a sample changes region).
    #[test]
    fn jacobian_matches_differences() {
        let m = model();
        let opts = AftOptions {
            harmonics: 6,
            ..AftOptions::default()
        };
        let mut aft = Aft::new(&m, &opts).unwrap();
        let x: Vec<f64> = (0..aft.dim())
            .map(|i| {
                if i == 0 {
                    1.05
                } else {
                    0.3 / (i * i) as f64 * (i as f64).cos()
                }
            })
            .collect();
        let lin = aft.linearise(&x, 0.8).unwrap();
        let eps = 1e-7;
        for j in 0..aft.dim() {
            let (mut xp, mut xm) = (x.clone(), x.clone());
            xp[j] += eps;
            xm[j] -= eps;
            let d =
                (aft.residual(&xp, 0.8).unwrap() - aft.residual(&xm, 0.8).unwrap()) / (2.0 * eps);
            for i in 0..aft.dim() {
                assert!(
                    (d[i] - lin.jx[(i, j)]).abs() < 1e-6,
                    "J[{i},{j}]: {} vs {}",
                    d[i],
                    lin.jx[(i, j)]
                );
            }
        }
        let dw = (aft.residual(&x, 0.8 + eps).unwrap() - aft.residual(&x, 0.8 - eps).unwrap())
            / (2.0 * eps);
        assert!((dw - lin.jw).amax() < 1e-6);
    }

    /// Round trip: the AFT of a linear f (teeth always in contact, k = 1) returns q - 1 exactly.
    #[test]
    fn contact_only_nonlinearity_is_linear() {
        let m = GearPair::paper(0.1, 0.05, 0.05, 0.8).unwrap();
        let mut aft = Aft::new(&m, &AftOptions::default()).unwrap();
        let mut x = vec![0.0; aft.dim()];
        x[0] = 3.0;
        x[1] = 0.4;
        x[4] = -0.2;
        aft.sample_time(&x).unwrap();
        let nl = aft.nonlinear().unwrap();
        for (i, v) in nl.iter().enumerate() {
            let expect = if i == 0 { 2.0 } else { x[i] };
            assert!((v - expect).abs() < 1e-14);
        }
    }
}
