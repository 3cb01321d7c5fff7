//! Outputs of `validate kubo`: `fits/kubo.json` and `reports/kubo/` (D_L against the measured
//! envelope, index.html, report.md).

use super::html::Page;
use super::staging::{finish_report, Staged};
use super::{
    any_stepped, data_kind_banner, interval_digits, narrow_fisher_note, profile_cell, STEPPED_NOTE,
};
use crate::data::{DataKind, KuboData};
use crate::error::Result;
use crate::plot::{write_xy, Series, XyPlot};
use crate::validate::{spread_interval, KuboValidation, PAIR_SPREAD};
use serde_json::json;
use std::path::{Path, PathBuf};

/// Where the fit holds parameter `name`, if it fitted it: looked up by name, since the STE is
/// not a fitted parameter when held, and the pair spread follows it only in the whole-curve fit.
fn fitted_index(r: &KuboValidation, name: &str) -> Option<usize> {
    r.fit
        .as_ref()
        .and_then(|f| f.names.iter().position(|n| n == name))
}

/// The fitted-parameter record.
pub fn kubo_json(data: &KuboData, r: &KuboValidation) -> serde_json::Value {
    let src = &data.rig.source;
    let index = |name: &str| fitted_index(r, name);
    let ci = |name: &str| {
        let i = index(name);
        json!({
            "covariance": r.fit.as_ref().zip(i).and_then(|(f, i)| f.ci95.get(i).map(|(a, b)| [*a, *b])),
            "profile": i.and_then(|i| r.ci95_profile.get(i)).map(|p| [p.lower, p.upper]),
            "profile_end_at_step": i.and_then(|i| r.ci95_profile.get(i)).map(|p| p.stepped),
        })
    };
    let std_error = |name: &str| {
        r.fit
            .as_ref()
            .zip(index(name))
            .and_then(|(f, i)| f.std_errors.get(i).copied())
    };
    let value = |name: &str| r.fit.as_ref().zip(index(name)).map(|(f, i)| f.params[i]);
    json!({
        "data_kind": src.kind.name(),
        "notice": data_kind_banner(&data.rig),
        "parameter_source": r.parameter_source,
        "zeta": r.zeta,
        "zeta_std_error": std_error("zeta"),
        "zeta_ci95": ci("zeta"),
        "omega_n_hz": r.omega_n_hz,
        "omega_n_hz_std_error": std_error("omega_n_hz"),
        "omega_n_hz_ci95": ci("omega_n_hz"),
        "ste_um": r.ste_um,
        "ste_um_std_error": std_error("ste_um"),
        "ste_um_ci95": ci("ste_um"),
        "noise_correlation": r.fit.as_ref().and_then(|f| f.noise.correlation.as_ref()),
        // The curve is even in the spread; its sign is the fit's accident.
        "pair_ste_half_spread": value(PAIR_SPREAD).map(f64::abs),
        "pair_ste_half_spread_std_error": std_error(PAIR_SPREAD),
        "ste_source": r.ste_source,
        "stated_ste": r.fit.as_ref().map(super::stated_ste_json).unwrap_or_default(),
        "load_n": r.load_n,
        "mean_force": r.mean_force,
        "points_used_in_fit": r.points_used_in_fit,
        "per_load": [{
            "load_n": r.load_n,
            "inside_envelope_fraction": r.inside_fraction,
            "outside_envelope_rms": r.outside_rms,
            "jump_measured_rpm": r.jump_measured_rpm,
            "jump_up_rpm": r.jump_up_rpm,
            "jump_error_rpm": r.jump_error_rpm,
            "jump_error_resolution_rpm": r.jump_error_resolution_rpm,
        }],
        "provenance": {
            "geardyn": env!("CARGO_PKG_VERSION"),
            "data_dir": data.dir.display().to_string(),
            "rig": data.rig.rig.name,
            "citation": src.citation,
            "figure": src.figure,
            "method": src.method,
            "uncertainty": src.uncertainty,
            "generator": src.generator,
            "truth_recorded_in_rig_toml": src.truth.as_ref().map(|t| toml::to_string(t).unwrap_or_default()),
        },
    })
}

/// Write fits/kubo.json and the report folder; returns the files written.
pub fn write_kubo_report(
    data: &KuboData,
    r: &KuboValidation,
    fits_dir: &Path,
    reports_dir: &Path,
) -> Result<Vec<PathBuf>> {
    let banner = data_kind_banner(&data.rig);
    let synthetic = data.rig.source.kind == DataKind::Synthetic;
    let kind = data.rig.source.kind.name();
    let stage = Staged::replacing(reports_dir)?;
    let mut page = Page::new("geardyn validate kubo: dynamic factor", &banner, synthetic);
    parameter_table(&mut page, r);
    let opt = |v: Option<f64>| v.map_or("-".to_string(), |x| format!("{x:.0}"));
    page.heading("Prediction against the measured envelope");
    page.table(
        &[
            "inside envelope",
            "RMS outside envelope",
            "transition measured (rpm)",
            "transition model up (rpm)",
            "transition error (rpm)",
        ],
        &[vec![
            format!("{:.0}%", 100.0 * r.inside_fraction),
            format!("{:.3}", r.outside_rms),
            opt(r.jump_measured_rpm),
            opt(r.jump_up_rpm),
            r.transition_error_text(""),
        ]],
    );
    page.paragraph("Columns:");
    page.definitions(&[
        ("inside envelope", "share of the measured speeds where the model's D_L (speed-up sweep) lies between the envelope's minimum and maximum."),
        ("RMS outside envelope", "root mean square distance of the model's D_L from the nearer envelope edge, over the speeds where it lies outside (dimensionless, as D_L)."),
        ("transition measured / model up (rpm)", "Kubo's transition frequency as a speed: the first steep step of the envelope's mean (larger than 6 median steps and a quarter of the largest step), and of the model's speed-up sweep; a jump or the steep flank of the resonance alike."),
        ("transition error (rpm)", "model transition minus measured transition, ± how finely the grids place it (half the envelope's speed step at its transition plus half the model sweep's at its own)."),
    ]);
    if let Some(t) = &data.rig.source.truth {
        page.heading("Truth of the synthetic data (recorded in rig.toml, never read by the fit)");
        page.preformatted(&toml::to_string(t).unwrap_or_default());
    }
    let plot = XyPlot {
        title: format!("Dynamic factor ({kind} data)"),
        caption: Some(format!(
            "zeta = {:.4}, omega_n = {:.0} Hz, F_m = {:.4}, F_ah = {:.4} (dimensionless forces)",
            r.zeta, r.omega_n_hz, r.mean_force, r.ste_amplitude
        )),
        x_label: "speed (rpm)".into(),
        y_label: "dynamic factor".into(),
        // Envelope edges in two line styles; the down sweep dashed under the solid up sweep,
        // so both show where they part and the legend notes where they coincide.
        series: vec![
            Series::dotted(
                format!("measured envelope min ({kind})"),
                r.envelope.iter().map(|e| (e.0, e.1)).collect(),
            )
            .with_color(0),
            Series::dashed(
                format!("measured envelope max ({kind})"),
                r.envelope.iter().map(|e| (e.0, e.2)).collect(),
            )
            .with_color(9),
            Series::dashed(
                "model D_L, speed down",
                r.down.iter().map(|u| (u.0, u.1)).collect(),
            )
            .with_color(2),
            Series::line(
                "model D_L, speed up",
                r.up.iter().map(|u| (u.0, u.1)).collect(),
            )
            .with_color(1),
        ],
        ..XyPlot::default()
    };
    write_xy(&plot, &stage.path("dynamic_factor"))?;
    page.image(
        "dynamic_factor.png",
        "dynamic factor against the measured envelope",
    );
    finish_report(
        stage,
        page,
        "geardyn validate kubo",
        &fits_dir.join("kubo.json"),
        &kubo_json(data, r),
    )
}

/// The parameters first: estimate, 95% intervals, unit and source, then the load's setting.
fn parameter_table(page: &mut Page, r: &KuboValidation) {
    let index = |name: &str| fitted_index(r, name);
    let fisher = |i: Option<usize>| {
        r.fit
            .as_ref()
            .zip(i)
            .and_then(|(f, i)| f.ci95.get(i).copied())
    };
    let interval = |c: Option<(f64, f64)>, min: usize| {
        c.map_or("-".to_string(), |(lo, hi)| {
            let d = interval_digits(lo, hi, min);
            format!("[{lo:.d$}, {hi:.d$}]")
        })
    };
    let profile =
        |i: Option<usize>, min: usize| profile_cell(i.and_then(|i| r.ci95_profile.get(i)), min);
    let source = match (&r.fit, r.points_used_in_fit) {
        (None, _) => r.parameter_source.clone(),
        (Some(_), n) if n == r.envelope.len() => {
            format!("{} (all {n} measured speeds)", r.parameter_source)
        }
        (Some(_), n) => format!(
            "{} ({n} points with D_L < {})",
            r.parameter_source,
            crate::validate::KUBO_CONTACT_LIMIT
        ),
    };
    let (zeta, omega, ste) = (index("zeta"), index("omega_n_hz"), index("ste_um"));
    let digits = |i: Option<usize>, min: usize| {
        fisher(i).map_or(min, |(lo, hi)| interval_digits(lo, hi, min))
    };
    let (dz, dw) = (digits(zeta, 4), digits(omega, 1));
    page.heading("Parameters");
    let mut rows = vec![
        vec![
            "ζ (damping ratio)".into(),
            format!("{:.dz$}", r.zeta),
            interval(fisher(zeta), 4),
            profile(zeta, dz),
            "".into(),
            source.clone(),
        ],
        vec![
            "ωₙ (natural frequency)".into(),
            format!("{:.dw$}", r.omega_n_hz),
            interval(fisher(omega), 1),
            profile(omega, dw),
            "Hz".into(),
            source,
        ],
        vec![
            "STE amplitude".into(),
            format!("{:.3}", r.ste_um),
            interval(fisher(ste), 3),
            profile(ste, 3),
            "µm".into(),
            r.ste_source.clone(),
        ],
        vec![
            "load".into(),
            format!("{}", r.load_n),
            "-".into(),
            "-".into(),
            "N".into(),
            format!(
                "rig.toml (Fₘ = {:.4}, Fₐₕ = {:.4}, dimensionless)",
                r.mean_force, r.ste_amplitude
            ),
        ],
    ];
    if let (Some(fit), Some(i)) = (&r.fit, index(PAIR_SPREAD)) {
        let folded = spread_interval(fit.ci95[i]);
        rows.insert(
            3,
            vec![
                "pairs' STE half-spread h".into(),
                format!("{:.3}", fit.params[i].abs()),
                interval(Some(folded), 3),
                "-".into(),
                "".into(),
                "whole-curve fit: its envelope edges are two tooth pairs with STE amplitudes (1 ± h) times the STE; seen only where the pairs jump at different speeds".into(),
            ],
        );
    }
    page.table(
        &[
            "parameter",
            "estimate",
            "95% interval (Fisher)",
            "95% interval (profile)",
            "unit",
            "source",
        ],
        &rows,
    );
    if any_stepped(&r.ci95_profile) {
        page.paragraph(STEPPED_NOTE);
    }
    if let Some(fit) = &r.fit {
        let compared: Vec<_> = [("ζ", zeta), ("ωₙ", omega), ("the STE amplitude", ste)]
            .into_iter()
            .filter_map(|(label, i)| {
                Some((label, fisher(i)?, i.and_then(|i| r.ci95_profile.get(i))))
            })
            .collect();
        if let Some(note) = narrow_fisher_note(&compared) {
            page.paragraph(&note);
        }
        page.paragraph(&format!(
            "Noise of the fit: each point's standard deviation is s times its level (the \
             model's D_L there: the scatter between tooth pairs grows with D_L), s = {:.2}% \
             estimated from the residuals ({} points, {} residual degrees of freedom).",
            100.0 * fit.noise.model.relative,
            fit.n,
            fit.residual_dof
        ));
        let midline = [format!("{} N midline", r.load_n)];
        if let Some(text) = super::correlation_summary(fit, &midline) {
            page.heading("Errors along speed");
            page.paragraph(&text);
        }
        if let Some(text) = super::stated_ste_text(&fit.measurements, |_| format!("{} N", r.load_n))
        {
            page.heading("Stated STE");
            page.paragraph(&text);
        }
        // Critical damping bounds every damping the rig could have.
        if fit.ci95.first().is_some_and(|c| c.1 >= 1.0) {
            page.paragraph(
                "ζ's Fisher interval reaches beyond critical damping: these data determine ζ \
                 poorly, and the profile interval is the one to read.",
            );
        }
    }
}
