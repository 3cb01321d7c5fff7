//! Kubo-layout sets (Kahraman & Singh 1990 Sec. 7, Fig. 23): the envelope (min and max over
//! tooth pairs) of the dynamic factor D_L = max over the steady state of (2 zeta q' + f(q)) / F_m
//! against speed, at one load.
//!
//! The scatter model is this crate's own, physically different from geardyn synth's (which
//! multiplies the nominal D_L by (1 + s z) per pair): each tooth pair j has its own STE amplitude
//! e_j = STE (1 + s_e z_j), drawn once per set (a pair's profile error does not change with
//! speed), and its own up-sweep through the nonlinear model (a pair near separation separates on
//! its own); each pair's reading at each speed then gets an independent measurement error
//! (SD = sqrt(floor^2 + (r D_L_j)^2); Gaussian, Student-t scaled to that SD, or Gaussian read to
//! a grid). The envelope is the min and max of the N readings at each speed.
//!
//! The correlated family instead reads the envelope with an error correlated along speed: one
//! standardized Gaussian AR(1) path z per set (the envelope of its one load), common to every
//! pair's reading at a speed, scaled by each reading's own SD (see [`KNoise::correlated_readings`]).

use crate::gen::{fmt_num, Grid, GENERATOR};
use crate::model::Excitation;
use crate::noise::{ar1_path, lower_z, Correlation, FloorStats, DEFAULT_RHO};
use crate::rig::Rig;
use crate::sim::{steady_state, Carried, SimConfig};
use rand::Rng;
use rand_chacha::rand_core::SeedableRng;
use rand_chacha::ChaCha20Rng;
use rand_distr::{Distribution, StandardNormal, StudentT};
use serde::{Deserialize, Serialize};
use serde_json::json;
use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

/// Kubo-like rig: the [rig] table of geardyn's data/kubo (placeholder geometry; 25/25 teeth,
/// module 4 mm, 2000 N, backlash 0.1 mm).
/// Solver settings of the Kubo mode: the default's, with a longer transient budget (zeta t = 100
/// instead of 40): near the jump of a lightly damped rig the approach to the orbit is slow (a
/// multiplier near 1) and a 64-period window of it is not the steady state. Converged points end
/// earlier, at the section repetition, so the budget only costs where it is needed.
pub fn kubo_sim(rtol: f64) -> SimConfig {
    SimConfig {
        rtol,
        atol: rtol / 100.0,
        transient_zeta_t: 100.0,
        ..SimConfig::default()
    }
}

pub const KUBO_RIG_TOML: &str = r#"[rig]
name = "Heavily damped four-square rig (placeholder geometry, Kubo-like damping)"
pinion_teeth = 25
gear_teeth = 25
module_mm = 4.0
pressure_angle_deg = 20.0
face_width_mm = 10.0
design_load_n = 2000.0
backlash_mm = 0.1
test_load_n = 2000.0
"#;

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum KFamily {
    Gaussian,
    StudentT,
    Quantized,
    /// Gaussian, SD of the others, correlated along speed (one AR(1) path per envelope).
    Correlated,
}

impl KFamily {
    #[allow(dead_code)]
    pub const ALL: [KFamily; 4] = [
        KFamily::Gaussian,
        KFamily::StudentT,
        KFamily::Quantized,
        KFamily::Correlated,
    ];
    pub fn name(self) -> &'static str {
        match self {
            KFamily::Gaussian => "gaussian",
            KFamily::StudentT => "student-t",
            KFamily::Quantized => "quantized",
            KFamily::Correlated => "correlated",
        }
    }
    pub fn parse(s: &str) -> Result<KFamily, String> {
        match s {
            "gaussian" | "normal" => Ok(KFamily::Gaussian),
            "student-t" | "student_t" | "t" => Ok(KFamily::StudentT),
            "quantized" | "grid" => Ok(KFamily::Quantized),
            "correlated" => Ok(KFamily::Correlated),
            _ => Err(format!(
                "unknown kubo noise family '{s}' (gaussian, student-t, quantized, correlated, none)"
            )),
        }
    }
}

/// Measurement error of one pair's reading of D_L.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct KNoise {
    pub family: KFamily,
    /// Relative part: SD r x D_L_j.
    pub relative: f64,
    /// Floor in D_L (added in quadrature).
    pub floor: f64,
    /// Degrees of freedom of the Student-t family.
    pub dof: f64,
    /// Reading grid of the quantized family (D_L units).
    pub quantum: f64,
    /// Correlation along speed of the correlated family (absent for the others, whose truth
    /// records are unchanged by it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub correlation: Option<Correlation>,
}

impl KNoise {
    pub fn sd(&self, level: f64) -> f64 {
        (self.floor.powi(2) + (self.relative * level).powi(2)).sqrt()
    }
    pub fn describe(&self) -> String {
        let independent = |tail: String| {
            format!(
                "each tooth pair's reading of D_L has an independent error of SD sqrt({}^2 + ({} x D_L_pair)^2), {tail}",
                self.floor, self.relative
            )
        };
        match self.family {
            KFamily::Gaussian => independent("Gaussian".into()),
            KFamily::StudentT => {
                independent(format!("Student-t with {} dof scaled to that SD", self.dof))
            }
            KFamily::Quantized => independent(format!(
                "Gaussian, then read to a {} grid (as a digitized figure)",
                self.quantum
            )),
            KFamily::Correlated => format!(
                "the envelope is read with an error correlated along speed: Gaussian, one standardized error path z per envelope, common to the tooth pairs at each speed, each pair's reading D_L_pair + SD z_i with SD = sqrt({}^2 + ({} x D_L_pair)^2), so each edge of the envelope carries SD(edge) z_i; z a stationary AR(1) in increasing speed, {}",
                self.floor,
                self.relative,
                self.correlation().describe()
            ),
        }
    }

    /// The correlation of the correlated family ([`DEFAULT_RHO`] on the grid if none was set).
    pub fn correlation(&self) -> Correlation {
        self.correlation
            .unwrap_or(Correlation::GridLag1 { rho: DEFAULT_RHO })
    }

    /// Correlated family: every pair's readings along the speeds (increasing) with one
    /// standardized error path z common to the pairs, reading_ji = D_ji + SD(D_ji) z_i; returns
    /// (readings per pair, z).
    ///
    /// z is a stationary Gaussian AR(1) in increasing speed ([`ar1_path`], innovations from
    /// `rng`). Since y -> y + SD(y) z_i is increasing in y (its slope 1 + z_i r^2 y / SD(y) >=
    /// 1 - |z_i| r > 0 for any |z_i| < 1 / r), the envelope's edges are the readings of the
    /// noise-free edges: min_i + SD(min_i) z_i and max_i + SD(max_i) z_i, each with exactly the
    /// family's error, and min <= max is kept (independent errors on the two edges would cross
    /// where the noise-free envelope is narrower than the reading error, as it is at low speed).
    /// A z_i that would make a reading negative has its innovation drawn again (counted in
    /// `stats`).
    pub fn correlated_readings<R: Rng>(
        &self,
        speeds_rpm: &[f64],
        pair_levels: &[Vec<f64>],
        rng: &mut R,
        stats: &mut FloorStats,
    ) -> Result<(Vec<Vec<f64>>, Vec<f64>), String> {
        let correlation = self.correlation();
        correlation.check()?;
        let phis = correlation.phis(speeds_rpm)?;
        if pair_levels.iter().any(|l| l.len() != speeds_rpm.len()) {
            return Err("kubo noise: a pair has not as many levels as speeds".into());
        }
        // The most restrictive bound over the pairs at each speed.
        let lower: Vec<f64> = (0..speeds_rpm.len())
            .map(|i| {
                pair_levels
                    .iter()
                    .map(|l| lower_z(l[i], self.sd(l[i])))
                    .fold(f64::NEG_INFINITY, f64::max)
            })
            .collect();
        let z = ar1_path(rng, &phis, &lower, stats);
        let readings = pair_levels
            .iter()
            .map(|l| {
                l.iter()
                    .zip(&z)
                    .map(|(&d, &zi)| (d + self.sd(d) * zi).max(0.0))
                    .collect()
            })
            .collect();
        Ok((readings, z))
    }

    /// One noisy reading (redrawn while negative; quantized readings rounded to the grid).
    /// Independent families only (the correlated one: [`KNoise::correlated_readings`]).
    pub fn draw<R: Rng>(&self, level: f64, rng: &mut R, t: &StudentT<f64>) -> (f64, usize) {
        let sd = self.sd(level);
        let t_sd = if self.dof > 2.0 {
            (self.dof / (self.dof - 2.0)).sqrt()
        } else {
            1.0
        };
        let mut redrawn = 0;
        let mut y = level;
        for _ in 0..1000 {
            let z: f64 = match self.family {
                KFamily::StudentT => t.sample(rng) / t_sd,
                _ => rng.sample(StandardNormal),
            };
            y = level + sd * z;
            if y >= 0.0 {
                break;
            }
            redrawn += 1;
        }
        let mut y = y.max(0.0);
        if self.family == KFamily::Quantized {
            y = (y / self.quantum).round() * self.quantum;
        }
        (y, redrawn)
    }
}

#[derive(Clone, Debug)]
pub struct KuboSpec {
    pub name: String,
    pub rig: Rig,
    pub zeta: f64,
    pub omega_n_hz: f64,
    /// Nominal first-harmonic STE amplitude (um) at the test load.
    pub ste_um: f64,
    pub tooth_pairs: usize,
    /// Relative SD of each pair's STE amplitude (drawn once per set).
    pub pair_ste_scatter: f64,
    pub grid: Grid,
    /// None: noise-free readings (each pair's D_L as simulated).
    pub noise: Option<KNoise>,
    /// Seeds of the pair STE draws and of the reading errors.
    pub pair_seed: u64,
    pub noise_seed: u64,
    /// Write [ste] amplitude_um (the nominal STE) into rig.toml.
    pub ste_in_rig: bool,
    pub sim: SimConfig,
    /// Threads over the pairs' sweeps within this set.
    pub threads: usize,
    pub extra: serde_json::Value,
}

impl KuboSpec {
    pub fn load_n(&self) -> f64 {
        self.rig
            .table
            .get("test_load_n")
            .and_then(|v| v.as_float().or(v.as_integer().map(|i| i as f64)))
            .unwrap_or(self.rig.design_load_n)
    }
}

#[derive(Clone, Debug, Serialize)]
pub struct DlPoint {
    pub speed_rpm: f64,
    pub omega: f64,
    pub dynamic_factor: f64,
    pub period: Option<usize>,
    pub transient_periods: usize,
}

#[derive(Clone, Debug, Serialize)]
pub struct DlCurve {
    pub ste_um: f64,
    pub fm: f64,
    pub fah: f64,
    pub points: Vec<DlPoint>,
    pub seconds: f64,
}

/// Noise-free D_L up-sweep of the model at one STE amplitude: state carried from speed to speed,
/// starting from the static equilibrium q = 1 + F_m, q' = 0 at the lowest speed.
pub fn dl_curve(
    rig: &Rig,
    zeta: f64,
    omega_n_hz: f64,
    load: f64,
    ste_um: f64,
    speeds: &[f64],
    sim: &SimConfig,
) -> Result<DlCurve, String> {
    let t0 = Instant::now();
    let b = rig.b_um();
    let (kh, _) = rig.mesh_stiffness();
    let fm = load / (b * kh);
    let fah = ste_um / b;
    let mut carried = Carried::new(1.0 + fm, 0.0);
    let mut points = Vec::with_capacity(speeds.len());
    for &rpm in speeds {
        let ex = Excitation {
            zeta,
            omega: rig.omega(rpm, omega_n_hz),
            fm,
            fah,
            fah2: 0.0,
            phi2: 0.0,
            fat: 0.0,
            psi_t: 0.0,
            eps: 0.0,
            psi_k: 0.0,
            contact: crate::model::Contact::LINEAR,
        };
        let sp = steady_state(&ex, &mut carried, sim)
            .map_err(|e| format!("STE {ste_um} um, {rpm} rpm: integration failed: {e}"))?;
        points.push(DlPoint {
            speed_rpm: rpm,
            omega: ex.omega,
            dynamic_factor: sp.force_max / fm,
            period: sp.period,
            transient_periods: sp.transient_periods,
        });
    }
    Ok(DlCurve {
        ste_um,
        fm,
        fah,
        points,
        seconds: t0.elapsed().as_secs_f64(),
    })
}

/// Each pair's STE factor 1 + s_e z_j (z_j standard normal; a factor below 0.2 is drawn again).
pub fn pair_factors(n: usize, s_e: f64, seed: u64) -> Vec<f64> {
    let mut rng = ChaCha20Rng::seed_from_u64(seed);
    (0..n)
        .map(|_| loop {
            let z: f64 = rng.sample(StandardNormal);
            let f = 1.0 + s_e * z;
            if f > 0.2 {
                break f;
            }
        })
        .collect()
}

fn toml_str(s: &str) -> String {
    toml::Value::String(s.to_string()).to_string()
}

pub fn scatter_text(spec: &KuboSpec) -> String {
    format!(
        "indep-synth pair model: {} tooth pairs, each with its own STE amplitude e_j = STE (1 + {} z_j), z_j standard normal drawn once per set, simulated through the nonlinear model (its own carried up-sweep); envelope = min and max over the pairs' readings at each speed",
        spec.tooth_pairs, spec.pair_ste_scatter
    )
}

pub fn rig_toml(spec: &KuboSpec) -> String {
    let mut s = String::new();
    s.push_str(&spec.rig.rig_table_text());
    s.push('\n');
    if spec.ste_in_rig {
        s.push_str("[ste]\n");
        let _ = writeln!(s, "load_n = [{:?}]", spec.load_n());
        let _ = writeln!(s, "amplitude_um = [{:?}]", spec.ste_um);
        s.push('\n');
    }
    s.push_str("[source]\n");
    s.push_str("kind = \"synthetic\"\n");
    let _ = writeln!(
        s,
        "citation = {}",
        toml_str("Synthetic stand-in imitating Kubo's dynamic-factor envelope over tooth pairs as shown in Kahraman & Singh (1990) Fig. 23: simulated by an independent generator, not measured")
    );
    s.push_str("figure = \"layout of Fig. 23 (envelope of tooth pairs)\"\n");
    let _ = writeln!(s, "generator = {}", toml_str(GENERATOR));
    let noise = match &spec.noise {
        Some(n) => format!("synthetic reading error: {}", n.describe()),
        None => "none (noise-free pair readings)".to_string(),
    };
    let _ = writeln!(s, "uncertainty = {}", toml_str(&noise));
    let _ = writeln!(
        s,
        "method = {}",
        toml_str(&format!(
            "up-sweep (speed increasing, state carried from speed to speed, a rig run-up); D_L = max over the steady state of (2 zeta q' + f(q)) / F_m; scatter: {}",
            scatter_text(spec)
        ))
    );
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

pub struct KWritten {
    pub seconds: f64,
    pub nominal: DlCurve,
    pub not_period1: usize,
}

/// Simulates the nominal curve and every pair, draws the readings, writes DIR/rig.toml +
/// DIR/dynamic_factor.csv and the truth JSON.
pub fn write_kubo_set(
    spec: &KuboSpec,
    dir: &Path,
    truth_path: &Path,
    digits: usize,
) -> Result<KWritten, String> {
    let t0 = Instant::now();
    let speeds = spec.grid.speeds();
    let load = spec.load_n();
    let factors = pair_factors(spec.tooth_pairs, spec.pair_ste_scatter, spec.pair_seed);
    // Curve 0 is the nominal STE, curves 1..=N the pairs.
    let stes: Vec<f64> = std::iter::once(spec.ste_um)
        .chain(factors.iter().map(|f| spec.ste_um * f))
        .collect();
    let mut curves: Vec<Option<Result<DlCurve, String>>> = (0..stes.len()).map(|_| None).collect();
    {
        let next = std::sync::atomic::AtomicUsize::new(0);
        let slots = std::sync::Mutex::new(&mut curves);
        std::thread::scope(|s| {
            for _ in 0..spec.threads.max(1) {
                s.spawn(|| loop {
                    let i = next.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
                    if i >= stes.len() {
                        break;
                    }
                    let c = dl_curve(
                        &spec.rig,
                        spec.zeta,
                        spec.omega_n_hz,
                        load,
                        stes[i],
                        &speeds,
                        &spec.sim,
                    )
                    .map_err(|e| format!("{}: curve {i}: {e}", spec.name));
                    slots.lock().unwrap()[i] = Some(c);
                });
            }
        });
    }
    let mut done = Vec::with_capacity(stes.len());
    for c in curves {
        done.push(c.expect("every curve computed")?);
    }
    let nominal = done.remove(0);
    let pairs = done;

    // Readings: pair-major order of draws from one stream (pair j, then speed i).
    let mut readings = vec![vec![0.0; speeds.len()]; pairs.len()];
    let mut redrawn = 0usize;
    let mut noise_z = None;
    match &spec.noise {
        Some(n) if n.family == KFamily::Correlated => {
            let mut rng = ChaCha20Rng::seed_from_u64(spec.noise_seed);
            let levels: Vec<Vec<f64>> = pairs
                .iter()
                .map(|c| c.points.iter().map(|p| p.dynamic_factor).collect())
                .collect();
            let mut stats = FloorStats::default();
            let (r, z) = n
                .correlated_readings(&speeds, &levels, &mut rng, &mut stats)
                .map_err(|e| format!("{}: {e}", spec.name))?;
            readings = r;
            redrawn = stats.redrawn;
            noise_z = Some(z);
        }
        Some(n) => {
            let mut rng = ChaCha20Rng::seed_from_u64(spec.noise_seed);
            let t = StudentT::new(n.dof).map_err(|e| format!("dof: {e}"))?;
            for (j, c) in pairs.iter().enumerate() {
                for (i, p) in c.points.iter().enumerate() {
                    let (y, r) = n.draw(p.dynamic_factor, &mut rng, &t);
                    readings[j][i] = y;
                    redrawn += r;
                }
            }
        }
        None => {
            for (j, c) in pairs.iter().enumerate() {
                for (i, p) in c.points.iter().enumerate() {
                    readings[j][i] = p.dynamic_factor;
                }
            }
        }
    }
    let mut csv = String::from("speed_rpm,dynamic_factor_min,dynamic_factor_max\n");
    let mut env = Vec::with_capacity(speeds.len());
    for (i, &rpm) in speeds.iter().enumerate() {
        let lo = readings.iter().map(|r| r[i]).fold(f64::INFINITY, f64::min);
        let hi = readings
            .iter()
            .map(|r| r[i])
            .fold(f64::NEG_INFINITY, f64::max);
        // Round both edges to the printed digits first so that min <= max holds as printed.
        let _ = writeln!(csv, "{},{:.*},{:.*}", fmt_num(rpm), digits, lo, digits, hi);
        env.push(json!({"speed_rpm": rpm, "min": lo, "max": hi}));
    }
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    std::fs::write(dir.join("rig.toml"), rig_toml(spec)).map_err(|e| e.to_string())?;
    std::fs::write(dir.join("dynamic_factor.csv"), csv).map_err(|e| e.to_string())?;

    let (kh, kh_source) = spec.rig.mesh_stiffness();
    let not_period1 = nominal
        .points
        .iter()
        .chain(pairs.iter().flat_map(|c| c.points.iter()))
        .filter(|p| p.period != Some(1))
        .count();
    let seconds = t0.elapsed().as_secs_f64();
    let mut truth = json!({
        "name": spec.name,
        "kind": "kubo",
        "generator": GENERATOR,
        "set_dir": dir.display().to_string(),
        "zeta": spec.zeta,
        "omega_n_hz": spec.omega_n_hz,
        "ste_um": spec.ste_um,
        "ste_in_rig_toml": spec.ste_in_rig,
        "load_n": load,
        "fm": nominal.fm,
        "fah": nominal.fah,
        "fhat": nominal.fm / nominal.fah,
        "rig_name": spec.rig.name,
        "backlash_mm": spec.rig.backlash_mm,
        "half_backlash_um": spec.rig.b_um(),
        "mesh_stiffness_n_per_um": kh,
        "mesh_stiffness_source": kh_source,
        "pinion_teeth": spec.rig.pinion_teeth,
        "tooth_pairs": spec.tooth_pairs,
        "pair_ste_scatter": spec.pair_ste_scatter,
        "pair_ste_factors": factors,
        "pair_ste_um": stes[1..].to_vec(),
        "scatter_model": scatter_text(spec),
        "noise": spec.noise,
        "noise_family": spec.noise.as_ref().map(|n| n.family.name()).unwrap_or("none"),
        "noise_redrawn": redrawn,
        "pair_seed": spec.pair_seed,
        "noise_seed": spec.noise_seed,
        "grid": spec.grid,
        "speeds_rpm": speeds,
        "dynamic_factor_definition": "max over the steady state (the orbit's p periods, else a 64-period window) of (2 zeta q' + k f(q)) / F_m",
        "integrator": {
            "method": "Dopri5 (Dormand-Prince 5(4), ode_solvers 0.6), restarted at each crossing of q = +-1; mesh-force maxima located on a quintic Hermite interpolant of each step",
            "rtol": spec.sim.rtol,
            "atol": spec.sim.atol,
            "sweep": "up (speed increasing), state carried; start at q = 1 + F_m, q' = 0",
            "transient": format!("until the section at forcing phase 0 repeats (max norm < {}) at a lag p <= {}, at most zeta t = {} (5 x while it repeats to 1e-4)", spec.sim.section_tol, spec.sim.max_period, spec.sim.transient_zeta_t),
        },
        "points_not_period1": not_period1,
        "extra": spec.extra,
        "seconds": seconds,
        "nominal": nominal,
        "pairs": pairs,
        "readings": readings,
        "envelope": env,
    });
    if let Some(z) = noise_z {
        // Correlated family only (the other families' truth files are unchanged): the drawn
        // standardized error path, common to the pairs, one value per speed.
        truth["noise_standardized_errors"] = json!(z);
    }
    if let Some(parent) = truth_path.parent() {
        std::fs::create_dir_all(parent).map_err(|e| e.to_string())?;
    }
    std::fs::write(truth_path, serde_json::to_string_pretty(&truth).unwrap())
        .map_err(|e| e.to_string())?;
    Ok(KWritten {
        seconds,
        nominal,
        not_period1,
    })
}
