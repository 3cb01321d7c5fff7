//! Checks of the generator against closed forms and its own tighter runs (no geardyn involved).

use crate::gen::Grid;
use crate::model::Excitation;
use crate::noise::{apply, apply_curves, Correlation, Curve, Family, FloorStats, NoiseSpec};
use crate::rig::Rig;
use crate::sim::{steady_state, Carried, SimConfig};
use std::f64::consts::PI;

fn ex(omega: f64) -> Excitation {
    Excitation {
        zeta: 0.0175,
        omega,
        fm: 0.2833,
        fah: 0.006,
        fah2: 0.0,
        phi2: 0.0,
        fat: 0.0,
        psi_t: 0.0,
        eps: 0.0,
        psi_k: 0.0,
        contact: crate::model::Contact::LINEAR,
    }
}

/// Complex numbers, just enough for the linear steady state in contact.
#[derive(Clone, Copy)]
struct C(f64, f64);
impl C {
    fn mul(self, o: C) -> C {
        C(self.0 * o.0 - self.1 * o.1, self.0 * o.1 + self.1 * o.0)
    }
    fn div(self, o: C) -> C {
        let d = o.0 * o.0 + o.1 * o.1;
        C(
            (self.0 * o.0 + self.1 * o.1) / d,
            (self.1 * o.0 - self.0 * o.1) / d,
        )
    }
    fn cis(a: f64) -> C {
        C(a.cos(), a.sin())
    }
}

/// pp of x = q + e/b for the linear model in contact (k = 1): x_j = e_j (1 + 2 i zeta w_j) /
/// (1 - w_j^2 + 2 i zeta w_j) for each STE harmonic, and F_aT / (1 - w^2 + 2 i zeta w) for the
/// ripple, as the imaginary part of a rotating phasor (sin convention).
fn linear_pp(e: &Excitation) -> f64 {
    let z = e.zeta;
    let resp = |w: f64| C(1.0 - w * w, 2.0 * z * w);
    let w1 = e.omega;
    let a1 = C(e.fah, 0.0).mul(C(1.0, 2.0 * z * w1)).div(resp(w1));
    let rip = C(e.fat, 0.0).mul(C::cis(e.psi_t)).div(resp(w1));
    let a1 = C(a1.0 + rip.0, a1.1 + rip.1);
    let w2 = 2.0 * w1;
    let a2 = C(e.fah2, 0.0)
        .mul(C::cis(e.phi2))
        .mul(C(1.0, 2.0 * z * w2))
        .div(resp(w2));
    let x = |th: f64| a1.mul(C::cis(th)).1 + a2.mul(C::cis(2.0 * th)).1;
    let n = 200_000;
    let (mut mx, mut mn) = (f64::NEG_INFINITY, f64::INFINITY);
    for i in 0..n {
        let v = x(2.0 * PI * i as f64 / n as f64);
        mx = mx.max(v);
        mn = mn.min(v);
    }
    mx - mn
}

#[test]
fn linear_contact_matches_closed_form() {
    let cfg = SimConfig::default();
    for &w in &[0.35, 0.7, 0.95, 1.2, 1.6] {
        let e = ex(w);
        let mut c = Carried::new(1.0 + e.fm, 0.0);
        let sp = steady_state(&e, &mut c, &cfg).unwrap();
        assert_eq!(sp.period, Some(1));
        let exact = linear_pp(&e);
        assert!(
            (sp.x_pp - exact).abs() < 1e-9 * exact.max(1e-3) + 1e-10,
            "w {w}: {} vs {}",
            sp.x_pp,
            exact
        );
    }
}

#[test]
fn second_harmonic_and_ripple_in_contact_match_closed_form() {
    let cfg = SimConfig::default();
    for &w in &[0.45, 0.8, 1.3] {
        let mut e = ex(w);
        e.fah2 = 0.4 * e.fah;
        e.phi2 = 1.0;
        let mut c = Carried::new(1.0 + e.fm, 0.0);
        let sp = steady_state(&e, &mut c, &cfg).unwrap();
        let exact = linear_pp(&e);
        assert!(
            (sp.x_pp - exact).abs() < 1e-8 * exact,
            "r2 w {w}: {} vs {}",
            sp.x_pp,
            exact
        );

        let mut e = ex(w);
        e.fat = 0.03 * 0.2833;
        e.psi_t = 2.0;
        let mut c = Carried::new(1.0 + e.fm, 0.0);
        let sp = steady_state(&e, &mut c, &cfg).unwrap();
        let exact = linear_pp(&e);
        assert!(
            (sp.x_pp - exact).abs() < 1e-8 * exact,
            "ripple w {w}: {} vs {}",
            sp.x_pp,
            exact
        );
    }
}

#[test]
fn impacting_motion_converges_with_the_tolerance() {
    // F_hat ~ 1 (Munro's 945 N) near resonance: single-sided impacts, events every period.
    let mut e = ex(0.9);
    e.fm = 0.0708;
    e.fah = 0.07;
    let run = |rtol: f64| {
        let cfg = SimConfig {
            rtol,
            atol: rtol / 100.0,
            ..SimConfig::default()
        };
        let mut c = Carried::new(1.0 + e.fm, 0.0);
        steady_state(&e, &mut c, &cfg).unwrap()
    };
    let a = run(1e-10);
    let b = run(1e-12);
    assert!(a.min_q < 1.0, "expected contact loss");
    assert_eq!(a.period, b.period);
    assert!((a.x_pp - b.x_pp).abs() < 1e-8, "{} vs {}", a.x_pp, b.x_pp);
}

#[test]
fn munro_mesh_stiffness_is_the_iso_estimate() {
    let rig = Rig::munro();
    let (k, _) = rig.mesh_stiffness();
    assert!((rig.contact_ratio() - 1.668).abs() < 5e-4);
    assert!((k - 266.83).abs() < 0.01, "{k}");
    assert_eq!(rig.b_um(), 50.0);
}

#[test]
fn noise_families_have_the_stated_sd_and_stay_non_negative() {
    let n = 200_000;
    let level = 20.0;
    for fam in Family::INDEPENDENT {
        let spec = NoiseSpec {
            family: fam,
            floor_um: 0.15,
            relative: 0.03,
            dof: 3.0,
            quantum_um: 0.25,
            seed: 7,
            correlation: None,
        };
        let mut st = FloorStats::default();
        let y = apply(&spec, &vec![level; n], &mut st);
        let m = y.iter().sum::<f64>() / n as f64;
        let sd = (y.iter().map(|v| (v - m).powi(2)).sum::<f64>() / (n - 1) as f64).sqrt();
        let want = spec.sd(level);
        let tol = if fam == Family::StudentT { 0.08 } else { 0.01 };
        assert!((sd / want - 1.0).abs() < tol, "{fam:?}: sd {sd} vs {want}");
        assert!((m - level).abs() < 0.01, "{fam:?}: mean {m}");
        if fam == Family::Quantized {
            assert!(y
                .iter()
                .all(|v| ((v / 0.25) - (v / 0.25).round()).abs() < 1e-9));
        }
    }
    // At the floor: a level of 0.1 um with SD 0.15 um gives no negative reading.
    let spec = NoiseSpec {
        family: Family::StudentT,
        floor_um: 0.15,
        relative: 0.03,
        dof: 3.0,
        quantum_um: 0.25,
        seed: 3,
        correlation: None,
    };
    let mut st = FloorStats::default();
    let y = apply(&spec, &vec![0.1; 10_000], &mut st);
    assert!(y.iter().all(|&v| v >= 0.0));
    assert!(st.redrawn > 0);
}

#[test]
fn nonuniform_grid_is_sorted_unique_in_range_and_reproducible() {
    let g = Grid::Nonuniform {
        n: 81,
        lo_rpm: 1000.0,
        hi_rpm: 5000.0,
        seed: 42,
        decimals: 2,
    };
    let a = g.speeds();
    assert_eq!(a.len(), 81);
    assert!(a.windows(2).all(|w| w[0] < w[1]));
    assert!(a.iter().all(|&x| (1000.0..=5000.0).contains(&x)));
    assert_eq!(a, g.speeds());
    let u = Grid::Uniform {
        start_rpm: 1000.0,
        stop_rpm: 5000.0,
        step_rpm: 50.0,
    }
    .speeds();
    assert_eq!(u.len(), 81);
    assert_eq!(u[80], 5000.0);
}

#[test]
fn brief_contact_after_an_event_does_not_stall_the_integration() {
    // A sweep that once stalled (validate batch seed 1010038, 945 N, 4650 rpm): the motion
    // re-entered contact with q' ~ 6e-4 and left it again within one step; the crossing back
    // lies after the excursion's peak, not at the step's start.
    use crate::gen::{clean_curve, Effect, SetSpec};
    let spec = SetSpec {
        name: "stall".into(),
        rig: Rig::munro(),
        zeta: 0.0225746438321689,
        omega_n_hz: 1649.9030235941984,
        loads: vec![(945.0, 3.5525426211892626)],
        effect: Effect::None,
        grid: Grid::Uniform {
            start_rpm: 1000.0,
            stop_rpm: 5000.0,
            step_rpm: 50.0,
        },
        noise: None,
        sim: SimConfig::default(),
        extra: serde_json::Value::Null,
    };
    let speeds = spec.grid.speeds();
    let c = clean_curve(&spec, 945.0, 3.5525426211892626, &speeds).unwrap();
    assert_eq!(c.points.len(), 81);
    assert!(c
        .points
        .iter()
        .all(|p| p.dte_pp_um.is_finite() && p.dte_pp_um > 0.0));
}

// ---- Kubo mode ----

/// D_L of the linear model in contact (k = 1): q = 1 + F_m + y, y'' + 2 zeta y' + y =
/// W^2 F_ah sin(W t), so y = Im(Y e^{i W t}), Y = W^2 F_ah / (1 - W^2 + 2 i zeta W); the mesh
/// force 2 zeta q' + (q - 1) = F_m + Im((1 + 2 i zeta W) Y e^{i W t}), whose maximum over a period
/// is F_m + |1 + 2 i zeta W| |Y|:
///   D_L = 1 + W^2 F_ah sqrt(1 + 4 zeta^2 W^2) / (F_m sqrt((1 - W^2)^2 + 4 zeta^2 W^2)),
/// valid while q stays above 1 (F_m > |Y|).
fn linear_dl(zeta: f64, w: f64, fm: f64, fah: f64) -> (f64, bool) {
    let den = ((1.0 - w * w).powi(2) + 4.0 * zeta * zeta * w * w).sqrt();
    let y = w * w * fah / den;
    (
        1.0 + y * (1.0 + 4.0 * zeta * zeta * w * w).sqrt() / fm,
        fm > y,
    )
}

#[test]
fn kubo_dynamic_factor_in_contact_matches_closed_form() {
    use crate::kubo::{dl_curve, KUBO_RIG_TOML};
    let rig = Rig::from_toml_str(KUBO_RIG_TOML).unwrap();
    let b = rig.b_um();
    let (kh, _) = rig.mesh_stiffness();
    let fm = 2000.0 / (b * kh);
    let fah = 3.0 / b;
    for &(zeta, fn_hz) in &[(0.1, 2500.0), (0.15, 2800.0)] {
        // Speeds where the linear solution keeps contact (below and above the resonance).
        let speeds = [2000.0, 3500.0, 4500.0, 8000.0, 10000.0];
        let c = dl_curve(
            &rig,
            zeta,
            fn_hz,
            2000.0,
            3.0,
            &speeds,
            &SimConfig::default(),
        )
        .unwrap();
        for p in &c.points {
            let (exact, contact) = linear_dl(zeta, p.omega, fm, fah);
            assert!(contact, "W {} not in contact", p.omega);
            assert_eq!(p.period, Some(1));
            assert!(
                (p.dynamic_factor - exact).abs() < 1e-6,
                "zeta {zeta} W {}: {} vs {}",
                p.omega,
                p.dynamic_factor,
                exact
            );
        }
    }
    // Single point with a stiffer sweep start (fresh state), at a larger F_m / F_ah.
    let mut e = ex(0.8);
    e.zeta = 0.1;
    let mut c = Carried::new(1.0 + e.fm, 0.0);
    let sp = steady_state(&e, &mut c, &SimConfig::default()).unwrap();
    let (exact, contact) = linear_dl(0.1, 0.8, e.fm, e.fah);
    assert!(contact);
    assert!((sp.force_max / e.fm - exact).abs() < 1e-6);
}

#[test]
fn kubo_dynamic_factor_with_separation_converges_with_the_tolerance() {
    use crate::kubo::{dl_curve, KUBO_RIG_TOML};
    let rig = Rig::from_toml_str(KUBO_RIG_TOML).unwrap();
    // zeta 0.06, 2200 Hz: the teeth separate over the resonance and the up-sweep jumps.
    let speeds: Vec<f64> = (0..=12).map(|i| 4200.0 + 100.0 * i as f64).collect();
    let run = |rtol: f64| {
        let cfg = SimConfig {
            rtol,
            atol: rtol / 100.0,
            ..SimConfig::default()
        };
        dl_curve(&rig, 0.06, 2200.0, 2000.0, 3.0, &speeds, &cfg).unwrap()
    };
    let a = run(1e-10);
    let b = run(1e-12);
    let fm = a.fm;
    let fah = a.fah;
    let mut separated = 0;
    for (p, q) in a.points.iter().zip(&b.points) {
        assert!((p.dynamic_factor - q.dynamic_factor).abs() < 1e-7);
        if !linear_dl(0.06, p.omega, fm, fah).1 {
            separated += 1;
        }
    }
    assert!(separated > 3, "expected separation in the sweep");
}

#[test]
fn kubo_reading_errors_have_the_stated_sd() {
    use crate::kubo::{KFamily, KNoise};
    use rand_chacha::rand_core::SeedableRng;
    let n = 200_000;
    let level = 1.6;
    for fam in [KFamily::Gaussian, KFamily::StudentT, KFamily::Quantized] {
        let spec = KNoise {
            family: fam,
            relative: 0.02,
            floor: 0.01,
            dof: 3.0,
            quantum: 0.02,
            correlation: None,
        };
        let t = rand_distr::StudentT::new(3.0).unwrap();
        let mut rng = rand_chacha::ChaCha20Rng::seed_from_u64(11);
        let y: Vec<f64> = (0..n).map(|_| spec.draw(level, &mut rng, &t).0).collect();
        let m = y.iter().sum::<f64>() / n as f64;
        let sd = (y.iter().map(|v| (v - m).powi(2)).sum::<f64>() / (n - 1) as f64).sqrt();
        let mut want = spec.sd(level);
        if fam == KFamily::Quantized {
            // Sheppard: rounding to a grid q adds q^2 / 12 to the variance.
            want = (want * want + 0.02f64.powi(2) / 12.0).sqrt();
            assert!(y
                .iter()
                .all(|v| ((v / 0.02) - (v / 0.02).round()).abs() < 1e-9));
        }
        let tol = if fam == KFamily::StudentT { 0.08 } else { 0.01 };
        assert!((sd / want - 1.0).abs() < tol, "{fam:?}: sd {sd} vs {want}");
        assert!((m - level).abs() < 5e-4, "{fam:?}: mean {m}");
    }
}

#[test]
fn kubo_pair_ste_factors_have_the_stated_scatter() {
    let f = crate::kubo::pair_factors(100_000, 0.05, 5);
    let n = f.len() as f64;
    let m = f.iter().sum::<f64>() / n;
    let sd = (f.iter().map(|v| (v - m).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
    assert!((m - 1.0).abs() < 1e-3, "{m}");
    assert!((sd / 0.05 - 1.0).abs() < 0.01, "{sd}");
    assert_eq!(crate::kubo::pair_factors(8, 0.05, 5), f[..8].to_vec());
}

// ---- The correlated noise family ----

/// Correlated-family noise at the studies' scale (floor 0.05 um, 3% of the level).
fn correlated_spec(correlation: Correlation, seed: u64) -> NoiseSpec {
    NoiseSpec {
        family: Family::Correlated,
        floor_um: 0.05,
        relative: 0.03,
        dof: 3.0,
        quantum_um: 0.25,
        seed,
        correlation: Some(correlation),
    }
}

/// A resonance-like noise-free curve (um), so that SD_i varies along speed (0.05-0.9 um).
fn peaked_levels(speeds: &[f64]) -> Vec<f64> {
    speeds
        .iter()
        .map(|&s| 0.5 + 30.0 * (-((s - 3000.0) / 400.0).powi(2)).exp())
        .collect()
}

/// Standardized errors z[set][curve][point] = (reading - level) / SD of `n_sets` sets of
/// `n_curves` curves with the same levels, set k drawn with seed 1000 + k; also checks that they
/// are the z the generator reports and that no draw met the floor.
fn draw_z(
    correlation: Correlation,
    speeds: &[f64],
    levels: &[f64],
    n_curves: usize,
    n_sets: usize,
) -> Vec<Vec<Vec<f64>>> {
    let curves = vec![
        Curve {
            speeds_rpm: speeds,
            levels,
        };
        n_curves
    ];
    (0..n_sets)
        .map(|k| {
            let spec = correlated_spec(correlation, 1000 + k as u64);
            let mut st = FloorStats::default();
            let drawn = apply_curves(&spec, &curves, &mut st).unwrap();
            assert_eq!(st.redrawn + st.clipped_to_zero + st.zero_readings, 0);
            let reported = drawn.z.expect("the correlated family reports its z");
            drawn
                .values
                .iter()
                .zip(&reported)
                .map(|(v, zr)| {
                    let z: Vec<f64> = v
                        .iter()
                        .zip(levels)
                        .map(|(&y, &l)| (y - l) / spec.sd(l))
                        .collect();
                    assert!(z.iter().zip(zr).all(|(a, b)| (a - b).abs() < 1e-9));
                    z
                })
                .collect()
        })
        .collect()
}

/// Pooled sample correlation of paired values (the mean is known to be 0).
fn corr0(pairs: impl Iterator<Item = (f64, f64)>) -> f64 {
    let (mut sxy, mut sxx, mut syy) = (0.0, 0.0, 0.0);
    for (x, y) in pairs {
        sxy += x * y;
        sxx += x * x;
        syy += y * y;
    }
    sxy / (sxx * syy).sqrt()
}

/// Bartlett's standard error of the lag-h sample autocorrelation of an AR(1) with coefficient
/// phi from n pairs: var = [(1 + phi^2)(1 - phi^(2h)) / (1 - phi^2) - 2 h phi^(2h)] / n.
fn ar1_acf_se(phi: f64, h: i32, n: usize) -> f64 {
    let p2h = phi.powi(2 * h);
    (((1.0 + phi * phi) * (1.0 - p2h) / (1.0 - phi * phi) - 2.0 * h as f64 * p2h) / n as f64).sqrt()
}

#[test]
fn correlated_noise_is_ar1_on_the_grid_with_the_stated_sd() {
    // 1000 sets x 4 curves of 81 speeds (1000-5000 rpm by 50), the studies' scale.
    let speeds = Grid::Uniform {
        start_rpm: 1000.0,
        stop_rpm: 5000.0,
        step_rpm: 50.0,
    }
    .speeds();
    let levels = peaked_levels(&speeds);
    let spec = correlated_spec(Correlation::GridLag1 { rho: 0.6 }, 0);
    for rho in [0.6, 0.9] {
        let z = draw_z(Correlation::GridLag1 { rho }, &speeds, &levels, 4, 1000);
        let curves: Vec<&Vec<f64>> = z.iter().flatten().collect();
        let n_curves = curves.len();
        let n = speeds.len();
        // Lag 1 and lag 2 pooled over every curve: rho and rho^2 within 4 Bartlett SEs.
        for h in [1usize, 2] {
            let r = corr0(
                curves
                    .iter()
                    .flat_map(|c| (h..n).map(move |k| (c[k], c[k - h]))),
            );
            let want = rho.powi(h as i32);
            let se = ar1_acf_se(rho, h as i32, n_curves * (n - h));
            assert!(
                (r - want).abs() < 4.0 * se,
                "rho {rho}: lag-{h} autocorrelation {r:.5} vs {want:.5} (se {se:.5})"
            );
        }
        // Stationary: the first and the last step have the same correlation across curves
        // (SE of a correlation from N pairs: (1 - rho^2) / sqrt(N)).
        let se = (1.0 - rho * rho) / (n_curves as f64).sqrt();
        for k in [1, n / 2, n - 1] {
            let r = corr0(curves.iter().map(|c| (c[k], c[k - 1])));
            assert!(
                (r - rho).abs() < 4.0 * se,
                "rho {rho}: step {k}: {r:.4} (se {se:.4})"
            );
        }
        // Marginal: at every speed the errors have mean 0 and SD sd_i (z: mean 0, SD 1), SE of
        // an SD from N Gaussian draws sd / sqrt(2 (N - 1)).
        let se_sd = 1.0 / (2.0 * (n_curves as f64 - 1.0)).sqrt();
        let se_mean = 1.0 / (n_curves as f64).sqrt();
        for k in 0..n {
            let m = curves.iter().map(|c| c[k]).sum::<f64>() / n_curves as f64;
            let sd = (curves.iter().map(|c| (c[k] - m).powi(2)).sum::<f64>()
                / (n_curves as f64 - 1.0))
                .sqrt();
            assert!(
                m.abs() < 4.0 * se_mean,
                "rho {rho}, {} rpm: mean z {m}",
                speeds[k]
            );
            assert!(
                (sd - 1.0).abs() < 4.0 * se_sd,
                "rho {rho}, {} rpm: SD {sd} x sd_i (sd_i {} um, se {se_sd:.4})",
                speeds[k],
                spec.sd(levels[k])
            );
        }
    }
}

#[test]
fn correlated_noise_length_form_follows_the_exponential_kernel_on_an_uneven_grid() {
    // Steps cycling 25, 75, 150, 40 rpm from 1000 rpm (61 speeds), L = 150 rpm.
    let steps = [25.0, 75.0, 150.0, 40.0];
    let mut speeds = vec![1000.0];
    for k in 0..60 {
        speeds.push(speeds[k] + steps[k % 4]);
    }
    let levels = peaked_levels(&speeds);
    let length = 150.0;
    let z = draw_z(
        Correlation::LengthRpm { length_rpm: length },
        &speeds,
        &levels,
        4,
        1000,
    );
    let curves: Vec<&Vec<f64>> = z.iter().flatten().collect();
    let n_curves = curves.len();
    // Pairs of points at a given spacing d (steps, sums of steps, whole cycles). The SE is taken
    // as if each curve gave one pair, (1 - r^2) / sqrt(N): conservative, since the pairs of one
    // curve are pooled.
    for d in [25.0, 40.0, 75.0, 100.0, 150.0, 290.0, 580.0] {
        let idx: Vec<(usize, usize)> = (0..speeds.len())
            .flat_map(|i| (i + 1..speeds.len()).map(move |j| (i, j)))
            .filter(|&(i, j)| speeds[j] - speeds[i] == d)
            .collect();
        assert!(!idx.is_empty(), "no pair at {d} rpm");
        let r = corr0(
            curves
                .iter()
                .flat_map(|c| idx.iter().map(move |&(i, j)| (c[i], c[j]))),
        );
        let want = (-d / length).exp();
        let se = (1.0 - want * want) / (n_curves as f64).sqrt();
        assert!(
            (r - want).abs() < 4.0 * se,
            "spacing {d} rpm: correlation {r:.4} vs exp(-d/L) {want:.4} (se {se:.4})"
        );
    }
    // Stationary on the uneven grid: SD 1 at every speed.
    let se_sd = 1.0 / (2.0 * (n_curves as f64 - 1.0)).sqrt();
    for k in 0..speeds.len() {
        let sd = (curves.iter().map(|c| c[k] * c[k]).sum::<f64>() / n_curves as f64).sqrt();
        assert!((sd - 1.0).abs() < 4.0 * se_sd, "{} rpm: SD {sd}", speeds[k]);
    }
    // The grid form on the same grid is, deliberately, not a kernel in rpm: rho at every
    // neighbouring pair, 25 rpm apart or 150.
    let rho = 0.6;
    let z = draw_z(Correlation::GridLag1 { rho }, &speeds, &levels, 4, 500);
    let curves: Vec<&Vec<f64>> = z.iter().flatten().collect();
    // (conservative SE as above; under the length form these steps would give 0.85 and 0.37)
    let se = (1.0 - rho * rho) / (curves.len() as f64).sqrt();
    for (phase, step) in steps.iter().enumerate() {
        let r = corr0(curves.iter().flat_map(|c| {
            (phase + 1..speeds.len())
                .step_by(4)
                .map(move |k| (c[k], c[k - 1]))
        }));
        assert!(
            (r - rho).abs() < 4.0 * se,
            "grid form, step {step} rpm: {r:.4} vs {rho} (se {se:.4})"
        );
    }
}

#[test]
fn correlated_noise_curves_are_independent_and_reproducible() {
    let speeds = Grid::Uniform {
        start_rpm: 1000.0,
        stop_rpm: 5000.0,
        step_rpm: 50.0,
    }
    .speeds();
    let levels = peaked_levels(&speeds);
    let rho: f64 = 0.8;
    let n_sets = 1000;
    let z = draw_z(Correlation::GridLag1 { rho }, &speeds, &levels, 4, n_sets);
    let n = speeds.len();
    // Cross-correlation of two curves of a set at lags -1, 0, 1, pooled over speeds and sets:
    // for two independent AR(1) paths its SE is sqrt((1 + rho^2) / (1 - rho^2) / n) (Bartlett).
    let se = ((1.0 + rho * rho) / (1.0 - rho * rho) / (n_sets * (n - 1)) as f64).sqrt();
    for a in 0..4 {
        for b in a + 1..4 {
            for lag in [-1i64, 0, 1] {
                let r = corr0(z.iter().flat_map(|set| {
                    (1..n - 1).map(move |k| (set[a][k], set[b][(k as i64 + lag) as usize]))
                }));
                assert!(
                    r.abs() < 4.0 * se,
                    "curves {a}, {b} lag {lag}: {r:.4} (se {se:.4})"
                );
            }
        }
    }
    // A curve does not continue the previous one's path: the first point of curve b against
    // the last of curve b - 1 (would be rho = 0.8 if the AR(1) ran on across curves).
    let se1 = 1.0 / (n_sets as f64).sqrt();
    for b in 1..4 {
        let r = corr0(z.iter().map(|set| (set[b - 1][n - 1], set[b][0])));
        assert!(
            r.abs() < 4.0 * se1,
            "curve {b} start vs curve {} end: {r:.4}",
            b - 1
        );
    }
    // Reproducible from the seed, different for another seed.
    let curves = [Curve {
        speeds_rpm: &speeds,
        levels: &levels,
    }; 4];
    let draw = |seed| {
        let spec = correlated_spec(Correlation::GridLag1 { rho }, seed);
        apply_curves(&spec, &curves, &mut FloorStats::default())
            .unwrap()
            .values
    };
    assert_eq!(draw(5), draw(5));
    assert_ne!(draw(5), draw(6));
    // rho 0 is the relative family, draw for draw (same stream, same order).
    let mut rel = correlated_spec(Correlation::GridLag1 { rho: 0.0 }, 5);
    let corr0_values = apply_curves(&rel, &curves, &mut FloorStats::default())
        .unwrap()
        .values;
    rel.family = Family::Relative;
    rel.correlation = None;
    let relative = apply_curves(&rel, &curves, &mut FloorStats::default()).unwrap();
    assert!(relative.z.is_none());
    assert_eq!(corr0_values, relative.values);
}

#[test]
fn correlated_noise_is_truncated_at_the_floor_without_breaking_the_path() {
    // Levels at the floor (0.02 um, SD 0.05 um): negative readings would be common; their
    // innovations are drawn again, every reading stays >= 0 and the path keeps its correlation
    // with the previous point (not a fresh draw).
    let speeds: Vec<f64> = (0..200).map(|i| 1000.0 + 10.0 * i as f64).collect();
    let levels = vec![0.02; speeds.len()];
    let spec = correlated_spec(Correlation::GridLag1 { rho: 0.7 }, 9);
    let mut st = FloorStats::default();
    let d = apply_curves(
        &spec,
        &[Curve {
            speeds_rpm: &speeds,
            levels: &levels,
        }],
        &mut st,
    )
    .unwrap();
    assert!(st.redrawn > 0);
    assert_eq!(st.clipped_to_zero, 0);
    assert!(d.values[0].iter().all(|&y| y >= 0.0));
    // Lag-one correlation of the (centred) truncated path: about 0.45-0.5 here; fresh draws at
    // the redrawn points would give 0 +- 0.07 (1 / sqrt(199)).
    let z = &d.z.expect("z of the correlated family")[0];
    let m = z.iter().sum::<f64>() / z.len() as f64;
    let r = corr0((1..z.len()).map(|k| (z[k] - m, z[k - 1] - m)));
    assert!(r > 0.3, "lag-one correlation at the floor {r:.3}");
    // Speeds must increase along a curve.
    let bad = [1000.0, 1000.0];
    assert!(apply_curves(
        &spec,
        &[Curve {
            speeds_rpm: &bad,
            levels: &[1.0, 1.0],
        }],
        &mut FloorStats::default()
    )
    .is_err());
}

#[test]
fn kubo_correlated_readings_share_one_ar1_path_per_envelope() {
    use crate::kubo::{KFamily, KNoise};
    use rand_chacha::rand_core::SeedableRng;
    let noise = KNoise {
        family: KFamily::Correlated,
        relative: 0.02,
        floor: 0.01,
        dof: 3.0,
        quantum: 0.02,
        correlation: Some(Correlation::GridLag1 { rho: 0.8 }),
    };
    let speeds: Vec<f64> = (0..81).map(|i| 2000.0 + 100.0 * i as f64).collect();
    // Four pairs 0.5% apart around a peaked D_L (noise-free envelope far narrower than the SD
    // at low speed, where independent edge errors would cross).
    let pairs: Vec<Vec<f64>> = (0..4)
        .map(|j| {
            speeds
                .iter()
                .map(|&s| {
                    (1.0 + 0.005 * j as f64)
                        * (1.04 + 1.3 * (-((s - 6000.0) / 900.0).powi(2)).exp())
                })
                .collect()
        })
        .collect();
    let mut lag1 = Vec::new();
    for seed in 0..400u64 {
        let mut rng = rand_chacha::ChaCha20Rng::seed_from_u64(seed);
        let mut st = FloorStats::default();
        let (r, z) = noise
            .correlated_readings(&speeds, &pairs, &mut rng, &mut st)
            .unwrap();
        assert_eq!(st.redrawn, 0);
        for (p, rp) in pairs.iter().zip(&r) {
            for i in 0..speeds.len() {
                assert!(((rp[i] - p[i]) / noise.sd(p[i]) - z[i]).abs() < 1e-12);
            }
        }
        // The pairs keep their order, so min <= max and the edges are the noise-free edges' readings.
        assert!(r
            .windows(2)
            .all(|w| w[0].iter().zip(&w[1]).all(|(a, b)| b > a)));
        lag1.extend((1..speeds.len()).map(|k| (z[k], z[k - 1])));
    }
    let n = lag1.len();
    let r = corr0(lag1.into_iter());
    let se = ar1_acf_se(0.8, 1, n);
    assert!((r - 0.8).abs() < 4.0 * se, "kubo lag-1 {r:.4} (se {se:.4})");
}

#[test]
fn correlated_flags_are_checked() {
    use crate::{kubo_families, kubo_set_noise, munro_families, noise_template, set_noise};
    use crate::{Cli, Cmd};
    use clap::Parser;
    let parse = |args: &str| -> Result<Cmd, String> {
        let mut v = vec!["indep-synth"];
        v.extend(args.split_whitespace());
        Cli::try_parse_from(v)
            .map(|c| c.cmd)
            .map_err(|e| e.to_string())
    };
    let set = |args: &str| match parse(&format!("set --out /nonexistent/s {args}"))? {
        Cmd::Set(a) => set_noise(&a),
        _ => unreachable!(),
    };
    let kubo = |args: &str| match parse(&format!("kubo-set --out /nonexistent/k {args}"))? {
        Cmd::KuboSet(a) => kubo_set_noise(&a).map(|n| n.and_then(|n| n.correlation)),
        _ => unreachable!(),
    };
    let batch = |args: &str| match parse(&format!("batch --out /nonexistent/b --seeds 2 {args}"))? {
        Cmd::Batch(a) if args.contains("kubo") => kubo_families(&a).map(|(_, c)| c),
        Cmd::Batch(a) => munro_families(&a)
            .and_then(|f| noise_template(&a.common, &f))
            .map(|t| t.correlation),
        _ => unreachable!(),
    };
    let err = |r: Result<Option<Correlation>, String>, want: &str| match r {
        Ok(c) => panic!("accepted ({c:?}); expected an error with '{want}'"),
        Err(e) => assert!(e.contains(want), "error '{e}' does not say '{want}'"),
    };
    let corr = |r: Result<Option<NoiseSpec>, String>| r.map(|n| n.and_then(|n| n.correlation));

    // Accepted, and recorded as given (the default: rho 0.6 on the grid).
    assert_eq!(
        corr(set("--noise correlated")),
        Ok(Some(Correlation::GridLag1 { rho: 0.6 }))
    );
    assert_eq!(
        corr(set("--noise correlated --noise-rho 0.999")),
        Ok(Some(Correlation::GridLag1 { rho: 0.999 }))
    );
    assert_eq!(
        corr(set("--noise correlated --rho 0")),
        Ok(Some(Correlation::GridLag1 { rho: 0.0 }))
    );
    assert_eq!(
        corr(set("--noise correlated --corr-length-rpm 150")),
        Ok(Some(Correlation::LengthRpm { length_rpm: 150.0 }))
    );
    let n = set("--noise correlated --noise-um 0.05 --rho 0.8 --seed 9")
        .unwrap()
        .unwrap();
    assert_eq!(
        (n.family, n.floor_um, n.relative, n.seed),
        (Family::Correlated, 0.05, 0.03, 9)
    );
    assert!(n.describe().contains("lag-one correlation 0.8"));
    assert_eq!(corr(set("--noise relative")), Ok(None));
    assert_eq!(
        kubo("--noise correlated --noise-corr-length-rpm 300"),
        Ok(Some(Correlation::LengthRpm { length_rpm: 300.0 }))
    );
    assert_eq!(
        batch("--kind validate --families correlated,relative --rho 0.8"),
        Ok(Some(Correlation::GridLag1 { rho: 0.8 }))
    );
    assert_eq!(
        batch("--kind kubo --families correlated"),
        Ok(Some(Correlation::GridLag1 { rho: 0.6 }))
    );

    // Out of range.
    for bad in ["1", "0.9995", "-0.1", "NaN", "inf"] {
        err(
            corr(set(&format!("--noise correlated --rho {bad}"))),
            "[0, 0.999]",
        );
        err(
            kubo(&format!("--noise correlated --noise-rho {bad}")),
            "[0, 0.999]",
        );
    }
    for bad in ["0", "-5", "inf", "NaN"] {
        err(
            corr(set(&format!("--noise correlated --corr-length-rpm {bad}"))),
            "finite number of rpm > 0",
        );
        err(
            kubo(&format!("--noise correlated --corr-length-rpm {bad}")),
            "finite number of rpm > 0",
        );
        err(
            batch(&format!(
                "--kind validate --families correlated --corr-length-rpm {bad}"
            )),
            "finite number of rpm > 0",
        );
    }
    err(
        corr(set("--noise correlated --rho 0.5 --corr-length-rpm 100")),
        "not both",
    );
    err(
        corr(set("--noise correlated --noise-relative=-0.03")),
        "--noise-relative",
    );
    err(
        kubo("--noise correlated --noise-floor=-0.01"),
        "--noise-floor",
    );
    err(corr(set("--noise correlated --rho abc")), "invalid value");
    // Not applying to the family in use.
    err(
        corr(set("--noise relative --rho 0.5")),
        "applies only to the correlated family",
    );
    err(
        corr(set("--noise none --corr-length-rpm 100")),
        "applies only to the correlated family",
    );
    err(
        kubo("--noise gaussian --rho 0.5"),
        "applies only to the correlated family",
    );
    err(
        batch("--kind validate --rho 0.5"),
        "applies only to the correlated family",
    );
    err(
        batch("--kind kubo --corr-length-rpm 100"),
        "applies only to the correlated family",
    );
    err(corr(set("--noise correlation")), "unknown noise family");
}

#[test]
fn correlated_set_records_its_noise_in_rig_toml_and_truth() {
    use crate::gen::{write_set, Effect, SetSpec};
    let dir = std::env::temp_dir().join(format!("indep-synth-test-{}", std::process::id()));
    let set_dir = dir.join("set");
    let truth_path = dir.join("truth.json");
    let spec = SetSpec {
        name: "corr".into(),
        rig: Rig::munro(),
        zeta: 0.02,
        omega_n_hz: 1600.0,
        loads: vec![(3780.0, 0.3), (945.0, 3.5)],
        effect: Effect::None,
        grid: Grid::Uniform {
            start_rpm: 1000.0,
            stop_rpm: 1400.0,
            step_rpm: 100.0,
        },
        noise: Some(correlated_spec(
            Correlation::LengthRpm { length_rpm: 150.0 },
            4,
        )),
        sim: SimConfig::default(),
        extra: serde_json::Value::Null,
    };
    write_set(&spec, &set_dir, &truth_path, 5).unwrap();
    let rig = std::fs::read_to_string(set_dir.join("rig.toml")).unwrap();
    assert!(rig.contains("correlated family") && rig.contains("exp(-|s_i - s_j| / 150 rpm)"));
    let truth: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&truth_path).unwrap()).unwrap();
    let n = &truth["noise"];
    assert_eq!(n["family"], "correlated");
    assert_eq!(n["correlation"]["form"], "length_rpm");
    assert_eq!(n["correlation"]["length_rpm"], 150.0);
    assert_eq!(
        (n["floor_um"].as_f64(), n["relative"].as_f64()),
        (Some(0.05), Some(0.03))
    );
    assert_eq!(n["seed"], 4);
    let z = truth["noise_standardized_errors"].as_array().unwrap();
    assert_eq!(z.len(), 2);
    assert!(z.iter().all(|c| c.as_array().map(|v| v.len()) == Some(5)));
    let _ = std::fs::remove_dir_all(&dir);
}

/// The contact law outside geardyn's library: at the design load's mean force its local
/// stiffness is 1 (the linear model's there), at a quarter of it (1/4)^((n-1)/n), and the
/// linear law is eq. 3c's.
#[test]
fn the_contact_law_is_stiff_as_the_linear_one_at_the_design_load() {
    use crate::model::Contact;
    let fm = 0.2833;
    for n in [1.2, 1.5, 2.0] {
        let c = Contact::stiff_at(n, fm);
        let d = c.deflection(fm);
        let (f, k) = c.force(d);
        assert!((f - fm).abs() < 1e-12 && (k - 1.0).abs() < 1e-12, "{n}: {f} {k}");
        let (_, k4) = c.force(c.deflection(fm / 4.0));
        let expected = 0.25f64.powf((n - 1.0) / n);
        assert!((k4 - expected).abs() < 1e-12, "{n}: {k4} vs {expected}");
        // Odd in the penetration, so the back flank's branch mirrors the drive flank's.
        assert_eq!(c.force(-d).0, -f);
    }
    assert_eq!(Contact::LINEAR.force(0.3), (0.3, 1.0));
}
