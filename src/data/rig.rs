//! The rig description `rig.toml` of a data set (design.md section 4): the `[rig]` table (units in
//! the key names), an optional `[ste]` table, an optional `[noise]` table, an optional
//! `[geometry]` table (read by [`load_rig_with_geometry`]) and the `[source]` provenance. docs/data-format.md documents every key.

use super::errors::{data_error, read_text};
use super::geometry::GearGeometry;
use super::same_load::same_load;
use super::source::Source;
use super::toml_doc::TomlDoc;
use crate::error::{readable, GearError, Result, WHOLE_FILE};
use crate::model::{Dimensional, MAX_DTE_UM, MAX_FORCE, MAX_LOAD_N};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The `[rig]` table: geometry and operating point of the test gear pair. Every key carries its
/// unit; unknown keys (e.g. `backlash` without `_mm`) are rejected.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Rig {
    /// Name of the rig, e.g. "Munro (1962) four-square rig".
    pub name: String,
    /// Number of teeth of the pinion (the mesh frequency is pinion_teeth x shaft speed), >= 5.
    pub pinion_teeth: u32,
    /// Number of teeth of the gear, >= 5.
    pub gear_teeth: u32,
    /// Module in millimetres (25.4 / diametral pitch in 1/in), in [0.05, 100].
    pub module_mm: f64,
    /// Pressure angle in degrees, in (10, 35).
    pub pressure_angle_deg: f64,
    /// Face width in millimetres, in [0.1, 2000].
    pub face_width_mm: f64,
    /// Design load in newtons (mean force F_bar_m transmitted at the design point), > 0.
    pub design_load_n: f64,
    /// Total backlash 2b in millimetres, in [0.001, 10].
    pub backlash_mm: f64,
    /// Mesh stiffness k_h in N/um if known; otherwise estimated (see `model::Dimensional`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mesh_stiffness_n_per_um: Option<f64>,
    /// Transverse contact ratio eps_alpha if known; otherwise computed from standard geometry.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contact_ratio: Option<f64>,
    /// Damping ratio zeta if given (otherwise it is fitted), in (0, 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub zeta: Option<f64>,
    /// Natural frequency omega_n in Hz if given (otherwise it is fitted), > 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub omega_n_hz: Option<f64>,
    /// Kubo: the load in newtons the curve was measured at (default `design_load_n`), > 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub test_load_n: Option<f64>,
}

/// The first problem found in a rig: key, offending value and reason.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct RigProblem {
    pub key: &'static str,
    pub value: f64,
    pub reason: &'static str,
}

impl std::fmt::Display for RigProblem {
    /// "key = value: reason", as a located error's message.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} = {}: {}",
            self.key,
            readable(self.value),
            self.reason
        )
    }
}

/// `Some(problem)` unless `ok(value)`.
pub(super) fn require(
    key: &'static str,
    value: f64,
    ok: bool,
    reason: &'static str,
) -> Option<RigProblem> {
    (!ok).then_some(RigProblem { key, value, reason })
}

/// Positive and finite.
pub(super) fn positive(key: &'static str, value: f64) -> Option<RigProblem> {
    require(
        key,
        value,
        value.is_finite() && value > 0.0,
        "must be a positive finite number",
    )
}

/// At most `hi` (NaN passes: [`positive`] reports it first).
pub(super) fn at_most(
    key: &'static str,
    value: f64,
    hi: f64,
    reason: &'static str,
) -> Option<RigProblem> {
    require(key, value, value.is_nan() || value <= hi, reason)
}

/// At least `lo` (NaN passes: [`positive`] reports it first).
pub(super) fn at_least(
    key: &'static str,
    value: f64,
    lo: f64,
    reason: &'static str,
) -> Option<RigProblem> {
    require(key, value, value.is_nan() || value >= lo, reason)
}

/// Smallest module, mm: the finest instrument and watch gears (ISO 54 starts at 0.05 mm).
pub const MIN_MODULE_MM: f64 = 0.05;
/// Smallest face width, mm.
pub const MIN_FACE_WIDTH_MM: f64 = 0.1;
/// Smallest backlash 2b, mm (1 um): below the flanks' roughness and profile errors.
pub const MIN_BACKLASH_MM: f64 = 0.001;

/// Tooth counts above this are a typing mistake (4294967295 teeth were accepted).
const MANY_TEETH: &str = "more than 1000 teeth: not a practical spur gear";

/// An optional value, checked with `check` when present.
pub(super) fn optional(
    value: Option<f64>,
    check: impl Fn(f64) -> Option<RigProblem>,
) -> Option<RigProblem> {
    value.and_then(check)
}

impl Rig {
    /// The first out-of-range value, if any (see each field for its range).
    pub(crate) fn first_problem(&self) -> Option<RigProblem> {
        self.gear_problem()
            .or_else(|| self.stated_problem())
            .or_else(|| self.scale_problem())
    }

    /// The design load's dimensionless mean force F_m = W / (k_h b) above the model's
    /// [`MAX_FORCE`]: each value in range, together they leave the backlash negligible.
    fn scale_problem(&self) -> Option<RigProblem> {
        // A contact ratio below 1 fails here; `Rig::dimensional` reports it.
        let dim = Dimensional::new(&self.gear_spec()).ok()?;
        require(
            "design_load_n",
            self.design_load_n,
            dim.mean_force(self.design_load_n) <= MAX_FORCE,
            "over the mesh stiffness times half the backlash this load is a mean force F_m above \
             1e9: the backlash is negligible beside the teeth's deflection (raise backlash_mm or \
             mesh_stiffness_n_per_um, or check the load's unit)",
        )
    }

    /// The first out-of-range value of the gears, the design load and the backlash.
    fn gear_problem(&self) -> Option<RigProblem> {
        let teeth = "fewer than 5 teeth: not a practical involute gear";
        let z1 = self.pinion_teeth as f64;
        let z2 = self.gear_teeth as f64;
        let alpha = self.pressure_angle_deg;
        require(
            "name",
            self.name.trim().len() as f64,
            !self.name.trim().is_empty(),
            "must not be empty",
        )
        .or_else(|| require("pinion_teeth", z1, self.pinion_teeth >= 5, teeth))
        .or_else(|| require("gear_teeth", z2, self.gear_teeth >= 5, teeth))
        .or_else(|| require("pinion_teeth", z1, self.pinion_teeth <= 1000, MANY_TEETH))
        .or_else(|| require("gear_teeth", z2, self.gear_teeth <= 1000, MANY_TEETH))
        .or_else(|| positive("module_mm", self.module_mm))
        .or_else(|| {
            at_least(
                "module_mm",
                self.module_mm,
                MIN_MODULE_MM,
                "a module below 0.05 mm (the finest instrument gears) gives teeth too small for \
                 their tip relief, stiffness and backlash to mean anything: a unit mistake?",
            )
        })
        .or_else(|| {
            at_most(
                "module_mm",
                self.module_mm,
                100.0,
                "a module above 100 mm is a unit mistake",
            )
        })
        .or_else(|| {
            require(
                "pressure_angle_deg",
                alpha,
                alpha.is_finite() && alpha > 10.0 && alpha < 35.0,
                "must be in (10, 35) degrees",
            )
        })
        .or_else(|| positive("face_width_mm", self.face_width_mm))
        .or_else(|| {
            at_least(
                "face_width_mm",
                self.face_width_mm,
                MIN_FACE_WIDTH_MM,
                "a face narrower than 0.1 mm is not a gear's (its stiffness, the load over it, \
                 would deflect the teeth by millimetres): a unit mistake?",
            )
        })
        .or_else(|| {
            at_most(
                "face_width_mm",
                self.face_width_mm,
                2000.0,
                "a face width above 2000 mm is a unit mistake",
            )
        })
        .or_else(|| positive("design_load_n", self.design_load_n))
        .or_else(|| {
            at_most(
                "design_load_n",
                self.design_load_n,
                MAX_LOAD_N,
                "a load above 1e8 N is a unit mistake",
            )
        })
        .or_else(|| positive("backlash_mm", self.backlash_mm))
        .or_else(|| {
            at_least(
                "backlash_mm",
                self.backlash_mm,
                MIN_BACKLASH_MM,
                "a backlash below 0.001 mm (1 um) is finer than the flanks' roughness and profile \
                 errors, and the model's forces scale with its inverse: state at least 0.001 mm \
                 (a unit mistake?)",
            )
        })
        .or_else(|| {
            at_most(
                "backlash_mm",
                self.backlash_mm,
                10.0,
                "a backlash above 10 mm is a unit mistake",
            )
        })
    }

    /// The first out-of-range value of the optional stated parameters (stiffness, contact
    /// ratio, zeta, omega_n, test load).
    fn stated_problem(&self) -> Option<RigProblem> {
        optional(self.mesh_stiffness_n_per_um, |v| {
            positive("mesh_stiffness_n_per_um", v).or_else(|| {
                require(
                    "mesh_stiffness_n_per_um",
                    v,
                    (0.01..=1e5).contains(&v),
                    "mesh stiffness must be in [0.01, 1e5] N/um (steel spur gears: 5 to 2000)",
                )
            })
        })
        .or_else(|| {
            optional(self.contact_ratio, |v| {
                require(
                    "contact_ratio",
                    v,
                    v.is_finite() && (1.0..=3.0).contains(&v),
                    "transverse contact ratio must be in [1, 3]",
                )
            })
        })
        .or_else(|| {
            optional(self.zeta, |v| {
                require(
                    "zeta",
                    v,
                    v.is_finite() && v > 0.0 && v < 1.0,
                    "damping ratio must be in (0, 1)",
                )
            })
        })
        .or_else(|| {
            optional(self.omega_n_hz, |v| {
                positive("omega_n_hz", v).or_else(|| {
                    require(
                        "omega_n_hz",
                        v,
                        (1.0..=1e6).contains(&v),
                        "natural frequency must be in [1, 1e6] Hz",
                    )
                })
            })
        })
        .or_else(|| {
            optional(self.test_load_n, |v| {
                positive("test_load_n", v).or_else(|| {
                    at_most(
                        "test_load_n",
                        v,
                        MAX_LOAD_N,
                        "a load above 1e8 N is a unit mistake",
                    )
                })
            })
        })
    }

    /// Check every value against its range; the first violation is an
    /// [`GearError::InvalidParameter`] naming the `[rig]` key.
    pub fn validate(&self) -> Result<()> {
        match self.first_problem() {
            Some(p) => Err(GearError::param(p.key, p.value, p.reason)),
            None => Ok(()),
        }
    }

    /// The load the (Kubo) curve was measured at: `test_load_n`, else `design_load_n`.
    pub fn test_load_or_design_n(&self) -> f64 {
        self.test_load_n.unwrap_or(self.design_load_n)
    }
}

/// The optional `[ste]` table: static transmission error amplitude per load.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SteTable {
    /// Loads in newtons, positive and distinct.
    pub load_n: Vec<f64>,
    /// STE amplitude e_bar (half peak-to-peak, um) at each load, positive.
    pub amplitude_um: Vec<f64>,
    /// Standard uncertainty of the stated amplitudes, um: one value for every load or one per
    /// load. With it a stated STE is a measurement the fit weighs against the curves
    /// ([`crate::fit::Measurement`]); without it `validate munro` and `discover` refuse the
    /// set, and `validate kubo` starts its fit there (or holds it with `--hold-ste`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sd_um: Option<SteUncertainty>,
}

/// `[ste] sd_um`: one standard uncertainty for every load, or one per load.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum SteUncertainty {
    Every(f64),
    PerLoad(Vec<f64>),
}

/// Smallest plausible `[ste]` value: an uncertainty at least [`MIN_NOISE_UM`], as a stated
/// noise (one below a nanometre would hold the STE all but exact, which the uncertainty is
/// there to prevent); the rest above 0.
fn ste_min(key: &str) -> f64 {
    if key == "sd_um" {
        MIN_NOISE_UM
    } else {
        0.0
    }
}

/// Largest plausible `[ste]` value: loads in N, amplitudes and their uncertainties in um.
fn ste_max(key: &str) -> f64 {
    if key == "load_n" {
        MAX_LOAD_N
    } else {
        MAX_DTE_UM
    }
}

impl SteTable {
    /// The STE amplitude (um) listed for `load_n` (relative tolerance 1e-9), if any.
    pub fn amplitude_at(&self, load_n: f64) -> Option<f64> {
        self.load_n
            .iter()
            .zip(&self.amplitude_um)
            .find(|(l, _)| same_load(**l, load_n))
            .map(|(_, a)| *a)
    }

    /// The standard uncertainty (um) of the amplitude stated for `load_n`, if both are given.
    pub fn sd_at(&self, load_n: f64) -> Option<f64> {
        let k = self.load_n.iter().position(|l| same_load(*l, load_n))?;
        match self.sd_um.as_ref()? {
            SteUncertainty::Every(sd) => Some(*sd),
            SteUncertainty::PerLoad(sd) => sd.get(k).copied(),
        }
    }

    /// Check lengths, signs and distinct loads; errors are located in `doc`.
    fn check(&self, doc: &TomlDoc) -> Result<()> {
        let sds: &[f64] = match &self.sd_um {
            None => &[],
            Some(SteUncertainty::Every(sd)) => std::slice::from_ref(sd),
            Some(SteUncertainty::PerLoad(sd)) => {
                if sd.len() != self.load_n.len() {
                    return Err(doc.error(
                        "ste",
                        "sd_um",
                        format!(
                            "{} uncertainties for {} loads: give one value for every load, or \
                             one per load",
                            sd.len(),
                            self.load_n.len()
                        ),
                    ));
                }
                sd
            }
        };
        if self.load_n.is_empty() {
            return Err(doc.error("ste", "load_n", "STE table has no loads"));
        }
        if self.load_n.len() != self.amplitude_um.len() {
            return Err(doc.error(
                "ste",
                "amplitude_um",
                format!(
                    "{} amplitudes for {} loads: the lists must have the same length",
                    self.amplitude_um.len(),
                    self.load_n.len()
                ),
            ));
        }
        for (key, values) in [
            ("load_n", self.load_n.as_slice()),
            ("amplitude_um", &self.amplitude_um),
            ("sd_um", sds),
        ] {
            if let Some((i, v)) = values.iter().enumerate().find(|(_, v)| {
                !(v.is_finite() && **v > 0.0 && **v >= ste_min(key) && **v <= ste_max(key))
            }) {
                let least = match ste_min(key) {
                    m if m > 0.0 => format!("at least {m} and "),
                    _ => String::new(),
                };
                return Err(doc.error(
                    "ste",
                    key,
                    format!(
                        "entry {} is {v}: must be a positive finite number, {least}at most {}",
                        i + 1,
                        ste_max(key)
                    ),
                ));
            }
        }
        // Loads that `same_load` takes for one (relative 1e-9) are one load: a second entry
        // there would never be read.
        for (i, l) in self.load_n.iter().enumerate() {
            if let Some(j) = self.load_n[..i].iter().position(|e| same_load(*e, *l)) {
                return Err(doc.error(
                    "ste",
                    "load_n",
                    format!(
                        "entry {} ({l} N) is the load of entry {} ({} N) to 1e-9: give each load once",
                        i + 1,
                        j + 1,
                        self.load_n[j]
                    ),
                ));
            }
        }
        Ok(())
    }
}

/// The optional `[noise]` table: the measurement noise of the `dte_pp_um` values as the data's
/// provider states it. Keys left out are estimated from the data (floor plus level-dependent
/// part); a per-point `dte_pp_sd_um` CSV column states it point by point instead.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StatedNoise {
    /// Noise floor: standard deviation of a reading (um) independent of its level; in
    /// [0.001, 1000) um (a larger floor is a unit mistake, not a DTE measurement), and
    /// not below `reading_um` where both are given.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub floor_um: Option<f64>,
    /// Level-dependent part: standard deviation as a fraction of the reading; in [0, 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub relative: Option<f64>,
    /// Reading uncertainty (um) of a digitized set (how finely values can be read off the
    /// figure), used by the fit as the lower bound of the noise floor; >= 0, finite and below
    /// 1000 um.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reading_um: Option<f64>,
    /// Correlation length (rpm) of the errors along speed within a curve,
    /// exp(-|s_i - s_j| / length) (docs/correlated-errors.md); 0 states independent errors.
    /// Finite, in [0, 1e6) rpm. Left out, the fit estimates it when the data say so.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub correlation_rpm: Option<f64>,
}

/// Largest plausible noise level in micrometres (a DTE noise of a millimetre is a unit mistake).
const NOISE_MAX_UM: f64 = 1000.0;
/// Smallest stated noise (floor or per point) in micrometres: 1 nm, finer than any
/// transmission-error measurement resolves; a smaller weight makes one point outweigh a curve.
pub const MIN_NOISE_UM: f64 = 1e-3;

impl StatedNoise {
    /// The first out-of-range value, if any (see each field for its range).
    fn first_problem(&self) -> Option<RigProblem> {
        let in_um = |key: &'static str, v: f64| {
            require(
                key,
                v,
                v.is_finite() && (0.0..NOISE_MAX_UM).contains(&v),
                "must be a finite number of micrometres in [0, 1000)",
            )
        };
        let floor = |v: f64| {
            require(
                "floor_um",
                v,
                v.is_finite() && (MIN_NOISE_UM..NOISE_MAX_UM).contains(&v),
                "must be a finite number of micrometres in [0.001, 1000): a stated noise needs a floor (with the relative part alone a reading at zero level would have no noise), and one below 1 nm is finer than any transmission-error measurement resolves (a unit mistake?)",
            )
        };
        let below_reading = |v: f64| {
            require(
                "floor_um",
                v,
                self.reading_um.is_none_or(|r| v >= r),
                "lies below reading_um, the reading uncertainty, which bounds the noise floor from below",
            )
        };
        optional(self.floor_um, floor)
            .or_else(|| {
                optional(self.relative, |v| {
                    require(
                        "relative",
                        v,
                        v.is_finite() && (0.0..1.0).contains(&v),
                        "relative noise (fraction of the reading) must be in [0, 1)",
                    )
                })
            })
            .or_else(|| optional(self.reading_um, |v| in_um("reading_um", v)))
            .or_else(|| {
                optional(self.correlation_rpm, |v| {
                    require(
                        "correlation_rpm",
                        v,
                        v.is_finite() && (0.0..1e6).contains(&v),
                        "the correlation length along speed must be a finite number of rpm in [0, 1000000) (0: independent errors)",
                    )
                })
            })
            .or_else(|| optional(self.floor_um, below_reading))
    }
}

/// The contents of `rig.toml`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RigFile {
    /// The `[rig]` table.
    pub rig: Rig,
    /// The optional `[ste]` table.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ste: Option<SteTable>,
    /// The optional `[noise]` table (stated measurement noise).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub noise: Option<StatedNoise>,
    /// The `[source]` table (provenance).
    pub source: Source,
}

impl RigFile {
    /// Check every table; errors are located in `doc`.
    fn check(&self, doc: &TomlDoc) -> Result<()> {
        if let Some(p) = self.rig.first_problem() {
            return Err(doc.error("rig", p.key, p.to_string()));
        }
        if let Some(ste) = &self.ste {
            ste.check(doc)?;
        }
        if let Some(p) = self.noise.as_ref().and_then(StatedNoise::first_problem) {
            return Err(doc.error("noise", p.key, p.to_string()));
        }
        self.source.check(doc)
    }
}

/// `rig.toml` as written: the tables of [`RigFile`] plus the optional `[geometry]` table, which
/// only the tooth-contact model reads (kept out of [`RigFile`] so that code building rig files
/// needs no change).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RigToml {
    rig: Rig,
    #[serde(default)]
    ste: Option<SteTable>,
    #[serde(default)]
    noise: Option<StatedNoise>,
    #[serde(default)]
    geometry: Option<GearGeometry>,
    source: Source,
}

/// The keys each required table must give (the others are optional or depend on the data kind).
const REQUIRED_KEYS: [(&str, &[&str]); 2] = [
    (
        "rig",
        &[
            "name",
            "pinion_teeth",
            "gear_teeth",
            "module_mm",
            "pressure_angle_deg",
            "face_width_mm",
            "design_load_n",
            "backlash_mm",
        ],
    ),
    ("source", &["kind", "citation"]),
];

/// Every required key missing from a table of `text`, in one error at the first one (so that
/// a new file, e.g. the template of `geardyn init-data`, is filled in one round); None when the
/// text is not TOML or nothing is missing.
fn missing_keys(doc: &TomlDoc, text: &str) -> Option<GearError> {
    let table: toml::Table = toml::from_str(text).ok()?;
    for (name, keys) in REQUIRED_KEYS {
        let Some(t) = table.get(name).and_then(|t| t.as_table()) else {
            continue;
        };
        let missing: Vec<&str> = keys
            .iter()
            .copied()
            .filter(|k| !t.contains_key(*k))
            .collect();
        if let Some(first) = missing.first() {
            return Some(doc.error(
                name,
                first,
                format!(
                    "missing in [{name}]: {} (each is marked REQUIRED in the template of \
                     `geardyn init-data`; docs/data-format.md lists every key)",
                    missing.join(", ")
                ),
            ));
        }
    }
    None
}

/// A located error for a TOML document that does not parse into the expected tables. serde
/// stops at the first missing key; every missing required key is named instead (an unknown key,
/// e.g. a unit typo, is reported first, at its line, as the parser found it).
fn parse_error(doc: &TomlDoc, text: &str, e: &toml::de::Error) -> GearError {
    let all_missing = e
        .message()
        .contains("missing field")
        .then(|| missing_keys(doc, text))
        .flatten();
    all_missing.unwrap_or_else(|| doc.toml_error(e))
}

/// Read and validate every table of a `rig.toml`.
/// The text of a rig.toml; a data set's folder given instead (`--rig data/munro`) names the
/// file meant.
fn read_rig_text(path: &Path) -> Result<String> {
    let inside = path.join("rig.toml");
    if path.is_dir() && inside.is_file() {
        let hint = format!(
            "is a folder, not a file; did you mean {}?",
            inside.display()
        );
        return Err(data_error(path, 0, WHOLE_FILE, hint));
    }
    read_text(path)
}

fn load_rig_toml(path: &Path) -> Result<(RigFile, GearGeometry)> {
    let text = read_rig_text(path)?;
    let doc = TomlDoc::new(path, &text);
    let t: RigToml = toml::from_str(&text).map_err(|e| parse_error(&doc, &text, &e))?;
    let rig = RigFile {
        rig: t.rig,
        ste: t.ste,
        noise: t.noise,
        source: t.source,
    };
    rig.check(&doc)?;
    let geometry = t.geometry.unwrap_or_default();
    if let Some(p) = geometry.first_problem() {
        return Err(doc.error("geometry", p.key, p.to_string()));
    }
    Ok((rig, geometry))
}

/// The gear pair of a `rig.toml` alone: its `[rig]` and `[ste]` tables, as the analysis commands
/// read them (`--rig`); the other tables (`[source]`, `[noise]`, `[geometry]`) describe a data
/// set and may be absent or unfinished. Errors as [`load_rig`].
pub fn load_gear_pair(path: &Path) -> Result<(Rig, Option<SteTable>)> {
    #[derive(Deserialize)]
    struct GearPairToml {
        rig: Rig,
        #[serde(default)]
        ste: Option<SteTable>,
    }
    let text = read_rig_text(path)?;
    let doc = TomlDoc::new(path, &text);
    let t: GearPairToml = toml::from_str(&text).map_err(|e| parse_error(&doc, &text, &e))?;
    if let Some(p) = t.rig.first_problem() {
        return Err(doc.error("rig", p.key, p.to_string()));
    }
    if let Some(ste) = &t.ste {
        ste.check(&doc)?;
    }
    Ok((t.rig, t.ste))
}

/// Read and validate a `rig.toml`. Every failure is one [`GearError::Data`] naming the file, the
/// line (0 when the key is absent) and the key path (e.g. `rig.backlash_mm`). An optional
/// `[geometry]` table is validated too; [`load_rig_with_geometry`] returns it.
pub fn load_rig(path: &Path) -> Result<RigFile> {
    load_rig_toml(path).map(|(rig, _)| rig)
}

/// Read and validate a `rig.toml` with its `[geometry]` table (all defaults when absent), for
/// the tooth-contact model ([`crate::mesh`]). Errors as [`load_rig`].
pub fn load_rig_with_geometry(path: &Path) -> Result<(RigFile, GearGeometry)> {
    load_rig_toml(path)
}

/// An error about `[table] key` of the `rig.toml` in the data set folder `dir`, located at the
/// key's line (the table's line when the key is absent, 0 when the file cannot be read again):
/// for checks made after loading (e.g. a key that one pipeline cannot use).
pub fn rig_key_error(dir: &Path, table: &str, key: &str, message: impl Into<String>) -> GearError {
    key_error_in(&dir.join("rig.toml"), table, key, message)
}

/// An error about `[table] key` of the rig file `path`, located as [`rig_key_error`]'s.
fn key_error_in(path: &Path, table: &str, key: &str, message: impl Into<String>) -> GearError {
    let text = std::fs::read_to_string(path).unwrap_or_default();
    TomlDoc::new(path, &text).error(table, key, message)
}

/// Tables of rig.toml whose keys an out-of-range parameter may be named by (`geometry.`...).
const RIG_TABLES: [&str; 4] = ["rig", "geometry", "ste", "noise"];

/// `e` located in the rig file `path` when it is an out-of-range parameter named by a rig.toml
/// key with its table (`geometry.pinion_bore_diameter_mm`, `rig.pressure_angle_deg`): the same
/// message at that key's line (line 0 when the key is left at its default). Other errors are
/// returned as they are.
pub fn locate_rig_key(path: &Path, e: GearError) -> GearError {
    let GearError::InvalidParameter {
        name,
        value,
        reason,
    } = e
    else {
        return e;
    };
    let (table, key) = match name.split_once('.') {
        Some((t, k)) if RIG_TABLES.contains(&t) => (t, k),
        _ => return GearError::param(name, value, reason),
    };
    let message = RigProblem { key, value, reason }.to_string();
    key_error_in(path, table, key, message)
}

/// Validate `rig` and write it as TOML to `path` (used by `geardyn synth`). An invalid rig is
/// not written, and the file appears complete or not at all (written aside, then renamed).
pub fn write_rig(path: &Path, rig: &RigFile) -> Result<()> {
    rig.check(&TomlDoc::new(path, ""))?;
    let text = toml::to_string(rig)
        .map_err(|e| data_error(path, 0, WHOLE_FILE, format!("cannot encode TOML: {e}")))?;
    let io = GearError::io(path);
    let mut tmp = path.as_os_str().to_owned();
    tmp.push(".partial");
    let tmp = std::path::PathBuf::from(tmp);
    std::fs::write(&tmp, text).map_err(&io)?;
    std::fs::rename(&tmp, path).map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        io(e)
    })
}
