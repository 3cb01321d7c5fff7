//! The validation pipeline on synthetic data with known truth: the design-load fit recovers zeta
//! and omega_n inside their reported 95% intervals, the reduced-load predictions match the truth's
//! own curves, and the command line writes fits/ and reports/ (and nothing on bad data).

mod common;
use common::geardyn;
use geardyn::data::{load_kubo, load_munro};
use geardyn::fit::ProfileInterval;
use geardyn::model::GearPair;
use geardyn::progress::NoProgress;
use geardyn::validate::{
    simulate_dte_curve, synth_kubo, synth_munro, validate_kubo, validate_munro, KuboFitPath,
    KuboOptions, KuboTruth, MunroOptions, MunroTruth,
};

/// The true zeta and omega_n lie inside the fit's 95% profile intervals.
fn assert_truth_inside(seed: u64, truth: [f64; 2], fitted: [f64; 2], ci: &[ProfileInterval]) {
    for (k, name) in ["zeta", "omega_n"].iter().enumerate() {
        assert!(
            ci[k].covers(truth[k]),
            "seed {seed}: {name} {} ci {:?}",
            fitted[k],
            ci[k]
        );
    }
}

/// Truth recovery over several noise seeds: the 95% profile interval must contain the truth in
/// each (a 95% interval misses with probability 0.05 per seed; the seeds are fixed, so this test is
/// deterministic and was checked to hold for them, and a systematic bias would fail it).
#[test]
fn fit_recovers_truth_and_predictions_match_truth_curves() {
    for seed in [1u64, 7, 42] {
        let dir = tempfile::tempdir().unwrap();
        let mut truth = MunroTruth::default_munro();
        truth.seed = seed;
        // Every STE stated as a measurement (a stated STE needs its uncertainty).
        truth.publish_ste = true;
        truth.ste_sd_um = Some(0.01);
        synth_munro(&truth, dir.path(), &NoProgress).unwrap();
        let data = load_munro(dir.path()).unwrap();
        let opts = MunroOptions {
            attractor_speeds: 3,
            ..MunroOptions::default()
        };
        let r = validate_munro(&data, &opts, &NoProgress).unwrap();
        assert_truth_inside(
            seed,
            [truth.zeta, truth.omega_n_hz],
            [r.zeta, r.omega_n_hz],
            &r.fit.ci95_profile,
        );
        let (c0, c1) = (r.fit.estimate.ci95[0], r.fit.estimate.ci95[1]);
        assert!(
            c0.0 <= truth.zeta && truth.zeta <= c0.1,
            "seed {seed}: covariance interval {c0:?}"
        );
        assert!(
            c1.0 <= truth.omega_n_hz && truth.omega_n_hz <= c1.1,
            "seed {seed}: covariance interval {c1:?}"
        );
        // Reduced loads with F_hat >= 2.8 (3/4 and 1/2 of design): the model's up-branch follows
        // the truth's noise-free curve to within the noise level (0.15 um) in RMS. At 1/4 load
        // the response is subharmonic/chaotic above ~4200 rpm, where no point-wise agreement can
        // be expected, so it is compared below that speed only.
        let dim = data.rig.rig.dimensional().unwrap();
        for l in r.loads.iter().filter(|l| !l.fitted) {
            let ste = truth
                .ste_um
                .iter()
                .find(|x| (x.0 - l.load_n).abs() < 1e-6)
                .unwrap()
                .1;
            let model = GearPair::paper(
                dim.mean_force(l.load_n),
                dim.ste_amplitude(ste),
                truth.zeta,
                1.0,
            )
            .unwrap();
            let speeds: Vec<f64> = l
                .measured
                .iter()
                .map(|m| m.0)
                .filter(|&s| l.force_ratio > 2.0 || s < 4100.0)
                .collect();
            let clean =
                simulate_dte_curve(&dim, &model, truth.omega_n_hz, &speeds, &NoProgress).unwrap();
            let diffs: Vec<f64> = speeds
                .iter()
                .zip(&clean)
                .map(|(s, c)| {
                    l.up.iter()
                        .find(|p| (p.speed_rpm - s).abs() < 1e-6)
                        .unwrap()
                        .dte_pp_um
                        - c
                })
                .collect();
            let rms = geardyn::validate::rms(&diffs);
            assert!(
                rms < 0.15,
                "seed {seed}, {} N: RMS to truth {rms} um",
                l.load_n
            );
        }
    }
}

/// A design load whose teeth separate over the resonance (F_hat 4.7: STE 3 um at 3780 N,
/// zeta 0.03, 1500 Hz), on sets made by DOP853 (not the fit's exact solver) with relative
/// noise: eq. 13's closed form would separate the teeth, so the design-load curve is fitted
/// through simulated up-sweeps, and both 95% intervals hold the truth. (The closed form alone
/// had fitted zeta 0.0683 [0.0652, 0.0715] on seed 7.) At zeta 0.0175 the same curve does not
/// determine the damping (the peak is set by the backlash) and the fit of seed 1 runs to the
/// least damping the sweeps take: it is refused, not reported.
#[test]
#[ignore = "about 26 s, too slow for the default run: .ci/run runs it (cargo test --release --test validate_pipeline -- --ignored)"]
fn a_design_load_that_separates_is_fitted_through_simulated_sweeps() {
    use geardyn::validate::{DesignModel, NoiseFamily};
    let set = |seed: u64, zeta: f64, omega_n_hz: f64, loads: Vec<(f64, f64)>| {
        let dir = tempfile::tempdir().unwrap();
        let mut truth = MunroTruth::default_munro();
        truth.seed = seed;
        truth.zeta = zeta;
        truth.omega_n_hz = omega_n_hz;
        truth.ste_um = loads;
        truth.noise = NoiseFamily::Relative.noise(0.15);
        truth.dop853_rtol = Some(1e-9);
        synth_munro(&truth, dir.path(), &NoProgress).unwrap();
        dir
    };
    let opts = MunroOptions {
        attractor_speeds: 2,
        ..MunroOptions::default()
    };
    for seed in [7u64, 11] {
        let dir = set(seed, 0.03, 1500.0, vec![(3780.0, 3.0), (1890.0, 3.5)]);
        let data = load_munro(dir.path()).unwrap();
        let r = validate_munro(&data, &opts, &NoProgress).unwrap();
        assert_eq!(r.fit.design_model, DesignModel::Swept, "seed {seed}");
        let ci = &r.fit.estimate.ci95;
        assert!(
            ci[0].0 <= 0.03 && 0.03 <= ci[0].1,
            "seed {seed}: zeta {} {:?}",
            r.zeta,
            ci[0]
        );
        assert!(
            ci[1].0 <= 1500.0 && 1500.0 <= ci[1].1,
            "seed {seed}: omega_n {} {:?}",
            r.omega_n_hz,
            ci[1]
        );
        assert_truth_inside(
            seed,
            [0.03, 1500.0],
            [r.zeta, r.omega_n_hz],
            &r.fit.ci95_profile,
        );
    }
    let loads = vec![(3780.0, 3.0), (2835.0, 1.5), (1890.0, 2.5), (945.0, 3.5)];
    let dir = set(1, 0.0175, 1600.0, loads);
    let data = load_munro(dir.path()).unwrap();
    match validate_munro(&data, &opts, &NoProgress) {
        Err(geardyn::error::GearError::FitFailed { reason, .. }) => {
            assert!(reason.contains("zeta"), "{reason}")
        }
        other => panic!("expected a refused fit, got {:?}", other.map(|r| r.zeta)),
    }
}

/// A light load (500 N, STE 3.5 um, 0.1 um noise, model-exact) whose curve jumps at 1800-1850
/// rpm and turns chaotic from 2700 rpm: the measured curve's first jump is found, not the
/// chaos's scatter, and the model's first jump lies within the grids' resolution of it.
#[test]
fn the_first_jump_at_a_light_load_is_compared_not_the_chaos_after_it() {
    use geardyn::validate::NoiseFamily;
    let dir = tempfile::tempdir().unwrap();
    let mut truth = MunroTruth::default_munro();
    truth.ste_um = vec![(3780.0, 0.3), (1890.0, 2.5), (500.0, 3.5)];
    truth.noise = NoiseFamily::Constant.noise(0.1);
    synth_munro(&truth, dir.path(), &NoProgress).unwrap();
    let data = load_munro(dir.path()).unwrap();
    let opts = MunroOptions {
        attractor_speeds: 2,
        ..MunroOptions::default()
    };
    let r = validate_munro(&data, &opts, &NoProgress).unwrap();
    let light = r.loads.iter().find(|l| l.load_n == 500.0).unwrap();
    let measured = light.jump_measured_rpm.unwrap();
    assert!((1800.0..=1850.0).contains(&measured), "{measured}");
    let (e, res) = (
        light.jump_error_rpm.unwrap(),
        light.jump_error_resolution_rpm.unwrap(),
    );
    assert!(e.abs() <= res, "jump error {e} beyond the resolution {res}");
}

/// The predictions' attractor searches on `data/munro`: at 945 N some of the grid's
/// trajectories end on chaotic sets at 4330 and 4500 rpm (Omega 1.44, 1.5) that all of them
/// leave within the horizon (chaotic transients): those are not drawn as steady states, so
/// every all-attractor point holds part of the grid. And the measurement-scale horizon (10,000
/// periods) finds the same attractors as `geardyn attractors`' 40,000 (the chaotic sets at
/// 4670-5000 rpm keep every trajectory for both); a chaotic set that still holds a few
/// trajectories at 10,000 periods is shown labelled as a transient (at 4333 rpm, whether it
/// does turns on the fit's last digits).
#[test]
#[ignore = "about 18 s, too slow for the default run: .ci/run runs it (cargo test --release --test validate_pipeline -- --ignored)"]
fn munro_predictions_show_only_sets_that_hold_trajectories() {
    let data = load_munro(std::path::Path::new("data/munro")).unwrap();
    let short = validate_munro(&data, &MunroOptions::default(), &NoProgress).unwrap();
    let long_opts = MunroOptions {
        escape: geardyn::sim::EscapeBudget::default(),
        ..MunroOptions::default()
    };
    assert_eq!(long_opts.escape.horizon, 40_000);
    let long = validate_munro(&data, &long_opts, &NoProgress).unwrap();
    let (mut chaotic, mut transients) = (0, 0);
    for (s, l) in short.loads.iter().zip(&long.loads) {
        assert!(!s.all.is_empty(), "{} N: no attractor", s.load_n);
        for p in &s.all {
            assert!(
                p.basin_fraction.is_some_and(|f| f > 0.0),
                "{} N, {} rpm: a set no trajectory is on",
                s.load_n,
                p.speed_rpm
            );
            // A set that still held trajectories at the short horizon is shown as such (a
            // chaotic transient, labelled), never as an attractor the long search would drop.
            assert!(
                matches!(
                    p.kind,
                    Some(geardyn::sim::SetKind::Attractor)
                        | Some(geardyn::sim::SetKind::ChaoticTransient)
                ),
                "{:?}",
                p.kind
            );
            transients += usize::from(!p.on_attractor());
            chaotic += usize::from(p.period.is_none());
        }
        let key = |l: &geardyn::validate::LoadResult| {
            l.all
                .iter()
                .filter(|p| p.on_attractor())
                .map(|p| (p.speed_rpm, p.dte_pp_um, p.period))
                .collect::<Vec<_>>()
        };
        assert_eq!(key(s), key(l), "{} N", s.load_n);
    }
    // The chaotic attractors at 945 N: the test is about them. A chaotic set near its
    // boundary may empty between the two horizons (at 945 N, 4333 rpm, 2 of 49 trajectories
    // held at 10,000 periods and none at 40,000): at most one, labelled a transient.
    assert!(chaotic >= 3, "{chaotic} chaotic attractors");
    assert!(transients <= 1, "{transients} transients shown");
}

/// Kubo: zeta and omega_n fitted to the contact part of a synthetic envelope (8 tooth pairs, 4%
/// scatter) recover the truth inside the 95% profile intervals over fixed seeds, and the
/// estimates are not biased: the mean zeta over the seeds is within 10% of the truth (its
/// standard error over 4 seeds is ~0.01/2 = 5%; selecting the points on the measured D_L instead
/// of the model biased it by +15%, 0.113-0.142, which this fails).
#[test]
fn kubo_fit_recovers_truth_without_selection_bias() {
    let mut zetas = Vec::new();
    for seed in [2u64, 3, 4, 5] {
        let dir = tempfile::tempdir().unwrap();
        let mut truth = KuboTruth::default_kubo();
        truth.seed = seed;
        synth_kubo(&truth, dir.path(), &NoProgress).unwrap();
        let data = load_kubo(dir.path()).unwrap();
        let r = validate_kubo(&data, &KuboOptions::default(), &NoProgress).unwrap();
        assert_truth_inside(
            seed,
            [truth.zeta, truth.omega_n_hz],
            [r.zeta, r.omega_n_hz],
            &r.ci95_profile,
        );
        zetas.push(r.zeta);
    }
    let mean = zetas.iter().sum::<f64>() / zetas.len() as f64;
    let truth = KuboTruth::default_kubo().zeta;
    assert!(
        (mean / truth - 1.0).abs() < 0.1,
        "mean zeta {mean} vs {truth}: {zetas:?}"
    );
}

/// Kubo with the test load's STE stated with an uncertainty (`[ste] sd_um`): the stated value
/// is weighed against the envelope as a measurement (Theil & Goldberger's mixed estimation), so
/// the STE's standard error falls below both the stated 0.02 um and the curve's own; a stated
/// value 30% off is fitted and said to disagree (|compatibility z| above 1.96), not absorbed;
/// `--hold-ste` with a stated uncertainty is refused (holding it exact throws the uncertainty
/// away).
#[test]
fn kubo_stated_ste_with_uncertainty_is_weighed_and_a_wrong_one_is_named() {
    let truth = KuboTruth::default_kubo();
    let dir = tempfile::tempdir().unwrap();
    synth_kubo(&truth, dir.path(), &NoProgress).unwrap();
    let rig = std::fs::read_to_string(dir.path().join("rig.toml")).unwrap();
    let stated = |amplitude: f64| -> String {
        rig.lines()
            .map(|l| {
                if l.starts_with("amplitude_um") {
                    format!("amplitude_um = [{amplitude}]\nsd_um = 0.02")
                } else {
                    l.to_string()
                }
            })
            .collect::<Vec<_>>()
            .join("\n")
    };
    let free = validate_kubo(
        &load_kubo(dir.path()).unwrap(),
        &KuboOptions::default(),
        &NoProgress,
    )
    .unwrap();
    let se_of = |r: &geardyn::validate::KuboValidation| {
        let f = r.fit.as_ref().unwrap();
        f.std_errors[f.names.iter().position(|n| n == "ste_um").unwrap()]
    };
    std::fs::write(dir.path().join("rig.toml"), stated(truth.ste_um)).unwrap();
    let data = load_kubo(dir.path()).unwrap();
    let r = validate_kubo(&data, &KuboOptions::default(), &NoProgress).unwrap();
    let m = &r.fit.as_ref().unwrap().measurements;
    assert_eq!(m.len(), 1, "{m:?}");
    assert!(m[0].compatibility_z.unwrap().abs() < 1.96, "{m:?}");
    // Two independent measurements of one value: 1/se^2 adds up, to first order.
    let combined = 1.0 / (1.0 / se_of(&free).powi(2) + 1.0 / 0.02_f64.powi(2)).sqrt();
    assert!(
        (se_of(&r) / combined - 1.0).abs() < 0.1,
        "se {} against {combined} (free {})",
        se_of(&r),
        se_of(&free)
    );
    assert!(r.ste_source.contains("weighed in"), "{}", r.ste_source);
    let held = KuboOptions {
        hold_ste: true,
        ..KuboOptions::default()
    };
    let err = validate_kubo(&data, &held, &NoProgress)
        .unwrap_err()
        .to_string();
    assert!(err.contains("sd_um") && err.contains("--hold-ste"), "{err}");

    std::fs::write(dir.path().join("rig.toml"), stated(1.3 * truth.ste_um)).unwrap();
    let r = validate_kubo(
        &load_kubo(dir.path()).unwrap(),
        &KuboOptions::default(),
        &NoProgress,
    )
    .unwrap();
    let fit = r.fit.as_ref().unwrap();
    let text = geardyn::report::stated_ste_text(&fit.measurements, |_| "2000 N".into()).unwrap();
    assert!(
        text.contains("WARNING") && text.contains("disagrees"),
        "{text}"
    );
}

/// Kubo on a lightly damped rig (zeta 0.06, 2200 Hz; envelopes made by DOP853, not the fit's
/// exact solver): the teeth separate over the whole resonance, so the contact part of the curve
/// does not determine zeta, and the fit takes the whole curve through simulated up-sweeps.
/// On each seed the fit is usable and within 4 standard errors of the truth (a wrong model of
/// the separated peak, e.g. the linear one, misses zeta by far more), and the whole-curve path
/// is taken at least once (before it, these sets were refused).
#[test]
#[ignore = "about 23 s, too slow for the default run: .ci/run runs it (cargo test --release --test validate_pipeline -- --ignored)"]
fn kubo_fit_takes_the_whole_curve_when_the_teeth_separate() {
    let mut whole = 0;
    for seed in [1u64, 2, 3] {
        let dir = tempfile::tempdir().unwrap();
        let truth = KuboTruth {
            zeta: 0.06,
            omega_n_hz: 2200.0,
            seed,
            dop853_rtol: Some(1e-9),
            ..KuboTruth::default_kubo()
        };
        synth_kubo(&truth, dir.path(), &NoProgress).unwrap();
        let data = load_kubo(dir.path()).unwrap();
        let r = validate_kubo(&data, &KuboOptions::default(), &NoProgress).unwrap();
        let fit = r.fit.as_ref().unwrap();
        for (i, t) in [truth.zeta, truth.omega_n_hz].into_iter().enumerate() {
            let z = (fit.params[i] - t) / fit.std_errors[i];
            assert!(z.abs() < 4.0, "seed {seed}, {}: z = {z}", fit.names[i]);
        }
        whole += usize::from(r.parameter_source.contains("whole curve"));
    }
    assert!(whole >= 1, "no seed needed the whole curve");
}

/// A rig whose teeth separate at nearly every measured speed (zeta 0.05, an STE of 8 um at
/// 2000 N, speeds from Omega 0.76 up): too few points have D_L < 1.8 for the contact part to be fitted at all, which
/// ended the run before the whole-curve fit existed ("only N points ... give zeta"); now the
/// whole curve is fitted, within 4 standard errors of the truth, the model inside the
/// envelope at over 90% of the speeds. Every start about the measured peak (the separated
/// branch grows to 8700 rpm) ended at zeta 0.33-0.36, 1180-1320 Hz, inside at 13-18% (with
/// standard errors wide enough to pass the first check); the starts screened on a coarse grid
/// reach the truth. The stated STE is fitted with zeta and omega_n. The two-pair model's fit
/// is refused here and the one-pair fit follows (zeta 0.0569 +- 0.0041). About 100 s on 2
/// cores (182 s before the Jacobian columns started from the base point's orbits, 5.6 minutes
/// before the profiles stopped at zeta's floor and at a better fit and stopped profiling a
/// refused fit), too long for `cargo test`'s budget: `.ci/run` runs it (`cargo test
/// --release --test validate_pipeline -- --ignored`).
#[test]
#[ignore = "about 100 s: .ci/run runs it (cargo test --release --test validate_pipeline -- --ignored)"]
fn kubo_curve_without_a_contact_part_is_fitted_whole() {
    let dir = tempfile::tempdir().unwrap();
    let truth = KuboTruth {
        zeta: 0.05,
        omega_n_hz: 2200.0,
        ste_um: 8.0,
        speeds_rpm: (4000.0, 10000.0, 100.0),
        seed: 5,
        ..KuboTruth::default_kubo()
    };
    synth_kubo(&truth, dir.path(), &NoProgress).unwrap();
    let data = load_kubo(dir.path()).unwrap();
    let contact = data
        .points
        .iter()
        .filter(|p| p.dynamic_factor_max < geardyn::validate::KUBO_CONTACT_LIMIT)
        .count();
    assert!(
        contact < 5,
        "the set must leave too few contact points: {contact}"
    );
    let r = validate_kubo(&data, &KuboOptions::default(), &NoProgress).unwrap();
    assert!(
        r.parameter_source.contains("whole curve"),
        "{}",
        r.parameter_source
    );
    let fit = r.fit.as_ref().unwrap();
    assert!(r.inside_fraction > 0.9, "inside {}", r.inside_fraction);
    for (i, t) in [truth.zeta, truth.omega_n_hz].into_iter().enumerate() {
        let z = (fit.params[i] - t) / fit.std_errors[i];
        assert!(z.abs() < 4.0, "{}: z = {z}", fit.names[i]);
    }
}

/// An envelope of 4 tooth pairs with 8% scatter (seed 140) on which the first contact fit runs
/// zeta to about 3e60: the point selection that follows asked the describing function for that
/// zeta and the run ended on "invalid parameter zeta". Such a fit selects nothing; the whole
/// curve is fitted instead, and its interval holds the truth.
#[test]
fn kubo_contact_fit_that_runs_away_falls_back_to_the_whole_curve() {
    let dir = tempfile::tempdir().unwrap();
    let truth = KuboTruth {
        seed: 140,
        tooth_pairs: 4,
        pair_scatter: 0.08,
        dop853_rtol: Some(1e-7),
        ..KuboTruth::default_kubo()
    };
    synth_kubo(&truth, dir.path(), &NoProgress).unwrap();
    let data = load_kubo(dir.path()).unwrap();
    let r = validate_kubo(&data, &KuboOptions::default(), &NoProgress).unwrap();
    assert!(
        r.parameter_source.contains("whole curve"),
        "{}",
        r.parameter_source
    );
    let (lo, hi) = r.ci95_profile[0].ends();
    assert!(
        lo.unwrap() < truth.zeta && truth.zeta < hi.unwrap(),
        "zeta {} [{lo:?}, {hi:?}]",
        r.zeta
    );
}

/// An envelope of 4 tooth pairs with 8% scatter (seed 15) whose first contact fit, on the
/// points with measured D_L < 1.8, runs zeta towards 0 (1e-12): the model's own point
/// selection at that zeta, refitted, recovers (zeta 0.115, truth 0.1 inside its interval). A
/// guard that stopped the selection at any zeta outside the plausible range sent 17 such sets
/// of 200 to the whole curve, which this test fails.
#[test]
fn kubo_first_contact_fit_towards_zero_damping_recovers_by_the_selection() {
    let dir = tempfile::tempdir().unwrap();
    let truth = KuboTruth {
        seed: 15,
        tooth_pairs: 4,
        pair_scatter: 0.08,
        dop853_rtol: Some(1e-7),
        ..KuboTruth::default_kubo()
    };
    synth_kubo(&truth, dir.path(), &NoProgress).unwrap();
    let data = load_kubo(dir.path()).unwrap();
    let opts = KuboOptions {
        fit_path: KuboFitPath::ContactPart,
        ..KuboOptions::default()
    };
    let r = validate_kubo(&data, &opts, &NoProgress).unwrap();
    let (lo, hi) = r.ci95_profile[0].ends();
    assert!(
        lo.unwrap() < truth.zeta && truth.zeta < hi.unwrap(),
        "zeta {} [{lo:?}, {hi:?}]",
        r.zeta
    );
}

/// `--fit whole` fits the whole curve where the contact part alone would do (the default
/// envelope, 8 pairs, 4%, seed 2): the peak it adds determines zeta several times better (the
/// standard error 0.0017 against 0.013 here; asserted: at least 3x) and omega_n better (4.6
/// against 11.2 Hz; asserted: 1.5x), the two estimates agree
/// within their contact-fit standard errors, and the truth is within 4 standard errors of the
/// whole-curve fit. `--fit contact` on a lightly damped set whose contact part does not
/// determine zeta with the STE held (`--hold-ste`) is refused with a hint to fit the whole
/// curve, not silently switched.
#[test]
#[ignore = "about 17 s, too slow for the default run: .ci/run runs it (cargo test --release --test validate_pipeline -- --ignored)"]
fn kubo_fit_path_is_the_one_asked_for() {
    let dir = tempfile::tempdir().unwrap();
    let truth = KuboTruth {
        seed: 2,
        ..KuboTruth::default_kubo()
    };
    synth_kubo(&truth, dir.path(), &NoProgress).unwrap();
    let data = load_kubo(dir.path()).unwrap();
    let run = |fit_path| {
        let opts = KuboOptions {
            fit_path,
            ..KuboOptions::default()
        };
        validate_kubo(&data, &opts, &NoProgress)
    };
    let contact = run(KuboFitPath::ContactPart).unwrap();
    let whole = run(KuboFitPath::WholeCurve).unwrap();
    assert!(contact.parameter_source.contains("contact part"));
    // The pairs' spread is fitted at about zero here, where the curve does not depend on it
    // (even in h): the one-pair model, nested at h = 0, is what is fitted.
    assert!(
        whole
            .parameter_source
            .starts_with("fitted to the whole curve by simulated up-sweeps"),
        "{}",
        whole.parameter_source
    );
    let (c, w) = (contact.fit.unwrap(), whole.fit.unwrap());
    for (i, gain) in [(0, 3.0), (1, 1.5)] {
        assert!(
            w.std_errors[i] * gain < c.std_errors[i],
            "{}: whole SE {} vs contact {}",
            c.names[i],
            w.std_errors[i],
            c.std_errors[i]
        );
        assert!(
            (w.params[i] - c.params[i]).abs() < c.std_errors[i],
            "{}: whole {} vs contact {} +- {}",
            c.names[i],
            w.params[i],
            c.params[i],
            c.std_errors[i]
        );
        let t = [truth.zeta, truth.omega_n_hz][i];
        let z = (w.params[i] - t) / w.std_errors[i];
        assert!(z.abs() < 4.0, "{}: z = {z}", w.names[i]);
    }

    let light = tempfile::tempdir().unwrap();
    let truth = KuboTruth {
        zeta: 0.06,
        omega_n_hz: 2200.0,
        seed: 3,
        dop853_rtol: Some(1e-9),
        ..KuboTruth::default_kubo()
    };
    synth_kubo(&truth, light.path(), &NoProgress).unwrap();
    let data = load_kubo(light.path()).unwrap();
    let opts = KuboOptions {
        fit_path: KuboFitPath::ContactPart,
        hold_ste: true,
        ..KuboOptions::default()
    };
    let e = validate_kubo(&data, &opts, &NoProgress).unwrap_err();
    assert!(e.to_string().contains("--fit whole"), "{e}");
}

/// The shipped data set runs end to end through the CLI and writes the artifacts; every image
/// the HTML report references exists and is a PNG.
#[test]
fn cli_validate_writes_fits_and_reports() {
    let tmp = tempfile::tempdir().unwrap();
    let (fits, reports) = (tmp.path().join("fits"), tmp.path().join("reports"));
    for which in ["munro", "kubo"] {
        let out = geardyn(&[
            "validate",
            which,
            "--data",
            &format!("{}/data/{which}", env!("CARGO_MANIFEST_DIR")),
            "--fits",
            fits.to_str().unwrap(),
            "--reports",
            reports.to_str().unwrap(),
        ]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let stdout = String::from_utf8_lossy(&out.stdout);
        assert!(
            stdout.lines().next().unwrap().contains("SYNTHETIC"),
            "first line must state the data kind"
        );
        let json: serde_json::Value = serde_json::from_str(
            &std::fs::read_to_string(fits.join(format!("{which}.json"))).unwrap(),
        )
        .unwrap();
        for key in [
            "zeta",
            "omega_n_hz",
            "zeta_ci95",
            "omega_n_hz_ci95",
            "data_kind",
            "per_load",
            "provenance",
        ] {
            assert!(!json[key].is_null(), "{which}.json lacks {key}");
        }
        assert_eq!(json["data_kind"], "synthetic");
        if which == "munro" {
            // The shipped set (noise 0.15 um): where the model is period-1 every load is at the
            // noise, 1/4 load included; its chaotic and subharmonic speeds are counted apart.
            for l in json["per_load"].as_array().unwrap() {
                let rms = l["rms_period1_um"].as_f64().unwrap();
                assert!(rms < 0.2, "{l}");
                let apart = l["not_period1_points"].as_u64().unwrap();
                assert_eq!(apart > 0, l["load_n"] == 945.0, "{l}");
            }
        }
        let html = std::fs::read_to_string(reports.join(which).join("index.html")).unwrap();
        assert!(html.contains("SYNTHETIC DATA"));
        let mut images = 0;
        for part in html.split("<img src=\"").skip(1) {
            let name = &part[..part.find('"').unwrap()];
            let bytes = std::fs::read(reports.join(which).join(name)).unwrap();
            assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "{name}");
            let svg = reports.join(which).join(name.replace(".png", ".svg"));
            assert!(svg.exists(), "{} missing", svg.display());
            images += 1;
        }
        assert!(images >= 1);
    }
}

/// Bad data: one clear error naming file, line and field; non-zero exit; nothing written.
#[test]
fn cli_validate_bad_data_writes_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    let data = tmp.path().join("bad");
    std::fs::create_dir_all(&data).unwrap();
    std::fs::copy(
        format!("{}/data/munro/rig.toml", env!("CARGO_MANIFEST_DIR")),
        data.join("rig.toml"),
    )
    .unwrap();
    std::fs::write(
        data.join("dte.csv"),
        "load_n,speed_rpm,dte_pp_um\n3780,1000,0.7\n3780,abc,0.8\n",
    )
    .unwrap();
    let (fits, reports) = (tmp.path().join("fits"), tmp.path().join("reports"));
    let out = geardyn(&[
        "validate",
        "munro",
        "--data",
        data.to_str().unwrap(),
        "--fits",
        fits.to_str().unwrap(),
        "--reports",
        reports.to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        err.contains("dte.csv") && err.contains(":3") && err.contains("speed_rpm"),
        "{err}"
    );
    assert!(!err.contains("panicked"));
    assert!(
        !fits.exists() && !reports.exists(),
        "partial output written"
    );
}

/// The errors' correlation along speed through the command line (docs/correlated-errors.md):
/// the shipped set, whose errors were drawn independently, keeps independent errors under
/// the default `auto` (its likelihood ratio 1.1 lies below 2.71) and munro.json gives each
/// curve's diagnostic; `--correlation on` estimates a length and reports its interval; a length
/// stated in rig.toml beside `--correlation` is refused, naming the key, and nothing is written.
#[test]
fn cli_validate_reports_the_errors_correlation_along_speed() {
    let tmp = tempfile::tempdir().unwrap();
    let shipped = format!("{}/data/munro", env!("CARGO_MANIFEST_DIR"));
    let run = |data: &str, extra: &[&str], tag: &str| {
        let fits = tmp.path().join(format!("fits-{tag}"));
        let reports = tmp.path().join(format!("reports-{tag}"));
        let mut args = vec![
            "validate",
            "munro",
            "--data",
            data,
            "--fits",
            fits.to_str().unwrap(),
            "--reports",
            reports.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        let out = geardyn(&args);
        let json = std::fs::read_to_string(fits.join("munro.json"))
            .ok()
            .map(|t| serde_json::from_str::<serde_json::Value>(&t).unwrap());
        (out, json, fits)
    };
    let (out, json, _) = run(&shipped, &[], "auto");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let c = &json.unwrap()["noise"]["correlation"];
    assert_eq!(c["source"], "independent_by_test", "{c}");
    assert_eq!(c["length_rpm"], 0.0);
    assert!(c["lr_vs_independent"].as_f64().unwrap() < 2.71);
    assert_eq!(c["curves"].as_array().unwrap().len(), 4);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        stdout.contains("Errors independent along speed"),
        "{stdout}"
    );

    let (out, json, _) = run(&shipped, &["--correlation", "on"], "on");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let c = &json.unwrap()["noise"]["correlation"];
    assert_eq!(c["source"], "estimated", "{c}");
    assert!(c["length_ci95"].is_array(), "{c}");

    let data = tmp.path().join("stated");
    std::fs::create_dir_all(&data).unwrap();
    std::fs::copy(format!("{shipped}/dte.csv"), data.join("dte.csv")).unwrap();
    let rig = std::fs::read_to_string(format!("{shipped}/rig.toml")).unwrap();
    std::fs::write(
        data.join("rig.toml"),
        rig.replace(
            "[source]\n",
            "[noise]\ncorrelation_rpm = 80.0\n\n[source]\n",
        ),
    )
    .unwrap();
    let (out, json, fits) = run(data.to_str().unwrap(), &["--correlation", "off"], "both");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        err.contains("correlation_rpm") && err.contains("state it once"),
        "{err}"
    );
    assert!(json.is_none() && !fits.exists());
}

/// A copy of `data/munro` whose rig.toml states each load's STE with an uncertainty of 0.05 um:
/// `amplitudes` (um) at 3780, 2835, 1890 and 945 N.
fn munro_with_stated_ste(dir: &std::path::Path, amplitudes: [f64; 4]) {
    let src = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("data/munro");
    std::fs::copy(src.join("dte.csv"), dir.join("dte.csv")).unwrap();
    let rig = std::fs::read_to_string(src.join("rig.toml")).unwrap();
    let table = format!(
        "[ste]\nload_n = [3780.0, 2835.0, 1890.0, 945.0]\namplitude_um = {amplitudes:?}\nsd_um = 0.05\n\n[source]\n"
    );
    std::fs::write(dir.join("rig.toml"), rig.replacen("[source]\n", &table, 1)).unwrap();
}

/// STEs stated with their uncertainty (rig.toml `[ste] sd_um`) are measurements the fit weighs
/// against the curves: stated at the set's truth (0.3, 1.5, 2.5, 3.5 um), each load's fitted
/// STE stays within 2 sd of it, the compatibility z of each lies within +-1.96 and munro.json
/// lists them; one stated 30% off (1.75 um at 1890 N, where the curves alone give 2.53 +- 0.014
/// um) is refused at `[ste] amplitude_um`, the disagreeing load named with its z, and nothing is
/// written.
#[test]
fn stated_ste_with_uncertainty_is_weighed_and_a_wrong_one_is_named() {
    let tmp = tempfile::tempdir().unwrap();
    let (data, out) = (tmp.path().join("set"), tmp.path().join("out"));
    std::fs::create_dir_all(&data).unwrap();
    munro_with_stated_ste(&data, [0.3, 1.5, 2.5, 3.5]);
    let args = |d: &std::path::Path, o: &std::path::Path| {
        let (fits, reports) = (o.join("fits"), o.join("reports"));
        geardyn(&[
            "validate",
            "munro",
            "--data",
            d.to_str().unwrap(),
            "--fits",
            fits.to_str().unwrap(),
            "--reports",
            reports.to_str().unwrap(),
        ])
    };
    let o = args(&data, &out);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        stdout.contains("agree within their uncertainties"),
        "{stdout}"
    );
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("fits/munro.json")).unwrap())
            .unwrap();
    let stated = json["stated_ste"].as_array().unwrap();
    assert_eq!(stated.len(), 4, "{stated:?}");
    for s in stated {
        let (v, f) = (
            s["stated_um"].as_f64().unwrap(),
            s["fitted_um"].as_f64().unwrap(),
        );
        assert!((v - f).abs() < 0.1, "{s}");
        assert!(s["compatibility_z"].as_f64().unwrap().abs() < 1.96, "{s}");
    }
    let per_load = json["per_load"].as_array().unwrap();
    assert!(
        per_load.iter().all(|l| l["ste_source"] == "measured"),
        "{per_load:?}"
    );

    let (wrong, wrong_out) = (tmp.path().join("wrong"), tmp.path().join("wrong-out"));
    std::fs::create_dir_all(&wrong).unwrap();
    munro_with_stated_ste(&wrong, [0.3, 1.5, 1.75, 3.5]);
    let o = args(&wrong, &wrong_out);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("rig.toml") && err.contains("ste.amplitude_um"),
        "{err}"
    );
    assert!(
        err.contains("1890 N: stated 1.75") && err.contains("disagree"),
        "{err}"
    );
    assert_eq!(
        err.matches("disagree,").count() + err.matches(", disagree)").count(),
        1,
        "{err}"
    );
    assert!(
        !wrong_out.exists(),
        "partial output in {}",
        wrong_out.display()
    );

    // An uncertainty list of another length than the loads': located, nothing written.
    let rig = std::fs::read_to_string(wrong.join("rig.toml")).unwrap();
    std::fs::write(
        wrong.join("rig.toml"),
        rig.replace("sd_um = 0.05", "sd_um = [0.05, 0.05]"),
    )
    .unwrap();
    let o = args(&wrong, &wrong_out);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("ste.sd_um") && err.contains("2 uncertainties for 4 loads"),
        "{err}"
    );
    assert!(!wrong_out.exists());
}
