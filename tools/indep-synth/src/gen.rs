//! One Munro-layout set: noise-free up-sweeps per load, noise, rig.toml + dte.csv, truth JSON.

use crate::model::{Contact, Excitation};
use crate::noise::{self, FloorStats, NoiseSpec};
use crate::rig::Rig;
use crate::sim::{steady_state, Carried, SimConfig};
use rand::Rng;
use rand_chacha::rand_core::SeedableRng;
use rand_chacha::ChaCha20Rng;
use serde::Serialize;
use serde_json::json;
use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

pub const GENERATOR: &str = "indep-synth 0.1 (independent of geardyn: Dopri5 from ode_solvers 0.6 with event location at q = +-1, rtol 1e-10; noise from rand_chacha/rand_distr)";

/// The hidden effect (names as geardyn's discover reports them).
#[derive(Clone, Copy, Debug, Serialize)]
#[serde(tag = "name", rename_all = "snake_case")]
pub enum Effect {
    None,
    /// k(t) = 1 + eps cos(Omega t + phase).
    MeshStiffnessVariation {
        eps: f64,
        phase_rad: f64,
    },
    /// Second STE harmonic r2 F_ah sin(2 Omega t + phase).
    SteHarmonics {
        r2: f64,
        phase_rad: f64,
    },
    /// External force ratio F_m(design) sin(Omega t + phase) at every load.
    TorqueRipple {
        ratio: f64,
        phase_rad: f64,
    },
    /// Contact force c (q - 1)^exponent instead of q - 1, the local stiffness 1 at the design
    /// load's mean deflection (outside geardyn's library: the stiffness grows with the load).
    ContactLaw {
        exponent: f64,
    },
}

impl Effect {
    pub fn label(&self) -> &'static str {
        match self {
            Effect::None => "none",
            Effect::MeshStiffnessVariation { .. } => "mesh_stiffness_variation",
            Effect::SteHarmonics { .. } => "ste_harmonics",
            Effect::TorqueRipple { .. } => "torque_ripple",
            Effect::ContactLaw { .. } => "contact_law",
        }
    }
    pub fn strength(&self) -> Option<f64> {
        match *self {
            Effect::None => None,
            Effect::MeshStiffnessVariation { eps, .. } => Some(eps),
            Effect::SteHarmonics { r2, .. } => Some(r2),
            Effect::TorqueRipple { ratio, .. } => Some(ratio),
            Effect::ContactLaw { exponent } => Some(exponent),
        }
    }
}

#[derive(Clone, Debug, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Grid {
    Uniform {
        start_rpm: f64,
        stop_rpm: f64,
        step_rpm: f64,
    },
    Nonuniform {
        n: usize,
        lo_rpm: f64,
        hi_rpm: f64,
        seed: u64,
        decimals: u32,
    },
}

impl Grid {
    pub fn speeds(&self) -> Vec<f64> {
        match *self {
            Grid::Uniform {
                start_rpm,
                stop_rpm,
                step_rpm,
            } => {
                let n = ((stop_rpm - start_rpm) / step_rpm + 1e-9).floor() as usize;
                (0..=n).map(|i| start_rpm + i as f64 * step_rpm).collect()
            }
            Grid::Nonuniform {
                n,
                lo_rpm,
                hi_rpm,
                seed,
                decimals,
            } => {
                let mut rng = ChaCha20Rng::seed_from_u64(seed);
                let scale = 10f64.powi(decimals as i32);
                let mut v: Vec<f64> = Vec::with_capacity(n);
                while v.len() < n {
                    let x = (rng.random_range(lo_rpm..=hi_rpm) * scale).round() / scale;
                    if !v.iter().any(|&y| (y - x).abs() < 0.5 / scale) {
                        v.push(x);
                    }
                }
                v.sort_by(|a, b| a.partial_cmp(b).unwrap());
                v
            }
        }
    }
}

#[derive(Clone, Debug)]
pub struct SetSpec {
    pub name: String,
    pub rig: Rig,
    pub zeta: f64,
    pub omega_n_hz: f64,
    /// (load N, first-harmonic STE amplitude um), design load first as in Munro's figures.
    pub loads: Vec<(f64, f64)>,
    pub effect: Effect,
    pub grid: Grid,
    /// None: noise-free set (for checking conventions only).
    pub noise: Option<NoiseSpec>,
    pub sim: SimConfig,
    /// Extra facts for the truth file (batch, draws).
    pub extra: serde_json::Value,
}

#[derive(Clone, Debug, Serialize)]
pub struct CleanPoint {
    pub speed_rpm: f64,
    pub omega: f64,
    pub dte_pp_um: f64,
    /// Least period of the steady state found (forcing periods), null when the section did not
    /// repeat within the transient budget (chaotic or still converging: the pp is then one
    /// 64-period window).
    pub period: Option<usize>,
    pub transient_periods: usize,
    pub section_distance: f64,
}

#[derive(Clone, Debug, Serialize)]
pub struct CleanCurve {
    pub load_n: f64,
    pub ste_um: f64,
    pub fm: f64,
    pub fah: f64,
    pub fhat: f64,
    pub points: Vec<CleanPoint>,
    pub steps: u64,
    pub seconds: f64,
}

fn excitation(spec: &SetSpec, load: f64, ste: f64, rpm: f64) -> Excitation {
    let rig = &spec.rig;
    let b = rig.b_um();
    let (kh, _) = rig.mesh_stiffness();
    let fah = ste / b;
    let mut ex = Excitation {
        zeta: spec.zeta,
        omega: rig.omega(rpm, spec.omega_n_hz),
        fm: load / (b * kh),
        fah,
        fah2: 0.0,
        phi2: 0.0,
        fat: 0.0,
        psi_t: 0.0,
        eps: 0.0,
        psi_k: 0.0,
        contact: Contact::LINEAR,
    };
    match spec.effect {
        Effect::None => {}
        Effect::MeshStiffnessVariation { eps, phase_rad } => {
            ex.eps = eps;
            ex.psi_k = phase_rad;
        }
        Effect::SteHarmonics { r2, phase_rad } => {
            ex.fah2 = r2 * fah;
            ex.phi2 = phase_rad;
        }
        Effect::TorqueRipple { ratio, phase_rad } => {
            ex.fat = ratio * rig.design_load_n / (b * kh);
            ex.psi_t = phase_rad;
        }
        Effect::ContactLaw { exponent } => {
            ex.contact = Contact::stiff_at(exponent, rig.design_load_n / (b * kh));
        }
    }
    ex
}

/// Noise-free up-sweep at one load: the state is carried from speed to speed (a rig run-up),
/// starting from the static equilibrium q = 1 + F_m, q' = 0 at the lowest speed.
pub fn clean_curve(
    spec: &SetSpec,
    load: f64,
    ste: f64,
    speeds: &[f64],
) -> Result<CleanCurve, String> {
    let t0 = Instant::now();
    let b = spec.rig.b_um();
    let ex0 = excitation(spec, load, ste, speeds[0]);
    let mut carried = Carried::new(1.0 + ex0.contact.deflection(ex0.fm), 0.0);
    let mut points = Vec::with_capacity(speeds.len());
    let mut steps = 0;
    for &rpm in speeds {
        let ex = excitation(spec, load, ste, rpm);
        let sp = steady_state(&ex, &mut carried, &spec.sim).map_err(|e| {
            format!(
                "{}: load {load} N, {rpm} rpm: integration failed: {e}",
                spec.name
            )
        })?;
        steps += sp.steps;
        points.push(CleanPoint {
            speed_rpm: rpm,
            omega: ex.omega,
            dte_pp_um: b * sp.x_pp,
            period: sp.period,
            transient_periods: sp.transient_periods,
            section_distance: sp.section_distance,
        });
    }
    Ok(CleanCurve {
        load_n: load,
        ste_um: ste,
        fm: ex0.fm,
        fah: ex0.fah,
        fhat: ex0.fm / ex0.fah,
        points,
        steps,
        seconds: t0.elapsed().as_secs_f64(),
    })
}

/// Compact number text: integers without a decimal point, else the shortest round-trip form.
pub fn fmt_num(x: f64) -> String {
    if x == x.trunc() && x.abs() < 1e15 {
        format!("{}", x as i64)
    } else {
        format!("{x}")
    }
}

fn toml_str(s: &str) -> String {
    toml::Value::String(s.to_string()).to_string()
}

/// rig.toml of the set: the template's [rig] (no zeta / omega_n_hz, no [ste], no [noise]: the fit
/// must estimate them), and [source] saying it is synthetic, what it imitates and how it was made.
/// The truth is NOT written here (blind test); `[source.truth]` (which geardyn's loader requires
/// for synthetic data, never read by a fit) only says where it is kept.
pub fn rig_toml(spec: &SetSpec) -> String {
    let mut s = String::new();
    s.push_str(&spec.rig.rig_table_text());
    s.push('\n');
    s.push_str("[source]\n");
    s.push_str("kind = \"synthetic\"\n");
    let _ = writeln!(
        s,
        "citation = {}",
        toml_str("Synthetic stand-in imitating Munro (1962) four-square rig curves as shown in Kahraman & Singh (1990) Figs 19-22 (pp DTE against speed at several loads): simulated by an independent generator, not measured")
    );
    s.push_str("figure = \"layout of Figs 19-22 (one curve per load)\"\n");
    let _ = writeln!(s, "generator = {}", toml_str(GENERATOR));
    let noise = match &spec.noise {
        Some(n) => n.describe(),
        None => "none (noise-free curves)".to_string(),
    };
    let _ = writeln!(s, "uncertainty = {}", toml_str(&noise));
    s.push_str("method = \"up-sweep (speed increasing, state carried from speed to speed, a rig run-up); pp of x = q + e/b over the steady state\"\n");
    s.push('\n');
    s.push_str("[source.truth]\n");
    let _ = writeln!(
        s,
        "withheld = {}",
        toml_str(&format!(
            "blind test set '{}': the generating parameters are kept outside this folder (the batch's truth/{}.json)",
            spec.name, spec.name
        ))
    );
    s
}

pub struct Written {
    pub curves: Vec<CleanCurve>,
    pub floor: FloorStats,
    pub seconds: f64,
}

/// Simulates, adds noise, writes DIR/rig.toml + DIR/dte.csv and the truth JSON.
pub fn write_set(
    spec: &SetSpec,
    dir: &Path,
    truth_path: &Path,
    digits: usize,
) -> Result<Written, String> {
    let t0 = Instant::now();
    let speeds = spec.grid.speeds();
    let mut curves = Vec::new();
    for &(load, ste) in &spec.loads {
        curves.push(clean_curve(spec, load, ste, &speeds)?);
    }
    // One noise curve per load, in the order of the CSV (design load first, speeds increasing).
    let levels: Vec<Vec<f64>> = curves
        .iter()
        .map(|c| c.points.iter().map(|p| p.dte_pp_um).collect())
        .collect();
    let mut floor = FloorStats::default();
    let (values, noise_z) = match &spec.noise {
        Some(n) => {
            let noise_curves: Vec<noise::Curve<'_>> = levels
                .iter()
                .map(|l| noise::Curve {
                    speeds_rpm: &speeds,
                    levels: l,
                })
                .collect();
            let drawn = noise::apply_curves(n, &noise_curves, &mut floor)
                .map_err(|e| format!("{}: {e}", spec.name))?;
            (drawn.values.concat(), drawn.z)
        }
        None => (levels.concat(), None),
    };
    let mut csv = String::from("load_n,speed_rpm,dte_pp_um\n");
    let mut i = 0;
    for c in &curves {
        for p in &c.points {
            let _ = writeln!(
                csv,
                "{},{},{:.*}",
                fmt_num(c.load_n),
                fmt_num(p.speed_rpm),
                digits,
                values[i]
            );
            i += 1;
        }
    }
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    std::fs::write(dir.join("rig.toml"), rig_toml(spec)).map_err(|e| e.to_string())?;
    std::fs::write(dir.join("dte.csv"), csv).map_err(|e| e.to_string())?;

    let (kh, kh_source) = spec.rig.mesh_stiffness();
    let seconds = t0.elapsed().as_secs_f64();
    let mut truth = json!({
        "name": spec.name,
        "generator": GENERATOR,
        "set_dir": dir.display().to_string(),
        "zeta": spec.zeta,
        "omega_n_hz": spec.omega_n_hz,
        "effect": spec.effect,
        "effect_name": spec.effect.label(),
        "effect_strength": spec.effect.strength(),
        "loads": spec.loads.iter().map(|&(l, e)| json!({"load_n": l, "ste_um": e})).collect::<Vec<_>>(),
        "rig_name": spec.rig.name,
        "design_load_n": spec.rig.design_load_n,
        "backlash_mm": spec.rig.backlash_mm,
        "half_backlash_um": spec.rig.b_um(),
        "mesh_stiffness_n_per_um": kh,
        "mesh_stiffness_source": kh_source,
        "pinion_teeth": spec.rig.pinion_teeth,
        "grid": spec.grid,
        "speeds_rpm": speeds,
        "noise": spec.noise,
        "noise_floor_handling": "a draw giving a negative pp is drawn again (noise truncated at -level); quantized readings may round to 0",
        "floor_stats": floor,
        "integrator": {
            "method": "Dopri5 (Dormand-Prince 5(4), ode_solvers 0.6), restarted at each crossing of q = +-1 located on a quintic Hermite interpolant of the accepted step and re-integrated to the root",
            "rtol": spec.sim.rtol,
            "atol": spec.sim.atol,
            "sweep": "up (speed increasing), state carried; start at q = 1 + F_m, q' = 0",
            "transient": format!("until the section at forcing phase 0 repeats (max norm < {}) at a lag p <= {}, at most zeta t = {}", spec.sim.section_tol, spec.sim.max_period, spec.sim.transient_zeta_t),
            "window": format!("pp of x = q + e/b over the found period, else over {} forcing periods; the state carried on is that at the end of a {}-period window", spec.sim.window_periods, spec.sim.window_periods),
        },
        "extra": spec.extra,
        "seconds": seconds,
        "clean": curves,
    });
    if let Some(z) = noise_z {
        // Correlated family only (the other families' truth files are unchanged): the drawn
        // standardized errors, one list per load in the order of `clean`.
        truth["noise_standardized_errors"] = json!(z);
    }
    if let Some(parent) = truth_path.parent() {
        std::fs::create_dir_all(parent).map_err(|e| e.to_string())?;
    }
    std::fs::write(truth_path, serde_json::to_string_pretty(&truth).unwrap())
        .map_err(|e| e.to_string())?;
    Ok(Written {
        curves,
        floor,
        seconds,
    })
}
