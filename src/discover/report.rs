//! Outputs of `geardyn discover`: discovery.json (design.md 3: effect, candidates [{name,
//! estimate, ci95, p_value}], gap_before, gap_after, and more), report.md / index.html and the
//! residual plots before and after (PNG + SVG) with the Omega windows marked. The folder is
//! staged and moved into place only when complete.

use super::effects::Candidate;
use super::forward::MIN_ZETA;
use super::noise::NoiseOrigin;
use super::run::{CandidateResult, Discovery, Gap, ResidualCurve};
use crate::data::{DataKind, MunroData};
use crate::error::{GearError, Result};
use crate::fit::{Distribution, NoiseModel};
use crate::numeric::min_max;
use crate::plot::{write_xy, Series, XyPlot};
use crate::report::{data_kind_banner, Page, Staged};
use serde_json::json;
use std::path::{Path, PathBuf};

/// The discovery.json record; its first field is the data-kind notice.
pub fn discovery_json(data: &MunroData, d: &Discovery) -> serde_json::Value {
    json!({
        "notice": data_kind_banner(&data.rig),
        "data_kind": data.rig.source.kind.name(),
        "effect": d.effect,
        "ambiguous_with": d.ambiguous_with,
        "held_out_prefers": d.held_out_prefers,
        "closest_candidate": d.closest_candidate,
        "detected": d.detected,
        "detected_by_tests": d.detected_by_tests,
        "detected_by_excluded_points": d.detected_by_excluded_points(),
        "candidates": d.candidates.iter().map(|c| json!({
            "name": c.name,
            "estimate": c.estimate,
            "estimate_of": c.estimate_name,
            "ci95": c.ci95.map(|(a, b)| [a, b]),
            "ci95_method": c.ci95_method,
            "wald_ci95": c.wald_ci95.map(|(a, b)| [a, b]),
            "profile_ci95": c.profile_ci95.map(|(a, b)| [a, b]),
            "interval_quantile": c.interval_quantile,
            "p_value": c.p_value,
            "p_holm": c.p_holm,
            "identifiable": c.identifiable,
            "note": c.note,
            "failed": c.failed,
            "score": c.score,
            "score_p_approx": c.score_p_approx,
            "lr": c.lr,
            "refit_lr": c.refit_lr,
            "delta": c.delta,
            "refit_zeta": c.refit_zeta,
            "refit_omega_n_hz": c.refit_omega_n_hz,
            "refit_other_start": c.other_start,
            "phase_deg": c.phase_deg,
            "phase_wald95_deg": c.phase_wald95_deg.iter().map(|(a, b)| [a, b]).collect::<Vec<_>>(),
            "phase_profile95_deg": c.phase_profile95_deg.map(|(a, b)| [a, b]),
        })).collect::<Vec<_>>(),
        "gap_before": d.gap_before,
        "gap_after": d.gap_after,
        "gap_after_model": d.gap_after_model,
        "detection": d.detection,
        "post_fit": d.post_fit,
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

/// The noise record of discovery.json: where it came from, the model (floor in um, relative part,
/// distribution), the scales it gives over the kept points, and how it was chosen.
fn noise_json(d: &Discovery) -> serde_json::Value {
    let n = &d.noise;
    let (dist, dof) = distribution_json(&n.model);
    let replicates = n.replicate_model.map(|m| {
        let (dist, dof) = distribution_json(&m);
        json!({"floor_um": m.floor, "relative": m.relative, "distribution": dist, "dof": dof})
    });
    json!({
        "source": n.origin,
        "description": n.origin.describe(),
        "floor_um": n.per_point.is_none().then_some(n.model.floor),
        "relative": n.per_point.is_none().then_some(n.model.relative),
        "distribution": dist,
        "dof": dof,
        "scale_range_um": [d.noise_range_um.0, d.noise_range_um.1],
        "relative_lr_adjusted": n.relative_lr,
        "replicates": replicates,
        "tails_lr_adjusted": n.tails_lr,
        "pseudo_residuals": n.pseudo_residuals,
        "trimmed": n.trimmed,
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
    let tails = tails_text(&n.model);
    let (lo, hi) = d.noise_range_um;
    // A range only where the scales differ at the printed digits.
    let range = if format!("{lo:.3}") == format!("{hi:.3}") {
        String::new()
    } else {
        format!("; {lo:.3}-{hi:.3} µm over the kept points")
    };
    // Where the test dropped the relative part, the bootstrap draws with it free.
    let replicates = n.replicate_model.map_or(String::new(), |m| {
        format!(
            "; bootstrap replicates drawn with the relative part free: {} ({})",
            scale_text(&m),
            tails_text(&m)
        )
    });
    format!(
        "noise {model} ({tails}{range}), {}{replicates}",
        n.origin.describe()
    )
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
            100.0 * super::windows::HALF_WIDTH
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
        plot = plot.with_series(Series::line_markers(label, pts).with_color(k));
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

/// Where a phase-carrying candidate's best refit in another phase basin ended, when one did.
fn other_start_text(c: &CandidateResult) -> Option<String> {
    let (o, kept) = (c.other_start.as_ref()?, c.delta.as_ref()?);
    let deg = |d: &[f64]| Candidate::first_phase(d).to_degrees().rem_euclid(360.0);
    Some(format!(
        "{}: the best refit in another phase basin ended at phase {:.0} deg (kept: {:.0} deg) with a training -2 log-likelihood larger by {:.2}{}",
        c.name,
        deg(&o.delta),
        deg(kept),
        o.deviance_increase,
        if o.phase_undetermined() {
            "; within chi2(0.95; 1) = 3.84 at a different phase: the training loads do not determine the phase, and the interval spans both fits"
        } else {
            ""
        }
    ))
}

/// A refitted phase-carrying candidate's phase and its 95% arcs (two when the phase is
/// undetermined between two basins), e.g. "315 deg (Wald 95% 312 .. 318)", with the profile's
/// arc when the phase was profiled ("profile 95% 300 .. 320"); empty otherwise.
fn phase_text(c: &CandidateResult) -> String {
    let Some(p) = c.phase_deg else {
        return String::new();
    };
    // Degrees to enough digits that a narrow arc is not printed as a point.
    let arc = |&(a, b): &(f64, f64)| {
        if b - a >= 360.0 {
            "any".to_string()
        } else if b - a < 4.0 {
            format!("{a:.1} .. {b:.1}")
        } else {
            format!("{a:.0} .. {b:.0}")
        }
    };
    let arcs: Vec<String> = c.phase_wald95_deg.iter().map(arc).collect();
    let mut parts = Vec::new();
    if !arcs.is_empty() {
        parts.push(format!("Wald 95% {}", arcs.join(" or ")));
    }
    if let Some(profile) = &c.phase_profile95_deg {
        parts.push(format!("profile 95% {}", arc(profile)));
    }
    if parts.is_empty() {
        format!("{p:.0} deg")
    } else {
        format!("{p:.0} deg ({})", parts.join("; "))
    }
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
        held_out_split_text(d),
        significant_undetected_text(d),
    ]
    .into_iter()
    .flatten()
    .collect()
}

/// The note when the noise was stated and the answer is "unexplained" with a scatter about the
/// best model larger than every stated scale: a noise stated too small makes every test reject,
/// whatever the model. On a set of scatter 0.15 um with `[noise] floor_um = 0.1` the answer was
/// "unexplained" and nothing said why.
fn stated_noise_text(d: &Discovery) -> Option<String> {
    let stated = !matches!(d.noise.origin, NoiseOrigin::Estimated { .. });
    let rms = d.gap_after.training.rms_um;
    let largest = d.noise_range_um.1;
    (stated && d.effect == "unexplained" && rms > largest).then(|| {
        format!(
            "the noise is {}, and the training RMS about {}, {rms:.3} µm, exceeds every stated scale (at most {largest:.3} µm): a noise stated smaller than the scatter makes every test reject, whatever the model; without the statement it is estimated from the data",
            d.noise.origin.describe(),
            d.gap_after_model
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

/// A bootstrap p-value to three decimals, or "<0.001" below that: the smallest p of 1999
/// replicates, 1 / 2000, would otherwise print as 0.001.
fn p_text(p: Option<f64>) -> String {
    match p {
        Some(p) if p < 0.001 => "<0.001".into(),
        p => opt(p, 3),
    }
}

/// A few lines for the terminal.
pub fn summary_text(d: &Discovery) -> String {
    let mut s = format!(
        "effect: {}{}\nM0: zeta {:.5}, omega_n {:.1} Hz; {}\n",
        d.effect,
        if d.ambiguous_with.is_empty() {
            d.closest_candidate.as_ref().map_or_else(
                || unexplained_by_excluded_text(d).unwrap_or_default(),
                |c| format!(" (closest candidate {c} leaves a discrepancy)"),
            )
        } else {
            format!(" between {}", d.ambiguous_with.join(", "))
        },
        d.zeta_m0,
        d.omega_n_hz_m0,
        noise_text(d)
    );
    for t in notes(d) {
        s.push_str(&format!("NOTE: {t}\n"));
    }
    for c in &d.candidates {
        s.push_str(&format!(
            "  {:<26} LR {:8.1}  p {:>6}  estimate {} {} [{} .. {}]{}{}{}\n",
            c.name,
            c.lr,
            p_text(c.p_value),
            c.estimate_name,
            opt(c.estimate, 4),
            opt(c.ci95.map(|x| x.0), 4),
            opt(c.ci95.map(|x| x.1), 4),
            interval_method_text(c),
            Some(phase_text(c))
                .filter(|t| !t.is_empty())
                .map_or(String::new(), |t| format!(", phase {t}")),
            remarks(c).map_or(String::new(), |n| format!("  ({n})"))
        ));
    }
    for t in d.candidates.iter().filter_map(other_start_text) {
        s.push_str(&format!("  {t}\n"));
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

/// Where the ends of M0's confidence region were clamped, as a clause (empty when none was).
fn clamped_text(clamped: &[&str]) -> String {
    if clamped.is_empty() {
        String::new()
    } else {
        format!(
            " (ends clamped: {}; the region there is the linearisation's, not the data's)",
            clamped.join(", ")
        )
    }
}

/// One line per load with excluded points, and a warning when measured points lie outside
/// everything M0 predicts there.
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
        let region = e.region_range_um.map_or_else(String::new, |r| {
            format!(
                ", {} over the models at the ends of M0's 95% confidence region in zeta and omega_n{}",
                range(r),
                clamped_text(&e.region_clamped)
            )
        });
        s.push_str(&format!(
            "excluded from the tests at {} N: {} points ({} non-period-1 in M0), measured {}, M0 predicted {predicted} ({over_windows} over 32 observation windows at its points that are not period-1{region}), {} measured far outside the widest of these\n",
            e.load_n,
            e.points,
            e.non_period1,
            range(e.measured_range_um),
            e.outside_model_range
        ));
    }
    if let Some(w) = excluded_warning(d) {
        s.push_str(&w);
        s.push('\n');
    }
    s
}

/// The warning when excluded points lie far outside M0's range, if any do.
fn excluded_warning(d: &Discovery) -> Option<String> {
    let outside = d.excluded_far_outside();
    (outside > 0).then(|| format!(
        "WARNING: {outside} excluded point(s) lie far outside every pp M0 produces there, in any observation window and at the ends of its 95% confidence region (by more than 3 sigma + 10% of the largest); the tests do not use them, the decision counts them as a detected discrepancy: look at the curves"
    ))
}

/// Why a candidate significant among the candidates' tests is neither refitted nor named.
/// Why the answer is "ambiguous" when the held-out loads prefer another candidate.
fn held_out_split_text(d: &Discovery) -> Option<String> {
    let other = d.held_out_prefers.as_ref()?;
    let leading = d.ambiguous_with.first()?;
    Some(format!(
        "The training loads prefer {leading}, but its refit fails the held-out chi-square; {other}'s refit passes both the training and the held-out chi-square: the loads do not agree on one effect."
    ))
}

fn significant_undetected_text(d: &Discovery) -> Option<String> {
    (!d.significant_undetected.is_empty()).then(|| {
        format!(
            "{} significant among the candidates' tests, but no discrepancy is detected (Holm over all the tests of M0, detection and candidates together, does not reject it): not refitted and not named (a name needs a detected discrepancy; on the null studies every name given without one was false).",
            d.significant_undetected.join(", ")
        )
    })
}

/// Why the effect is "unexplained" when only the excluded points detected a discrepancy and
/// no candidate is significant.
fn unexplained_by_excluded_text(d: &Discovery) -> Option<String> {
    (d.effect == "unexplained" && d.detected_by_excluded_points() && !d.detected_by_tests).then(
        || {
            format!(
                " (no test significant, but {} excluded point(s) lie far outside M0's range, and no candidate is significant)",
                d.excluded_far_outside()
            )
        },
    )
}

/// Write the output folder `out`; returns the files written.
pub fn write_discovery(data: &MunroData, d: &Discovery, out: &Path) -> Result<Vec<PathBuf>> {
    let banner = data_kind_banner(&data.rig);
    let stage = Staged::replacing(out)?;
    let mut files = vec!["discovery.json".to_string()];
    for (name, curves, title) in [
        (
            "residuals_before",
            &d.residuals_before,
            "Residuals of M0 (paper's model)",
        ),
        (
            "residuals_after",
            &d.residuals_after,
            "Residuals with the leading candidate added (M0 if none)",
        ),
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
    detection_section(
        &mut page,
        "Detection (bootstrap p-values under M0, Holm-adjusted over these and the candidates' tests)",
        &d.detection,
    );
    candidates_section(&mut page, d);
    if !d.post_fit.is_empty() {
        detection_section(
            &mut page,
            "Detection tests after adding the leading candidate",
            &d.post_fit,
        );
    }
    excluded_section(&mut page, d);
    gap_section(&mut page, d);
    let (html, md) = page.finish("geardyn discover");
    stage.write("index.html", &html)?;
    stage.write("report.md", &md)?;
    files.push("index.html".into());
    files.push("report.md".into());
    let dest = stage.commit()?;
    Ok(files.into_iter().map(|f| dest.join(f)).collect())
}

/// The answer, the loads, M0's fit, the noise, and the notes that qualify the answer.
fn summary_section(page: &mut Page, d: &Discovery) {
    page.paragraph(&format!(
        "Effect: {}{}. Training loads {:?} N, held-out loads {:?} N. M0 fitted on the training loads: zeta {:.5}, omega_n {:.1} Hz. {}. {} points excluded from the tests. {} bootstrap replicates under M0.",
        d.effect,
        if d.ambiguous_with.is_empty() { unexplained_by_excluded_text(d).unwrap_or_default() } else { format!(" ({})", d.ambiguous_with.join(", ")) },
        d.training_loads_n,
        d.held_out_loads_n,
        d.zeta_m0,
        d.omega_n_hz_m0,
        noise_text(d),
        d.excluded_points,
        d.bootstrap
    ));
    for t in notes(d) {
        page.paragraph(&t);
    }
}

/// A table of detection tests: statistic, bootstrap p-value and Holm-adjusted p-value.
fn detection_section(page: &mut Page, heading: &str, tests: &[super::run::TestResult]) {
    page.heading(heading);
    let rows: Vec<Vec<String>> = tests
        .iter()
        .map(|x| {
            vec![
                x.name.clone(),
                if x.statistic.is_nan() {
                    "- (no points in the window)".to_string()
                } else {
                    format!("{:.2}", x.statistic)
                },
                opt(x.p_value, 4),
                opt(x.p_holm, 4),
            ]
        })
        .collect();
    page.table(&["test", "statistic", "p", "p (Holm)"], &rows);
}

/// What is said of a candidate beside its numbers: "failed, because ..." when it failed, and
/// its note; None when neither.
fn remarks(c: &CandidateResult) -> Option<String> {
    let failed = c.failed.as_ref().map(|b| format!("failed, because {b}"));
    let said: Vec<String> = failed.into_iter().chain(c.note.clone()).collect();
    (!said.is_empty()).then(|| said.join("; "))
}

/// Every candidate's score, test, refit estimate with its interval and phase.
fn candidates_section(page: &mut Page, d: &Discovery) {
    page.heading("Candidates");
    let rows: Vec<Vec<String>> = d
        .candidates
        .iter()
        .map(|c| {
            vec![
                c.name.to_string(),
                format!("{:.2}", c.score),
                format!("{:.2}", c.lr),
                opt(c.p_value, 4),
                opt(c.p_holm, 4),
                format!("{} = {}", c.estimate_name, opt(c.estimate, 4)),
                c.ci95.map_or("-".into(), |(a, b)| {
                    format!("{a:.4} .. {b:.4}{}", interval_method_text(c))
                }),
                phase_text(c),
                remarks(c).unwrap_or_default(),
            ]
        })
        .collect();
    page.table(
        &[
            "candidate",
            "score",
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
    for t in d.candidates.iter().filter_map(other_start_text) {
        page.paragraph(&t);
    }
}

/// The points left out of the tests, their measured and predicted ranges.
fn excluded_section(page: &mut Page, d: &Discovery) {
    if d.excluded_by_load.is_empty() {
        return;
    }
    page.heading("Points excluded from the tests");
    page.paragraph("Where M0 predicts non-period-1 motion, or a jump between two speeds, a point-wise residual says nothing: these points are left out of every test and gap. The ranges below compare them anyway. A measured chaotic pp is one observation window's sample, so M0's range includes, at each of its chaotic or aperiodic points, the pp of 32 consecutive windows of 64 periods after the predicted one. Where a measured point lies far outside that range, the range is widened over the models at the ends of M0's 95% confidence region in zeta and omega_n (the training STE amplitudes at their conditional best, the held-out ones fitted again): the question is whether any model the data allow reaches the point. Measured points far outside the widest range (by more than 3 sigma plus 10% of its largest pp: beyond the noise, beyond any window of the motion and beyond the onset of non-period-1 motion moving a little with the parameters) are a discrepancy the tests cannot see.");
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
                e.region_range_um
                    .map_or_else(|| "-".into(), |r| format!("{:.1} .. {:.1}", r.0, r.1)),
                e.outside_model_range.to_string(),
            ]
        })
        .collect();
    page.table(
        &[
            "load (N)",
            "excluded points",
            "non-period-1 in M0",
            "measured pp (um)",
            "M0 predicted pp (um)",
            "M0 pp over 32 windows (um)",
            "over M0's 95% confidence region (um)",
            "measured outside the widest range by > 3 sigma + 10% of its top",
        ],
        &rows,
    );
    if let Some(e) = d
        .excluded_by_load
        .iter()
        .find(|e| !e.region_clamped.is_empty())
    {
        page.paragraph(&format!(
            "M0's confidence region{}.",
            clamped_text(&e.region_clamped)
        ));
    }
    if let Some(w) = excluded_warning(d) {
        page.paragraph(&w);
    }
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
    page.table(&["loads", "before (M0)", "after"], &g);
    page.image("residuals_before.png", "residuals of M0 versus Omega");
    page.image(
        "residuals_after.png",
        "residuals after adding the effect versus Omega",
    );
}

/// " (hull of the profile-likelihood and Wald intervals)" and the like after an interval that
/// is not the Wald interval every refit gets, and the Student-t quantile it spans where the
/// noise was estimated (1.96 goes without saying).
fn interval_method_text(c: &CandidateResult) -> String {
    if c.ci95.is_none() {
        return String::new();
    }
    let mut parts = Vec::new();
    if c.ci95_method != "Wald" {
        parts.push(c.ci95_method.to_string());
    }
    if let Some(q) = c.interval_quantile.filter(|q| *q > 1.965) {
        parts.push(format!("Student-t quantile {q:.2}"));
    }
    if parts.is_empty() {
        String::new()
    } else {
        format!(" ({})", parts.join("; "))
    }
}
