//! The gear-pair model of Kahraman & Singh (1990), eq. 3a generalised by eq. 20 and a
//! time-varying mesh stiffness (design.md, section 1).

mod dimensional;
mod excitation;
mod mesh;
mod operating_point;
mod params;

pub use dimensional::{Dimensional, StiffnessSource, ISO6336_C_PRIME};
pub use excitation::Harmonic;
pub use mesh::{dead_zone, Impact, Region};
pub use operating_point::OperatingPoint;
pub use params::{GearPair, Term};
