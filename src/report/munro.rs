//! Outputs of `validate munro`: `fits/munro.json` and `reports/munro/` (overlays per load,
//! residuals, index.html, report.md).

use super::data_kind_banner;
use super::html::Page;
use super::staging::{finish_report, Staged};
use crate::data::{DataKind, MunroData};
use crate::error::Result;
use crate::plot::{write_xy, Marker, Series, XyPlot};
use crate::validate::MunroValidation;
use serde_json::json;
use std::path::{Path, PathBuf};

fn ci(r: &MunroValidation, i: usize) -> serde_json::Value {
    let c = r.fit.ci95_covariance.get(i).copied();
    let p = r.ci95_profile.get(i).copied();
    json!({
        "covariance": c.map(|(a, b)| [a, b]),
        "profile": p.map(|(a, b)| [a, b]),
    })
}

/// The fitted-parameter record (design.md section 3 fields and more).
pub fn munro_json(data: &MunroData, r: &MunroValidation) -> serde_json::Value {
    let src = &data.rig.source;
    let ste_fitted = r.fit.names.iter().position(|n| n == "ste_um");
    json!({
        "data_kind": src.kind.name(),
        "notice": data_kind_banner(&data.rig),
        "zeta": r.zeta,
        "zeta_std_error": r.fit.std_errors[0],
        "zeta_ci95": ci(r, 0),
        "omega_n_hz": r.omega_n_hz,
        "omega_n_hz_std_error": r.fit.std_errors[1],
        "omega_n_hz_ci95": ci(r, 1),
        "ste_design_um": ste_fitted.map(|i| r.fit.params[i]),
        "ste_design_um_ci95": ste_fitted.map(|i| ci(r, i)),
        "residual_sigma_um": r.fit.sigma,
        "design_points": r.fit.n,
        "design_load_in_contact": r.design_load_in_contact,
        "mesh_stiffness_n_per_um": r.mesh_stiffness_n_per_um,
        "mesh_stiffness_source": r.stiffness_source,
        "half_backlash_um": r.half_backlash_um,
        "per_load": r.loads.iter().map(|l| json!({
            "load_n": l.load_n,
            "fitted": l.fitted,
            "mean_force": l.mean_force,
            "ste_um": l.ste_um,
            "ste_source": l.ste_source,
            "force_ratio": l.force_ratio,
            "rms_um": l.rms_um,
            "rms_up_um": l.rms_up_um,
            "rms_down_um": l.rms_down_um,
            "rms_period1_um": l.rms_period1_um,
            "not_period1_points": l.not_period1_points,
            "not_period1_measured_um": l.not_period1_measured_um,
            "not_period1_model_um": l.not_period1_model_um,
            "jump_measured_rpm": l.jump_measured_rpm,
            "jump_up_rpm": l.jump_up_rpm,
            "jump_down_rpm": l.jump_down_rpm,
            "jump_error_rpm": l.jump_error_rpm,
        })).collect::<Vec<_>>(),
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

/// Write fits/munro.json and the report folder; returns the files written.
pub fn write_munro_report(
    data: &MunroData,
    r: &MunroValidation,
    fits_dir: &Path,
    reports_dir: &Path,
) -> Result<Vec<PathBuf>> {
    let banner = data_kind_banner(&data.rig);
    let synthetic = data.rig.source.kind == DataKind::Synthetic;
    let stage = Staged::new(reports_dir)?;
    let kind = data.rig.source.kind.name();
    let mut page = Page::new(
        "geardyn validate munro: pp dynamic transmission error",
        &banner,
        synthetic,
    );
    page.paragraph(&format!(
        "zeta = {:.5} (95% profile {}), omega_n = {:.1} Hz (95% profile {}), fitted at the design load {} N where the teeth {} in contact. Mesh stiffness {:.1} N/um ({}), half backlash b = {:.1} um.",
        r.zeta,
        fmt_ci(r.ci95_profile.first()),
        r.omega_n_hz,
        fmt_ci(r.ci95_profile.get(1)),
        data.rig.rig.design_load_n,
        if r.design_load_in_contact { "stay" } else { "do NOT stay (the linear fit model is then approximate)" },
        r.mesh_stiffness_n_per_um,
        r.stiffness_source,
        r.half_backlash_um
    ));
    let opt = |v: Option<f64>| v.map_or("-".to_string(), |x| format!("{x:.0}"));
    let rows: Vec<Vec<String>> = r
        .loads
        .iter()
        .map(|l| {
            vec![
                format!("{}", l.load_n),
                if l.fitted { "fit" } else { "prediction" }.to_string(),
                format!("{:.2}", l.force_ratio),
                format!("{:.2} ({:?})", l.ste_um, l.ste_source),
                format!("{:.3}", l.rms_um),
                format!("{:.3}", l.rms_up_um),
                format!("{:.3}", l.rms_down_um),
                l.rms_period1_um.map_or("-".into(), |v| format!("{v:.3}")),
                match (l.not_period1_measured_um, l.not_period1_model_um) {
                    (Some(m), Some(f)) => format!(
                        "{}: measured {:.1} .. {:.1}, model {:.1} .. {:.1}",
                        l.not_period1_points, m.0, m.1, f.0, f.1
                    ),
                    _ => "0".into(),
                },
                opt(l.jump_measured_rpm),
                opt(l.jump_up_rpm),
                opt(l.jump_error_rpm),
            ]
        })
        .collect();
    page.heading("Errors per load");
    page.table(
        &[
            "load (N)",
            "role",
            "F_hat",
            "STE (um)",
            "RMS best (um)",
            "RMS up (um)",
            "RMS down (um)",
            "RMS where the model is period-1 (um)",
            "points where it is not: pp ranges (um)",
            "jump measured (rpm)",
            "jump model up (rpm)",
            "jump error (rpm)",
        ],
        &rows,
    );
    if let Some(t) = &data.rig.source.truth {
        page.heading("Truth of the synthetic data (recorded in rig.toml, never read by the fit)");
        page.preformatted(&toml::to_string(t).unwrap_or_default());
    }
    for l in &r.loads {
        let stem = format!("load_{:.0}", l.load_n);
        let mut series = vec![
            Series::markers(format!("measured ({kind})"), l.measured.clone())
                .with_color(0)
                .with_marker(Marker::Square),
            Series::line(
                "model, speed up",
                l.up.iter().map(|p| (p.speed_rpm, p.dte_pp_um)).collect(),
            )
            .with_color(1),
            Series::dashed(
                "model, speed down",
                l.down.iter().map(|p| (p.speed_rpm, p.dte_pp_um)).collect(),
            )
            .with_color(2),
        ];
        if !l.all.is_empty() {
            series.push(
                Series::markers(
                    "model, all attractors",
                    l.all.iter().map(|p| (p.speed_rpm, p.dte_pp_um)).collect(),
                )
                .with_color(3)
                .with_marker(Marker::Cross),
            );
        }
        let plot = XyPlot {
            title: format!("{} N{} ({kind} data)", l.load_n, if l.fitted { ", design load, fitted" } else { ", predicted" }),
            caption: Some(format!(
                "F_m = {:.4}, F_ah = {:.4} (STE {:.2} um, {:?}), F_hat = {:.2}, zeta = {:.4}, omega_n = {:.0} Hz",
                l.mean_force, l.ste_amplitude, l.ste_um, l.ste_source, l.force_ratio, r.zeta, r.omega_n_hz
            )),
            x_label: "speed (rpm)".into(),
            y_label: "pp dynamic transmission error (um)".into(),
            series,
            ..XyPlot::default()
        };
        write_xy(&plot, &stage.path(&stem))?;
        let res = XyPlot {
            title: format!("Residuals at {} N ({kind} data)", l.load_n),
            caption: Some("measured minus the nearer model branch (up or down)".into()),
            x_label: "speed (rpm)".into(),
            y_label: "residual (um)".into(),
            series: vec![Series::markers("residual", l.residuals.clone())],
            ..XyPlot::default()
        };
        write_xy(&res, &stage.path(&format!("{stem}_residuals")))?;
        page.heading(&format!("{} N", l.load_n));
        page.image(&format!("{stem}.png"), &format!("pp DTE at {} N", l.load_n));
        page.image(
            &format!("{stem}_residuals.png"),
            &format!("residuals at {} N", l.load_n),
        );
    }
    finish_report(
        stage,
        page,
        "geardyn validate munro",
        &fits_dir.join("munro.json"),
        &munro_json(data, r),
    )
}

fn fmt_ci(c: Option<&(Option<f64>, Option<f64>)>) -> String {
    match c {
        Some((a, b)) => format!(
            "[{}, {}]",
            a.map_or("unbounded".to_string(), |v| format!("{v:.4}")),
            b.map_or("unbounded".to_string(), |v| format!("{v:.4}"))
        ),
        None => "-".into(),
    }
}
