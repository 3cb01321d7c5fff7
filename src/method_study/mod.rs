//! Studies of the statistical methods over seeded synthetic sets whose truth is known: how
//! often `discover` answers right (null and recovery rates, with Wilson intervals); `geardyn
//! discover-study` runs it. `validate`'s interval-coverage study is `crate::validate`'s own.

pub mod discover;
