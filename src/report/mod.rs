//! Reports of the validation pipelines: fitted parameters as JSON (CI artifacts in `fits/`),
//! figures, Markdown and an HTML page in `reports/<name>/`. Output folders are staged and moved
//! into place only when complete, so a failure leaves no partial output.

pub mod html;
mod kubo;
mod munro;
mod staging;

pub use html::Page;
pub use kubo::{kubo_json, write_kubo_report};
pub use munro::{munro_json, write_munro_report};
pub use staging::{write_file_atomic, Staged};

use crate::data::{DataKind, RigFile};

/// The first line of every report and output: the data kind, prominently.
pub fn data_kind_banner(rig: &RigFile) -> String {
    match rig.source.kind {
        DataKind::Synthetic => "SYNTHETIC DATA: these curves were simulated by geardyn synth from stated truth parameters; they are NOT measurements.".to_string(),
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
