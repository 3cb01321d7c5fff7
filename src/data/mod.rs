//! Loading and validating data sets (design.md section 4).
//!
//! A data set is a folder holding `rig.toml` (rig description with units in the key names, an
//! optional STE table, an optional stated-noise table and the `[source]` provenance) and one or
//! more CSV curve files (every `*.csv` of the folder, sorted by name) with unit-suffixed headers:
//!
//! ```text
//! load_n,speed_rpm,dte_pp_um[,dte_pp_sd_um]           Munro (or mesh_freq_hz for speed_rpm)
//! speed_rpm,dynamic_factor_min,dynamic_factor_max     Kubo  (or mesh_freq_hz for speed_rpm)
//! ```
//!
//! docs/data-format.md documents every key and column with its unit and range.
//!
//! Every problem with the input is one [`crate::GearError::Data`] naming the file, the 1-based
//! line as seen in an editor (0 when none applies) and the field; no input makes the loaders
//! panic.

mod csv_curves;
mod curve_order;
mod errors;
mod geometry;
mod kubo;
mod munro;
mod profile_table;
mod rig;
mod rig_scales;
mod same_load;
mod source;
mod template;
mod toml_doc;

pub use geometry::GearGeometry;
pub use kubo::{load_kubo, KuboData, KuboPoint, MAX_DYNAMIC_FACTOR};
pub use munro::{load_munro, loads_text, munro_rig, MunroData, MunroPoint};
pub use profile_table::{load_profile_table, ProfilePoints, TableLines, PROFILE_HEADER};
pub use rig::{
    load_gear_pair, load_rig, load_rig_with_geometry, locate_rig_key, rig_key_error, write_rig,
    Rig, RigFile, StatedNoise, SteTable, SteUncertainty,
};
pub use same_load::same_load;
pub use source::{DataKind, Source};
pub use template::{csv_template, rig_template, Layout};

#[cfg(test)]
mod tests;
