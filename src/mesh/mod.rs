//! Excitation from the gear geometry (issue 24): the static transmission error (STE) and the
//! mesh stiffness of a spur gear pair, from its teeth, module, pressure angle, face width and
//! profile modification, as the model's k(t) and e(t) need them.
//!
//! - [`geometry`]: involute pair geometry, path of contact, contact ratio;
//! - [`tooth_stiffness`]: tooth-pair stiffness along the path of contact by the
//!   potential-energy method (bending, shear, axial compression, Hertzian contact, fillet
//!   foundation after Sainsot et al. 2004);
//! - [`profile_deviation`]: a profile modification given point by point on each flank;
//! - [`ste`]: loaded STE with load sharing, tip relief and contact loss over one mesh period;
//! - [`harmonics`]: Fourier coefficients in the model's conventions (F_ahj, eps_j, phases);
//! - [`harris`]: STE peak-to-peak against load, and relief sizing by "minimum STE at the
//!   design load";
//! - [`iso6336`]: ISO 6336-1 method B single-pair and mesh stiffness, for comparison;
//! - [`analysis`]: all of the above for a rig, as `geardyn mesh` reports it.
//!
//! docs/mesh-geometry.md gives the equations with their sources and the checks.

pub mod analysis;
pub mod geometry;
pub mod harmonics;
pub mod harris;
pub mod iso6336;
pub mod profile_deviation;
pub mod ste;
pub mod tooth_stiffness;

#[cfg(test)]
mod tests;

pub use analysis::{analyse, LoadResult, MeshAnalysis, MeshOptions, ReliefChoice};
pub use geometry::{GearBody, GearPairGeometry};
pub use harmonics::{mesh_harmonics, MeshHarmonic};
pub use harris::{design_relief, harris_map, HarrisPoint};
pub use iso6336::{IsoPair, IsoStiffness};
pub use profile_deviation::ProfileDeviation;
pub use ste::{MeshModel, PairState, ReliefShape, SteWaveform, TipRelief};
pub use tooth_stiffness::{pair_stiffness, PairStiffness, StiffnessTable, ToothCompliance};
