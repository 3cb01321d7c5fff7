//! Checks of the generator against closed forms and its own tighter runs (no geardyn involved).

use crate::gen::Grid;
use crate::model::Excitation;
use crate::noise::{apply, Family, FloorStats, NoiseSpec};
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
    for fam in Family::ALL {
        let spec = NoiseSpec {
            family: fam,
            floor_um: 0.15,
            relative: 0.03,
            dof: 3.0,
            quantum_um: 0.25,
            seed: 7,
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
        let c = dl_curve(&rig, zeta, fn_hz, 2000.0, 3.0, &speeds, &SimConfig::default()).unwrap();
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
            assert!(y.iter().all(|v| ((v / 0.02) - (v / 0.02).round()).abs() < 1e-9));
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
