//! A profile-modification table (CSV): the relief of each gear's flank against diameter, as a
//! profile inspection (K-chart) or a modification drawing gives it, for the tooth-contact model
//! (`geardyn mesh --profile-table FILE`, docs/data-format.md):
//!
//! ```text
//! gear,diameter_mm,relief_um
//! pinion,190.0,0.0
//! pinion,215.9,12.5
//! gear,190.0,0.0
//! ```
//!
//! `relief_um` is material removed from the true involute, measured along the line of action
//! (positive as a tip relief; negative for excess material). A gear without rows has no
//! deviation. The model does not know this file: it gets the points ([`ProfilePoints`]).

use super::csv_curves::CsvTable;
use super::errors::data_error;
use crate::error::{GearError, Result};
use std::path::{Path, PathBuf};

/// The header the table expects.
pub const PROFILE_HEADER: &str = "gear,diameter_mm,relief_um";

/// Largest plausible diameter, mm (a 10 m gear).
const MAX_DIAMETER_MM: f64 = 1e4;
/// Largest plausible relief or deviation, um.
const MAX_RELIEF_UM: f64 = 1000.0;
/// Most rows read (a profile scan has hundreds).
const MAX_ROWS: usize = 100_000;

/// The table's points per gear, (diameter mm, relief um), in increasing diameter.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ProfilePoints {
    /// Pinion flank.
    pub pinion: Vec<(f64, f64)>,
    /// Gear flank.
    pub gear: Vec<(f64, f64)>,
    /// The table the points were read from, with each point's line, so that a point the
    /// geometry refuses is named where it was written (`None`: points given in code).
    pub source: Option<TableLines>,
}

/// Where a profile table's points were written.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TableLines {
    pub file: PathBuf,
    /// Line of each pinion point, then of each gear point.
    pub pinion: Vec<usize>,
    pub gear: Vec<usize>,
}

impl ProfilePoints {
    /// The error for point `point` of `gear` ("pinion" or "gear"; `None`: its rows as a whole,
    /// named at its last row): located in the table when it was read from one.
    pub fn error_at(&self, gear: &str, point: Option<usize>, message: String) -> GearError {
        let Some(src) = &self.source else {
            return GearError::Unsupported(message);
        };
        let lines = if gear == "pinion" {
            &src.pinion
        } else {
            &src.gear
        };
        let line = point
            .and_then(|i| lines.get(i))
            .or(lines.last())
            .copied()
            .unwrap_or(0);
        let field = if point.is_some() {
            "diameter_mm"
        } else {
            "gear"
        };
        data_error(&src.file, line, field, message)
    }
}

/// Read a profile-modification table. Errors name the file, line and column: a missing column,
/// a gear other than `pinion` or `gear`, a diameter or relief outside its plausible range, a
/// diameter not above the previous one of the same gear, a gear with a single row.
pub fn load_profile_table(path: &Path) -> Result<ProfilePoints> {
    let mut table = CsvTable::read(path, PROFILE_HEADER)?;
    let gear_col = table.require("gear", PROFILE_HEADER)?;
    let d_col = table.require("diameter_mm", PROFILE_HEADER)?;
    let r_col = table.require("relief_um", PROFILE_HEADER)?;
    let mut points = ProfilePoints::default();
    let mut lines = TableLines {
        file: path.to_path_buf(),
        ..TableLines::default()
    };
    let mut rows = 0;
    let mut last_line = 0;
    while let Some(row) = table.next_row()? {
        rows += 1;
        last_line = row.line;
        if rows > MAX_ROWS {
            return Err(row.error(
                "gear",
                format!("more than {MAX_ROWS} rows: a profile table has hundreds"),
            ));
        }
        let which = row.text(gear_col);
        let (list, at) = match which.as_str() {
            "pinion" => (&mut points.pinion, &mut lines.pinion),
            "gear" => (&mut points.gear, &mut lines.gear),
            _ => return Err(row.error("gear", format!("'{which}': expected pinion or gear"))),
        };
        let d = row.within(d_col, "diameter_mm", (0.0, true), MAX_DIAMETER_MM)?;
        let r = row.within(r_col, "relief_um", (-MAX_RELIEF_UM, false), MAX_RELIEF_UM)?;
        if let Some(&(prev, _)) = list.last() {
            if d <= prev {
                return Err(row.error(
                    "diameter_mm",
                    format!(
                        "{d} mm is not above the previous {which} row's {prev} mm: list each \
                         gear's points in increasing diameter"
                    ),
                ));
            }
        }
        list.push((d, r));
        at.push(row.line);
    }
    for (name, list) in [("pinion", &points.pinion), ("gear", &points.gear)] {
        if list.len() == 1 {
            return Err(data_error(
                path,
                last_line,
                "gear",
                format!("{name} has one row: give at least two points of its flank, or none"),
            ));
        }
    }
    points.source = Some(lines);
    Ok(points)
}
