//! The bad-input catalogue: every case runs the `bridgetwin` binary in a fresh temporary
//! folder on one bad scenario, argument or output path, and checks that
//!
//! - the exit code is 1 (error) or 2 (usage), the one the case expects, without a panic;
//! - stderr names the field path (`bridge.span_m`, `sensors.2.rate_hz`) or the file, and
//!   the offending value (the case's expected substrings, e.g. `bridge.span_m = NaN`);
//! - nothing is left behind: no `X.mcap`, no `X.mcap.partial`, no new file or folder, and
//!   every input (an existing output file included) is unchanged.
//!
//! Scenarios are the default scenario (`bridgetwin scenario show`) with edits, either on the
//! text or on the parsed `toml::Table` by path (`sensors.2.rate_hz`). Cases that would
//! simulate if the input were (wrongly) accepted are capped at 0.5 s of simulated time.
//! A failing case prints its name, the command and the full stderr; `BAD_INPUT_SHOW=1`
//! prints every case's stderr.

mod cli;
mod harness;
mod monitoring;
mod physics;
mod railway;
mod schema_view;
mod syntax;

use std::os::unix::fs::FileTypeExt;
use std::path::Path;

use cli::{cli_cases, output_cases};
use harness::{edited, run_all, Case};
use monitoring::{condition_cases, instrument_cases, monitoring_cases, traffic_cases};
use physics::physics_cases;
use railway::railway_cases;
use syntax::syntax_cases;

#[test]
fn traffic() {
    run_all("traffic", &traffic_cases());
}

#[test]
fn condition() {
    run_all("condition", &condition_cases());
}

#[test]
fn monitoring() {
    run_all("monitoring", &monitoring_cases());
}

#[test]
fn instruments() {
    run_all("instruments", &instrument_cases());
}

#[test]
fn railway() {
    run_all("railway", &railway_cases());
}

#[test]
fn scenario_syntax() {
    run_all("scenario syntax", &syntax_cases());
}

#[test]
fn physics() {
    run_all("physics", &physics_cases());
}

#[test]
fn output() {
    run_all("output", &output_cases());
    // The device is still the device.
    let meta = std::fs::metadata("/dev/full").expect("/dev/full");
    assert!(meta.file_type().is_char_device());
    assert!(!Path::new("/dev/full.partial").exists());
}

#[test]
fn cli() {
    run_all("CLI", &cli_cases());
}

/// Every case of the catalogue.
fn all_cases() -> Vec<Case> {
    [
        syntax_cases(),
        physics_cases(),
        output_cases(),
        cli_cases(),
        monitoring_cases(),
        traffic_cases(),
        condition_cases(),
        railway_cases(),
    ]
    .into_iter()
    .flatten()
    .collect()
}

#[test]
fn the_schema_rejects_every_case_it_can_see() {
    // Editors validate with the scenario's JSON Schema; see schema_view.rs for the cases
    // it accepts and why.
    let cases = all_cases();
    let views: Vec<schema_view::CaseView> = cases
        .iter()
        .map(|c| schema_view::CaseView {
            name: &c.name,
            scenario: c.scenario.as_deref(),
            expect: &c.expect,
        })
        .collect();
    let report = schema_view::disagreements(&views, &edited(&[]));
    assert!(report.is_empty(), "{}", report.join("\n"));
}

#[test]
fn the_catalogue_has_at_least_45_cases() {
    let counts = [
        ("scenario syntax", syntax_cases().len()),
        ("physics", physics_cases().len()),
        ("output", output_cases().len()),
        ("CLI", cli_cases().len()),
        ("monitoring", monitoring_cases().len()),
        ("traffic", traffic_cases().len()),
        ("condition", condition_cases().len()),
    ];
    let total: usize = counts.iter().map(|c| c.1).sum();
    eprintln!("bad-input cases: {counts:?}, total {total}");
    assert!(total >= 45, "{counts:?}");
    let mut names = std::collections::BTreeSet::new();
    for case in syntax_cases()
        .iter()
        .chain(&physics_cases())
        .chain(&output_cases())
        .chain(&cli_cases())
        .chain(&monitoring_cases())
        .chain(&traffic_cases())
        .chain(&condition_cases())
    {
        assert!(
            names.insert(case.name.clone()),
            "duplicate case {}",
            case.name
        );
    }
}
