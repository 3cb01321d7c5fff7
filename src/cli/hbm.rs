//! `geardyn hbm`: harmonic-balance frequency response, every solution at each Omega (Sec. 4).

use super::common::{parse_range, print_text, write_text, ModelArgs};
use super::progress_bar::Bar;
use super::response_plot::{write_response_plot, ResponseRow};
use clap::{Args as ClapArgs, ValueEnum};
use geardyn::hb::{
    continue_branch, df_response, transition_frequencies, AftOptions, ContinuationOptions, DfMethod,
};
use std::path::PathBuf;

#[derive(ClapArgs, Debug)]
pub struct Args {
    #[command(flatten)]
    model: ModelArgs,
    /// Frequency range START:STOP:STEP.
    #[arg(long, allow_hyphen_values = true)]
    omega: String,
    /// df-exact: describing functions of eq. 8 (exact g, h); df-truncated: the paper's two-term
    /// series of eq. 9 with per-case formulas (eq. 12-19).
    #[arg(long, value_enum, default_value_t = Method::DfExact)]
    method: Method,
    /// Harmonics of the AFT ansatz (--method aft).
    #[arg(long, default_value_t = 15)]
    harmonics: usize,
    /// Subharmonic order nu of the AFT ansatz (period-nu orbits).
    #[arg(long, default_value_t = 1)]
    subharmonic: u32,
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
    let omegas = parse_range("--omega", &a.omega)?;
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
    let (t1, t2) = transition_frequencies(a.model.fm, a.model.fah, a.model.zeta)?;
    let method_name = match a.method {
        Method::DfExact | Method::DfTruncated => {
            let method = if a.method == Method::DfExact {
                DfMethod::Exact
            } else {
                DfMethod::Truncated
            };
            let sols = df_response(a.model.fm, a.model.fah, a.model.zeta, &omegas, method)?;
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
                subharmonic: a.subharmonic,
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
    let fmt = |t: Option<f64>| t.map_or("none".to_string(), |v| format!("{v:.4}"));
    let caption = format!(
        "F_m = {}, F_ah = {}, zeta = {}, {}; eq. 14 transitions {} and {}",
        a.model.fm,
        a.model.fah,
        a.model.zeta,
        method_name,
        fmt(t1),
        fmt(t2)
    );
    let mut written = write_response_plot(
        &rows,
        "Frequency response (harmonic balance)",
        &caption,
        &a.out.join("hbm"),
    )?;
    write_text(&a.out.join("hbm.csv"), &csv_text)?;
    written.push(a.out.join("hbm.csv"));
    print_text(&csv_text)?;
    for p in written {
        eprintln!("wrote {}", p.display());
    }
    Ok(())
}
