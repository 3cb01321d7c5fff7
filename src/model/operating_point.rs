//! A gear pair given in the rig's units: the rig's scales ([`Dimensional`], paper Sec. 2.1)
//! with a load in newtons, an STE amplitude in micrometres, a damping ratio and a natural
//! frequency in hertz. It gives the dimensionless model of eq. 5 and converts every result back:
//! speeds to Omega_h and back, lengths q and x to micrometres (b q), the dynamic factor to a
//! mesh force (D_L F_bar_m).

use super::dimensional::Dimensional;
use super::params::GearPair;
use crate::error::{GearError, Result};
use crate::numeric::to_significant;
use serde::Serialize;

/// Largest plausible load, N (a unit mistake beyond).
pub const MAX_LOAD_N: f64 = 1e8;

/// Whether `load_n` is a load geardyn takes: in (0, [`MAX_LOAD_N`]] newtons (NaN is not).
pub fn valid_load(load_n: f64) -> bool {
    load_n > 0.0 && load_n <= MAX_LOAD_N
}
/// Largest plausible transmission error, um (a peak-to-peak DTE and its standard deviation, an
/// STE amplitude): a millimetre of transmission error is a unit mistake, not a measurement.
pub const MAX_DTE_UM: f64 = 1000.0;

/// The operating point of a gear pair in the rig's units.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct OperatingPoint {
    /// The rig's half backlash b, mesh stiffness k_h and pinion teeth.
    pub dim: Dimensional,
    /// Mean load F_bar_m transmitted by the mesh, N, in (0, 1e8].
    pub load_n: f64,
    /// STE amplitude e_bar (half the peak-to-peak static transmission error), um, in [0, 1000].
    pub ste_um: f64,
    /// Damping ratio zeta = c_h / (2 m_c omega_n), in (0, 1).
    pub zeta: f64,
    /// Natural frequency f_n = omega_n / (2 pi) = sqrt(k_h / m_c) / (2 pi), Hz, in [1, 1e6].
    pub omega_n_hz: f64,
}

impl OperatingPoint {
    /// The operating point, every value checked against its range
    /// ([`GearError::InvalidParameter`] naming it otherwise).
    pub fn new(
        dim: Dimensional,
        load_n: f64,
        ste_um: f64,
        zeta: f64,
        omega_n_hz: f64,
    ) -> Result<Self> {
        let checks: [(&'static str, f64, bool, &'static str); 4] = [
            (
                "load_n",
                load_n,
                valid_load(load_n),
                "mean load must be in (0, 1e8] N",
            ),
            (
                "ste_um",
                ste_um,
                (0.0..=MAX_DTE_UM).contains(&ste_um),
                "STE amplitude must be in [0, 1000] um",
            ),
            (
                "zeta",
                zeta,
                zeta > 0.0 && zeta < 1.0,
                "damping ratio must be in (0, 1)",
            ),
            (
                "omega_n_hz",
                omega_n_hz,
                (1.0..=1e6).contains(&omega_n_hz),
                "natural frequency must be in [1, 1e6] Hz",
            ),
        ];
        if let Some((name, value, _, reason)) = checks.into_iter().find(|c| !c.2) {
            return Err(GearError::param(name, value, reason));
        }
        Ok(OperatingPoint {
            dim,
            load_n,
            ste_um,
            zeta,
            omega_n_hz,
        })
    }

    /// Dimensionless mean load F_m = F_bar_m / (b k_h).
    pub fn mean_force(&self) -> f64 {
        self.dim.mean_force(self.load_n)
    }

    /// Dimensionless STE amplitude F_ah = e_bar / b.
    pub fn ste_amplitude(&self) -> f64 {
        self.dim.ste_amplitude(self.ste_um)
    }

    /// The paper's model (eq. 5) at this operating point and dimensionless frequency `omega`.
    pub fn model(&self, omega: f64) -> Result<GearPair> {
        GearPair::paper(self.mean_force(), self.ste_amplitude(), self.zeta, omega)
    }

    /// Omega_h = f_mesh / f_n at a pinion speed in rpm (f_mesh = teeth x rpm / 60).
    pub fn omega(&self, speed_rpm: f64) -> f64 {
        self.dim.omega(speed_rpm, self.omega_n_hz)
    }

    /// Pinion speed in rpm at Omega_h (inverse of [`OperatingPoint::omega`]).
    pub fn speed_rpm(&self, omega: f64) -> f64 {
        self.dim.speed_rpm(omega, self.omega_n_hz)
    }

    /// Mesh frequency in Hz at Omega_h: Omega_h f_n.
    pub fn mesh_frequency_hz(&self, omega: f64) -> f64 {
        omega * self.omega_n_hz
    }

    /// A length of the dimensionless model (q, its half or mid range, the pp DTE x_pp) in
    /// micrometres: b times it.
    pub fn micrometres(&self, x: f64) -> f64 {
        self.dim.dte_um(x)
    }

    /// The largest mesh force in newtons for a dynamic factor D_L (mesh force over mean force).
    pub fn mesh_force_n(&self, dynamic_factor: f64) -> f64 {
        dynamic_factor * self.load_n
    }

    /// The conversion in words, one equation a line with its numbers (for the command line and
    /// reports), with the speed `example_rpm` converted as an example.
    pub fn conversion_lines(&self, example_rpm: f64) -> Vec<String> {
        let b_um = to_significant(self.dim.half_backlash_m * 1e6, 6);
        let k = to_significant(self.dim.mesh_stiffness_n_per_m * 1e-6, 6);
        let z = self.dim.pinion_teeth;
        let ste_um = to_significant(self.ste_um, 6);
        let f_n = to_significant(self.omega_n_hz, 8);
        vec![
            "Rig units to the dimensionless model (Kahraman & Singh 1990, Sec. 2.1):".to_string(),
            format!("  b    = backlash / 2 = {b_um} µm (half backlash)"),
            format!(
                "  k_h  = {k} N/µm (mesh stiffness: {})",
                self.dim.stiffness_source.describe()
            ),
            format!(
                "  F_m  = F̄_m / (b k_h) = {} N / ({b_um} µm × {k} N/µm) = {:.6}",
                self.load_n,
                self.mean_force()
            ),
            format!(
                "  F_ah = ē / b = {ste_um} µm / {b_um} µm = {:.6};  F̂ = F_m / F_ah = {}",
                self.ste_amplitude(),
                if self.ste_um > 0.0 {
                    format!("{:.4}", self.mean_force() / self.ste_amplitude())
                } else {
                    "∞ (no STE)".to_string()
                }
            ),
            format!("  ζ    = c_h / (2 m_c ω_n) = {} (dimensionless)", self.zeta),
            format!(
                "  Ω_h  = f_mesh / f_n, f_mesh = z₁ n / 60 = {z} n / 60, f_n = {f_n} Hz: n = {} rpm gives f_mesh = {:.6} Hz, Ω_h = {:.6}",
                example_rpm,
                self.dim.mesh_frequency_hz(example_rpm),
                self.omega(example_rpm)
            ),
            format!(
                "  back to the rig: q̄ = b q and pp DTE = b x_pp (µm, b = {b_um} µm), peak mesh force = D_L F̄_m (N)"
            ),
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{munro_spec, GearSpec};

    /// Munro's rig with a given mesh stiffness of 250 N/um and 2b = 0.1 mm, so that every
    /// scale is a round number: b k_h = 50e-6 m x 250e6 N/m = 12500 N.
    fn munro_250() -> Dimensional {
        let gears = GearSpec {
            mesh_stiffness_n_per_um: Some(250.0),
            ..munro_spec()
        };
        Dimensional::new(&gears).unwrap()
    }

    #[test]
    fn converts_by_hand_numbers() {
        let p = OperatingPoint::new(munro_250(), 1250.0, 2.5, 0.02, 1600.0).unwrap();
        // F_m = 1250 N / 12500 N = 0.1; F_ah = 2.5 um / 50 um = 0.05.
        assert!((p.mean_force() - 0.1).abs() < 1e-15);
        assert!((p.ste_amplitude() - 0.05).abs() < 1e-15);
        // 1500 rpm x 32 / 60 = 800 Hz mesh frequency = Omega 0.5 at 1600 Hz.
        assert!((p.omega(1500.0) - 0.5).abs() < 1e-15);
        assert!((p.speed_rpm(0.5) - 1500.0).abs() < 1e-9);
        assert!((p.mesh_frequency_hz(0.5) - 800.0).abs() < 1e-12);
        assert!((p.micrometres(2.0) - 100.0).abs() < 1e-12);
        assert!((p.mesh_force_n(1.5) - 1875.0).abs() < 1e-12);
        let m = p.model(0.5).unwrap();
        assert_eq!((m.zeta, m.omega), (0.02, 0.5));
        let text = p.conversion_lines(1500.0).join("\n");
        assert!(text.contains("= 0.100000") && text.contains("Ω_h = 0.500000"));
    }

    #[test]
    fn out_of_range_values_are_named() {
        let cases = [
            ("load_n", (0.0, 2.5, 0.02, 1600.0)),
            ("ste_um", (1000.0, f64::NAN, 0.02, 1600.0)),
            ("zeta", (1000.0, 2.5, 1.0, 1600.0)),
            ("omega_n_hz", (1000.0, 2.5, 0.02, 0.5)),
        ];
        for (name, (l, e, z, f)) in cases {
            match OperatingPoint::new(munro_250(), l, e, z, f) {
                Err(GearError::InvalidParameter { name: n, .. }) => assert_eq!(n, name),
                other => panic!("{name}: {other:?}"),
            }
        }
    }
}
