//! The estimation problem both of `validate kubo`'s fits share: a model curve of D_L fitted to
//! the envelope midline, zeta and omega_n (and the STE amplitude when rig.toml gives none), each
//! point's noise proportional to the model's level. The contact-part fit ([`super::kubo`]) and
//! the whole-curve fit ([`super::kubo_swept`]) differ only in the curve.

use super::design_fit::CorrelationChoice;
use crate::data::KuboPoint;
use crate::error::Result;
use crate::fit::{
    estimate_warm, profile_interval_or_better, Axis, Estimate, EstimateOptions, Measurement,
    NearModel, NoiseSetting, Param, ProfileInterval, Profiled, Robust, Stop,
};

/// STE amplitude (um): the one held, else the third fitted parameter.
pub(super) fn ste_of(held: Option<f64>, params: &[f64]) -> f64 {
    held.unwrap_or_else(|| params.get(2).copied().unwrap_or(f64::NAN))
}

/// What a midline fit holds: the STE amplitude held at a value or fitted from a start (and
/// weighed as a measurement where rig.toml states its uncertainty), and how the errors'
/// correlation along speed is treated.
#[derive(Clone, Copy, Debug)]
pub(super) struct MidlineSetting {
    /// The value it is held at (None: fitted).
    pub held: Option<f64>,
    /// Where the fit starts it, um (the stated value when rig.toml states one).
    pub start: f64,
    /// The standard uncertainty of the stated value (`[ste] sd_um`, um): a fitted STE is then
    /// weighed against it as a measurement ([`Measurement`]).
    pub stated_sd: Option<f64>,
    pub correlation: CorrelationChoice,
}

impl MidlineSetting {
    /// The stated STE as a measurement of the fitted one (parameter 2), where it is fitted and
    /// its uncertainty is stated.
    fn measurements(&self) -> Vec<Measurement> {
        match (self.held, self.stated_sd) {
            (None, Some(sd)) => vec![Measurement {
                param: 2,
                value: self.start,
                sd,
            }],
            _ => Vec::new(),
        }
    }
}

/// The midline of the envelope at each of `points`: the data both fits take.
pub(super) fn midline<'a>(points: impl IntoIterator<Item = &'a KuboPoint>) -> Vec<f64> {
    points
        .into_iter()
        .map(|k| 0.5 * (k.dynamic_factor_min + k.dynamic_factor_max))
        .collect()
}

/// The speed of the measured envelope's highest point (None for no points): where both fits
/// place the resonance before they fit it.
pub(super) fn measured_peak_rpm(points: &[KuboPoint]) -> Option<f64> {
    points
        .iter()
        .max_by(|a, b| a.dynamic_factor_max.total_cmp(&b.dynamic_factor_max))
        .map(|p| p.speed_rpm)
}

/// Name of the relative half-spread of the tooth pairs' STE amplitudes (see
/// `MidlineFit::new`).
pub const PAIR_SPREAD: &str = "pair_ste_half_spread";

/// The 95% interval of |h|, the pairs' STE half-spread, from that of the fitted (signed) h:
/// the curve is even in h, so the interval of |h| is h's folded at zero.
pub fn spread_interval((lo, hi): (f64, f64)) -> (f64, f64) {
    if lo <= 0.0 && hi >= 0.0 {
        (0.0, lo.abs().max(hi.abs()))
    } else {
        (lo.abs().min(hi.abs()), lo.abs().max(hi.abs()))
    }
}

/// A fit of some model curve to a midline.
pub(super) struct MidlineFit {
    /// The measured speeds (rpm) and the envelope's midline there.
    speeds: Vec<f64>,
    /// How the STE is held or weighed and the errors' correlation along speed treated.
    ste: MidlineSetting,
    y: Vec<f64>,
    params: Vec<Param>,
    /// Parameters whose profile intervals are wanted (the pair spread is a nuisance).
    profiled: usize,
    stop: Stop,
    /// The stop of the profile intervals' inner fits.
    profile_stop: Stop,
}

impl MidlineFit {
    /// The problem on `midline`: zeta, omega_n, and the STE amplitude unless `ste` holds it; last,
    /// when `pair_spread` gives its start, the relative half-spread h of the tooth pairs' STE
    /// amplitudes (the curve is then the mean of two pairs' at STE (1 - h) and (1 + h): the
    /// envelope's edges are its extreme pairs, see [`super::kubo_swept`]). The fit stops at
    /// `stop`, the inner fits of its profile intervals at `profile_stop`.
    pub fn new(
        (speeds, midline): (Vec<f64>, Vec<f64>),
        ste: MidlineSetting,
        pair_spread: Option<f64>,
        (stop, profile_stop): (Stop, Stop),
    ) -> Self {
        let mut params = vec![
            Param::positive("zeta", 0.1),
            Param::positive("omega_n_hz", 1000.0),
        ];
        if ste.held.is_none() {
            params.push(Param::positive("ste_um", 1.0));
        }
        let profiled = params.len();
        if let Some(h) = pair_spread {
            // Signed, not positive: the curve is even in h, and a fit that finds no spread
            // ends at h = 0 (a log or logistic coordinate would run off to -infinity there).
            params.push(Param::signed(PAIR_SPREAD, h, h));
        }
        MidlineFit {
            speeds,
            ste,
            y: midline,
            params,
            profiled,
            stop,
            profile_stop,
        }
    }

    /// This problem with zeta's profile going no lower than `floor` (see
    /// [`Param::profile_floor`]): the least damping its curve is trusted at.
    pub fn with_zeta_floor(mut self, floor: f64) -> Self {
        self.params[0] = self.params[0].clone().with_profile_floor(floor);
        self
    }

    /// The fit of `curve` (D_L at every point for a parameter vector) from each of `starts`,
    /// its Jacobian columns from `near` when given.
    pub fn fit<C>(
        &self,
        curve: &C,
        near: Option<NearModel<'_>>,
        starts: &[Vec<f64>],
    ) -> Result<Estimate>
    where
        C: Fn(&[f64]) -> Result<Vec<f64>> + Sync,
    {
        estimate_warm(
            curve,
            near,
            &self.y,
            &self.params,
            &EstimateOptions {
                // Each point's noise scale is proportional to its level: the scatter between
                // tooth pairs grows with D_L, and the fit estimates the common factor. The level
                // is the model's (iteratively reweighted), not the measured midline: weighting
                // each point by its own measured value gives the points that happen to read low
                // more weight, a curve biased low and zeta biased high (4 pairs, 8% scatter:
                // +1.4%, 0.4 standard errors, on the whole-curve fit; docs/validation.md). A
                // floor and a relative part both estimated are confounded over D_L 1-3 and
                // widened the intervals (zeta covered 100% on 84 whole-curve fits). The
                // envelope's half-width is the scale's noisiest estimate (the range of eight
                // pairs varies by about 30% from speed to speed); weighting by it left the
                // standard errors 10-20% small.
                noise: NoiseSetting::ProportionalToLevel,
                // The midline's errors may drift along speed as a measured curve's do
                // (docs/correlated-errors.md).
                correlation: self
                    .ste
                    .correlation
                    .setting(Axis::new(vec![0; self.speeds.len()], self.speeds.clone())?),
                robust: Robust::Off,
                stop: self.stop,
                starts: starts.to_vec(),
                noise_start: None,
                measurements: self.ste.measurements(),
            },
        )
    }

    /// Profile-likelihood 95% intervals of zeta, omega_n and a fitted STE of the fit `est` of
    /// `curve` (not of the pair spread: a nuisance parameter, not reported).
    pub fn profile<C>(&self, curve: &C, est: &Estimate) -> Result<Vec<ProfileInterval>>
    where
        C: Fn(&[f64]) -> Result<Vec<f64>> + Sync,
    {
        let (intervals, _) = self.profile_while(curve, None, est, None, |_| true)?;
        Ok(intervals)
    }

    /// The intervals of [`MidlineFit::profile`] in order, stopping after the first for which
    /// `go_on` (given the intervals so far) is false: a fit refused on zeta's interval is not
    /// worth the others' (on a rig whose teeth separate at nearly every speed, 81 s of the
    /// refused two-pair fit's 216). With `better_by`, a profile point fitting better than
    /// `est` by more than that (sigma^2) also stops them, and is handed back (the full parameter
    /// vector) to fit again from ([`profile_interval_or_better`]). The inner
    /// fits take their Jacobian columns from `near` when given.
    pub fn profile_while<C>(
        &self,
        curve: &C,
        near: Option<NearModel<'_>>,
        est: &Estimate,
        better_by: Option<f64>,
        go_on: impl Fn(&[ProfileInterval]) -> bool,
    ) -> Result<(Vec<ProfileInterval>, Option<Vec<f64>>)>
    where
        C: Fn(&[f64]) -> Result<Vec<f64>> + Sync,
    {
        let mut out = Vec::new();
        for i in 0..self.profiled.min(est.params.len()) {
            let stop = self.profile_stop;
            match profile_interval_or_better(curve, near, &self.y, est, i, stop, better_by)? {
                Profiled::Interval(interval) => out.push(interval),
                Profiled::Better(p) => return Ok((out, Some(p))),
            }
            if !go_on(&out) {
                break;
            }
        }
        Ok((out, None))
    }
}
