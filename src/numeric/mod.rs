//! Numerical leaves shared by every layer: seeded random numbers ([`Rng`]), rates over
//! seeds ([`wilson95`], [`clopper_pearson_upper95`], [`ks_from_uniform`]), scalar root finding (Brent's method and sign-change
//! brackets), rounding to significant digits ([`to_significant`]) and the range of a set of
//! values ([`min_max`]).
//!
//! A leaf: it imports nothing of the crate (the layers above it, from `model` up, import it).

mod format;
mod min_max;
mod rates;
mod rng;
mod roots;

pub use format::to_significant;
pub use min_max::min_max;
pub use rates::{chi_square_power, clopper_pearson_upper95, ks_from_uniform, wilson95};
pub use rng::Rng;
pub(crate) use roots::{brent, sign_changes};
