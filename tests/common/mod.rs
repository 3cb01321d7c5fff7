//! Helpers shared by the integration tests: run the geardyn binary as a user would.

#![allow(dead_code)]

use serde_json::Value;
use std::process::{Command, Output};

/// Run geardyn with arguments; return the raw output.
pub fn geardyn(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_geardyn"))
        .args(args)
        .output()
        .expect("the geardyn binary runs")
}

/// Run geardyn, require success, parse standard output as JSON.
pub fn geardyn_json(args: &[&str]) -> Value {
    let out = geardyn(args);
    assert!(
        out.status.success(),
        "geardyn {:?} failed: {}",
        args,
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("valid JSON on stdout")
}

/// Attractors of eq. 5 at one frequency from the paper's IC square [-2, 2]^2.
pub fn attractors(
    fm: f64,
    fah: f64,
    zeta: f64,
    omega: f64,
    grid: &str,
    extra: &[&str],
) -> Vec<Value> {
    let (fm, fah, zeta, omega) = (
        fm.to_string(),
        fah.to_string(),
        zeta.to_string(),
        omega.to_string(),
    );
    let mut args = vec![
        "attractors",
        "--fm",
        &fm,
        "--fah",
        &fah,
        "--zeta",
        &zeta,
        "--omega",
        &omega,
        "--ic-grid",
        grid,
        "--json",
    ];
    args.extend_from_slice(extra);
    geardyn_json(&args)["attractors"]
        .as_array()
        .expect("attractors array")
        .clone()
}

/// (period, impact) of each attractor, periods as 0 when none.
pub fn kinds(list: &[Value]) -> Vec<(u64, String)> {
    list.iter()
        .map(|a| {
            (
                a["period"].as_u64().unwrap_or(0),
                a["impact"].as_str().unwrap_or("?").to_string(),
            )
        })
        .collect()
}

/// Attractors with a given period.
pub fn with_period(list: &[Value], p: u64) -> Vec<&Value> {
    list.iter()
        .filter(|a| a["period"].as_u64() == Some(p))
        .collect()
}

/// The (x, y) pairs of a digitized CSV: the last two columns of every row after the header
/// (constant columns such as load_n come first).
pub fn read_xy_csv(path: &std::path::Path) -> Vec<(f64, f64)> {
    let text = std::fs::read_to_string(path).unwrap();
    text.lines()
        .skip(1)
        .map(|l| {
            let v: Vec<f64> = l.split(',').map(|v| v.parse().unwrap()).collect();
            (v[v.len() - 2], v[v.len() - 1])
        })
        .collect()
}
