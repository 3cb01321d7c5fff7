//! Starting coefficients for the multi-harmonic balance: the linear (no-impact) solution of
//! eq. 13, and the Fourier coefficients of a simulated orbit.

use super::aft::{Aft, AftOptions};
use crate::error::{GearError, Result};
use crate::model::GearPair;
use crate::sim::{ExactFlow, PeriodFlow, State};
use realfft::RealFftPlanner;

/// Coefficients of the no-impact solution (Case I, eq. 13 generalised to every forcing harmonic):
/// with the teeth in permanent contact and k = 1, eq. 3a is linear, q_m = 1 + F_m, and each
/// forcing harmonic passes through 1 / (1 - w^2 + 2 i zeta w). This is the exact solution when
/// q stays above 1 and k(t) = 1; otherwise a starting guess (k(t) is ignored).
pub fn linear_guess(model: &GearPair, opts: &AftOptions) -> Result<Vec<f64>> {
    let model = model.clone().validated()?;
    let aft = Aft::new(&model, opts)?;
    let f = aft.forcing(model.omega);
    let wv = model.omega / opts.subharmonic as f64;
    let mut x = vec![0.0; aft.dim()];
    x[0] = 1.0 + model.mean_force;
    for k in 1..=opts.harmonics {
        let kw = k as f64 * wv;
        let (p, q) = (1.0 - kw * kw, 2.0 * model.zeta * kw);
        let d = p * p + q * q;
        // [[p, q], [-q, p]] (a, b) = (F_cos, F_sin)
        let (fc, fs) = (f[2 * k - 1], f[2 * k]);
        x[2 * k - 1] = (p * fc - q * fs) / d;
        x[2 * k] = (q * fc + p * fs) / d;
    }
    Ok(x)
}

/// Coefficients (H harmonics of Omega / nu) of the trajectory of the exact simulation that starts
/// at `x0` (forcing phase 0), sampled over nu forcing periods: a starting guess on a branch the
/// simulation reached, e.g. from a steady state's Poincare point. Requires k(t) = 1 (the exact
/// piecewise solver).
pub fn guess_from_state(model: &GearPair, x0: State, opts: &AftOptions) -> Result<Vec<f64>> {
    if !(x0[0].is_finite() && x0[1].is_finite()) {
        return Err(GearError::param(
            "state",
            if x0[0].is_finite() { x0[1] } else { x0[0] },
            "the initial state must be finite",
        ));
    }
    let n = opts.resolve(model)?;
    let flow = ExactFlow::new(model)?;
    let nu = opts.subharmonic as usize;
    let period = flow.period();
    let dt = nu as f64 * period / n as f64;
    let mut samples = vec![f64::NAN; n];
    let mut x = x0;
    for p in 0..nu {
        let offset = p as f64 * period;
        x = flow.step(
            x,
            Some(&mut |piece| {
                let (a, b) = piece.span();
                let first = ((offset + a) / dt).ceil().max(0.0) as usize;
                for (i, s) in samples.iter_mut().enumerate().skip(first) {
                    let local = i as f64 * dt - offset;
                    if local > b {
                        break;
                    }
                    *s = piece.eval(local)[0];
                }
            }),
        )?;
    }
    if samples.iter().any(|v| !v.is_finite()) {
        return Err(GearError::Numerical(
            "the simulated trajectory did not cover the sampling grid".into(),
        ));
    }
    let fft = RealFftPlanner::<f64>::new().plan_fft_forward(n);
    let mut spec = fft.make_output_vec();
    fft.process(&mut samples, &mut spec)
        .map_err(|e| GearError::Numerical(format!("forward FFT: {e}")))?;
    let nf = n as f64;
    let mut out = vec![0.0; 2 * opts.harmonics + 1];
    out[0] = spec[0].re / nf;
    for k in 1..=opts.harmonics {
        out[2 * k - 1] = 2.0 * spec[k].re / nf;
        out[2 * k] = -2.0 * spec[k].im / nf;
    }
    Ok(out)
}
