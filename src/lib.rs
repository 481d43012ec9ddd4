//! bridgetwin: a digital twin of a road bridge under traffic.
//!
//! The modules follow the layers of `ARCHITECTURE.md`, top to bottom; a module only uses
//! the ones below it. Physics (`bridge`, `vehicle`, `road`, `solver`, `analytic`) never
//! touches output (`sink`) or the command line (`cli`).

pub mod analytic;
pub mod bench;
pub mod bridge;
pub mod cli;
pub mod daq;
pub mod environment;
pub mod error;
pub mod excitation;
pub mod plot;
pub mod road;
pub mod scenario;
pub mod sensor;
pub mod sim;
pub mod sink;
pub mod solver;
pub mod study;
pub mod sweep;
pub mod traffic;
pub mod vehicle;
pub mod verify;
pub mod wim;

pub use error::{Error, Result};
