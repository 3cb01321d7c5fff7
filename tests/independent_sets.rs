//! `validate munro` on sets geardyn did not make: four blind sets written by
//! `tools/indep-synth` (its own model code from the paper, Dopri5 of the `ode_solvers` crate, its
//! own noise draws), one per noise family (constant, relative, Student-t, read to a 0.25 um grid),
//! with zeta and omega_n drawn away from the defaults. Their truth is in
//! `tests/data/independent/truth.toml`, outside the set folders.
//!
//! The sets are the first of each family of a 60-set batch (not chosen by the outcome); over
//! that batch and 40 sets on a non-uniform grid the covariance intervals covered zeta on 98/100
//! and omega_n on 94/100 (docs/independent-sets.md). Each interval misses with probability 0.05,
//! so asserting all four would fail by chance one time in five; the test asks for three of four
//! per parameter and a standardized error under 3 everywhere (two-sided probability 0.0027), which
//! the standard errors three times too small that issue "Calibrated inference" found on such sets
//! fail at once.

use geardyn::data::{load_kubo, load_munro};
use geardyn::progress::NoProgress;
use geardyn::validate::{validate_kubo, validate_munro, KuboFitPath, KuboOptions, MunroOptions};
use std::path::Path;

#[derive(serde::Deserialize)]
struct Truth {
    noise_family: String,
    zeta: f64,
    omega_n_hz: f64,
}

#[test]
fn validate_munro_covers_the_truth_of_independent_sets() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/independent");
    let text = std::fs::read_to_string(root.join("truth.toml")).expect("truth.toml");
    let truths: std::collections::BTreeMap<String, Truth> =
        toml::from_str(&text).expect("truth.toml parses");
    assert_eq!(truths.len(), 4);
    let mut covered = [0usize; 2];
    for (key, truth) in &truths {
        let set = root.join(key.replace('_', "-"));
        let data = load_munro(&set).expect("set loads");
        let opts = MunroOptions {
            attractor_speeds: 3,
            ..MunroOptions::default()
        };
        let r = validate_munro(&data, &opts, &NoProgress).expect("fit");
        let e = &r.fit.estimate;
        for (k, t) in [truth.zeta, truth.omega_n_hz].into_iter().enumerate() {
            let (lo, hi) = e.ci95[k];
            let z = (e.params[k] - t) / e.std_errors[k];
            assert!(
                z.abs() < 3.0,
                "{key} ({}): {} = {} [{lo}, {hi}], truth {t}, z {z:.2}",
                truth.noise_family,
                e.names[k],
                e.params[k]
            );
            if lo <= t && t <= hi {
                covered[k] += 1;
            }
        }
    }
    assert!(
        covered.iter().all(|&c| c >= 3),
        "covered zeta {}/4, omega_n {}/4",
        covered[0],
        covered[1]
    );
}

#[derive(serde::Deserialize)]
struct KuboTruth {
    noise_family: String,
    tooth_pairs: usize,
    zeta: f64,
    omega_n_hz: f64,
}

/// `validate kubo --fit whole` on two envelopes of `tools/indep-synth`'s batch 515, where each
/// tooth pair has its own STE amplitude and jumps down at its own speed: the envelope's
/// midline over the jump is the mean of a pair still on the resonance branch and one already
/// down. Fitted with one pair's D_L, zeta came out +16% (z +5.8) and +14% (z +3.3), their
/// intervals missing the truth; over the batch's 118 fitted sets the intervals covered 84%
/// (docs/validation.md). The fit now models the midline as the mean of two pairs (STE
/// (1 +- h)); the truth must be inside the 95% covariance and profile intervals and within 3
/// standard errors, on each set. Each profile end must lie at least one standard error from
/// the estimate: the sum of squares steps where a pair's jump crosses a measured speed, and
/// profile points whose inner fits started on the wrong side of such a step put zeta's lower
/// end at the estimate on set-008 and 0.05 standard errors below it on set-058 (above the
/// truth), before `fit::profile` started its inner fits from the nearest point inside and,
/// where a point came out surprisingly high, from the likelihood's ridge.
#[test]
#[ignore = "about 40 s: .ci/run runs it (cargo test --release --test independent_sets -- --ignored)"]
fn validate_kubo_whole_curve_follows_pairs_that_jump_apart() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/independent-kubo");
    let text = std::fs::read_to_string(root.join("truth.toml")).expect("truth.toml");
    let truths: std::collections::BTreeMap<String, KuboTruth> =
        toml::from_str(&text).expect("truth.toml parses");
    assert_eq!(truths.len(), 2);
    for (key, truth) in &truths {
        let data = load_kubo(&root.join(key.replace('_', "-"))).expect("set loads");
        let opts = KuboOptions {
            fit_path: KuboFitPath::WholeCurve,
            ..KuboOptions::default()
        };
        let r = validate_kubo(&data, &opts, &NoProgress).expect("fit");
        let e = r.fit.as_ref().expect("fitted");
        for (k, t) in [truth.zeta, truth.omega_n_hz].into_iter().enumerate() {
            let (lo, hi) = e.ci95[k];
            let z = (e.params[k] - t) / e.std_errors[k];
            let what = format!(
                "{key} ({} pairs, {}): {} = {} [{lo}, {hi}], truth {t}, z {z:.2}",
                truth.tooth_pairs, truth.noise_family, e.names[k], e.params[k]
            );
            assert!(z.abs() < 3.0, "{what}");
            assert!(lo <= t && t <= hi, "{what}");
            let (Some(plo), Some(phi)) = r.ci95_profile[k].ends() else {
                panic!("{what}: profile {:?}", r.ci95_profile[k]);
            };
            let profile = format!("{what}, profile [{plo}, {phi}]");
            assert!(plo <= t && t <= phi, "{profile}");
            assert!(e.params[k] - plo > e.std_errors[k], "{profile}");
            assert!(phi - e.params[k] > e.std_errors[k], "{profile}");
        }
    }
}
