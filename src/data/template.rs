//! Templates of a new data set (`geardyn init-data`): a `rig.toml` in which every key of
//! `[rig]`, `[source]`, `[ste]`, `[noise]` and `[geometry]` is written out, commented, with its
//! unit, the range the loader accepts and a plausible value, and a CSV file with its header and
//! the meaning of each column. docs/data-format.md is the reference; a test checks that every
//! key it lists is in the template.
//!
//! The template does not load until it is filled: the required keys are commented out, so the
//! loader names the missing ones, and the CSV has no data rows.

/// The layout of the curves: Munro's pp DTE per load, or Kubo's dynamic-factor envelope.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Layout {
    /// `load_n,speed_rpm,dte_pp_um`: pp DTE against speed, one curve per load.
    Munro,
    /// `speed_rpm,dynamic_factor_min,dynamic_factor_max`: one envelope at one load.
    Kubo,
}

impl Layout {
    /// Name of the CSV file the template writes.
    pub fn csv_name(self) -> &'static str {
        match self {
            Layout::Munro => "dte.csv",
            Layout::Kubo => "dynamic_factor.csv",
        }
    }

    /// The `validate` subcommand that reads this layout.
    pub fn command(self) -> &'static str {
        match self {
            Layout::Munro => "munro",
            Layout::Kubo => "kubo",
        }
    }
}

const RIG_HEAD: &str = r##"# rig.toml of a geardyn data set: the test gear pair and where the numbers come from.
#
# Fill in every line marked REQUIRED: remove its leading "# " and replace the example value
# with yours. OPTIONAL lines may stay commented out (to use one, also uncomment its [table]
# header). Units are part of the key names; each comment gives the unit, the range geardyn
# accepts (a value outside is taken for a typing or unit mistake) and what is typical.
# Every key: docs/data-format.md. Check the filled set with
#     geardyn validate COMMAND --data DIR
# which names the file, line and key of anything it cannot use.

[rig]
# name = "Four-square rig, gear lab"    # REQUIRED. text, not blank: name of the rig
# pinion_teeth = 32        # REQUIRED. integer in [5, 1000]: teeth of the pinion (mesh frequency = pinion_teeth x rpm / 60); typical 15-100
# gear_teeth = 32          # REQUIRED. integer in [5, 1000]: teeth of the gear
# module_mm = 6.35         # REQUIRED. mm in [0.05, 100]: module (25.4 / diametral pitch in 1/in); typical 1-20
# pressure_angle_deg = 20.0    # REQUIRED. degrees in (10, 35): pressure angle; typical 20
# face_width_mm = 12.7     # REQUIRED. mm in [0.1, 2000]: face width; typical 5-200
# design_load_n = 3780.0   # REQUIRED. N in (0, 1e8]: mean force along the line of action at the design point (torque / base radius); validate munro fits the curve at this load
# backlash_mm = 0.1        # REQUIRED. mm in [0.001, 10]: total backlash 2b along the line of action; typical 0.02-0.5
# mesh_stiffness_n_per_um = 250.0   # OPTIONAL. N/um in [0.01, 1e5]: mean mesh stiffness k_h (steel spur gears 5-2000, about 14-20 N/um per mm of face width); ISO 6336-1 estimate when absent
# contact_ratio = 1.65     # OPTIONAL. dimensionless in [1, 3]: transverse contact ratio; computed for standard full-depth teeth when absent
# zeta = 0.02              # OPTIONAL. dimensionless in (0, 1): damping ratio (typical 0.01-0.1). validate kubo: fixed with omega_n_hz; validate munro fits it and refuses a given value; sweep, simulate ... --rig: the default --zeta
# omega_n_hz = 1600.0      # OPTIONAL. Hz in [1, 1e6]: natural frequency of the mesh. As zeta: validate kubo fixed, validate munro refused (fitted), --rig default --omega-n-hz
# test_load_n = 3780.0     # OPTIONAL. N in (0, 1e8]: Kubo layout only, the load the envelope was measured at (default design_load_n)

# [ste]                    # OPTIONAL table: static transmission error per load (else read from each curve's low-speed end)
# load_n = [3780.0, 1890.0]      # N, each in (0, 1e8], no load twice
# amplitude_um = [0.3, 2.5]      # um, each in (0, 1000]: STE amplitude (its first harmonic; half its peak-to-peak if sinusoidal), one per load
# sd_um = 0.05                   # um, in [0.001, 1000], one value or one per load: the amplitudes' standard uncertainty, needed by validate munro and discover (they weigh a stated STE against the curves as a measurement)

# [noise]                  # OPTIONAL table: the measurement noise of the curve values, as you know it (else estimated from the data)
# floor_um = 0.2           # um in [0.001, 1000), not below reading_um: standard deviation of a reading, independent of its level
# relative = 0.02          # dimensionless in [0, 1): standard deviation as a fraction of the reading
# reading_um = 0.1         # um in [0, 1000): how finely a digitized value can be read off its figure (lower bound of the fitted floor)
# correlation_rpm = 100.0  # rpm in [0, 1e6): correlation length of the errors along speed within a curve (0: independent; else estimated when the data say so)

# [geometry]               # OPTIONAL table, read by `geardyn mesh` and `validate munro --ste geometry` only; defaults: standard full-depth steel gears at the standard centre distance
# pinion_profile_shift = 0.0     # dimensionless in [-1, 1.5]: profile shift coefficient x1 (default 0)
# gear_profile_shift = 0.0       # dimensionless in [-1, 1.5]: profile shift coefficient x2 (default 0)
# addendum_coefficient = 1.0     # dimensionless in [0.5, 1.5]: addendum of the basic rack over the module h_a* (default 1.0)
# dedendum_coefficient = 1.25    # dimensionless in [0.8, 2], above h_a*: dedendum of the basic rack over the module h_f* (default 1.25)
# root_fillet_coefficient = 0.38 # dimensionless in [0, 0.6]: root fillet radius of the basic rack over the module rho_fP* (default 0.38, ISO 53 profile A)
# pinion_tip_diameter_mm = 215.9 # mm, above the base diameter: tip diameter of the pinion (default m (z1 + 2 h_a* + 2 x1))
# gear_tip_diameter_mm = 215.9   # mm, above the base diameter: tip diameter of the gear (default m (z2 + 2 h_a* + 2 x2))
# centre_distance_mm = 203.2     # mm, above the sum of the base radii: operating centre distance (default m (z1 + z2) / 2 without shift)
# pinion_bore_diameter_mm = 50.0 # mm, below the root diameter: bore of the pinion body (default a third of its root diameter)
# gear_bore_diameter_mm = 50.0   # mm, below the root diameter: bore of the gear body (default a third of its root diameter)
# youngs_modulus_gpa = 206.0     # GPa in [1, 1000]: Young's modulus of both gears (default 206, steel)
# poisson_ratio = 0.3            # dimensionless in (0, 0.5): Poisson's ratio of both gears (default 0.3)

[source]
kind = "measured"          # measured (your rig), digitized (read off a published figure) or synthetic (made by a model); reports print it first
# citation = "Gear lab test report TR-12 (2024)"   # REQUIRED. text: the test report or publication
# instrument = "two optical encoders, 5000 lines/rev; DTE from the shaft angle difference"   # REQUIRED for measured data. text: sensor, resolution, how the DTE was derived
# date = 2024-05-17        # REQUIRED for measured data. a date (2024-05-17) or text ("May 2024"): when it was measured
# uncertainty = "+-0.1 um"   # REQUIRED for measured data (and digitized data). text: measurement or reading uncertainty
# figure = "Fig. 20"       # OPTIONAL. text: the figure the data were read from
# method = "geardyn digitize, markers"   # OPTIONAL; required for digitized data. text: digitization method (tool, calibration)
# generator = "geardyn synth 0.1.0"      # OPTIONAL; required for synthetic data. text: the program that made the data
# [source.truth]           # OPTIONAL table; required for synthetic data: the generating parameters (printed in reports, never fitted)
"##;

const MUNRO_CSV: &str = r#"# Peak-to-peak dynamic transmission error against speed, one row per point, one curve per
# load (docs/data-format.md, "Munro style"). Comma-separated, "." as the decimal point; lines
# starting with # are comments. Columns:
#   load_n        N    (0, 1e8]      mean load of the point's curve: the curve at rig.toml's
#                                    design_load_n is fitted, the other loads are predicted
#   speed_rpm     rpm  [0.01, 1e6]   pinion speed (or a column mesh_freq_hz, Hz, instead)
#   dte_pp_um     um   [0, 1000]     peak-to-peak dynamic transmission error
#   dte_pp_sd_um  um   [0.001, 1000]   OPTIONAL column: standard deviation of each dte_pp_um
# Within a curve, list the points by increasing speed; no speed twice in a curve. The fit needs
# the design-load curve with at least 6 points, better 30 or more through the resonance.
load_n,speed_rpm,dte_pp_um
"#;

const KUBO_CSV: &str = r#"# Envelope of the dynamic factor against speed, one curve at rig.toml's test_load_n
# (default design_load_n); docs/data-format.md, "Kubo style". Comma-separated, "." as the
# decimal point; lines starting with # are comments. Columns:
#   speed_rpm            rpm  [0.01, 1e6]   pinion speed (or a column mesh_freq_hz, Hz, instead)
#   dynamic_factor_min   -    [0, 100]      lower edge of the envelope of the dynamic factor
#   dynamic_factor_max   -    [min, 100]    upper edge (largest mesh force over the mean force)
# List the points by increasing speed; no speed twice.
speed_rpm,dynamic_factor_min,dynamic_factor_max
"#;

/// The commented `rig.toml` template for `layout`.
pub fn rig_template(layout: Layout) -> String {
    RIG_HEAD.replace("COMMAND", layout.command())
}

/// The CSV template for `layout`: comments on each column, then the header line.
pub fn csv_template(layout: Layout) -> &'static str {
    match layout {
        Layout::Munro => MUNRO_CSV,
        Layout::Kubo => KUBO_CSV,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every key documented in docs/data-format.md (the first cell of its tables, in backticks)
    /// appears as a key of the template, so the two cannot drift apart.
    #[test]
    fn template_has_every_documented_key() {
        let doc = include_str!("../../docs/data-format.md");
        let rig = rig_template(Layout::Munro);
        let section =
            &doc[doc.find("## rig.toml").unwrap()..doc.find("## CSV curve files").unwrap()];
        let mut keys = 0;
        for line in section.lines().filter(|l| l.starts_with("| `")) {
            let cell = line.split('|').nth(1).unwrap_or("");
            for key in cell.split(',').filter_map(|k| k.trim().strip_prefix('`')) {
                let key = key.trim_end_matches('`');
                let key = key.trim_start_matches('[').trim_end_matches(']');
                assert!(
                    rig.contains(&format!("# {key} = "))
                        || rig.contains(&format!("\n{key} = "))
                        || rig.contains(&format!("# [{key}]")),
                    "{key} is documented but not in the template"
                );
                keys += 1;
            }
        }
        assert!(keys >= 35, "only {keys} keys found in docs/data-format.md");
    }

    #[test]
    fn csv_templates_end_with_their_header() {
        assert!(csv_template(Layout::Munro).ends_with("load_n,speed_rpm,dte_pp_um\n"));
        assert!(csv_template(Layout::Kubo)
            .ends_with("speed_rpm,dynamic_factor_min,dynamic_factor_max\n"));
        assert!(rig_template(Layout::Kubo).contains("geardyn validate kubo --data DIR"));
    }
}
