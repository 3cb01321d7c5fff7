//! The gear pair and its frequencies on the command line: dimensionless (`--fm --fah --zeta
//! --omega`, the paper's eq. 5), or in the rig's units (`--rig rig.toml --load-n --ste-um --zeta
//! --omega-n-hz --speed-rpm`), converted by the library's `OperatingPoint` (paper Sec. 2.1).

use super::geometry_excitation::{geometry_error, ExcitationArgs};
use super::limits::{check_range, real, FAH, FM, OMEGA, ZETA};
use anyhow::Context;
use clap::Args as ClapArgs;
use geardyn::data::{load_gear_pair, load_rig_with_geometry};
use geardyn::model::{GearPair, OperatingPoint, Term, MAX_DTE_UM, MAX_LOAD_N};
use geardyn::numeric::to_significant;
use geardyn::validate::{GearMesh, GeometryOperatingPoint, GeometryOptions, StiffnessChoice};
use std::path::PathBuf;

/// Parameters of eq. 5, dimensionless or in the rig's units.
#[derive(ClapArgs, Debug, Clone)]
pub struct ModelArgs {
    /// Mean load F_m = F̄_m / (b k_h), dimensionless, in [0, 1e4]; harmonic balance (hbm)
    /// needs F_m > 0, simulate the unloaded case (or --rig with --load-n).
    #[arg(long = "fm", allow_hyphen_values = true, value_parser = real(FM.0, FM.1, false),
          required_unless_present = "rig", conflicts_with = "rig")]
    pub fm: Option<f64>,
    /// STE amplitude F_ah = ē / b, dimensionless, in [0, 1e3]; force ratio F̂ = F_m / F_ah (or
    /// --rig with --ste-um).
    #[arg(long = "fah", allow_hyphen_values = true, value_parser = real(FAH.0, FAH.1, false),
          required_unless_present = "rig", conflicts_with = "rig")]
    pub fah: Option<f64>,
    /// Damping ratio ζ, dimensionless, in [0.001, 0.9]; with --rig the default is rig.toml's
    /// `zeta`.
    #[arg(long, allow_hyphen_values = true, value_parser = real(ZETA.0, ZETA.1, false),
          required_unless_present = "rig")]
    pub zeta: Option<f64>,
    /// The gear pair's rig.toml (docs/data-format.md; `geardyn init-data` writes one): give
    /// --load-n, --ste-um, --omega-n-hz and --speed-rpm in the rig's units instead of --fm,
    /// --fah and --omega. The conversion is printed to standard error.
    #[arg(long, value_name = "FILE")]
    pub rig: Option<PathBuf>,
    /// Mean load F̄_m transmitted by the mesh, N, in (0, 1e8] (default: the rig's
    /// design_load_n).
    #[arg(long, value_name = "N", requires = "rig", allow_hyphen_values = true,
          value_parser = real(0.0, MAX_LOAD_N, true))]
    pub load_n: Option<f64>,
    /// STE amplitude ē (half the static transmission error's peak-to-peak), µm, in (0, 1000]
    /// (default: rig.toml's [ste] amplitude at the load).
    #[arg(long, value_name = "UM", requires = "rig", allow_hyphen_values = true,
          value_parser = real(0.0, MAX_DTE_UM, true))]
    pub ste_um: Option<f64>,
    /// Natural frequency f_n = ω_n / 2π of the mesh, Hz, in [1, 1e6] (default: rig.toml's
    /// omega_n_hz).
    #[arg(long, value_name = "HZ", requires = "rig", allow_hyphen_values = true,
          value_parser = real(OMEGA_N_HZ.0, OMEGA_N_HZ.1, false))]
    pub omega_n_hz: Option<f64>,
    /// External torque amplitude F_aT of eq. 4, dimensionless (a force F_aT sin(Ω t) at the
    /// mesh frequency, Ω_T = Ω_h as in Sec. 8.1), in [0, 1e3]; with --fah 0 the model is eq. 4
    /// alone, otherwise both excitations act together (or --rig with --torque-n).
    #[arg(long = "fat", allow_hyphen_values = true, value_parser = real(FAH.0, FAH.1, false),
          conflicts_with = "rig")]
    pub fat: Option<f64>,
    /// External torque amplitude of eq. 4 as a mesh force T̄_a / r_b, N, in [0, 1e8] (with
    /// --rig; F_aT = T̄_a / (r_b b k_h)). Default 0: no external torque.
    #[arg(long, value_name = "N", requires = "rig", allow_hyphen_values = true,
          value_parser = real(0.0, MAX_LOAD_N, false))]
    pub torque_n: Option<f64>,
}

/// The model's dimensionless parameters and, with `--rig`, the operating point they came from.
#[derive(Clone, Debug)]
pub struct Model {
    pub fm: f64,
    pub fah: f64,
    /// External torque amplitude F_aT of eq. 4 (0: the paper's eq. 5 alone).
    pub fat: f64,
    pub zeta: f64,
    /// The rig's units (None: dimensionless use).
    pub rig: Option<OperatingPoint>,
    /// Where zeta and f_n came from (an option or rig.toml), for the printed conversion.
    origins: Vec<String>,
    /// With `--excitation geometry`: the model at Omega = 1 with the geometry's STE and
    /// stiffness harmonics, and how they were made.
    geometry: Option<GeometryExcitation>,
}

/// The excitation of `--excitation geometry`, made by the library's tooth-contact model.
#[derive(Clone, Debug)]
struct GeometryExcitation {
    point: GeometryOperatingPoint,
    stiffness: StiffnessChoice,
    relief_rule: String,
    harmonics: usize,
}

/// A value from its option, else from rig.toml's `[rig] rig_key`, else an error naming both;
/// checked against `bounds` (the option's range).
fn option_or_rig(
    (option, flag): (Option<f64>, &str),
    (rig_value, rig_key): (Option<f64>, &str),
    bounds: (f64, f64),
    origins: &mut Vec<String>,
) -> anyhow::Result<f64> {
    let (v, origin) = match (option, rig_value) {
        (Some(v), _) => (v, flag.to_string()),
        (None, Some(v)) => (v, format!("rig.toml [rig] {rig_key}")),
        (None, None) => {
            anyhow::bail!("{flag} is needed with --rig (rig.toml gives no `{rig_key}` in [rig])")
        }
    };
    check_range(&origin, rig_key, v, bounds)?;
    origins.push(format!("{rig_key} = {v} from {origin}"));
    Ok(v)
}

impl ModelArgs {
    /// The model these options describe; with `--rig` the rig file is read and every value
    /// converted (and checked against the dimensionless ranges, naming the option).
    pub fn resolve(&self) -> anyhow::Result<Model> {
        let Some(path) = &self.rig else {
            // clap lets a `requires = "rig"` option through when an option that conflicts
            // with --rig (--fm) is present, so the rig-unit options are checked here.
            let rig_only = [
                ("--load-n", self.load_n),
                ("--ste-um", self.ste_um),
                ("--omega-n-hz", self.omega_n_hz),
                ("--torque-n", self.torque_n),
            ];
            if let Some((flag, _)) = rig_only.iter().find(|(_, v)| v.is_some()) {
                anyhow::bail!(
                    "{flag} is in the rig's units and needs --rig rig.toml (dimensionless: --fm, \
                     --fah, --fat)"
                );
            }
            return Ok(Model {
                fm: self.fm.context("--fm is required")?,
                fah: self.fah.context("--fah is required")?,
                fat: self.fat.unwrap_or(0.0),
                zeta: self.zeta.context("--zeta is required")?,
                rig: None,
                origins: Vec::new(),
                geometry: None,
            });
        };
        let (rig_table, ste_table) = load_gear_pair(path)?;
        let rig = &rig_table;
        let dim = rig.dimensional()?;
        let mut origins = Vec::new();
        let load = self.load_n.unwrap_or(rig.design_load_n);
        let ste = match (
            self.ste_um,
            ste_table.as_ref().and_then(|t| t.amplitude_at(load)),
        ) {
            (Some(e), _) => e,
            (None, Some(e)) => {
                origins.push(format!("ē = {e} µm at {load} N from rig.toml [ste]"));
                e
            }
            (None, None) => anyhow::bail!(
                "--ste-um is needed: rig.toml {} lists no STE amplitude at {load} N",
                path.display()
            ),
        };
        let (zeta, f_n) = self.damping_and_frequency(rig, &mut origins)?;
        let op = OperatingPoint::new(dim, load, ste, zeta, f_n)?;
        self.checked_model(op, "--ste-um", origins, None)
    }

    /// zeta and f_n from their options, else from rig.toml's [rig] (each noted in `origins`).
    fn damping_and_frequency(
        &self,
        rig: &geardyn::data::Rig,
        origins: &mut Vec<String>,
    ) -> anyhow::Result<(f64, f64)> {
        let zeta = option_or_rig((self.zeta, "--zeta"), (rig.zeta, "zeta"), ZETA, origins)?;
        let f_n = option_or_rig(
            (self.omega_n_hz, "--omega-n-hz"),
            (rig.omega_n_hz, "omega_n_hz"),
            OMEGA_N_HZ,
            origins,
        )?;
        Ok((zeta, f_n))
    }

    /// The model of `op` (and the geometry's excitation, if any), its F_m, F_ah (given by
    /// `ste_flag`) and F_aT checked against their ranges.
    fn checked_model(
        &self,
        op: OperatingPoint,
        ste_flag: &str,
        origins: Vec<String>,
        geometry: Option<GeometryExcitation>,
    ) -> anyhow::Result<Model> {
        let (fm, fah) = (op.mean_force(), op.ste_amplitude());
        check_range("--load-n", "gives F_m", fm, FM)?;
        check_range(ste_flag, "gives F_ah", fah, FAH)?;
        let fat = op.dim.mean_force(self.torque_n.unwrap_or(0.0));
        check_range("--torque-n", "gives F_aT", fat, FAH)?;
        Ok(Model {
            fm,
            fah,
            fat,
            zeta: op.zeta,
            rig: Some(op),
            origins,
            geometry,
        })
    }

    /// As [`ModelArgs::resolve`], with the excitation of `excitation`: with `--excitation
    /// geometry` the STE harmonics and the mesh stiffness come from rig.toml's gears.
    pub fn resolve_with(&self, excitation: &ExcitationArgs) -> anyhow::Result<Model> {
        if !excitation.uses_geometry()? {
            return self.resolve();
        }
        let Some(path) = &self.rig else {
            anyhow::bail!("--excitation geometry needs --rig rig.toml (the gears are in it)");
        };
        if self.ste_um.is_some() {
            anyhow::bail!(
                "--ste-um and --excitation geometry both give the STE: leave out --ste-um (the \
                 tooth-contact model gives it) or use --excitation rig"
            );
        }
        let (rig_file, geometry) = load_rig_with_geometry(path)?;
        let rig = &rig_file.rig;
        let mut origins = Vec::new();
        let (zeta, f_n) = self.damping_and_frequency(rig, &mut origins)?;
        let load = self.load_n.unwrap_or(rig.design_load_n);
        let r = &excitation.relief;
        let options = GeometryOptions {
            relief_length_mm: r.relief_length_mm,
            relief_shape: r.shape(),
            profile: r.profile()?,
            ..GeometryOptions::design_rule(geometry)
        };
        let mesh = GearMesh::new(rig, &options)
            .map_err(|e| geometry_error(path, "the gear geometry of", e))?;
        let (relief_um, relief_rule) = match (r.tip_relief_um, r.tip_relief_design_load_n) {
            (Some(a), _) => (a, "given".to_string()),
            (None, design) => {
                let at = design.unwrap_or(rig.design_load_n);
                (
                    mesh.design_rule_um(at)?,
                    format!("sized for minimum STE pp at {at} N"),
                )
            }
        };
        let stiffness = excitation.stiffness();
        let point = mesh.operating_point(
            rig,
            load,
            relief_um,
            excitation.ste_harmonics as u32,
            stiffness,
            zeta,
            f_n,
        )?;
        let op = point.op.clone();
        let geometry = GeometryExcitation {
            point,
            stiffness,
            relief_rule,
            harmonics: excitation.ste_harmonics,
        };
        self.checked_model(op, "--excitation geometry", origins, Some(geometry))
    }
}

impl ModelArgs {
    /// The model at the one frequency of `f`: resolved, its conversion printed (rig units) and
    /// checked, before any work.
    pub fn at_frequency(&self, f: &Frequency) -> anyhow::Result<(Model, f64, GearPair)> {
        self.model_at_frequency(self.resolve()?, f)
    }

    /// As [`ModelArgs::at_frequency`], with the excitation of `excitation`.
    pub fn at_frequency_with(
        &self,
        f: &Frequency,
        excitation: &ExcitationArgs,
    ) -> anyhow::Result<(Model, f64, GearPair)> {
        self.model_at_frequency(self.resolve_with(excitation)?, f)
    }

    fn model_at_frequency(
        &self,
        m: Model,
        f: &Frequency,
    ) -> anyhow::Result<(Model, f64, GearPair)> {
        let omega = f.omega(&m)?;
        m.print_conversion(omega);
        let model = m.at(omega)?;
        Ok((m, omega, model))
    }
}

impl Model {
    /// The paper's model (eq. 5, with eq. 4's torque when F_aT > 0) at frequency `omega`.
    pub fn at(&self, omega: f64) -> anyhow::Result<GearPair> {
        if let Some(g) = &self.geometry {
            let mut pair = g.point.model.clone();
            if self.fat > 0.0 {
                pair.torque = vec![Term::new(1, self.fat)];
            }
            return Ok(pair.at_omega(omega)?);
        }
        Ok(GearPair::excited(
            self.fm, self.fah, self.fat, self.zeta, omega,
        )?)
    }

    /// The forcing of the describing-function solution (STE and external torque).
    pub fn forcing(&self) -> geardyn::hb::DfForcing {
        geardyn::hb::DfForcing {
            ste: self.fah,
            torque: self.fat,
        }
    }

    /// Print the conversion to standard error (rig units only), with `omega` as the example.
    pub fn print_conversion(&self, omega: f64) {
        if let Some(op) = &self.rig {
            for line in op.conversion_lines(num_value(op.speed_rpm(omega))) {
                eprintln!("{line}");
            }
            if self.fat > 0.0 {
                eprintln!(
                    "  F_aT = T̄_a / (r_b b k_h) = {} N / (b k_h) = {:.6} (external torque of eq. 4)",
                    num(self.torque_n()),
                    self.fat
                );
            }
            if let Some(g) = &self.geometry {
                for line in g.lines() {
                    eprintln!("{line}");
                }
            }
            if !self.origins.is_empty() {
                eprintln!("  ({})", self.origins.join("; "));
            }
        }
    }

    /// The external torque's amplitude as a mesh force T̄_a / r_b, N (rig units only; 0
    /// otherwise).
    fn torque_n(&self) -> f64 {
        self.rig
            .as_ref()
            .map_or(0.0, |op| self.fat / op.mean_force() * op.load_n)
    }

    /// The parameters for a plot caption, briefly: the rig's units, or the dimensionless values.
    pub fn caption(&self) -> String {
        match &self.rig {
            Some(op) => format!(
                "load {} N, {}{}, ζ {}, f_n {} Hz",
                op.load_n,
                match &self.geometry {
                    Some(g) => g.caption(),
                    None => format!("ē {} µm", op.ste_um),
                },
                if self.fat > 0.0 {
                    format!(", torque {} N", num(self.torque_n()))
                } else {
                    String::new()
                },
                op.zeta,
                num(op.omega_n_hz)
            ),
            None => format!(
                "F_m {}, F_ah {}{}, ζ {}",
                num(self.fm),
                num(self.fah),
                if self.fat > 0.0 {
                    format!(", F_aT {}", num(self.fat))
                } else {
                    String::new()
                },
                self.zeta
            ),
        }
    }

    /// The parameters as JSON: the dimensionless ones, and the rig's units when given.
    pub fn json(&self) -> serde_json::Value {
        let mut v =
            serde_json::json!({"fm": self.fm, "fah": self.fah, "fat": self.fat, "zeta": self.zeta});
        if let Some(op) = &self.rig {
            v["load_n"] = op.load_n.into();
            v["ste_um"] = op.ste_um.into();
            v["omega_n_hz"] = op.omega_n_hz.into();
            v["torque_n"] = num_value(self.torque_n()).into();
            v["half_backlash_um"] = (op.dim.half_backlash_m * 1e6).into();
            v["mesh_stiffness_n_per_um"] = (op.dim.mesh_stiffness_n_per_m * 1e-6).into();
            v["mesh_stiffness_source"] = op.dim.stiffness_source.tag().into();
            v["pinion_teeth"] = op.dim.pinion_teeth.into();
        }
        if let Some(g) = &self.geometry {
            v["excitation"] = g.json();
        }
        v
    }
}

impl GeometryExcitation {
    /// The excitation in words, after the conversion: the relief and every harmonic.
    fn lines(&self) -> Vec<String> {
        let p = &self.point;
        let mut out = vec![format!(
            "  excitation from the gear geometry (geardyn mesh) at {} N: tip relief {:.3} µm ({}), \
             STE pp {:.3} µm, k_h(F) {:.1} N/µm, contact loss {:.1}% of the mesh period",
            p.op.load_n,
            p.relief_um,
            self.relief_rule,
            p.excitation.ste_pp_um,
            p.excitation.mesh_stiffness_mean_n_per_um,
            100.0 * p.excitation.contact_loss_fraction
        )];
        match self.stiffness {
            StiffnessChoice::Geometry => out.extend([
                format!(
                    "    f_n = {} Hz at the design load {} N (k_h {:.3} N/µm), scaled to this \
                     load's stiffness with the same mass: {} Hz × √({:.3} / {:.3}) = {:.2} Hz",
                    num(p.omega_n_design_hz),
                    num(p.design_load_n),
                    p.design_stiffness_n_per_um,
                    num(p.omega_n_design_hz),
                    p.excitation.mesh_stiffness_mean_n_per_um,
                    p.design_stiffness_n_per_um,
                    p.op.omega_n_hz,
                ),
                "    effective excitation (the model's STE terms below): the loaded STE less the \
                 static deflection F̄_m / k(t) that the model's own k(t) makes, so that the two \
                 add up to the loaded STE; these are not the STE's own harmonics (geardyn mesh \
                 lists those)"
                    .to_string(),
            ]),
            StiffnessChoice::Constant => out.push(format!(
                "    constant mesh stiffness (--mesh-stiffness constant): k_h = {:.3} N/µm as \
                 above, not the tooth-contact model's {:.3} N/µm, and f_n = {} Hz as given; the \
                 model's STE terms below are the loaded STE's own harmonics",
                p.op.dim.mesh_stiffness_n_per_m * 1e-6,
                p.excitation.mesh_stiffness_mean_n_per_um,
                num(p.op.omega_n_hz)
            )),
        }
        let model = &p.model;
        for s in model.ste.iter().take(self.harmonics) {
            let k =
                model
                    .stiffness
                    .iter()
                    .find(|k| k.order == s.order)
                    .map_or(String::new(), |k| {
                        format!(
                            ", ε_{} = {:.5}, ψ_{} = {:.4} rad",
                            k.order, k.amplitude, k.order, k.phase
                        )
                    });
            out.push(format!(
                "    F_ah{} = {:.6} (ē_{} = {:.4} µm), φ_{} = {:.4} rad{k}",
                s.order,
                s.amplitude,
                s.order,
                p.op.micrometres(s.amplitude),
                s.order,
                s.phase
            ));
        }
        let rest = &model.ste[self.harmonics.min(model.ste.len())..];
        if let Some(largest) = rest.iter().map(|s| s.amplitude).reduce(f64::max) {
            out.push(format!(
                "    and orders {} to {} (the static deflection's harmonics above the stiffness's, \
                 each at most {:.4} µm): the excitation of a time-varying k(t) is the STE less \
                 the deflection F̄_m / k(t) the model makes itself",
                rest[0].order,
                rest[rest.len() - 1].order,
                p.op.micrometres(largest)
            ));
        }
        out
    }

    /// For plot captions.
    fn caption(&self) -> String {
        format!(
            "excitation from geometry (relief {:.1} µm, {} harmonics{})",
            self.point.relief_um,
            self.harmonics,
            match self.stiffness {
                StiffnessChoice::Geometry => ", k(t)",
                StiffnessChoice::Constant => "",
            }
        )
    }

    fn json(&self) -> serde_json::Value {
        let p = &self.point;
        serde_json::json!({
            "source": "geometry",
            "relief_um": p.relief_um,
            "relief_rule": self.relief_rule,
            "mesh_stiffness": match self.stiffness {
                StiffnessChoice::Geometry => "geometry",
                StiffnessChoice::Constant => "constant",
            },
            "ste_pp_um": p.excitation.ste_pp_um,
            "loaded_mesh_stiffness_n_per_um": p.excitation.mesh_stiffness_mean_n_per_um,
            "contact_loss_fraction": p.excitation.contact_loss_fraction,
            "ste_terms": p.model.ste,
            "stiffness_terms": p.model.stiffness,
        })
    }
}

/// A steady state in the rig's units: speed, mesh frequency, q_a, q_m, the q range and the pp
/// DTE in µm (b times the dimensionless values), and the peak mesh force D_L F̄_m in N.
#[derive(serde::Serialize)]
pub struct SteadyInRigUnits {
    speed_rpm: f64,
    mesh_freq_hz: f64,
    qa_um: f64,
    qm_um: f64,
    q_min_um: f64,
    q_max_um: f64,
    dte_pp_um: f64,
    mesh_force_max_n: Option<f64>,
}

impl SteadyInRigUnits {
    /// The steady state `s` at `omega` in the rig's units (None for dimensionless use).
    pub fn new(model: &Model, omega: f64, s: &geardyn::sim::SteadyState) -> Option<Self> {
        let op = model.rig.as_ref()?;
        let um = |x: f64| num_value(op.micrometres(x));
        Some(SteadyInRigUnits {
            speed_rpm: num_value(op.speed_rpm(omega)),
            mesh_freq_hz: num_value(op.mesh_frequency_hz(omega)),
            qa_um: um(s.qa),
            qm_um: um(s.qm),
            q_min_um: um(s.q_min),
            q_max_um: um(s.q_max),
            dte_pp_um: um(s.dte_pp),
            mesh_force_max_n: s.dl_max.map(|d| num_value(op.mesh_force_n(d))),
        })
    }

    /// One line of text: pp DTE and peak mesh force, with `detail` the speed and q_a, q_m too.
    pub fn text(&self, detail: bool) -> String {
        let force = self
            .mesh_force_max_n
            .map_or(String::new(), |f| format!(", peak mesh force {f:.0} N"));
        if detail {
            format!(
                "at {} rpm (mesh frequency {} Hz): pp DTE {:.3} µm, b q_a {:.3} µm, b q_m {:.3} µm{force}",
                self.speed_rpm, self.mesh_freq_hz, self.dte_pp_um, self.qa_um, self.qm_um
            )
        } else {
            format!("pp DTE {:.3} µm{force}", self.dte_pp_um)
        }
    }

    /// As JSON (null for dimensionless use).
    pub fn json(me: &Option<Self>) -> serde_json::Value {
        serde_json::to_value(me).unwrap_or_default()
    }
}

/// One frequency: Omega_h, or a pinion speed with `--rig`.
#[derive(ClapArgs, Debug, Clone)]
pub struct Frequency {
    /// Mesh frequency over natural frequency Ω_h = Ω̄_h / ω_n, dimensionless, in [0.001, 100]
    /// (or --rig with --speed-rpm).
    #[arg(long, allow_hyphen_values = true, value_parser = real(OMEGA.0, OMEGA.1, false),
          required_unless_present = "speed_rpm")]
    pub omega: Option<f64>,
    /// Pinion speed n, rpm, in [0.01, 1e6] (with --rig; mesh frequency = pinion teeth × n / 60).
    #[arg(long, value_name = "RPM", requires = "rig", conflicts_with = "omega",
          allow_hyphen_values = true, value_parser = real(SPEED_RPM.0, SPEED_RPM.1, false))]
    pub speed_rpm: Option<f64>,
}

/// Plausible natural frequencies, Hz (as rig.toml's omega_n_hz).
const OMEGA_N_HZ: (f64, f64) = (1.0, 1e6);

/// Plausible pinion speeds, rpm (as in the data sets' CSV files).
const SPEED_RPM: (f64, f64) = (0.01, 1e6);

impl Frequency {
    /// Omega_h, converted from the speed with the rig's units.
    pub fn omega(&self, model: &Model) -> anyhow::Result<f64> {
        match (self.omega, self.speed_rpm, &model.rig) {
            (Some(w), _, _) => Ok(w),
            (None, Some(n), Some(op)) => speed_to_omega("--speed-rpm", n, op),
            _ => anyhow::bail!("give --omega, or --speed-rpm with --rig"),
        }
    }
}

/// A range of frequencies: Omega_h or pinion speeds (with `--rig`), START:STOP:STEP.
#[derive(ClapArgs, Debug, Clone)]
pub struct FrequencyRange {
    /// Ω_h range START:STOP:STEP, dimensionless (START, STOP in [0.001, 100]; at most 100000
    /// values), e.g. 0.2:1.6:0.01 (or --rig with --speed-rpm).
    #[arg(
        long,
        allow_hyphen_values = true,
        required_unless_present = "speed_rpm"
    )]
    pub omega: Option<String>,
    /// Pinion speed range START:STOP:STEP, rpm (START, STOP in [0.01, 1e6]; at most 100000
    /// values), e.g. 1000:5000:50 (with --rig).
    #[arg(
        long,
        value_name = "RPM",
        requires = "rig",
        conflicts_with = "omega",
        allow_hyphen_values = true
    )]
    pub speed_rpm: Option<String>,
}

impl FrequencyRange {
    /// The Omega_h grid (made by index, see `frequency_range`); with `--speed-rpm`, the speeds'
    /// Omega_h, each checked against the Omega range.
    pub fn omegas(&self, model: &Model) -> anyhow::Result<Vec<f64>> {
        match (&self.omega, &self.speed_rpm, &model.rig) {
            (Some(text), _, _) => parse_range("--omega", text, OMEGA),
            (None, Some(text), Some(op)) => parse_range("--speed-rpm", text, SPEED_RPM)?
                .into_iter()
                .map(|n| speed_to_omega("--speed-rpm", n, op))
                .collect(),
            _ => anyhow::bail!("give --omega, or --speed-rpm with --rig"),
        }
    }

    /// The range as typed, for messages.
    pub fn text(&self) -> String {
        match (&self.omega, &self.speed_rpm) {
            (Some(t), _) => format!("--omega {t}"),
            (None, Some(t)) => format!("--speed-rpm {t}"),
            _ => String::new(),
        }
    }
}

/// Omega_h of a pinion speed, which must fall in the Omega range.
fn speed_to_omega(flag: &str, speed_rpm: f64, op: &OperatingPoint) -> anyhow::Result<f64> {
    let w = op.omega(speed_rpm);
    if !(OMEGA.0..=OMEGA.1).contains(&w) {
        anyhow::bail!(
            "{flag}: {speed_rpm} rpm is Ω_h = {w:.4e} at f_n = {} Hz and {} pinion teeth: \
             must be in [{}, {}]",
            op.omega_n_hz,
            op.dim.pinion_teeth,
            OMEGA.0,
            OMEGA.1
        );
    }
    Ok(w)
}

/// Parse START:STOP:STEP (or one value) with START and STOP in `bounds` into the grid of
/// `geardyn::sim::frequency_range`, at most 100000 values.
pub fn parse_range(flag: &str, text: &str, bounds: (f64, f64)) -> anyhow::Result<Vec<f64>> {
    let parts: Vec<&str> = text.split(':').collect();
    let num = |s: &str, what: &str| -> anyhow::Result<f64> {
        s.trim().parse::<f64>().map_err(|_| {
            anyhow::anyhow!(
                "{flag} '{text}': {what} '{s}' is not a number; expected START:STOP:STEP"
            )
        })
    };
    let bounded = |s: &str, what: &str| -> anyhow::Result<f64> {
        let v = num(s, what)?;
        check_range(&format!("{flag} '{text}'"), what, v, bounds)?;
        Ok(v)
    };
    let (a, b, step) = match parts.as_slice() {
        [one] => {
            let w = bounded(one, "value")?;
            (w, w, 1.0)
        }
        [a, b, c] => (bounded(a, "START")?, bounded(b, "STOP")?, num(c, "STEP")?),
        _ => anyhow::bail!("{flag} '{text}': expected START:STOP:STEP, e.g. 0.3:1.5:0.01"),
    };
    if b < a {
        anyhow::bail!("{flag} '{text}': STOP must not be below START");
    }
    if !(step.is_finite() && step > 0.0) {
        anyhow::bail!("{flag} '{text}': STEP must be a positive finite number");
    }
    let count = (b - a) / step + 1.0;
    if count > 100_000.0 {
        anyhow::bail!("{flag} '{text}': {count:.0} values, at most 100000; use a larger STEP");
    }
    Ok(geardyn::sim::frequency_range(a, b, step)?)
}

/// A number for text and CSV output: its value to 10 significant digits, printed as briefly as
/// that allows (1.2, not 1.2000000000000002).
pub fn num(x: f64) -> String {
    format!("{}", num_value(x))
}

/// The value printed by [`num`].
pub fn num_value(x: f64) -> f64 {
    to_significant(x, 10)
}
