//! `geardyn study NAME` (issue 3, item 4) at reduced resolution: the files are written and a
//! physically meaningful number of each study holds.

mod common;

use common::geardyn_json;
use serde_json::Value;
use std::path::Path;

fn study(name: &str, points: &str, out: &Path) -> Value {
    let o = out.to_string_lossy().to_string();
    geardyn_json(&["study", name, "--points", points, "--out", &o])
}

fn assert_files(dir: &Path, name: &str, figures: &[&str]) {
    let d = dir.join(name);
    for f in figures {
        for ext in ["png", "svg"] {
            assert!(d.join(format!("{f}.{ext}")).is_file(), "{f}.{ext}");
        }
    }
    for ext in ["csv", "json"] {
        assert!(d.join(format!("{name}.{ext}")).is_file(), "{name}.{ext}");
    }
}

fn f(v: &Value) -> f64 {
    v.as_f64().unwrap_or(f64::NAN)
}

/// Eq. 13, the contact-only amplitude.
fn eq13(fah: f64, zeta: f64, w: f64) -> f64 {
    w * w * fah / ((1.0 - w * w).powi(2) + (2.0 * zeta * w).powi(2)).sqrt()
}

/// Figs 15, 16. At F_hat 10 the response is single-valued and linear: every case I solution is
/// eq. 13 within 1e-9 (the df-exact solution in contact has N_a = 1 exactly, so only the root
/// finder's rounding remains). Eq. 13 peaks at F_ah / (2 zeta sqrt(1 - zeta^2)) = 1.00125 F_m, so
/// the teeth just separate (case II) between the eq. 14 transitions ~1.000 and ~1.005 and only
/// there, with q_a within 1e-4 of F_m. Lower F_hat has three solutions somewhere (the jump).
#[test]
fn parametric_load_fhat10_is_linear() {
    let dir = tempfile::tempdir().expect("temp dir");
    let v = study("parametric-load", "57", dir.path());
    assert_files(dir.path(), "parametric-load", &["fig15-qa", "fig16-qm"]);
    let curves = v["curves"].as_array().cloned().unwrap_or_default();
    assert_eq!(curves.len(), 4);
    let c10 = &curves[0];
    assert_eq!(f(&c10["force_ratio"]), 10.0);
    assert_eq!(c10["max_solutions_per_omega"].as_u64(), Some(1));
    assert!(f(&c10["case_i_max_abs_diff_from_eq13"]) < 1e-9);
    let csv = std::fs::read_to_string(dir.path().join("parametric-load/parametric-load.csv"))
        .unwrap_or_default();
    let (t1, t2) = (
        f(&c10["eq14_transitions"][0]),
        f(&c10["eq14_transitions"][1]),
    );
    let mut n = 0;
    for line in csv.lines().filter(|l| l.contains("F_hat = 10,")) {
        let cols: Vec<&str> = line.rsplitn(6, ',').collect();
        // rsplitn: period, stable, case, qm, qa, rest(study,series,omega)
        let qa: f64 = cols[4].parse().unwrap_or(f64::NAN);
        let omega: f64 = cols[5]
            .rsplit(',')
            .next()
            .and_then(|s| s.parse().ok())
            .unwrap_or(f64::NAN);
        match cols[2] {
            "1" => assert!((qa - eq13(0.01, 0.05, omega)).abs() < 1e-9, "{line}"),
            "2" => assert!(
                omega >= t1 - 1e-12 && omega <= t2 && (qa - 0.1).abs() < 1e-4,
                "{line}"
            ),
            _ => panic!("case III at F_hat 10: {line}"),
        }
        n += 1;
    }
    assert_eq!(n, 57);
    for c in &curves[1..] {
        assert_eq!(c["max_solutions_per_omega"].as_u64(), Some(3), "{c}");
    }
}

/// Fig. 17: the jump region exists for F_hat 4, 2, 1 and moves to lower Omega as F_m falls
/// (softening by earlier tooth separation), and F_hat 10 stays single-valued.
#[test]
fn parametric_mean_jump_moves_down_with_load() {
    let dir = tempfile::tempdir().expect("temp dir");
    let v = study("parametric-mean", "57", dir.path());
    assert_files(dir.path(), "parametric-mean", &["fig17-qa", "fig17-qm"]);
    let curves = v["curves"].as_array().cloned().unwrap_or_default();
    assert_eq!(curves[0]["max_solutions_per_omega"].as_u64(), Some(1));
    let starts: Vec<f64> = curves[1..]
        .iter()
        .map(|c| f(&c["multivalued_omega_range"][0]))
        .collect();
    assert!(starts[0] > starts[1] && starts[1] > starts[2], "{starts:?}");
}

/// Fig. 18: more damping narrows the multivalued (jump) region and lowers the peak.
#[test]
fn damping_narrows_the_jump() {
    let dir = tempfile::tempdir().expect("temp dir");
    let v = study("damping", "57", dir.path());
    assert_files(dir.path(), "damping", &["fig18-qa", "fig18-qm"]);
    let curves = v["curves"].as_array().cloned().unwrap_or_default();
    let peaks: Vec<f64> = curves.iter().map(|c| f(&c["peak"]["qa"])).collect();
    assert!(peaks.windows(2).all(|w| w[0] > w[1]), "{peaks:?}");
    let widths: Vec<f64> = curves
        .iter()
        .map(|c| f(&c["multivalued_omega_range"][1]) - f(&c["multivalued_omega_range"][0]))
        .collect();
    assert!(widths.windows(2).all(|w| w[0] > w[1]), "{widths:?}");
}

/// Figs 24, 25 (Sec. 8.1): eq. 5 always has a case I regime at low Omega, eq. 4 has none at
/// F_hat 0.5 (the paper's statement; the force amplitude F_aT > F_m separates the teeth at any
/// Omega); at F_hat 10 both are single-valued.
#[test]
fn excitation_internal_vs_external() {
    let dir = tempfile::tempdir().expect("temp dir");
    let v = study("excitation", "29", dir.path());
    assert_files(dir.path(), "excitation", &["fig24-25-qa", "fig24-25-qm"]);
    let fr = v["force_ratios"].as_array().cloned().unwrap_or_default();
    assert_eq!(fr.len(), 4);
    for c in &fr {
        assert_eq!(c["internal_eq5"]["case_i_at_lowest_omega"], true, "{c}");
    }
    assert_eq!(fr[3]["external_eq4"]["case_i_at_lowest_omega"], false);
    for k in ["internal_eq5", "external_eq4"] {
        assert_eq!(fr[0][k]["max_coexisting_stable"].as_u64(), Some(1));
    }
}

/// Figs 26, 27: the superposition with phases follows the simultaneous response; RMS difference
/// below 0.01 over the sweep (the peak q_a is ~0.2, so 5%; the paper calls the agreement
/// satisfactory), and near Omega 1/2 and 1/3 the superposition is closer than the harmonic alone.
#[test]
fn superposition_tracks_simultaneous() {
    let dir = tempfile::tempdir().expect("temp dir");
    let v = study("superposition", "29", dir.path());
    assert_files(dir.path(), "superposition", &["fig26-27-superposition"]);
    assert!(f(&v["rms_superposition_minus_simultaneous"]) < 0.01, "{v}");
    for k in ["omega_1_2", "omega_1_3"] {
        let w = &v["near_resonance"][k];
        assert!(
            f(&w["rms_superposition_minus_simultaneous"])
                < f(&w["rms_harmonic_alone_minus_simultaneous"]),
            "{w}"
        );
    }
}

/// Fig. 28: away from the jumps the superposition of the three single-harmonic df-exact solutions
/// (with phases) is within RMS 0.005 of the simultaneous AFT response (q_a up to ~0.35; 0.0012 at
/// 281 points), and the superposition is multi-valued around the first harmonic's jump, which
/// the paper places between Omega 0.7 and 0.8 for F_hat 2 (Fig. 15b).
#[test]
fn superposition_hb_tracks_simultaneous_aft() {
    let dir = tempfile::tempdir().expect("temp dir");
    let v = study("superposition-hb", "57", dir.path());
    assert_files(dir.path(), "superposition-hb", &["fig28-superposition-hb"]);
    assert!(
        v["single_valued_points_compared"].as_u64().unwrap_or(0) >= 40,
        "{v}"
    );
    assert!(
        f(&v["rms_superposition_minus_simultaneous_single_valued"]) < 0.005,
        "{v}"
    );
    let mv = &v["superposition_multivalued_omega"];
    assert!(f(&mv[0]) <= 0.75 && f(&mv[1]) >= 0.78, "{v}");
}

/// Fig. 29: where every response is single-valued, the superposition of the torque-alone and
/// STE-alone AFT responses is within RMS 0.02 of the simultaneous one (q_a up to ~0.3 there).
#[test]
fn combined_superposition_where_single_valued() {
    let dir = tempfile::tempdir().expect("temp dir");
    let v = study("combined", "29", dir.path());
    assert_files(dir.path(), "combined", &["fig29-combined"]);
    assert!(v["single_valued_points"].as_u64().unwrap_or(0) >= 15, "{v}");
    assert!(
        f(&v["rms_superposition_minus_simultaneous_single_valued"]) < 0.02,
        "{v}"
    );
}
