//! Peak-to-peak DTE of a steady state over consecutive observation windows. A periodic orbit
//! gives the same pp in every window; a chaotic or aperiodic motion does not: a measured pp
//! there is one sample of a distribution over windows (and over the history that led to the
//! window), which the range over many windows describes.

use super::extrema::extremes_over;
use super::flow::{PeriodFlow, State};
use crate::error::{GearError, Result};

/// Dimensionless pp of the DTE x = q + e/b in each of `windows` consecutive windows of
/// `periods` forcing periods, the first starting at the phase-0 section point `x`. With `x` the
/// first section point of a [`super::SteadyState`] and `periods` its `keep`, the first window is
/// the one the steady-state analysis measured.
pub fn dte_pp_over_windows(
    flow: &dyn PeriodFlow,
    x: State,
    periods: usize,
    windows: usize,
) -> Result<Vec<f64>> {
    if periods == 0 || windows == 0 {
        return Err(GearError::param(
            "windows",
            (periods.min(windows)) as f64,
            "observation windows need at least one window of at least one period",
        ));
    }
    let mut z = x;
    let mut out = Vec::with_capacity(windows);
    for _ in 0..windows {
        let (ext, next) = extremes_over(flow, z, periods)?;
        out.push(ext.dte.1 - ext.dte.0);
        z = next;
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{munro_spec, Dimensional, GearPair};
    use crate::sim::{steady_state, ExactFlow, SteadyOptions};

    /// Munro's rig at a quarter of the design load with 3.5 um of STE (the stand-in data's
    /// 945 N curve), zeta 0.0175, omega_n 1600 Hz, at a pinion speed in rpm.
    fn munro_quarter_load(rpm: f64) -> ExactFlow {
        let dim = Dimensional::new(&munro_spec()).unwrap();
        let m = GearPair::paper(dim.mean_force(945.0), dim.ste_amplitude(3.5), 0.0175, 1.0)
            .unwrap()
            .at_omega(dim.omega(rpm, 1600.0))
            .unwrap();
        ExactFlow::new(&m).unwrap()
    }

    fn steady_then_windows(rpm: f64) -> (crate::sim::SteadyState, Vec<f64>) {
        let f = munro_quarter_load(rpm);
        let opts = SteadyOptions::default();
        let x0 = [1.0 + f.model().mean_force, 0.0];
        let s = steady_state(&f, x0, &opts).unwrap();
        let w = dte_pp_over_windows(&f, s.poincare[0], opts.keep, 16).unwrap();
        (s, w)
    }

    /// Chaotic motion (4300 rpm, no period up to 32): the first window is the analysed one, to
    /// the last bit, and the later windows spread widely (35-84 um over 32 windows at this
    /// speed in an up-sweep; a spread above 10% of the largest is asserted).
    #[test]
    fn chaotic_pp_spreads_over_windows_and_the_first_is_the_analysed_one() {
        let (s, w) = steady_then_windows(4300.0);
        assert_eq!(s.period, None);
        assert_eq!(w[0], s.dte_pp);
        let (lo, hi) = crate::numeric::min_max(w.iter().copied()).unwrap();
        assert!(hi - lo > 0.1 * hi, "windows {lo}..{hi}");
    }

    /// A period-1 orbit repeats: every window measures its pp (to the refinement of the
    /// extrema, 1e-9 relative).
    #[test]
    fn periodic_pp_is_the_same_in_every_window() {
        let (s, w) = steady_then_windows(3000.0);
        assert_eq!(s.period, Some(1));
        for v in &w {
            assert!(
                (v - s.dte_pp).abs() < 1e-9 * s.dte_pp,
                "{v} vs {}",
                s.dte_pp
            );
        }
    }

    #[test]
    fn empty_windows_are_an_error() {
        let f = munro_quarter_load(3000.0);
        assert!(dte_pp_over_windows(&f, [1.0, 0.0], 0, 4).is_err());
        assert!(dte_pp_over_windows(&f, [1.0, 0.0], 64, 0).is_err());
    }
}
