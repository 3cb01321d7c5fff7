//! Munro-style data sets (paper Sec. 7, Figs. 19-22): peak-to-peak dynamic transmission error
//! against speed, one curve per mean load.
//!
//! CSV header `load_n,speed_rpm,dte_pp_um` or `load_n,mesh_freq_hz,dte_pp_um` (mesh frequency
//! = pinion_teeth x rpm / 60, converted to rpm on loading), optionally with a `dte_pp_sd_um`
//! column (each point's stated standard deviation); other extra columns are ignored.

use super::csv_curves::{csv_files, CsvTable, SpeedColumns};
use super::curve_order::{CurveOrder, LoadGroups};
use super::errors::{check_data_folder, data_error};
use super::rig::{load_rig, rig_key_error, Rig, RigFile, MIN_NOISE_UM};
use super::same_load::same_load;
use crate::error::Result;
use crate::model::{MAX_DTE_UM, MAX_LOAD_N};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// Header of a Munro curve file, as shown in error messages.
const HEADER: &str = "load_n,speed_rpm,dte_pp_um";

/// Optional column: the stated standard deviation of each point's `dte_pp_um`.
const SD_COLUMN: &str = "dte_pp_sd_um";

/// One measured (or synthetic) point of a Munro curve.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MunroPoint {
    /// Mean load F_bar_m in newtons, > 0.
    pub load_n: f64,
    /// Pinion shaft speed in rpm, > 0 (converted from `mesh_freq_hz` if that was given).
    pub speed_rpm: f64,
    /// Peak-to-peak dynamic transmission error in micrometres, >= 0.
    pub dte_pp_um: f64,
    /// Stated standard deviation of `dte_pp_um` in micrometres (> 0, finite), from the optional
    /// `dte_pp_sd_um` column; `None` when the file has no such column (the noise is then taken
    /// from `[noise]` in rig.toml or estimated).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sd_um: Option<f64>,
    /// 1-based line of the point in its file.
    pub line: usize,
    /// The CSV file of the point.
    pub file: PathBuf,
}

/// A loaded and validated Munro data set.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MunroData {
    /// The data set folder.
    pub dir: PathBuf,
    /// Its `rig.toml`.
    pub rig: RigFile,
    /// All points, file by file (files sorted by name) in file order.
    pub points: Vec<MunroPoint>,
}

impl MunroData {
    /// The distinct loads of the data set, descending.
    pub fn loads(&self) -> Vec<f64> {
        let mut loads: Vec<f64> = Vec::new();
        for p in &self.points {
            if !loads.iter().any(|l| same_load(*l, p.load_n)) {
                loads.push(p.load_n);
            }
        }
        loads.sort_by(|a, b| b.total_cmp(a));
        loads
    }

    /// The loads of rig.toml's `[ste]` table that have no curve: an STE stated there is never
    /// used, and is most likely a typo (3870 for 3780 N) that drops the STE meant.
    pub fn ste_loads_without_curve(&self) -> Vec<f64> {
        let loads = self.loads();
        self.rig.ste.as_ref().map_or(Vec::new(), |ste| {
            ste.load_n
                .iter()
                .copied()
                .filter(|l| !loads.iter().any(|c| same_load(*c, *l)))
                .collect()
        })
    }

    /// The points measured at `load_n` (relative tolerance 1e-9), sorted by speed.
    pub fn curve(&self, load_n: f64) -> Vec<&MunroPoint> {
        let mut c: Vec<&MunroPoint> = self
            .points
            .iter()
            .filter(|p| same_load(p.load_n, load_n))
            .collect();
        c.sort_by(|a, b| a.speed_rpm.total_cmp(&b.speed_rpm));
        c
    }
}

/// Munro's rig as stated in Sec. 7: 32/32 teeth, diametral pitch 4 /in (module 6.35 mm), face
/// 12.7 mm, design load 3780 N, assumed backlash 2b = 0.1 mm; 20 degree pressure angle assumed.
pub fn munro_rig() -> Rig {
    Rig {
        name: "Munro four-square rig (geometry of Sec. 7)".into(),
        pinion_teeth: 32,
        gear_teeth: 32,
        module_mm: 6.35,
        pressure_angle_deg: 20.0,
        face_width_mm: 12.7,
        design_load_n: 3780.0,
        backlash_mm: 0.1,
        mesh_stiffness_n_per_um: None,
        contact_ratio: None,
        zeta: None,
        omega_n_hz: None,
        test_load_n: None,
    }
}

/// Load a Munro data set: `dir/rig.toml` and every `dir/*.csv` (sorted by name). Every failure
/// is one [`crate::GearError::Data`] naming the file, line and field.
pub fn load_munro(dir: &Path) -> Result<MunroData> {
    check_data_folder(dir)?;
    let rig = load_rig(&dir.join("rig.toml"))?;
    let mut points = Vec::new();
    let mut order = CurveOrder::default();
    let mut groups = LoadGroups::default();
    let files = csv_files(dir)?;
    for (i, file) in files.iter().enumerate() {
        let mut table = CsvTable::read(file, HEADER)?;
        let load_col = table.require("load_n", HEADER)?;
        let speed = SpeedColumns::find(&table, rig.rig.pinion_teeth, HEADER)?;
        let dte_col = table.require("dte_pp_um", HEADER)?;
        let sd_col = table.column(SD_COLUMN);
        order.start_file(file, i + 1 < files.len());
        while let Some(row) = table.next_row()? {
            let load_n = row.within(load_col, "load_n", (0.0, true), MAX_LOAD_N)?;
            let speed_rpm = speed.speed_rpm(&row)?;
            let dte_pp_um = row.within(dte_col, "dte_pp_um", (0.0, false), MAX_DTE_UM)?;
            let sd_um = sd_col
                .map(|c| row.within(c, SD_COLUMN, (MIN_NOISE_UM, false), MAX_DTE_UM))
                .transpose()?;
            let curve = groups
                .curve_of(load_n)
                .map_err(|message| row.error("load_n", message))?;
            order.check(curve, Some(load_n), speed_rpm, &row, speed.name())?;
            points.push(MunroPoint {
                load_n,
                speed_rpm,
                dte_pp_um,
                sd_um,
                line: row.line,
                file: file.clone(),
            });
        }
    }
    check_noise_statements(dir, &rig, &points)?;
    Ok(MunroData {
        dir: dir.to_path_buf(),
        rig,
        points,
    })
}

/// The noise is stated once or not at all: a `dte_pp_sd_um` column on every point or on none
/// (a file without it would leave its points to a noise the others do not share), and not
/// both a column and a `[noise]` model. Left to the fit, a column on some files only was
/// dropped without a word, and a column beside `[noise] floor_um` won without one.
fn check_noise_statements(dir: &Path, rig: &RigFile, points: &[MunroPoint]) -> Result<()> {
    let stated = points.iter().filter(|p| p.sd_um.is_some()).count();
    if stated == 0 {
        return Ok(());
    }
    if let Some(p) = points.iter().find(|p| p.sd_um.is_none()) {
        return Err(data_error(
            &p.file,
            p.line,
            SD_COLUMN,
            format!(
                "{SD_COLUMN} is given for {stated} of {} points but not for this one (its file has no such column): state it on every point of every file, or on none",
                points.len()
            ),
        ));
    }
    if let Some(noise) = &rig.noise {
        let key = if noise.floor_um.is_some() {
            Some("floor_um")
        } else {
            noise.relative.map(|_| "relative")
        };
        if let Some(key) = key {
            return Err(rig_key_error(
                dir,
                "noise",
                key,
                format!("the noise is stated twice, here and by the {SD_COLUMN} column of the CSV files: keep one"),
            ));
        }
    }
    Ok(())
}

/// Loads as "3780, 2835, 1890" (N).
pub fn loads_text(loads: &[f64]) -> String {
    loads
        .iter()
        .map(|l| format!("{l}"))
        .collect::<Vec<_>>()
        .join(", ")
}
