//! Discrepancy discovery (issue 5) on seeded synthetic sets with an effect hidden: the null case
//! gives "none" and never reads the truth, the two effects the paper points to are named with
//! their true size inside the 95% interval (and load-dependent damping on a five-load set), an
//! effect outside the library is "unexplained",
//! backlash is reported not identifiable without back-side contact (and identifiable where a
//! smaller backlash reaches the back flank), and bad input fails cleanly.
//! Sets use a 100 rpm grid (41 speeds per load) to keep the suite short; the null-rate and
//! recovery rates over many seeds come from `geardyn discover-study` (README).

mod common;
use common::geardyn;
use geardyn::data::load_munro;
use geardyn::discover::{discover, Candidate, CandidateResult, DiscoverOptions, Discovery};
use geardyn::progress::NoProgress;
use geardyn::validate::{synth_munro, HiddenEffects, MunroTruth};
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

/// The rattle-regime backlash set: true b 0.7 of the stated one, STE 8-12 um at the light
/// loads (synthetic), on a grid of `step_rpm`.
fn rattle_backlash_set(dir: &Path, seed: u64, step_rpm: f64) {
    let hidden = HiddenEffects {
        backlash_factor: 0.7,
        ..HiddenEffects::default()
    };
    let loads = vec![(3780.0, 0.3), (1890.0, 8.0), (945.0, 10.0), (472.0, 12.0)];
    make_set_on(dir, hidden, seed, loads, step_rpm);
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
/// `data/munro` (made by an older solver build) and on a null set made by DOP853 (seed 8), the
/// largest excluded 945 N point lies beyond M0's predicted pp by more than the rule's margin
/// (84 um against 71 um; 75 against 67), so comparing with the prediction alone answered
/// "unexplained". It lies inside the pp M0 produces over 32 later windows: "none".
#[test]
fn chaotic_points_from_another_solver_stay_inside_m0s_window_range() {
    let tmp = tempfile::tempdir().unwrap();
    let dop853 = tmp.path().join("dop853");
    let mut t = MunroTruth::default_munro();
    t.seed = 8;
    t.dop853_rtol = Some(1e-9);
    synth_munro(&t, &dop853, &NoProgress).unwrap();
    let shipped = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/munro");
    for dir in [shipped, dop853] {
        let d = run(&dir);
        assert_eq!(d.effect, "none", "{}", dir.display());
        assert_eq!(d.excluded_far_outside(), 0, "{:?}", d.excluded_by_load);
        let e = d
            .excluded_by_load
            .iter()
            .find(|e| e.load_n == 945.0)
            .unwrap();
        let margin = |top: f64| 3.0 * d.noise.model.scale(top) + 0.1 * top;
        let top = e.measured_range_um.1;
        assert!(
            top > e.predicted_range_um.1 + margin(e.predicted_range_um.1),
            "{e:?}"
        );
        assert!(
            top <= e.model_range_um.1 + margin(e.model_range_um.1),
            "{e:?}"
        );
    }
}

/// k(t) = 1 + 0.2 cos(Omega t): named, eps inside its 95% interval, held-out gap shrinks.
#[test]
fn hidden_mesh_stiffness_variation_is_named_and_sized() {
    let h = HiddenEffects {
        stiffness_eps: 0.2,
        ..HiddenEffects::default()
    };
    let d = discover_hidden(h, 7, MunroTruth::default_munro().ste_um);
    assert_named_with_truth_inside(&d, "mesh_stiffness_variation", 0.2);
    // M0 absorbs the stiffness variation with the least damping it may use (true zeta 0.0175),
    // and says so.
    assert!(d.m0_zeta_at_lower_bound(), "M0 zeta {}", d.zeta_m0);
    let (b, a) = held_out_rms(&d);
    assert!(a < 0.5 * b, "held-out RMS {b} -> {a}");
    assert!(d.gap_after.training.rms_um < 0.5 * d.gap_before.training.rms_um);
}

/// `discover` on k(t) = 1 + 0.1 cos(Omega t) (true psi 0) at `seed`: asserts the effect is
/// named with eps inside its interval and psi within 45 degrees of 0, and returns the named
/// candidate (its delta is present).
fn weak_stiffness_variation_found(seed: u64) -> CandidateResult {
    let h = HiddenEffects {
        stiffness_eps: 0.1,
        ..HiddenEffects::default()
    };
    let d = discover_hidden(h, seed, MunroTruth::default_munro().ste_um);
    assert_named_with_truth_inside(&d, "mesh_stiffness_variation", 0.1);
    let c = d
        .candidates
        .into_iter()
        .find(|c| c.name == d.effect)
        .unwrap();
    let delta = c.delta.as_ref().unwrap();
    let psi = delta[1].atan2(delta[0]);
    assert!(psi.abs() < std::f64::consts::FRAC_PI_4, "psi {psi} rad");
    c
}

/// Seed 4: the best dictionary probe is the smallest amplitude (0.05) at 240 degrees, and a
/// refit from there alone stopped at psi = pi with eps 0.08 and zeta absorbing the rest
/// (interval 0.066-0.093, missing the truth). The refit also runs from the opposite phase (of
/// the design-load fit) and keeps the better fit of all training loads. The other minimum, near
/// 180 degrees, is reported with it, and is close enough that the interval spans both.
#[test]
fn weak_mesh_stiffness_variation_refit_finds_the_true_phase() {
    let c = weak_stiffness_variation_found(4);
    // The opposite start ends at psi = pi, eps 0.079, only about 1 sigma^2 worse: the training
    // loads do not determine the phase, so the interval spans both fits.
    let o = c.other_start.as_ref().unwrap();
    let psi_o = o.delta[1].atan2(o.delta[0]);
    assert!(psi_o.abs() > 0.75 * std::f64::consts::PI, "{o:?}");
    assert!(o.phase_undetermined(c.delta.as_ref().unwrap()), "{o:?}");
    let (lo, hi) = c.ci95.unwrap();
    let (olo, ohi) = o.ci95.unwrap();
    assert!(lo <= olo && hi >= ohi, "{:?} vs {o:?}", c.ci95);
}

/// Seed 7, where the opposite phase must be taken after the design-load fit: flipping the probe
/// before it was not enough, the design load pulled both starts to psi = pi (eps 0.081, zeta
/// 0.011, interval 0.065-0.098, missing the truth), 7.6 sigma^2 above the true minimum. Now the
/// psi = pi minimum is reported as clearly worse (beyond chi2(0.95; 1)), so the interval is the
/// kept fit's own and not widened over both phases.
#[test]
fn weak_mesh_stiffness_variation_refit_leaves_the_wrong_basin() {
    let c = weak_stiffness_variation_found(7);
    let o = c.other_start.as_ref().unwrap();
    assert!(!o.phase_undetermined(c.delta.as_ref().unwrap()), "{o:?}");
    assert!(o.rss_increase > 3.84, "{o:?}");
}

/// A second STE harmonic at 40% of the first: named, ratio inside its 95% interval, training
/// gap down to the noise level; the held-out loads' STE amplitudes, fitted alone with the
/// effect, come back to their true values (1.5 and 3.5 um) within 5% (about two noise sigma of
/// the quasi-static pp at 945 N), and the held-out gap falls below twice the noise (0.15 um).
#[test]
fn hidden_second_ste_harmonic_is_named_and_sized() {
    let h = HiddenEffects {
        ste2_ratio: 0.4,
        ..HiddenEffects::default()
    };
    let d = discover_hidden(h, 3, MunroTruth::default_munro().ste_um);
    assert_named_with_truth_inside(&d, "ste_harmonics", 0.4);
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

/// The same seed on Munro's 50 rpm grid (the synth default). The design-load fit turned the r2
/// probe's phase from 0 to -37 degrees, and the all-load fit, which hardly moves a phase (the
/// pp jumps with it), ended at -37 and -177 degrees from there and from its opposite: 1871 and
/// 252 sigma^2 against 74.4 from a start at the truth, so the refit left a discrepancy and the
/// answer was "unexplained". The phase profile at the design-load fit starts it in the true
/// basin.
#[test]
fn second_ste_harmonic_on_the_50_rpm_grid_is_named_with_its_phase() {
    let tmp = tempfile::tempdir().unwrap();
    let h = HiddenEffects {
        ste2_ratio: 0.4,
        ..HiddenEffects::default()
    };
    make_set_on(tmp.path(), h, 3, MunroTruth::default_munro().ste_um, 50.0);
    let d = run(tmp.path());
    assert_named_with_truth_inside(&d, "ste_harmonics", 0.4);
    let c = d.candidates.iter().find(|c| c.name == d.effect).unwrap();
    let psi = Candidate::first_phase(c.delta.as_ref().unwrap());
    assert!(
        psi.to_degrees().abs() < 10.0,
        "phase {} deg",
        psi.to_degrees()
    );
    let (b, a) = held_out_rms(&d);
    assert!(a < 0.3 && a < b, "held-out RMS {b} -> {a}");
}

/// Damping that rises at light load, zeta (W / W_design)^-1, on a five-load set (training
/// 3780, 1890 and 945 N): on Munro's four loads the training curves (3780, 1890 N) do not
/// change by more than the noise, so the light load must be in the training set. Named, gamma
/// inside its 95% interval, held-out gap smaller.
#[test]
fn hidden_load_dependent_damping_is_named_and_sized() {
    let h = HiddenEffects {
        damping_exponent: -1.0,
        ..HiddenEffects::default()
    };
    let loads = vec![
        (3780.0, 0.3),
        (2835.0, 1.5),
        (1890.0, 2.5),
        (1418.0, 3.0),
        (945.0, 3.5),
    ];
    let d = discover_hidden(h, 2, loads);
    assert_eq!(d.training_loads_n, vec![3780.0, 1890.0, 945.0]);
    assert_named_with_truth_inside(&d, "damping_law", -1.0);
    let (b, a) = held_out_rms(&d);
    assert!(a < b, "held-out RMS {b} -> {a}");
}

/// A backlash smaller than stated, hidden in a rattle-regime set (light loads, STE 8-12 um,
/// true b 0.7 of the stated one): the data hammer both flanks (pp DTE to ~600 um) where M0 at
/// the stated b has no back-side contact at any kept training point.
/// - The guard asks whether b changes the fitted curves, not whether M0 reaches the back flank:
///   the probes (b x 0.61-0.78) bring it back. The old guard called b not identifiable here.
/// - The backlash has the largest dictionary LR but is not the leading candidate by score (the
///   local statistic), so it is refitted as the LR leader even with `refit_top` 1; its refit
///   explains the curves, and it is named with 0.7 inside its interval (about +-0.004) and the
///   held-out gap (tens of um) shrinking to the noise. Refitting by score alone never refitted
///   it (seed 1, default options: "unexplained", damping_law closest). The design-load stage
///   cannot see b (the teeth stay in contact) and leaves it out: left free, b followed the
///   forward model's last bits to b_stated e^-667 (and on seed 4 to e^37), where the exact
///   solver hung.
#[test]
fn backlash_hidden_in_a_rattle_regime_set_is_identifiable_named_and_sized() {
    let tmp = tempfile::tempdir().unwrap();
    rattle_backlash_set(tmp.path(), 2, 100.0);
    let opts = DiscoverOptions {
        bootstrap: 399,
        refit_top: 1,
        ..DiscoverOptions::default()
    };
    let d = run_with(tmp.path(), &opts);
    let b = d.candidates.iter().find(|c| c.name == "backlash").unwrap();
    assert!(b.identifiable, "{:?}", b.note);
    // 1 / (B + 1) is the smallest bootstrap p-value: nothing under M0 comes near this LR.
    assert!(b.p_value.unwrap() <= 1.0 / 400.0 + 1e-12, "{b:?}");
    assert!(d.detected);
    assert_named_with_truth_inside(&d, "backlash", 0.7);
    let (before, after) = held_out_rms(&d);
    assert!(after < 0.1 * before, "held-out RMS {before} -> {after}");
}

/// The same rattle-regime set where M0 settles far off (seed 16, Munro's 50 rpm grid: M0 zeta
/// 0.066 and omega_n 1821 Hz against a true 0.0175 and 1600 Hz). There the dictionary's best
/// backlash probe is b x 1.65, the wrong direction, and the refit used to start from it and
/// stay there (no back contact at 945 N, so b unseen: "unexplained"). Two repairs name it:
/// - the design load cannot see b, so the all-load stage starts from the best of a profile
///   over b at the design-load fit (sharp minimum at b x 0.70), not from the probe;
/// - a jump onto the back flank (single-sided impacts at 30 um to double-sided ones at
///   157 um, separated on both sides) counts as a jump of the contact regime, so the point
///   straddling it, 120 um off when the refit's jump came one speed early, is not compared.
#[test]
fn backlash_is_named_when_m0_settles_far_off_and_its_best_probe_points_the_wrong_way() {
    let tmp = tempfile::tempdir().unwrap();
    rattle_backlash_set(tmp.path(), 16, 50.0);
    let opts = DiscoverOptions {
        bootstrap: 399,
        ..DiscoverOptions::default()
    };
    let d = run_with(tmp.path(), &opts);
    // The precondition that makes this case: M0 far from the truth (zeta 0.0175).
    assert!(d.zeta_m0 > 0.04, "M0 zeta {}", d.zeta_m0);
    assert_named_with_truth_inside(&d, "backlash", 0.7);
    // Training and held-out loads at the noise (0.15 um) after, tens of um before.
    assert!(d.gap_after.training.rms_um < 0.3, "{:?}", d.gap_after);
    let (before, after) = held_out_rms(&d);
    assert!(
        after < 0.5 && after < 0.05 * before,
        "held-out RMS {before} -> {after}"
    );
}

/// A measuring-chain resonance at 2300 Hz (+50%) is nothing in the library: "unexplained".
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
        "399",
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
}
