//! `geardyn compare` (issue 3, item 3): harmonic balance against simulation, through the CLI.

mod common;

use common::geardyn_json;
use serde_json::Value;

fn compare(fah: &str, omega: &str, out: &std::path::Path) -> Value {
    let out = out.to_string_lossy().to_string();
    geardyn_json(&[
        "compare",
        "--fm",
        "0.1",
        "--fah",
        fah,
        "--zeta",
        "0.05",
        "--omega",
        omega,
        "--ic-grid",
        "-2:2:7",
        "--harmonics",
        "15",
        "--json",
        "--out",
        &out,
    ])
}

fn omegas_of(list: &Value) -> Vec<f64> {
    list.as_array()
        .map(|a| a.iter().filter_map(|g| g["omega"].as_f64()).collect())
        .unwrap_or_default()
}

/// F_hat 2 (Fig. 11-13 parameters): in the dual-valued region the AFT branch (H = 15) has a
/// stable lower (case I) and a stable upper (case II) solution, and the simulation reaches both
/// from the 7 x 7 IC grid. Tolerance 1%: the AFT series with 15 harmonics differs from the exact
/// piecewise solution only by the truncation of the impact kink (observed <= 3e-5 here), and 1%
/// is the match tolerance of the comparison itself; a wrong branch differs by > 50%.
#[test]
fn both_branches_of_the_dual_valued_region_are_matched() {
    let dir = tempfile::tempdir().expect("temp dir");
    let v = compare("0.05", "0.6:0.9:0.02", dir.path());
    let gaps = &v["gaps"];
    let matched = gaps["matched"].as_array().cloned().unwrap_or_default();
    assert!(omegas_of(&gaps["sim_unmatched"]).is_empty(), "{gaps}");
    assert!(omegas_of(&gaps["aft_unreached"]).is_empty(), "{gaps}");
    assert!(omegas_of(&gaps["non_period1"]).is_empty(), "{gaps}");
    let mut dual = Vec::new();
    for k in 0..16 {
        let w = 0.6 + 0.02 * k as f64;
        let here: Vec<&Value> = matched
            .iter()
            .filter(|m| m["omega"].as_f64().is_some_and(|o| (o - w).abs() < 1e-9))
            .collect();
        assert!(!here.is_empty(), "no match at {w}");
        for m in &here {
            assert!(m["rel"].as_f64().is_some_and(|r| r <= 0.01), "{m}");
        }
        if here.len() == 2 {
            let qa: Vec<f64> = here.iter().filter_map(|m| m["aft_qa"].as_f64()).collect();
            assert!(
                qa[1] > 2.0 * qa[0] || qa[0] > 2.0 * qa[1],
                "distinct branches {qa:?}"
            );
            dual.push(w);
        }
    }
    let (lo, hi) = (dual[0], dual[dual.len() - 1]);
    assert!(
        (0.68..=0.74).contains(&lo) && (0.80..=0.84).contains(&hi),
        "{dual:?}"
    );
    assert_eq!(
        dual.len(),
        ((hi - lo) / 0.02).round() as usize + 1,
        "{dual:?}"
    );
    for f in ["compare.png", "compare.svg", "compare.csv", "compare.json"] {
        assert!(dir.path().join(f).is_file(), "{f}");
    }
    let csv = std::fs::read_to_string(dir.path().join("compare.csv")).unwrap_or_default();
    assert!(csv.starts_with("source,omega,qa,qm"));
    for src in [
        "df-exact",
        "aft,",
        "aft-grid",
        "sweep-up",
        "sweep-down",
        "attractors",
    ] {
        assert!(csv.contains(&format!("\n{src}")), "{src}");
    }
}

/// F_hat 0.5 (Sec. 5(b)): above Omega ~ 0.78 the simulation finds period-2, other subharmonic
/// and chaotic attractors, which period-1 harmonic balance cannot represent; below, every
/// period-1 attractor has an AFT point within 1%.
#[test]
fn subharmonic_and_chaotic_attractors_are_reported_as_missed_by_hb() {
    let dir = tempfile::tempdir().expect("temp dir");
    let v = compare("0.2", "0.7:1.0:0.04", dir.path());
    let gaps = &v["gaps"];
    let np1 = omegas_of(&gaps["non_period1"]);
    for k in 0..8 {
        let w = 0.7 + 0.04 * k as f64;
        let found = np1.iter().any(|o| (o - w).abs() < 1e-9);
        assert_eq!(found, w > 0.78, "non-period-1 at {w}: {np1:?}");
    }
    assert!(
        gaps["non_period1"]
            .as_array()
            .is_some_and(|a| a.iter().all(|g| g["period"].as_u64() != Some(1))),
        "{gaps}"
    );
    let unmatched = omegas_of(&gaps["sim_unmatched"]);
    assert!(unmatched.is_empty(), "{unmatched:?}");
    let summary = v["summary"].to_string();
    assert!(summary.contains("non-period-1"), "{summary}");
}
