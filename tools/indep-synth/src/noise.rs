//! Measurement-noise families, drawn with this crate's own generator (ChaCha20 from rand_chacha,
//! normal and Student-t from rand_distr).

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
}

impl Family {
    pub const ALL: [Family; 4] = [
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
        }
    }
    pub fn parse(s: &str) -> Result<Family, String> {
        match s {
            "constant" => Ok(Family::Constant),
            "relative" => Ok(Family::Relative),
            "student-t" | "student_t" | "t" => Ok(Family::StudentT),
            "quantized" => Ok(Family::Quantized),
            _ => Err(format!(
                "unknown noise family '{s}' (constant, relative, student-t, quantized)"
            )),
        }
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
        }
    }
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

/// Adds noise to noise-free levels (um). A reading is kept only if non-negative: a negative draw
/// is drawn again (so the noise is a distribution truncated at -level; at Munro's levels and
/// noise this almost never happens). Quantized readings are then rounded to the grid (a reading
/// may round to 0, a valid pp).
pub fn apply(spec: &NoiseSpec, levels: &[f64], stats: &mut FloorStats) -> Vec<f64> {
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
