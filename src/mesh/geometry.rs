//! Involute spur-gear pair geometry: base, tip and root radii, the operating pressure angle and
//! centre distance, the path of contact and the transverse contact ratio (ISO 21771 / any
//! gearing text, e.g. Maitra, *Handbook of Gear Design*, ch. 1).
//!
//! Positions on the line of action are roll distances `s` (metres) from T1, the point where the
//! line of action touches the pinion's base circle. With T1T2 = a sin(alpha_w):
//!
//! - contact starts at A, where the gear's tip circle cuts the line of action:
//!   s_A = a sin(alpha_w) - sqrt(r_a2^2 - r_b2^2);
//! - contact ends at E, on the pinion's tip circle: s_E = sqrt(r_a1^2 - r_b1^2);
//! - the pitch point C is at s_C = r_b1 tan(alpha_w);
//! - path of contact g_alpha = s_E - s_A, base pitch p_b = pi m cos(alpha),
//!   transverse contact ratio eps_alpha = g_alpha / p_b.

use super::iso6336::{IsoPair, IsoStiffness};
use crate::data::{GearGeometry, Rig};
use crate::error::{GearError, Result};
use serde::Serialize;
use std::f64::consts::PI;

/// Involute function inv(alpha) = tan(alpha) - alpha.
pub fn involute(alpha: f64) -> f64 {
    alpha.tan() - alpha
}

/// One gear of the pair (lengths in metres, angles in radians).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct GearBody {
    /// Number of teeth z.
    pub teeth: f64,
    /// Profile shift coefficient x.
    pub profile_shift: f64,
    /// Base radius r_b = m z cos(alpha) / 2.
    pub base_radius_m: f64,
    /// Reference (pitch) radius r = m z / 2.
    pub pitch_radius_m: f64,
    /// Tip radius r_a (from `[geometry]` tip diameter, else m (z/2 + h_a* + x)).
    pub tip_radius_m: f64,
    /// Root radius r_f = m (z/2 - h_f* + x).
    pub root_radius_m: f64,
    /// Bore radius (inner radius of the gear body, for the fillet-foundation term).
    pub bore_radius_m: f64,
    /// Half tooth angle at the base circle, alpha_2 = (pi/2 + 2 x tan(alpha)) / z + inv(alpha)
    /// (tooth thickness of a gear cut with zero backlash by the standard rack).
    pub half_base_angle: f64,
    /// Half angle theta_f of the tooth's root between the ends of its two fillets, as the basic
    /// rack (dedendum h_f*, tip radius rho*) cuts it: the rack's flat tip, pi m / 2 - 2 h_f* m
    /// tan(alpha) - 2 rho* m (1 - sin(alpha)) / cos(alpha) wide (less 2 x m tan(alpha) when
    /// shifted), is the space between two teeth on the root circle, so the tooth spans
    /// theta_f = (pi/2 + 2 x tan(alpha) + 2 tan(alpha) (h_f* - rho*) + 2 rho* / cos(alpha)) / z
    /// (rack lengths over the pitch radius; e.g. Ma et al., Mech. Syst. Signal Process. 70-71,
    /// 2016). The fillet-foundation term of Sainsot et al. (2004) takes S_f = 2 r_f theta_f.
    pub root_half_angle: f64,
}

/// A spur gear pair in mesh, with the material of both gears.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct GearPairGeometry {
    /// Pinion (gear 1, the driver).
    pub pinion: GearBody,
    /// Gear (gear 2).
    pub gear: GearBody,
    /// Module m, metres.
    pub module_m: f64,
    /// Standard pressure angle alpha, radians.
    pub pressure_angle: f64,
    /// Operating pressure angle alpha_w, radians: cos(alpha_w) = a_0 cos(alpha) / a.
    pub working_pressure_angle: f64,
    /// Operating centre distance a, metres.
    pub centre_distance_m: f64,
    /// Dedendum of the basic rack over the module, h_f* (= h_fP / m).
    pub rack_dedendum: f64,
    /// Face width L, metres.
    pub face_width_m: f64,
    /// Young's modulus E, Pa.
    pub youngs_modulus_pa: f64,
    /// Poisson's ratio nu.
    pub poisson_ratio: f64,
}

/// `Err(InvalidParameter)` with `name` unless `ok`.
fn check(ok: bool, name: &'static str, value: f64, reason: &'static str) -> Result<()> {
    if ok {
        Ok(())
    } else {
        Err(GearError::param(name, value, reason))
    }
}

/// inv^-1 by Newton's method (alpha in (0, pi/2)); converges in a few steps for gear angles.
fn inverse_involute(target: f64) -> f64 {
    let mut a = (3.0 * target).cbrt().clamp(1e-6, 1.5);
    for _ in 0..60 {
        let t = a.tan();
        let step = (t - a - target) / (t * t);
        a = (a - step).clamp(1e-9, 1.55);
        if step.abs() < 1e-15 {
            break;
        }
    }
    a
}

/// The centre distance and working pressure angle: as stated in `[geometry]`, or the
/// zero-backlash one of the profile shifts (inv(alpha_w) = inv(alpha) + 2 tan(alpha)
/// (x1 + x2) / (z1 + z2), a = a_0 cos(alpha) / cos(alpha_w)).
fn working_centre_distance(
    m: f64,
    alpha: f64,
    (z1, z2): (f64, f64),
    (x1, x2): (f64, f64),
    g: &GearGeometry,
) -> Result<(f64, f64)> {
    let a0 = m * (z1 + z2) / 2.0;
    Ok(match g.centre_distance_mm {
        Some(a_mm) => {
            let a = a_mm * 1e-3;
            let c = a0 * alpha.cos() / a;
            check(
                c < 1.0,
                "geometry.centre_distance_mm",
                a_mm,
                "is not above the sum of the base radii: the teeth cannot mesh",
            )?;
            (a, c.acos())
        }
        None => {
            let inv_w = involute(alpha) + 2.0 * alpha.tan() * (x1 + x2) / (z1 + z2);
            let aw = inverse_involute(inv_w);
            (a0 * alpha.cos() / aw.cos(), aw)
        }
    })
}

/// Largest root-to-bore ratio h_f = r_f / r_bore the fillet-foundation polynomial is used at
/// (the default bore, a third of the root, is 3): its compliance terms grow as h_f^2 beyond 10.
const MAX_ROOT_OVER_BORE: f64 = 10.0;

/// A gear's circles in order (base below tip, root above zero, bore below root) and a tooth
/// that does not come to a point below its tip; an error names the tip-diameter, bore-diameter
/// or profile-shift key given.
fn check_body(b: &GearBody, [tip, bore, root]: [&'static str; 3]) -> Result<()> {
    check(
        b.tip_radius_m > b.base_radius_m,
        tip,
        2e3 * b.tip_radius_m,
        "tip circle must lie outside the base circle",
    )?;
    check(
        b.root_radius_m > 0.0,
        root,
        b.profile_shift,
        "root circle radius is not positive",
    )?;
    check(
        b.bore_radius_m < b.root_radius_m,
        bore,
        2e3 * b.bore_radius_m,
        "bore must be smaller than the root circle",
    )?;
    check(
        b.root_radius_m <= MAX_ROOT_OVER_BORE * b.bore_radius_m,
        bore,
        2e3 * b.bore_radius_m,
        "bore below a tenth of the root diameter: the fillet-foundation formula (Sainsot et al. \
         2004) grows as (root / bore)^2 beyond, which would make a solid gear softer than a rim; \
         give at least a tenth of the root diameter",
    )?;
    // The tooth must be thicker than zero at the tip: half angle at r_a positive.
    let phi_a = (b.base_radius_m / b.tip_radius_m).acos();
    check(
        b.half_base_angle - involute(phi_a) > 0.0,
        tip,
        2e3 * b.tip_radius_m,
        "tooth comes to a point below this tip circle (pointed tooth)",
    )?;
    Ok(())
}

/// Contact on the involutes (above the base circle and the root circle of each gear: otherwise
/// the tip of one gear digs into the other's fillet), and a transverse contact ratio of at
/// least 1.
fn check_contact(geo: &GearPairGeometry, g: &GearGeometry, pressure_angle_deg: f64) -> Result<()> {
    let (s_a, s_e) = (geo.start_of_contact(), geo.end_of_contact());
    let lowest = |b: &GearBody| {
        let r = b.root_radius_m.max(b.base_radius_m);
        (r * r - b.base_radius_m * b.base_radius_m).sqrt()
    };
    check(
        s_a >= lowest(&geo.pinion),
        "geometry.gear_tip_diameter_mm",
        2e3 * geo.gear.tip_radius_m,
        "the gear's tip reaches below the pinion's involute (interference)",
    )?;
    check(
        geo.line_of_action_length() - s_e >= lowest(&geo.gear),
        "geometry.pinion_tip_diameter_mm",
        2e3 * geo.pinion.tip_radius_m,
        "the pinion's tip reaches below the gear's involute (interference)",
    )?;
    // The first stated value that shortens the path of contact is blamed; with none stated,
    // the pressure angle (with the teeth) is what made it short.
    const SHORT: &str = "leaves a transverse contact ratio below 1 (the tip circles overlap too \
                         little, or not at all): the mesh would lose contact between pairs";
    let (key, value) = [
        ("geometry.centre_distance_mm", g.centre_distance_mm),
        ("geometry.pinion_tip_diameter_mm", g.pinion_tip_diameter_mm),
        ("geometry.gear_tip_diameter_mm", g.gear_tip_diameter_mm),
        ("geometry.addendum_coefficient", g.addendum_coefficient),
    ]
    .into_iter()
    .find_map(|(k, v)| v.map(|v| (k, v)))
    .unwrap_or(("rig.pressure_angle_deg", pressure_angle_deg));
    check(geo.contact_ratio() >= 1.0, key, value, SHORT)
}

impl GearPairGeometry {
    /// The pair described by `[rig]` and `[geometry]`. Defaults: no profile shift, h_a* = 1,
    /// h_f* = 1.25, tip diameters from the rack, the zero-backlash centre distance
    /// (inv(alpha_w) = inv(alpha) + 2 tan(alpha) (x1 + x2) / (z1 + z2), a = a_0 cos(alpha) /
    /// cos(alpha_w)), bores a third of the root diameters, E = 206 GPa, nu = 0.3.
    ///
    /// Errors ([`GearError::InvalidParameter`], naming the `geometry.` or `rig.` key): a value
    /// out of range, a tip circle not above the base circle, a centre distance that does not
    /// bring the teeth into mesh, contact outside the involutes (interference), or a contact
    /// ratio below 1.
    pub fn from_rig(rig: &Rig, g: &GearGeometry) -> Result<Self> {
        rig.validate()?;
        if let Some(p) = g.first_problem() {
            return Err(GearError::param(p.key, p.value, p.reason));
        }
        let m = rig.module_mm * 1e-3;
        let alpha = rig.pressure_angle_deg.to_radians();
        let (z1, z2) = (rig.pinion_teeth as f64, rig.gear_teeth as f64);
        let (x1, x2) = (
            g.pinion_profile_shift.unwrap_or(0.0),
            g.gear_profile_shift.unwrap_or(0.0),
        );
        let ha = g.addendum_coefficient.unwrap_or(1.0);
        let hf = g.dedendum_coefficient.unwrap_or(1.25);
        let rho = g.root_fillet_coefficient.unwrap_or(0.38);
        // The rack's tip, pi/4 - h_f* tan(alpha) half wide, must hold the two tip radii.
        let rho_max = (PI / 4.0 - hf * alpha.tan()) * alpha.cos() / (1.0 - alpha.sin());
        // The fillet left at its default, the pressure angle is what the user chose to change.
        match g.root_fillet_coefficient {
            Some(_) => check(
                rho <= rho_max,
                "geometry.root_fillet_coefficient",
                rho,
                "is too large for the rack's tooth tip at this dedendum and pressure angle",
            )?,
            None => check(
                rho <= rho_max,
                "rig.pressure_angle_deg",
                rig.pressure_angle_deg,
                "leaves the generating rack's tooth tip too narrow for the default root fillet \
                 (0.38 module; with the default dedendum 1.25 about 23 degrees at most): lower \
                 it, or state a smaller [geometry] root_fillet_coefficient",
            )?,
        }
        check(
            hf > ha,
            "geometry.dedendum_coefficient",
            hf,
            "must exceed the addendum coefficient (1.0 by default)",
        )?;
        let (a, alpha_w) = working_centre_distance(m, alpha, (z1, z2), (x1, x2), g)?;
        let body = |z: f64, x: f64, tip_d_mm: Option<f64>, bore_d_mm: Option<f64>| {
            let rf = m * (z / 2.0 - hf + x);
            GearBody {
                teeth: z,
                profile_shift: x,
                base_radius_m: m * z * alpha.cos() / 2.0,
                pitch_radius_m: m * z / 2.0,
                tip_radius_m: tip_d_mm.map_or(m * (z / 2.0 + ha + x), |d| d * 1e-3 / 2.0),
                root_radius_m: rf,
                bore_radius_m: bore_d_mm.map_or(rf / 3.0, |d| d * 1e-3 / 2.0),
                half_base_angle: (PI / 2.0 + 2.0 * x * alpha.tan()) / z + involute(alpha),
                root_half_angle: (PI / 2.0
                    + 2.0 * x * alpha.tan()
                    + 2.0 * alpha.tan() * (hf - rho)
                    + 2.0 * rho / alpha.cos())
                    / z,
            }
        };
        let pinion = body(z1, x1, g.pinion_tip_diameter_mm, g.pinion_bore_diameter_mm);
        let gear = body(z2, x2, g.gear_tip_diameter_mm, g.gear_bore_diameter_mm);
        check_body(
            &pinion,
            [
                "geometry.pinion_tip_diameter_mm",
                "geometry.pinion_bore_diameter_mm",
                "geometry.pinion_profile_shift",
            ],
        )?;
        check_body(
            &gear,
            [
                "geometry.gear_tip_diameter_mm",
                "geometry.gear_bore_diameter_mm",
                "geometry.gear_profile_shift",
            ],
        )?;
        let geo = GearPairGeometry {
            pinion,
            gear,
            module_m: m,
            pressure_angle: alpha,
            working_pressure_angle: alpha_w,
            centre_distance_m: a,
            rack_dedendum: hf,
            face_width_m: rig.face_width_mm * 1e-3,
            youngs_modulus_pa: g.youngs_modulus_gpa.unwrap_or(206.0) * 1e9,
            poisson_ratio: g.poisson_ratio.unwrap_or(0.3),
        };
        check_contact(&geo, g, rig.pressure_angle_deg)?;
        Ok(geo)
    }

    /// Length T1T2 of the line of action between the base-circle tangency points,
    /// a sin(alpha_w), metres.
    pub fn line_of_action_length(&self) -> f64 {
        self.centre_distance_m * self.working_pressure_angle.sin()
    }

    /// Roll distance s_A of the start of contact from T1 (gear tip), metres.
    pub fn start_of_contact(&self) -> f64 {
        let g = &self.gear;
        self.line_of_action_length()
            - (g.tip_radius_m * g.tip_radius_m - g.base_radius_m * g.base_radius_m).sqrt()
    }

    /// Roll distance s_E of the end of contact from T1 (pinion tip), metres.
    pub fn end_of_contact(&self) -> f64 {
        let p = &self.pinion;
        (p.tip_radius_m * p.tip_radius_m - p.base_radius_m * p.base_radius_m).sqrt()
    }

    /// Roll distance s_C of the pitch point from T1, r_b1 tan(alpha_w), metres.
    pub fn pitch_point(&self) -> f64 {
        self.pinion.base_radius_m * self.working_pressure_angle.tan()
    }

    /// Path of contact g_alpha = s_E - s_A, metres.
    pub fn path_of_contact(&self) -> f64 {
        self.end_of_contact() - self.start_of_contact()
    }

    /// Base pitch p_b = pi m cos(alpha), metres (equal on both gears).
    pub fn base_pitch(&self) -> f64 {
        PI * self.module_m * self.pressure_angle.cos()
    }

    /// Transverse contact ratio eps_alpha = g_alpha / p_b.
    pub fn contact_ratio(&self) -> f64 {
        self.path_of_contact() / self.base_pitch()
    }

    /// ISO 6336-1 method B stiffness of this (spur, solid) pair, scaled to its Young's modulus
    /// by E / E_st (ISO 6336-1 clause 9.3; both gears of one material here, so E = E1 = E2).
    pub fn iso6336(&self) -> IsoStiffness {
        IsoStiffness::new(&IsoPair {
            teeth: (self.pinion.teeth, self.gear.teeth),
            profile_shift: (self.pinion.profile_shift, self.gear.profile_shift),
            pressure_angle: self.pressure_angle,
            helix_angle: 0.0,
            rack_dedendum: self.rack_dedendum,
            contact_ratio: self.contact_ratio(),
            rim_factor: 1.0,
            youngs_modulus_pa: (self.youngs_modulus_pa, self.youngs_modulus_pa),
        })
    }

    /// The single-tooth-contact zone [s_E - p_b, s_A + p_b], metres, of length (2 - eps_alpha)
    /// p_b (empty, start after end, when eps_alpha >= 2): a pair there has no neighbour within
    /// [s_A, s_E]; over the rest of the path two pairs share the load.
    pub fn single_contact_zone(&self) -> (f64, f64) {
        (
            self.end_of_contact() - self.base_pitch(),
            self.start_of_contact() + self.base_pitch(),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inverse_involute_inverts() {
        for deg in [10.0_f64, 20.0, 25.0, 35.0] {
            let a = deg.to_radians();
            assert!((inverse_involute(involute(a)) - a).abs() < 1e-12);
        }
    }
}
