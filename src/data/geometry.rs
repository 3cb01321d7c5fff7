//! The optional `[geometry]` table of `rig.toml`: the spur-gear data beyond `[rig]` that the
//! tooth-contact model of [`crate::mesh`] needs (profile shift, addendum and dedendum, tip
//! diameters, centre distance, bores, material). Every key is optional; docs/data-format.md
//! lists the defaults (standard full-depth 20 deg gears of steel at the standard centre distance).

use super::rig::{optional, positive, require, RigProblem};
use serde::{Deserialize, Serialize};

/// The `[geometry]` table. Absent keys take the defaults documented on each field.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GearGeometry {
    /// Profile shift coefficient x1 of the pinion (default 0), in [-1, 1.5].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pinion_profile_shift: Option<f64>,
    /// Profile shift coefficient x2 of the gear (default 0), in [-1, 1.5].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gear_profile_shift: Option<f64>,
    /// Addendum coefficient h_a* of the basic rack (default 1.0), in [0.5, 1.5].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub addendum_coefficient: Option<f64>,
    /// Dedendum coefficient h_f* of the basic rack (default 1.25), in [0.8, 2], above h_a*.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dedendum_coefficient: Option<f64>,
    /// Root fillet radius coefficient rho_fP* of the basic rack (tip radius of the cutting rack
    /// over the module; default 0.38, ISO 53 profile A), in [0, 0.6] and small enough to fit
    /// the rack's tooth tip.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub root_fillet_coefficient: Option<f64>,
    /// Tip diameter of the pinion in mm (default m (z1 + 2 h_a* + 2 x1)), > 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pinion_tip_diameter_mm: Option<f64>,
    /// Tip diameter of the gear in mm (default m (z2 + 2 h_a* + 2 x2)), > 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gear_tip_diameter_mm: Option<f64>,
    /// Operating centre distance in mm (default: the zero-backlash distance of the shifted
    /// pair, m (z1 + z2) / 2 without shift), > 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub centre_distance_mm: Option<f64>,
    /// Bore diameter of the pinion in mm (default a third of its root diameter), > 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pinion_bore_diameter_mm: Option<f64>,
    /// Bore diameter of the gear in mm (default a third of its root diameter), > 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gear_bore_diameter_mm: Option<f64>,
    /// Young's modulus of both gears in GPa (default 206, steel), in [1, 1000].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub youngs_modulus_gpa: Option<f64>,
    /// Poisson's ratio of both gears (default 0.3), in (0, 0.5).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub poisson_ratio: Option<f64>,
}

impl GearGeometry {
    /// The first out-of-range value, if any (ranges as documented on each field). Consistency
    /// between keys (tip above base circle, contact ratio above 1) is checked by
    /// [`crate::mesh::GearPairGeometry::from_rig`], which knows the whole pair.
    pub(crate) fn first_problem(&self) -> Option<RigProblem> {
        let shift = |key: &'static str, v: f64| {
            require(
                key,
                v,
                v.is_finite() && (-1.0..=1.5).contains(&v),
                "profile shift coefficient must be in [-1, 1.5]",
            )
        };
        let ha = self.addendum_coefficient;
        optional(self.pinion_profile_shift, |v| {
            shift("pinion_profile_shift", v)
        })
        .or_else(|| optional(self.gear_profile_shift, |v| shift("gear_profile_shift", v)))
        .or_else(|| {
            optional(ha, |v| {
                require(
                    "addendum_coefficient",
                    v,
                    v.is_finite() && (0.5..=1.5).contains(&v),
                    "addendum coefficient must be in [0.5, 1.5]",
                )
            })
        })
        .or_else(|| {
            optional(self.dedendum_coefficient, |v| {
                require(
                    "dedendum_coefficient",
                    v,
                    v.is_finite() && (0.8..=2.0).contains(&v) && v > ha.unwrap_or(1.0),
                    "dedendum coefficient must be in [0.8, 2] and above the addendum coefficient",
                )
            })
        })
        .or_else(|| {
            optional(self.root_fillet_coefficient, |v| {
                require(
                    "root_fillet_coefficient",
                    v,
                    v.is_finite() && (0.0..=0.6).contains(&v),
                    "root fillet radius coefficient must be in [0, 0.6]",
                )
            })
        })
        .or_else(|| {
            optional(self.pinion_tip_diameter_mm, |v| {
                positive("pinion_tip_diameter_mm", v)
            })
        })
        .or_else(|| {
            optional(self.gear_tip_diameter_mm, |v| {
                positive("gear_tip_diameter_mm", v)
            })
        })
        .or_else(|| {
            optional(self.centre_distance_mm, |v| {
                positive("centre_distance_mm", v)
            })
        })
        .or_else(|| {
            optional(self.pinion_bore_diameter_mm, |v| {
                positive("pinion_bore_diameter_mm", v)
            })
        })
        .or_else(|| {
            optional(self.gear_bore_diameter_mm, |v| {
                positive("gear_bore_diameter_mm", v)
            })
        })
        .or_else(|| {
            optional(self.youngs_modulus_gpa, |v| {
                require(
                    "youngs_modulus_gpa",
                    v,
                    v.is_finite() && (1.0..=1000.0).contains(&v),
                    "Young's modulus must be in [1, 1000] GPa",
                )
            })
        })
        .or_else(|| {
            optional(self.poisson_ratio, |v| {
                require(
                    "poisson_ratio",
                    v,
                    v.is_finite() && v > 0.0 && v < 0.5,
                    "Poisson's ratio must be in (0, 0.5)",
                )
            })
        })
    }
}
