//! The measurement noise of a discovery run as its reports and point-wise rules read it: a scale
//! sigma_ij at every point of every curve from the engine's noise model (`crate::fit::NoiseModel`:
//! a floor plus a part proportional to the level, Gaussian or Student-t, correlated along speed),
//! stated by the data set or fitted with M0. Stated noise, in the order `validate munro` takes it
//! (`validate::noise_setting`): `--noise-um` (a constant), a `dte_pp_sd_um` column on every
//! point, rig.toml `[noise]` (`floor_um`, `relative`, `correlation_rpm`); `[noise] reading_um`
//! alone bounds the fitted floor below.

use crate::fit::NoiseModel;
use serde::Serialize;

/// How the noise of a set is known.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(rename_all = "snake_case", tag = "kind")]
pub enum NoiseOrigin {
    /// Stated constant, `--noise-um`.
    StatedOption,
    /// Stated in rig.toml `[noise]`.
    StatedRig,
    /// A `dte_pp_sd_um` column on every point.
    PerPoint,
    /// Estimated with M0's fit by restricted maximum likelihood, the floor at least
    /// `floor_min`.
    Fitted { floor_min: f64 },
}

impl NoiseOrigin {
    /// Human wording for the reports.
    pub fn describe(&self) -> String {
        match self {
            NoiseOrigin::StatedOption => "stated (--noise-um)".into(),
            NoiseOrigin::StatedRig => "stated in rig.toml [noise]".into(),
            NoiseOrigin::PerPoint => "stated per point (dte_pp_sd_um column)".into(),
            NoiseOrigin::Fitted { floor_min } if *floor_min > 0.0 => format!(
                "estimated with M0's fit by restricted maximum likelihood (floor at least the stated reading uncertainty {floor_min} µm)"
            ),
            NoiseOrigin::Fitted { .. } => {
                "estimated with M0's fit by restricted maximum likelihood".into()
            }
        }
    }
}

/// The noise of a discovery run: a model, or stated per-point scales.
#[derive(Clone, Debug, Serialize)]
pub struct DiscoveryNoise {
    pub origin: NoiseOrigin,
    /// The model (for per-point noise: unit floor, no relative part).
    pub model: NoiseModel,
    /// Stated scale of every point, per curve (per-point noise only).
    #[serde(skip)]
    pub per_point: Option<Vec<Vec<f64>>>,
}

/// Per curve, per point: the same shape as the curves.
pub type Scales = Vec<Vec<f64>>;

impl DiscoveryNoise {
    /// A model.
    pub fn stated(origin: NoiseOrigin, model: NoiseModel) -> Self {
        DiscoveryNoise {
            origin,
            model,
            per_point: None,
        }
    }

    /// Stated scales of every point.
    pub fn per_point(scales: Scales) -> Self {
        DiscoveryNoise {
            per_point: Some(scales),
            ..DiscoveryNoise::stated(NoiseOrigin::PerPoint, NoiseModel::constant(1.0))
        }
    }

    /// The noise scale at every point at the model levels `levels` (per curve, per point).
    pub fn scales(&self, levels: &[Vec<f64>]) -> Scales {
        levels
            .iter()
            .enumerate()
            .map(|(i, c)| {
                c.iter()
                    .enumerate()
                    .map(|(j, l)| self.scale_at(i, j, *l))
                    .collect()
            })
            .collect()
    }

    /// The noise scale at point j of curve i at the model level `level`: the scale, not the
    /// standard deviation (which Student-t errors of 2 degrees of freedom or fewer lack).
    pub fn scale_at(&self, i: usize, j: usize, level: f64) -> f64 {
        match &self.per_point {
            Some(s) => s[i][j],
            None => self.model.scale(level),
        }
    }
}

/// How the tails of the errors are chosen.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TailChoice {
    /// Gaussian errors.
    Gaussian,
    /// Student-t errors when the likelihood-ratio test of M0's fit rejects Gaussian ones at 5%.
    Auto,
}
