//! Reports of the validation pipelines: fitted parameters as JSON (CI artifacts in `fits/`),
//! figures, Markdown and an HTML page in `reports/<name>/`. Output folders are staged and moved
//! into place only when complete, so a failure leaves no partial output.

mod discover;
pub mod html;
mod kubo;
mod munro;
mod staging;

pub use discover::{discovery_json, discovery_stated_ste_text, discovery_summary, write_discovery};
pub use html::Page;
pub use kubo::{kubo_json, write_kubo_report};
pub use munro::{
    curve_names as munro_curve_names, munro_json, stated_ste_text as munro_stated_ste_text,
    write_munro_report, MunroFigures,
};
pub use staging::{
    check_replaceable, remove_unfinished, track_unfinished, untrack_unfinished, write_file_atomic,
    Staged, OUTPUT_MARKER,
};

/// Decimal places that show a 95% interval [lo, hi] and its estimate apart: at least `min`,
/// and enough that the interval's width has two significant digits (so that a value near an
/// end can be seen to lie inside or outside it).
pub fn interval_digits(lo: f64, hi: f64, min: usize) -> usize {
    let width = (hi - lo).abs();
    if !(width.is_finite() && width > 0.0) {
        return min;
    }
    let needed = (1.0 - width.log10().floor()).max(0.0) as usize;
    needed.clamp(min, 12)
}

/// A profile-likelihood interval as a table cell: its ends at `digits` decimals (more where
/// its width needs them, [`interval_digits`]), "unbounded" on a side without an end, and
/// [`STEPPED_MARK`] after an end where the profile stepped.
pub fn profile_cell(p: Option<&ProfileInterval>, digits: usize) -> String {
    let Some(p) = p else {
        return "-".into();
    };
    let digits = match p.ends() {
        (Some(lo), Some(hi)) => interval_digits(lo, hi, digits),
        _ => digits,
    };
    let end = |v: Option<f64>, stepped: bool| {
        v.map_or("unbounded".to_string(), |v| {
            format!("{v:.digits$}{}", if stepped { STEPPED_MARK } else { "" })
        })
    };
    format!(
        "[{}, {}]",
        end(p.lower, p.stepped[0]),
        end(p.upper, p.stepped[1])
    )
}

/// The mark of a profile end where the profile stepped, and its note under the table.
pub const STEPPED_MARK: &str = "†";
pub const STEPPED_NOTE: &str = "† The profile likelihood steps at this end rather than rising: \
     the fit's curve jumps (an up-sweep leaving its resonance branch) across a measured speed, \
     which tells on which side of that speed the jump falls, not how far the parameter may move. \
     The end given is the Wald (Fisher) end, or the step where that is farther.";

/// Whether any of `profiles` stepped at an end (the report then adds [`STEPPED_NOTE`]).
pub fn any_stepped(profiles: &[ProfileInterval]) -> bool {
    profiles.iter().any(|p| p.stepped.contains(&true))
}

/// A profile interval at least this many times as wide as the Fisher interval is named under
/// the table. Where the log-likelihood is near quadratic the two agree to a few per cent; a
/// skewed one (a parameter near its floor) moves one end by up to about a factor 2. Three
/// times the width is beyond that: the curvature at the fit, which the Fisher interval rests
/// on, then says nothing of how far the parameter may move (a Kubo fit whose up-sweep jump
/// crosses a measured speed had a zeta Fisher interval 36 times narrower than its profile's,
/// and 23 standard errors from the truth, which the profile interval held).
pub const NARROW_FISHER_RATIO: f64 = 3.0;

/// The note naming the parameters, given as (label, Fisher interval, profile interval), whose
/// profile interval is unbounded or at least [`NARROW_FISHER_RATIO`] times as wide as their
/// Fisher interval; None when there is none.
pub fn narrow_fisher_note(
    params: &[(&str, (f64, f64), Option<&ProfileInterval>)],
) -> Option<String> {
    let named: Vec<String> = params
        .iter()
        .filter_map(|&(label, (lo, hi), profile)| {
            let p = profile?;
            let fisher = hi - lo;
            match p.ends() {
                (Some(a), Some(b)) if (b - a) >= NARROW_FISHER_RATIO * fisher => {
                    Some(format!("{label} ({:.0} times as wide)", (b - a) / fisher))
                }
                (Some(_), Some(_)) => None,
                _ if fisher.is_finite() => Some(format!("{label} (unbounded)")),
                _ => None,
            }
        })
        .collect();
    (!named.is_empty()).then(|| {
        format!(
            "The profile interval is much wider than the Fisher interval for {}: the Fisher \
             interval rests on the curvature of the likelihood at the fit, which here does not \
             tell how far the parameter may move. Read the profile interval.",
            named.join(", ")
        )
    })
}

/// Legend text of a data set's points: "measured" only for measured data.
pub fn measured_label(kind: DataKind) -> &'static str {
    match kind {
        DataKind::Measured => "measured",
        DataKind::Digitized => "digitized from the figure",
        DataKind::Synthetic => "synthetic data (simulated, not measured)",
    }
}

use crate::data::{DataKind, RigFile};
use crate::fit::ProfileInterval;

/// The first line of every report and output: the data kind, prominently.
pub fn data_kind_banner(rig: &RigFile) -> String {
    match rig.source.kind {
        DataKind::Synthetic => match rig.source.generator.as_deref() {
            Some(g) if g.trim_start().starts_with("geardyn synth") => "SYNTHETIC DATA: these curves were simulated by geardyn synth from stated truth parameters; they are NOT measurements.".to_string(),
            Some(g) => format!("SYNTHETIC DATA: these curves were made by {g} (the set's stated generator), not measured; they are NOT measurements."),
            None => "SYNTHETIC DATA: these curves were generated by a model (generator not stated); they are NOT measurements.".to_string(),
        },
        DataKind::Measured => format!(
            "MEASURED DATA: {} ({}, {})",
            rig.source.citation,
            rig.source.instrument.as_deref().unwrap_or("instrument not stated"),
            rig.source.date.as_deref().unwrap_or("date not stated")
        ),
        DataKind::Digitized => format!(
            "DIGITIZED DATA from {} ({})",
            rig.source.citation,
            rig.source.figure.as_deref().unwrap_or("figure not stated")
        ),
    }
}

/// Whether a stated noise agrees with the scatter about the fit
/// ([`crate::fit::NoiseFit::stated_noise_p`]): a mismatch (warned) below p 0.01, a doubt
/// between 0.01 and 0.05, consistent above; the verdict in words. None where the noise was not
/// stated.
pub fn stated_noise_verdict(e: &crate::fit::Estimate) -> Option<(bool, String)> {
    let p = e.noise.stated_noise_p?;
    let side = if e.chi_square < e.residual_dof as f64 {
        "larger than"
    } else {
        "smaller than (or the model falls short of)"
    };
    Some(if p < 0.01 {
        let p = p_text(p);
        (
            true,
            format!("two-sided p {p}: the stated noise is {side} the scatter about the fit"),
        )
    } else if p < 0.05 {
        (
            false,
            format!("two-sided p {p:.3}: the stated noise may be {side} the scatter about the fit (below 0.05; warned below 0.01)"),
        )
    } else {
        (
            false,
            format!(
                "two-sided p {p:.2}: the stated noise is consistent with the scatter about the fit"
            ),
        )
    })
}

/// `lo` and `hi` with `digits` decimals joined by `sep`, or one value where they print alike
/// (a per-point noise stated the same at every point is not a range).
pub(crate) fn range_text(lo: f64, hi: f64, digits: usize, sep: &str) -> String {
    let (a, b) = (format!("{lo:.digits$}"), format!("{hi:.digits$}"));
    if a == b {
        a
    } else {
        format!("{a}{sep}{b}")
    }
}

/// One line on the noise of an engine fit: its model (or the stated per-point scales), the
/// error law and the outliers, and where the noise was stated, whether the scatter about the
/// fit agrees with it ([`crate::fit::NoiseFit::stated_noise_p`], flagged below 0.01).
pub fn noise_summary(e: &crate::fit::Estimate) -> String {
    use crate::fit::{Distribution, NoiseSource};
    let n = &e.noise;
    let model = match n.source {
        NoiseSource::PerPoint => {
            let (lo, hi) = n.scale_range();
            format!(
                "stated per point (dte_pp_sd_um column), {} um",
                range_text(lo, hi, 3, "-")
            )
        }
        NoiseSource::Stated => format!(
            "stated floor {:.3} um, relative {:.4}",
            n.model.floor, n.model.relative
        ),
        NoiseSource::Estimated => format!(
            "floor {:.3} um{}, relative {:.4}",
            n.model.floor,
            if n.floor_held {
                " (held at the stated reading uncertainty: the scatter is smaller)"
            } else {
                ""
            },
            n.model.relative
        ),
        NoiseSource::Proportional => {
            format!("proportional to the level, {:.4} of it", n.model.relative)
        }
    };
    let law = match n.model.distribution {
        Distribution::Gaussian => "Gaussian".to_string(),
        Distribution::StudentT { dof } => format!("Student-t ({dof} dof)"),
    };
    let outliers = if n.outliers.is_empty() {
        String::new()
    } else {
        format!(", {} outlying points", n.outliers.len())
    };
    let check = stated_noise_verdict(e).map_or(String::new(), |(mismatch, verdict)| {
        format!(
            "; {}chi-square {:.1} on {} degrees of freedom ({verdict})",
            if mismatch { "WARNING: " } else { "" },
            e.chi_square,
            e.residual_dof
        )
    });
    format!("{model}, {law}{outliers}{check}")
}

/// The errors' correlation along speed of an engine fit in words
/// (docs/correlated-errors.md): the length and what it means at the curves' step, or why the
/// errors are taken as independent; then each curve's residual diagnostic (`names`: the
/// curves' names by label), with a warning where even the chosen noise model leaves a pattern
/// (Ljung-Box p below 0.01). None where the fit had no speed axis.
pub fn correlation_summary(e: &crate::fit::Estimate, names: &[String]) -> Option<String> {
    Some(correlation_text(e.noise.correlation.as_ref()?, names))
}

/// [`correlation_summary`] of a fit's correlation part.
pub fn correlation_text(c: &crate::fit::CorrelationFit, names: &[String]) -> String {
    use crate::fit::CorrelationSource;
    use crate::fit::CORRELATION_LR_CRITICAL;
    let step = c.median_step_rpm.map_or(String::new(), |h| {
        format!(
            " (speeds {h:.0} rpm apart: correlation {:.2})",
            c.rho_median_step
        )
    });
    let model = match c.source {
        CorrelationSource::Estimated => {
            let ci = c.length_ci95.map_or(String::new(), |(lo, hi)| {
                format!(
                    " [{lo:.0}, {}]",
                    hi.map_or("unbounded".to_string(), |h| format!("{h:.0}"))
                )
            });
            let test = c.lr_vs_independent.map_or(String::new(), |lr| {
                format!(", likelihood ratio {lr:.1} against independent errors")
            });
            format!(
                "Errors correlated along speed: length {:.0} rpm{ci}{step}{test}. Neighbouring readings err alike (as a drawn line's reading or a rig's slow drift does), so the curves hold fewer independent readings than points; the intervals allow for it",
                c.length_rpm
            )
        }
        CorrelationSource::IndependentByTest => format!(
            "Errors independent along speed: neighbouring residuals move together no more than chance allows (likelihood ratio of a correlation {:.2}, below {CORRELATION_LR_CRITICAL:.2})",
            c.lr_vs_independent.unwrap_or(0.0)
        ),
        CorrelationSource::Stated if c.length_rpm > 0.0 => {
            format!("Errors correlated along speed, length stated {:.0} rpm{step}", c.length_rpm)
        }
        CorrelationSource::Stated => "Errors taken as independent along speed (not estimated: --correlation off or a stated length of 0)".into(),
    };
    let name = |k: usize| {
        names
            .get(k)
            .cloned()
            .unwrap_or_else(|| format!("curve {k}"))
    };
    let curves: Vec<String> = c
        .curves
        .iter()
        .map(|d| {
            let lb = d.ljung_box.map_or(String::new(), |(_, _, _, p)| {
                format!(", Ljung-Box p {}", p_text(p))
            });
            format!("{}: lag-1 {:+.2}{lb}", name(d.curve), d.lag1)
        })
        .collect();
    let flagged: Vec<String> = c
        .curves
        .iter()
        .filter(|d| d.ljung_box.is_some_and(|l| l.3 < 0.01))
        .map(|d| name(d.curve))
        .collect();
    let warning = if flagged.is_empty() {
        String::new()
    } else {
        format!(
            ". WARNING: the residuals of {} still follow a pattern along speed that the noise model does not explain (a missing effect, or errors correlated in another way): read the intervals with care",
            flagged.join(", ")
        )
    };
    format!(
        "{model}. Residual correlation per curve (lag-1 of the standardized residuals; Ljung-Box of what the noise model leaves): {}{warning}",
        curves.join("; ")
    )
}

/// A p-value as printed: three decimals, or "< 0.001".
pub fn p_text(p: f64) -> String {
    if p < 0.001 {
        "< 0.001".into()
    } else {
        format!("{p:.3}")
    }
}

/// A fit's stated STEs ([`crate::fit::Measurement`]s of its STE parameters), each weighed
/// against the curves: stated, fitted, and whether the two agree (Theil & Goldberger's
/// compatibility z within +-1.96), in words, the load of a parameter named by `load_of`;
/// None where the fit weighs none.
pub fn stated_ste_text(
    measurements: &[crate::fit::MeasurementFit],
    load_of: impl Fn(usize) -> String,
) -> Option<String> {
    if measurements.is_empty() {
        return None;
    }
    let mut parts = Vec::new();
    let mut disagree = Vec::new();
    for m in measurements {
        let z = m.compatibility_z;
        parts.push(format!(
            "{}: stated {:.3} ± {:.3} um, fitted {:.3} um{}",
            load_of(m.measurement.param),
            m.measurement.value,
            m.measurement.sd,
            m.fitted,
            z.map_or(String::new(), |z| format!(" (z {z:+.2})"))
        ));
        if z.is_some_and(|z| z.abs() > 1.96) {
            disagree.push(load_of(m.measurement.param));
        }
    }
    let verdict = if disagree.is_empty() {
        "stated and measured curves agree within their uncertainties".to_string()
    } else {
        format!(
            "WARNING: the stated STE disagrees with the curves at {} (|z| above 1.96: the curves pull it further than the stated uncertainty allows; check the STE measurement, its uncertainty, or the load it belongs to)",
            disagree.join(", ")
        )
    };
    Some(format!(
        "STE stated with its uncertainty and weighed against the curves: {}; {verdict}",
        parts.join("; ")
    ))
}

/// A fit's stated STEs as the JSON files list them: the parameter with [`stated_ste_row`].
pub fn stated_ste_json(e: &crate::fit::Estimate) -> Vec<serde_json::Value> {
    e.measurements
        .iter()
        .map(|m| {
            stated_ste_row(
                ("parameter", e.names[m.measurement.param].clone().into()),
                m,
            )
        })
        .collect()
}

/// One stated STE as the JSON files list it: what names it (`key`: its parameter or its load),
/// the stated value and its uncertainty, the fitted value, its z and the compatibility z
/// ([`crate::fit::MeasurementFit`]).
pub fn stated_ste_row(
    (name, key): (&str, serde_json::Value),
    m: &crate::fit::MeasurementFit,
) -> serde_json::Value {
    let mut row = serde_json::json!({
        "stated_um": m.measurement.value,
        "sd_um": m.measurement.sd,
        "fitted_um": m.fitted,
        "z": m.z,
        "compatibility_z": m.compatibility_z,
    });
    row[name] = key;
    row
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Profile intervals wider than the Fisher one by the ratio or more, or unbounded, are
    /// named with their ratio; one a little wider or narrower is not, and none gives no note.
    #[test]
    fn a_profile_interval_much_wider_than_fishers_is_named() {
        let p = |lower, upper| ProfileInterval {
            lower,
            upper,
            stepped: [false; 2],
        };
        let (wide, near, open) = (
            p(Some(0.033), Some(0.0699)),
            p(Some(0.040), Some(0.0485)),
            p(None, Some(2.0)),
        );
        let note = narrow_fisher_note(&[
            ("ζ", (0.0436, 0.0446), Some(&wide)),
            ("ωₙ", (2166.0, 2270.0), Some(&p(Some(2158.0), Some(2272.0)))),
            ("h", (0.0, 1.0), Some(&open)),
            ("STE", (7.8, 8.2), None),
            ("x", (0.040, 0.0446), Some(&near)),
        ])
        .unwrap();
        assert!(note.contains("ζ (37 times as wide)"), "{note}");
        assert!(note.contains("h (unbounded)"), "{note}");
        assert!(!note.contains("ωₙ") && !note.contains("STE") && !note.contains("x ("));
        assert_eq!(
            narrow_fisher_note(&[("ωₙ", (2166.0, 2270.0), Some(&near))]),
            None
        );
    }

    #[test]
    fn interval_digits_resolve_the_width() {
        assert_eq!(interval_digits(0.0173, 0.0182, 2), 5);
        assert_eq!(interval_digits(1599.4, 1601.0, 1), 1);
        assert_eq!(interval_digits(1599.94, 1600.06, 1), 2);
        assert_eq!(interval_digits(0.0, 0.0, 3), 3);
        // The estimate 0.01775 and the bound 0.01776 must print apart.
        let d = interval_digits(0.01710, 0.01776, 3);
        assert_ne!(format!("{:.d$}", 0.01775), format!("{:.d$}", 0.01776));
    }

    /// A stepped end carries the mark, an unbounded side says so, and the digits follow the
    /// width as for the Fisher interval.
    #[test]
    fn profile_cell_marks_a_stepped_end() {
        let p = ProfileInterval {
            lower: Some(0.07404),
            upper: Some(0.08003),
            stepped: [true, false],
        };
        assert_eq!(profile_cell(Some(&p), 3), "[0.0740†, 0.0800]");
        assert!(any_stepped(&[p]));
        let open = ProfileInterval {
            lower: Some(2.5),
            upper: None,
            stepped: [false, false],
        };
        assert_eq!(profile_cell(Some(&open), 2), "[2.50, unbounded]");
        assert!(!any_stepped(&[open]));
        assert_eq!(profile_cell(None, 2), "-");
    }

    #[test]
    fn banner_names_geardyn_synth_only_when_it_is_the_generator() {
        let mut rig: RigFile = toml::from_str(
            "[rig]\nname = \"r\"\npinion_teeth = 32\ngear_teeth = 32\nmodule_mm = 6.35\npressure_angle_deg = 20.0\nface_width_mm = 12.7\ndesign_load_n = 3780.0\nbacklash_mm = 0.1\n[source]\nkind = \"synthetic\"\ncitation = \"c\"\ngenerator = \"geardyn synth 0.1.0\"\n",
        )
        .unwrap();
        assert!(data_kind_banner(&rig).contains("simulated by geardyn synth"));
        rig.source.generator = Some("scipy DOP853 script".into());
        let b = data_kind_banner(&rig);
        assert!(
            !b.contains("geardyn synth") && b.contains("scipy DOP853 script"),
            "{b}"
        );
        rig.source.kind = DataKind::Measured;
        rig.source.generator = None;
        let b = data_kind_banner(&rig);
        assert!(
            b.starts_with("MEASURED DATA") && !b.contains("synth"),
            "{b}"
        );
        rig.source.kind = DataKind::Digitized;
        assert!(!data_kind_banner(&rig).contains("synth"));
        assert_eq!(measured_label(DataKind::Measured), "measured");
        assert!(measured_label(DataKind::Synthetic).contains("synthetic"));
    }
}
