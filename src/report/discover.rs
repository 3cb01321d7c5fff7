//! Outputs of `geardyn discover`: discovery.json (design.md 3: effect, candidates [{name,
//! estimate, ci95, p_value}], gap_before, gap_after, and more), report.md / index.html, which
//! open with the answer and why, and the residual plots before and after (PNG + SVG) with the
//! Omega windows marked. The folder is staged and moved into place only when complete.

use super::{correlation_text, data_kind_banner, Page, Staged};
use crate::data::{DataKind, MunroData};
use crate::discover::{CandidateResult, Discovery, Gap, NoiseOrigin, ResidualCurve, MIN_ZETA};
use crate::error::{GearError, Result};
use crate::fit::{Distribution, NoiseModel};
use crate::numeric::min_max;
use crate::plot::{write_xy, Marker, Series, XyPlot};
use serde_json::json;
use std::path::{Path, PathBuf};

/// The discovery.json record; its first field is the data-kind notice.
pub fn discovery_json(data: &MunroData, d: &Discovery) -> serde_json::Value {
    json!({
        "notice": data_kind_banner(&data.rig),
        "data_kind": data.rig.source.kind.name(),
        "effect": d.effect,
        "answer": answer_text(d),
        "ambiguous_with": d.ambiguous_with,
        "closest_candidate": d.closest_candidate,
        "misfit": d.misfit,
        "goodness_of_fit": d.goodness_of_fit,
        "held_out_prediction": d.held_out_prediction,
        "prediction_check": d.prediction_check,
        "stated_ste": d.stated_ste.iter()
            .map(|(load, m)| super::stated_ste_row(("load_n", json!(load)), m))
            .collect::<Vec<_>>(),
        "power_bound": d.power_bound,
        "candidates": d.candidates.iter().map(|c| json!({
            "name": c.name,
            "estimate": c.estimate,
            "estimate_of": c.estimate_name,
            "ci95": c.ci95.map(|(a, b)| [a, b]),
            "ci95_method": c.ci95_method,
            "wald_ci95": c.wald_ci95.map(|(a, b)| [a, b]),
            "profile_ci95": c.profile_ci95.map(|(a, b)| [a, b]),
            "p_value": c.p_value,
            "p_holm": c.p_holm,
            "identifiable": c.identifiable,
            "note": c.note,
            "failed": c.failed,
            "prediction_failed": c.prediction_failed,
            "lr": c.lr.is_finite().then_some(c.lr),
            "delta": c.delta,
            "zeta": c.zeta,
            "omega_n_hz": c.omega_n_hz,
            "phase_deg": c.phase_deg,
            "phase_wald95_deg": c.phase_wald95_deg.map(|(a, b)| [a, b]),
        })).collect::<Vec<_>>(),
        "gap_before": d.gap_before,
        "gap_after": d.gap_after,
        "gap_after_model": d.gap_after_model,
        "noise": noise_json(d),
        "m0": {
            "zeta": d.zeta_m0,
            "omega_n_hz": d.omega_n_hz_m0,
            "zeta_at_lower_bound": d.m0_zeta_at_lower_bound(),
        },
        "design_load_n": d.design_load_n,
        "design_load_missing": d.design_load_missing(),
        "training_loads_n": d.training_loads_n,
        "held_out_loads_n": d.held_out_loads_n,
        "held_out_ste_um": d.held_out_ste_um.iter().map(|(l, b, a)| json!({
            "load_n": l, "before": b, "after": a,
        })).collect::<Vec<_>>(),
        "excluded_points": d.excluded_points,
        "excluded_by_load": d.excluded_by_load,
        "bootstrap_replicates": d.bootstrap,
        "windows": d.windows,
        "provenance": {
            "geardyn": env!("CARGO_PKG_VERSION"),
            "data_dir": data.dir.display().to_string(),
            "truth_read": false,
        },
    })
}

/// A noise model's distribution for discovery.json: its name and degrees of freedom.
fn distribution_json(m: &NoiseModel) -> (&'static str, Option<f64>) {
    match m.distribution {
        Distribution::Gaussian => ("gaussian", None),
        Distribution::StudentT { dof } => ("student_t", Some(dof)),
    }
}

/// The noise record of discovery.json: where it came from, the model (floor in um, relative
/// part, distribution, correlation along speed) and the scales it gives over the kept points.
fn noise_json(d: &Discovery) -> serde_json::Value {
    let n = &d.noise;
    let (dist, dof) = distribution_json(&n.model);
    json!({
        "source": n.origin,
        "description": n.origin.describe(),
        "floor_um": n.per_point.is_none().then_some(n.model.floor),
        "relative": n.per_point.is_none().then_some(n.model.relative),
        "distribution": dist,
        "dof": dof,
        "correlation_length_rpm": n.model.correlation_length,
        "correlation": d.noise_correlation,
        "scale_range_um": [d.noise_range_um.0, d.noise_range_um.1],
    })
}

/// A noise model in words: its scale ("0.150 µm", or "floor 0.150 µm + 3.00% of the level").
fn scale_text(m: &NoiseModel) -> String {
    if m.relative > 0.0 {
        format!(
            "floor {:.3} µm + {:.2}% of the level",
            m.floor,
            100.0 * m.relative
        )
    } else {
        format!("{:.3} µm", m.floor)
    }
}

/// A noise model's distribution in words.
fn tails_text(m: &NoiseModel) -> String {
    match m.distribution {
        Distribution::Gaussian => "Gaussian".to_string(),
        Distribution::StudentT { dof } => format!("Student-t, {dof} degrees of freedom"),
    }
}

/// One line on the noise, for the terminal and the report.
pub fn noise_text(d: &Discovery) -> String {
    let n = &d.noise;
    let model = if n.per_point.is_some() {
        "a stated scale per point".to_string()
    } else {
        scale_text(&n.model)
    };
    let (lo, hi) = d.noise_range_um;
    // A range only where the scales differ at the printed digits.
    let range = if format!("{lo:.3}") == format!("{hi:.3}") {
        String::new()
    } else {
        format!("; {lo:.3}-{hi:.3} µm over the kept points")
    };
    let length = match n.model.correlation_length {
        l if l > 0.0 => format!("; correlated along speed, length {l:.0} rpm"),
        _ => String::new(),
    };
    format!(
        "noise {model} ({}{range}{length}), {}",
        tails_text(&n.model),
        n.origin.describe()
    )
}

/// The answer in a sentence or two: what was found, its size, and why (a name, none, or why
/// the data are unexplained).
pub fn answer_text(d: &Discovery) -> String {
    let check = d.prediction_check.as_ref().map_or(String::new(), |c| {
        format!(
            " The held-out loads' log-likelihood is {:.1} with it against {:.1} with M0.",
            c.held_out_log_likelihood_candidate, c.held_out_log_likelihood_m0
        )
    });
    match d.effect.as_str() {
        "none" => format!(
            "None: M0, the paper's model, explains the training loads{}; no candidate effect improves their likelihood beyond what the noise gives (bootstrap, Holm over the candidates at 5%).",
            if d.held_out_prediction.is_some() { " and predicts the held-out ones within their noise" } else { "" }
        ),
        "unexplained" => match (&d.closest_candidate, &d.misfit) {
            (Some(c), None) => match failed_prediction(d, c) {
                Some(why) => format!(
                    "Unexplained: {c} fits the training loads significantly better than M0, but it cannot predict the held-out loads ({why}), so it is not named."
                ),
                None => format!(
                    "Unexplained: {c} fits the training loads significantly better than M0, but it predicts the held-out loads worse, so it is not named.{check}"
                ),
            },
            (c, Some(why)) => format!(
                "Unexplained: {why}, and no candidate of the library passes its test{}.",
                c.as_ref().map_or(String::new(), |c| format!("; the closest is {c}"))
            ),
            (None, None) => "Unexplained.".to_string(),
        },
        "ambiguous" => format!(
            "Ambiguous: {} fits the training loads significantly better than M0, and {} fits them within the likelihood's 95% support of it and predicts the held-out loads about as well; the data do not tell them apart.{check}",
            d.closest_candidate.as_deref().unwrap_or("-"),
            d.ambiguous_with.join(", ")
        ),
        _ => match d.named() {
            Some(c) => format!(
                "{}: {} = {} [{} .. {}] (95%, {}){}; the likelihood ratio against M0 is {:.1} (bootstrap p {}, Holm {}).{check}",
                c.name,
                c.estimate_name,
                opt(c.estimate, 4),
                opt(c.ci95.map(|x| x.0), 4),
                opt(c.ci95.map(|x| x.1), 4),
                c.ci95_method,
                phase_text(c).map_or(String::new(), |p| format!(", phase {p}")),
                c.lr,
                p_text(c.p_value),
                p_text(c.p_holm),
            ),
            None => d.effect.clone(),
        },
    }
}

/// Why candidate `name`'s prediction of the held-out loads failed, if it did.
fn failed_prediction<'a>(d: &'a Discovery, name: &str) -> Option<&'a str> {
    d.candidates
        .iter()
        .find(|c| c.name == name)?
        .prediction_failed
        .as_deref()
}

/// discovery.json as text with the data-kind notice as its first field (serde_json sorts the
/// other keys), so the file's first data line says whether the curves are synthetic.
pub fn discovery_json_text(data: &MunroData, d: &Discovery) -> Result<String> {
    let json_err = |e: serde_json::Error| GearError::Numerical(format!("JSON: {e}"));
    let mut v = discovery_json(data, d);
    let notice = v
        .as_object_mut()
        .and_then(|o| o.remove("notice"))
        .unwrap_or_default();
    let rest = serde_json::to_string_pretty(&v).map_err(json_err)?;
    let notice = serde_json::to_string(&notice).map_err(json_err)?;
    Ok(format!(
        "{{\n  \"notice\": {notice},{}\n",
        rest.trim_start_matches('{')
    ))
}

fn residual_plot(
    curves: &[ResidualCurve],
    d: &Discovery,
    title: &str,
    stem: &Path,
) -> Result<Vec<PathBuf>> {
    let mut plot = XyPlot::new(title, "Omega = mesh frequency / omega_n (M0)", "residual (measured - model), um")
        .with_caption(format!(
            "Shaded: windows around Ω = 1/3, 1/2, 2/3, 1, 2 (±{:.0}%); points excluded from the tests (non-period-1 or next to a jump) not drawn",
            100.0 * crate::discover::WINDOW_HALF_WIDTH
        ));
    let (lo, hi) = min_max(curves.iter().flat_map(|c| c.points.iter().map(|p| p.1)))
        .unwrap_or((f64::INFINITY, f64::NEG_INFINITY));
    for w in &d.windows {
        if w.hi >= lo && w.lo <= hi {
            plot = plot.with_band(w.lo, w.hi).with_vline(w.centre, w.label);
        }
    }
    for (k, c) in curves.iter().enumerate() {
        // An excluded point breaks the line (NaN): no segment bridges the speeds left out.
        let pts: Vec<(f64, f64)> = c
            .points
            .iter()
            .map(|p| {
                if p.3 {
                    (p.1, p.2)
                } else {
                    (f64::NAN, f64::NAN)
                }
            })
            .collect();
        let label = format!(
            "{:.0} N ({})",
            c.load_n,
            if c.training { "training" } else { "held out" }
        );
        // A marker shape per load as well as a colour: the loads stay apart in grayscale.
        let marker = [
            Marker::Circle,
            Marker::Square,
            Marker::Triangle,
            Marker::Cross,
        ][k % 4];
        plot = plot.with_series(
            Series::line_markers(label, pts)
                .with_color(k)
                .with_marker(marker),
        );
    }
    write_xy(&plot, stem)
}

fn gap_text(g: &Gap) -> String {
    let loads: Vec<String> = g
        .per_load
        .iter()
        .map(|(l, r, _)| format!("{l:.0} N {r:.3}"))
        .collect();
    format!(
        "RMS {:.3} um over {} points ({}), worst window {} at {:.3} um",
        g.rms_um,
        g.points,
        loads.join(", "),
        g.worst_window.as_deref().unwrap_or("-"),
        g.worst_window_rms_um
    )
}

/// A named phase-carrying candidate's phase and its 95% Wald arc, e.g. "315 deg (Wald 95%
/// 312 .. 318)".
fn phase_text(c: &CandidateResult) -> Option<String> {
    let p = c.phase_deg?;
    Some(match c.phase_wald95_deg {
        Some((a, b)) if b - a >= 360.0 => format!("{p:.0} deg (any)"),
        Some((a, b)) if b - a < 4.0 => format!("{p:.1} deg (Wald 95% {a:.1} .. {b:.1})"),
        Some((a, b)) => format!("{p:.0} deg (Wald 95% {a:.0} .. {b:.0})"),
        None => format!("{p:.0} deg"),
    })
}

/// The note when no curve was measured at the design load.
fn design_load_text(d: &Discovery) -> Option<String> {
    let highest = d.training_loads_n.first()?;
    d.design_load_missing().then(|| format!(
        "no curve at the design load ({} N of rig.toml): M0's zeta and omega_n are fitted with the highest load, {} N, in its place; the damping law and the torque ripple still refer to the design load",
        d.design_load_n, highest
    ))
}

/// The notes of a run, for the terminal and the report alike.
fn notes(d: &Discovery) -> Vec<String> {
    [
        design_load_text(d),
        zeta_bound_text(d),
        stated_noise_text(d),
        excluded_warning(d),
    ]
    .into_iter()
    .flatten()
    .collect()
}

/// The note when the noise was stated and the answer is "unexplained" with a scatter about M0
/// larger than every stated scale: a noise stated too small makes M0 fail its goodness of fit,
/// whatever the model.
fn stated_noise_text(d: &Discovery) -> Option<String> {
    let stated = !matches!(d.noise.origin, NoiseOrigin::Fitted { .. });
    let rms = d.gap_before.training.rms_um;
    let largest = d.noise_range_um.1;
    (stated && d.effect == "unexplained" && rms > largest).then(|| {
        format!(
            "the noise is {}, and the training RMS about M0, {rms:.3} µm, exceeds every stated scale (at most {largest:.3} µm): a noise stated smaller than the scatter makes M0 fail, whatever the model; without the statement it is estimated with the fit",
            d.noise.origin.describe(),
        )
    })
}

/// The note when M0's zeta sits at the fits' lower bound.
fn zeta_bound_text(d: &Discovery) -> Option<String> {
    d.m0_zeta_at_lower_bound().then(|| format!(
        "M0's zeta sits at the fits' lower bound ({MIN_ZETA}): M0 fits these curves only with the least damping it may use, itself a sign that something is missing"
    ))
}

fn opt(v: Option<f64>, prec: usize) -> String {
    v.map_or("-".into(), |x| format!("{x:.prec$}"))
}

fn p_text(p: Option<f64>) -> String {
    p.map_or("-".into(), crate::report::p_text)
}

/// A few lines for the terminal: the answer first.
pub fn discovery_summary(d: &Discovery) -> String {
    let mut s = format!(
        "effect: {}
{}
M0: zeta {:.5}, omega_n {:.1} Hz; {}
",
        d.effect,
        answer_text(d),
        d.zeta_m0,
        d.omega_n_hz_m0,
        noise_text(d)
    );
    for t in notes(d) {
        s.push_str(&format!("NOTE: {t}\n"));
    }
    if let Some(t) = discovery_stated_ste_text(d) {
        s.push_str(&format!("M0: {t}\n"));
    }
    for c in &d.candidates {
        s.push_str(&format!(
            "  {:<26} LR {:>8}  p {:>7}  Holm {:>7}{}\n",
            c.name,
            if c.lr.is_finite() {
                format!("{:.1}", c.lr)
            } else {
                "-".into()
            },
            p_text(c.p_value),
            p_text(c.p_holm),
            remarks(c).map_or(String::new(), |n| format!("  ({n})"))
        ));
    }
    s.push_str(&format!(
        "gap before: training {}\n",
        gap_text(&d.gap_before.training)
    ));
    s.push_str(&format!(
        "gap after ({}):  training {}\n",
        d.gap_after_model,
        gap_text(&d.gap_after.training)
    ));
    if let (Some(b), Some(a)) = (&d.gap_before.held_out, &d.gap_after.held_out) {
        s.push_str(&format!("gap before: held out {}\n", gap_text(b)));
        s.push_str(&format!(
            "gap after ({}):  held out {}\n",
            d.gap_after_model,
            gap_text(a)
        ));
    }
    s.push_str(&excluded_text(d));
    s
}

/// One line per load with excluded points.
fn excluded_text(d: &Discovery) -> String {
    let mut s = String::new();
    for e in &d.excluded_by_load {
        let range = |(a, b): (f64, f64)| format!("{a:.1}-{b:.1} um");
        let predicted = range(e.predicted_range_um);
        let windows = range(e.model_range_um);
        let over_windows = if windows == predicted {
            "the same".to_string()
        } else {
            windows
        };
        s.push_str(&format!(
            "left out of the likelihood at {} N: {} points ({} non-period-1 in M0), measured {}, M0 predicted {predicted} ({over_windows} over 32 observation windows at its points that are not period-1), {} measured far outside that\n",
            e.load_n,
            e.points,
            e.non_period1,
            range(e.measured_range_um),
            e.outside_model_range
        ));
    }
    s
}

/// The warning when excluded points lie far outside M0's range, if any do.
fn excluded_warning(d: &Discovery) -> Option<String> {
    let outside = d.excluded_far_outside();
    (outside > 0).then(|| format!(
        "{outside} point(s) left out of the likelihood (M0 not period-1 there, or next to a jump) lie far outside every pp M0 produces there, in any observation window (by more than 3 sigma + 10% of the largest): a disagreement the likelihood does not see; look at the curves"
    ))
}

/// Write the output folder `out`; returns the files written.
pub fn write_discovery(data: &MunroData, d: &Discovery, out: &Path) -> Result<Vec<PathBuf>> {
    let banner = data_kind_banner(&data.rig);
    let stage = Staged::replacing(out)?;
    let mut files = vec!["discovery.json".to_string()];
    let after_title = format!("Residuals of {}", d.gap_after_model);
    for (name, curves, title) in [
        (
            "residuals_before",
            &d.residuals_before,
            "Residuals of M0 (paper's model)",
        ),
        ("residuals_after", &d.residuals_after, after_title.as_str()),
    ] {
        for p in residual_plot(curves, d, title, &stage.path(name))? {
            if let Some(f) = p.file_name() {
                files.push(f.to_string_lossy().into_owned());
            }
        }
    }
    stage.write("discovery.json", &discovery_json_text(data, d)?)?;
    let mut page = Page::new(
        "geardyn discover: discrepancy discovery",
        &banner,
        data.rig.source.kind == DataKind::Synthetic,
    );
    summary_section(&mut page, d);
    gap_section(&mut page, d);
    candidates_section(&mut page, d);
    noise_section(&mut page, d);
    excluded_section(&mut page, d);
    let (html, md) = page.finish("geardyn discover");
    stage.write("index.html", &html)?;
    stage.write("report.md", &md)?;
    files.push("index.html".into());
    files.push("report.md".into());
    let dest = stage.commit()?;
    Ok(files.into_iter().map(|f| dest.join(f)).collect())
}

/// The answer, the loads and M0's fit, and the notes that qualify the answer.
fn summary_section(page: &mut Page, d: &Discovery) {
    page.paragraph(&answer_text(d));
    page.paragraph(&format!(
        "Training loads {:?} N, held-out loads {:?} N. M0 fitted on the training loads: zeta {:.5}, omega_n {:.1} Hz. {} points left out of the likelihood. {} bootstrap replicates under M0.",
        d.training_loads_n,
        d.held_out_loads_n,
        d.zeta_m0,
        d.omega_n_hz_m0,
        d.excluded_points,
        d.bootstrap
    ));
    for t in notes(d) {
        page.paragraph(&t);
    }
}

/// What is said of a candidate beside its numbers: "failed, because ..." when its fit failed,
/// why its prediction of the held-out loads failed, and its note; None when none of them.
fn remarks(c: &CandidateResult) -> Option<String> {
    let failed = c.failed.as_ref().map(|b| format!("failed, because {b}"));
    let prediction = c
        .prediction_failed
        .as_ref()
        .map(|b| format!("its prediction of the held-out loads failed: {b}"));
    let said: Vec<String> = failed
        .into_iter()
        .chain(prediction)
        .chain(c.note.clone())
        .collect();
    (!said.is_empty()).then(|| said.join("; "))
}

/// Every candidate's test, and the named one's estimate with its interval and phase.
fn candidates_section(page: &mut Page, d: &Discovery) {
    page.heading("Candidates");
    page.paragraph("Each candidate is M0 plus one effect, nested (its parameters at zero give M0), fitted to the training loads with the same noise model as M0, its scale refitted. LR is twice the gain in log-likelihood over M0; its p-value is the share of parametric bootstrap replicates (M0's curves plus errors drawn from M0's fitted noise model, correlation along speed included) whose LR is as large; Holm's correction runs over the candidates tested and M0's checks that can answer \"unexplained\" (its prediction of the held-out loads; with a stated noise, its goodness of fit).");
    let rows: Vec<Vec<String>> = d
        .candidates
        .iter()
        .map(|c| {
            vec![
                c.name.to_string(),
                if c.lr.is_finite() {
                    format!("{:.2}", c.lr)
                } else {
                    "-".into()
                },
                p_text(c.p_value),
                p_text(c.p_holm),
                format!("{} = {}", c.estimate_name, opt(c.estimate, 4)),
                c.ci95.map_or("-".into(), |(a, b)| {
                    format!("{a:.4} .. {b:.4} ({})", c.ci95_method)
                }),
                phase_text(c).unwrap_or_default(),
                remarks(c).unwrap_or_default(),
            ]
        })
        .collect();
    page.table(
        &[
            "candidate",
            "LR",
            "p (bootstrap)",
            "p (Holm)",
            "estimate",
            "95% interval",
            "phase",
            "note",
        ],
        &rows,
    );
}

/// The noise model, M0's goodness of fit and the errors' correlation along speed.
fn noise_section(page: &mut Page, d: &Discovery) {
    page.heading("Noise");
    page.paragraph(&format!("M0's {}.", noise_text(d)));
    let names: Vec<String> = d
        .training_loads_n
        .iter()
        .map(|l| format!("{l:.0} N"))
        .collect();
    if let Some(c) = &d.noise_correlation {
        page.paragraph(&format!("{}.", correlation_text(c, &names)));
    }
    if let Some(text) = discovery_stated_ste_text(d) {
        page.paragraph(&format!("M0's fit: {text}."));
    }
    if let Some(h) = &d.held_out_prediction {
        page.paragraph(&format!(
            "M0's prediction of the held-out loads (each load's STE fitted alone, zeta and omega_n from the training loads) has deviance -2 log L = {:.1} under the training loads' noise; bootstrap p {}, {} after Holm's correction with the candidates. A small p says M0 predicts loads it did not see worse than its errors allow: an effect the training fit absorbed.",
            h.statistic,
            p_text(h.p_value),
            p_text(h.p_holm)
        ));
    }
    page.paragraph(&format!(
        "M0's chi-square of innovations (the standardized residuals decorrelated along speed) is {:.1}; bootstrap p {}{}.",
        d.goodness_of_fit.statistic,
        p_text(d.goodness_of_fit.p_value),
        match d.goodness_of_fit.p_holm {
            Some(p) => format!(", {} after Holm's correction with the candidates", p_text(Some(p))),
            None => " (with the noise fitted to the same residuals it is near its degrees of freedom by construction: reported, not decisive)".to_string(),
        }
    ));
}

/// The points left out of the likelihood, their measured and predicted ranges.
fn excluded_section(page: &mut Page, d: &Discovery) {
    if d.excluded_by_load.is_empty() {
        return;
    }
    page.heading("Points left out of the likelihood");
    page.paragraph("Where M0 predicts non-period-1 motion, or a jump between two speeds, a point-wise residual says nothing: these points are left out of every fit and gap. The ranges below compare them anyway. A measured chaotic pp is one observation window's sample, so M0's range includes, at each of its chaotic or aperiodic points, the pp of 32 consecutive windows of 64 periods after the predicted one.");
    let rows: Vec<Vec<String>> = d
        .excluded_by_load
        .iter()
        .map(|e| {
            vec![
                format!("{}", e.load_n),
                e.points.to_string(),
                e.non_period1.to_string(),
                format!(
                    "{:.1} .. {:.1}",
                    e.measured_range_um.0, e.measured_range_um.1
                ),
                format!(
                    "{:.1} .. {:.1}",
                    e.predicted_range_um.0, e.predicted_range_um.1
                ),
                format!("{:.1} .. {:.1}", e.model_range_um.0, e.model_range_um.1),
                e.outside_model_range.to_string(),
            ]
        })
        .collect();
    page.table(
        &[
            "load (N)",
            "points left out",
            "non-period-1 in M0",
            "measured pp (um)",
            "M0 predicted pp (um)",
            "M0 pp over 32 windows (um)",
            "measured outside by > 3 sigma + 10% of its top",
        ],
        &rows,
    );
}

/// The gap before and after on the training and held-out loads, and the residual figures.
fn gap_section(page: &mut Page, d: &Discovery) {
    page.heading("Gap before and after");
    let mut g = vec![vec![
        "training".into(),
        gap_text(&d.gap_before.training),
        gap_text(&d.gap_after.training),
    ]];
    if let (Some(b), Some(a)) = (&d.gap_before.held_out, &d.gap_after.held_out) {
        g.push(vec!["held out".into(), gap_text(b), gap_text(a)]);
    }
    page.table(
        &[
            "loads",
            "before (M0)",
            format!("after ({})", d.gap_after_model).as_str(),
        ],
        &g,
    );
    page.image("residuals_before.png", "residuals of M0 versus Omega");
    page.image(
        "residuals_after.png",
        "residuals after adding the effect versus Omega",
    );
}

/// The stated STEs against M0's fits, training and held-out loads, in words
/// ([`super::stated_ste_text`]; each row's parameter is its place in the list).
pub fn discovery_stated_ste_text(d: &Discovery) -> Option<String> {
    let fits: Vec<crate::fit::MeasurementFit> = d
        .stated_ste
        .iter()
        .enumerate()
        .map(|(k, (_, m))| {
            let mut m = *m;
            m.measurement.param = k;
            m
        })
        .collect();
    super::stated_ste_text(&fits, |k| format!("{} N", d.stated_ste[k].0))
}
