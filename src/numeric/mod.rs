//! Numerical leaves shared by every layer: seeded random numbers ([`Rng`]), the Wilson
//! interval of a proportion ([`wilson95`]), scalar root finding (Brent's method and sign-change
//! brackets), rounding to significant digits ([`to_significant`]) and the range of a set of
//! values ([`min_max`]).
//!
//! A leaf: it imports nothing of the crate (the layers above it, from `model` up, import it).

mod format;
mod min_max;
mod rng;
mod roots;
mod wilson;

pub use format::to_significant;
pub use min_max::min_max;
pub use rng::Rng;
pub(crate) use roots::{brent, sign_changes};
pub use wilson::wilson95;
