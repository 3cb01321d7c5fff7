//! Kubo-style data sets (paper Sec. 7, Fig. 23): the envelope of the dynamic factor over eight
//! tooth pairs against speed, one curve at the test load.
//!
//! CSV header `speed_rpm,dynamic_factor_min,dynamic_factor_max` (or `mesh_freq_hz` instead of
//! `speed_rpm`, converted to rpm on loading); extra columns are ignored.

use super::csv_curves::{csv_files, CsvTable, SpeedColumns};
use super::curve_order::CurveOrder;
use super::errors::{check_data_folder, data_error};
use super::rig::{load_rig, RigFile};
use crate::error::Result;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// Header of a Kubo curve file, as shown in error messages.
const HEADER: &str = "speed_rpm,dynamic_factor_min,dynamic_factor_max";

/// One point of the dynamic-factor envelope.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct KuboPoint {
    /// Pinion shaft speed in rpm, > 0 (converted from `mesh_freq_hz` if that was given).
    pub speed_rpm: f64,
    /// Lower edge of the envelope of the dynamic factor, >= 0.
    pub dynamic_factor_min: f64,
    /// Upper edge of the envelope, >= `dynamic_factor_min`.
    pub dynamic_factor_max: f64,
    /// 1-based line of the point in its file.
    pub line: usize,
    /// The CSV file of the point.
    pub file: PathBuf,
}

/// A loaded and validated Kubo data set.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct KuboData {
    /// The data set folder.
    pub dir: PathBuf,
    /// Its `rig.toml` (`rig.test_load_n` is the load of the curve).
    pub rig: RigFile,
    /// All points, file by file (files sorted by name) in file order.
    pub points: Vec<KuboPoint>,
}

/// Largest plausible dynamic factor (peak over mean mesh force).
pub const MAX_DYNAMIC_FACTOR: f64 = 100.0;

/// Load a Kubo data set: `dir/rig.toml` and every `dir/*.csv` (sorted by name). Every failure
/// is one [`crate::GearError::Data`] naming the file, line and field.
pub fn load_kubo(dir: &Path) -> Result<KuboData> {
    check_data_folder(dir)?;
    let rig = load_rig(&dir.join("rig.toml"))?;
    let mut points = Vec::new();
    let mut order = CurveOrder::default();
    let files = csv_files(dir)?;
    for (i, file) in files.iter().enumerate() {
        let mut table = CsvTable::read(file, HEADER)?;
        let speed = SpeedColumns::find(&table, rig.rig.pinion_teeth, HEADER)?;
        let min_col = table.require("dynamic_factor_min", HEADER)?;
        let max_col = table.require("dynamic_factor_max", HEADER)?;
        order.start_file(file, i + 1 < files.len());
        while let Some(row) = table.next_row()? {
            let speed_rpm = speed.speed_rpm(&row)?;
            let lo = row.within(
                min_col,
                "dynamic_factor_min",
                (0.0, false),
                MAX_DYNAMIC_FACTOR,
            )?;
            let hi = row.within(
                max_col,
                "dynamic_factor_max",
                (0.0, false),
                MAX_DYNAMIC_FACTOR,
            )?;
            if lo > hi {
                return Err(row.error(
                    "dynamic_factor_min",
                    format!("dynamic_factor_min {lo} exceeds dynamic_factor_max {hi}"),
                ));
            }
            order.check(0, None, speed_rpm, &row, speed.name())?;
            points.push(KuboPoint {
                speed_rpm,
                dynamic_factor_min: lo,
                dynamic_factor_max: hi,
                line: row.line,
                file: file.clone(),
            });
        }
    }
    check_envelope_width(&points)?;
    Ok(KuboData {
        dir: dir.to_path_buf(),
        rig,
        points,
    })
}

/// A band with a width somewhere: min = max on every row is one column given twice (or a curve
/// without its scatter), from which the fit cannot read the spread from tooth pair to tooth pair.
fn check_envelope_width(points: &[KuboPoint]) -> Result<()> {
    let flat = points.len() > 1
        && points
            .iter()
            .all(|p| p.dynamic_factor_min == p.dynamic_factor_max);
    match points.first() {
        Some(first) if flat => Err(data_error(
            &first.file,
            first.line,
            "dynamic_factor_max",
            "dynamic_factor_min equals dynamic_factor_max on every row: not an envelope (Kubo's \
             band has the width of the scatter from tooth pair to tooth pair, which the fit \
             reads); give the band's lower and upper edges, or a single curve as the band of \
             its reading uncertainty (value - u, value + u)",
        )),
        _ => Ok(()),
    }
}
