//! Parsing and formatting helpers of `geardyn digitize`: colon-separated numbers, pixel
//! indices, the crop box and marker size, column names, constant columns, CSV numbers and the check-file paths.

use anyhow::{bail, Context};
use geardyn::digitize::PixelBox;
use std::path::{Path, PathBuf};

/// Exactly `N` colon-separated finite numbers.
pub fn numbers<const N: usize>(flag: &str, text: &str, form: &str) -> anyhow::Result<[f64; N]> {
    let parts: Vec<&str> = text.split(':').collect();
    if parts.len() != N {
        bail!("{flag} '{text}': expected {form} ({N} numbers separated by ':')");
    }
    let mut out = [0.0; N];
    for (o, s) in out.iter_mut().zip(&parts) {
        *o = s
            .trim()
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .with_context(|| {
                format!("{flag} '{text}': '{s}' is not a finite number; expected {form}")
            })?;
    }
    Ok(out)
}

/// A pixel index: a whole number >= 0.
pub fn pixel(v: f64) -> anyhow::Result<u32> {
    if v >= 0.0 && v.fract() == 0.0 && v <= f64::from(u32::MAX) {
        Ok(v as u32)
    } else {
        bail!("{v} is not a pixel index (a whole number >= 0)")
    }
}

/// The two names of --columns.
pub fn columns(text: &str) -> anyhow::Result<(String, String)> {
    let names: Vec<&str> = text.split(',').map(str::trim).collect();
    match names.as_slice() {
        [x, y] if !x.is_empty() && !y.is_empty() && x != y => Ok((x.to_string(), y.to_string())),
        _ => {
            bail!("--columns '{text}': expected two different names X,Y, e.g. speed_rpm,dte_pp_um")
        }
    }
}

/// The --const NAME=VALUE pairs, in order, with distinct names other than the two columns.
pub fn constants(items: &[String], taken: [&str; 2]) -> anyhow::Result<Vec<(String, f64)>> {
    let mut out: Vec<(String, f64)> = Vec::new();
    for item in items {
        let Some((name, value)) = item.split_once('=') else {
            bail!("--const '{item}': expected NAME=VALUE, e.g. load_n=1890");
        };
        let name = name.trim();
        if name.is_empty() || name.contains(',') {
            bail!("--const '{item}': the name must be non-empty and without commas");
        }
        if taken.contains(&name) || out.iter().any(|(n, _)| n == name) {
            bail!("--const '{item}': column '{name}' is given twice");
        }
        let v = value
            .trim()
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .with_context(|| format!("--const '{item}': '{value}' is not a finite number"))?;
        out.push((name.to_string(), v));
    }
    Ok(out)
}

/// A value rounded to 9 significant digits (far finer than any pixel of a figure) and written in
/// the shortest form that reads back to that rounded value.
pub fn number(v: f64) -> String {
    let rounded = format!("{v:.8e}").parse::<f64>().unwrap_or(v);
    format!("{rounded}")
}

/// `out` without its extension, with `suffix` appended (`_check`, `_plot`).
pub fn stem_with(out: &Path, suffix: &str) -> PathBuf {
    let mut name = out.file_stem().unwrap_or_default().to_os_string();
    name.push(suffix);
    out.with_file_name(name)
}

/// `--crop X0:Y0:X1:Y1` (pixels).
pub fn crop_box(t: &str) -> anyhow::Result<PixelBox> {
    let [x0, y0, x1, y1] = numbers::<4>("--crop", t, "X0:Y0:X1:Y1")?.map(pixel);
    let ctx = || format!("--crop '{t}'");
    Ok(PixelBox {
        x0: x0.with_context(ctx)?,
        y0: y0.with_context(ctx)?,
        x1: x1.with_context(ctx)?,
        y1: y1.with_context(ctx)?,
    })
}

/// `--marker-size MIN:MAX` (pixels).
pub fn marker_size(t: &str) -> anyhow::Result<(u32, u32)> {
    let [lo, hi] = numbers::<2>("--marker-size", t, "MIN:MAX")?.map(pixel);
    let ctx = || format!("--marker-size '{t}'");
    let (lo, hi) = (lo.with_context(ctx)?, hi.with_context(ctx)?);
    if lo > hi {
        bail!("--marker-size '{t}': MIN is larger than MAX");
    }
    Ok((lo, hi))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parsing_helpers() {
        assert_eq!(
            numbers::<4>("f", "1:-2:3e2: 4", "F").unwrap(),
            [1.0, -2.0, 300.0, 4.0]
        );
        assert!(numbers::<4>("f", "1:2:3", "F").is_err());
        assert!(numbers::<2>("f", "1:nan", "F").is_err());
        assert!(pixel(-1.0).is_err() && pixel(1.5).is_err());
        assert_eq!(pixel(7.0).unwrap(), 7);
        assert_eq!(columns("a, b").unwrap(), ("a".into(), "b".into()));
        assert!(columns("a").is_err() && columns("a,a").is_err() && columns("a,").is_err());
        let c = constants(&["load_n=1890".into()], ["x", "y"]).unwrap();
        assert_eq!(c, [("load_n".to_string(), 1890.0)]);
        assert!(constants(&["x=1".into()], ["x", "y"]).is_err());
        assert!(constants(&["load".into()], ["x", "y"]).is_err());
        assert!(constants(&["l=inf".into()], ["x", "y"]).is_err());
        assert_eq!(number(1890.0), "1890");
        assert_eq!(number(0.1 + 0.2), "0.3");
        assert_eq!(number(1234.567890123), "1234.56789");
        assert_eq!(
            stem_with(Path::new("d/m/load.csv"), "_check"),
            Path::new("d/m/load_check")
        );
        assert_eq!(
            stem_with(Path::new("load"), "_plot"),
            Path::new("load_plot")
        );
    }
}
