//! A memo of the forward model's predicted curves, by their exact inputs. A run asks for the same
//! curve at the same parameters many times (a fit's start, a Jacobian's base, the report); a
//! prediction is deterministic in the curve's speeds and load and the parameters, so the stored
//! curve changes no output, only when it is computed. `quick_cache` is concurrent (predictions
//! come from every thread at once) and bounded by weight (points), so a large set cannot overgrow.

use super::effects::{Candidate, Effect};
use super::forward::{Curve, CurvePrediction, Globals};
use quick_cache::sync::Cache;
use quick_cache::Weighter;

/// Points of predicted curves the memo holds, about 60 bytes each (12 MB): more than a run on
/// a 50 rpm grid predicts in all, so it finds every earlier curve; a larger set evicts the
/// least used.
const MEMO_POINTS: u64 = 200_000;

/// Everything a [`super::forward::predict`] of one curve depends on, by the bits of each number.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
struct Key {
    load_n: u64,
    design_load_n: u64,
    speeds_rpm: Vec<u64>,
    zeta: u64,
    omega_n_hz: u64,
    ste_um: u64,
    candidate: Option<Candidate>,
    delta: Vec<u64>,
}

/// A curve weighs its number of points (at least 1, as `quick_cache` ignores zero weights when
/// it evicts).
#[derive(Clone)]
struct Points;

impl Weighter<Key, CurvePrediction> for Points {
    fn weight(&self, _key: &Key, val: &CurvePrediction) -> u64 {
        (val.dte_pp_um.len() as u64).max(1)
    }
}

/// Predicted curves of one set by their exact inputs. A clone starts empty: the clone's curves
/// may be changed, and the memo's key holds only what a prediction reads.
pub struct PredictionMemo(Cache<Key, CurvePrediction, Points>);

impl PredictionMemo {
    pub fn new() -> Self {
        PredictionMemo(Cache::with_weighter(
            (MEMO_POINTS / 64) as usize,
            MEMO_POINTS,
            Points,
        ))
    }

    /// The stored prediction of `curve` at these parameters, or `predict`'s, stored when it
    /// succeeds. Two threads asking at once may both compute it; they get the same curve.
    pub fn get_or_predict<E>(
        &self,
        curve: &Curve,
        design_load_n: f64,
        g: Globals,
        ste_um: f64,
        effect: &Effect,
        predict: impl FnOnce() -> Result<CurvePrediction, E>,
    ) -> Result<CurvePrediction, E> {
        let key = Key {
            load_n: curve.load_n.to_bits(),
            design_load_n: design_load_n.to_bits(),
            speeds_rpm: curve.speeds_rpm.iter().map(|v| v.to_bits()).collect(),
            zeta: g.zeta.to_bits(),
            omega_n_hz: g.omega_n_hz.to_bits(),
            ste_um: ste_um.to_bits(),
            candidate: effect.candidate,
            delta: effect.delta.iter().map(|v| v.to_bits()).collect(),
        };
        if let Some(p) = self.0.get(&key) {
            return Ok(p);
        }
        let p = predict()?;
        self.0.insert(key, p.clone());
        Ok(p)
    }
}

impl Clone for PredictionMemo {
    fn clone(&self) -> Self {
        Self::new()
    }
}

impl std::fmt::Debug for PredictionMemo {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "PredictionMemo({} curves)", self.0.len())
    }
}
