//! `geardyn hbm`: harmonic-balance frequency response, every solution at each Omega (Sec. 4).

use super::common::{check_out_dir, commit, parse_range, print_text, stage, write_text, ModelArgs};
use super::limits::whole;
use super::progress_bar::Bar;
use super::response_plot::{write_response_plot, ResponseRow};
use clap::{Args as ClapArgs, ValueEnum};
use geardyn::hb::{
    continue_branch, df_response_forced, forced_transition_frequencies, AftOptions,
    ContinuationOptions, DfMethod,
};
use std::path::PathBuf;

#[derive(ClapArgs, Debug)]
pub struct Args {
    #[command(flatten)]
    model: ModelArgs,
    /// Frequency range START:STOP:STEP (START, STOP in [0.001, 100]; at most 100000 values).
    #[arg(long, allow_hyphen_values = true)]
    omega: String,
    /// df-exact: describing functions of eq. 8 (exact g, h); df-truncated: the paper's two-term
    /// series of eq. 9 with per-case formulas (eq. 12-19).
    #[arg(long, value_enum, default_value_t = Method::DfExact)]
    method: Method,
    /// Harmonics of the AFT ansatz (--method aft), 1 to 128 (time grows about as H^2.8).
    #[arg(long, default_value_t = 15, allow_hyphen_values = true,
          value_parser = whole(1..=geardyn::hb::MAX_HARMONICS))]
    harmonics: usize,
    /// Subharmonic order nu of the AFT ansatz (period-nu orbits), 1 to 32.
    #[arg(long, default_value_t = 1, allow_hyphen_values = true,
          value_parser = whole(1..=geardyn::sim::MAX_PERIOD as usize))]
    subharmonic: usize,
    /// Output format on standard output.
    #[arg(long, value_enum, default_value_t = Format::Csv)]
    format: Format,
    /// Folder for the plot (PNG + SVG) and a copy of the CSV.
    #[arg(long, default_value = "reports/hbm")]
    out: PathBuf,
}

#[derive(ValueEnum, Debug, Clone, Copy, PartialEq, Eq)]
enum Method {
    DfExact,
    DfTruncated,
    /// Multi-harmonic balance (AFT) with pseudo-arclength continuation and Floquet stability.
    Aft,
}

#[derive(ValueEnum, Debug, Clone, Copy, PartialEq, Eq)]
enum Format {
    Csv,
}

pub fn run(a: Args) -> anyhow::Result<()> {
    check_out_dir("--out", &a.out)?;
    let omegas = parse_range("--omega", &a.omega)?;
    // Every method gets the model's checks (F_m, F_ah, zeta) before any work.
    a.model.model(omegas[0])?;
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record([
        "omega",
        "qa",
        "qm",
        "case",
        "impact",
        "phase",
        "stable",
        "method",
        "fold",
        "period_doubling",
    ])?;
    let mut rows = Vec::new();
    let transitions = forced_transition_frequencies(a.model.fm, a.model.forcing(), a.model.zeta)?;
    let method_name = match a.method {
        Method::DfExact | Method::DfTruncated => {
            let method = if a.method == Method::DfExact {
                DfMethod::Exact
            } else {
                DfMethod::Truncated
            };
            let sols =
                df_response_forced(a.model.fm, a.model.forcing(), a.model.zeta, &omegas, method)?;
            for s in &sols {
                w.write_record([
                    format!("{}", s.omega),
                    format!("{:.10}", s.qa),
                    format!("{:.10}", s.qm),
                    s.case.case().to_string(),
                    s.case.name().to_string(),
                    format!("{:.10}", s.phase),
                    s.stable.map_or(String::new(), |b| b.to_string()),
                    method.name().to_string(),
                    String::new(),
                    String::new(),
                ])?;
                rows.push(ResponseRow {
                    omega: s.omega,
                    qa: s.qa,
                    qm: s.qm,
                    impact: s.case,
                    stable: s.stable,
                });
            }
            method.name().to_string()
        }
        Method::Aft => {
            let model = a.model.model(omegas[0])?;
            let opts = AftOptions {
                harmonics: a.harmonics,
                subharmonic: a.subharmonic as u32,
                ..AftOptions::default()
            };
            let last = omegas[omegas.len() - 1];
            let pts = continue_branch(
                &model,
                omegas[0],
                last,
                &opts,
                &ContinuationOptions::default(),
                &Bar::new(),
            )?;
            for p in &pts {
                w.write_record([
                    format!("{}", p.omega),
                    format!("{:.10}", p.qa),
                    format!("{:.10}", p.qm),
                    p.case.case().to_string(),
                    p.case.name().to_string(),
                    String::new(),
                    p.stable.map_or(String::new(), |b| b.to_string()),
                    format!("aft-h{}-nu{}", a.harmonics, a.subharmonic),
                    p.fold.to_string(),
                    p.period_doubling.to_string(),
                ])?;
                rows.push(ResponseRow {
                    omega: p.omega,
                    qa: p.qa,
                    qm: p.qm,
                    impact: p.case,
                    stable: p.stable,
                });
            }
            format!(
                "AFT H = {}, nu = {}, continuation",
                a.harmonics, a.subharmonic
            )
        }
    };
    let csv_text = String::from_utf8(w.into_inner()?)?;
    let caption = format!(
        "{}, {}; case I ends / resumes at Ω {} (eq. 14)",
        a.model.caption(),
        method_name,
        if transitions.is_empty() {
            "none".to_string()
        } else {
            transitions
                .iter()
                .map(|t| format!("{t:.4}"))
                .collect::<Vec<_>>()
                .join(", ")
        }
    );
    let stage = stage("--out", &a.out)?;
    let d = stage.dir().to_path_buf();
    let mut written = write_response_plot(
        &rows,
        "Frequency response (harmonic balance)",
        &caption,
        &d.join("hbm"),
    )?;
    write_text(&d.join("hbm.csv"), &csv_text)?;
    written.push(d.join("hbm.csv"));
    let written = commit(stage, &written)?;
    print_text(&csv_text)?;
    for p in written {
        eprintln!("wrote {}", p.display());
    }
    Ok(())
}
