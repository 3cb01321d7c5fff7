//! Reading curve CSV files: header lookup, numeric fields and line numbers.
//!
//! A curve file has a header row of unit-suffixed column names (extra columns are ignored),
//! comma-separated values, optional `#` comment lines, and may use CRLF line endings, a UTF-8
//! byte-order mark and blank lines. Line numbers are 1-based as shown in an editor.
//!
//! Rows are read one at a time into one reused record and line numbers are kept by a running
//! count, so a file is read in time and memory linear in its size (10^6 rows in well under a
//! second in release builds); no row is kept after the caller has looked at it.

use super::errors::{data_error, read_text};
use crate::error::{readable, GearError, Result, WHOLE_FILE};
use std::io::Cursor;
use std::path::{Path, PathBuf};

/// Field name used for "the file has no data rows".
pub(crate) const ROWS: &str = "(rows)";
/// Field name used for problems with the header line.
pub(crate) const HEADER_FIELD: &str = "(header)";
/// Field name used for problems with a row as a whole (malformed, too many fields).
pub(crate) const ROW_FIELD: &str = "(row)";

/// Maps byte offsets of a text to 1-based line numbers, for offsets that (almost always) only
/// grow: each query counts the newlines since the previous one. Counting from the start of the
/// file for every record made reading quadratic in the number of rows.
struct LineCounter {
    /// Byte offset of the last query.
    offset: usize,
    /// 1-based line of `offset`.
    line: usize,
}

impl LineCounter {
    fn new() -> Self {
        LineCounter { offset: 0, line: 1 }
    }

    /// 1-based line of byte `offset` of `text` (offsets past the end give the last line).
    fn line_at(&mut self, text: &[u8], offset: usize) -> usize {
        let offset = offset.min(text.len());
        if offset < self.offset {
            // Not expected (csv positions only move forward), but stay correct if it happens.
            *self = LineCounter::new();
        }
        self.line += text[self.offset..offset]
            .iter()
            .filter(|&&b| b == b'\n')
            .count();
        self.offset = offset;
        self.line
    }

    /// 1-based line of the record whose csv position is `pos`.
    ///
    /// csv positions point just past the previous record's terminator (so at the `\n` of a CRLF)
    /// and before any blank or `#` comment lines the reader skips, and csv's own
    /// `Position::line` counts from there too: skip those lines to the record itself.
    fn record_line(&mut self, text: &[u8], pos: &csv::Position) -> usize {
        let mut i = usize::try_from(pos.byte()).map_or(text.len(), |b| b.min(text.len()));
        loop {
            while i < text.len() && (text[i] == b'\r' || text[i] == b'\n') {
                i += 1;
            }
            if i < text.len() && text[i] == b'#' {
                while i < text.len() && text[i] != b'\n' {
                    i += 1;
                }
                continue;
            }
            break;
        }
        self.line_at(text, i)
    }
}

/// A curve file being read: trimmed header names, then its data rows one at a time
/// ([`CsvTable::next_row`]).
pub(crate) struct CsvTable {
    file: PathBuf,
    headers: Vec<String>,
    header_line: usize,
    reader: csv::Reader<Cursor<String>>,
    lines: LineCounter,
    /// The current data row (reused for every row).
    record: csv::StringRecord,
    /// 1-based line of `record`.
    line: usize,
    /// `record` holds the first data row, read ahead by [`CsvTable::read`] and not yet handed out.
    pending: bool,
}

/// One data record of a [`CsvTable`].
pub(crate) struct Row<'a> {
    file: &'a Path,
    /// 1-based line of the record.
    pub line: usize,
    record: &'a csv::StringRecord,
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

/// The separator a one-column header seems to use instead of commas (';' as spreadsheets in
/// locales with a decimal comma export, or a tab), if any.
fn foreign_separator(header: &csv::StringRecord) -> Option<&'static str> {
    if header.len() != 1 {
        return None;
    }
    let name = header.get(0).unwrap_or("").trim();
    if name.contains(';') {
        Some("';'")
    } else if name.contains('\t') {
        Some("tabs")
    } else {
        None
    }
}

impl CsvTable {
    /// Open `path` and read its header and first data row; an error if it is unreadable, not
    /// text, has no header or no data rows. `expected_header` is shown in error messages.
    pub(crate) fn read(path: &Path, expected_header: &str) -> Result<Self> {
        let text = read_text(path)?;
        if text.trim().is_empty() {
            return Err(data_error(
                path,
                1,
                HEADER_FIELD,
                format!("empty file: expected a header line `{expected_header}` and data rows"),
            ));
        }
        let mut reader = csv::ReaderBuilder::new()
            .has_headers(true)
            .flexible(true)
            // Fields are trimmed where they are read (headers, blank rows, numbers): csv's own
            // trimming copies every record, a third of the reading time on large files.
            .comment(Some(b'#'))
            .from_reader(Cursor::new(text));
        let mut lines = LineCounter::new();
        let header = match reader.headers() {
            Ok(h) => h.clone(),
            Err(e) => {
                let bytes = reader.get_ref().get_ref().as_bytes();
                let line = e.position().map_or(1, |p| lines.record_line(bytes, p));
                return Err(data_error(
                    path,
                    line,
                    HEADER_FIELD,
                    format!("bad header: {e}"),
                ));
            }
        };
        let bytes = reader.get_ref().get_ref().as_bytes();
        let header_line = header.position().map_or(1, |p| lines.record_line(bytes, p));
        let headers: Vec<String> = header.iter().map(|h| h.trim().to_string()).collect();
        if let Some(sep) = foreign_separator(&header) {
            return Err(data_error(
                path,
                header_line,
                HEADER_FIELD,
                format!(
                    "the header `{}` is separated by {sep}, not commas: geardyn expects \
                     comma-separated values with '.' as decimal point (e.g. `{expected_header}`)",
                    headers.join(",")
                ),
            ));
        }
        let mut table = CsvTable {
            file: path.to_path_buf(),
            headers,
            header_line,
            reader,
            lines,
            record: csv::StringRecord::new(),
            line: header_line,
            pending: false,
        };
        table.check_duplicate_headers()?;
        if !table.advance()? {
            return Err(data_error(
                path,
                header_line + 1,
                ROWS,
                format!(
                    "no data rows after the header `{}`",
                    table.headers.join(",")
                ),
            ));
        }
        table.pending = true;
        Ok(table)
    }

    /// Read the next data row into `record`, skipping blank ones; `false` at the end of the
    /// file. An error if the row is malformed or has more fields than the header.
    fn advance(&mut self) -> Result<bool> {
        loop {
            let read = self.reader.read_record(&mut self.record);
            let bytes = self.reader.get_ref().get_ref().as_bytes();
            let more = read.map_err(|e| {
                let line = e
                    .position()
                    .map_or(self.line + 1, |p| self.lines.record_line(bytes, p));
                data_error(
                    &self.file,
                    line,
                    ROW_FIELD,
                    format!("malformed CSV row: {e}"),
                )
            })?;
            if !more {
                return Ok(false);
            }
            self.line = match self.record.position() {
                Some(p) => self.lines.record_line(bytes, p),
                None => self.line + 1,
            };
            // Whitespace-only lines and rows of empty cells (",,,", as spreadsheets export) are
            // blank lines.
            if self.record.iter().all(|f| f.trim().is_empty()) {
                continue;
            }
            if self.record.len() > self.headers.len() {
                return Err(data_error(
                    &self.file,
                    self.line,
                    ROW_FIELD,
                    format!(
                        "row has {} fields, header has {}: a stray comma, or a decimal comma \
                         (geardyn expects '.' as decimal point)?",
                        self.record.len(),
                        self.headers.len()
                    ),
                ));
            }
            return Ok(true);
        }
    }

    /// The next data row in file order, `None` after the last.
    pub(crate) fn next_row(&mut self) -> Result<Option<Row<'_>>> {
        if self.pending {
            self.pending = false;
        } else if !self.advance()? {
            return Ok(None);
        }
        Ok(Some(Row {
            file: &self.file,
            line: self.line,
            record: &self.record,
        }))
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

    /// An error (line of the header, field `name`) for a missing column.
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
}

impl Row<'_> {
    /// A located error about column `name` of this row.
    pub(crate) fn error(&self, name: &str, message: impl Into<String>) -> GearError {
        data_error(self.file, self.line, name, message)
    }

    /// The trimmed text in column `col` (empty when missing).
    pub(crate) fn text(&self, col: usize) -> String {
        self.record.get(col).unwrap_or("").trim().to_string()
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

    /// The number in column `col`, within the plausible range [`lo`, `hi`] of its unit
    /// (`lo_open`: `lo` itself excluded). Values far outside are unit or typing mistakes
    /// (411700 for 0.4117) that would otherwise reach the fit.
    pub(crate) fn within(
        &self,
        col: usize,
        name: &str,
        (lo, lo_open): (f64, bool),
        hi: f64,
    ) -> Result<f64> {
        let v = self.number(col, name)?;
        let low = if lo_open { v <= lo } else { v < lo };
        if low || v > hi {
            let open = if lo_open { "(" } else { "[" };
            return Err(self.error(
                name,
                format!(
                    "{} is outside the plausible range {open}{}, {}] of {name}",
                    readable(v),
                    readable(lo),
                    readable(hi)
                ),
            ));
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

/// Plausible shaft speeds, rpm: beyond them the dimensionless frequency leaves the solvers'
/// range (1e-200 rpm or 1e12 rpm hung the fit).
pub(crate) const SPEED_RPM_RANGE: (f64, f64) = (0.01, 1e6);

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

    /// Shaft speed (rpm) of `row`, in [`SPEED_RPM_RANGE`].
    pub(crate) fn speed_rpm(&self, row: &Row) -> Result<f64> {
        let (lo, hi) = SPEED_RPM_RANGE;
        let from_hz = |c| -> Result<f64> {
            let hz = row.positive(c, MESH_FREQ_HZ)?;
            let rpm = hz * 60.0 / self.pinion_teeth;
            if !(lo..=hi).contains(&rpm) {
                return Err(row.error(
                    MESH_FREQ_HZ,
                    format!(
                        "{hz} Hz is {rpm} rpm with {} pinion teeth: outside the plausible \
                         range [{lo}, {hi}] rpm",
                        self.pinion_teeth
                    ),
                ));
            }
            Ok(rpm)
        };
        let rpm_col = |r| row.within(r, SPEED_RPM, (lo, false), hi);
        match (self.rpm, self.mesh_hz) {
            (Some(r), None) => rpm_col(r),
            (None, Some(h)) => from_hz(h),
            (Some(r), Some(h)) => {
                let rpm = rpm_col(r)?;
                let other = from_hz(h)?;
                if (rpm - other).abs() > SPEED_AGREEMENT * rpm {
                    // The column's value back to its printed digits (not 1066.6700000000001).
                    let hz = (other * self.pinion_teeth / 60.0 * 1e6).round() / 1e6;
                    return Err(row.error(
                        MESH_FREQ_HZ,
                        format!(
                            "the two speed columns disagree: mesh_freq_hz {hz} Hz is {} rpm \
                             with {} pinion teeth, speed_rpm says {rpm} rpm; they agree for \
                             {} teeth: is rig.toml's pinion_teeth right?",
                            (other * 10.0).round() / 10.0,
                            self.pinion_teeth,
                            (hz * 60.0 / rpm * 10.0).round() / 10.0
                        ),
                    ));
                }
                Ok(rpm)
            }
            (None, None) => Err(row.error(SPEED_RPM, "no speed column")),
        }
    }
}
