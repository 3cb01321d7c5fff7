//! geardyn: non-linear dynamics of a spur gear pair with backlash.
//!
//! The model and its equation numbers are those of Kahraman & Singh, "Non-linear dynamics of a
//! spur gear pair", J. Sound Vib. 142(1), 1990 (see `design.md` of the project for the generalised
//! form). The library does no printing; the `geardyn` binary is a thin command line over it.

pub mod bifurcation;
pub mod compare;
pub mod data;
pub mod digitize;
pub mod discover;
pub mod error;
pub(crate) mod fast_math;
pub mod fit;
pub mod hb;
pub mod mesh;
pub mod method_study;
pub mod model;
pub mod numeric;
pub mod plot;
pub mod progress;
pub mod report;
pub mod reproduce;
pub mod sim;
pub mod study;
pub mod validate;

pub use error::{GearError, Result};
