//! Located data errors and text reading shared by the rig and curve loaders.
//!
//! Every failure is one [`GearError::Data`] naming the file, the 1-based line as the user sees
//! it in an editor (0 when no line applies) and the field (a column, a `table.key` path, or
//! [`WHOLE_FILE`] for problems with the file as a whole).

use crate::error::{GearError, Result, WHOLE_FILE};
use std::path::Path;

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
            format!(
                "not UTF-8 text (invalid byte at offset {good}); {}",
                encoding_hint(bytes)
            ),
        )
    })?;
    Ok(match text.strip_prefix('\u{feff}') {
        Some(rest) => rest.to_string(),
        None => text,
    })
}

/// What a file that is not UTF-8 probably is, and what to do: UTF-16 (a byte-order mark, or
/// every other byte zero, as spreadsheet programs save "Unicode text"), a binary file (other
/// zero bytes), else text in a single-byte code page (Latin-1, Windows-1252: a degree sign or
/// a micro sign saved by an older editor).
fn encoding_hint(bytes: &[u8]) -> &'static str {
    let head = &bytes[..bytes.len().min(4096)];
    let zeros_at = |parity: usize| {
        head.iter()
            .enumerate()
            .filter(|(k, b)| k % 2 == parity && **b == 0)
            .count()
    };
    let half = head.len() / 2;
    let utf16 = head.starts_with(&[0xFF, 0xFE])
        || head.starts_with(&[0xFE, 0xFF])
        || (half > 0 && (zeros_at(0) * 4 > half * 3 || zeros_at(1) * 4 > half * 3));
    if utf16 {
        "it looks like UTF-16 (\"Unicode text\"): save it as UTF-8 (CSV UTF-8)"
    } else if head.contains(&0) {
        "is this a binary file (a spreadsheet, not its CSV export)?"
    } else {
        "it looks like text in a single-byte code page (Latin-1, Windows-1252): save it as UTF-8"
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// UTF-16 with and without its byte-order mark, a binary file and Latin-1 text are told
    /// apart.
    #[test]
    fn a_file_that_is_not_utf8_gets_the_likely_encoding() {
        let utf16le: Vec<u8> = "load_n,speed_rpm\n"
            .encode_utf16()
            .flat_map(u16::to_le_bytes)
            .collect();
        assert!(encoding_hint(&utf16le).contains("UTF-16"));
        let with_bom = [&[0xFF, 0xFE][..], &utf16le].concat();
        assert!(encoding_hint(&with_bom).contains("UTF-16"));
        assert!(
            encoding_hint(b"PK\x03\x04\x14\x00\x06\x00\x08\x00\x00\x00!\x00\xff")
                .contains("binary")
        );
        assert!(encoding_hint(b"load_n,speed_rpm,note\n3780,1000,25\xb0C\n").contains("Latin-1"));
    }

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
