//! Reading curve CSV files: header lookup, numeric fields and line numbers.
//!
//! A curve file has a header row of unit-suffixed column names (extra columns are ignored),
//! comma-separated values, optional `#` comment lines, and may use CRLF line endings, a UTF-8
//! byte-order mark and blank lines. Line numbers are 1-based as shown in an editor.

use super::errors::{data_error, line_of_offset, read_text, WHOLE_FILE};
use crate::error::{GearError, Result};
use std::path::{Path, PathBuf};

/// Field name used for "the file has no data rows".
pub(crate) const ROWS: &str = "(rows)";

/// A parsed CSV file: trimmed header names and data records with their line numbers.
pub(crate) struct CsvTable {
    file: PathBuf,
    headers: Vec<String>,
    header_line: usize,
    rows: Vec<(usize, csv::StringRecord)>,
}

/// One data record of a [`CsvTable`].
pub(crate) struct Row<'a> {
    file: &'a Path,
    /// 1-based line of the record.
    pub line: usize,
    record: &'a csv::StringRecord,
}

/// 1-based line of the record at a csv position in `text`.
///
/// csv positions point just past the previous record's terminator (so at the `\n` of a CRLF)
/// and before any blank or `#` comment lines the reader skips: skip those to the record itself.
fn line_of(text: &str, pos: &csv::Position) -> usize {
    let b = text.as_bytes();
    let mut i = (pos.byte() as usize).min(b.len());
    loop {
        while i < b.len() && (b[i] == b'\r' || b[i] == b'\n') {
            i += 1;
        }
        if i < b.len() && b[i] == b'#' {
            while i < b.len() && b[i] != b'\n' {
                i += 1;
            }
            continue;
        }
        break;
    }
    line_of_offset(text, i)
}

/// Line of a csv error, or `fallback`.
fn csv_error_line(text: &str, e: &csv::Error, fallback: usize) -> usize {
    e.position().map(|p| line_of(text, p)).unwrap_or(fallback)
}

/// All `*.csv` files of `dir`, sorted by name; an error if there are none.
pub(crate) fn csv_files(dir: &Path) -> Result<Vec<PathBuf>> {
    let entries = std::fs::read_dir(dir)
        .map_err(|e| data_error(dir, 0, WHOLE_FILE, format!("cannot read data folder: {e}")))?;
    let mut files = Vec::new();
    for entry in entries {
        let entry = entry
            .map_err(|e| data_error(dir, 0, WHOLE_FILE, format!("cannot read data folder: {e}")))?;
        let path = entry.path();
        let is_csv = path
            .extension()
            .is_some_and(|x| x.eq_ignore_ascii_case("csv"));
        if is_csv && path.is_file() {
            files.push(path);
        }
    }
    files.sort();
    if files.is_empty() {
        return Err(data_error(
            dir,
            0,
            WHOLE_FILE,
            "no *.csv curve files in the data folder",
        ));
    }
    Ok(files)
}

impl CsvTable {
    /// Read `path`; an error if it is unreadable, not text, has no header or no data rows.
    pub(crate) fn read(path: &Path, expected_header: &str) -> Result<Self> {
        let text = read_text(path)?;
        if text.trim().is_empty() {
            return Err(data_error(
                path,
                1,
                "(header)",
                format!("empty file: expected a header line `{expected_header}` and data rows"),
            ));
        }
        let mut reader = csv::ReaderBuilder::new()
            .has_headers(true)
            .flexible(true)
            .trim(csv::Trim::All)
            .comment(Some(b'#'))
            .from_reader(text.as_bytes());
        let header = reader.headers().map_err(|e| {
            let line = csv_error_line(&text, &e, 1);
            data_error(path, line, "(header)", format!("bad header: {e}"))
        })?;
        let header_line = header.position().map(|p| line_of(&text, p)).unwrap_or(1);
        let headers: Vec<String> = header.iter().map(|h| h.trim().to_string()).collect();
        let mut rows = Vec::new();
        for (i, rec) in reader.records().enumerate() {
            let rec = rec.map_err(|e| {
                let line = csv_error_line(&text, &e, header_line + i + 1);
                data_error(path, line, "(row)", format!("malformed CSV row: {e}"))
            })?;
            let line = rec
                .position()
                .map(|p| line_of(&text, p))
                .unwrap_or(header_line + i + 1);
            // Whitespace-only lines and rows of empty cells (",,,", as spreadsheets export) are
            // blank lines.
            if rec.iter().all(|f| f.trim().is_empty()) {
                continue;
            }
            rows.push((line, rec));
        }
        if rows.is_empty() {
            return Err(data_error(
                path,
                header_line + 1,
                ROWS,
                format!("no data rows after the header `{}`", headers.join(",")),
            ));
        }
        let table = CsvTable {
            file: path.to_path_buf(),
            headers,
            header_line,
            rows,
        };
        table.check_duplicate_headers()?;
        Ok(table)
    }

    /// An error if a column name appears twice.
    fn check_duplicate_headers(&self) -> Result<()> {
        for (i, h) in self.headers.iter().enumerate() {
            if !h.is_empty() && self.headers[..i].contains(h) {
                return Err(data_error(
                    &self.file,
                    self.header_line,
                    h.clone(),
                    "duplicate column",
                ));
            }
        }
        Ok(())
    }

    /// Index of column `name`, if present.
    pub(crate) fn column(&self, name: &str) -> Option<usize> {
        self.headers.iter().position(|h| h == name)
    }

    /// An error (line 1, field `name`) for a missing column.
    pub(crate) fn missing(&self, name: &str, expected_header: &str) -> GearError {
        data_error(
            &self.file,
            self.header_line,
            name,
            format!(
                "missing column '{name}' (found: {}; expected e.g. `{expected_header}`)",
                self.headers.join(", ")
            ),
        )
    }

    /// Index of column `name`, or an error naming it.
    pub(crate) fn require(&self, name: &str, expected_header: &str) -> Result<usize> {
        self.column(name)
            .ok_or_else(|| self.missing(name, expected_header))
    }

    /// The data rows in file order.
    pub(crate) fn rows(&self) -> impl Iterator<Item = Row<'_>> {
        self.rows.iter().map(|(line, record)| Row {
            file: &self.file,
            line: *line,
            record,
        })
    }

    /// The file this table was read from.
    pub(crate) fn file(&self) -> &Path {
        &self.file
    }
}

impl Row<'_> {
    /// A located error about column `name` of this row.
    pub(crate) fn error(&self, name: &str, message: impl Into<String>) -> GearError {
        data_error(self.file, self.line, name, message)
    }

    /// The finite number in column `col` (named `name`).
    pub(crate) fn number(&self, col: usize, name: &str) -> Result<f64> {
        let raw = self.record.get(col).unwrap_or("").trim();
        if raw.is_empty() {
            return Err(self.error(name, "missing value"));
        }
        let v: f64 = raw
            .parse()
            .map_err(|_| self.error(name, format!("'{raw}' is not a number")))?;
        if !v.is_finite() {
            return Err(self.error(name, format!("'{raw}' is not a finite number")));
        }
        Ok(v)
    }

    /// The positive finite number in column `col`.
    pub(crate) fn positive(&self, col: usize, name: &str) -> Result<f64> {
        let v = self.number(col, name)?;
        if v <= 0.0 {
            return Err(self.error(name, format!("{v} must be positive")));
        }
        Ok(v)
    }

    /// The non-negative finite number in column `col`.
    pub(crate) fn non_negative(&self, col: usize, name: &str) -> Result<f64> {
        let v = self.number(col, name)?;
        if v < 0.0 {
            return Err(self.error(name, format!("{v} must not be negative")));
        }
        Ok(v)
    }
}

/// Where the shaft speed of a row comes from: a `speed_rpm` column, a `mesh_freq_hz` column
/// (converted with the pinion's teeth), or both (then they must agree).
pub(crate) struct SpeedColumns {
    rpm: Option<usize>,
    mesh_hz: Option<usize>,
    pinion_teeth: f64,
}

/// Column name of shaft speed.
pub(crate) const SPEED_RPM: &str = "speed_rpm";
/// Column name of mesh frequency.
pub(crate) const MESH_FREQ_HZ: &str = "mesh_freq_hz";

/// Relative disagreement tolerated between `speed_rpm` and `mesh_freq_hz` given together.
const SPEED_AGREEMENT: f64 = 5e-3;

impl SpeedColumns {
    /// Find the speed columns of `table`; an error if neither is present.
    pub(crate) fn find(table: &CsvTable, pinion_teeth: u32, expected: &str) -> Result<Self> {
        let rpm = table.column(SPEED_RPM);
        let mesh_hz = table.column(MESH_FREQ_HZ);
        if rpm.is_none() && mesh_hz.is_none() {
            return Err(table.missing(SPEED_RPM, expected));
        }
        Ok(SpeedColumns {
            rpm,
            mesh_hz,
            pinion_teeth: pinion_teeth as f64,
        })
    }

    /// Name of the column the speed of a row is read from.
    pub(crate) fn name(&self) -> &'static str {
        if self.rpm.is_some() {
            SPEED_RPM
        } else {
            MESH_FREQ_HZ
        }
    }

    /// Shaft speed (rpm) of `row`, positive.
    pub(crate) fn speed_rpm(&self, row: &Row) -> Result<f64> {
        let from_hz =
            |c| -> Result<f64> { Ok(row.positive(c, MESH_FREQ_HZ)? * 60.0 / self.pinion_teeth) };
        match (self.rpm, self.mesh_hz) {
            (Some(r), None) => row.positive(r, SPEED_RPM),
            (None, Some(h)) => from_hz(h),
            (Some(r), Some(h)) => {
                let rpm = row.positive(r, SPEED_RPM)?;
                let other = from_hz(h)?;
                if (rpm - other).abs() > SPEED_AGREEMENT * rpm {
                    return Err(row.error(
                        MESH_FREQ_HZ,
                        format!(
                            "inconsistent units: mesh_freq_hz gives {other:.6} rpm with {} \
                             pinion teeth but speed_rpm is {rpm}",
                            self.pinion_teeth
                        ),
                    ));
                }
                Ok(rpm)
            }
            (None, None) => Err(row.error(SPEED_RPM, "no speed column")),
        }
    }
}
