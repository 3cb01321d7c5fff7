//! The JSON entry and the text line of one steady state of an attractor search, shared by
//! `attractors` and `basins` (design.md section 3: every entry carries its kind), with the rig's
//! units when the model came from `--rig`.

use super::model_args::{num, Model, SteadyInRigUnits};
use geardyn::reproduce::attractor_name;
use geardyn::sim::{Attractor, AttractorMap};
use serde_json::{json, Value};

/// JSON entry of attractor `at` of `map`, found at frequency `omega` of model `m`.
pub fn entry(at: &Attractor, map: &AttractorMap, m: &Model, omega: f64) -> Value {
    let s = &at.steady;
    let mut v = json!({
        "kind": at.kind,
        "period": s.period, "settled": s.settled, "motion": s.motion, "impact": s.impact,
        "case": s.impact.case(),
        "qa": s.qa, "qm": s.qm, "q_min": s.q_min, "q_max": s.q_max, "dte_pp": s.dte_pp,
        "dl_max": s.dl_max, "lyapunov": s.lyapunov, "floquet": s.floquet,
        "floquet_rate": s.floquet_rate,
        "basin_fraction": at.basin_fraction, "basin_count": at.basin_count,
        "basin": map.basin_time, "basin_at_periods": map.horizon,
        "basin_fraction_asymptotic": at.basin_fraction_asymptotic,
        "example_ic": at.example_ic, "poincare": s.poincare,
        "rig_units": SteadyInRigUnits::json(&SteadyInRigUnits::new(m, omega, s)),
    });
    if let Some(k) = map
        .attractors
        .iter()
        .position(|b| std::ptr::eq(b, at))
        .and_then(|i| map.floquet_match(i))
    {
        v["lyapunov_is_floquet_rate_of"] = json!(k);
    }
    if let Some(r) = &at.escape {
        let destinations: Vec<Value> = r
            .destinations
            .iter()
            .map(|&(k, n)| {
                let d = &map.attractors[k].steady;
                json!({"attractor": k, "period": d.period, "impact": d.impact, "qa": d.qa, "escapes": n})
            })
            .collect();
        v["escape_rate_per_period"] = json!(r.rate);
        v["escape_rate_ci95"] = json!([r.rate_ci95.0, r.rate_ci95.1]);
        v["mean_lifetime_periods"] = json!(r.mean_lifetime());
        v["escapes"] = json!(r.escapes);
        v["followed"] = json!({
            "trajectories": r.entered, "from_periods": r.start_periods,
            "to_periods": r.end_periods, "exposure_periods": r.exposure,
        });
        v["survival"] = json!(r
            .survival
            .iter()
            .map(|p| [p.periods, p.alive])
            .collect::<Vec<_>>());
        v["destinations"] = json!(destinations);
    }
    v
}

/// One line of text for attractor `i` of `map` (with its escape, when followed, on a second).
pub fn line(i: usize, at: &Attractor, map: &AttractorMap, m: &Model, omega: f64) -> String {
    let s = &at.steady;
    let mut t = format!(
        "  #{i}: {}, q_a {:.5}, q_m {:.5}, basin {:.1}%",
        attractor_name(at),
        s.qa,
        s.qm,
        100.0 * at.basin_fraction
    );
    if let Some(f) = at.basin_fraction_asymptotic {
        if map.basin_time == geardyn::sim::BasinTime::FiniteTime {
            t.push_str(&format!(" (asymptotic {:.1}%)", 100.0 * f));
        }
    }
    if let Some(l) = s.lyapunov.filter(|_| s.period.is_none()) {
        t.push_str(&format!(", lyapunov {l:.4} per unit time"));
        if let Some(k) = map.floquet_match(i) {
            t.push_str(&format!(
                " (the Floquet rate of #{k}: a slow approach to that orbit)"
            ));
        }
    }
    if let Some(r) = s.floquet_rate {
        t.push_str(&format!(", floquet rate {r:.4}"));
    }
    if let Some(r) = SteadyInRigUnits::new(m, omega, s) {
        t.push_str(&format!("; {}", r.text(false)));
    }
    if let Some(r) = &at.escape {
        if r.escapes > 0 {
            let dest: Vec<String> = r
                .destinations
                .iter()
                .map(|&(k, n)| format!("{n} to #{k}"))
                .collect();
            t.push_str(&format!(
                "\n      escape rate {:.3e} per period (95% {:.3e} .. {:.3e}), mean lifetime {:.0} \
                 periods; {} of {} followed from period {} to {} escaped ({})",
                r.rate,
                r.rate_ci95.0,
                r.rate_ci95.1,
                1.0 / r.rate,
                r.escapes,
                r.entered,
                r.start_periods,
                r.end_periods,
                dest.join(", ")
            ));
        } else {
            t.push_str(&format!(
                "\n      no escape: {} trajectories followed from period {} to {}, escape rate \
                 below {:.2e} per period (95%)",
                r.entered, r.start_periods, r.end_periods, r.rate_ci95.1
            ));
        }
    }
    t.push('\n');
    t
}

/// The header line of a map's text report at frequency `omega`.
pub fn header(map: &AttractorMap, omega: f64) -> String {
    let g = &map.grid;
    let basin = match map.basin_time {
        geardyn::sim::BasinTime::Asymptotic => "asymptotic basins".to_string(),
        geardyn::sim::BasinTime::FiniteTime => {
            format!("basins at {} periods (finite time)", map.horizon)
        }
    };
    format!(
        "{} steady state(s) at Ω_h = {} from {}x{} initial conditions in [{}, {}]^2 (q and q' \
         dimensionless), {basin}\n",
        map.attractors.len(),
        num(omega),
        g.n,
        g.n,
        g.lo,
        g.hi
    )
}
