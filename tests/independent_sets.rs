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

use geardyn::data::load_munro;
use geardyn::progress::NoProgress;
use geardyn::validate::{validate_munro, MunroOptions};
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
