//! Setup shared by the themes of the suite: a scenario through the library (parse ->
//! resolve -> prepare -> run into memory), written once here instead of once per file.

use std::io::Write;
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};

use bridgetwin::record::{Quantities, RunManifest};
use bridgetwin::scenario::Scenario;
use bridgetwin::sim::{prepare, run, Record, RunSummary, VecRecorder};

/// What a run into memory gives.
pub struct Run {
    pub records: Vec<Record>,
    pub summary: RunSummary,
    pub manifest: RunManifest,
}

/// Resolves, prepares and runs `scenario` into memory; on failure the error of the stage
/// that failed, prefixed with it (`resolve: ...`, `prepare: ...`, `run: ...`).
pub fn try_run(scenario: &Scenario) -> Result<Run, String> {
    let resolved = scenario.resolve().map_err(|e| format!("resolve: {e}"))?;
    let prepared = prepare(&resolved).map_err(|e| format!("prepare: {e}"))?;
    let mut recorder = VecRecorder::default();
    let summary = run(&resolved, &prepared, &mut recorder, &mut |_, _| {})
        .map_err(|e| format!("run: {e}"))?;
    let manifest = recorder
        .manifest
        .ok_or_else(|| "run: the recorder was never given the manifest".to_string())?;
    Ok(Run {
        records: recorder.records,
        summary,
        manifest,
    })
}

/// The run of `scenario`; panics with the failing stage's error.
pub fn run_scenario(scenario: &Scenario) -> Run {
    try_run(scenario).unwrap_or_else(|e| panic!("{e}"))
}

/// The records of a run of the scenario text `toml`.
pub fn records_of(toml: &str) -> Vec<Record> {
    let scenario = Scenario::from_toml(toml, "test").unwrap_or_else(|e| panic!("parse: {e}"));
    run_scenario(&scenario).records
}

/// The records of a run of `toml` whose relative paths (road or temperature CSV) are
/// read from `dir`.
pub fn records_in(toml: &str, dir: &Path) -> Vec<Record> {
    let mut scenario = Scenario::from_toml(toml, "test").unwrap_or_else(|e| panic!("parse: {e}"));
    scenario.resolve_relative_paths(dir);
    run_scenario(&scenario).records
}

/// The `bridgetwin` binary cargo built for the suite.
pub const BIN: &str = env!("CARGO_BIN_EXE_bridgetwin");

/// Checks skipped so far in this run of the suite.
static SKIPPED: AtomicUsize = AtomicUsize::new(0);

/// Says that a check did not run, and why, where it is seen: written straight to stderr
/// (the test harness captures `eprintln!` of passing tests, not the stream itself), as
/// `SKIPPED <what>: <why>`, with the count of skips so far. A skipped check is reported,
/// never passed silently.
pub fn skip(what: &str, why: &str) {
    let count = SKIPPED.fetch_add(1, Ordering::Relaxed) + 1;
    let _ = writeln!(
        std::io::stderr(),
        "SKIPPED {what}: {why} (skip {count} of this run)"
    );
}

/// (true instant, stamp, measured, truth quantities) of one sensor sample.
pub type Sample = (u64, i64, Option<f64>, Quantities);

/// The samples of sensor `index`, in record order.
pub fn sensor_samples(records: &[Record], index: usize) -> Vec<Sample> {
    records
        .iter()
        .filter_map(|r| match r {
            Record::Sensor {
                sensor,
                t_ns,
                stamp_ns,
                measured,
                truth,
            } if *sensor == index => Some((*t_ns, *stamp_ns, *measured, *truth)),
            _ => None,
        })
        .collect()
}

/// `bridgetwin simulate --duration-s DURATION` of the default scenario by the binary, into
/// `dir/run.mcap`; returns the file's path.
pub fn simulate_default_file(dir: &Path, duration_s: f64) -> std::path::PathBuf {
    let out = dir.join("run.mcap");
    simulate_file(None, &out, duration_s);
    out
}

/// `bridgetwin simulate [SCENARIO] --duration-s DURATION --out OUT` by the binary, as a
/// user runs it (the default scenario without `scenario`); panics with its stderr if it
/// fails.
pub fn simulate_file(scenario: Option<&Path>, out: &Path, duration_s: f64) {
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_bridgetwin"))
        .arg("simulate")
        .args(scenario)
        .args(["--duration-s", &duration_s.to_string(), "--quiet", "--out"])
        .arg(out)
        .output()
        .unwrap();
    assert!(
        output.status.success(),
        "simulate {scenario:?} --duration-s {duration_s}: {}",
        String::from_utf8_lossy(&output.stderr)
    );
}

/// (t ns, support reactions) of every `/truth/bridge` shape record.
pub fn shape_reactions(records: &[Record]) -> Vec<(u64, Vec<f64>)> {
    records
        .iter()
        .filter_map(|r| match r {
            Record::BridgeShape {
                t_ns,
                support_reaction_n,
                ..
            } => Some((*t_ns, support_reaction_n.clone())),
            _ => None,
        })
        .collect()
}
