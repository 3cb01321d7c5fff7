//! A discovery model (M0, or M0 with one candidate effect) on a set of curves, as one curve for
//! the estimation engine: its parameters (zeta, omega_n, one STE per curve, the effect's), its
//! values at the kept points, the errors' speed axis and its fit under the run's error family.
//! Every fit of a run goes through here, so that all maximise the one likelihood of `crate::fit`.

use super::compare::Mask;
use super::effects::{Candidate, Effect};
use super::forward::{
    fitted_damping_admissible, predict, simulate, CurvePrediction, Globals, Setup,
};
use crate::error::{GearError, Result};
use crate::fit::{
    estimate_warm, Axis, CorrelationSetting, Estimate, EstimateOptions, Measurement, NoiseModel,
    NoiseSetting, Param, Robust, Stop,
};
use rayon::prelude::*;

/// How a fit's parameters after (zeta, omega_n, the STEs) stand for the effect.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum EffectParams {
    /// None: the paper's model, M0.
    None,
    /// The candidate's delta, nested at zero: the tests' coordinates, smooth through M0.
    Delta(Candidate),
    /// The candidate's profile coordinate (an amplitude, gamma or beta) then the rest of its
    /// delta ([`Candidate::profiled`]): the coordinates of the named effect's interval.
    Profiled(Candidate),
    /// The effect held as it is (a held-out load's STE fitted alone under a fitted model).
    Held,
}

/// A model on the curves `idx` of a set, compared with the data at the points `mask` keeps.
pub struct Curves<'a> {
    pub setup: &'a Setup,
    pub idx: Vec<usize>,
    pub mask: &'a Mask,
    pub effect: EffectParams,
    /// Zeta, omega_n and the effect held (a held-out load's STE fitted alone): STEs only.
    pub held: Option<(Globals, Effect)>,
}

impl<'a> Curves<'a> {
    /// Zeta, omega_n, the STEs of curves `idx` and the effect as `effect` says.
    pub fn new(setup: &'a Setup, idx: &[usize], mask: &'a Mask, effect: EffectParams) -> Self {
        Curves {
            setup,
            idx: idx.to_vec(),
            mask,
            effect,
            held: None,
        }
    }

    /// The same curves and kept points with the effect as `effect` says.
    pub fn with_effect(&self, effect: EffectParams) -> Curves<'a> {
        Curves::new(self.setup, &self.idx, self.mask, effect)
    }

    /// The STE of curve `i` alone, zeta, omega_n and the effect held at `g`, `effect`.
    pub fn ste_of(setup: &'a Setup, i: usize, mask: &'a Mask, g: Globals, effect: Effect) -> Self {
        Curves {
            held: Some((g, effect)),
            ..Curves::new(setup, &[i], mask, EffectParams::Held)
        }
    }

    /// Number of parameters before the effect's.
    fn leading(&self) -> usize {
        match self.held {
            Some(_) => self.idx.len(),
            None => 2 + self.idx.len(),
        }
    }

    /// Zeta, omega_n, the STEs and the effect at parameters `p`.
    pub fn unpack(&self, p: &[f64]) -> (Globals, Vec<f64>, Effect) {
        if let Some((g, e)) = &self.held {
            return (*g, p.to_vec(), e.clone());
        }
        let g = Globals {
            zeta: p[0],
            omega_n_hz: p[1],
        };
        let lead = self.leading();
        let ste = p[2..lead].to_vec();
        let tail = &p[lead..];
        let effect = match self.effect {
            EffectParams::None | EffectParams::Held => Effect::none(),
            EffectParams::Delta(c) => Effect::of(c, tail.to_vec()),
            EffectParams::Profiled(c) => Effect::of(c, c.unprofiled(tail[0], &tail[1..])),
        };
        (g, ste, effect)
    }

    /// The parameter vector of `g`, `ste` and `effect` in this model's coordinates.
    pub fn pack(&self, g: Globals, ste: &[f64], effect: &Effect) -> Vec<f64> {
        let mut p = match self.held {
            Some(_) => Vec::new(),
            None => vec![g.zeta, g.omega_n_hz],
        };
        p.extend_from_slice(ste);
        match self.effect {
            EffectParams::None | EffectParams::Held => {}
            EffectParams::Delta(c) => p.extend(if effect.candidate == Some(c) {
                effect.delta.clone()
            } else {
                vec![0.0; c.dim()]
            }),
            EffectParams::Profiled(c) => {
                let (u, free) = c.profiled(&effect.delta);
                p.push(u);
                p.extend(free);
            }
        }
        p
    }

    /// The parameters, starting from `start`: signed, with the typical sizes the finite
    /// differences use (a damping below the fits' floor is refused by the model at every
    /// load, which no transform of zeta alone can express); a profiled amplitude positive (a
    /// negative one is the opposite phase).
    pub fn params(&self, start: &[f64]) -> Vec<Param> {
        let mut p = Vec::with_capacity(start.len());
        if self.held.is_none() {
            p.push(Param::signed("zeta", start[0], 0.005));
            p.push(Param::signed("omega_n_hz", start[1], 10.0));
        }
        let lead = self.leading();
        let first_ste = lead - self.idx.len();
        for (k, &i) in self.idx.iter().enumerate() {
            let name = format!("ste_um_{}N", self.setup.curves[i].load_n);
            p.push(Param::signed(&name, start[first_ste + k], 0.05));
        }
        let tail = &start[lead..];
        match self.effect {
            EffectParams::None | EffectParams::Held => {}
            EffectParams::Delta(c) => {
                for (k, &v) in tail.iter().enumerate() {
                    p.push(Param::signed(&format!("{}_{k}", c.name()), v, c.scale()));
                }
            }
            EffectParams::Profiled(c) => {
                let name = c.estimate_name();
                p.push(if c.has_phase() {
                    Param::positive(name, tail[0].max(1e-3 * c.scale()))
                } else {
                    Param::signed(name, tail[0], c.scale())
                });
                for (k, &v) in tail.iter().enumerate().skip(1) {
                    // A phase-carrying candidate's first free coordinate is its phase (rad).
                    let scale = if k == 1 && c.has_phase() {
                        0.05
                    } else {
                        c.scale()
                    };
                    p.push(Param::signed(&format!("{}_free_{k}", c.name()), v, scale));
                }
            }
        }
        p
    }

    /// Indices of the kept points of each curve, in the fit's order.
    fn kept(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        self.idx.iter().flat_map(move |&i| {
            (0..self.mask[i].len())
                .filter(move |&j| self.mask[i][j])
                .map(move |j| (i, j))
        })
    }

    /// The STEs rig.toml states with an uncertainty, as measurements of this model's STE
    /// parameters: one more Gaussian factor of the likelihood (Theil & Goldberger 1961).
    pub fn measurements(&self) -> Vec<Measurement> {
        let first_ste = self.leading() - self.idx.len();
        self.idx
            .iter()
            .enumerate()
            .filter_map(|(k, &i)| {
                let (value, sd) = self.setup.curves[i].stated_ste?;
                Some(Measurement {
                    param: first_ste + k,
                    value,
                    sd,
                })
            })
            .collect()
    }

    /// The measured pp DTE (um) at the kept points.
    pub fn data(&self) -> Vec<f64> {
        self.kept()
            .map(|(i, j)| self.setup.curves[i].dte_pp_um[j])
            .collect()
    }

    /// The kept points' speed axis, each curve its own (docs/correlated-errors.md).
    pub fn axis(&self) -> Result<Axis> {
        let (curve, speed): (Vec<usize>, Vec<f64>) = self
            .kept()
            .map(|(i, j)| (i, self.setup.curves[i].speeds_rpm[j]))
            .unzip();
        Axis::new(curve, speed)
    }

    /// Stated scales (um) of the kept points, where the set has a `dte_pp_sd_um` column.
    pub fn stated_scales(&self) -> Option<Vec<f64>> {
        self.kept()
            .map(|(i, j)| self.setup.curves[i].sd_um.as_ref().map(|s| s[j]))
            .collect()
    }

    /// The values of `preds` (one per curve of `idx`) at the kept points.
    pub fn at_kept(&self, preds: &[CurvePrediction]) -> Vec<f64> {
        self.idx
            .iter()
            .zip(preds)
            .flat_map(|(&i, p)| {
                (0..self.mask[i].len())
                    .filter(move |&j| self.mask[i][j])
                    .map(move |j| p.dte_pp_um[j])
            })
            .collect()
    }

    /// The predicted curves at parameters `p`, one per curve of `idx`, every speed.
    pub fn predictions(&self, p: &[f64]) -> Result<Vec<CurvePrediction>> {
        let (g, ste, effect) = self.unpack(p);
        if self.held.is_none() {
            fitted_damping_admissible(self.setup, &self.idx, g, &effect)?;
        }
        self.idx
            .par_iter()
            .zip(&ste)
            .map(|(&i, &e)| predict(self.setup, i, g, e, &effect))
            .collect()
    }

    /// The model's values at the kept points at parameters `p`.
    pub fn model(&self, p: &[f64]) -> Result<Vec<f64>> {
        Ok(self.at_kept(&self.predictions(p)?))
    }

    /// [`Curves::model`] at `p` near `base` (a Jacobian column): each curve whose parameters
    /// moved continues the base's sweep; the others are the base's curves from the set's memo.
    pub fn near(&self, p: &[f64], base: &[f64]) -> Result<Vec<f64>> {
        let (g, ste, effect) = self.unpack(p);
        let (g0, ste0, effect0) = self.unpack(base);
        if self.held.is_none() {
            fitted_damping_admissible(self.setup, &self.idx, g, &effect)?;
        }
        let preds: Vec<CurvePrediction> = self
            .idx
            .par_iter()
            .zip(ste.par_iter().zip(&ste0))
            .map(|(&i, (&e, &e0))| {
                let at_base = predict(self.setup, i, g0, e0, &effect0)?;
                if g == g0 && e == e0 && effect.delta == effect0.delta {
                    return Ok(at_base);
                }
                simulate(self.setup, i, g, e, &effect, Some(&at_base))
            })
            .collect::<Result<_>>()?;
        Ok(self.at_kept(&preds))
    }

    /// Fit the model to the data from `starts` (full parameter vectors, the best fit kept) under
    /// `family`, its first weights those of `noise_start` where given ([`EstimateOptions`]).
    pub fn fit(
        &self,
        starts: Vec<Vec<f64>>,
        family: &Family,
        stop: Stop,
        noise_start: Option<NoiseModel>,
    ) -> Result<Estimate> {
        let first = starts
            .first()
            .ok_or_else(|| GearError::Numerical("a fit needs a start".into()))?;
        let params = self.params(first);
        let opts = EstimateOptions {
            noise: family.noise_setting(self)?,
            correlation: family.correlation_setting(self.axis()?),
            robust: family.robust,
            stop,
            starts,
            noise_start,
            measurements: self.measurements(),
        };
        let model = |p: &[f64]| self.model(p);
        let near = |p: &[f64], base: &[f64]| self.near(p, base);
        estimate_warm(&model, Some(&near), &self.data(), &params, &opts)
    }
}

/// What a run knows of its errors: their scale (stated or estimated), tails and correlation
/// along speed. M0's fit makes the automatic choices ([`Family::chosen_by`]); every later fit
/// re-estimates the chosen family's parameters, so that the likelihoods compared are of one model.
#[derive(Clone, Debug)]
pub struct Family {
    pub scale: Scale,
    pub robust: Robust,
    pub correlation: Correlation,
}

/// The errors' scale.
#[derive(Clone, Debug)]
pub enum Scale {
    /// Floor plus relative part estimated, the floor at least `floor_min` (um).
    Estimated { floor_min: f64 },
    /// A stated model (`--noise-um`, rig.toml `[noise]`).
    Stated(NoiseModel),
    /// A stated standard deviation of each point (`dte_pp_sd_um`).
    PerPoint,
}

/// The errors' correlation along speed within a curve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Correlation {
    /// Estimated, kept when the likelihood-ratio test rejects independent errors.
    Auto,
    /// Always estimated.
    Estimated,
    /// Stated length (rpm; 0: independent errors).
    Stated(f64),
}

impl Family {
    fn noise_setting(&self, curves: &Curves) -> Result<NoiseSetting> {
        Ok(match &self.scale {
            Scale::Estimated { floor_min } => NoiseSetting::Estimate(crate::fit::NoiseFreedom {
                floor_min: *floor_min,
                relative: true,
            }),
            Scale::Stated(m) => NoiseSetting::Stated(*m),
            Scale::PerPoint => NoiseSetting::PerPoint(curves.stated_scales().ok_or_else(|| {
                GearError::Numerical("a per-point noise needs dte_pp_sd_um on every point".into())
            })?),
        })
    }

    fn correlation_setting(&self, axis: Axis) -> CorrelationSetting {
        match self.correlation {
            Correlation::Auto => CorrelationSetting::Auto(axis),
            Correlation::Estimated => CorrelationSetting::Estimated(axis),
            Correlation::Stated(l) => CorrelationSetting::Stated(axis, l),
        }
    }

    /// This family with the automatic choices made as M0's fit `m0` made them: Student-t
    /// errors or Gaussian ones, a correlation estimated or independent errors.
    pub fn chosen_by(&self, m0: &Estimate) -> Family {
        let robust = match (self.robust, m0.noise.model.distribution) {
            (Robust::Auto, crate::fit::Distribution::StudentT { .. }) => Robust::On,
            (Robust::Auto, crate::fit::Distribution::Gaussian) => Robust::Off,
            (r, _) => r,
        };
        let correlation = match self.correlation {
            Correlation::Auto if m0.noise.model.correlation_length > 0.0 => Correlation::Estimated,
            Correlation::Auto => Correlation::Stated(0.0),
            c => c,
        };
        Family {
            scale: self.scale.clone(),
            robust,
            correlation,
        }
    }

    /// The family with every parameter held as M0's fit `m0` estimated it, Gaussian: the
    /// scale of a held-out load's STE fit, which the training loads set (its likelihood is
    /// taken under M0's distribution by the caller).
    pub fn held_at(&self, m0: &Estimate) -> Family {
        let scale = match &self.scale {
            Scale::Estimated { .. } | Scale::Stated(_) => Scale::Stated(NoiseModel {
                distribution: crate::fit::Distribution::Gaussian,
                ..m0.noise.model
            }),
            Scale::PerPoint => Scale::PerPoint,
        };
        Family {
            scale,
            robust: Robust::Off,
            correlation: Correlation::Stated(m0.noise.model.correlation_length),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{Curves, EffectParams};
    use crate::discover::compare::tests::set_of;
    use crate::discover::effects::Effect;
    use crate::discover::forward::Globals;
    use crate::fit::Measurement;

    /// A stated STE is a measurement of its own load's STE parameter, in every model's
    /// coordinates: after zeta and omega_n in a training fit, alone in a held-out load's fit;
    /// a load without a statement has none.
    #[test]
    fn a_stated_ste_measures_its_loads_parameter() {
        let (mut setup, _) = set_of(2, &[3780.0, 2835.0, 1890.0]);
        setup.curves[0].stated_ste = Some((0.3, 0.05));
        setup.curves[2].stated_ste = Some((2.5, 0.1));
        let mask = vec![vec![true; 2]; 3];
        let training = Curves::new(&setup, &[0, 2], &mask, EffectParams::None);
        let m = |param, value, sd| Measurement { param, value, sd };
        assert_eq!(
            training.measurements(),
            vec![m(2, 0.3, 0.05), m(3, 2.5, 0.1)]
        );
        let g = Globals {
            zeta: 0.02,
            omega_n_hz: 2000.0,
        };
        assert_eq!(
            Curves::ste_of(&setup, 2, &mask, g, Effect::none()).measurements(),
            vec![m(0, 2.5, 0.1)]
        );
        assert!(Curves::ste_of(&setup, 1, &mask, g, Effect::none())
            .measurements()
            .is_empty());
    }
}
