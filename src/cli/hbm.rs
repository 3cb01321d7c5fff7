//! `geardyn hbm`: harmonic-balance frequency response, every solution at each Omega (Sec. 4).

use super::common::{parse_range, print_text, write_text, ModelArgs};
use super::response_plot::{write_response_plot, ResponseRow};
use clap::{Args as ClapArgs, ValueEnum};
use geardyn::hb::{df_response, transition_frequencies, DfMethod};
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
}

#[derive(ValueEnum, Debug, Clone, Copy, PartialEq, Eq)]
enum Format {
    Csv,
}

pub fn run(a: Args) -> anyhow::Result<()> {
    let omegas = parse_range("--omega", &a.omega)?;
    let method = match a.method {
        Method::DfExact => DfMethod::Exact,
        Method::DfTruncated => DfMethod::Truncated,
    };
    let sols = df_response(a.model.fm, a.model.fah, a.model.zeta, &omegas, method)?;
    let (t1, t2) = transition_frequencies(a.model.fm, a.model.fah, a.model.zeta)?;
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record([
        "omega", "qa", "qm", "case", "impact", "phase", "stable", "method",
    ])?;
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
        ])?;
    }
    let csv_text = String::from_utf8(w.into_inner()?)?;
    let rows: Vec<ResponseRow> = sols
        .iter()
        .map(|s| ResponseRow {
            omega: s.omega,
            qa: s.qa,
            qm: s.qm,
            impact: s.case,
            stable: s.stable,
        })
        .collect();
    let fmt = |t: Option<f64>| t.map_or("none".to_string(), |v| format!("{v:.4}"));
    let caption = format!(
        "F_m = {}, F_ah = {}, zeta = {}, {}; eq. 14 transitions {} and {}",
        a.model.fm,
        a.model.fah,
        a.model.zeta,
        method.name(),
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
