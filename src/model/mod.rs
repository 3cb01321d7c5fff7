//! The gear-pair model of Kahraman & Singh (1990), eq. 3a generalised by eq. 20 and a
//! time-varying mesh stiffness (design.md, section 1).

mod dimensional;
mod excitation;
mod mesh;
mod operating_point;
mod params;

#[cfg(test)]
pub(crate) use dimensional::munro_spec;
pub use dimensional::{Dimensional, GearSpec, StiffnessSource, ISO6336_C_PRIME};
pub use excitation::Harmonic;
pub use mesh::{dead_zone, Impact, Region};
pub use operating_point::{valid_load, OperatingPoint, MAX_DTE_UM, MAX_LOAD_N};
pub use params::{GearPair, Term, MAX_FORCE};
