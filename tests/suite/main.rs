//! The integration suite: one test binary whose modules are the themes (one link
//! instead of one per file; `cargo test --test suite THEME` runs one theme, e.g.
//! `cargo test --release --test suite bad_input`).
//!
//! Proptest keeps the seeds of past failures beside this folder, in
//! `tests/proptest-regressions/<module path>.txt` (its default `SourceParallel`
//! persistence, which anchors at the folder holding `main.rs`).

mod ambient;
mod analytic_references;
mod bad_input;
mod bench_cmd;
mod big_models;
mod common;
mod console;
mod continuous_study;
mod damaged_files;
mod daq;
mod determinism;
mod dlc_study;
mod doc_figures;
mod doc_links;
mod environment;
mod environment_run;
mod estimate;
mod examples;
mod foxglove;
mod gauge_moment;
mod girder_conditions;
mod girder_sensors;
mod hslm_study;
mod input_decoders;
mod input_read;
mod inspect;
mod interrupts;
mod layers;
mod markdown;
mod mcap_output;
mod monitoring_streams;
mod multi_axle;
mod output_hashes;
mod preview;
mod properties;
mod provenance;
mod python_tools;
mod railway;
mod readme_tour;
mod road_profiles;
mod scenario_schema;
mod sensor_chain;
mod sensor_presets;
mod simulate;
mod simulate_mcap;
mod solver_paths_study;
mod split_output;
mod sweep;
mod traffic;
mod traffic_run;
mod trains;
mod vehicle_instruments;
mod verification;
mod wim_models;
