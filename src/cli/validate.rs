//! `geardyn validate munro|kubo`: fit, predict, compare, and write fits/ and reports/.

use super::common::{check_out_dir, check_out_replaced, print_text, EscapeArgs};
use super::geometry_excitation::{Shape, Stiffness};
use super::progress_bar::Bar;
use clap::{Args as ClapArgs, Subcommand, ValueEnum};
use geardyn::data::{load_kubo, load_munro, load_rig_with_geometry};
use geardyn::report::{
    data_kind_banner, interval_digits, write_kubo_report, write_munro_report, MunroFigures,
};
use geardyn::validate::{
    spread_interval, validate_kubo, validate_munro, CorrelationChoice, DesignModel,
    GeometryOptions, KuboFitPath, KuboOptions, KuboValidation, LoadResult, MunroOptions,
    ReliefRule, SteMode, PAIR_SPREAD,
};
use std::path::PathBuf;

#[derive(ClapArgs, Debug)]
pub struct Args {
    #[command(subcommand)]
    which: Which,
}

#[derive(Subcommand, Debug)]
enum Which {
    /// Peak-to-peak DTE curves at several loads (Munro layout, Figs 19-22): fit zeta and f_n at
    /// the design load, predict the other loads.
    #[command(after_help = super::examples::VALIDATE_MUNRO)]
    Munro(MunroArgs),
    /// Dynamic-factor envelope at one load (Kubo layout, Fig. 23).
    #[command(after_help = super::examples::VALIDATE_KUBO)]
    Kubo(KuboArgs),
}

#[derive(ClapArgs, Debug)]
struct Dirs {
    /// Data set folder (rig.toml + CSV curves, docs/data-format.md); default: the shipped
    /// data/munro or data/kubo, relative to the current folder.
    #[arg(long)]
    data: Option<PathBuf>,
    /// Not an option of `validate` (the analysis commands' `--rig FILE`): refused with a hint
    /// to give the data set's folder as `--data`, which holds its rig.toml.
    #[arg(long, hide = true)]
    rig: Option<PathBuf>,
    /// Folder for the fitted-parameter JSON.
    #[arg(long, default_value = "fits")]
    fits: PathBuf,
    /// Parent folder of the report folder (reports/munro or reports/kubo).
    #[arg(long, default_value = "reports")]
    reports: PathBuf,
}

#[derive(ClapArgs, Debug)]
struct KuboArgs {
    #[command(flatten)]
    dirs: Dirs,
    /// What zeta and omega_n are fitted to (when rig.toml does not give them). auto: the part
    /// of the envelope where the teeth stay in contact (closed form, hundredths of a second),
    /// the whole curve when that part does not determine zeta; contact: that part only; whole:
    /// the whole curve through simulated up-sweeps, the peak and jump included (narrower
    /// intervals, about 10 s).
    #[arg(long, value_enum, default_value_t = KuboFit::Auto)]
    fit: KuboFit,
    /// Hold the STE amplitude at rig.toml's value. By default a stated STE is where the fit
    /// starts it: a nominal STE held as exact biases zeta and narrows its interval.
    #[arg(long)]
    hold_ste: bool,
    /// Errors correlated along speed (docs/correlated-errors.md). off (the default here, until
    /// a coverage study of the Kubo fits with it): independent errors; auto: estimated, and kept
    /// when the data reject independent errors; on: always estimated.
    #[arg(long, value_enum, default_value_t = CorrelationArg::Off)]
    correlation: CorrelationArg,
}

#[derive(ValueEnum, Debug, Clone, Copy, PartialEq, Eq)]
enum KuboFit {
    Auto,
    Contact,
    Whole,
}

impl KuboFit {
    fn path(self) -> KuboFitPath {
        match self {
            KuboFit::Auto => KuboFitPath::Auto,
            KuboFit::Contact => KuboFitPath::ContactPart,
            KuboFit::Whole => KuboFitPath::WholeCurve,
        }
    }
}

#[derive(ClapArgs, Debug)]
struct MunroArgs {
    #[command(flatten)]
    dirs: Dirs,
    /// Where the STE at the predicted loads comes from: each curve's low-speed part, or (beside
    /// it, both reported) the gear geometry of rig.toml with a tip relief.
    #[arg(long, value_enum, default_value_t = Ste::Curve)]
    ste: Ste,
    /// Geometry path: the tip relief depth. design-rule: sized for minimum STE peak-to-peak at
    /// the design load (Munro's gears); fit: fitted to the design-load curve with zeta, omega_n;
    /// given: --tip-relief-um.
    #[arg(long, value_enum, default_value_t = Relief::DesignRule)]
    relief: Relief,
    /// Geometry path: the relief depth, µm (with --relief given).
    #[arg(long, allow_hyphen_values = true)]
    tip_relief_um: Option<f64>,
    /// Geometry path: relief length along the line of action, mm (default: Harris's long
    /// relief, (eps_alpha - 1) p_b).
    #[arg(long, allow_hyphen_values = true)]
    relief_length_mm: Option<f64>,
    /// Geometry path: relief shape.
    #[arg(long, value_enum, default_value_t = Shape::Linear)]
    relief_shape: Shape,
    /// Geometry path: number of STE harmonics in the model, 1 to 5 (1 is the paper's model).
    #[arg(long, default_value_t = 1)]
    ste_harmonics: u32,
    /// Geometry path: mesh stiffness of the predictions. constant: k = 1, k_h as the per-curve
    /// path; geometry: the loaded k_h(F) and k(t) of the geometry (DOP853, ~30 s).
    #[arg(long, value_enum, default_value_t = Stiffness::Constant)]
    mesh_stiffness: Stiffness,
    /// Figures: fit the pp DTE axis to every attractor, far ones included. By default it fits
    /// the data and the two sweeps, and attractors beyond are arrows on the frame, counted in
    /// the legend, so a few far attractors do not squeeze the curves.
    #[arg(long)]
    all_attractors_in_range: bool,
    /// Errors correlated along speed within a curve (docs/correlated-errors.md). auto:
    /// estimated, and kept when the data reject independent errors; off: independent errors;
    /// on: always estimated. Default: auto, or the length rig.toml's [noise] correlation_rpm
    /// states.
    #[arg(long, value_enum)]
    correlation: Option<CorrelationArg>,
    /// The predictions' attractor searches (25 speeds, 7 x 7 initial conditions each).
    #[command(flatten)]
    escape: EscapeArgs,
}

#[derive(ValueEnum, Debug, Clone, Copy, PartialEq, Eq)]
enum CorrelationArg {
    Auto,
    Off,
    On,
}

impl CorrelationArg {
    fn choice(self) -> CorrelationChoice {
        match self {
            CorrelationArg::Auto => CorrelationChoice::Auto,
            CorrelationArg::Off => CorrelationChoice::Off,
            CorrelationArg::On => CorrelationChoice::On,
        }
    }
}

#[derive(ValueEnum, Debug, Clone, Copy, PartialEq, Eq)]
enum Ste {
    Curve,
    Geometry,
}

#[derive(ValueEnum, Debug, Clone, Copy, PartialEq, Eq)]
enum Relief {
    DesignRule,
    Fit,
    Given,
}

impl MunroArgs {
    /// The STE mode; the geometry is read from `rig` (its [geometry] table).
    fn ste_mode(&self, rig: &std::path::Path) -> anyhow::Result<SteMode> {
        if self.ste == Ste::Curve {
            if self.relief != Relief::DesignRule || self.tip_relief_um.is_some() {
                anyhow::bail!("--relief and --tip-relief-um apply to --ste geometry only");
            }
            return Ok(SteMode::Curve);
        }
        let relief = match (self.relief, self.tip_relief_um) {
            (Relief::Given, Some(a)) => ReliefRule::Given { amount_um: a },
            (Relief::Given, None) => anyhow::bail!("--relief given needs --tip-relief-um"),
            (_, Some(_)) => anyhow::bail!("--tip-relief-um needs --relief given"),
            (Relief::DesignRule, None) => ReliefRule::DesignRule,
            (Relief::Fit, None) => ReliefRule::Fit,
        };
        let (_, geometry) = load_rig_with_geometry(rig)?;
        Ok(SteMode::Geometry(Box::new(GeometryOptions {
            relief,
            relief_length_mm: self.relief_length_mm,
            relief_shape: self.relief_shape.relief_shape(),
            ste_harmonics: self.ste_harmonics,
            stiffness: self.mesh_stiffness.choice(),
            ..GeometryOptions::design_rule(geometry)
        })))
    }
}

/// One load's line of the summary.
fn load_line(l: &LoadResult) -> String {
    format!(
        "  {:>7.1} N {:>10}: F_hat {:6.2}, STE {:.3} um, RMS {:.3} um{}, jump error {}\n",
        l.load_n,
        if l.fitted { "(fit)" } else { "(predicted)" },
        l.force_ratio,
        l.ste_um,
        l.rms_um,
        match (l.not_period1_points, l.rms_period1_um) {
            (0, _) => String::new(),
            (n, Some(r)) => format!(
                " ({r:.3} um where the model is period-1; {n} speeds chaotic or subharmonic)"
            ),
            (n, None) => format!(" ({n} speeds chaotic or subharmonic)"),
        },
        l.jump_error_text(" rpm")
    )
}

pub fn run(a: Args) -> anyhow::Result<()> {
    let d = match &a.which {
        Which::Munro(m) => &m.dirs,
        Which::Kubo(k) => &k.dirs,
    };
    if let Some(rig) = &d.rig {
        anyhow::bail!(
            "validate reads a whole data set: give its folder as --data DIR (rig.toml and the CSV curves), not --rig {}",
            rig.display()
        );
    }
    check_out_dir("--fits", &d.fits)?;
    let report = match &a.which {
        Which::Munro(_) => "munro",
        Which::Kubo(_) => "kubo",
    };
    check_out_replaced("--reports", &d.reports.join(report))?;
    let (written, banner, summary) = match a.which {
        Which::Munro(m) => {
            let dir = data_dir(m.dirs.data.as_deref(), "munro")?;
            let data = load_munro(&dir)?;
            let defaults = MunroOptions::default();
            let opts = MunroOptions {
                ste: m.ste_mode(&dir.join("rig.toml"))?,
                escape: m.escape.budget(defaults.escape),
                correlation: m.correlation.map(CorrelationArg::choice),
                ..defaults
            };
            let r = validate_munro(&data, &opts, &Bar::new())?;
            let unused = data.ste_loads_without_curve();
            let d = m.dirs;
            let figures = MunroFigures {
                all_attractors_in_range: m.all_attractors_in_range,
            };
            let written =
                write_munro_report(&data, &r, &figures, &d.fits, &d.reports.join("munro"))?;
            let mut s = format!(
                "zeta {}, omega_n {} Hz\n",
                value_ci(r.zeta, r.fit.estimate.ci95[0], 4),
                value_ci(r.omega_n_hz, r.fit.estimate.ci95[1], 1)
            );
            if !unused.is_empty() {
                s.push_str(&format!(
                    "WARNING: rig.toml [ste] states an STE at {} N, where no CSV file has a curve (their loads: {} N): it is not used\n",
                    geardyn::data::loads_text(&unused),
                    geardyn::data::loads_text(&data.loads())
                ));
            }
            if r.fit.design_model == DesignModel::Swept {
                s.push_str(
                    "design-load fit through simulated up-sweeps: the teeth separate at some speeds under eq. 13's closed form\n",
                );
            }
            s.push_str(&format!(
                "noise: {}\n",
                geardyn::report::noise_summary(&r.fit.estimate)
            ));
            let names = geardyn::report::munro_curve_names(&r);
            if let Some(c) = geardyn::report::correlation_summary(&r.fit.estimate, &names) {
                s.push_str(&format!("{c}\n"));
            }
            if let Some(t) = geardyn::report::munro_stated_ste_text(&r) {
                s.push_str(&format!("{t}\n"));
            }
            if r.geometry.is_some() {
                s.push_str("STE read from each curve:\n");
            }
            for l in &r.loads {
                s.push_str(&load_line(l));
            }
            if let Some(g) = &r.geometry {
                let e = &g.fit.estimate;
                s.push_str(&format!(
                    "STE from the geometry (relief {:.2} um, {}): zeta {}, omega_n {} Hz, fitted at the design load alone\n",
                    g.relief.relief_um,
                    match g.relief.relief_rule {
                        ReliefRule::DesignRule => "design rule: minimum STE pp at the design load".to_string(),
                        ReliefRule::Given { .. } => "given".to_string(),
                        ReliefRule::Fit => format!("fitted, {}", ci_text(e.ci95[2], 2)),
                    },
                    value_ci(g.zeta, e.ci95[0], 4),
                    value_ci(g.omega_n_hz, e.ci95[1], 1)
                ));
                if g.fit.design_model == DesignModel::Swept {
                    s.push_str(
                        "geometry path: design-load fit through simulated up-sweeps: the teeth separate at some speeds under eq. 13's closed form\n",
                    );
                }
                for l in &g.loads {
                    s.push_str(&load_line(l));
                }
            }
            (written, data_kind_banner(&data.rig), s)
        }
        Which::Kubo(k) => {
            let d = &k.dirs;
            let data = load_kubo(&data_dir(d.data.as_deref(), "kubo")?)?;
            let opts = KuboOptions {
                fit_path: k.fit.path(),
                hold_ste: k.hold_ste,
                correlation: k.correlation.choice(),
                ..KuboOptions::default()
            };
            let r = validate_kubo(&data, &opts, &Bar::new())?;
            let written = write_kubo_report(&data, &r, &d.fits, &d.reports.join("kubo"))?;
            let s = format!(
                "zeta {:.4}, omega_n {:.1} Hz ({}), model inside the envelope at {:.0}% of speeds, transition error {}\n{}",
                r.zeta,
                r.omega_n_hz,
                r.parameter_source,
                100.0 * r.inside_fraction,
                r.transition_error_text(" rpm"),
                kubo_intervals(&r)
            );
            let names = [format!("{} N midline", r.load_n)];
            let correlation = r
                .fit
                .as_ref()
                .and_then(|f| geardyn::report::correlation_summary(f, &names))
                .map_or(String::new(), |c| format!("{c}\n"));
            let stated = r
                .fit
                .as_ref()
                .and_then(|f| {
                    geardyn::report::stated_ste_text(&f.measurements, |_| format!("{} N", r.load_n))
                })
                .map_or(String::new(), |t| format!("{t}\n"));
            let s = format!("{s}{correlation}{stated}");
            (written, data_kind_banner(&data.rig), s)
        }
    };
    let mut text = format!("{banner}\n{summary}");
    for p in written {
        text.push_str(&format!("wrote {}\n", p.display()));
    }
    print_text(&text)
}

/// The data set folder: `--data`, else the shipped `data/NAME` of the repository, which must
/// then exist in the current folder (a hint otherwise: outside the repository a missing default
/// is no fault in any file).
fn data_dir(given: Option<&std::path::Path>, name: &str) -> anyhow::Result<PathBuf> {
    if let Some(d) = given {
        return Ok(d.to_path_buf());
    }
    let d = PathBuf::from("data").join(name);
    if !d.join("rig.toml").is_file() {
        let here = std::env::current_dir().map_or(String::from("."), |p| p.display().to_string());
        anyhow::bail!(
            "no data set given and the default {}/rig.toml is not in {here}: give your data \
             set with --data DIR (a folder with rig.toml and CSV curves; `geardyn init-data DIR` \
             writes a template), or run from the geardyn repository for the shipped set",
            d.display()
        );
    }
    Ok(d)
}

/// One line per fitted Kubo parameter: its value with the covariance (inverse Fisher) and the
/// profile-likelihood 95% intervals (nothing when zeta and omega_n were given).
fn kubo_intervals(r: &KuboValidation) -> String {
    let Some(fit) = &r.fit else {
        return String::new();
    };
    let mut s = String::new();
    for (i, name) in fit.names.iter().enumerate() {
        // The curve is even in the pairs' spread h: |h| and its folded interval.
        let spread = name == PAIR_SPREAD;
        let (value, cov) = if spread {
            (fit.params[i].abs(), spread_interval(fit.ci95[i]))
        } else {
            (fit.params[i], fit.ci95[i])
        };
        // At least the digits of the summary line above (zeta 4, omega_n 1).
        let least = match name.as_str() {
            "zeta" => 4,
            "ste_um" => 3,
            _ => 1,
        };
        let digits = interval_digits(cov.0, cov.1, least);
        let profile = r.ci95_profile.get(i).map_or("-".to_string(), |p| {
            let end = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{v:.digits$}"));
            format!("{} .. {}", end(p.lower), end(p.upper))
        });
        let name = if spread {
            format!("|{name}|")
        } else {
            name.clone()
        };
        // Critical damping bounds every damping the rig could have: an interval beyond it
        // says the data hardly determine zeta.
        let note = if name == "zeta" && cov.1 >= 1.0 {
            " (the covariance interval reaches beyond critical damping: these data determine zeta poorly; read the profile interval)"
        } else {
            ""
        };
        s.push_str(&format!(
            "  {name} {value:.digits$}: 95% covariance {:.digits$} .. {:.digits$}, profile {profile}{note}\n",
            cov.0, cov.1
        ));
    }
    s
}

/// A value and its 95% interval, with the interval's digits.
fn value_ci(v: f64, ci: (f64, f64), min_digits: usize) -> String {
    let d = interval_digits(ci.0, ci.1, min_digits);
    format!("{v:.d$} [{}]", ci_text(ci, d))
}

/// A 95% interval with enough digits to see whether a value lies inside it.
fn ci_text((a, b): (f64, f64), min_digits: usize) -> String {
    let digits = interval_digits(a, b, min_digits);
    format!("95% covariance {a:.digits$} .. {b:.digits$}")
}
