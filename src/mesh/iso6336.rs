//! Tooth stiffness by ISO 6336-1:2006, method B (clause 9): the single-pair stiffness c' and the
//! mesh stiffness c_gamma_alpha of a gear pair, the standard's own estimate against which the
//! potential-energy stiffness of [`super::tooth_stiffness`] is checked.
//!
//! ```text
//! q'        = C1 + C2/z_n1 + C3/z_n2 + C4 x1 + C5 x1/z_n1 + C6 x2 + C7 x2/z_n2
//!             + C8 x1^2 + C9 x2^2                           (mm um/N; eq. 64, Table 8)
//! c'_th     = 1 / q'                                        (N/(mm um))
//! c'        = c'_th C_M C_R C_B cos(beta) (E / E_st)        (eq. 62; E / E_st: clause 9.3)
//! C_B       = (1 + 0.5 (1.2 - h_fP/m_n)) (1 - 0.02 (20 deg - alpha_n))   basic rack factor
//! E         = 2 E1 E2 / (E1 + E2),  E_st = 206 000 N/mm^2
//! c_gamma_alpha = c' (0.75 eps_alpha + 0.25)                (eq. 65)
//! ```
//!
//! with z_n = z / (cos^2(beta_b) cos(beta)) the virtual numbers of teeth, C_M = 0.8 (the
//! measured-over-theoretical correction for solid disc gears) and C_R = 1 (solid gears).
//!
//! q' is stated for steel on steel. For other materials ISO 6336-1 (clause 9.3, method B)
//! multiplies c', and so c_gamma, by E / E_st with E = 2 E1 E2 / (E1 + E2) the pair's equivalent
//! modulus and E_st = 206 000 N/mm^2 ([`IsoStiffness::material_factor`]). The 2006 text was not
//! at hand to check the equation number of this factor; third-party code cites it as eqs. 90-91
//! of the 2019 edition. The standard states c' for a line load F_t / b of at least 100 N/mm;
//! below that, c' is reduced in proportion ([`IsoStiffness::line_load_factor`]). Checked in the
//! tests against ISO/TR 6336-30:2017, Example 1.

use serde::Serialize;

/// Coefficients C1..C9 of q', ISO 6336-1:2006 Table 8.
const Q_COEFFICIENTS: [f64; 9] = [
    0.04723, 0.15551, 0.25791, -0.00635, -0.11654, -0.00193, -0.24188, 0.00529, 0.00182,
];

/// Correction from the theoretical to the measured stiffness of solid disc gears, C_M.
const C_M: f64 = 0.8;

/// Line load F_t / b (N/mm) at and above which c' applies unreduced.
const FULL_LINE_LOAD_N_PER_MM: f64 = 100.0;

/// Young's modulus of the steel q' and c' are stated for, E_st = 206 000 N/mm^2 (ISO 6336-1,
/// clause 9.3), in Pa.
pub const STEEL_YOUNGS_MODULUS_PA: f64 = 206e9;

/// What ISO 6336-1 method B needs of a gear pair.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IsoPair {
    /// Numbers of teeth z1, z2.
    pub teeth: (f64, f64),
    /// Profile shift coefficients x1, x2.
    pub profile_shift: (f64, f64),
    /// Normal pressure angle alpha_n, radians.
    pub pressure_angle: f64,
    /// Helix angle beta at the reference circle, radians (0: spur).
    pub helix_angle: f64,
    /// Dedendum of the basic rack over the module, h_fP / m_n.
    pub rack_dedendum: f64,
    /// Transverse contact ratio eps_alpha.
    pub contact_ratio: f64,
    /// Rim factor C_R (1 for solid gears).
    pub rim_factor: f64,
    /// Young's moduli E1, E2 of the pinion's and the gear's material, Pa
    /// ([`STEEL_YOUNGS_MODULUS_PA`] for both: steel, factor 1).
    pub youngs_modulus_pa: (f64, f64),
}

/// The steps of method B, each as the standard names it (stiffness in N/(mm um)).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct IsoStiffness {
    /// Virtual numbers of teeth z_n1, z_n2.
    pub virtual_teeth: (f64, f64),
    /// Minimum flexibility of a tooth pair q', mm um/N.
    pub q_prime: f64,
    /// Theoretical single-pair stiffness c'_th = 1 / q'.
    pub c_prime_theoretical: f64,
    /// Basic rack factor C_B.
    pub basic_rack_factor: f64,
    /// Material factor E / E_st, E = 2 E1 E2 / (E1 + E2), E_st = 206 000 N/mm^2 (ISO 6336-1
    /// clause 9.3; 1 for steel on steel).
    pub material_factor: f64,
    /// Single-pair stiffness c' (with the material factor).
    pub c_prime: f64,
    /// Mesh stiffness c_gamma_alpha = c' (0.75 eps_alpha + 0.25).
    pub c_gamma_alpha: f64,
}

impl IsoStiffness {
    /// Method B for `pair`.
    pub fn new(pair: &IsoPair) -> Self {
        let (alpha, beta) = (pair.pressure_angle, pair.helix_angle);
        let beta_b = (beta.sin() * alpha.cos()).asin();
        let zn = |z: f64| z / (beta_b.cos().powi(2) * beta.cos());
        let (zn1, zn2) = (zn(pair.teeth.0), zn(pair.teeth.1));
        let (x1, x2) = pair.profile_shift;
        let c = Q_COEFFICIENTS;
        let q = c[0]
            + c[1] / zn1
            + c[2] / zn2
            + c[3] * x1
            + c[4] * x1 / zn1
            + c[5] * x2
            + c[6] * x2 / zn2
            + c[7] * x1 * x1
            + c[8] * x2 * x2;
        let c_th = 1.0 / q;
        let c_b =
            (1.0 + 0.5 * (1.2 - pair.rack_dedendum)) * (1.0 - 0.02 * (20.0 - alpha.to_degrees()));
        let (e1, e2) = pair.youngs_modulus_pa;
        let material = 2.0 * e1 * e2 / (e1 + e2) / STEEL_YOUNGS_MODULUS_PA;
        let c_prime = c_th * C_M * pair.rim_factor * c_b * beta.cos() * material;
        IsoStiffness {
            virtual_teeth: (zn1, zn2),
            q_prime: q,
            c_prime_theoretical: c_th,
            basic_rack_factor: c_b,
            material_factor: material,
            c_prime,
            c_gamma_alpha: c_prime * (0.75 * pair.contact_ratio + 0.25),
        }
    }

    /// The factor on c' and c_gamma_alpha at line load `n_per_mm` = F_t / b: 1 at and above
    /// 100 N/mm, (F_t / b) / 100 below (ISO 6336-1 clause 9.3).
    pub fn line_load_factor(n_per_mm: f64) -> f64 {
        (n_per_mm / FULL_LINE_LOAD_N_PER_MM).min(1.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// ISO/TR 6336-30:2017, Example 1 (helical, case-carburized: m_n 8 mm, alpha_n 20 deg,
    /// z 17/103, x 0.145/0, beta 15.8 deg, basic rack type D with h_fP = 1.4 m_n): the report
    /// gives z_n 18.905/114.543, c'_th = 17.85584 and c' = 12.37047 N/(mm um). (Values as
    /// copied in the public MATLAB code gfsReboucas/Drivetrain, MATISO_6336.m, example_01;
    /// the report itself was not at hand. C_B = 0.9 and c' / c'_th = 0.8 x 0.9 x cos(beta)
    /// agree to 7 digits.) The contact ratio is not quoted there, so c_gamma_alpha is checked
    /// through its definition only.
    #[test]
    fn iso_tr_6336_30_example_1() {
        let s = IsoStiffness::new(&IsoPair {
            teeth: (17.0, 103.0),
            profile_shift: (0.145, 0.0),
            pressure_angle: 20f64.to_radians(),
            helix_angle: 15.8f64.to_radians(),
            rack_dedendum: 1.4,
            contact_ratio: 1.5,
            rim_factor: 1.0,
            youngs_modulus_pa: (STEEL_YOUNGS_MODULUS_PA, STEEL_YOUNGS_MODULUS_PA),
        });
        assert!(
            (s.virtual_teeth.0 - 18.905).abs() < 5e-4,
            "{:?}",
            s.virtual_teeth
        );
        assert!(
            (s.virtual_teeth.1 - 114.543).abs() < 5e-4,
            "{:?}",
            s.virtual_teeth
        );
        assert!(
            (s.c_prime_theoretical - 17.85584).abs() < 2e-5,
            "{}",
            s.c_prime_theoretical
        );
        assert!((s.basic_rack_factor - 0.9).abs() < 1e-12);
        assert!((s.c_prime - 12.37047).abs() < 2e-5, "{}", s.c_prime);
        assert!((s.c_gamma_alpha - s.c_prime * 1.375).abs() < 1e-12);
    }

    /// Munro's spur gears (z 32/32, x 0, 20 deg, h_fP 1.25 m): q' = 0.04723 + (0.15551 +
    /// 0.25791) / 32 = 0.0601494 by hand, c'_th = 16.6253, C_B = 0.975, c' = 12.968.
    #[test]
    fn munro_spur_pair_by_hand() {
        let s = IsoStiffness::new(&IsoPair {
            teeth: (32.0, 32.0),
            profile_shift: (0.0, 0.0),
            pressure_angle: 20f64.to_radians(),
            helix_angle: 0.0,
            rack_dedendum: 1.25,
            contact_ratio: 1.667642,
            rim_factor: 1.0,
            youngs_modulus_pa: (STEEL_YOUNGS_MODULUS_PA, STEEL_YOUNGS_MODULUS_PA),
        });
        assert!((s.q_prime - 0.0601494).abs() < 1e-7);
        assert!((s.c_prime_theoretical - 16.6253).abs() < 1e-3);
        assert!((s.basic_rack_factor - 0.975).abs() < 1e-12);
        assert!((s.c_prime - 12.968).abs() < 1e-3);
        assert!((s.c_gamma_alpha - 12.968 * (0.75 * 1.667642 + 0.25)).abs() < 2e-3);
        assert_eq!(IsoStiffness::line_load_factor(50.0), 0.5);
        assert_eq!(IsoStiffness::line_load_factor(297.6), 1.0);
    }

    /// Other materials: c' scales by E / E_st with E = 2 E1 E2 / (E1 + E2) (ISO 6336-1 clause
    /// 9.3). Steel (206 GPa) on a 103 GPa bronze: E = 2 x 206 x 103 / 309 = 137.33 GPa, factor
    /// 2/3 by hand; the steel pair's c' and c_gamma_alpha scale by it and nothing else changes.
    #[test]
    fn other_materials_scale_by_the_equivalent_modulus() {
        let steel = IsoPair {
            teeth: (32.0, 32.0),
            profile_shift: (0.0, 0.0),
            pressure_angle: 20f64.to_radians(),
            helix_angle: 0.0,
            rack_dedendum: 1.25,
            contact_ratio: 1.667642,
            rim_factor: 1.0,
            youngs_modulus_pa: (STEEL_YOUNGS_MODULUS_PA, STEEL_YOUNGS_MODULUS_PA),
        };
        let bronze = IsoPair {
            youngs_modulus_pa: (206e9, 103e9),
            ..steel
        };
        let (s, b) = (IsoStiffness::new(&steel), IsoStiffness::new(&bronze));
        assert_eq!(s.material_factor, 1.0);
        assert!((b.material_factor - 2.0 / 3.0).abs() < 1e-12);
        assert!((b.c_prime - s.c_prime * 2.0 / 3.0).abs() < 1e-9);
        assert!((b.c_gamma_alpha - s.c_gamma_alpha * 2.0 / 3.0).abs() < 1e-9);
        assert_eq!(b.c_prime_theoretical, s.c_prime_theoretical);
    }
}
