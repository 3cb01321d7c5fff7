//! Located data errors and text reading shared by the rig and curve loaders.
//!
//! Every failure is one [`GearError::Data`] naming the file, the 1-based line as the user sees
//! it in an editor (0 when no line applies) and the field (a column, a `table.key` path, or
//! [`WHOLE_FILE`] for problems with the file as a whole).

use crate::error::{GearError, Result};
use std::path::Path;

/// Field name used when the problem concerns the whole file (unreadable, not text, missing).
pub const WHOLE_FILE: &str = "(file)";

/// Build a located data error.
pub(crate) fn data_error(
    file: &Path,
    line: usize,
    field: impl Into<String>,
    message: impl Into<String>,
) -> GearError {
    GearError::Data {
        file: file.to_path_buf(),
        line,
        field: field.into(),
        message: message.into(),
    }
}

/// 1-based line number of byte offset `offset` in `text` (offsets past the end give the last line).
pub(crate) fn line_of_offset(text: &str, offset: usize) -> usize {
    let end = offset.min(text.len());
    1 + text.as_bytes()[..end]
        .iter()
        .filter(|&&b| b == b'\n')
        .count()
}

/// A data set's folder must exist and be a folder (not its rig.toml or a CSV file).
pub(crate) fn check_data_folder(dir: &Path) -> Result<()> {
    if dir.is_dir() {
        return Ok(());
    }
    let why = if dir.exists() {
        "is a file; a data set is a folder with rig.toml and CSV curves (`geardyn init-data DIR` \
         writes one)"
    } else {
        "data folder not found"
    };
    Err(data_error(dir, 0, WHOLE_FILE, why))
}

/// Read a whole file as UTF-8 text, without a leading byte-order mark.
///
/// A missing or unreadable file, or bytes that are not UTF-8 (reported at the line of the first
/// bad byte), give a located [`GearError::Data`].
pub(crate) fn read_text(path: &Path) -> Result<String> {
    if path.is_dir() {
        return Err(data_error(path, 0, WHOLE_FILE, "is a folder, not a file"));
    }
    let bytes = std::fs::read(path).map_err(|e| {
        let what = match e.kind() {
            std::io::ErrorKind::NotFound => "file not found".to_string(),
            _ => format!("cannot read file: {e}"),
        };
        data_error(path, 0, WHOLE_FILE, what)
    })?;
    let text = String::from_utf8(bytes).map_err(|e| {
        let good = e.utf8_error().valid_up_to();
        let bytes = e.as_bytes();
        let line = 1 + bytes[..good.min(bytes.len())]
            .iter()
            .filter(|&&b| b == b'\n')
            .count();
        data_error(
            path,
            line,
            WHOLE_FILE,
            format!("not UTF-8 text (invalid byte at offset {good}); is this a binary file?"),
        )
    })?;
    Ok(match text.strip_prefix('\u{feff}') {
        Some(rest) => rest.to_string(),
        None => text,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn line_numbers_are_one_based() {
        let t = "a\nb\r\nc";
        assert_eq!(line_of_offset(t, 0), 1);
        assert_eq!(line_of_offset(t, 2), 2);
        assert_eq!(line_of_offset(t, 5), 3);
        assert_eq!(line_of_offset(t, 1000), 3);
    }

    #[test]
    fn binary_and_missing_files_are_located_errors() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("junk.csv");
        std::fs::write(&p, b"ok\nline\n\xff\xfe\x00junk").unwrap();
        match read_text(&p) {
            Err(GearError::Data { line, field, .. }) => {
                assert_eq!(line, 3);
                assert_eq!(field, WHOLE_FILE);
            }
            other => panic!("expected a data error, got {other:?}"),
        }
        let missing = dir.path().join("nope.toml");
        assert!(matches!(
            read_text(&missing),
            Err(GearError::Data { line: 0, .. })
        ));
    }

    #[test]
    fn bom_is_stripped() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("bom.csv");
        std::fs::write(&p, "\u{feff}a,b\n").unwrap();
        assert_eq!(read_text(&p).unwrap(), "a,b\n");
    }
}
