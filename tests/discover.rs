//! Discrepancy discovery on seeded synthetic sets: the null case gives "none" and never reads the
//! truth, also on sets made by another integrator with level-dependent and heavy-tailed noise on
//! a non-uniform grid; a stated noise (column, rig.toml, option) is used as stated; a second STE
//! harmonic is named with its true size inside the 95% interval; a candidate significant where
//! no discrepancy is detected is not refitted; an effect outside the library is "unexplained"; backlash is reported not identifiable without back-side contact; bad input
//! fails cleanly. Sets use a 100 rpm grid (41 speeds per load) to keep the suite short. The
//! recovery of the other effects (stiffness variation at any phase, torque ripple, damping law,
//! backlash) runs as `discover-study` in `.ci/run`, and the rates over many seeds are in
//! docs/discover-studies.md.

mod common;
use common::geardyn;
use geardyn::data::load_munro;
use geardyn::discover::{discover, DiscoverOptions, Discovery, NoiseOrigin};
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

fn run(dir: &Path) -> Discovery {
    run_with(dir, &DiscoverOptions::default())
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
    // The named effect's interval is the hull of its profile-likelihood and Wald intervals,
    // and the profile brackets the estimate: each profile side is a fit at which the residual
    // sum of squares rose by 3.84 sigma^2 from the refit's.
    assert_eq!(
        c.ci95_method,
        "hull of the profile-likelihood and Wald intervals"
    );
    let (wl, wh) = c.wald_ci95.unwrap();
    let (pl, ph) = c.profile_ci95.unwrap();
    let (pl, ph) = (pl.unwrap(), ph.unwrap());
    let est = c.estimate.unwrap();
    assert!(pl < est && est < ph, "profile [{pl}, {ph}] about {est}");
    assert_eq!((lo, hi), (wl.min(pl), wh.max(ph)));
}

/// The named effect's true phase (rad) lies on one of its 95% phase arcs (degrees), and the
/// arcs are arcs, not the whole circle.
fn assert_phase_on_arcs(d: &Discovery, truth_rad: f64) {
    let c = d.candidates.iter().find(|c| c.name == d.effect).unwrap();
    let t = truth_rad.to_degrees();
    let on = |&(lo, hi): &(f64, f64)| (t - lo).rem_euclid(360.0) <= hi - lo;
    assert!(
        c.phase_wald95_deg.iter().any(on),
        "true phase {t} deg, estimate {:?} deg, arcs {:?}",
        c.phase_deg,
        c.phase_wald95_deg
    );
    assert!(c.phase_wald95_deg.iter().all(|(lo, hi)| hi - lo < 180.0));
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
/// solver did not make (measurements) draw other windows than its prediction. On the shipped
/// `data/munro` (made by an older solver build) the largest excluded 945 N point (84 um) must
/// lie inside the pp M0 produces over its prediction's and 32 later windows, or inside what
/// the fits at the ends of M0's 95% confidence region produce: "none". Which window, even which
/// of the curve's coexisting chaotic attractors, M0's prediction draws depends on the state the
/// sweep carries from the speed before, down to its last bits: 73 um when that state came
/// 2000 periods later (after a Lyapunov exponent a fit never read), and comparing with the
/// prediction alone answered "unexplained"; 88 um over the 32 windows on one build, 74 um on a
/// build whose Newton shots take a period-1 orbit's shortest lag first (the same orbits to
/// 1e-12), where the region's fits reach 85 um. (The rule's false-positive rate on sets made
/// by DOP853 is measured by the null studies, docs/discover-studies.md.)
#[test]
fn chaotic_points_from_another_solver_stay_inside_m0s_window_range() {
    let shipped = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/munro");
    let d = run(&shipped);
    assert_eq!(d.effect, "none");
    assert_eq!(d.excluded_far_outside(), 0, "{:?}", d.excluded_by_load);
    let e = d
        .excluded_by_load
        .iter()
        .find(|e| e.load_n == 945.0)
        .unwrap();
    let margin = |top: f64| 3.0 * d.noise.scale_at(0, 0, top) + 0.1 * top;
    // The range starts from the prediction's own windows; the 32 later windows reach past
    // them.
    assert!(e.model_range_um.1 > e.predicted_range_um.1, "{e:?}");
    let reach = e
        .region_range_um
        .map_or(e.model_range_um.1, |r| r.1.max(e.model_range_um.1));
    let top = e.measured_range_um.1;
    assert!(top <= reach + margin(reach), "{e:?}");
    assert_eq!(e.outside_model_range, 0, "{e:?}");
}

/// A second STE harmonic at 40% of the first: named, ratio inside its 95% interval, training
/// gap down to the noise level; the held-out loads' STE amplitudes, fitted alone with the
/// effect, come back to their true values (1.5 and 3.5 um) within 5% (about two noise sigma of
/// the quasi-static pp at 945 N), and the held-out gap falls below twice the noise (0.15 um).
#[test]
#[ignore = "about 21 s, too slow for the default run: .ci/run runs it (cargo test --release --test discover -- --ignored)"]
fn hidden_second_ste_harmonic_is_named_and_sized() {
    let h = HiddenEffects {
        ste2_ratio: 0.4,
        ..HiddenEffects::default()
    };
    let d = discover_hidden(h, 3, MunroTruth::default_munro().ste_um);
    assert_named_with_truth_inside(&d, "ste_harmonics", 0.4);
    assert_phase_on_arcs(&d, 0.0);
    assert!(
        d.gap_after.training.rms_um < 0.3,
        "{:?}",
        d.gap_after.training
    );
    assert!(d.gap_before.training.rms_um > 1.0);
    for (load, truth) in [(2835.0, 1.5), (945.0, 3.5)] {
        let (_, _, after) = d
            .held_out_ste_um
            .iter()
            .find(|x| x.0 == load)
            .copied()
            .unwrap();
        assert!((after / truth - 1.0).abs() < 0.05, "{load} N: STE {after}");
    }
    let (b, a) = held_out_rms(&d);
    assert!(a < 0.3 && a < b, "held-out RMS {b} -> {a}");
}

/// An independent set (tools/indep-synth: a 2nd STE harmonic of 40% at phase 0, relative noise
/// 3% + 0.05 um, 64 speeds at Omega 0.4-1.45, zeta 0.019 and 2120 Hz; the command and truth in
/// tests/data/independent-discover/truth.toml) on which M0 ends at zeta 0.64 and 1282 Hz: the
/// damping law's probe gamma = -1 asks for zeta 1.27 at 1890 N, outside 0 < zeta < 1. That
/// ended the whole run with the bare "invalid parameter zeta = 1.27..". A failure inside a
/// candidate is the candidate's: the damping law is reported "failed, because" its probe could
/// not be simulated (console and discovery.json), and the run goes on to name the harmonic with
/// its truth inside the interval.
#[test]
#[ignore = "about 10 s, too slow for the default run: .ci/run runs it (cargo test --release --test discover -- --ignored)"]
fn a_candidate_that_fails_inside_is_reported_failed_and_the_run_goes_on() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/independent-discover/ste2-m0-overdamped");
    let data = load_munro(&dir).unwrap();
    let d = discover(&data, &DiscoverOptions::default(), &NoProgress).unwrap();
    let failed: Vec<&str> = d
        .candidates
        .iter()
        .filter(|c| c.failed.is_some())
        .map(|c| c.name)
        .collect();
    assert_eq!(failed, ["damping_law"], "{:#?}", d.candidates);
    let damping = d
        .candidates
        .iter()
        .find(|c| c.name == "damping_law")
        .unwrap();
    let why = damping.failed.as_deref().unwrap();
    assert!(
        why.starts_with("its probe delta = [-1.0] could not be simulated at M0's fit")
            && why.contains("invalid parameter zeta"),
        "{why}"
    );
    assert!(damping.p_value.is_none() && damping.estimate.is_none());
    let text = geardyn::discover::summary_text(&d);
    assert!(
        text.contains("(failed, because its probe delta = [-1.0]"),
        "{text}"
    );
    let json = geardyn::discover::discovery_json(&data, &d);
    assert_eq!(json["candidates"][2]["name"], "damping_law");
    assert_eq!(json["candidates"][2]["failed"], why);
    assert!(json["candidates"][1]["failed"].is_null());
    assert_named_with_truth_inside(&d, "ste_harmonics", 0.4);
    assert_phase_on_arcs(&d, 0.0);
}

/// Damping falling at light load (gamma +1) on Munro's four loads: the tests cannot see it (the
/// training loads barely change and 945 N changes only where M0 predicts chaos, which the tests
/// exclude), but the excluded points at 945 N (a period-3 double-sided branch of 157-181 um
/// where M0 gives chaos up to ~80 um) lie far outside M0's range: a discrepancy is detected
/// there, no candidate is significant, and the answer is "unexplained", not "none".
/// (On this grid the last point before the 2835 N jump, 4 um higher with the lighter damping,
/// is flagged too: a real trace of the effect.)
#[test]
fn damping_falling_at_light_load_is_flagged_among_the_excluded_points() {
    let hidden = HiddenEffects {
        damping_exponent: 1.0,
        ..HiddenEffects::default()
    };
    let d = discover_hidden(hidden, 3, MunroTruth::default_munro().ste_um);
    assert!(!d.detected_by_tests && d.detected_by_excluded_points() && d.detected);
    assert_eq!(d.effect, "unexplained");
    assert!(geardyn::discover::summary_text(&d).contains("excluded point(s) lie far outside"));
    let e945 = d
        .excluded_by_load
        .iter()
        .find(|e| e.load_n == 945.0)
        .unwrap();
    assert!(e945.outside_model_range >= 5, "{e945:?}");
    assert!(
        e945.measured_range_um.1 > 1.5 * e945.model_range_um.1,
        "{e945:?}"
    );
    assert!(geardyn::discover::summary_text(&d).contains("WARNING"));
}

/// A measuring-chain resonance at 2300 Hz (+50%) is nothing in the library: "unexplained",
/// and the report still gives the closest candidate's refit and its gap after.
#[test]
fn effect_outside_the_library_is_unexplained() {
    let h = HiddenEffects {
        sensor_peak_hz: 2300.0,
        sensor_peak_gain: 0.5,
        ..HiddenEffects::default()
    };
    let d = discover_hidden(h, 3, MunroTruth::default_munro().ste_um);
    assert!(d.detected);
    assert_eq!(d.effect, "unexplained", "{:#?}", d.candidates);
    if let Some(c) = &d.closest_candidate {
        assert_eq!(d.gap_after_model, format!("M0 + {c}"));
        assert_ne!(
            d.gap_after.training.rms_um, d.gap_before.training.rms_um,
            "the gap after is the closest candidate's refit, not a copy of M0's"
        );
    }
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
        "599",
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
    // Every detection test with enough points (the Omega = 2 window has none below 5000 rpm)
    // and every identifiable candidate has a p-value per seed, and the calibration counts them.
    let cal = s["calibration"].as_array().unwrap();
    let names: Vec<&str> = cal.iter().map(|c| c["name"].as_str().unwrap()).collect();
    for n in [
        "chi_square_training",
        "chi_square_held_out",
        "runs_along_frequency",
        "window_omega_1/2",
        "window_omega_1",
        "candidate_torque_ripple",
    ] {
        assert!(names.contains(&n), "{names:?}");
    }
    assert!(!names.contains(&"window_omega_2") && !names.contains(&"candidate_backlash"));
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
/// noise (floor 0.15 um + 3%), heavy-tailed noise (the same as Student-t of 3 dof) and noise
/// read to a grid: "none" on each, where a single estimated sigma answered "unexplained" on
/// every such set. The estimated noise finds the level-dependent part: a floor within a factor
/// 1.6 of 0.15 um and a relative part of 1.5-6% (the sampling spread of two parameters from
/// about 200 pseudo-residuals), the Student-t set's heavy tails or their standard deviation
/// (sd of t3 = sqrt 3 scales).
#[test]
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
        assert_eq!(d.effect, "none", "{}: {:#?}", family.name(), d.detection);
        assert!(d.noise.is_estimated());
        let m = d.noise.model;
        let sd_floor = d.noise.scale_at(0, 0, 0.0);
        assert!(
            sd_floor > 0.15 / 1.6 && sd_floor < 0.15 * 1.6 * 3f64.sqrt(),
            "{}: {m:?}",
            family.name()
        );
        assert!(
            d.noise.relative_estimated && m.relative > 0.015 && m.relative < 0.06,
            "{}: {:?}",
            family.name(),
            d.noise
        );
        if family != NoiseFamily::StudentT {
            assert_eq!(m.distribution, Distribution::Gaussian, "{}", family.name());
        }
    }
}

/// `discover` as `discover-study --dop853-rtol 1e-9 --bootstrap 999` runs it on `seed` of
/// `family` (noise floor 0.15 um, the bootstrap seeded 12345 + seed) for the set `truth` with
/// its seed, noise and solver set so.
fn study_seed(mut t: MunroTruth, family: NoiseFamily, seed: u64) -> Discovery {
    let tmp = tempfile::tempdir().unwrap();
    t.seed = seed;
    t.noise = family.noise(0.15);
    t.dop853_rtol = Some(1e-9);
    synth_munro(&t, tmp.path(), &NoProgress).unwrap();
    let opts = DiscoverOptions {
        bootstrap: 999,
        seed: 12_345 + seed,
        ..DiscoverOptions::default()
    };
    run_with(tmp.path(), &opts)
}

/// [`study_seed`] of `discover-study --hidden none` (the 50 rpm grid).
fn study_null_seed(family: NoiseFamily, seed: u64) -> Discovery {
    study_seed(MunroTruth::default_munro(), family, seed)
}

/// [`study_seed`] of `discover-study --speed-step 100` with `hidden` at its phase (the one
/// `--random-phase` drew for the seed, or another).
fn study_seed_on_100_rpm(hidden: HiddenEffects, family: NoiseFamily, seed: u64) -> Discovery {
    let mut t = MunroTruth::default_munro();
    t.speeds_rpm = (1000.0, 5000.0, 100.0);
    t.hidden = hidden;
    study_seed(t, family, seed)
}

/// On a 300 rpm grid the design load's peak can fall between two speeds, and eq. 13's start
/// narrows it towards zeta 0, below the fits' floor, where every prediction is refused: on this
/// null set (relative noise, DOP853, study seed 2) the whole run failed. M0 now starts at the
/// floor and moves off it.
#[test]
fn a_coarse_grid_whose_linear_start_narrows_the_peak_still_answers() {
    let mut t = MunroTruth::default_munro();
    t.speeds_rpm = (1000.0, 5000.0, 300.0);
    let d = study_seed(t, NoiseFamily::Relative, 2);
    assert_eq!(d.effect, "none");
    assert!(d.zeta_m0 > 0.005, "M0 zeta {}", d.zeta_m0);
}

/// M0's second fit is weighted by the noise about its first with the relative part free. On
/// this 300 rpm null set (Student-t noise, DOP853, study seed 36) the estimate about the first
/// fit drops a true 3% (a resonance holds one or two of a curve's 14 speeds), and weighted by
/// that constant scale the second fit ran to zeta 0.003 at the fits' floor (true 0.0175): every
/// test rejected, "unexplained". With the relative part free: zeta 0.0229, "none".
#[test]
fn m0_is_weighted_with_the_relative_part_a_coarse_grid_could_not_establish() {
    let mut t = MunroTruth::default_munro();
    t.speeds_rpm = (1000.0, 5000.0, 300.0);
    let d = study_seed(t, NoiseFamily::StudentT, 36);
    assert!(d.zeta_m0 > 0.01, "M0 zeta {}", d.zeta_m0);
    assert!(!d.m0_zeta_at_lower_bound());
    assert_eq!(d.effect, "none");
}

/// On a 300 rpm grid M0's damping is poorly determined, and a chaotic point at 945 N can lie
/// beyond every pp the fitted M0 makes there: on this null set (relative noise, DOP853, study
/// seed 43) 77.6 um against 58.3 um. The fits at the ends of M0's 95% confidence region reach
/// it (82 um), so it is not a discrepancy: "none", where the rule that took M0 as fitted
/// answered "unexplained". (Seed 4 showed the same, 77.8 um against 60.3 um, until the sets'
/// chaotic points moved with the last bits of the states their sweeps carry.)
#[test]
fn a_point_beyond_the_fitted_m0_but_within_its_confidence_region_is_no_discrepancy() {
    let mut t = MunroTruth::default_munro();
    t.speeds_rpm = (1000.0, 5000.0, 300.0);
    let d = study_seed(t, NoiseFamily::Relative, 43);
    assert_eq!(d.effect, "none", "{:#?}", d.excluded_by_load);
    let e945 = d
        .excluded_by_load
        .iter()
        .find(|e| e.load_n == 945.0)
        .unwrap();
    let region = e945
        .region_range_um
        .expect("widened over the confidence region");
    assert!(
        e945.measured_range_um.1 > e945.model_range_um.1 + 10.0,
        "{e945:?}"
    );
    assert!(region.1 > e945.model_range_um.1, "{e945:?}");
    assert_eq!(e945.outside_model_range, 0, "{e945:?}");
}

/// On a 300 rpm grid the few points high on a resonance hardly inform the noise's relative
/// part, and on about a quarter of the sets with 3% of the level the estimate drops it. On this
/// null set (quantized noise, DOP853, study seed 48) it does: when the replicates were drawn
/// from that constant model, their points at Omega = 1 scattered by the floor while the data's
/// scatter by 3% of tens of um, and the Omega = 1 window's test gave p 0.003 and the answer
/// "unexplained". The replicates are drawn with the relative part free (about 3% here).
#[test]
fn replicates_carry_the_relative_part_a_coarse_grid_could_not_establish() {
    let mut t = MunroTruth::default_munro();
    t.speeds_rpm = (1000.0, 5000.0, 300.0);
    let d = study_seed(t, NoiseFamily::Quantized, 48);
    assert_eq!(d.noise.model.relative, 0.0, "{:?}", d.noise);
    let drawn = d
        .noise
        .replicate_model
        .expect("drawn with the relative part free");
    assert!(drawn.relative > 0.01, "{drawn:?}");
    let window = d
        .detection
        .iter()
        .find(|t| t.name == "window_omega_1")
        .and_then(|t| t.p_value)
        .expect("the Omega = 1 window holds points");
    assert!(window > 0.01, "{window}");
    assert_eq!(d.effect, "none");
}

/// Where the information of M0's fit is nearly singular, an end of its confidence region can
/// lie below the fits' floor in zeta; it is clamped there, and an end at the floor can reach
/// almost any pp, so the run says so. On this null set (Student-t noise, 300 rpm grid, study
/// seed 90) a chaotic point at 945 N lies far outside M0's range, and the region's zeta ends
/// reach the floor.
#[test]
fn a_confidence_region_clamped_at_the_floor_is_reported() {
    let mut t = MunroTruth::default_munro();
    t.speeds_rpm = (1000.0, 5000.0, 300.0);
    let d = study_seed(t, NoiseFamily::StudentT, 90);
    let e945 = d
        .excluded_by_load
        .iter()
        .find(|e| e.load_n == 945.0)
        .expect("points excluded at 945 N");
    assert!(e945.region_range_um.is_some(), "{e945:?}");
    assert_eq!(e945.region_clamped, ["zeta at the fits' floor"], "{e945:?}");
    let text = geardyn::discover::summary_text(&d);
    assert!(
        text.contains("ends clamped: zeta at the fits' floor"),
        "{text}"
    );
}

/// A candidate significant among the candidates' tests where M0's tests together do not reject
/// it is neither refitted nor named, and the run says why. On this null set (constant noise,
/// DOP853, the 50 rpm grid: study seed 1031) the torque ripple's test gives p 0.006, below
/// Holm's 2.5% among the four candidates (0.024) and above it over every test of M0.
#[test]
fn a_significant_candidate_without_a_detected_discrepancy_is_not_refitted() {
    let d = study_null_seed(NoiseFamily::Constant, 1031);
    assert!(!d.detected, "{:#?}", d.detection);
    assert_eq!(d.effect, "none");
    assert_eq!(d.significant_undetected, ["torque_ripple"]);
    assert!(d.candidates.iter().all(|c| c.estimate.is_none()));
    assert_eq!(d.gap_after_model, "M0, no candidate refitted");
    let text = geardyn::discover::summary_text(&d);
    assert!(
        text.contains(
            "torque_ripple significant among the candidates' tests, but no discrepancy is detected"
        ),
        "{text}"
    );
}

/// A damping law that only its own test sees: gamma -1 on five loads (the damping study's set,
/// 100 rpm grid, constant noise, seed 3). Every detection test stays above Holm's level (the
/// smallest p 0.2) while the candidate's test gives p 0.001, which rejects M0 with Holm over
/// every test; the damping law is named and gamma -1 lies inside its interval.
#[test]
fn a_damping_law_only_its_own_test_sees_is_detected_and_named() {
    let mut t = MunroTruth::default_munro();
    t.ste_um = vec![
        (3780.0, 0.3),
        (2835.0, 1.5),
        (1890.0, 2.5),
        (1418.0, 3.0),
        (945.0, 3.5),
    ];
    t.speeds_rpm = (1000.0, 5000.0, 100.0);
    t.hidden.damping_exponent = -1.0;
    let d = study_seed(t, NoiseFamily::Constant, 3);
    // Holm among the detection tests alone: its smallest adjusted p-value is m times the
    // smallest raw one (the reported p_holm is over every test of M0).
    let p: Vec<f64> = d.detection.iter().filter_map(|x| x.p_value).collect();
    let least = p.iter().copied().fold(1.0, f64::min);
    assert!(least * p.len() as f64 >= 0.025, "{:#?}", d.detection);
    assert!(d.detected_by_tests);
    assert_named_with_truth_inside(&d, "damping_law", -1.0);
}

/// A stiffness variation at a phase where |STE + its mesh-frequency equivalent| falls toward
/// zero STE is not taken for a 2nd STE harmonic. On this set (eps 0.2 at 254 deg, Student-t
/// noise, the 100 rpm grid: study seed 13) the matched start of the design load had only the
/// upper root of that magnitude (the lower one negative), its refit ended far from the truth,
/// and a harmonic with zeta 0.0045 against a true 0.0175 led by 755 against 740 sigma^2: it was
/// named, then, once its profile demoted it, the stiffness variation was decided on again.
/// With zero STE scored as well, the stiffness variation leads from the first decision
/// (only its profile is taken) and is named with the truth inside its interval.
#[test]
#[ignore = "about 33 s, too slow for the default run: .ci/run runs it (cargo test --release --test discover -- --ignored)"]
fn a_stiffness_variation_whose_matched_ste_is_near_zero_is_named() {
    let hidden = HiddenEffects {
        stiffness_eps: 0.2,
        stiffness_phase: 4.428205224803389,
        ..HiddenEffects::default()
    };
    let d = study_seed_on_100_rpm(hidden, NoiseFamily::StudentT, 13);
    assert_named_with_truth_inside(&d, "mesh_stiffness_variation", 0.2);
    assert_phase_on_arcs(&d, 4.428205224803389);
    assert_eq!(
        d.decided_on(),
        ["mesh_stiffness_variation"],
        "{:#?}",
        d.candidates
    );
}

/// The phase's profile likelihood (`--phase-profile`) where the refit's phase is not the
/// likelihood's best. On this set (eps 0.15 at 163.8 deg, relative noise, the 100 rpm grid:
/// study seed 6) the refit ends at 181 deg (its Wald arc 169 .. 193 deg, as without the
/// option); the phase profile finds a point that fits the training curves better, and the
/// refit continues from there: phase 165 deg, the arc the hull of its Wald arc (154 .. 177)
/// and the profile's (151 .. 181), which holds the truth. (Study seed 14 showed the restart
/// until the Wald variance took the secants' too: its wider Wald arc starts the profile's
/// search elsewhere, which no longer lands on the better point; its arc, 246 .. 313 deg, then
/// spans both of the likelihood's minima and the truth between them.)
#[test]
#[ignore = "a study seed of about 40 s: cargo test --release --test discover -- --ignored (run by .ci/run)"]
fn a_phase_profile_that_fits_better_restarts_the_refit() {
    let truth = 2.858156548378564;
    let tmp = tempfile::tempdir().unwrap();
    let mut t = MunroTruth::default_munro();
    t.speeds_rpm = (1000.0, 5000.0, 100.0);
    t.hidden = HiddenEffects {
        stiffness_eps: 0.15,
        stiffness_phase: truth,
        ..HiddenEffects::default()
    };
    t.seed = 6;
    t.noise = NoiseFamily::Relative.noise(0.15);
    t.dop853_rtol = Some(1e-9);
    synth_munro(&t, tmp.path(), &NoProgress).unwrap();
    let with = |phase_profile: bool| {
        let opts = DiscoverOptions {
            bootstrap: 999,
            seed: 12_345 + 6,
            phase_profile,
            ..DiscoverOptions::default()
        };
        let d = run_with(tmp.path(), &opts);
        assert_named_with_truth_inside(&d, "mesh_stiffness_variation", 0.15);
        d.candidates
            .into_iter()
            .find(|c| c.name == "mesh_stiffness_variation")
            .unwrap()
    };
    // Without the profile the refit stays at its own minimum.
    let alone = with(false).phase_deg.expect("a phase");
    assert!((176.0..186.0).contains(&alone), "phase {alone} deg");
    // With it the refit moved to the profile's better point, near the truth.
    let c = with(true);
    let phase = c.phase_deg.expect("a phase");
    assert!((160.0..170.0).contains(&phase), "phase {phase} deg");
    let arc = c.phase_profile95_deg.expect("the phase was profiled");
    let on = |deg: f64, (lo, hi): (f64, f64)| (deg - lo).rem_euclid(360.0) <= hi - lo;
    assert!(
        on(phase, arc) && on(truth.to_degrees(), arc),
        "profile arc {arc:?}"
    );
    // The profile's arc contains the Wald arc (the hull) and is not the whole circle.
    let w = c.phase_wald95_deg[0];
    assert!(arc.0 <= w.0 + 1e-9 && arc.1 >= w.1 - 1e-9 && arc.1 - arc.0 < 180.0);
}

/// When the training loads prefer one candidate and the held-out loads another, the answer is
/// "ambiguous" between them, not a name. On this set (a torque ripple of 0.03 at 246 deg,
/// constant noise, the 100 rpm grid: study seed 38) a damping law fits the training loads best
/// and passes their chi-square (p 0.94) but fails the held-out one (p 0.001); the torque
/// ripple's refit passes both. The damping law used to be named.
#[test]
fn a_name_the_held_out_loads_reject_in_favour_of_another_is_ambiguous() {
    let hidden = HiddenEffects {
        torque_ripple_ratio: 0.03,
        torque_ripple_phase: 4.294180151578195,
        ..HiddenEffects::default()
    };
    let d = study_seed_on_100_rpm(hidden, NoiseFamily::Constant, 38);
    assert_eq!(d.effect, "ambiguous", "{:#?}", d.candidates);
    assert_eq!(d.ambiguous_with, ["damping_law", "torque_ripple"]);
    assert_eq!(d.held_out_prefers.as_deref(), Some("torque_ripple"));
    let held_out = d.post_fit.iter().find(|t| t.name == "chi_square_held_out");
    assert!(held_out.and_then(|t| t.p_value).is_some_and(|p| p < 0.025));
    let text = geardyn::discover::summary_text(&d);
    assert!(
        text.contains(
            "The training loads prefer damping_law, but its refit fails the held-out chi-square"
        ),
        "{text}"
    );
}

/// A name the held-out loads reject has the candidates significant only before Holm's
/// correction refitted as its rivals. On this set (eps 0.1 at 3.34 rad, 191 deg, relative
/// noise, the 100 rpm grid, noise seed 2) the stiffness variation's own test gives p 0.001 and
/// the torque ripple's 0.017, which Holm over the three identifiable candidates does not pass
/// (0.034); the stiffness variation's refit passes the training chi-square and fails the
/// held-out one (p 0.014). The torque ripple, refitted as a rival, does not pass both, so the
/// name stands: a rival can split a name the held-out loads reject, never replace it.
///
/// Until the probes were matched to the effects' first-order part, eps 0.15 at 265 deg (seed
/// 2) took this path to "ambiguous": the stiffness variation's own test was short of Holm
/// (p 0.016), a 2nd STE harmonic was named and failed the held-out chi-square, and the
/// stiffness variation, refitted as its rival, passed both. With matched probes that set is
/// named outright, and no study seed since has ended "ambiguous" through a rival; the split
/// itself is `a_name_the_held_out_loads_reject_in_favour_of_another_is_ambiguous`.
#[test]
#[ignore = "a study seed of about 40 s: cargo test --release --test discover -- --ignored (run by .ci/run)"]
fn a_rival_significant_only_before_holm_is_refitted_for_a_name_the_held_out_loads_reject() {
    let hidden = HiddenEffects {
        stiffness_eps: 0.1,
        stiffness_phase: 3.3397603637242277,
        ..HiddenEffects::default()
    };
    let d = study_seed_on_100_rpm(hidden, NoiseFamily::Relative, 2);
    assert_eq!(d.effect, "mesh_stiffness_variation", "{:#?}", d.candidates);
    let held_out = d.post_fit.iter().find(|t| t.name == "chi_square_held_out");
    assert!(held_out.and_then(|t| t.p_value).is_some_and(|p| p < 0.025));
    assert_eq!(d.held_out_prefers, None);
    let ripple = d
        .candidates
        .iter()
        .find(|c| c.name == "torque_ripple")
        .expect("the torque ripple is a candidate");
    assert!(
        ripple.p_value.is_some_and(|p| p < 0.025) && ripple.p_holm.is_some_and(|p| p >= 0.025),
        "{ripple:#?}"
    );
    assert!(
        ripple.estimate.is_some(),
        "the rival was refitted: {ripple:#?}"
    );
}

/// A stated noise is used as stated and not re-estimated: a `dte_pp_sd_um` column on every
/// point, rig.toml `[noise] floor_um`/`relative`, and `--noise-um`, in that order of
/// precedence from the option down; each run says where its noise came from.
#[test]
fn stated_noise_is_used_as_stated() {
    let tmp = tempfile::tempdir().unwrap();
    let base = tmp.path().join("base");
    make_set(&base, HiddenEffects::default(), 5);
    let opts = DiscoverOptions {
        bootstrap: 599,
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
            ..opts
        },
    );
    assert_eq!(d.noise.origin, NoiseOrigin::StatedOption);
    assert_eq!(d.noise_range_um, (0.3, 0.3));
    // A noise stated at a third of the set's (0.15 um): every test rejects, no candidate
    // explains it, and the answer says that the stated noise lies below the scatter.
    let d = run_with(
        &base,
        &DiscoverOptions {
            noise_um: Some(0.05),
            ..opts
        },
    );
    assert_eq!(d.effect, "unexplained");
    let text = geardyn::discover::summary_text(&d);
    assert!(
        text.contains("a noise stated smaller than the scatter makes every test reject"),
        "{text}"
    );
}

/// The Student-t null set of the discover study's seed 1076 (DOP853, 50 rpm grid, floor 0.15
/// um + 3%, 3 dof): the design-load linear start (eq. 13, which depends on Omega^2 only) ended
/// at omega_n = -1599.7 Hz and every prediction after it was refused, so `discover` failed on a
/// valid set and stopped the study. Now it answers "none" with omega_n near 1600 Hz.
#[test]
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

/// On the design-load curve alone there is nothing to hold out: the held-out chi-square is not
/// run (no statistic, no p-value, not in Holm's family), rather than a zero statistic with
/// p 1 that counted as a test.
#[test]
fn a_single_load_runs_no_held_out_test() {
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
    let held = d
        .detection
        .iter()
        .find(|t| t.name == "chi_square_held_out")
        .expect("listed");
    assert!(held.statistic.is_nan() && held.p_value.is_none() && held.p_holm.is_none());
    let training = d
        .detection
        .iter()
        .find(|t| t.name == "chi_square_training")
        .expect("listed");
    assert!(training.p_value.is_some());
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
