//! Dimensional <-> dimensionless conversion of Sec. 2.1 (design.md section 1, "Dimensional form").
//!
//! With half backlash b, mesh stiffness k_h and natural frequency omega_n = sqrt(k_h / m_c):
//! F_m = F_bar_m / (b k_h), F_ah = e_bar / b, Omega_h = Omega_bar_h / omega_n, zeta =
//! c_h / (2 m_c omega_n), and the dynamic transmission error x_bar = b x. The mesh frequency is
//! (teeth of the pinion) x (shaft speed).
//!
//! When the rig does not give k_h, it is estimated from the gear geometry with ISO 6336-1
//! (method B/C values for solid steel spur gears with a standard basic rack):
//!
//! - single-pair stiffness c' = 14 N/(mm um) ([`ISO6336_C_PRIME`]),
//! - mesh stiffness c_gamma = c' (0.75 eps_alpha + 0.25), per millimetre of face width,
//! - k_h = c_gamma x face width (N/um), i.e. 1e6 x that in N/m,
//!
//! where the transverse contact ratio eps_alpha is the rig's `contact_ratio`, else that of
//! standard full-depth involute gears ([`Dimensional::standard_contact_ratio`]). The estimate is
//! a mean over the mesh cycle, valid for loads above about 100 N/mm of face width; the source of
//! k_h is recorded in [`StiffnessSource`] so that reports can say which was used.
//!
//! The scales are made from plain numbers ([`GearSpec`]); a data set's rig file gives them, and
//! its conversion (checked first) lives where data meets the model, `data::Rig::dimensional`.

use super::Term;
use crate::error::{GearError, Result};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// ISO 6336-1 single-pair tooth stiffness c' for solid steel spur gears, N/(mm um).
pub const ISO6336_C_PRIME: f64 = 14.0;

/// Where the mesh stiffness k_h came from.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum StiffnessSource {
    /// Given in the rig file (`mesh_stiffness_n_per_um`).
    Given,
    /// Estimated with ISO 6336-1: c_gamma = c' (0.75 eps_alpha + 0.25), k_h = c_gamma x face width.
    Iso6336Estimate {
        /// Single-pair stiffness c', N/(mm um).
        c_prime_n_per_mm_um: f64,
        /// Mesh stiffness per face width c_gamma, N/(mm um).
        c_gamma_n_per_mm_um: f64,
        /// Transverse contact ratio eps_alpha used.
        contact_ratio: f64,
    },
    /// The mean loaded mesh stiffness k_h(F) of the tooth-contact model (`crate::mesh`) at a
    /// load.
    Geometry {
        /// The load, N.
        load_n: f64,
    },
}

impl StiffnessSource {
    /// A snake_case tag for machine-readable outputs: `rig_toml` or `iso6336_estimate`.
    pub fn tag(&self) -> &'static str {
        match self {
            StiffnessSource::Given => "rig_toml",
            StiffnessSource::Iso6336Estimate { .. } => "iso6336_estimate",
            StiffnessSource::Geometry { .. } => "geometry",
        }
    }

    /// The source in words, with the estimate's numbers (for reports).
    pub fn describe(&self) -> String {
        match self {
            StiffnessSource::Given => "given in rig.toml (mesh_stiffness_n_per_um)".into(),
            StiffnessSource::Iso6336Estimate {
                c_prime_n_per_mm_um,
                c_gamma_n_per_mm_um,
                contact_ratio,
            } => format!(
                "ISO 6336-1 estimate: c' = {c_prime_n_per_mm_um:.1} N/(mm um), c_gamma = c' (0.75 eps_alpha + 0.25) = {c_gamma_n_per_mm_um:.2} N/(mm um) at eps_alpha = {contact_ratio:.3}, times the face width"
            ),
            StiffnessSource::Geometry { load_n } => format!(
                "mean loaded stiffness of the tooth-contact model at {load_n} N (geardyn mesh)"
            ),
        }
    }
}

/// What the dimensional scales of a gear pair are made from, in the rig's units (the keys of
/// the same names in a rig file's `[rig]` table).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GearSpec {
    /// Number of teeth of the pinion (the mesh frequency is pinion_teeth x shaft speed).
    pub pinion_teeth: u32,
    /// Number of teeth of the gear.
    pub gear_teeth: u32,
    /// Module in millimetres.
    pub module_mm: f64,
    /// Pressure angle in degrees.
    pub pressure_angle_deg: f64,
    /// Face width in millimetres.
    pub face_width_mm: f64,
    /// Total backlash 2b in millimetres.
    pub backlash_mm: f64,
    /// Mesh stiffness k_h in N/um if known; otherwise estimated with ISO 6336-1.
    pub mesh_stiffness_n_per_um: Option<f64>,
    /// Transverse contact ratio eps_alpha if known; otherwise that of standard geometry.
    pub contact_ratio: Option<f64>,
}

/// The dimensional scales of a rig: half backlash b, mesh stiffness k_h and the pinion's teeth.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Dimensional {
    /// Half backlash b in metres (half of `backlash_mm`).
    pub half_backlash_m: f64,
    /// Mesh stiffness k_h in N/m.
    pub mesh_stiffness_n_per_m: f64,
    /// Whether k_h was given or estimated.
    pub stiffness_source: StiffnessSource,
    /// Teeth of the pinion (mesh frequency = teeth x shaft speed).
    pub pinion_teeth: u32,
    /// Base circle diameter of the pinion d_b1 = m z1 cos(alpha), metres.
    pub base_diameter_pinion_m: f64,
    /// Base circle diameter of the gear d_b2 = m z2 cos(alpha), metres.
    pub base_diameter_gear_m: f64,
}

impl Dimensional {
    /// Transverse contact ratio of standard full-depth involute spur gears (addendum = 1
    /// module, standard centre distance a = m (z1 + z2) / 2):
    ///
    /// eps_alpha = (sqrt(ra1^2 - rb1^2) + sqrt(ra2^2 - rb2^2) - a sin(alpha)) / (pi m cos(alpha)),
    ///
    /// with ra = m (z/2 + 1), rb = m z cos(alpha) / 2. Independent of the module.
    pub fn standard_contact_ratio(
        pinion_teeth: u32,
        gear_teeth: u32,
        pressure_angle_deg: f64,
    ) -> f64 {
        let alpha = pressure_angle_deg.to_radians();
        let (z1, z2) = (pinion_teeth as f64, gear_teeth as f64);
        // lengths in modules
        let path = |z: f64| {
            let ra = z / 2.0 + 1.0;
            let rb = z / 2.0 * alpha.cos();
            (ra * ra - rb * rb).max(0.0).sqrt()
        };
        let a = (z1 + z2) / 2.0;
        (path(z1) + path(z2) - a * alpha.sin()) / (PI * alpha.cos())
    }

    /// The scales of a gear pair: b = backlash / 2, k_h given or estimated with ISO 6336-1 (see
    /// the module's notes), d_b = m z cos(alpha). The values are taken as given (a rig file's are
    /// range-checked before, by `data::Rig::dimensional`); a contact ratio below 1 gives
    /// [`GearError::InvalidParameter`].
    pub fn new(gears: &GearSpec) -> Result<Self> {
        let alpha = gears.pressure_angle_deg.to_radians();
        let m = gears.module_mm * 1e-3;
        let (k, source) = match gears.mesh_stiffness_n_per_um {
            Some(k_um) => (k_um * 1e6, StiffnessSource::Given),
            None => {
                let eps = match gears.contact_ratio {
                    Some(e) => e,
                    None => Self::standard_contact_ratio(
                        gears.pinion_teeth,
                        gears.gear_teeth,
                        gears.pressure_angle_deg,
                    ),
                };
                if !(eps.is_finite() && eps >= 1.0) {
                    return Err(GearError::param(
                        "contact_ratio",
                        eps,
                        "standard geometry gives a contact ratio below 1; give \
                         mesh_stiffness_n_per_um or contact_ratio in rig.toml",
                    ));
                }
                let c_gamma = ISO6336_C_PRIME * (0.75 * eps + 0.25);
                (
                    c_gamma * gears.face_width_mm * 1e6,
                    StiffnessSource::Iso6336Estimate {
                        c_prime_n_per_mm_um: ISO6336_C_PRIME,
                        c_gamma_n_per_mm_um: c_gamma,
                        contact_ratio: eps,
                    },
                )
            }
        };
        Ok(Dimensional {
            half_backlash_m: gears.backlash_mm / 2.0 * 1e-3,
            mesh_stiffness_n_per_m: k,
            stiffness_source: source,
            pinion_teeth: gears.pinion_teeth,
            base_diameter_pinion_m: m * gears.pinion_teeth as f64 * alpha.cos(),
            base_diameter_gear_m: m * gears.gear_teeth as f64 * alpha.cos(),
        })
    }

    /// Dimensionless mean force F_m = F_bar_m / (b k_h) for a load in newtons.
    pub fn mean_force(&self, load_n: f64) -> f64 {
        load_n / (self.half_backlash_m * self.mesh_stiffness_n_per_m)
    }

    /// Dimensionless STE amplitude F_ah = e_bar / b for an amplitude e_bar in micrometres.
    pub fn ste_amplitude(&self, ste_um: f64) -> f64 {
        ste_um * 1e-6 / self.half_backlash_m
    }

    /// The STE terms of eq. 5 / eq. 20 (order j, F_ahj, phase) of harmonics given as (order,
    /// amplitude e_j in micrometres, phase rad).
    pub fn ste_terms(&self, terms_um: &[(u32, f64, f64)]) -> Vec<Term> {
        terms_um
            .iter()
            .map(|&(order, um, phase)| Term {
                order,
                amplitude: self.ste_amplitude(um),
                phase,
            })
            .collect()
    }

    /// STE amplitude e_bar in micrometres for a dimensionless F_ah (inverse of
    /// [`Dimensional::ste_amplitude`]).
    pub fn ste_um(&self, f_ah: f64) -> f64 {
        f_ah * self.half_backlash_m * 1e6
    }

    /// Mesh frequency in Hz at a pinion speed in rpm: teeth x rpm / 60.
    pub fn mesh_frequency_hz(&self, speed_rpm: f64) -> f64 {
        self.pinion_teeth as f64 * speed_rpm / 60.0
    }

    /// Dimensionless mesh frequency Omega_h = Omega_bar_h / omega_n: mesh frequency over natural
    /// frequency, both in Hz.
    pub fn omega(&self, speed_rpm: f64, omega_n_hz: f64) -> f64 {
        self.mesh_frequency_hz(speed_rpm) / omega_n_hz
    }

    /// Pinion speed in rpm at dimensionless frequency Omega_h (inverse of [`Dimensional::omega`]).
    pub fn speed_rpm(&self, omega: f64, omega_n_hz: f64) -> f64 {
        omega * omega_n_hz * 60.0 / self.pinion_teeth as f64
    }

    /// Dimensional peak-to-peak DTE in micrometres, b x pp(x), for a dimensionless pp(x).
    pub fn dte_um(&self, x_pp: f64) -> f64 {
        x_pp * self.half_backlash_m * 1e6
    }

    /// Equivalent mass m_c = k_h / omega_n^2 (kg), omega_n = 2 pi omega_n_hz rad/s.
    pub fn equivalent_mass_kg(&self, omega_n_hz: f64) -> f64 {
        let w = 2.0 * PI * omega_n_hz;
        self.mesh_stiffness_n_per_m / (w * w)
    }

    /// Mesh damping c_h = 2 zeta m_c omega_n (N s/m), omega_n in rad/s.
    pub fn damping_n_s_per_m(&self, zeta: f64, omega_n_hz: f64) -> f64 {
        2.0 * zeta * self.equivalent_mass_kg(omega_n_hz) * 2.0 * PI * omega_n_hz
    }
}

/// Munro's rig (paper Sec. 7): 32/32 teeth, DP 4 (m = 6.35 mm), 20 deg, face 12.7 mm, assumed
/// 2b = 0.1 mm, stiffness and contact ratio not given (for tests).
#[cfg(test)]
pub(crate) fn munro_spec() -> GearSpec {
    GearSpec {
        pinion_teeth: 32,
        gear_teeth: 32,
        module_mm: 6.35,
        pressure_angle_deg: 20.0,
        face_width_mm: 12.7,
        backlash_mm: 0.1,
        mesh_stiffness_n_per_um: None,
        contact_ratio: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn munro_contact_ratio_against_independent_forms() {
        let eps = Dimensional::standard_contact_ratio(32, 32, 20.0);
        // Hand computation (mm): ra = 107.95, rb = 101.6 cos 20 = 95.4728, a = 203.2:
        // (2 sqrt(107.95^2 - 95.4728^2) - 203.2 sin 20) / (pi 6.35 cos 20)
        // = (2 x 50.3801 - 69.4985) / 18.7463 = 1.66764.
        assert!((eps - 1.66764).abs() < 1e-4, "eps = {eps}");
        // Independent form via the pressure angle at the tip circle alpha_a (roll angles):
        // eps = [z1 (tan alpha_a1 - tan alpha) + z2 (tan alpha_a2 - tan alpha)] / (2 pi).
        let alpha = 20f64.to_radians();
        let alpha_a = (16.0 * alpha.cos() / 17.0).acos();
        let eps_roll = 2.0 * 32.0 * (alpha_a.tan() - alpha.tan()) / (2.0 * PI);
        assert!((eps - eps_roll).abs() < 1e-12);
        // Published approximation for standard 20 deg spur gears (Niemann / DIN 3960):
        // eps ~ 1.88 - 3.2 (1/z1 + 1/z2) = 1.68; it is good to about 0.02 for z >= 20.
        let approx = 1.88 - 3.2 * (1.0 / 32.0 + 1.0 / 32.0);
        assert!(
            (eps - approx).abs() < 0.02,
            "eps = {eps}, approx = {approx}"
        );
    }

    #[test]
    fn munro_stiffness_and_mean_force() {
        let d = Dimensional::new(&munro_spec()).unwrap();
        let StiffnessSource::Iso6336Estimate {
            c_prime_n_per_mm_um,
            c_gamma_n_per_mm_um,
            contact_ratio,
        } = d.stiffness_source
        else {
            panic!("expected the ISO estimate")
        };
        assert_eq!(c_prime_n_per_mm_um, 14.0);
        assert!((contact_ratio - 1.66764).abs() < 1e-4);
        // c_gamma = 14 (0.75 x 1.66764 + 0.25) = 21.0102 N/(mm um)
        assert!((c_gamma_n_per_mm_um - 21.0102).abs() < 1e-3);
        // k_h = 21.0102 x 12.7 = 266.83 N/um
        assert!((d.mesh_stiffness_n_per_m - 266.83e6).abs() < 0.01e6);
        assert!((d.half_backlash_m - 50e-6).abs() < 1e-15);
        // F_m = 3780 / (50e-6 x 266.83e6) = 0.28333
        assert!((d.mean_force(3780.0) - 0.28333).abs() < 1e-4);
        // d_b = 6.35 x 32 x cos 20 = 190.9455 mm
        assert!((d.base_diameter_pinion_m - 0.1909455).abs() < 1e-7);
        assert_eq!(d.base_diameter_pinion_m, d.base_diameter_gear_m);
        assert!((d.mesh_frequency_hz(1500.0) - 800.0).abs() < 1e-12);
    }

    #[test]
    fn given_stiffness_and_contact_ratio_are_used() {
        let mut gears = munro_spec();
        gears.contact_ratio = Some(2.0);
        let d = Dimensional::new(&gears).unwrap();
        assert!((d.mesh_stiffness_n_per_m - 14.0 * 1.75 * 12.7e6).abs() < 1.0);
        gears.mesh_stiffness_n_per_um = Some(250.0);
        let d = Dimensional::new(&gears).unwrap();
        assert_eq!(d.stiffness_source, StiffnessSource::Given);
        assert!((d.mesh_stiffness_n_per_m - 250e6).abs() < 1e-6);
    }

    #[test]
    fn round_trips() {
        let d = Dimensional::new(&munro_spec()).unwrap();
        for rpm in [10.0, 1234.5, 6000.0] {
            let w = d.omega(rpm, 1600.0);
            assert!((d.speed_rpm(w, 1600.0) - rpm).abs() < 1e-9 * rpm);
        }
        for um in [0.5, 2.0, 4.0] {
            let f = d.ste_amplitude(um);
            assert!((d.ste_um(f) - um).abs() < 1e-12);
        }
        assert!((d.ste_amplitude(5.0) - 0.1).abs() < 1e-12);
        assert!((d.dte_um(2.0) - 100.0).abs() < 1e-9);
        // zeta = c_h / (2 m_c omega_n) and omega_n = sqrt(k_h / m_c) are recovered.
        let (zeta, f_n) = (0.0175, 1600.0);
        let m = d.equivalent_mass_kg(f_n);
        let wn = (d.mesh_stiffness_n_per_m / m).sqrt();
        assert!((wn - 2.0 * PI * f_n).abs() < 1e-9 * wn);
        let c = d.damping_n_s_per_m(zeta, f_n);
        assert!((c / (2.0 * m * wn) - zeta).abs() < 1e-12);
    }
}
