//! bridgetwin: a digital twin of a road bridge under traffic.
//!
//! The folders are the layers of the architecture; a layer uses only the layers below
//! it (`tests/suite/layers.rs` fails on an import that runs upward), bottom to top:
//!
//! | layer | what it holds |
//! |---|---|
//! | [`base`] | named random streams, signal estimates, constants |
//! | [`record`] | what a run emits: records, the recorder trait, the run manifest |
//! | [`physics`] | bridge, vehicles, road, solver, temperature and damage, ambient loads, traffic |
//! | [`measurement`] | sensor channels and chains, DAQ clocks and faults, WIM stations |
//! | [`scenario`] | TOML -> one resolved, typed run description |
//! | [`sim`] | the one time loop: physics and measurement -> records |
//! | [`output`] | records and manifest -> protobuf -> MCAP |
//! | [`app`] | drives runs: a scenario through the loop into an output; sweeps |
//! | [`studies`] | verification ladder, paper studies, benches, analytic references, plots |
//! | [`cli`] | the commands: parse, print, map errors to exit codes |
//!
//! Physics and measurement never touch output or the command line; output sees records
//! and the manifest only.

pub mod app;
pub mod base;
pub mod cli;
pub mod error;
pub mod input;
pub mod measurement;
pub mod output;
pub mod physics;
pub mod record;
pub mod scenario;
pub mod sim;
pub mod studies;

pub use error::{Error, Result};
