//! Fitted parameters and their transforms. The optimiser works on unconstrained internal
//! coordinates u; each parameter maps u to its value p, so a positive parameter (a damping
//! ratio, a frequency, a noise floor) can never step to zero or below, and a bounded one never
//! leaves its range. Wald intervals are formed in u and mapped back, so they respect the same
//! constraints (Bates & Watts 1988, Sec. 3.5: reparametrisation for better-behaved intervals).

use serde::Serialize;

/// How a parameter's value p depends on its internal coordinate u.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(rename_all = "snake_case", tag = "kind")]
pub enum Transform {
    /// p = exp(u): strictly positive, steps are relative.
    Log,
    /// p = u: any sign (an effect nested at zero).
    Signed,
    /// p = lo + (hi - lo) / (1 + exp(-u)): strictly inside (lo, hi).
    Bounded { lo: f64, hi: f64 },
}

impl Transform {
    /// Value p of internal coordinate u.
    pub fn value(self, u: f64) -> f64 {
        match self {
            Transform::Log => u.exp(),
            Transform::Signed => u,
            Transform::Bounded { lo, hi } => lo + (hi - lo) / (1.0 + (-u).exp()),
        }
    }

    /// Internal coordinate of value p; None where p is outside the transform's range.
    pub fn internal(self, p: f64) -> Option<f64> {
        match self {
            Transform::Log => (p > 0.0 && p.is_finite()).then(|| p.ln()),
            Transform::Signed => p.is_finite().then_some(p),
            Transform::Bounded { lo, hi } => {
                let s = (p - lo) / (hi - lo);
                (s > 0.0 && s < 1.0).then(|| (s / (1.0 - s)).ln())
            }
        }
    }

    /// dp/du at u.
    pub fn derivative(self, u: f64) -> f64 {
        match self {
            Transform::Log => u.exp(),
            Transform::Signed => 1.0,
            Transform::Bounded { lo, hi } => {
                let e = (-u.abs()).exp();
                (hi - lo) * e / ((1.0 + e) * (1.0 + e))
            }
        }
    }
}

/// One fitted parameter.
#[derive(Clone, Debug, Serialize)]
pub struct Param {
    pub name: String,
    /// Starting value (inside the transform's range).
    pub start: f64,
    pub transform: Transform,
    /// Typical size of the parameter: the finite-difference step of a signed parameter is
    /// 1e-4 max(|p|, scale), and below a change of `scale` the residuals count as not seeing it.
    pub scale: f64,
    /// The least value the model is trusted at: a profile interval ([`super::profile_interval`])
    /// still inside there, or whose stepped end (the Wald end) lies below it, is unbounded
    /// below, and the profile goes no lower. A model that cannot be evaluated below some value
    /// (a fit through simulated sweeps refuses zeta where its transients would take minutes)
    /// otherwise has its profile halve towards that value with ever slower fits, to report an
    /// end that is the floor's, not the data's.
    pub profile_floor: Option<f64>,
}

impl Param {
    /// A strictly positive parameter (log transform).
    pub fn positive(name: &str, start: f64) -> Param {
        Param {
            name: name.into(),
            start,
            transform: Transform::Log,
            scale: start.abs(),
            profile_floor: None,
        }
    }

    /// A parameter of any sign with typical size `scale`.
    pub fn signed(name: &str, start: f64, scale: f64) -> Param {
        Param {
            name: name.into(),
            start,
            transform: Transform::Signed,
            scale,
            profile_floor: None,
        }
    }

    /// This parameter with its profile interval going no lower than `floor` (see
    /// [`Param::profile_floor`]).
    pub fn with_profile_floor(self, floor: f64) -> Param {
        Param {
            profile_floor: Some(floor),
            ..self
        }
    }
}

/// The parameters `params` starting from `values` instead (same names, transforms, scales).
pub fn restarted(params: &[Param], values: &[f64]) -> Vec<Param> {
    params
        .iter()
        .zip(values)
        .map(|(d, v)| Param {
            start: *v,
            ..d.clone()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn transforms_round_trip_and_differentiate() {
        for t in [
            Transform::Log,
            Transform::Signed,
            Transform::Bounded { lo: 0.5, hi: 2.0 },
        ] {
            for p in [0.7, 1.0, 1.9] {
                let u = t.internal(p).unwrap();
                assert!((t.value(u) - p).abs() < 1e-12, "{t:?} {p}");
                let h = 1e-6;
                let fd = (t.value(u + h) - t.value(u - h)) / (2.0 * h);
                assert!((fd - t.derivative(u)).abs() < 1e-8, "{t:?} {p}");
            }
        }
        assert_eq!(Transform::Log.internal(0.0), None);
        assert_eq!(Transform::Bounded { lo: 0.0, hi: 1.0 }.internal(1.0), None);
    }
}
