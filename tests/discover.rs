//! Discrepancy discovery on seeded synthetic sets: the null case gives "none" and never reads the
//! truth, also on sets made by another integrator with level-dependent, heavy-tailed, quantized
//! and correlated noise on a non-uniform grid; a stated noise (column, rig.toml, option) is used
//! as stated; a second STE harmonic is named with its true size inside the 95% interval, on a
//! set of geardyn's and on one made by an independent code; backlash is reported not
//! identifiable without back-side contact; bad input fails cleanly. Sets use a 100 rpm grid
//! (41 speeds per load) to keep the suite short. The recovery of the other effects runs as
//! `discover-study`, and the rates over many seeds are in docs/discover-studies.md.

mod common;
use common::geardyn;
use geardyn::data::load_munro;
use geardyn::discover::{discover, Candidate, DiscoverOptions, Discovery, Effect, NoiseOrigin};
use geardyn::fit::Distribution;
use geardyn::progress::NoProgress;
use geardyn::validate::{synth_munro, HiddenEffects, MunroTruth, NoiseFamily, SpeedGrid};
use std::path::Path;

fn make_set(dir: &Path, hidden: HiddenEffects, seed: u64) {
    make_set_at(dir, hidden, seed, MunroTruth::default_munro().ste_um);
}

/// A set at the given (load N, STE um) pairs on the 100 rpm grid.
fn make_set_at(dir: &Path, hidden: HiddenEffects, seed: u64, loads: Vec<(f64, f64)>) {
    make_set_on(dir, hidden, seed, loads, 100.0);
}

/// A set at the given (load N, STE um) pairs, speeds 1000-5000 rpm in steps of `step_rpm`.
fn make_set_on(
    dir: &Path,
    hidden: HiddenEffects,
    seed: u64,
    loads: Vec<(f64, f64)>,
    step_rpm: f64,
) {
    let mut t = MunroTruth::default_munro();
    t.ste_um = loads;
    t.seed = seed;
    t.speeds_rpm = (1000.0, 5000.0, step_rpm);
    t.hidden = hidden;
    synth_munro(&t, dir, &NoProgress).unwrap();
}

/// `discover` on a fresh set at the given loads with `hidden` inside.
fn discover_hidden(hidden: HiddenEffects, seed: u64, loads: Vec<(f64, f64)>) -> Discovery {
    let tmp = tempfile::tempdir().unwrap();
    make_set_at(tmp.path(), hidden, seed, loads);
    run(tmp.path())
}

/// The replicates of the suite's runs: the least for which a p-value of 1 / (B + 1) can pass
/// Holm's correction over five candidates at 5% is 100.
const BOOTSTRAP: usize = 199;

fn run(dir: &Path) -> Discovery {
    run_with(
        dir,
        &DiscoverOptions {
            bootstrap: BOOTSTRAP,
            ..DiscoverOptions::default()
        },
    )
}

fn run_with(dir: &Path, opts: &DiscoverOptions) -> Discovery {
    let data = load_munro(dir).unwrap();
    discover(&data, opts, &NoProgress).unwrap()
}

/// The effect is named `name` and its true value lies inside the reported 95% interval.
fn assert_named_with_truth_inside(d: &Discovery, name: &str, truth: f64) {
    assert_eq!(d.effect, name, "{:#?}", d.candidates);
    let c = d.candidates.iter().find(|c| c.name == d.effect).unwrap();
    let (lo, hi) = c.ci95.unwrap();
    assert!(
        lo <= truth && truth <= hi,
        "{name} {:?} [{lo}, {hi}]",
        c.estimate
    );
    // The named effect's interval is its profile-likelihood interval, which brackets the
    // estimate: each side is a fit whose -2 log L rose by the t quantile's square.
    assert_eq!(c.ci95_method, "profile likelihood");
    let (pl, ph) = c.profile_ci95.unwrap();
    let (pl, ph) = (pl.unwrap(), ph.unwrap());
    let est = c.estimate.unwrap();
    assert!(pl < est && est < ph, "profile [{pl}, {ph}] about {est}");
    assert_eq!((lo, hi), (pl, ph));
    // Its likelihood ratio passed Holm's correction, and it predicts the held-out loads.
    assert!(c.p_holm.unwrap() < 0.05, "{c:?}");
    assert!(d
        .prediction_check
        .as_ref()
        .is_none_or(|p| p.candidate_predicts()));
}

/// Held-out RMS gap (um) before and after adding the effect.
fn held_out_rms(d: &Discovery) -> (f64, f64) {
    (
        d.gap_before.held_out.as_ref().unwrap().rms_um,
        d.gap_after.held_out.as_ref().unwrap().rms_um,
    )
}

fn read_json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// M0 plus noise: "none"; the same answer and numbers with [source.truth] replaced by a false
/// truth in rig.toml (so the workflow cannot have used it); backlash not identifiable because the
/// training loads never reach the back flank; the outputs state the data kind first.
#[test]
fn null_set_gives_none_without_reading_the_truth() {
    let tmp = tempfile::tempdir().unwrap();
    let (a, b) = (tmp.path().join("a"), tmp.path().join("b"));
    make_set(&a, HiddenEffects::default(), 11);
    std::fs::create_dir_all(&b).unwrap();
    std::fs::copy(a.join("dte.csv"), b.join("dte.csv")).unwrap();
    let rig = std::fs::read_to_string(a.join("rig.toml")).unwrap();
    let cut = rig
        .find("[source.truth]")
        .expect("the set records its truth");
    // The loader insists that synthetic data carry a truth table: replace it by a false one.
    let false_truth = "[source.truth]\nzeta = 0.3\nomega_n_hz = 900.0\nnoise_um = 2.0\n\n\
                       [source.truth.hidden_effects]\nstiffness_eps = 0.3\nste2_ratio = 0.5\n";
    std::fs::write(b.join("rig.toml"), format!("{}{false_truth}", &rig[..cut])).unwrap();
    let mut outs = Vec::new();
    for (data, name) in [(&a, "out_a"), (&b, "out_b")] {
        let out = tmp.path().join(name);
        let o = geardyn(&[
            "discover",
            "--data",
            data.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--bootstrap",
            "199",
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let stdout = String::from_utf8_lossy(&o.stdout).to_string();
        assert!(stdout.starts_with("SYNTHETIC DATA"), "{stdout}");
        let text = std::fs::read_to_string(out.join("discovery.json")).unwrap();
        assert!(
            text.lines().nth(1).unwrap().contains("SYNTHETIC DATA"),
            "{text}"
        );
        let md = std::fs::read_to_string(out.join("report.md")).unwrap();
        assert!(md.starts_with("**SYNTHETIC DATA"));
        for f in ["residuals_before", "residuals_after"] {
            for ext in ["png", "svg"] {
                assert!(out.join(format!("{f}.{ext}")).metadata().unwrap().len() > 1000);
            }
        }
        outs.push(read_json(&out.join("discovery.json")));
    }
    let j = &outs[0];
    assert_eq!(j["effect"], "none", "{j:#}");
    for c in j["candidates"].as_array().unwrap() {
        assert!(c["name"].is_string() && c.get("estimate").is_some() && c.get("ci95").is_some());
        assert!(c.get("p_value").is_some());
    }
    let backlash = j["candidates"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c["name"] == "backlash")
        .unwrap();
    assert_eq!(backlash["identifiable"], false);
    assert!(backlash["note"]
        .as_str()
        .unwrap()
        .contains("not identifiable"));
    // The excluded points (M0 chaotic at 945 N) agree with M0's range: no warning.
    for e in j["excluded_by_load"].as_array().unwrap() {
        assert_eq!(e["outside_model_range"], 0, "{e}");
    }
    // M0 fits with physical damping (true zeta 0.0175), not at the lower bound.
    assert_eq!(j["m0"]["zeta_at_lower_bound"], false, "{}", j["m0"]);
    // M0 residuals at the noise level (0.15 um) on both sets of loads.
    let rms = j["gap_before"]["held_out"]["rms_um"].as_f64().unwrap();
    assert!(rms < 0.2, "held-out RMS {rms}");
    // Without the truth table: the same decision and statistics.
    let strip = |v: &serde_json::Value| {
        let mut v = v.clone();
        v["provenance"]["data_dir"] = serde_json::Value::Null;
        v
    };
    assert_eq!(strip(&outs[0]), strip(&outs[1]));
}

/// A measured chaotic pp is one observation window of the attractor, and data the fitting
/// solver did not make draw other windows than its prediction. On the shipped `data/munro`
/// (made by an older solver build) the excluded 945 N points lie inside the pp M0 produces
/// over its prediction's and 32 later windows (with the margin of 3 sigma + 10%): "none" and
/// no warning. (Whether the later windows reach past the prediction's own depends on where on
/// the chaotic orbit M0's fit to the last digit puts it: not asserted.)
#[test]
fn chaotic_points_from_another_solver_stay_inside_m0s_window_range() {
    let shipped = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/munro");
    let d = run(&shipped);
    assert_eq!(
        d.effect,
        "none",
        "{}",
        geardyn::report::discovery_summary(&d)
    );
    assert_eq!(d.excluded_far_outside(), 0, "{:?}", d.excluded_by_load);
    let e = d
        .excluded_by_load
        .iter()
        .find(|e| e.load_n == 945.0)
        .unwrap();
    assert_eq!(e.outside_model_range, 0, "{e:?}");
}

/// A second STE harmonic at 40% of the first: named, ratio inside its profile interval,
/// training gap down to the noise level; the held-out gap shrinks.
#[test]
#[ignore = "about a minute, too slow for the default run: .ci/run runs it (cargo test --release --test discover -- --ignored)"]
fn hidden_second_ste_harmonic_is_named_and_sized() {
    let h = HiddenEffects {
        ste2_ratio: 0.4,
        ..HiddenEffects::default()
    };
    let d = discover_hidden(h, 3, MunroTruth::default_munro().ste_um);
    assert_named_with_truth_inside(&d, "ste_harmonics", 0.4);
    assert!(d.gap_after.training.rms_um < 0.25, "{:?}", d.gap_after);
    let (before, after) = held_out_rms(&d);
    assert!(after < 0.5 * before, "held-out RMS {before} -> {after}");
}

/// The set of tests/data/independent-discover (made by tools/indep-synth, not geardyn: Dopri5
/// with event location; 64 speeds per load over Omega 0.4-1.45, f_n 2120 Hz, zeta 0.019,
/// relative 3% + 0.05 um) hides a 2nd STE harmonic of ratio 0.4 at phase 0. The previous
/// procedure stopped on it with an internal error; M0 misfits it so badly that its noise comes
/// out heavy-tailed and correlated along speed, and still the harmonic is named, its ratio
/// within 10% of the truth, and the held-out loads predicted far better. Its interval is not
/// asserted: the best fit lies half a turn from the generator's phase (-166 deg, the contact
/// twin, a likelihood ratio 57 above the fit at 4 deg), and there the profile's upper side does
/// not leave the estimate (0.373 [0.364, 0.373]; Wald [0.349, 0.399]): open, in
/// docs/independent-sets.md.
#[test]
#[ignore = "about two minutes, too slow for the default run: .ci/run runs it (cargo test --release --test discover -- --ignored)"]
fn the_independent_second_harmonic_set_is_named() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/independent-discover/ste2-m0-overdamped");
    let d = run(&dir);
    assert_eq!(
        d.effect,
        "ste_harmonics",
        "{}",
        geardyn::report::discovery_summary(&d)
    );
    let r2 = d.named().and_then(|c| c.estimate).unwrap();
    assert!((r2 / 0.4 - 1.0).abs() < 0.1, "r2 {r2}");
    let (before, after) = held_out_rms(&d);
    assert!(after < 0.5 * before, "held-out RMS {before} -> {after}");
}

/// A null set whose every STE is stated (0.05 um, drawn about the truth): "none", and each
/// load's statement is reported against M0's fit of it, the two training loads' from M0's fit
/// and the two held-out loads' from their own STE fits, all compatible with the curves.
#[test]
#[ignore = "about 30 s, too slow for the default run: .ci/run runs it (cargo test --release --test discover -- --ignored)"]
fn every_stated_ste_is_weighed_and_reported_training_and_held_out() {
    let tmp = tempfile::tempdir().unwrap();
    let mut t = MunroTruth::default_munro();
    t.seed = 5;
    t.speeds_rpm = (1000.0, 5000.0, 100.0);
    t.publish_ste = true;
    t.ste_sd_um = Some(0.05);
    synth_munro(&t, tmp.path(), &NoProgress).unwrap();
    let d = run(tmp.path());
    let summary = geardyn::report::discovery_summary(&d);
    assert_eq!(d.effect, "none", "{summary}");
    let mut loads: Vec<f64> = d.stated_ste.iter().map(|s| s.0).collect();
    loads.sort_by(f64::total_cmp);
    assert_eq!(loads, vec![945.0, 1890.0, 2835.0, 3780.0], "{summary}");
    for (load, m) in &d.stated_ste {
        assert_eq!(m.measurement.sd, 0.05);
        let z = m.compatibility_z.unwrap_or(m.z);
        assert!(z.abs() < 3.0, "{load} N: z {z}: {summary}");
    }
    let text = geardyn::report::discovery_stated_ste_text(&d).unwrap();
    for load in ["945 N", "1890 N", "2835 N", "3780 N"] {
        assert!(text.contains(load), "{text}");
    }
}

/// An effect outside the library, from the independent generator: a contact force
/// c (q - 1)^1.2 (the mesh stiffening with load, tests/data/independent-discover/truth.toml).
/// No candidate passes; M0's residuals are one smooth curve (its noise model takes the misfit
/// as a correlation longer than the curves), so the answer is "unexplained" with that reason,
/// never a name, and the candidate of the largest likelihood ratio is refitted to show the gap
/// it leaves.
#[test]
#[ignore = "about 20 s, too slow for the default run: .ci/run runs it (cargo test --release --test discover -- --ignored)"]
fn an_effect_outside_the_library_is_unexplained() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/independent-discover/contact-law-1.2");
    let d = run(&dir);
    let summary = geardyn::report::discovery_summary(&d);
    assert_eq!(d.effect, "unexplained", "{summary}");
    assert!(
        d.misfit
            .as_deref()
            .is_some_and(|m| m.contains("one smooth curve")),
        "{summary}"
    );
    assert!(d.closest_candidate.is_some(), "{summary}");
    assert!(
        d.gap_after_model.starts_with("M0 + "),
        "{}",
        d.gap_after_model
    );
    // Each candidate holds M0 (its effect at zero) and is fitted from M0's optimum at M0's
    // weights, so it reaches M0's likelihood: its ratio is not below zero by more than the two
    // models' restricted noise estimates can differ (about 0.5 here). Started from equal
    // weights, three candidates ended 26-80 below it in a basin of their own.
    for c in d.candidates.iter().filter(|c| c.identifiable) {
        assert!(c.lr > -2.0, "{} LR {}: {summary}", c.name, c.lr);
    }
}

/// A model-exact set whose errors drift along speed (0.15 um + 3%, AR(1) along speed with
/// correlation 0.6 between neighbouring speeds, made by DOP853; study seed 3): "none". The
/// previous procedure, whose noise came from second differences and whose tests assumed
/// independent errors, answered "unexplained" on 20 of 20 such sets. The noise model finds the
/// correlation (a length of the order of the grid's step / ln(1/0.6) = 98 rpm).
#[test]
fn a_null_set_with_errors_correlated_along_speed_gives_none() {
    let tmp = tempfile::tempdir().unwrap();
    let mut t = MunroTruth::default_munro();
    t.seed = 3;
    t.noise = NoiseFamily::Correlated.noise(0.15);
    t.dop853_rtol = Some(1e-9);
    synth_munro(&t, tmp.path(), &NoProgress).unwrap();
    let d = run(tmp.path());
    assert_eq!(
        d.effect,
        "none",
        "{}",
        geardyn::report::discovery_summary(&d)
    );
    let length = d.noise.model.correlation_length;
    assert!(length > 30.0 && length < 400.0, "length {length} rpm");
}

/// Bad input: one clear error, non-zero exit, no output folder.
#[test]
fn bad_input_fails_without_output() {
    let tmp = tempfile::tempdir().unwrap();
    let data = tmp.path().join("bad");
    make_set(&data, HiddenEffects::default(), 1);
    let csv = std::fs::read_to_string(data.join("dte.csv")).unwrap();
    std::fs::write(
        data.join("dte.csv"),
        csv.replacen("\n3780,1100,", "\n3780,1100,NaN", 1),
    )
    .unwrap();
    let out = tmp.path().join("out");
    let o = geardyn(&[
        "discover",
        "--data",
        data.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("dte.csv"), "{err}");
    assert!(!out.exists());
    // Too few bootstrap replicates to ever reach significance after Holm: refused up front.
    let good = tmp.path().join("good");
    make_set(&good, HiddenEffects::default(), 1);
    let o = geardyn(&[
        "discover",
        "--data",
        good.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--bootstrap",
        "99",
    ]);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("bootstrap"));
    assert!(!out.exists());
}

/// `discover-study` as a user runs it, on two null seeds: the summary's counts, intervals and
/// per-test calibration agree with its own per-seed outcomes, which were also written one line
/// per seed as they finished, the scratch sets are removed, and a study that cannot run fails
/// with one message and no summary.
#[test]
#[ignore = "a two-seed study, too slow for the default run: .ci/run runs it (cargo test --release --test discover -- --ignored)"]
fn null_study_summarises_rates_and_per_test_calibration() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("study").join("summary.json");
    let args = [
        "discover-study",
        "--hidden",
        "none",
        "--seeds",
        "2",
        "--speed-step",
        "100",
        "--bootstrap",
        "199",
        "--out",
        out.to_str().unwrap(),
    ];
    let o = geardyn(&args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let stdout = String::from_utf8_lossy(&o.stdout).to_string();
    assert!(stdout.starts_with("SYNTHETIC DATA"), "{stdout}");
    assert!(stdout.contains("one-sided 95% upper bound"), "{stdout}");
    let s = read_json(&out);
    let outcomes = s["outcomes"].as_array().unwrap();
    assert_eq!(outcomes.len(), 2);
    let nones = outcomes.iter().filter(|o| o["effect"] == "none").count();
    assert_eq!(s["correct"].as_u64().unwrap() as usize, nones);
    let fp = 2 - nones;
    let warned = outcomes
        .iter()
        .filter(|o| o["excluded_far_outside"].as_u64().unwrap() > 0)
        .count();
    assert_eq!(s["warned"].as_u64().unwrap() as usize, warned);
    // Clopper-Pearson one-sided upper bounds for n = 2 in closed form.
    let upper = [1.0 - 0.05f64.sqrt(), 0.95f64.sqrt(), 1.0][fp];
    assert!((s["false_positive_upper95"].as_f64().unwrap() - upper).abs() < 1e-9);
    // M0's goodness of fit and every tested candidate have a p-value per seed (the backlash,
    // which the training loads cannot see without back-side contact, none), and the
    // calibration counts them.
    let cal = s["calibration"].as_array().unwrap();
    let names: Vec<&str> = cal.iter().map(|c| c["name"].as_str().unwrap()).collect();
    for n in [
        "m0_goodness_of_fit",
        "candidate_mesh_stiffness_variation",
        "candidate_ste_harmonics",
        "candidate_torque_ripple",
    ] {
        assert!(names.contains(&n), "{names:?}");
    }
    assert!(!names.contains(&"candidate_backlash"));
    for c in cal {
        let name = c["name"].as_str().unwrap();
        let p: Vec<f64> = outcomes
            .iter()
            .flat_map(|o| o["p_values"].as_array().unwrap())
            .filter(|x| x[0] == name)
            .map(|x| x[1].as_f64().unwrap())
            .collect();
        assert_eq!(c["seeds"].as_u64().unwrap() as usize, p.len(), "{name}");
        assert!(p.iter().all(|p| *p > 0.0 && *p <= 1.0), "{name}: {p:?}");
        let below = p.iter().filter(|p| **p < 0.05).count();
        assert_eq!(c["below_5pct"][0].as_u64().unwrap() as usize, below);
    }
    // Each seed's outcome was also written as it finished, one JSON line each, the same as
    // the summary's.
    let lines = std::fs::read_to_string(out.with_extension("seeds.jsonl")).unwrap();
    let per_seed: Vec<serde_json::Value> = lines
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(&per_seed, outcomes);
    let mut left: Vec<_> = std::fs::read_dir(out.parent().unwrap())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    left.sort();
    assert_eq!(left, ["summary.json", "summary.seeds.jsonl"]);
    // The null study hides nothing, so a strength is an error.
    let bad = tmp.path().join("bad").join("summary.json");
    let o = geardyn(&[
        "discover-study",
        "--hidden",
        "none",
        "--strength",
        "0.2",
        "--seeds",
        "1",
        "--out",
        bad.to_str().unwrap(),
    ]);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("strength"));
    assert!(!bad.exists());
    // STE amplitudes that carry the curves beyond the data's plausible range (over 1000 um):
    // synth refuses the seed's set, and the error says which seed and what to change.
    let o = geardyn(&[
        "discover-study",
        "--hidden",
        "none",
        "--loads",
        "3780:40,945:40",
        "--seeds",
        "1",
        "--out",
        bad.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("seed 1") && err.contains("STE amplitude"),
        "{err}"
    );
    assert!(err.contains("dte_pp_um"), "{err}");
    assert!(!bad.exists());
    assert!(
        !bad.parent().unwrap().exists()
            || std::fs::read_dir(bad.parent().unwrap())
                .unwrap()
                .next()
                .is_none()
    );
}

/// A second `discover-study` given the `--out` of one still running is refused before its
/// first seed, and the running study's per-seed lines are left as they are (the two once wrote
/// over each other in one file).
#[test]
fn a_study_on_the_out_of_a_running_one_is_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("summary.json");
    let seeds = out.with_extension("seeds.jsonl");
    std::fs::write(&seeds, "{\"seed\":1}\n").unwrap();
    // The running study's lock, held here.
    let running = std::fs::File::open(&seeds).unwrap();
    running.lock().unwrap();
    let o = geardyn(&[
        "discover-study",
        "--hidden",
        "none",
        "--seeds",
        "1",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("another study"), "{err}");
    assert_eq!(std::fs::read_to_string(&seeds).unwrap(), "{\"seed\":1}\n");
    assert!(!out.exists());
}

/// A null set made by DOP853 (not the fitting solver) on a non-uniform grid of 61 speeds, with
/// noise of `family` (floor 0.15 um plus 3% of the level; Student-t of 3 dof; read to 0.25 um).
fn null_set_of_family(dir: &Path, family: NoiseFamily, seed: u64) {
    let mut t = MunroTruth::default_munro();
    t.seed = seed;
    t.noise = family.noise(0.15);
    t.dop853_rtol = Some(1e-9);
    t.speed_list = Some(
        SpeedGrid::NonUniform {
            points: 61,
            seed: 7_777,
        }
        .speeds()
        .unwrap(),
    );
    synth_munro(&t, dir, &NoProgress).unwrap();
}

/// Sets geardyn's fit did not make (DOP853 curves, a non-uniform grid) with level-dependent
/// noise (floor 0.15 um + 3%), heavy-tailed noise (Student-t of 3 dof) and noise read to a grid:
/// "none" on each. The noise fitted with M0 finds the level-dependent part: a floor within a
/// factor 1.6 of 0.15 um (times the t scale's sqrt 3 at most) and a relative part of 1.5-6%.
#[test]
#[ignore = "three discover runs, too slow for the default run: .ci/run runs it (cargo test --release --test discover -- --ignored)"]
fn null_sets_with_level_dependent_and_heavy_tailed_noise_give_none() {
    let tmp = tempfile::tempdir().unwrap();
    for (k, family) in [
        NoiseFamily::Relative,
        NoiseFamily::StudentT,
        NoiseFamily::Quantized,
    ]
    .into_iter()
    .enumerate()
    {
        let dir = tmp.path().join(family.name());
        null_set_of_family(&dir, family, 21 + k as u64);
        let d = run(&dir);
        assert_eq!(
            d.effect,
            "none",
            "{}: {}",
            family.name(),
            geardyn::report::discovery_summary(&d)
        );
        assert!(matches!(d.noise.origin, NoiseOrigin::Fitted { .. }));
        let m = d.noise.model;
        assert!(
            m.floor > 0.15 / 1.6 && m.floor < 0.15 * 1.6 * 3f64.sqrt(),
            "{}: {m:?}",
            family.name()
        );
        assert!(
            m.relative > 0.015 && m.relative < 0.06,
            "{}: {m:?}",
            family.name()
        );
        if family != NoiseFamily::StudentT {
            assert_eq!(m.distribution, Distribution::Gaussian, "{}", family.name());
        }
    }
}

/// `discover` as `discover-study --dop853-rtol 1e-9 --bootstrap 199` runs it on `seed` of
/// `family` (noise floor 0.15 um, the bootstrap seeded 12345 + seed) for the set `truth` with
/// its seed, noise and solver set so.
fn study_seed(mut t: MunroTruth, family: NoiseFamily, seed: u64) -> Discovery {
    let tmp = tempfile::tempdir().unwrap();
    t.seed = seed;
    t.noise = family.noise(0.15);
    t.dop853_rtol = Some(1e-9);
    synth_munro(&t, tmp.path(), &NoProgress).unwrap();
    let opts = DiscoverOptions {
        bootstrap: BOOTSTRAP,
        seed: 12_345 + seed,
        ..DiscoverOptions::default()
    };
    run_with(tmp.path(), &opts)
}

/// [`study_seed`] of `discover-study --hidden none` (the 50 rpm grid).
fn study_null_seed(family: NoiseFamily, seed: u64) -> Discovery {
    study_seed(MunroTruth::default_munro(), family, seed)
}

/// A stated noise is used as stated and not re-estimated: a `dte_pp_sd_um` column on every
/// point, rig.toml `[noise] floor_um`/`relative`, and `--noise-um`, in that order of
/// precedence from the option down; each run says where its noise came from.
#[test]
#[ignore = "four discover runs, too slow for the default run: .ci/run runs it (cargo test --release --test discover -- --ignored)"]
fn stated_noise_is_used_as_stated() {
    let tmp = tempfile::tempdir().unwrap();
    let base = tmp.path().join("base");
    make_set(&base, HiddenEffects::default(), 5);
    let opts = DiscoverOptions {
        bootstrap: BOOTSTRAP,
        ..DiscoverOptions::default()
    };
    // rig.toml [noise].
    let rig = std::fs::read_to_string(base.join("rig.toml")).unwrap();
    let stated = tmp.path().join("stated");
    std::fs::create_dir_all(&stated).unwrap();
    std::fs::copy(base.join("dte.csv"), stated.join("dte.csv")).unwrap();
    std::fs::write(
        stated.join("rig.toml"),
        format!("{rig}\n[noise]\nfloor_um = 0.2\nrelative = 0.01\n"),
    )
    .unwrap();
    let d = run_with(&stated, &opts);
    assert_eq!(d.noise.origin, NoiseOrigin::StatedRig);
    assert_eq!((d.noise.model.floor, d.noise.model.relative), (0.2, 0.01));
    // sqrt(0.2^2 + (0.01 x level)^2): the floor at the low levels, more at the resonances.
    assert!(
        d.noise_range_um.0 >= 0.2 && d.noise_range_um.0 < 0.201,
        "{:?}",
        d.noise_range_um
    );
    assert!(d.noise_range_um.1 > 0.201, "{:?}", d.noise_range_um);
    // A per-point column.
    let column = tmp.path().join("column");
    std::fs::create_dir_all(&column).unwrap();
    std::fs::copy(base.join("rig.toml"), column.join("rig.toml")).unwrap();
    let csv = std::fs::read_to_string(base.join("dte.csv")).unwrap();
    let mut lines = csv.lines();
    let mut out = format!("{},dte_pp_sd_um\n", lines.next().unwrap());
    for l in lines.filter(|l| !l.is_empty()) {
        out.push_str(&format!("{l},0.25\n"));
    }
    std::fs::write(column.join("dte.csv"), out).unwrap();
    let d = run_with(&column, &opts);
    assert_eq!(d.noise.origin, NoiseOrigin::PerPoint);
    assert_eq!(d.noise_range_um, (0.25, 0.25));
    // The option overrides both.
    let d = run_with(
        &column,
        &DiscoverOptions {
            noise_um: Some(0.3),
            ..opts.clone()
        },
    );
    assert_eq!(d.noise.origin, NoiseOrigin::StatedOption);
    assert_eq!(d.noise_range_um, (0.3, 0.3));
    // A noise stated at a third of the set's (0.15 um): M0's goodness of fit fails, no
    // candidate explains it, and the answer says that the stated noise lies below the scatter.
    let d = run_with(
        &base,
        &DiscoverOptions {
            noise_um: Some(0.05),
            ..opts
        },
    );
    assert_eq!(d.effect, "unexplained");
    let text = geardyn::report::discovery_summary(&d);
    assert!(
        text.contains("a noise stated smaller than the scatter makes M0 fail"),
        "{text}"
    );
}

/// The Student-t null set of the discover study's seed 1076 (DOP853, 50 rpm grid, floor 0.15
/// um + 3%, 3 dof): the design-load linear start (eq. 13, which depends on Omega^2 only) ended
/// at omega_n = -1599.7 Hz and every prediction after it was refused, so `discover` failed on a
/// valid set and stopped the study. Now it answers "none" with omega_n near 1600 Hz.
#[test]
#[ignore = "a study seed on the 50 rpm grid, about 40 s: cargo test --release --test discover -- --ignored (run by .ci/run)"]
fn linear_start_does_not_end_at_a_negative_natural_frequency() {
    let d = study_null_seed(NoiseFamily::StudentT, 1076);
    assert_eq!(d.effect, "none");
    assert!(
        (d.omega_n_hz_m0 - 1600.0).abs() < 20.0,
        "{}",
        d.omega_n_hz_m0
    );
}

/// A small rig measured on a coarse grid (23/41 teeth, 0.05 mm backlash, design load 2000 N,
/// 2 loads x 15 speeds 500 rpm apart, zeta 0.03, 2500 Hz; made by DOP853 with relative noise):
/// at the design load the teeth separate for a moment at the resonance peak (6500 rpm) along
/// one continuous branch, and those points stay; M0's zeta comes back near the truth. Dropping
/// the peak and its neighbours as a jump left M0 without zeta, which ran to its floor 0.003.
#[test]
fn a_coarse_grid_keeps_the_resonance_peak_at_which_the_teeth_separate() {
    let tmp = tempfile::tempdir().unwrap();
    let mut t = MunroTruth::default_munro();
    t.rig = geardyn::data::Rig {
        name: "small rig, coarse grid".into(),
        pinion_teeth: 23,
        gear_teeth: 41,
        module_mm: 3.0,
        face_width_mm: 20.0,
        design_load_n: 2000.0,
        backlash_mm: 0.05,
        ..t.rig
    };
    t.zeta = 0.03;
    t.omega_n_hz = 2500.0;
    t.ste_um = vec![(2000.0, 0.3), (1000.0, 0.8)];
    t.speeds_rpm = (2000.0, 9000.0, 500.0);
    t.noise = NoiseFamily::Relative.noise(0.05);
    t.dop853_rtol = Some(1e-9);
    t.seed = 4;
    synth_munro(&t, tmp.path(), &NoProgress).unwrap();
    let d = run(tmp.path());
    assert!(
        d.excluded_by_load.iter().all(|e| e.load_n != 2000.0),
        "{:?}",
        d.excluded_by_load
    );
    assert!(!d.m0_zeta_at_lower_bound());
    assert!((d.zeta_m0 / 0.03 - 1.0).abs() < 0.1, "zeta {}", d.zeta_m0);
}

/// On the design-load curve alone there is nothing to hold out: no held-out gap and no
/// prediction check, and the answer stands on the training loads.
#[test]
fn a_single_load_has_nothing_held_out() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("design");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::copy("data/munro/rig.toml", dir.join("rig.toml")).unwrap();
    let csv = std::fs::read_to_string("data/munro/dte.csv").unwrap();
    let design: Vec<&str> = csv
        .lines()
        .filter(|l| l.starts_with("load_n") || l.starts_with("3780,"))
        .collect();
    assert!(design.len() > 50, "{} lines", design.len());
    std::fs::write(dir.join("dte.csv"), design.join("\n") + "\n").unwrap();
    let d = run(&dir);
    assert!(d.gap_before.held_out.is_none() && d.prediction_check.is_none());
    assert!(d.goodness_of_fit.p_value.is_some());
    assert!(!d.design_load_missing());
}

/// Without a curve at the design load M0 is fitted to the highest load in its place, and the
/// discovery says so.
#[test]
fn a_set_without_the_design_load_says_so() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("light");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::copy("data/munro/rig.toml", dir.join("rig.toml")).unwrap();
    let csv = std::fs::read_to_string("data/munro/dte.csv").unwrap();
    let light: Vec<&str> = csv
        .lines()
        .filter(|l| l.starts_with("load_n") || l.starts_with("2835,"))
        .collect();
    std::fs::write(dir.join("dte.csv"), light.join("\n") + "\n").unwrap();
    let d = run(&dir);
    assert_eq!(d.training_loads_n, vec![2835.0]);
    assert!(d.design_load_missing());
}

/// The power bound a study asks for: on a null set, a damping law's test at gamma -0.6 has
/// hardly more power than its level (M0's zeta and STEs make most of its change), and a
/// stronger law more; the power never falls below the level.
#[test]
#[ignore = "two discover runs, too slow for the default run: .ci/run runs it (cargo test --release --test discover -- --ignored)"]
fn the_power_bound_grows_with_the_effect() {
    let tmp = tempfile::tempdir().unwrap();
    make_set(tmp.path(), HiddenEffects::default(), 3);
    let power = |gamma: f64| {
        let opts = DiscoverOptions {
            bootstrap: BOOTSTRAP,
            power_at: Some(Effect::of(Candidate::DampingLaw, vec![gamma])),
            ..DiscoverOptions::default()
        };
        let p = run_with(tmp.path(), &opts)
            .power_bound
            .expect("a power bound");
        assert_eq!(p.candidate, "damping_law");
        assert!((p.level - 0.01).abs() < 1e-12, "{}", p.level);
        assert!(p.power >= p.level - 1e-9 && p.power <= 1.0, "{p:?}");
        (p.noncentrality, p.power)
    };
    let (weak, strong) = (power(-0.6), power(-3.0));
    assert!(
        strong.0 > weak.0 && strong.1 > weak.1,
        "gamma -0.6: {weak:?}; gamma -3: {strong:?}"
    );
}
