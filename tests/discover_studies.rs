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

/// The per-seed outcomes of `discover-study` with `args`, on DOP853-made sets with 999
/// bootstrap replicates.
fn outcomes(args: &[&str]) -> Vec<Value> {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("summary.json");
    let mut all = vec![
        "discover-study",
        "--dop853-rtol",
        "1e-9",
        "--bootstrap",
        "999",
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

/// Null sets, four seeds of each noise family (constant, level-dependent, heavy-tailed, read
/// to a grid): at most one answer other than `none` over the 16. At the nominal 5% the
/// chance of two or more is 19%; at the measured 2.5% (5/200 over the four families), 6%.
#[test]
#[ignore = "slow study: cargo test --release --test discover_studies -- --ignored"]
fn null_sets_of_every_noise_family_answer_none() {
    let mut wrong = Vec::new();
    for noise in ["constant", "relative", "student-t", "quantized"] {
        let o = outcomes(&["--hidden", "none", "--seeds", "4", "--noise", noise]);
        assert_eq!(o.len(), 4);
        wrong.extend(
            o.iter()
                .filter(|x| x["effect"] != "none")
                .map(|x| format!("{noise} seed {}: {}", x["seed"], x["effect"])),
        );
    }
    assert!(wrong.len() <= 1, "{wrong:?}");
}

/// A hidden effect at a random phase with level-dependent noise on a 100 rpm grid, four seeds:
/// named in at least three and the truth inside the 95% interval in at least three. With the
/// required 90% recovery and nominal coverage, three or more of four has probability 95%.
/// Only for the effects whose measured rates meet the requirement (a torque ripple of 3% does
/// not: see docs/discover-studies.md).
fn recovered(hidden: &str, noise: &str) {
    let o = outcomes(&[
        "--hidden",
        hidden,
        "--seeds",
        "4",
        "--noise",
        noise,
        "--speed-step",
        "100",
        "--random-phase",
    ]);
    assert_eq!(o.len(), 4);
    let summary: Vec<String> = o
        .iter()
        .map(|x| {
            format!(
                "seed {}: {} {} {}",
                x["seed"], x["effect"], x["estimate"], x["ci95"]
            )
        })
        .collect();
    assert!(count(&o, "correct") >= 3, "{summary:?}");
    assert!(count(&o, "covered") >= 3, "{summary:?}");
}

#[test]
#[ignore = "slow study: cargo test --release --test discover_studies -- --ignored"]
fn stiffness_variation_at_random_phases_is_named_and_covered() {
    recovered("mesh_stiffness_variation", "relative");
}

#[test]
#[ignore = "slow study: cargo test --release --test discover_studies -- --ignored"]
fn second_ste_harmonic_at_random_phases_is_named_and_covered() {
    recovered("ste_harmonics", "relative");
}

/// A second STE harmonic of 40% (phase 0) on Munro's 50 rpm grid with constant noise, the set
/// `geardyn bench --discover-refit` times: named, 0.4 inside its interval. With the probes'
/// gains computed on clipped residuals its dictionary LR was 0 and the answer "unexplained".
#[test]
#[ignore = "slow study: cargo test --release --test discover_studies -- --ignored"]
fn strong_second_ste_harmonic_on_munros_grid_is_named() {
    let tmp = tempfile::tempdir().unwrap();
    let set = tmp.path().join("set");
    let out = tmp.path().join("out");
    let s = set.to_str().unwrap();
    let o = geardyn(&[
        "synth",
        "munro",
        "--ste2-ratio",
        "0.4",
        "--seed",
        "1",
        "--out",
        s,
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let o = geardyn(&["discover", "--data", s, "--out", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let d: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("discovery.json")).unwrap())
            .unwrap();
    assert_eq!(d["effect"], "ste_harmonics", "{}", d["candidates"]);
    let c = d["candidates"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c["name"] == "ste_harmonics")
        .unwrap();
    let (lo, hi) = (
        c["ci95"][0].as_f64().unwrap(),
        c["ci95"][1].as_f64().unwrap(),
    );
    assert!(lo <= 0.4 && 0.4 <= hi, "[{lo}, {hi}]");
}
