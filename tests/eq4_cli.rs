//! The external torque excitation of eq. 4 (`--fat`, alone with `--fah 0` or together with the
//! STE of eq. 5) through the simulation and harmonic-balance commands, checked against the
//! closed form of the linear regime and between the exact simulation and AFT.

mod common;
use common::geardyn_json;

/// Linear amplitude of a force F sin(Omega t): F / |D|.
fn linear_qa(force: f64, zeta: f64, w: f64) -> f64 {
    force / ((1.0 - w * w).powi(2) + (2.0 * zeta * w).powi(2)).sqrt()
}

/// In contact (q_a < F_m) the response is linear: q_a = F_aT / |D| for eq. 4 alone and
/// (F_ah Omega^2 + F_aT) / |D| with both excitations in phase; q_m = 1 + F_m (eq. 13's form).
#[test]
fn linear_regime_matches_the_closed_form() {
    for (fah, fat) in [(0.0, 0.02), (0.01, 0.01)] {
        let w = 0.5;
        let v = geardyn_json(&[
            "simulate",
            "--fm",
            "0.1",
            "--fah",
            &fah.to_string(),
            "--fat",
            &fat.to_string(),
            "--zeta",
            "0.05",
            "--omega",
            "0.5",
            "--json",
        ]);
        let qa = linear_qa(fah * w * w + fat, 0.05, w);
        assert_eq!(v["impact"], "none");
        assert!((v["qa"].as_f64().unwrap() - qa).abs() < 1e-9, "{v}");
        assert!((v["qm"].as_f64().unwrap() - 1.1).abs() < 1e-9);
        assert_eq!(v["parameters"]["fat"].as_f64(), Some(fat));
    }
}

/// Eq. 4 at F_hat 2 (F_aT 0.05) across its resonance, with tooth separation: every stable
/// period-1 AFT solution (15 harmonics) on the grid is a simulated steady state, within 1e-4 in
/// q_a (the harmonics beyond 15 carry less), and every simulated period-1 state an AFT one.
#[test]
fn aft_and_simulation_agree_for_the_torque_excitation() {
    let (_dir, out) = tmp("c4");
    let v = geardyn_json(&[
        "compare",
        "--fm",
        "0.1",
        "--fah",
        "0",
        "--fat",
        "0.05",
        "--zeta",
        "0.05",
        "--omega",
        "0.6:1.0:0.1",
        "--ic-grid",
        "-2:2:3",
        "--json",
        "--out",
        &out,
    ]);
    let matched = v["gaps"]["matched"].as_array().unwrap();
    assert!(matched.len() >= 5, "{}", v["summary"]);
    for m in matched {
        assert!(m["rel"].as_f64().unwrap() < 1e-4, "{m}");
    }
    assert_eq!(v["gaps"]["sim_unmatched"].as_array().map(Vec::len), Some(0));
    assert_eq!(v["gaps"]["aft_unreached"].as_array().map(Vec::len), Some(0));
    // Tooth separation is reached (single-sided impact at Omega 0.8).
    assert!(
        matched
            .iter()
            .any(|m| m["case"] == "single" || m["case"] == 2),
        "{v}"
    );
}

/// The describing-function solution for eq. 4 loses case I exactly where F_aT / |D| reaches F_m
/// (the torque form of eq. 14: Omega 0.71069 and 1.21857 for F_aT 0.05, F_m 0.1, zeta 0.05).
#[test]
fn describing_function_case_one_ends_at_the_torque_transitions() {
    // x^2 - 2 (1 - 2 zeta^2) x + 1 - r^2 = 0 with r = 0.5.
    let b: f64 = 1.0 - 2.0 * 0.05 * 0.05;
    let s = (b * b - 0.75).sqrt();
    let (t1, t2) = ((b - s).sqrt(), (b + s).sqrt());
    assert!((t1 - 0.71069).abs() < 1e-5 && (t2 - 1.21857).abs() < 1e-5);
    let case_one_at = |w: f64| {
        let (_guard, dir) = tmp(&format!("h4-{w}"));
        let out = common::geardyn(&[
            "hbm",
            "--fm",
            "0.1",
            "--fah",
            "0",
            "--fat",
            "0.05",
            "--zeta",
            "0.05",
            "--omega",
            &w.to_string(),
            "--out",
            &dir,
        ]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let text = String::from_utf8_lossy(&out.stdout).to_string();
        text.lines()
            .skip(1)
            .any(|l| l.split(',').nth(3) == Some("1"))
    };
    assert!(case_one_at(t1 - 1e-4));
    assert!(!case_one_at(t1 + 1e-4));
    assert!(!case_one_at(t2 - 1e-4));
    assert!(case_one_at(t2 + 1e-4));
}

/// A fresh temporary folder (removed when the guard drops) and the path `name` inside it.
fn tmp(name: &str) -> (tempfile::TempDir, String) {
    let d = tempfile::tempdir().unwrap();
    let p = d.path().join(name).to_string_lossy().to_string();
    (d, p)
}
