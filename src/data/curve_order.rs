//! Order checks of curve points: within one curve, speeds increase strictly down a file and no
//! speed appears twice (in any file of the data set).

use super::csv_curves::Row;
use crate::error::Result;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// Tracks the points seen so far, curve by curve (a curve is identified by a number, e.g. its
/// load; use one value for a data set with a single curve).
#[derive(Default)]
pub(crate) struct CurveOrder {
    /// Last speed of each (file, curve) pair.
    last: HashMap<(PathBuf, u64), f64>,
    /// Where each (curve, speed) pair was first seen.
    seen: HashMap<(u64, u64), (PathBuf, usize)>,
}

impl CurveOrder {
    /// Check the point of `row` at `speed_rpm` on curve `curve` of `file`; the error names the
    /// offending row and its speed column `field`.
    pub(crate) fn check(
        &mut self,
        file: &Path,
        curve: f64,
        curve_label: &str,
        speed_rpm: f64,
        row: &Row,
        field: &str,
    ) -> Result<()> {
        let c = curve.to_bits();
        if let Some((f, line)) = self.seen.get(&(c, speed_rpm.to_bits())) {
            let at = if f == file {
                format!("line {line}")
            } else {
                format!("{}:{line}", f.display())
            };
            return Err(row.error(
                field,
                format!("duplicate speed {speed_rpm} rpm{curve_label} (also at {at})"),
            ));
        }
        if let Some(prev) = self.last.get(&(file.to_path_buf(), c)) {
            if speed_rpm < *prev {
                return Err(row.error(
                    field,
                    format!(
                        "speeds not sorted{curve_label}: {speed_rpm} rpm follows {prev} rpm; \
                         list each curve by increasing speed"
                    ),
                ));
            }
        }
        self.last.insert((file.to_path_buf(), c), speed_rpm);
        self.seen
            .insert((c, speed_rpm.to_bits()), (file.to_path_buf(), row.line));
        Ok(())
    }
}
