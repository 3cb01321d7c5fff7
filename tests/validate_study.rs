//! Calibrated intervals on data the fit did not make (a seeded subset of the `validate-study`
//! runs in docs/calibrated-inference.md): design-load curves made by DOP853, not by the fit's
//! closed form, with measurement noise whose scatter grows with the level (3% plus a 0.15 um
//! floor). An unweighted fit with one estimated sigma covered the truth in about half the
//! sets; the noise model estimated jointly with the fit must cover it at close to 95%.

use geardyn::progress::NoProgress;
use geardyn::validate::{run_validate_study, NoiseFamily, ValidateStudyOptions};

/// 40 seeds: with a true coverage of 95% the count is below 34 with probability 0.5%; the
/// old fit (coverage 44-48%) would give about 19.
#[test]
fn intervals_cover_the_truth_under_level_dependent_noise_from_another_integrator() {
    let dir = tempfile::tempdir().unwrap();
    let opts = ValidateStudyOptions {
        seeds: 40,
        noise: NoiseFamily::Relative.noise(0.15),
        ..ValidateStudyOptions::default()
    };
    assert_eq!(opts.dop853_rtol, Some(1e-9), "the sets come from DOP853");
    let s = run_validate_study(&opts, dir.path(), &NoProgress, &mut |_| Ok(())).unwrap();
    assert_eq!(
        s.coverage.len(),
        6,
        "zeta, omega_n, design STE, three other loads' STE"
    );
    for c in &s.coverage {
        assert!(
            c.fisher.0 >= 34,
            "{}: {}/40 inside the 95% interval",
            c.name,
            c.fisher.0
        );
    }
    // The reported standard errors match the spread of the estimates (within the sampling
    // error of a 40-seed standard deviation, ~11%, and the t quantile's widening).
    for c in &s.coverage[..2] {
        let ratio = c.mean_std_error / c.sd;
        assert!((0.7..1.4).contains(&ratio), "{}: se/sd {ratio}", c.name);
    }
}

/// Every load's STE stated in rig.toml as a measurement of the truth with an uncertainty of
/// 0.01 um (`[ste] sd_um`, each seed's stated values drawn from it): the fit weighs them against
/// the curves, and its intervals of the other loads' STE narrow to about 0.009 um (0.017-0.026
/// with the STEs free; 200 seeds in docs/calibrated-inference.md) while still covering. 40
/// seeds: below 34 with probability 0.5% at 95% coverage. A fit that ignored the measurements
/// would give standard errors of 0.017-0.026 um and fail the second check.
#[test]
fn stated_ste_with_uncertainty_narrows_the_intervals_and_they_cover() {
    let dir = tempfile::tempdir().unwrap();
    let opts = ValidateStudyOptions {
        seeds: 40,
        noise: NoiseFamily::Relative.noise(0.15),
        ste_sd_um: Some(0.01),
        ..ValidateStudyOptions::default()
    };
    let s = run_validate_study(&opts, dir.path(), &NoProgress, &mut |_| Ok(())).unwrap();
    assert_eq!(s.coverage.len(), 6);
    for c in &s.coverage {
        assert!(c.fisher.0 >= 34, "{}: {}/40 inside", c.name, c.fisher.0);
    }
    for c in &s.coverage[3..] {
        assert!(
            c.mean_std_error < 0.0105 && c.mean_std_error > 0.006,
            "{}: mean standard error {} um",
            c.name,
            c.mean_std_error
        );
    }
}

/// Heavy-tailed scatter (Student-t, 3 degrees of freedom): the likelihood-ratio test picks
/// Student-t errors on some sets, and the intervals still cover.
#[test]
fn heavy_tailed_noise_is_recognised_and_intervals_cover() {
    let dir = tempfile::tempdir().unwrap();
    let opts = ValidateStudyOptions {
        seeds: 30,
        noise: NoiseFamily::StudentT.noise(0.15),
        ..ValidateStudyOptions::default()
    };
    let s = run_validate_study(&opts, dir.path(), &NoProgress, &mut |_| Ok(())).unwrap();
    assert!(
        s.student_t_chosen >= 10,
        "Student-t chosen on {}/30",
        s.student_t_chosen
    );
    for c in &s.coverage[..2] {
        assert!(c.fisher.0 >= 25, "{}: {}/30", c.name, c.fisher.0);
    }
}

/// `validate kubo` on 200 seeded envelopes (8 tooth pairs, 4% relative scatter, zeta 0.15,
/// omega_n 2800 Hz: away from the shipped set's 0.1 and 2500). Weighted by each point's
/// observed half-width, omega_n's interval covered 173/200 and its standard error was 14% below
/// the estimates' spread; weighted by the level, the count is inside [180, 196] (a true 95%
/// falls outside with probability about 2%) and the standard errors match the spread to within
/// its sampling error (a 200-seed standard deviation: 5%). About 70 s on 2 cores (11 of the 200
/// sets take the whole-curve path, 5-8 s each), so `.ci/run` runs it with `--ignored`.
#[test]
#[ignore = "a 200-seed coverage study (about 70 s); .ci/run runs it"]
fn kubo_intervals_cover_the_truth() {
    use geardyn::data::load_kubo;
    use geardyn::validate::{synth_kubo, validate_kubo, KuboOptions, KuboTruth};
    use rayon::prelude::*;
    const ZETA: f64 = 0.15;
    const OMEGA_N_HZ: f64 = 2800.0;
    let truth = |seed: u64| KuboTruth {
        zeta: ZETA,
        omega_n_hz: OMEGA_N_HZ,
        seed,
        ..KuboTruth::default_kubo()
    };
    /// One set's standardized errors and 95% intervals, zeta then omega_n.
    struct Fitted {
        z: [f64; 2],
        ci: [(f64, f64); 2],
    }
    let fits: Vec<Fitted> = (1..=200u64)
        .into_par_iter()
        .filter_map(|seed| {
            let dir = tempfile::tempdir().unwrap();
            synth_kubo(&truth(seed), dir.path(), &NoProgress).unwrap();
            let data = load_kubo(dir.path()).unwrap();
            // A set whose contact part does not bound zeta is refused, with that reason.
            let v = validate_kubo(&data, &KuboOptions::default(), &NoProgress).ok()?;
            let fit = v.fit.expect("zeta and omega_n fitted");
            Some(Fitted {
                z: [
                    (fit.params[0] - ZETA) / fit.std_errors[0],
                    (fit.params[1] - OMEGA_N_HZ) / fit.std_errors[1],
                ],
                ci: [fit.ci95[0], fit.ci95[1]],
            })
        })
        .collect();
    assert!(fits.len() >= 196, "{} of 200 sets fitted", fits.len());
    let n = fits.len();
    let sd = |z: Vec<f64>| {
        let m = z.iter().sum::<f64>() / z.len() as f64;
        (z.iter().map(|v| (v - m).powi(2)).sum::<f64>() / (z.len() - 1) as f64).sqrt()
    };
    for (i, (name, value)) in [("zeta", ZETA), ("omega_n", OMEGA_N_HZ)]
        .into_iter()
        .enumerate()
    {
        let k = fits
            .iter()
            .filter(|f| f.ci[i].0 <= value && value <= f.ci[i].1)
            .count();
        let rate = k as f64 / n as f64;
        assert!((0.90..=0.98).contains(&rate), "{name}: {k}/{n}");
        let s = sd(fits.iter().map(|f| f.z[i]).collect());
        assert!(
            (0.88..1.12).contains(&s),
            "{name}: standardized errors' sd {s}"
        );
    }
}
