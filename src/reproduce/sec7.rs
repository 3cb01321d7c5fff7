//! Sec. 7 (experimental validation, Figs 19-23) on the shipped data sets. The shipped sets are
//! synthetic, so every claim about agreement with Munro's or Kubo's measurements is "not testable"
//! and says so; geardyn's numbers from the pipelines are reported beside it.

use super::artifacts::Artifact;
use super::claims::{Claim, Verdict};
use super::Resolution;
use crate::data::{load_kubo, load_munro, DataKind, KuboData, MunroData};
use crate::error::Result;
use crate::progress::{NoProgress, Progress};
use crate::validate::{validate_kubo, validate_munro, KuboValidation, MunroValidation};
use std::path::Path;

/// Output sub-folder of the validation reports (`munro/`, `kubo/`, `fits/`).
pub const DIR: &str = "sec7-validation";

/// The Munro and Kubo data sets, loaded (and validated) before any computation starts.
pub(crate) struct DataSets {
    munro: MunroData,
    kubo: KuboData,
}

/// Load `data_dir/munro` and `data_dir/kubo`.
pub(crate) fn load(data_dir: &Path) -> Result<DataSets> {
    Ok(DataSets {
        munro: load_munro(&data_dir.join("munro"))?,
        kubo: load_kubo(&data_dir.join("kubo"))?,
    })
}

/// Validate both data sets and build the claim rows of Sec. 7.
pub(crate) fn build(
    res: &Resolution,
    data: DataSets,
    progress: &dyn Progress,
) -> Result<(Vec<Claim>, Vec<Artifact>)> {
    let DataSets { munro, kubo } = data;
    let m = validate_munro(&munro, &res.munro, &NoProgress)?;
    progress.advance(1);
    let k = validate_kubo(&kubo, &res.kubo, &NoProgress)?;
    progress.advance(1);
    let munro_kind = munro.rig.source.kind;
    let kubo_kind = kubo.rig.source.kind;
    let claims = claims(&m, munro_kind, &k, kubo_kind);
    let artifacts = vec![
        Artifact::Munro {
            dir: DIR.into(),
            data: Box::new(munro),
            result: Box::new(m),
        },
        Artifact::Kubo {
            dir: DIR.into(),
            data: Box::new(kubo),
            result: Box::new(k),
        },
    ];
    Ok((claims, artifacts))
}

/// The verdict of a comparison with measurements: only measured or digitized data can test it.
fn measured(kind: DataKind, ok: bool) -> Verdict {
    match kind {
        DataKind::Synthetic => Verdict::NotTestableSynthetic,
        DataKind::Measured | DataKind::Digitized if ok => Verdict::Agree,
        DataKind::Measured | DataKind::Digitized => Verdict::Differ,
    }
}

fn kind_text(kind: DataKind) -> &'static str {
    match kind {
        DataKind::Synthetic => "SYNTHETIC data (geardyn synth, not measurements)",
        DataKind::Measured => "measured data",
        DataKind::Digitized => "digitized data",
    }
}

fn claims(m: &MunroValidation, mk: DataKind, k: &KuboValidation, kk: DataKind) -> Vec<Claim> {
    let mut out = Vec::new();
    let why = |kind: DataKind, text: String| {
        match kind {
        DataKind::Synthetic => format!(
            "the shipped data are synthetic, so agreement with the measurements cannot be tested; {text}"
        ),
        DataKind::Measured | DataKind::Digitized => text,
    }
    };
    out.push(Claim::new(
        "S7-01",
        "7",
        "Fig. 19",
        "Munro, design load 3780 N: teeth stay in contact (F_hat ~ 50), linear behaviour; zeta estimated 0.0175",
        format!(
            "{}: fitted zeta {:.4}, omega_n {:.1} Hz; model in contact at the design load: {}",
            kind_text(mk),
            m.zeta,
            m.omega_n_hz,
            m.design_load_in_contact
        ),
        measured(mk, m.design_load_in_contact),
        why(mk, format!("on these data the fitted model stays in contact: {}", m.design_load_in_contact)),
    ));
    for (id, fig, frac) in [
        ("S7-02", "Fig. 20", 0.75),
        ("S7-03", "Fig. 21", 0.5),
        ("S7-04", "Fig. 22", 0.25),
    ] {
        let design = m.loads.iter().map(|l| l.load_n).fold(0.0, f64::max);
        let l = m
            .loads
            .iter()
            .find(|l| (l.load_n - frac * design).abs() < 1e-6 * design.max(1.0));
        let (text, ok) = match l {
            Some(l) => (
                format!(
                    "{}: load {:.0} N, F_hat {:.2}, RMS {:.3} um ({} where the model is period-1, {} speeds chaotic or subharmonic), jump measured {}, predicted up {}, error {}",
                    kind_text(mk),
                    l.load_n,
                    l.force_ratio,
                    l.rms_um,
                    l.rms_period1_um.map_or("-".into(), |v| format!("{v:.3} um")),
                    l.not_period1_points,
                    l.jump_measured_rpm.map_or("none".into(), |v| format!("{v:.0} rpm")),
                    l.jump_up_rpm.map_or("none".into(), |v| format!("{v:.0} rpm")),
                    l.jump_error_text(" rpm")
                ),
                l.jump_up_rpm.is_some(),
            ),
            None => (format!("{}: no curve at {frac} of the design load", kind_text(mk)), false),
        };
        out.push(Claim::new(
            id,
            "7",
            fig,
            &format!("Munro, {frac} of design load: tooth separation and a jump in the response; theory matches the measurements very well"),
            text,
            measured(mk, ok),
            why(mk, format!("the model predicts a jump at this load: {ok}")),
        ));
    }
    out.push(Claim::new(
        "S7-05",
        "7",
        "Fig. 23",
        "Kubo: predictions mostly outside the measured envelope, but the transition frequency and jump amplitude are predicted accurately",
        format!(
            "{}: zeta {:.3}, model inside the envelope at {:.0}% of speeds, transition (first steep step) measured {}, predicted {}",
            kind_text(kk),
            k.zeta,
            100.0 * k.inside_fraction,
            k.jump_measured_rpm.map_or("none".into(), |v| format!("{v:.0} rpm")),
            k.jump_up_rpm.map_or("none".into(), |v| format!("{v:.0} rpm"))
        ),
        measured(kk, k.jump_error_rpm.is_some_and(|e| e.abs() < 200.0)),
        why(kk, format!("transition error {}", k.transition_error_text(" rpm"))),
    ));
    out
}
