//! Seeded subsets of the `discover-study` rates of docs/discover-studies.md, on sets geardyn's
//! fit did not make: made by DOP853 (rtol 1e-9, not the fit's solver), with level-dependent and
//! heavy-tailed noise, effects at random phases. Too slow for the default test run (a refit
//! takes 20-40 s on 2 cores); `.ci/run` runs them:
//!
//!     cargo test --release --test discover_studies -- --ignored
//!
//! The seeds are fixed, so each test is a deterministic regression check; its threshold is
//! what the study's rate implies for that many seeds, not what these seeds happen to give.

mod common;

use common::geardyn;
use serde_json::Value;

/// The per-seed outcomes of `discover-study` with `args`, on DOP853-made sets with 199
/// bootstrap replicates.
fn outcomes(args: &[&str]) -> Vec<Value> {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("summary.json");
    let mut all = vec![
        "discover-study",
        "--dop853-rtol",
        "1e-9",
        "--bootstrap",
        "199",
    ];
    all.extend_from_slice(args);
    all.extend_from_slice(&["--out", out.to_str().unwrap()]);
    let o = geardyn(&all);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let s: Value = serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    s["outcomes"].as_array().unwrap().clone()
}

fn count(o: &[Value], key: &str) -> usize {
    o.iter().filter(|x| x[key] == true).count()
}

/// Null sets, two seeds of each noise family (constant, level-dependent, heavy-tailed, read to
/// a grid, correlated along speed): at most one answer other than `none` over the 10. At the
/// nominal 5% the chance of two or more is 9%.
#[test]
#[ignore = "slow study: cargo test --release --test discover_studies -- --ignored"]
fn null_sets_of_every_noise_family_answer_none() {
    let mut wrong = Vec::new();
    for noise in [
        "constant",
        "relative",
        "student-t",
        "quantized",
        "correlated",
    ] {
        let o = outcomes(&["--hidden", "none", "--seeds", "2", "--noise", noise]);
        assert_eq!(o.len(), 2);
        wrong.extend(
            o.iter()
                .filter(|x| x["effect"] != "none")
                .map(|x| format!("{noise} seed {}: {}", x["seed"], x["effect"])),
        );
    }
    assert!(wrong.len() <= 1, "{wrong:?}");
}

/// A hidden effect at a random phase with level-dependent noise on a 100 rpm grid, three seeds:
/// named in at least two and the truth inside the 95% interval in at least two. With the
/// required 90% recovery and nominal coverage, two or more of three has probability 97%.
/// Only for the effects whose measured rates meet the requirement (a torque ripple of 3% does
/// not: see docs/discover-studies.md).
fn recovered(hidden: &str, noise: &str, coverage: bool) {
    let o = outcomes(&[
        "--hidden",
        hidden,
        "--seeds",
        "3",
        "--noise",
        noise,
        "--speed-step",
        "100",
        "--random-phase",
    ]);
    assert_eq!(o.len(), 3);
    let summary: Vec<String> = o
        .iter()
        .map(|x| {
            format!(
                "seed {}: {} {} {}",
                x["seed"], x["effect"], x["estimate"], x["ci95"]
            )
        })
        .collect();
    assert!(count(&o, "correct") >= 2, "{summary:?}");
    if coverage {
        assert!(count(&o, "covered") >= 2, "{summary:?}");
    }
}

#[test]
#[ignore = "slow study: cargo test --release --test discover_studies -- --ignored"]
/// Named only: the stiffness variation's profile interval undercovers (seeds 1-3: 1 of the 2
/// named covered, 0.190 [0.179, 0.199] against 0.2), as the previous procedure's Wald
/// intervals did (their standard errors 15% small); open in docs/discover-studies.md.
fn stiffness_variation_at_random_phases_is_named() {
    recovered("mesh_stiffness_variation", "relative", false);
}

#[test]
#[ignore = "slow study: cargo test --release --test discover_studies -- --ignored"]
fn second_ste_harmonic_at_random_phases_is_named_and_covered() {
    recovered("ste_harmonics", "relative", true);
}
