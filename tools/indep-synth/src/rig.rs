//! The rig (rig.toml `[rig]` table, keys as in geardyn's docs/data-format.md) and its conversion
//! to the dimensionless model (docs/validation.md "Dimensional form", README "Your gears in
//! physical units"): b = backlash / 2, k_h from rig.toml or the ISO 6336-1 estimate
//! c' = 14 N/(mm um), c_gamma = c' (0.75 eps_alpha + 0.25), times the face width;
//! F_m = F / (b k_h), F_ah = e / b, Omega = pinion_teeth x rpm / 60 / f_n.

use std::f64::consts::PI;
use std::path::Path;

#[derive(Clone, Debug)]
pub struct Rig {
    /// The `[rig]` table as read (written back into the set unchanged, less zeta/omega_n_hz).
    pub table: toml::Table,
    pub name: String,
    pub pinion_teeth: u32,
    pub gear_teeth: u32,
    pub module_mm: f64,
    pub pressure_angle_deg: f64,
    pub face_width_mm: f64,
    pub design_load_n: f64,
    pub backlash_mm: f64,
    pub mesh_stiffness_n_per_um: Option<f64>,
    pub contact_ratio: Option<f64>,
}

/// Munro's rig as described in the paper (Sec. 7) and data/munro/rig.toml.
pub const MUNRO_RIG_TOML: &str = r#"[rig]
name = "Munro four-square rig (geometry of Sec. 7)"
pinion_teeth = 32
gear_teeth = 32
module_mm = 6.35
pressure_angle_deg = 20.0
face_width_mm = 12.7
design_load_n = 3780.0
backlash_mm = 0.1
"#;

fn num(t: &toml::Table, key: &str) -> Result<Option<f64>, String> {
    match t.get(key) {
        None => Ok(None),
        Some(toml::Value::Float(f)) => Ok(Some(*f)),
        Some(toml::Value::Integer(i)) => Ok(Some(*i as f64)),
        Some(v) => Err(format!("[rig] {key} = {v}: not a number")),
    }
}

impl Rig {
    pub fn from_toml_str(text: &str) -> Result<Rig, String> {
        let doc: toml::Table = text.parse().map_err(|e| format!("rig.toml: {e}"))?;
        let rig = doc
            .get("rig")
            .and_then(|v| v.as_table())
            .ok_or("rig.toml: no [rig] table")?
            .clone();
        let req = |k: &str| -> Result<f64, String> {
            num(&rig, k)?.ok_or(format!("rig.toml: [rig] {k} missing"))
        };
        let name = rig
            .get("name")
            .and_then(|v| v.as_str())
            .unwrap_or("rig")
            .to_string();
        Ok(Rig {
            name,
            pinion_teeth: req("pinion_teeth")? as u32,
            gear_teeth: req("gear_teeth")? as u32,
            module_mm: req("module_mm")?,
            pressure_angle_deg: req("pressure_angle_deg")?,
            face_width_mm: req("face_width_mm")?,
            design_load_n: req("design_load_n")?,
            backlash_mm: req("backlash_mm")?,
            mesh_stiffness_n_per_um: num(&rig, "mesh_stiffness_n_per_um")?,
            contact_ratio: num(&rig, "contact_ratio")?,
            table: rig,
        })
    }

    pub fn from_file(path: &Path) -> Result<Rig, String> {
        let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
        Rig::from_toml_str(&text)
    }

    pub fn munro() -> Rig {
        Rig::from_toml_str(MUNRO_RIG_TOML).expect("built-in rig")
    }

    /// Half backlash b in um.
    pub fn b_um(&self) -> f64 {
        self.backlash_mm * 1000.0 / 2.0
    }

    /// Transverse contact ratio of standard full-depth gears (addendum = module) at the standard
    /// centre distance, unless rig.toml gives one.
    pub fn contact_ratio(&self) -> f64 {
        if let Some(c) = self.contact_ratio {
            return c;
        }
        let m = self.module_mm;
        let alpha = self.pressure_angle_deg.to_radians();
        let (z1, z2) = (self.pinion_teeth as f64, self.gear_teeth as f64);
        let (r1, r2) = (m * z1 / 2.0, m * z2 / 2.0);
        let (ra1, ra2) = (r1 + m, r2 + m);
        let (rb1, rb2) = (r1 * alpha.cos(), r2 * alpha.cos());
        let a = r1 + r2;
        let path =
            (ra1 * ra1 - rb1 * rb1).sqrt() + (ra2 * ra2 - rb2 * rb2).sqrt() - a * alpha.sin();
        path / (PI * m * alpha.cos())
    }

    /// Mesh stiffness k_h in N/um and where it came from.
    pub fn mesh_stiffness(&self) -> (f64, String) {
        if let Some(k) = self.mesh_stiffness_n_per_um {
            return (k, "rig.toml mesh_stiffness_n_per_um".into());
        }
        let eps = self.contact_ratio();
        let c_gamma = 14.0 * (0.75 * eps + 0.25);
        (
            c_gamma * self.face_width_mm,
            format!("ISO 6336-1 estimate: c' = 14 N/(mm um), c_gamma = c'(0.75 eps_alpha + 0.25) = {c_gamma:.4} N/(mm um), eps_alpha = {eps:.5}, times face width {} mm", self.face_width_mm),
        )
    }

    /// Omega_h = mesh frequency / natural frequency.
    pub fn omega(&self, rpm: f64, omega_n_hz: f64) -> f64 {
        self.pinion_teeth as f64 * rpm / 60.0 / omega_n_hz
    }

    /// The `[rig]` table as TOML text for the set (zeta and omega_n_hz removed: validate munro
    /// fits them and refuses a given value).
    pub fn rig_table_text(&self) -> String {
        let mut t = self.table.clone();
        t.remove("zeta");
        t.remove("omega_n_hz");
        let mut doc = toml::Table::new();
        doc.insert("rig".into(), toml::Value::Table(t));
        toml::to_string(&doc).expect("toml")
    }
}
