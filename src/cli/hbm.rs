//! `geardyn hbm`: harmonic-balance frequency response, every solution at each Omega (Sec. 4).

use super::common::{check_out_dir, commit, print_text, stage, write_text};
use super::limits::whole;
use super::model_args::{num, FrequencyRange, Model, ModelArgs};
use super::progress_bar::Bar;
use super::response_plot::{write_response_plot, ResponseRow};
use clap::{Args as ClapArgs, ValueEnum};
use geardyn::hb::{
    continue_branch, df_response_forced, forced_transition_frequencies, subharmonic_branch,
    AftOptions, ContinuationOptions, DfMethod,
};
use geardyn::model::GearPair;
use geardyn::sim::IcGrid;
use std::path::PathBuf;

#[derive(ClapArgs, Debug)]
pub struct Args {
    #[command(flatten)]
    model: ModelArgs,
    #[command(flatten)]
    frequencies: FrequencyRange,
    /// df-exact: describing functions of eq. 8 (exact g, h); df-truncated: the paper's two-term
    /// series of eq. 9 with per-case formulas (eq. 12-19).
    #[arg(long, value_enum, default_value_t = Method::DfExact)]
    method: Method,
    /// Harmonics of the AFT ansatz (--method aft), 1 to 128 (time grows about as H^2.8).
    #[arg(long, default_value_t = 15, allow_hyphen_values = true,
          value_parser = whole(1..=geardyn::hb::MAX_HARMONICS))]
    harmonics: usize,
    /// Subharmonic order nu of the AFT ansatz (period-nu orbits), 1 to 32; above 1 the branch
    /// starts from a period-nu orbit the simulation reaches (see --ic-grid).
    #[arg(long, default_value_t = 1, allow_hyphen_values = true,
          value_parser = whole(1..=geardyn::sim::MAX_PERIOD as usize))]
    subharmonic: usize,
    /// Grid of initial conditions q(0), q'(0) (dimensionless, LO:HI:N) on which simulation
    /// looks for the period-nu orbit that seeds a --subharmonic branch (nu > 1), frequency by
    /// frequency from the range's start.
    #[arg(long, default_value = super::common::SWEEP_IC_GRID, allow_hyphen_values = true)]
    ic_grid: String,
    /// Output format on standard output (columns: docs/output-columns.md).
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

/// One row of the hbm CSV: the dimensionless columns, and with the rig's units the speed and
/// mesh frequency first and q_a, q_m in µm last.
fn hbm_record(m: &Model, omega: f64, qa: f64, qm: f64, middle: [String; 7]) -> Vec<String> {
    let mut row = Vec::with_capacity(14);
    if let Some(op) = &m.rig {
        row.extend([num(op.speed_rpm(omega)), num(op.mesh_frequency_hz(omega))]);
    }
    row.extend([num(omega), format!("{qa:.10}"), format!("{qm:.10}")]);
    row.extend(middle);
    if let Some(op) = &m.rig {
        row.extend([
            format!("{:.6}", op.micrometres(qa)),
            format!("{:.6}", op.micrometres(qm)),
        ]);
    }
    row
}

/// One method's solutions: a CSV record and a plot row each, and the method's name for the
/// caption.
struct Solved {
    records: Vec<Vec<String>>,
    rows: Vec<ResponseRow>,
    method: String,
}

impl Solved {
    fn push(&mut self, record: Vec<String>, row: ResponseRow) {
        self.records.push(record);
        self.rows.push(row);
    }
}

pub fn run(a: Args) -> anyhow::Result<()> {
    check_out_dir("--out", &a.out)?;
    let m = a.model.resolve()?;
    let omegas = a.frequencies.omegas(&m)?;
    m.print_conversion(omegas[0]);
    // Every method gets the model's checks (F_m, F_ah, zeta) before any work.
    let model = m.at(omegas[0])?;
    let transitions = forced_transition_frequencies(m.fm, m.forcing(), m.zeta)?;
    let solved = match a.method {
        Method::DfExact => solve_df(&m, &omegas, DfMethod::Exact)?,
        Method::DfTruncated => solve_df(&m, &omegas, DfMethod::Truncated)?,
        Method::Aft => solve_aft(&a, &m, &model, &omegas)?,
    };
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record(header(&m))?;
    for r in &solved.records {
        w.write_record(r)?;
    }
    let csv_text = String::from_utf8(w.into_inner()?)?;
    let caption = caption(&m, &solved.method, &transitions);
    let stage = stage("--out", &a.out)?;
    let d = stage.dir().to_path_buf();
    let mut written = write_response_plot(
        &solved.rows,
        m.rig.as_ref(),
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

/// The CSV header: the rig's speed columns first and its lengths last when there is a rig.
fn header(m: &Model) -> Vec<&'static str> {
    let mut header: Vec<&str> = Vec::new();
    if m.rig.is_some() {
        header.extend(["speed_rpm", "mesh_freq_hz"]);
    }
    header.extend([
        "omega", "qa", "qm", "case", "impact", "phase", "stable", "method",
    ]);
    header.extend(["fold", "period_doubling"]);
    if m.rig.is_some() {
        header.extend(["qa_um", "qm_um"]);
    }
    header
}

/// The describing-function solutions (Sec. 4) at every frequency.
fn solve_df(m: &Model, omegas: &[f64], method: DfMethod) -> anyhow::Result<Solved> {
    let sols = df_response_forced(m.fm, m.forcing(), m.zeta, omegas, method)?;
    let mut out = Solved {
        records: Vec::new(),
        rows: Vec::new(),
        method: method.name().to_string(),
    };
    for s in &sols {
        let record = hbm_record(
            m,
            s.omega,
            s.qa,
            s.qm,
            [
                s.case.case().to_string(),
                s.case.name().to_string(),
                format!("{:.10}", s.phase),
                s.stable.map_or(String::new(), |b| b.to_string()),
                method.name().to_string(),
                String::new(),
                String::new(),
            ],
        );
        let row = ResponseRow {
            omega: s.omega,
            qa: s.qa,
            qm: s.qm,
            impact: s.case,
            stable: s.stable,
            branch: None,
            transient: false,
        };
        out.push(record, row);
    }
    Ok(out)
}

/// The multi-harmonic (AFT) branch continued over the frequency range, with its stability,
/// folds and period doublings.
fn solve_aft(a: &Args, m: &Model, model: &GearPair, omegas: &[f64]) -> anyhow::Result<Solved> {
    let opts = AftOptions {
        harmonics: a.harmonics,
        subharmonic: a.subharmonic as u32,
        ..AftOptions::default()
    };
    let last = omegas[omegas.len() - 1];
    let cont = ContinuationOptions::default();
    let (pts, seeded) = if a.subharmonic > 1 {
        let grid = IcGrid::parse(&a.ic_grid)?;
        let b = subharmonic_branch(model, omegas, &grid, &opts, &cont, &Bar::new())?;
        (
            b.points,
            format!(
                ", seeded by a simulated period-{} orbit at Ω = {}",
                a.subharmonic, b.seed_omega
            ),
        )
    } else {
        let b = continue_branch(model, omegas[0], last, &opts, &cont, &Bar::new())?;
        (b, String::new())
    };
    let mut out = Solved {
        records: Vec::new(),
        rows: Vec::new(),
        method: format!(
            "AFT H = {}, ν = {}, continuation{seeded}",
            a.harmonics, a.subharmonic
        ),
    };
    for p in &pts {
        let record = hbm_record(
            m,
            p.omega,
            p.qa,
            p.qm,
            [
                p.case.case().to_string(),
                p.case.name().to_string(),
                String::new(),
                p.stable.map_or(String::new(), |b| b.to_string()),
                format!("aft-h{}-nu{}", a.harmonics, a.subharmonic),
                p.fold.to_string(),
                p.period_doubling.to_string(),
            ],
        );
        let row = ResponseRow {
            omega: p.omega,
            qa: p.qa,
            qm: p.qm,
            impact: p.case,
            stable: p.stable,
            branch: None,
            transient: false,
        };
        out.push(record, row);
    }
    Ok(out)
}

/// The plot caption: the model, the method and where case I ends or resumes (eq. 14).
fn caption(m: &Model, method: &str, transitions: &[f64]) -> String {
    let fmt = |v: f64| match &m.rig {
        Some(op) => format!("{:.0} rpm (Ω_h {v:.4})", op.speed_rpm(v)),
        None => format!("{v:.4}"),
    };
    format!(
        "{}, {}; case I ends / resumes at {} (eq. 14)",
        m.caption(),
        method,
        if transitions.is_empty() {
            "none".to_string()
        } else {
            transitions
                .iter()
                .map(|&t| fmt(t))
                .collect::<Vec<_>>()
                .join(", ")
        }
    )
}
