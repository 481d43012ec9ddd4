//! The bottom layer: small pieces every other layer may use and which use nothing of the
//! crate but its error type: named random streams, signal estimates, physical constants, `kind`-tagged
//! enums for serde, schema bounds for the scenario's JSON Schema.

pub mod build_info;
pub mod dot;
pub mod random;
pub mod rate;
pub mod schema;
pub mod signal;
pub mod tagged;
pub mod units;
