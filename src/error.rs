//! Typed errors of the library. Every error a user can cause names what was wrong with the input.

use std::path::{Path, PathBuf};

/// Errors raised by geardyn's library code.
#[derive(Debug, thiserror::Error)]
pub enum GearError {
    /// A model or solver parameter is outside its admissible range.
    #[error("invalid parameter {name} = {}: {reason}", readable(*value))]
    InvalidParameter {
        name: &'static str,
        value: f64,
        reason: &'static str,
    },
    /// A request that the chosen method cannot honour (e.g. the exact solver with k(t) != 1).
    #[error("{0}")]
    Unsupported(String),
    /// Malformed input data, located by file, line and field (line 0: the file as a whole, a
    /// key it lacks, or a check over several lines).
    #[error("{location}: {what}{message}", location = located(file, *line), what = field_part(field))]
    Data {
        file: PathBuf,
        line: usize,
        field: String,
        message: String,
    },
    /// A numerical method failed to produce a trustworthy answer.
    #[error("numerical failure: {0}")]
    Numerical(String),
    /// A fit to a data set ended where its result cannot be used (a parameter run to a bound,
    /// an infinite interval, a non-finite residual): nothing is predicted or written from it.
    #[error("the fit to {data} failed: {reason}", data = data.display())]
    FitFailed { data: PathBuf, reason: String },
    /// File system errors while reading inputs or writing outputs.
    #[error("{path}: {source}", path = path.display())]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// A figure image could not be digitized as asked (e.g. no pixel of the curve colour, a crop
    /// box outside the image).
    #[error("{0}")]
    Digitize(String),
    /// Rendering a figure failed.
    #[error("plot {path}: {message}", path = path.display())]
    Plot { path: PathBuf, message: String },
}

/// The field of a [`GearError::Data`] whose problem concerns the whole file (unreadable, not
/// text, missing).
pub const WHOLE_FILE: &str = "(file)";

/// Shorthand result type.
pub type Result<T> = std::result::Result<T, GearError>;

impl GearError {
    /// An I/O error on `path`, as a closure for `map_err`.
    pub fn io(path: &Path) -> impl Fn(std::io::Error) -> GearError + '_ {
        move |source| GearError::Io {
            path: path.to_path_buf(),
            source,
        }
    }

    /// Convenience constructor for an out-of-range parameter.
    pub fn param(name: &'static str, value: f64, reason: &'static str) -> Self {
        GearError::InvalidParameter {
            name,
            value,
            reason,
        }
    }
}

/// A value as a message shows it: Rust's shortest exact decimal, in exponent form outside
/// [1e-4, 1e7) so that 1e-300 does not print as 300 digits.
pub fn readable(x: f64) -> String {
    let a = x.abs();
    if a == 0.0 || !a.is_finite() || (1e-4..1e7).contains(&a) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// "field 'F': ", or nothing when the problem is the file as a whole.
fn field_part(field: &str) -> String {
    if field == WHOLE_FILE {
        String::new()
    } else {
        format!("field '{field}': ")
    }
}

/// `file:line`, or the file alone when no line applies (line 0).
fn located(file: &Path, line: usize) -> String {
    match line {
        0 => file.display().to_string(),
        n => format!("{}:{n}", file.display()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_read_in_a_few_characters() {
        assert_eq!(readable(0.1), "0.1");
        assert_eq!(readable(3780.0), "3780");
        assert_eq!(readable(1e-300), "1e-300");
        assert_eq!(readable(-2.5e299), "-2.5e299");
        assert_eq!(readable(f64::NAN), "NaN");
        let e = GearError::param("F_m", 2.8e271, "too large");
        assert_eq!(e.to_string(), "invalid parameter F_m = 2.8e271: too large");
    }
}
