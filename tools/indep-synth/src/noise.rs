//! Measurement-noise families, drawn with this crate's own generator (ChaCha20 from rand_chacha,
//! normal and Student-t from rand_distr).
//!
//! Four families draw every point independently (constant, relative, student-t, quantized). The
//! fifth, `correlated`, has the scale of `relative` and Gaussian errors correlated along the speed
//! axis within each curve (a stationary AR(1) of the standardized errors in increasing speed), as
//! the reading of a drawn line or a rig's slow drift gives; curves are independent of each other.

use rand::Rng;
use rand_chacha::rand_core::SeedableRng;
use rand_chacha::ChaCha20Rng;
use rand_distr::{Distribution, StandardNormal, StudentT};
use serde::{Deserialize, Serialize};

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Family {
    Constant,
    Relative,
    StudentT,
    Quantized,
    /// Scale of `relative`, Gaussian, AR(1) along speed within each curve (see [`Correlation`]).
    Correlated,
}

impl Family {
    /// The families whose points are drawn independently: the default rotation of batches.
    pub const INDEPENDENT: [Family; 4] = [
        Family::Constant,
        Family::Relative,
        Family::StudentT,
        Family::Quantized,
    ];
    pub fn name(self) -> &'static str {
        match self {
            Family::Constant => "constant",
            Family::Relative => "relative",
            Family::StudentT => "student-t",
            Family::Quantized => "quantized",
            Family::Correlated => "correlated",
        }
    }
    pub fn parse(s: &str) -> Result<Family, String> {
        match s {
            "constant" => Ok(Family::Constant),
            "relative" => Ok(Family::Relative),
            "student-t" | "student_t" | "t" => Ok(Family::StudentT),
            "quantized" => Ok(Family::Quantized),
            "correlated" => Ok(Family::Correlated),
            _ => Err(format!(
                "unknown noise family '{s}' (constant, relative, student-t, quantized, correlated)"
            )),
        }
    }
}

/// Lag-one correlation on the grid of the correlated family when neither form is given.
pub const DEFAULT_RHO: f64 = 0.6;
/// Largest lag-one correlation accepted (1 would be one offset per curve, not a process).
pub const MAX_RHO: f64 = 0.999;

/// How the standardized errors z_i of one curve are correlated along speed. In both forms they
/// are a stationary Gaussian AR(1) in increasing speed, z_1 ~ N(0, 1),
/// z_k = phi_k z_(k-1) + sqrt(1 - phi_k^2) eps_k with eps_k independent N(0, 1); only phi_k
/// differs.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "form", rename_all = "snake_case")]
pub enum Correlation {
    /// phi_k = rho at every step: rho is the correlation of neighbouring points of the grid
    /// (index lag one), whatever their spacing in rpm. On a non-uniform grid this is deliberately
    /// not an exponential kernel in rpm.
    GridLag1 { rho: f64 },
    /// phi_k = exp(-(s_k - s_(k-1)) / length_rpm): corr(z_i, z_j) = exp(-|s_i - s_j| / length_rpm),
    /// an Ornstein-Uhlenbeck process sampled at the actual speeds.
    LengthRpm { length_rpm: f64 },
}

impl Correlation {
    /// The correlation of the command-line flags: at most one of `rho` (on the grid) and
    /// `length_rpm` (in rpm), [`DEFAULT_RHO`] on the grid when neither is given. Refuses rho
    /// outside [0, MAX_RHO], a length that is not finite and positive, and both together.
    pub fn from_flags(rho: Option<f64>, length_rpm: Option<f64>) -> Result<Correlation, String> {
        let c = match (rho, length_rpm) {
            (Some(_), Some(_)) => {
                return Err(
                    "give the correlation either on the grid (--noise-rho) or in rpm (--noise-corr-length-rpm), not both".into(),
                )
            }
            (Some(rho), None) => Correlation::GridLag1 { rho },
            (None, Some(length_rpm)) => Correlation::LengthRpm { length_rpm },
            (None, None) => Correlation::GridLag1 { rho: DEFAULT_RHO },
        };
        c.check()?;
        Ok(c)
    }

    /// Checks the value's range (see [`Correlation::from_flags`]).
    pub fn check(&self) -> Result<(), String> {
        match *self {
            Correlation::GridLag1 { rho } => {
                if !(0.0..=MAX_RHO).contains(&rho) {
                    return Err(format!(
                        "--noise-rho {rho}: the lag-one correlation on the grid must lie in [0, {MAX_RHO}]"
                    ));
                }
            }
            Correlation::LengthRpm { length_rpm } => {
                if !(length_rpm.is_finite() && length_rpm > 0.0) {
                    return Err(format!(
                        "--noise-corr-length-rpm {length_rpm}: the correlation length must be a finite number of rpm > 0"
                    ));
                }
            }
        }
        Ok(())
    }

    /// phi_k of each point of a curve at these speeds (increasing): phi_0 = 0 (the first point
    /// is a fresh N(0, 1) draw), phi_k the correlation of point k with point k - 1. Err if the
    /// speeds do not increase (the process runs in increasing speed).
    pub fn phis(&self, speeds_rpm: &[f64]) -> Result<Vec<f64>, String> {
        // (also refuses NaN speeds)
        if !speeds_rpm.windows(2).all(|w| w[1] > w[0]) {
            return Err("correlated noise: the speeds of a curve must increase".into());
        }
        let step = |k: usize| match *self {
            Correlation::GridLag1 { rho } => rho,
            Correlation::LengthRpm { length_rpm } => {
                (-(speeds_rpm[k] - speeds_rpm[k - 1]) / length_rpm).exp()
            }
        };
        Ok((0..speeds_rpm.len())
            .map(|k| if k == 0 { 0.0 } else { step(k) })
            .collect())
    }

    /// Text for rig.toml's [source] `uncertainty`.
    pub fn describe(&self) -> String {
        match *self {
            Correlation::GridLag1 { rho } => format!(
                "lag-one correlation {rho} between neighbouring speeds of the grid (z_k = {rho} z_(k-1) + sqrt(1 - {rho}^2) eps_k, whatever the spacing)"
            ),
            Correlation::LengthRpm { length_rpm } => format!(
                "corr(z_i, z_j) = exp(-|s_i - s_j| / {length_rpm} rpm) (z_k = phi_k z_(k-1) + sqrt(1 - phi_k^2) eps_k, phi_k = exp(-(s_k - s_(k-1)) / {length_rpm}))"
            ),
        }
    }
}

/// Draws tries of one standardized error before the point is set to its bound.
const MAX_TRIES: usize = 1000;

/// One stationary Gaussian AR(1) path z along a curve: z_0 = eps_0, z_k = phi_k z_(k-1) +
/// sqrt(1 - phi_k^2) eps_k (`phis` from [`Correlation::phis`]), the eps_k drawn in order from `rng`.
///
/// `lower[k]` is the smallest admissible z_k (a reading must stay >= 0: -level / SD). A z_k below
/// it has its innovation eps_k drawn again (counted in `stats.redrawn`; the path goes on from the
/// accepted value, so the process is truncated at the floor, as the other families' draws are);
/// after [`MAX_TRIES`] tries z_k = lower[k] (`stats.clipped_to_zero`). At the levels of Munro's
/// and Kubo's curves lower[k] is below -10 and no draw is ever redrawn.
pub fn ar1_path<R: Rng>(
    rng: &mut R,
    phis: &[f64],
    lower: &[f64],
    stats: &mut FloorStats,
) -> Vec<f64> {
    debug_assert_eq!(phis.len(), lower.len());
    let mut z = Vec::with_capacity(phis.len());
    let mut prev = 0.0;
    for (&phi, &lo) in phis.iter().zip(lower) {
        let innovation_sd = (1.0 - phi * phi).sqrt();
        let mut value = None;
        for _ in 0..MAX_TRIES {
            let eps: f64 = rng.sample(StandardNormal);
            let zk = phi * prev + innovation_sd * eps;
            if zk >= lo {
                value = Some(zk);
                break;
            }
            stats.redrawn += 1;
        }
        let zk = value.unwrap_or_else(|| {
            stats.clipped_to_zero += 1;
            lo
        });
        z.push(zk);
        prev = zk;
    }
    z
}

/// The smallest standardized error that keeps a reading of this level and SD non-negative.
pub fn lower_z(level: f64, sd: f64) -> f64 {
    if sd > 0.0 {
        -level / sd
    } else {
        f64::NEG_INFINITY
    }
}

#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct NoiseSpec {
    pub family: Family,
    /// Floor: the SD of the constant family, and the level-independent part of the others (um).
    pub floor_um: f64,
    /// Relative part of the level-dependent families (fraction of the noise-free level).
    pub relative: f64,
    /// Degrees of freedom of the Student-t family.
    pub dof: f64,
    /// Reading grid of the quantized family (um).
    pub quantum_um: f64,
    pub seed: u64,
    /// Correlation along speed of the correlated family (absent for the other families, whose
    /// truth records are unchanged by it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub correlation: Option<Correlation>,
}

impl NoiseSpec {
    /// Standard deviation at a noise-free level (um).
    pub fn sd(&self, level: f64) -> f64 {
        match self.family {
            Family::Constant => self.floor_um,
            _ => (self.floor_um.powi(2) + (self.relative * level).powi(2)).sqrt(),
        }
    }

    /// One-line description for rig.toml's [source].
    pub fn describe(&self) -> String {
        match self.family {
            Family::Constant => format!(
                "synthetic noise, constant family: Gaussian, SD {} um at every point",
                self.floor_um
            ),
            Family::Relative => format!(
                "synthetic noise, relative family: Gaussian, SD_i = sqrt({}^2 + ({} x level_i)^2) um, level_i the noise-free pp",
                self.floor_um, self.relative
            ),
            Family::StudentT => format!(
                "synthetic noise, student-t family: Student-t with {} dof scaled to SD_i = sqrt({}^2 + ({} x level_i)^2) um",
                self.dof, self.floor_um, self.relative
            ),
            Family::Quantized => format!(
                "synthetic noise, quantized family: Gaussian, SD_i = sqrt({}^2 + ({} x level_i)^2) um, then read to a {} um grid",
                self.floor_um, self.relative, self.quantum_um
            ),
            Family::Correlated => format!(
                "synthetic noise, correlated family: Gaussian, SD_i = sqrt({}^2 + ({} x level_i)^2) um, level_i the noise-free pp; within each load's curve the standardized errors z_i = e_i / SD_i are a stationary AR(1) in increasing speed, {}; curves independent",
                self.floor_um,
                self.relative,
                self.correlation().describe()
            ),
        }
    }

    /// The correlation of the correlated family ([`DEFAULT_RHO`] on the grid if none was set).
    pub fn correlation(&self) -> Correlation {
        self.correlation
            .unwrap_or(Correlation::GridLag1 { rho: DEFAULT_RHO })
    }
}

/// One curve's noise-free levels at its speeds (increasing).
#[derive(Clone, Copy, Debug)]
pub struct Curve<'a> {
    pub speeds_rpm: &'a [f64],
    pub levels: &'a [f64],
}

/// Readings of a set's curves, and for the correlated family the standardized errors drawn.
#[derive(Clone, Debug)]
pub struct Drawn {
    /// One vector of readings per curve, in the curves' order.
    pub values: Vec<Vec<f64>>,
    /// Correlated family: the standardized errors z of each curve (after any redraw); None for
    /// the independent families.
    pub z: Option<Vec<Vec<f64>>>,
}

/// Adds noise to the noise-free levels of a set's curves.
///
/// Independent families: one stream over the points of every curve in order, exactly [`apply`] on
/// the concatenated levels. Correlated family: for each curve in order, one AR(1) path of
/// standardized errors drawn from the same stream ([`ar1_path`]), reading_i = level_i + SD_i z_i.
pub fn apply_curves(
    spec: &NoiseSpec,
    curves: &[Curve<'_>],
    stats: &mut FloorStats,
) -> Result<Drawn, String> {
    if curves.iter().any(|c| c.speeds_rpm.len() != c.levels.len()) {
        return Err("noise: a curve has not as many levels as speeds".into());
    }
    if spec.family != Family::Correlated {
        let levels: Vec<f64> = curves
            .iter()
            .flat_map(|c| c.levels.iter().copied())
            .collect();
        let mut flat = apply(spec, &levels, stats).into_iter();
        let values = curves
            .iter()
            .map(|c| flat.by_ref().take(c.levels.len()).collect())
            .collect();
        return Ok(Drawn { values, z: None });
    }
    let correlation = spec.correlation();
    correlation.check()?;
    let mut rng = ChaCha20Rng::seed_from_u64(spec.seed);
    let mut values = Vec::with_capacity(curves.len());
    let mut zs = Vec::with_capacity(curves.len());
    for c in curves {
        let phis = correlation.phis(c.speeds_rpm)?;
        let sds: Vec<f64> = c.levels.iter().map(|&l| spec.sd(l)).collect();
        let lower: Vec<f64> = c
            .levels
            .iter()
            .zip(&sds)
            .map(|(&l, &sd)| lower_z(l, sd))
            .collect();
        let z = ar1_path(&mut rng, &phis, &lower, stats);
        let v: Vec<f64> = c
            .levels
            .iter()
            .zip(&sds)
            .zip(&z)
            .map(|((&level, &sd), &zk)| (level + sd * zk).max(0.0))
            .collect();
        stats.zero_readings += v.iter().filter(|&&y| y == 0.0).count();
        values.push(v);
        zs.push(z);
    }
    Ok(Drawn {
        values,
        z: Some(zs),
    })
}

/// Counters of what happened at the floor (pp >= 0).
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct FloorStats {
    /// Draws that gave a negative pp and were drawn again (the noise is truncated at -level).
    pub redrawn: usize,
    /// Points that still had no non-negative draw after 1000 tries and were set to 0.
    pub clipped_to_zero: usize,
    /// Points whose reading is exactly 0 (quantized family: rounded down to 0).
    pub zero_readings: usize,
}

/// Adds independent noise to noise-free levels (um). A reading is kept only if non-negative: a
/// negative draw is drawn again (so the noise is a distribution truncated at -level; at Munro's
/// levels and noise this almost never happens). Quantized readings are then rounded to the grid
/// (a reading may round to 0, a valid pp). The correlated family needs the curves and their
/// speeds: use [`apply_curves`] (here it would draw every point independently).
pub fn apply(spec: &NoiseSpec, levels: &[f64], stats: &mut FloorStats) -> Vec<f64> {
    debug_assert_ne!(spec.family, Family::Correlated, "use apply_curves");
    let mut rng = ChaCha20Rng::seed_from_u64(spec.seed);
    let t = StudentT::new(spec.dof).expect("dof");
    let t_sd = if spec.dof > 2.0 {
        (spec.dof / (spec.dof - 2.0)).sqrt()
    } else {
        1.0
    };
    levels
        .iter()
        .map(|&level| {
            let sd = spec.sd(level);
            let mut value = None;
            for _ in 0..1000 {
                let z: f64 = match spec.family {
                    Family::StudentT => t.sample(&mut rng) / t_sd,
                    _ => rng.sample(StandardNormal),
                };
                let y = level + sd * z;
                if y >= 0.0 {
                    value = Some(y);
                    break;
                }
                stats.redrawn += 1;
            }
            let mut y = value.unwrap_or_else(|| {
                stats.clipped_to_zero += 1;
                0.0
            });
            if spec.family == Family::Quantized {
                y = (y / spec.quantum_um).round() * spec.quantum_um;
            }
            if y == 0.0 {
                stats.zero_readings += 1;
            }
            y
        })
        .collect()
}
