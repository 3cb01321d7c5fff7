//! `geardyn simulate`: the steady state from one initial condition.

use super::common::{check_out_dir, print_json, print_text, with_omega, SolverArgs};
use super::geometry_excitation::ExcitationArgs;
use super::limits::{real, STATE};
use super::model_args::{Frequency, ModelArgs, SteadyInRigUnits};
use clap::Args as ClapArgs;
use geardyn::sim::steady_state;
use serde_json::json;

#[derive(ClapArgs, Debug)]
pub struct Args {
    #[command(flatten)]
    model: ModelArgs,
    #[command(flatten)]
    excitation: ExcitationArgs,
    #[command(flatten)]
    frequency: Frequency,
    /// Initial displacement q(0) = q̄(0) / b, dimensionless (half backlashes), in [-1e6, 1e6].
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true,
          value_parser = real(-STATE, STATE, false))]
    q0: f64,
    /// Initial velocity q'(0) = dq/dt at t = ω_n t̄ = 0, dimensionless, in [-1e6, 1e6].
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true,
          value_parser = real(-STATE, STATE, false))]
    v0: f64,
    #[command(flatten)]
    solver: SolverArgs,
    /// Also compute the largest Lyapunov exponent of periodic motion.
    #[arg(long)]
    lyapunov: bool,
    /// Print the result as JSON.
    #[arg(long)]
    json: bool,
    /// Also write time history, phase plane and Poincare map (CSV, PNG, SVG) into this folder.
    #[arg(long)]
    out: Option<std::path::PathBuf>,
}

pub fn run(a: Args) -> anyhow::Result<()> {
    if let Some(dir) = &a.out {
        check_out_dir("--out", dir)?;
    }
    let (m, omega, model) = a.model.at_frequency_with(&a.frequency, &a.excitation)?;
    let flow = a.solver.flow(&model)?;
    let mut opts = a.solver.options()?;
    opts.lyapunov = a.lyapunov;
    let s = steady_state(flow.as_ref(), [a.q0, a.v0], &opts)?;
    let written = match &a.out {
        Some(dir) => {
            let caption = format!(
                "{}, Ω_h = {}, q(0) = {}, q'(0) = {}",
                m.caption(),
                geardyn::numeric::to_significant(omega, 6),
                a.q0,
                a.v0
            );
            super::simulate_figures::write(flow.as_ref(), &s, &caption, dir)?
        }
        None => Vec::new(),
    };
    for p in &written {
        eprintln!("wrote {}", p.display());
    }
    if !s.settled {
        eprintln!("{}", super::common::unsettled_warning(s.transient_periods));
    }
    let rig_units = SteadyInRigUnits::new(&m, omega, &s);
    if a.json {
        let mut parameters = with_omega(m.json(), omega);
        parameters["q0"] = a.q0.into();
        parameters["v0"] = a.v0.into();
        print_json(&json!({
            "period": s.period,
            "settled": s.settled,
            "motion": s.motion,
            "impact": s.impact,
            "case": s.impact.case(),
            "qa": s.qa,
            "qm": s.qm,
            "q_min": s.q_min,
            "q_max": s.q_max,
            "dte_pp": s.dte_pp,
            "dl_max": s.dl_max,
            "lyapunov": s.lyapunov,
            "floquet": s.floquet,
            "floquet_rate": s.floquet_rate,
            "poincare": s.poincare,
            "transient_periods": s.transient_periods,
            "integrator": flow.method(),
            "parameters": parameters,
            "rig_units": SteadyInRigUnits::json(&rig_units),
        }))?;
    } else {
        let mut text = format!(
            "period {} ({}), impact {} (case {}), q_a {:.6}, q_m {:.6}, pp DTE {:.6}{}{} (dimensionless)\n",
            s.period.map_or("none".to_string(), |p| p.to_string()),
            s.motion.name(),
            s.impact.name(),
            s.impact.roman(),
            s.qa,
            s.qm,
            s.dte_pp,
            s.dl_max
                .map_or(String::new(), |d| format!(", D_L {d:.4}")),
            match (s.floquet_rate, s.lyapunov) {
                (Some(r), _) => format!(", floquet rate {r:.5}"),
                (None, Some(l)) => format!(", lyapunov {l:.5} per unit time"),
                (None, None) => String::new(),
            }
        );
        if let Some(r) = rig_units {
            text.push_str(&r.text(true));
            text.push('\n');
        }
        print_text(&text)?;
    }
    Ok(())
}
