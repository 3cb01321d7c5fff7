//! Outputs of `validate munro`: `fits/munro.json` and `reports/munro/` (overlays per load,
//! residuals, index.html, report.md).

use super::html::Page;
use super::staging::{finish_report, Staged};
use super::{
    any_stepped, data_kind_banner, interval_digits, measured_label, narrow_fisher_note,
    profile_cell, STEPPED_NOTE,
};
use crate::data::{DataKind, MunroData};
use crate::error::Result;
use crate::numeric::min_max;
use crate::plot::{write_xy, Marker, Series, XyPlot};
use crate::validate::{
    DesignModel, GeometryValidation, LoadResult, ModelPoint, MunroValidation, LOW_SPEED_OMEGA,
};
use serde_json::json;
use std::path::{Path, PathBuf};

fn ci(r: &MunroValidation, i: usize) -> serde_json::Value {
    let e = &r.fit.estimate;
    let pair = |c: Option<&(f64, f64)>| c.map(|(a, b)| [*a, *b]);
    json!({
        "covariance": pair(e.ci95.get(i)),
        "sandwich": pair(e.ci95_sandwich.get(i)),
        "profile": r.fit.ci95_profile.get(i).map(|p| [p.lower, p.upper]),
        "profile_end_at_step": r.fit.ci95_profile.get(i).map(|p| p.stepped),
    })
}

/// The noise model of the design-load fit, with the speeds of its outliers.
fn noise_json(r: &MunroValidation) -> serde_json::Value {
    let n = &r.fit.estimate.noise;
    let design = r.loads.iter().find(|l| l.fitted);
    let outlier_speeds: Vec<f64> = n
        .outliers
        .iter()
        .filter_map(|&i| design.and_then(|l| l.measured.get(i)).map(|m| m.0))
        .collect();
    // Per-point noise has no floor or relative part: its model is the unit scale the stated
    // sigma_i multiply.
    let per_point = n.source == crate::fit::NoiseSource::PerPoint;
    json!({
        "source": n.source,
        "floor_um": (!per_point).then_some(n.model.floor),
        "floor_um_ci95": n.floor_ci95,
        "floor_held_at_reading_um": n.floor_held,
        "relative": (!per_point).then_some(n.model.relative),
        "relative_ci95": n.relative_ci95,
        "distribution": n.model.distribution,
        "robust_lr": n.robust_lr,
        "stated_noise_p": n.stated_noise_p,
        "correlation": n.correlation,
        "correlation_curves": curve_names(r),
        "outlier_speeds_rpm": outlier_speeds,
        "chi_square": r.fit.estimate.chi_square,
        "residual_dof": r.fit.estimate.residual_dof,
        "interval_dof": r.fit.estimate.dof,
    })
}

/// The fitted-parameter record (design.md section 3 fields and more).
pub fn munro_json(data: &MunroData, r: &MunroValidation) -> serde_json::Value {
    let src = &data.rig.source;
    let e = &r.fit.estimate;
    let ste_fitted = e.names.iter().position(|n| n == "ste_um");
    json!({
        "data_kind": src.kind.name(),
        "notice": data_kind_banner(&data.rig),
        "zeta": r.zeta,
        "zeta_std_error": e.std_errors[0],
        "zeta_std_error_sandwich": e.std_errors_sandwich[0],
        "zeta_ci95": ci(r, 0),
        "omega_n_hz": r.omega_n_hz,
        "omega_n_hz_std_error": e.std_errors[1],
        "omega_n_hz_std_error_sandwich": e.std_errors_sandwich[1],
        "omega_n_hz_ci95": ci(r, 1),
        "ste_design_um": ste_fitted.map(|i| e.params[i]),
        "ste_design_um_ci95": ste_fitted.map(|i| ci(r, i)),
        "stated_ste": super::stated_ste_json(e),
        "noise": noise_json(r),
        "design_points": r.fit.design_points,
        "fit_points": e.n,
        "design_load_in_contact": r.design_load_in_contact,
        "design_model": r.fit.design_model,
        "mesh_stiffness_n_per_um": r.mesh_stiffness_n_per_um,
        "mesh_stiffness_source": r.stiffness_source,
        "half_backlash_um": r.half_backlash_um,
        "mesh_stiffness_source_text": r.stiffness_source_text,
        "per_load": r.loads.iter().map(load_json).collect::<Vec<_>>(),
        "ste_mode": if r.geometry.is_some() { "geometry" } else { "curve" },
        "ste_geometry": r.geometry.as_ref().map(geometry_json),
        "ste_paths": r.geometry.as_ref().map(|g| paths_json(r, g)),
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

/// The errors of one load's prediction (either STE path).
fn load_json(l: &LoadResult) -> serde_json::Value {
    json!({
        "load_n": l.load_n,
        "fitted": l.fitted,
        "mean_force": l.mean_force,
        "ste_um": l.ste_um,
        "ste_um_ci95": l.ste_ci95_um,
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
        "jump_up_onto_period": l.jump_up_onto_period,
        "jump_down_rpm": l.jump_down_rpm,
        "jump_error_rpm": l.jump_error_rpm,
        "jump_error_resolution_rpm": l.jump_error_resolution_rpm,
    })
}

/// The geometry path: its fit, relief, and per load the geometry's excitation and the errors.
fn geometry_json(g: &GeometryValidation) -> serde_json::Value {
    let e = &g.fit.estimate;
    let param = |i: usize| {
        json!({
            "name": e.names[i],
            "value": e.params[i],
            "std_error": e.std_errors[i],
            "ci95": {
                "covariance": e.ci95[i],
                "sandwich": e.ci95_sandwich[i],
                "profile": g.fit.ci95_profile.get(i).map(|p| [p.lower, p.upper]),
                "profile_end_at_step": g.fit.ci95_profile.get(i).map(|p| p.stepped),
            },
        })
    };
    json!({
        "zeta": g.zeta,
        "omega_n_hz": g.omega_n_hz,
        "parameters": (0..e.params.len()).map(param).collect::<Vec<_>>(),
        "fit_points": e.n,
        "noise_floor_um": e.noise.model.floor,
        "noise_relative": e.noise.model.relative,
        "noise_correlation": e.noise.correlation,
        "relief": g.relief,
        "design_load_in_contact": g.design_load_in_contact,
        "design_model": g.fit.design_model,
        "per_load": g.loads.iter().zip(&g.excitation).map(|(l, x)| {
            let mut v = load_json(l);
            v["geometry"] = json!(x);
            v
        }).collect::<Vec<_>>(),
    })
}

/// Both STE paths per load: the STE amplitude each used and their prediction errors.
fn paths_json(r: &MunroValidation, g: &GeometryValidation) -> serde_json::Value {
    let side = |l: &LoadResult| {
        json!({
            "ste_um": l.ste_um,
            "ste_source": l.ste_source,
            "rms_um": l.rms_um,
            "rms_period1_um": l.rms_period1_um,
            "not_period1_points": l.not_period1_points,
            "jump_error_rpm": l.jump_error_rpm,
        })
    };
    r.loads
        .iter()
        .filter_map(|c| {
            let geo = g
                .loads
                .iter()
                .find(|l| crate::data::same_load(l.load_n, c.load_n))?;
            Some(json!({
                "load_n": c.load_n,
                "design_load": c.fitted,
                "curve": side(c),
                "geometry": side(geo),
            }))
        })
        .collect()
}

/// A value and its interval with enough digits to tell whether a number lies inside.
fn with_ci(v: f64, ci: Option<(f64, f64)>, min: usize) -> String {
    match ci {
        Some((lo, hi)) => {
            let d = interval_digits(lo, hi, min);
            format!("{v:.d$} [{lo:.d$}, {hi:.d$}]")
        }
        None => format!("{v:.min$}"),
    }
}

/// The side-by-side section of `--ste geometry`: relief, the design-load fit, and both paths'
/// errors per load.
fn geometry_section(
    page: &mut Page,
    data: &MunroData,
    r: &MunroValidation,
    g: &GeometryValidation,
) {
    use crate::validate::ReliefRule;
    let e = &g.fit.estimate;
    let rl = &g.relief;
    page.heading("STE from the gear geometry (--ste geometry) beside the STE read from each curve");
    page.paragraph(&format!(
        "Geometry path: the tooth-contact model of rig.toml's geometry (geardyn mesh) with a {} tip relief {:.2} µm deep over {:.2} mm of the line of action ({}). ζ and ωₙ{} were fitted to the design-load curve ({} N, {} points) alone, with the geometry's STE there; every other load is predicted with the geometry's STE ({}) and {}. STE amplitudes below are first-harmonic amplitudes e₁ (the model's F_ah = e₁/b), not half the peak-to-peak.",
        rl.relief_shape.name(),
        rl.relief_um,
        rl.relief_length_mm,
        match rl.relief_rule {
            ReliefRule::DesignRule => format!("sized for minimum STE peak-to-peak at the design load {} N, the paper's statement on Munro's gears", data.rig.rig.design_load_n),
            ReliefRule::Given { .. } => "given".to_string(),
            ReliefRule::Fit => format!("fitted to the design-load curve{}", rl.mirror_relief_um.map_or(String::new(), |m| format!("; a depth of {m:.2} µm on the other side of the STE minimum gives the same design-load e₁ and fits equally"))),
        },
        if rl.relief_rule == ReliefRule::Fit { " and the relief depth" } else { "" },
        data.rig.rig.design_load_n,
        e.n,
        if rl.ste_harmonics == 1 { "first harmonic, as the paper's model".to_string() } else { format!("harmonics 1-{}", rl.ste_harmonics) },
        match rl.stiffness {
            crate::validate::StiffnessChoice::Constant => "constant mesh stiffness (k = 1, k_h as the per-curve path)",
            crate::validate::StiffnessChoice::Geometry => "the geometry's loaded mesh stiffness k_h(F) and k(t) (ωₙ scaled by √(k_h(F)/k_h(design)))",
        },
    ));
    page.paragraph(&format!(
        "{} (the geometry path's fit).",
        design_model_text(g.fit.design_model, g.design_load_in_contact).trim_end_matches('.')
    ));
    let rows: Vec<Vec<String>> = (0..e.params.len())
        .map(|i| {
            let min = match e.names[i].as_str() {
                "zeta" => 4,
                "omega_n_hz" => 1,
                _ => 2,
            };
            vec![
                e.names[i].clone(),
                with_ci(e.params[i], Some(e.ci95[i]), min),
                profile_cell(g.fit.ci95_profile.get(i), min),
            ]
        })
        .collect();
    page.table(
        &[
            "parameter (geometry path)",
            "estimate [95% Fisher]",
            "95% profile",
        ],
        &rows,
    );
    if any_stepped(&g.fit.ci95_profile) {
        page.paragraph(STEPPED_NOTE);
    }
    let p1 = |l: &LoadResult| l.rms_period1_um.map_or("-".into(), |v| format!("{v:.3}"));
    let rows: Vec<Vec<String>> = r
        .loads
        .iter()
        .filter_map(|c| {
            let k = g
                .loads
                .iter()
                .position(|l| crate::data::same_load(l.load_n, c.load_n))?;
            let (l, x) = (&g.loads[k], &g.excitation[k]);
            Some(vec![
                format!("{}{}", c.load_n, if c.fitted { " (design)" } else { "" }),
                with_ci(c.ste_um, c.ste_ci95_um, 3),
                format!("{:.3} (pp {:.2})", x.ste_first_harmonic_um, x.ste_pp_um),
                format!("{:.3}", c.rms_um),
                format!("{:.3}", l.rms_um),
                p1(c),
                p1(l),
                c.jump_error_text(""),
                l.jump_error_text(""),
            ])
        })
        .collect();
    page.table(
        &[
            "load (N)",
            "STE e₁ read from the curve (µm)",
            "STE e₁ from geometry (µm)",
            "RMS, curve STE (µm)",
            "RMS, geometry STE (µm)",
            "RMS period-1, curve (µm)",
            "RMS period-1, geometry (µm)",
            "jump error, curve (rpm)",
            "jump error, geometry (rpm)",
        ],
        &rows,
    );
}

/// How the report's figures are drawn.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct MunroFigures {
    /// Fit the pp DTE axis to every attractor. Off: the axis fits the data and the two sweeps,
    /// and farther attractors are arrows on the frame, counted in the legend.
    pub all_attractors_in_range: bool,
}

/// Write fits/munro.json and the report folder; returns the files written.
pub fn write_munro_report(
    data: &MunroData,
    r: &MunroValidation,
    figures: &MunroFigures,
    fits_dir: &Path,
    reports_dir: &Path,
) -> Result<Vec<PathBuf>> {
    let banner = data_kind_banner(&data.rig);
    let synthetic = data.rig.source.kind == DataKind::Synthetic;
    let stage = Staged::replacing(reports_dir)?;
    let mut page = Page::new(
        "geardyn validate munro: pp dynamic transmission error",
        &banner,
        synthetic,
    );
    page.toc();
    parameter_table(&mut page, data, r);
    errors_per_load(&mut page, r);
    if let Some(g) = &r.geometry {
        geometry_section(&mut page, data, r, g);
    }
    if let Some(t) = &data.rig.source.truth {
        page.heading("Truth of the synthetic data (recorded in rig.toml, never read by the fit)");
        page.preformatted(&toml::to_string(t).unwrap_or_default());
    }
    for l in &r.loads {
        load_figures(&stage, &mut page, data, r, figures, l)?;
    }
    finish_report(
        stage,
        page,
        "geardyn validate munro",
        &fits_dir.join("munro.json"),
        &munro_json(data, r),
    )
}

/// The table of errors per load, with what each column means.
fn errors_per_load(page: &mut Page, r: &MunroValidation) {
    let opt = |v: Option<f64>| v.map_or("-".to_string(), |x| format!("{x:.0}"));
    let rows: Vec<Vec<String>> = r
        .loads
        .iter()
        .map(|l| {
            vec![
                format!("{}", l.load_n),
                if l.fitted {
                    "fitted (design load)"
                } else {
                    "predicted"
                }
                .to_string(),
                format!("{:.2}", l.force_ratio),
                format!(
                    "{} ({})",
                    with_ci(l.ste_um, l.ste_ci95_um, 3),
                    ste_source_text(l.ste_source)
                ),
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
                l.jump_error_text(""),
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
            "RMS period-1 (um)",
            "not period-1: points, pp ranges (um)",
            "jump measured (rpm)",
            "jump model up (rpm)",
            "jump error (rpm)",
        ],
        &rows,
    );
    page.paragraph("Columns:");
    page.definitions(&[
        ("role", "fitted: the design-load curve that ζ and ωₙ were fitted to; predicted: a load the fit never saw, predicted with the fitted ζ and ωₙ and that load's STE."),
        ("F_hat", "F_m / F_ah, the mean force over the STE force amplitude (dimensionless); above about 10 the teeth stay in contact."),
        ("STE (um)", "amplitude of the static transmission error at this load, with its 95% interval and where it came from."),
        ("RMS best (um)", "root mean square of measured minus model pp DTE, each point taken against the nearer of the two model sweeps (up or down): the error when the model is allowed to be on either branch of a jump."),
        ("RMS up (um)", "the same against the speed-up sweep alone (speed increasing, each state carried to the next speed), the branch a run-up follows."),
        ("RMS down (um)", "the same against the speed-down sweep alone; large where the down sweep stays on the upper branch of a jump that the data do not follow."),
        ("RMS period-1 (um)", "RMS best over the speeds where the model's steady state is period-1 (one mesh period), where pp DTE is a single number."),
        ("not period-1: points, pp ranges (um)", "number of speeds where the model is subharmonic or chaotic, and the pp DTE ranges there of the data and of the model."),
        ("jump measured / model up (rpm)", "speed of the first jump of the data, and of the model's speed-up sweep (a step larger than 6 median steps with the curve smooth on one side and keeping its new level on the other, not part of a steep flank); - where there is none."),
        ("jump error (rpm)", "model jump minus measured jump, ± how finely the grids place it (half the data's speed step at its jump plus half the model sweep's at its jump)."),
    ]);
}

/// The pp DTE figure of load `l` (measured, the model's sweeps, the geometry path's when it
/// ran, every attractor) and its residuals, written as PNG and SVG and shown on the page.
fn load_figures(
    stage: &Staged,
    page: &mut Page,
    data: &MunroData,
    r: &MunroValidation,
    figures: &MunroFigures,
    l: &LoadResult,
) -> Result<()> {
    let kind = data.rig.source.kind.name();
    let stem = format!("load_{:.0}", l.load_n);
    let geo = r.geometry.as_ref().and_then(|g| {
        g.loads
            .iter()
            .find(|x| crate::data::same_load(x.load_n, l.load_n))
    });
    let series = load_series(data, figures, l, geo);
    let plot = XyPlot {
        title: format!(
            "{} N{} ({kind} data)",
            l.load_n,
            if l.fitted {
                ", design load, fitted"
            } else {
                ", predicted"
            }
        ),
        caption: Some(load_caption(r, l, geo)),
        x_label: "speed (rpm)".into(),
        y_label: "pp dynamic transmission error (um)".into(),
        series,
        ..XyPlot::default()
    };
    write_xy(&plot, &stage.path(&stem))?;
    let res = XyPlot {
        title: format!("Residuals at {} N ({kind} data)", l.load_n),
        caption: Some(format!(
            "{} minus the nearer model branch (up or down)",
            measured_label(data.rig.source.kind)
        )),
        x_label: "speed (rpm)".into(),
        y_label: "residual (um)".into(),
        series: residual_series(data, r, l),
        ..XyPlot::default()
    };
    write_xy(&res, &stage.path(&format!("{stem}_residuals")))?;
    page.heading(&format!("{} N", l.load_n));
    page.image(&format!("{stem}.png"), &format!("pp DTE at {} N", l.load_n));
    page.image(
        &format!("{stem}_residuals.png"),
        &format!("residuals at {} N", l.load_n),
    );
    Ok(())
}

/// The residuals of load `l`, the zero line, and the noise band +-2 sigma_i at each measured
/// speed: the stated standard deviation of a per-point noise, else the fitted (or stated)
/// noise model at the model's level there (measured minus residual). Residuals inside the band
/// are what the noise model expects; a run of them outside is the model's.
fn residual_series(data: &MunroData, r: &MunroValidation, l: &LoadResult) -> Vec<Series> {
    let noise = &r.fit.estimate.noise;
    // The load's points, in the order of its measured values and residuals (by speed).
    let curve = data.curve(l.load_n);
    let sigma = |point: &crate::data::MunroPoint, level: f64| match noise.source {
        crate::fit::NoiseSource::PerPoint => point.sd_um,
        _ => Some(noise.model.scale(level)),
    };
    let band: Option<Vec<(f64, f64)>> = l
        .residuals
        .iter()
        .zip(&l.measured)
        .zip(&curve)
        .map(|((&(speed, res), &(_, y)), p)| sigma(p, y - res).map(|s| (speed, 2.0 * s)))
        .collect();
    let mut series = vec![Series::markers("residual", l.residuals.clone()).with_color(0)];
    if let Some((lo, hi)) = min_max(l.residuals.iter().map(|p| p.0)) {
        series.insert(
            0,
            Series::line("", vec![(lo, 0.0), (hi, 0.0)]).with_color(6),
        );
    }
    if let Some(band) = band {
        let scale = match noise.model.distribution {
            crate::fit::Distribution::Gaussian => "σ",
            crate::fit::Distribution::StudentT { .. } => "scales",
        };
        series
            .push(Series::dashed(format!("±2 {scale} (noise model)"), band.clone()).with_color(1));
        series.push(Series::dashed("", band.iter().map(|&(x, s)| (x, -s)).collect()).with_color(1));
    }
    series
}

/// The series of load `l`'s figure: measured, the model's sweeps, the geometry path's (`geo`)
/// when it ran, and every attractor (transient sets apart).
fn load_series(
    data: &MunroData,
    figures: &MunroFigures,
    l: &LoadResult,
    geo: Option<&LoadResult>,
) -> Vec<Series> {
    let mut series = vec![
        Series::markers(measured_label(data.rig.source.kind), l.measured.clone())
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
    if let Some(gl) = geo {
        series.push(
            Series::line(
                "geometry STE, speed up",
                gl.up.iter().map(|p| (p.speed_rpm, p.dte_pp_um)).collect(),
            )
            .with_color(4),
        );
        series.push(
            Series::dashed(
                "geometry STE, speed down",
                gl.down.iter().map(|p| (p.speed_rpm, p.dte_pp_um)).collect(),
            )
            .with_color(5),
        );
    }
    let (attractors, transients): (Vec<&ModelPoint>, Vec<&ModelPoint>) =
        l.all.iter().partition(|p| p.on_attractor());
    for (label, points, marker) in [
        ("model, all attractors", attractors, Marker::Cross),
        (
            "model, transient sets at the search's horizon",
            transients,
            Marker::Triangle,
        ),
    ] {
        if points.is_empty() {
            continue;
        }
        let all = Series::markers(
            label,
            points.iter().map(|p| (p.speed_rpm, p.dte_pp_um)).collect(),
        )
        .with_color(3)
        .with_marker(marker);
        series.push(if figures.all_attractors_in_range {
            all
        } else {
            all.outside_range()
        });
    }
    series
}

/// The caption of load `l`'s figure: the forcing and the fitted parameters, from the curve's
/// STE and, when the geometry path ran, from the geometry's.
fn load_caption(r: &MunroValidation, l: &LoadResult, geo: Option<&LoadResult>) -> String {
    match (geo, r.geometry.as_ref()) {
            (Some(gl), Some(g)) => format!(
                "STE from the curve {:.2} µm: F_hat {:.2}, ζ {:.4}, ωₙ {:.0} Hz | from the geometry {:.2} µm: F_hat {:.2}, ζ {:.4}, ωₙ {:.0} Hz",
                l.ste_um, l.force_ratio, r.zeta, r.omega_n_hz,
                gl.ste_um, gl.force_ratio, g.zeta, g.omega_n_hz
            ),
            _ => format!(
                "F_m = {:.4}, F_ah = {:.4} (STE {:.2} µm, {}), F_hat = {:.2}, ζ = {:.4}, ωₙ = {:.0} Hz",
                l.mean_force,
                l.ste_amplitude,
                l.ste_um,
                ste_source_text(l.ste_source),
                l.force_ratio,
                r.zeta,
                r.omega_n_hz
            ),
        }
}

/// The fitted parameters first: estimate, 95% intervals (Fisher, sandwich, profile), unit,
/// source; then the noise model and the fit's setting.
fn parameter_table(page: &mut Page, data: &MunroData, r: &MunroValidation) {
    let e = &r.fit.estimate;
    let pair = |c: (f64, f64), d: usize| {
        let d = interval_digits(c.0, c.1, d);
        format!("[{:.d$}, {:.d$}]", c.0, c.1)
    };
    let design = if r.fit.other_loads.is_empty() {
        format!(
            "design-load curve ({} N, {} points)",
            data.rig.rig.design_load_n, r.fit.design_points
        )
    } else {
        format!(
            "design-load curve ({} N, {} points) with the other loads' low-speed parts, {} points in all",
            data.rig.rig.design_load_n, r.fit.design_points, e.n
        )
    };
    // The other loads' STE amplitudes follow zeta, omega_n and (when fitted) the design one.
    let first_other = e.params.len() - r.fit.other_loads.len();
    let rows: Vec<Vec<String>> = e
        .params
        .iter()
        .enumerate()
        .map(|(i, v)| {
            let (label, unit, d, source) = match (e.names[i].as_str(), i.checked_sub(first_other)) {
                ("zeta", _) => ("ζ (damping ratio)".to_string(), "", 5, design.clone()),
                ("omega_n_hz", _) => ("ωₙ (natural frequency)".to_string(), "Hz", 2, design.clone()),
                (_, Some(k)) => {
                    let (load, points) = r.fit.other_loads[k];
                    (
                        format!("STE amplitude at {load} N"),
                        "µm",
                        4,
                        format!("low-speed part of its curve (Ω ≤ {LOW_SPEED_OMEGA}, {points} points), in the same fit"),
                    )
                }
                _ => (
                    format!("STE amplitude at the design load ({} N)", data.rig.rig.design_load_n),
                    "µm",
                    4,
                    design.clone(),
                ),
            };
            let d = interval_digits(e.ci95[i].0, e.ci95[i].1, d);
            vec![
                label,
                format!("{v:.d$}"),
                pair(e.ci95[i], d),
                pair(e.ci95_sandwich[i], d),
                profile_cell(r.fit.ci95_profile.get(i), d),
                unit.to_string(),
                source,
            ]
        })
        .collect();
    page.heading("Fitted parameters");
    page.table(
        &[
            "parameter",
            "estimate",
            "95% interval (Fisher)",
            "95% interval (sandwich)",
            "95% interval (profile)",
            "unit",
            "source",
        ],
        &rows,
    );
    if any_stepped(&r.fit.ci95_profile) {
        page.paragraph(STEPPED_NOTE);
    }
    let compared: Vec<_> = rows
        .iter()
        .zip(&e.ci95)
        .enumerate()
        .map(|(i, (row, &fisher))| (row[0].as_str(), fisher, r.fit.ci95_profile.get(i)))
        .collect();
    if let Some(note) = narrow_fisher_note(&compared) {
        page.paragraph(&note);
    }
    let n = &e.noise;
    let noise_rows = if n.source == crate::fit::NoiseSource::PerPoint {
        let (lo, hi) = n.scale_range();
        vec![vec![
            "noise standard deviation per point".to_string(),
            super::range_text(lo, hi, 4, " .. "),
            "stated (dte_pp_sd_um column)".into(),
            "µm".into(),
        ]]
    } else {
        vec![
            vec![
                "noise floor".to_string(),
                format!("{:.4}", n.model.floor),
                match n.floor_ci95 {
                    Some(c) => pair(c, 4),
                    None if n.floor_held => "held at the stated reading uncertainty".into(),
                    None => "stated".into(),
                },
                "µm".into(),
            ],
            vec![
                "noise relative part".to_string(),
                format!("{:.4}", n.model.relative),
                n.relative_ci95.map_or("-".into(), |c| pair(c, 4)),
                "of the level".into(),
            ],
        ]
    };
    page.heading("Noise model (σᵢ² = floor² + (relative · level)²)");
    page.table(&["part", "estimate", "95% interval", "unit"], &noise_rows);
    let dist = match n.model.distribution {
        crate::fit::Distribution::Gaussian => "Gaussian errors".to_string(),
        crate::fit::Distribution::StudentT { dof } => {
            format!("Student-t errors with {dof} degrees of freedom (outliers down-weighted)")
        }
    };
    let source = match n.source {
        crate::fit::NoiseSource::Estimated => "estimated jointly with the fit",
        crate::fit::NoiseSource::Stated => "stated in rig.toml",
        crate::fit::NoiseSource::PerPoint => "stated per point (dte_pp_sd_um column)",
        crate::fit::NoiseSource::Proportional => "proportional to the level",
    };
    page.paragraph(&format!(
        "{dist}; noise {source}. Likelihood ratio Student-t against Gaussian: {}. Standardized residuals: χ² = {:.1} on {} degrees of freedom{}. Points beyond the Bonferroni bound: {}. {} Mesh stiffness {:.1} N/µm ({}), half backlash b = {:.1} µm.",
        n.robust_lr.map_or("not computed".into(), |v| format!(
            "{v:.2} ({} errors kept: Student-t is chosen above {:.2})",
            if matches!(n.model.distribution, crate::fit::Distribution::Gaussian) { "Gaussian" } else { "Student-t" },
            crate::fit::ROBUST_LR_CRITICAL
        )),
        e.chi_square,
        e.residual_dof,
        super::stated_noise_verdict(e).map_or(String::new(), |(_, v)| format!(" ({v})")),
        if n.outliers.is_empty() { "none".to_string() } else { n.outliers.len().to_string() },
        design_model_text(r.fit.design_model, r.design_load_in_contact),
        r.mesh_stiffness_n_per_um,
        r.stiffness_source_text,
        r.half_backlash_um
    ));
    if let Some(text) = super::correlation_summary(e, &curve_names(r)) {
        page.heading("Errors along speed");
        page.paragraph(&text);
    }
    if let Some(text) = stated_ste_text(r) {
        page.heading("Stated STE");
        page.paragraph(&text);
    }
}

/// The loads whose STE rig.toml states with an uncertainty (`[ste] sd_um`), each weighed
/// against the curves as a measurement ([`crate::fit::Measurement`]), in words
/// ([`super::stated_ste_text`]); None where no STE is stated with an uncertainty.
pub fn stated_ste_text(r: &MunroValidation) -> Option<String> {
    let design = r
        .loads
        .iter()
        .find(|l| l.fitted)
        .map_or(f64::NAN, |l| l.load_n);
    let e = &r.fit.estimate;
    super::stated_ste_text(&e.measurements, |param| {
        r.fit
            .ste_load(param, design)
            .map_or_else(|| e.names[param].clone(), |l| format!("{l} N"))
    })
}

/// The names of the design-load fit's curves, in the engine's order: the design load, then the
/// loads whose low-speed parts joined it.
pub fn curve_names(r: &MunroValidation) -> Vec<String> {
    let design = r.loads.iter().find(|l| l.fitted).map(|l| l.load_n);
    design
        .into_iter()
        .chain(r.fit.other_loads.iter().map(|(l, _)| *l))
        .map(|l| format!("{l} N"))
        .collect()
}

/// How the design-load curve was modelled in a fit (`model`; `in_contact`: whether the fit
/// keeps the design load's teeth in contact), as a sentence.
pub(crate) fn design_model_text(model: DesignModel, in_contact: bool) -> &'static str {
    match (model, in_contact) {
        (DesignModel::Swept, _) => {
            "Under the closed form of eq. 13 the design load's teeth separate at some measured \
             speeds, where that form does not hold: the design-load curve was fitted through the \
             exact solver's up-sweeps (each speed started from the last one's state; \
             separation, impacts and jumps included), started from the closed form's fit."
        }
        (DesignModel::Linear, true) => {
            "The design load's teeth stay in contact at every measured speed under the fit, \
             where the closed form of eq. 13 is exact."
        }
        (DesignModel::Linear, false) => {
            "The design load's teeth separate at some measured speeds under the fit."
        }
    }
}

/// Human wording of where an STE amplitude came from.
fn ste_source_text(s: crate::validate::SteSource) -> &'static str {
    use crate::validate::SteSource;
    match s {
        SteSource::RigToml => "given in rig.toml",
        SteSource::Measured => "given in rig.toml with its uncertainty, fitted with ζ and ωₙ",
        SteSource::Fitted => "fitted with ζ and ωₙ",
        SteSource::LowSpeedFit => "fitted to the curve's low-speed part",
        SteSource::LowSpeedEnd => "from the lowest-speed point",
        SteSource::Geometry => "first harmonic of the geometry's loaded STE",
    }
}
