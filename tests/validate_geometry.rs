//! `validate munro --ste geometry` (issue 24 item 5): zeta and omega_n fitted at the design load
//! alone with the STE of the gear geometry (relief by the design rule), every other load
//! predicted with the geometry's STE, beside the per-curve path.
//!
//! 1. On a set made by `synth munro` whose truth STE per load is the geometry's first harmonic
//!    (the relief sized by the design rule): the geometry path recovers zeta and omega_n and
//!    predicts every load to the noise level without reading the other curves.
//! 2. On the shipped set (truth STE 0.3 / 1.5 / 2.5 / 3.5 um, not made from geometry) both paths
//!    are reported per load, and the per-curve path is the better one, as it must be.
//! 3. The command line writes both paths into fits/munro.json.

mod common;
use common::geardyn;
use geardyn::data::{load_munro, GearGeometry};
use geardyn::progress::NoProgress;
use geardyn::validate::{
    dte_gain, synth_munro, validate_munro, GearMesh, GeometryOptions, MunroOptions, MunroTruth,
    ReliefRule, SteMode, SteSource,
};

const LOADS: [f64; 4] = [3780.0, 2835.0, 1890.0, 945.0];

fn geometry_options() -> MunroOptions {
    MunroOptions {
        attractor_speeds: 3,
        ic_per_axis: 3,
        ste: SteMode::Geometry(Box::new(GeometryOptions::design_rule(
            GearGeometry::default(),
        ))),
        ..MunroOptions::default()
    }
}

/// The geometry's first-harmonic STE per load with the design-rule relief, um.
fn geometry_ste(truth: &MunroTruth) -> Vec<(f64, f64)> {
    let mesh = GearMesh::new(
        &truth.rig,
        &GeometryOptions::design_rule(GearGeometry::default()),
    )
    .unwrap();
    let relief = mesh.design_rule_um(truth.rig.design_load_n).unwrap();
    LOADS
        .iter()
        .map(|&l| (l, mesh.excitation(l, relief).unwrap().ste_first_harmonic_um))
        .collect()
}

#[test]
fn geometry_path_predicts_a_set_whose_ste_came_from_the_geometry() {
    let dir = tempfile::tempdir().unwrap();
    let mut truth = MunroTruth::default_munro();
    truth.ste_um = geometry_ste(&truth);
    synth_munro(&truth, dir.path(), &NoProgress).unwrap();
    let data = load_munro(dir.path()).unwrap();
    let r = validate_munro(&data, &geometry_options(), &NoProgress).unwrap();
    let g = r.geometry.as_ref().expect("the geometry path ran");
    // Only zeta and omega_n are fitted (relief by the design rule), to the design load alone.
    assert_eq!(g.fit.estimate.params.len(), 2);
    assert_eq!(g.fit.estimate.n, r.fit.design_points);
    let (cz, cw) = (g.fit.estimate.ci95[0], g.fit.estimate.ci95[1]);
    assert!(
        cz.0 <= truth.zeta && truth.zeta <= cz.1,
        "zeta {} {cz:?}",
        g.zeta
    );
    assert!(
        cw.0 <= truth.omega_n_hz && truth.omega_n_hz <= cw.1,
        "omega_n {} {cw:?}",
        g.omega_n_hz
    );
    let b_um = r.half_backlash_um;
    let mut report = String::new();
    for (l, c) in g.loads.iter().zip(&r.loads) {
        let e1 = truth
            .ste_um
            .iter()
            .find(|x| (x.0 - l.load_n).abs() < 1e-6)
            .unwrap()
            .1;
        // The STE the model gets is the truth's e_1, as F_ah = e_1 / b.
        assert_eq!(l.ste_source, SteSource::Geometry);
        assert!((l.ste_um - e1).abs() < 1e-9 * e1, "{} vs {e1}", l.ste_um);
        assert!((l.ste_amplitude * b_um - e1).abs() < 1e-9 * e1);
        report.push_str(&format!(
            "{} N: STE curve {:.3} geometry {:.3} (truth {e1:.3}); RMS curve {:.3} geometry {:.3}; period-1 {:?} {:?}\n",
            l.load_n, c.ste_um, l.ste_um, c.rms_um, l.rms_um, c.rms_period1_um, l.rms_period1_um
        ));
        // Where the model is period-1 the prediction is at the noise level (0.15 um; RMS of
        // 60-81 residuals: 0.15 +- 0.02), with the fitted zeta, omega_n adding a little.
        let p1 = l.rms_period1_um.expect("period-1 points");
        assert!(p1 < 0.2, "{} N: period-1 RMS {p1} um\n{report}", l.load_n);
        // At the lowest speed the simulated pp DTE is 2 e_1 |H_x|: the amplitude convention
        // reaches the simulation (half the STE pp would differ by 12% at 945 N and 4x at 3780 N).
        let (s0, y0) = (l.up[0].speed_rpm, l.up[0].dte_pp_um);
        let om = s0 * 32.0 / 60.0 / g.omega_n_hz;
        let expected = 2.0 * e1 * dte_gain(g.zeta, om);
        if l.force_ratio > 1.0 {
            assert!(
                (y0 - expected).abs() < 1e-3 * expected,
                "{} N: {y0} vs {expected}",
                l.load_n
            );
        }
    }
    eprintln!("{report}");
}

#[test]
fn shipped_set_reports_both_paths_per_load() {
    let data = load_munro(std::path::Path::new("data/munro")).unwrap();
    // With the design rule's relief the geometry's STE at the design load (0.126 um) is well under
    // half the curve's (0.305 um): the design-load fit's residuals are one smooth curve. Taken
    // as correlated errors (the default) their correlation length is not bounded within the
    // curve; taken as independent (--correlation off) zeta runs to 0 with a profile interval
    // unbounded below. Either way a failed fit, refused with its reason (issue 22).
    match validate_munro(&data, &geometry_options(), &NoProgress) {
        Err(geardyn::GearError::FitFailed { reason, .. }) => {
            assert!(reason.contains("not bounded within the curves"), "{reason}")
        }
        Err(e) => panic!("expected a failed fit, got {e}"),
        Ok(_) => panic!("the design-rule geometry fit of the shipped set was accepted"),
    }
    let mut opts = geometry_options();
    if let SteMode::Geometry(g) = &mut opts.ste {
        g.relief = ReliefRule::Fit;
    }
    let r = validate_munro(&data, &opts, &NoProgress).unwrap();
    let g = r.geometry.as_ref().unwrap();
    assert_eq!(g.loads.len(), r.loads.len());
    // The fitted relief gives the design load the curve's STE (docs/validation.md: 21.94 um,
    // e_1 = 0.305 um at 3780 N) ...
    let e3780 = g.loads.iter().find(|l| l.load_n == 3780.0).unwrap().ste_um;
    assert!((e3780 - 0.305).abs() < 0.01, "{e3780}");
    assert!(
        (g.relief.relief_um - 21.94).abs() < 0.05,
        "{}",
        g.relief.relief_um
    );
    // ... but the shipped truth (0.3 .. 3.5 um) was not made from the geometry: reading the STE
    // off each curve predicts 2835 and 1890 N at the noise level, the geometry's STE does not.
    for load in [2835.0, 1890.0] {
        let c = r.loads.iter().find(|l| l.load_n == load).unwrap();
        let x = g.loads.iter().find(|l| l.load_n == load).unwrap();
        assert!(c.rms_um < 0.2, "{load} N curve path {}", c.rms_um);
        assert!(
            x.rms_um > 3.0 * c.rms_um,
            "{load} N: {} vs {}",
            x.rms_um,
            c.rms_um
        );
    }
}

#[test]
fn command_line_writes_both_paths() {
    let dir = tempfile::tempdir().unwrap();
    let (fits, reports) = (dir.path().join("fits"), dir.path().join("reports"));
    // The design rule's relief fails the design-load fit of the shipped set (above): refused,
    // with the reason and a hint, and nothing written.
    let out = geardyn(&[
        "validate",
        "munro",
        "--ste",
        "geometry",
        "--fits",
        fits.to_str().unwrap(),
        "--reports",
        reports.to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("failed") && err.contains("--relief fit"));
    assert!(!fits.exists() && !reports.exists(), "{err}");
    let out = geardyn(&[
        "validate",
        "munro",
        "--ste",
        "geometry",
        "--relief",
        "fit",
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
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("STE from the geometry"), "{text}");
    let j: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(fits.join("munro.json")).unwrap()).unwrap();
    assert_eq!(j["ste_mode"], "geometry");
    assert_eq!(j["mesh_stiffness_source"], "iso6336_estimate");
    let paths = j["ste_paths"].as_array().unwrap();
    assert_eq!(paths.len(), 4);
    for p in paths {
        assert!(p["curve"]["rms_um"].is_number() && p["geometry"]["rms_um"].is_number());
        assert_eq!(p["geometry"]["ste_source"], "geometry");
    }
    assert_eq!(j["ste_geometry"]["relief"]["relief_rule"], "fit");
    let html = std::fs::read_to_string(reports.join("munro/index.html")).unwrap();
    assert!(html.contains("STE from the gear geometry"));
    // --tip-relief-um without --relief given is refused, and nothing is written.
    let bad = dir.path().join("bad");
    let out = geardyn(&[
        "validate",
        "munro",
        "--ste",
        "geometry",
        "--tip-relief-um",
        "20",
        "--fits",
        bad.to_str().unwrap(),
        "--reports",
        bad.to_str().unwrap(),
    ]);
    assert!(!out.status.success() && !bad.exists());
}

/// A design load whose teeth separate over the resonance (STE 3 um at 3780 N, zeta 0.03,
/// 1500 Hz; made by DOP853 with relative noise, seed 7), on the geometry path with the relief
/// fitted: the geometry's STE at the fitted depth is the curve's, eq. 13's multi-harmonic
/// closed form would separate the teeth, so the design-load curve is fitted through simulated
/// up-sweeps as on the per-curve path, and the 95% interval of zeta holds the truth. (The
/// closed form alone had fitted zeta 0.0710 [0.0672, 0.0749].)
#[test]
fn the_geometry_path_fits_a_separating_design_load_through_sweeps() {
    use geardyn::validate::{DesignModel, NoiseFamily};
    let dir = tempfile::tempdir().unwrap();
    let mut truth = MunroTruth::default_munro();
    truth.seed = 7;
    truth.zeta = 0.03;
    truth.omega_n_hz = 1500.0;
    truth.ste_um = vec![(3780.0, 3.0), (1890.0, 3.5)];
    truth.noise = NoiseFamily::Relative.noise(0.15);
    truth.dop853_rtol = Some(1e-9);
    synth_munro(&truth, dir.path(), &NoProgress).unwrap();
    let data = load_munro(dir.path()).unwrap();
    let mut opts = geometry_options();
    if let SteMode::Geometry(g) = &mut opts.ste {
        g.relief = ReliefRule::Fit;
    }
    let r = validate_munro(&data, &opts, &NoProgress).unwrap();
    let g = r.geometry.as_ref().unwrap();
    assert_eq!(g.fit.design_model, DesignModel::Swept);
    let zeta_ci = g.fit.estimate.ci95[0];
    assert!(
        zeta_ci.0 <= 0.03 && 0.03 <= zeta_ci.1,
        "zeta {} {zeta_ci:?}",
        g.zeta
    );
    let wn_ci = g.fit.estimate.ci95[1];
    assert!(wn_ci.0 <= 1500.0 && 1500.0 <= wn_ci.1, "omega_n {wn_ci:?}");
}
