//! `geardyn simulate`: the steady state from one initial condition.

use super::common::{check_out_dir, print_json, print_text, with_omega, ModelArgs, SolverArgs};
use super::limits::{real, OMEGA, STATE};
use clap::Args as ClapArgs;
use geardyn::sim::steady_state;
use serde_json::json;

#[derive(ClapArgs, Debug)]
pub struct Args {
    #[command(flatten)]
    model: ModelArgs,
    /// Mesh (excitation) frequency Omega_h = Omega_bar_h / omega_n, in [0.001, 100].
    #[arg(long, allow_hyphen_values = true, value_parser = real(OMEGA.0, OMEGA.1, false))]
    omega: f64,
    /// Initial displacement q(0), in [-1e6, 1e6].
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true,
          value_parser = real(-STATE, STATE, false))]
    q0: f64,
    /// Initial velocity q'(0), in [-1e6, 1e6].
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
    let model = a.model.model(a.omega)?;
    let flow = a.solver.flow(&model)?;
    let mut opts = a.solver.options()?;
    opts.lyapunov = a.lyapunov;
    let s = steady_state(flow.as_ref(), [a.q0, a.v0], &opts)?;
    let written = match &a.out {
        Some(dir) => {
            let caption = format!(
                "{}, Ω = {}, q(0) = {}, q'(0) = {}",
                a.model.caption(),
                a.omega,
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
    if a.json {
        let mut params = with_omega(a.model.json(), a.omega);
        params["q0"] = json!(a.q0);
        params["v0"] = json!(a.v0);
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
            "parameters": params,
        }))?;
    } else {
        print_text(&format!(
            "period {} ({:?}), impact {} (case {}), qa {:.6}, qm {:.6}, pp DTE {:.6}{}\n",
            s.period.map_or("none".to_string(), |p| p.to_string()),
            s.motion,
            s.impact.name(),
            s.impact.case(),
            s.qa,
            s.qm,
            s.dte_pp,
            match (s.floquet_rate, s.lyapunov) {
                (Some(r), _) => format!(", floquet rate {r:.5}"),
                (None, Some(l)) => format!(", lyapunov {l:.5}"),
                (None, None) => String::new(),
            }
        ))?;
    }
    Ok(())
}
