//! Outputs of `validate kubo`: `fits/kubo.json` and `reports/kubo/` (D_L against the measured
//! envelope, index.html, report.md).

use super::data_kind_banner;
use super::html::Page;
use super::staging::{finish_report, Staged};
use crate::data::{DataKind, KuboData};
use crate::error::Result;
use crate::plot::{write_xy, Series, XyPlot};
use crate::validate::KuboValidation;
use serde_json::json;
use std::path::{Path, PathBuf};

/// The fitted-parameter record.
pub fn kubo_json(data: &KuboData, r: &KuboValidation) -> serde_json::Value {
    let src = &data.rig.source;
    let ci = |i: usize| {
        json!({
            "covariance": r.fit.as_ref().and_then(|f| f.ci95.get(i).map(|(a, b)| [*a, *b])),
            "profile": r.ci95_profile.get(i).map(|(a, b)| [*a, *b]),
        })
    };
    json!({
        "data_kind": src.kind.name(),
        "notice": data_kind_banner(&data.rig),
        "parameter_source": r.parameter_source,
        "zeta": r.zeta,
        "zeta_std_error": r.fit.as_ref().map(|f| f.std_errors[0]),
        "zeta_ci95": ci(0),
        "omega_n_hz": r.omega_n_hz,
        "omega_n_hz_std_error": r.fit.as_ref().map(|f| f.std_errors[1]),
        "omega_n_hz_ci95": ci(1),
        "ste_um": r.ste_um,
        "ste_source": r.ste_source,
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
    let stage = Staged::new(reports_dir)?;
    let mut page = Page::new("geardyn validate kubo: dynamic factor", &banner, synthetic);
    page.paragraph(&format!(
        "zeta = {:.4}, omega_n = {:.1} Hz ({}; {} points with D_L < {} used), STE {:.2} um ({}), load {} N (F_m = {:.4}).",
        r.zeta,
        r.omega_n_hz,
        r.parameter_source,
        r.points_used_in_fit,
        crate::validate::KUBO_CONTACT_LIMIT,
        r.ste_um,
        r.ste_source,
        r.load_n,
        r.mean_force
    ));
    let opt = |v: Option<f64>| v.map_or("-".to_string(), |x| format!("{x:.0}"));
    page.table(
        &[
            "inside envelope",
            "RMS outside envelope",
            "jump measured (rpm)",
            "jump model up (rpm)",
            "jump error (rpm)",
        ],
        &[vec![
            format!("{:.0}%", 100.0 * r.inside_fraction),
            format!("{:.3}", r.outside_rms),
            opt(r.jump_measured_rpm),
            opt(r.jump_up_rpm),
            opt(r.jump_error_rpm),
        ]],
    );
    if let Some(t) = &data.rig.source.truth {
        page.heading("Truth of the synthetic data (recorded in rig.toml, never read by the fit)");
        page.preformatted(&toml::to_string(t).unwrap_or_default());
    }
    let plot = XyPlot {
        title: format!("Dynamic factor ({kind} data)"),
        caption: Some(format!(
            "zeta = {:.4}, omega_n = {:.0} Hz, F_m = {:.4}, F_ah = {:.4}",
            r.zeta, r.omega_n_hz, r.mean_force, r.ste_amplitude
        )),
        x_label: "speed (rpm)".into(),
        y_label: "dynamic factor".into(),
        series: vec![
            Series::dashed(
                format!("measured envelope min ({kind})"),
                r.envelope.iter().map(|e| (e.0, e.1)).collect(),
            )
            .with_color(0),
            Series::dashed(
                format!("measured envelope max ({kind})"),
                r.envelope.iter().map(|e| (e.0, e.2)).collect(),
            )
            .with_color(0),
            Series::line(
                "model D_L, speed up",
                r.up.iter().map(|u| (u.0, u.1)).collect(),
            )
            .with_color(1),
            Series::line(
                "model D_L, speed down",
                r.down.iter().map(|u| (u.0, u.1)).collect(),
            )
            .with_color(2),
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
