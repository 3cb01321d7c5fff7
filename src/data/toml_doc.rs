//! Locating keys of a TOML document, so that errors in `rig.toml` name a line and a key path.
//!
//! The `toml` crate reports a byte span and a message but not the key path; this module recovers
//! the path from the text: the table header in force at the error's line plus the key on that
//! line (or the key named in a "missing field" / "unknown field" message).

use super::errors::{data_error, line_of_offset};
use crate::error::GearError;
use std::path::Path;

/// The text of a TOML file and its path, for located errors.
pub(crate) struct TomlDoc<'a> {
    path: &'a Path,
    text: &'a str,
}

/// Table name of a header line `[a.b]` or `[[a.b]]`, without spaces or quotes.
fn header_name(line: &str) -> Option<String> {
    let t = line.trim();
    let inner = t.strip_prefix('[')?;
    let inner = inner.strip_prefix('[').unwrap_or(inner);
    let end = inner.find(']')?;
    Some(clean_key(&inner[..end]))
}

/// A key with surrounding spaces, spaces around dots and quotes removed.
fn clean_key(raw: &str) -> String {
    raw.split('.')
        .map(|part| part.trim().trim_matches('"').trim_matches('\''))
        .collect::<Vec<_>>()
        .join(".")
}

/// The key of a `key = value` line, if the line is one.
fn key_of_line(line: &str) -> Option<String> {
    let t = line.trim();
    if t.starts_with('#') || t.starts_with('[') {
        return None;
    }
    let eq = t.find('=')?;
    let key = clean_key(&t[..eq]);
    (!key.is_empty()).then_some(key)
}

/// The name between the first pair of backticks of `message` following `prefix`.
fn quoted_after(message: &str, prefix: &str) -> Option<String> {
    let rest = &message[message.find(prefix)? + prefix.len()..];
    let rest = rest.strip_prefix('`')?;
    let end = rest.find('`')?;
    Some(rest[..end].to_string())
}

/// `table.key`, or `key` at the top level.
fn join(table: &str, key: &str) -> String {
    if table.is_empty() {
        key.to_string()
    } else {
        format!("{table}.{key}")
    }
}

impl<'a> TomlDoc<'a> {
    /// A document at `path` with contents `text` (empty text: every line is reported as 0).
    pub(crate) fn new(path: &'a Path, text: &'a str) -> Self {
        TomlDoc { path, text }
    }

    /// Table header in force at 1-based `line` ("" before any header).
    fn table_at(&self, line: usize) -> String {
        let mut table = String::new();
        for l in self.text.lines().take(line) {
            if let Some(name) = header_name(l) {
                table = name;
            }
        }
        table
    }

    /// 1-based line where `key` of `table` is set, else the line of the table's header or of an
    /// inline `table = {..}`, else 0.
    pub(crate) fn line_of(&self, table: &str, key: &str) -> usize {
        let mut current = String::new();
        let mut table_line = 0;
        for (i, l) in self.text.lines().enumerate() {
            if let Some(name) = header_name(l) {
                if name == table && table_line == 0 {
                    table_line = i + 1;
                }
                current = name;
                continue;
            }
            let Some(k) = key_of_line(l) else { continue };
            if (current == table && k == key) || (current.is_empty() && k == join(table, key)) {
                return i + 1;
            }
            if current.is_empty() && k == table && table_line == 0 {
                table_line = i + 1;
            }
        }
        table_line
    }

    /// A located error about `key` of `table`.
    pub(crate) fn error(&self, table: &str, key: &str, message: impl Into<String>) -> GearError {
        data_error(
            self.path,
            self.line_of(table, key),
            join(table, key),
            message,
        )
    }

    /// Translate a `toml` syntax or deserialization error into a located data error.
    pub(crate) fn toml_error(&self, err: &toml::de::Error) -> GearError {
        let message = err
            .message()
            .trim()
            .lines()
            .map(str::trim)
            .collect::<Vec<_>>()
            .join("; ")
            // serde names Rust's types; a rig.toml's author wrote a number or a text.
            .replace("expected f64", "expected a number (unquoted)")
            .replace("expected u32", "expected a whole number (unquoted)")
            .replace("expected usize", "expected a whole number (unquoted)")
            .replace("expected a string", "expected a text (in quotes)");
        // An empty span at the start is how toml reports a missing top-level table: no line.
        let at = err
            .span()
            .filter(|s| !(s.start == 0 && s.end == 0))
            .map(|s| line_of_offset(self.text, s.start))
            .unwrap_or(0);
        // toml meets an array left open where the next key starts; the slip is on the line
        // that opened it.
        let unclosed = message
            .starts_with("invalid array")
            .then(|| unclosed_array_before(self.text, at))
            .flatten();
        let line = unclosed.unwrap_or(at);
        let table = if line > 0 {
            self.table_at(line)
        } else {
            String::new()
        };
        let named = quoted_after(&message, "missing field ")
            .or_else(|| quoted_after(&message, "unknown field "));
        let on_line = if line > 0 {
            self.text.lines().nth(line - 1).and_then(key_of_line)
        } else {
            None
        };
        let field = match (&named, &on_line) {
            (Some(k), _) => join(&table, k),
            (None, Some(k)) => join(&table, k),
            (None, None) => "(toml)".to_string(),
        };
        let message = if message.starts_with("unknown field") {
            format!("{message} (keys carry their unit, e.g. backlash_mm, design_load_n)")
        } else if field == "source" && message.starts_with("missing field") {
            "missing [source] table: every data set states its provenance (kind = \
             \"measured\", \"digitized\" or \"synthetic\", citation, ...)"
                .to_string()
        } else if field == "rig" && message.starts_with("missing field") {
            "missing [rig] table (name, pinion_teeth, gear_teeth, module_mm, ...)".to_string()
        } else if message.starts_with("missing field") {
            match (&named, table.is_empty()) {
                (Some(k), false) => format!("missing key `{k}` in [{table}]"),
                _ => message,
            }
        } else if unclosed.is_some() {
            "this array is not closed with `]` before the next key".to_string()
        } else {
            let text = (line > 0)
                .then(|| self.text.lines().nth(line - 1))
                .flatten();
            match text
                .and_then(syntax_hint)
                .or_else(|| text.and_then(header_hint))
            {
                Some(hint) => format!("{message} ({hint})"),
                None => message,
            }
        };
        data_error(self.path, line, field, message)
    }
}

/// What a line whose value TOML cannot read probably meant: a decimal comma (`6,35`, as a
/// spreadsheet in many locales writes it) or text without its quotes.
fn syntax_hint(line: &str) -> Option<String> {
    let value = line.split_once('=')?.1.split('#').next()?.trim();
    let digits = |t: &str| !t.is_empty() && t.chars().all(|c| c.is_ascii_digit());
    if let Some((int, frac)) = value.trim_start_matches(['-', '+']).split_once(',') {
        if digits(int) && digits(frac) {
            return Some(format!(
                "`{value}` has a decimal comma: TOML numbers take a point, {}",
                value.replace(',', ".")
            ));
        }
    }
    let first = value.chars().next()?;
    let keyword = ["true", "false", "inf", "nan"].contains(&value);
    (first.is_alphabetic() && !keyword).then(|| format!("text goes in double quotes: \"{value}\""))
}

/// The line (1-based) before `line` on which a key's array opens and is still open there:
/// brackets counted outside strings and comments. None when every array before is closed.
fn unclosed_array_before(text: &str, line: usize) -> Option<usize> {
    let (mut depth, mut opened) = (0i64, None);
    for (k, l) in text.lines().enumerate().take(line.saturating_sub(1)) {
        let mut in_string = false;
        for c in l.chars() {
            match c {
                '"' => in_string = !in_string,
                '#' if !in_string => break,
                // A header's bracket is no array; a nested one inside an open array is.
                '[' if !in_string && (depth > 0 || key_of_line(l).is_some()) => {
                    if depth == 0 {
                        opened = Some(k + 1);
                    }
                    depth += 1;
                }
                ']' if !in_string && depth > 0 => depth -= 1,
                _ => {}
            }
        }
    }
    (depth > 0).then_some(opened).flatten()
}

/// What a table header TOML cannot read probably lacks: its closing bracket.
fn header_hint(line: &str) -> Option<String> {
    let t = line.split('#').next()?.trim();
    (t.starts_with('[') && !t.ends_with(']'))
        .then(|| format!("a table header is closed with `]`: {t}]"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_are_found_in_their_table() {
        let text = "top = 1\n[rig]\nname = \"x\"\n  backlash_mm=0.1\n[source]\nname = 2\n\
                    [source.truth]\nzeta = 0.1\n";
        let d = TomlDoc::new(Path::new("rig.toml"), text);
        assert_eq!(d.line_of("rig", "backlash_mm"), 4);
        assert_eq!(d.line_of("source", "name"), 6);
        assert_eq!(d.line_of("source.truth", "zeta"), 8);
        assert_eq!(d.line_of("source", "kind"), 5);
        assert_eq!(d.line_of("ste", "load_n"), 0);
        assert_eq!(d.table_at(6), "source");
        assert_eq!(d.table_at(1), "");
    }

    /// An array left open is reported on the line that opened it, not where toml noticed; a
    /// table header without its bracket is named.
    #[test]
    fn an_open_array_is_reported_where_it_opens() {
        let text = "[rig]\nname = \"a [b\" # [\nloads = [1, 2,\n  3\nbacklash_mm = 0.1\n";
        assert_eq!(unclosed_array_before(text, 5), Some(3));
        assert_eq!(unclosed_array_before("a = [1,\n 2]\nb = 3\n", 3), None);
        assert_eq!(
            unclosed_array_before("a = [\n [1, 2],\n [3\nb = 3\n", 4),
            Some(1)
        );
        let d = TomlDoc::new(Path::new("rig.toml"), text);
        let err = toml::from_str::<toml::Value>(text).unwrap_err();
        let shown = d.toml_error(&err).to_string();
        assert!(shown.contains("rig.toml:3"), "{shown}");
        assert!(shown.contains("rig.loads"), "{shown}");
        assert!(shown.contains("not closed with `]`"), "{shown}");
        assert_eq!(
            header_hint("[rig # the rig").as_deref(),
            Some("a table header is closed with `]`: [rig]")
        );
        assert_eq!(header_hint("[rig]"), None);
    }

    /// A decimal comma and unquoted text are named; a value TOML reads is not.
    #[test]
    fn a_syntax_error_names_the_likely_slip() {
        let hint = |l: &str| syntax_hint(l).unwrap_or_default();
        assert!(hint("module_mm = 6,35").contains("decimal comma: TOML numbers take a point, 6.35"));
        assert!(hint("name = Lab B rig # ours").contains("double quotes: \"Lab B rig\""));
        assert_eq!(syntax_hint("module_mm = 6.35"), None);
        assert_eq!(syntax_hint("uncertainty = [1, 2]"), None);
        assert_eq!(syntax_hint("synthetic = true"), None);
    }

    #[test]
    fn dotted_and_inline_keys() {
        let text = "rig.name = \"x\"\nsource = { kind = \"synthetic\" }\n";
        let d = TomlDoc::new(Path::new("rig.toml"), text);
        assert_eq!(d.line_of("rig", "name"), 1);
        assert_eq!(d.line_of("source", "kind"), 2);
    }
}
