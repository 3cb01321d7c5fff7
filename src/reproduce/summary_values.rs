//! Reading numbers out of the studies' JSON summaries (`src/study`), by path.

use serde_json::Value;

/// The value at a path of object keys and array indices, e.g. `&["curves", "1", "peak", "qa"]`.
pub fn at<'a>(v: &'a Value, path: &[&str]) -> Option<&'a Value> {
    path.iter()
        .try_fold(v, |cur, key| match key.parse::<usize>() {
            Ok(i) if cur.is_array() => cur.get(i),
            _ => cur.get(*key),
        })
}

/// A number at a path.
pub fn num(v: &Value, path: &[&str]) -> Option<f64> {
    at(v, path).and_then(Value::as_f64)
}

/// A `[lo, hi]` pair at a path (`None` when null or absent).
pub fn range(v: &Value, path: &[&str]) -> Option<(f64, f64)> {
    let a = at(v, path)?.as_array()?;
    Some((a.first()?.as_f64()?, a.get(1)?.as_f64()?))
}

/// A list of numbers at a path (empty when absent).
pub fn list(v: &Value, path: &[&str]) -> Vec<f64> {
    at(v, path)
        .and_then(Value::as_array)
        .map(|a| a.iter().filter_map(Value::as_f64).collect())
        .unwrap_or_default()
}

/// A boolean at a path.
pub fn flag(v: &Value, path: &[&str]) -> Option<bool> {
    at(v, path).and_then(Value::as_bool)
}
