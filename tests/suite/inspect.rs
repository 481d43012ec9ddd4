//! `bridgetwin inspect`: what it reports about runs of `bridgetwin simulate`, checked against
//! an independent read with the `mcap` crate, the closed-form natural frequency and the
//! physics of the default scenario; damaged and missing files.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use serde_json::Value;

const BIN: &str = env!("CARGO_BIN_EXE_bridgetwin");

fn run(args: &[&str]) -> Output {
    Command::new(BIN)
        .args(args)
        .output()
        .expect("the bridgetwin binary runs")
}

/// Simulates `scenario` (default: the embedded one) into `dir/name`.
fn simulate(dir: &Path, name: &str, scenario: Option<&Path>, extra: &[&str]) -> PathBuf {
    let out = dir.join(name);
    let mut args = vec!["simulate"];
    if let Some(s) = scenario {
        args.push(s.to_str().unwrap());
    }
    args.extend(["--out", out.to_str().unwrap()]);
    args.extend(extra);
    let o = run(&args);
    assert!(
        o.status.success(),
        "simulate failed: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    out
}

/// `inspect FILE --json`, which must succeed.
fn inspect_json(file: &Path) -> Value {
    inspect_json_exiting(file, 0)
}

/// `inspect FILE --json` on a file that must exit `code` (3: damaged, read up to the
/// damage) and still print its report.
fn inspect_json_exiting(file: &Path, code: i32) -> Value {
    let o = run(&["inspect", file.to_str().unwrap(), "--json"]);
    assert_eq!(
        o.status.code(),
        Some(code),
        "inspect: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    serde_json::from_slice(&o.stdout).expect("inspect --json prints one JSON object")
}

fn channels(report: &Value) -> &Vec<Value> {
    report["channels"].as_array().expect("channels array")
}

/// Messages per topic, counted by the `mcap` crate's own reader.
fn independent_counts(file: &Path) -> BTreeMap<String, u64> {
    let bytes = std::fs::read(file).unwrap();
    let mut counts = BTreeMap::new();
    for m in mcap::MessageStream::new(&bytes).unwrap() {
        *counts.entry(m.unwrap().channel.topic.clone()).or_insert(0) += 1;
    }
    counts
}

fn relative_error(value: f64, reference: f64) -> f64 {
    ((value - reference) / reference).abs()
}

#[test]
fn channel_counts_match_an_independent_read() {
    let dir = tempfile::tempdir().unwrap();
    let file = simulate(dir.path(), "run.mcap", None, &["--duration-s", "4"]);
    let report = inspect_json(&file);
    let expected = independent_counts(&file);
    let reported: BTreeMap<String, u64> = channels(&report)
        .iter()
        .map(|c| {
            let topic = c["topic"].as_str().unwrap().to_string();
            (topic, c["message_count"].as_u64().unwrap())
        })
        .filter(|(_, n)| *n > 0)
        .collect();
    assert_eq!(reported, expected);
    let total: u64 = expected.values().sum();
    assert_eq!(report["message_count"].as_u64(), Some(total));
    assert_eq!(report["has_summary"], Value::Bool(true));
    assert_eq!(report["notes"].as_array().map(Vec::len), Some(0));
    let duration_s = report["duration_s"].as_f64().unwrap();
    assert!((duration_s - 4.0).abs() < 1e-9, "{duration_s}");
    assert_eq!(report["start_time"], "2026-01-01T00:00:00Z");
}

#[test]
fn accelerometers_are_reported_at_200_hz() {
    let dir = tempfile::tempdir().unwrap();
    let file = simulate(dir.path(), "run.mcap", None, &["--duration-s", "4"]);
    let report = inspect_json(&file);
    let accel: Vec<&Value> = channels(&report)
        .iter()
        .filter(|c| c["topic"].as_str().unwrap().starts_with("/sensors/accel/"))
        .collect();
    assert_eq!(accel.len(), 7);
    for c in accel {
        let rate = c["message_rate_hz"].as_f64().unwrap();
        assert!(relative_error(rate, 200.0) < 0.01, "{}: {rate}", c["topic"]);
        assert_eq!(c["metadata"]["unit"], "m/s^2");
        assert_eq!(c["metadata"]["sample_rate_hz"], "200");
        assert!(c["metadata"]["position_m"].as_str().is_some());
    }
}

#[test]
fn f1_matches_the_metadata_and_the_closed_form() {
    let dir = tempfile::tempdir().unwrap();
    let file = simulate(dir.path(), "run.mcap", None, &["--duration-s", "4"]);
    let report = inspect_json(&file);
    let f1 = report["truth"]["natural_frequencies_hz"][0]
        .as_f64()
        .unwrap();
    assert_eq!(report["truth"]["frequency_source"], "/truth/bridge");
    let bridge_model = report["metadata"]
        .as_array()
        .unwrap()
        .iter()
        .find(|m| m["name"] == "bridge_model")
        .expect("bridge_model metadata");
    let listed = bridge_model["entries"]["natural_frequencies_hz"]
        .as_str()
        .unwrap();
    let f1_metadata: f64 = listed.split(',').next().unwrap().parse().unwrap();
    assert!(
        relative_error(f1, f1_metadata) < 1e-6,
        "{f1} vs {f1_metadata}"
    );
    let b = bridgetwin::scenario::Scenario::default_scenario().bridge;
    let closed_form = std::f64::consts::FRAC_PI_2 / b.length_m().powi(2)
        * (b.flexural_rigidity_n_m2 / b.mass_per_length_kg_m).sqrt();
    assert!(
        relative_error(f1, closed_form) < 0.01,
        "{f1} vs {closed_form}"
    );
    let zeta = report["truth"]["damping_ratios"][0].as_f64().unwrap();
    assert!(relative_error(zeta, b.damping_ratio) < 1e-6, "{zeta}");
}

/// The full default run: the truck reaches the bridge at 5 s, so a 4 s run has no DLC.
#[test]
fn dlc_of_every_axle_is_plausible() {
    let dir = tempfile::tempdir().unwrap();
    let file = simulate(dir.path(), "run.mcap", None, &[]);
    let report = inspect_json(&file);
    let axles = report["truth"]["axles"].as_array().unwrap();
    assert_eq!(axles.len(), 2, "the two-axle truck");
    for a in axles {
        let dlc = a["dlc"].as_f64().expect("the axle crossed the bridge");
        assert!(dlc.is_finite() && (1.0..=1.5).contains(&dlc), "{a}");
        let rms = a["rms_dynamic_ratio"].as_f64().unwrap();
        assert!(rms.is_finite() && rms > 0.0 && rms < 0.5, "{a}");
        assert!(a["samples_on_bridge"].as_u64().unwrap() > 100, "{a}");
    }
    assert_eq!(report["truth"]["wim_records"]["WIM1"].as_u64(), Some(1));
    assert!(report["truth"]["events"].as_u64().unwrap() >= 2);
}

#[test]
fn the_table_names_topics_and_truth_but_not_the_scenario_text() {
    let dir = tempfile::tempdir().unwrap();
    let file = simulate(dir.path(), "run.mcap", None, &["--duration-s", "4"]);
    let o = run(&["inspect", file.to_str().unwrap()]);
    assert!(o.status.success());
    let text = String::from_utf8(o.stdout).unwrap();
    for needle in [
        "/sensors/accel/A1",
        "/truth/axle_loads",
        "bridgetwin.v1.AxleLoads",
        "f1 = 3.78",
        "toml = (",
        "road_profile.csv",
        "2026-01-01T00:00:00Z",
    ] {
        assert!(text.contains(needle), "missing {needle:?} in\n{text}");
    }
    assert!(!text.contains("[bridge]"), "the scenario TOML is printed");
}

#[test]
fn a_missing_file_exits_1_naming_the_path() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("no_such_run.mcap");
    let o = run(&["inspect", missing.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(stderr.contains("no_such_run.mcap"), "{stderr}");
}

#[test]
fn a_file_of_garbage_exits_1() {
    let dir = tempfile::tempdir().unwrap();
    let garbage = dir.path().join("garbage.mcap");
    let bytes: Vec<u8> = (0..4096u32)
        .map(|i| (i.wrapping_mul(2_654_435_761) >> 13) as u8)
        .collect();
    std::fs::write(&garbage, bytes).unwrap();
    let o = run(&["inspect", garbage.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(stderr.contains("garbage.mcap"), "{stderr}");
}

#[test]
fn a_truncated_file_is_inspected_by_a_linear_scan() {
    let dir = tempfile::tempdir().unwrap();
    let file = simulate(dir.path(), "run.mcap", None, &["--duration-s", "4"]);
    let full = inspect_json(&file);
    let bytes = std::fs::read(&file).unwrap();
    let cut = dir.path().join("cut.mcap");
    std::fs::write(&cut, &bytes[..bytes.len() - 1000]).unwrap();
    let report = inspect_json_exiting(&cut, 3);
    assert!(report["damage"].as_str().unwrap().contains("cut short"));
    assert_eq!(report["has_summary"], Value::Bool(false));
    assert!(!report["notes"].as_array().unwrap().is_empty());
    let messages = report["message_count"].as_u64().unwrap();
    assert!(messages > 0);
    assert!(messages <= full["message_count"].as_u64().unwrap());

    // A run killed early: the file ends inside its only chunk, with no summary at all.
    let killed = dir.path().join("killed.mcap.partial");
    std::fs::write(&killed, &bytes[..bytes.len() / 2]).unwrap();
    let report = inspect_json_exiting(&killed, 3);
    let notes = report["notes"].to_string();
    assert!(notes.contains("no summary section"), "{notes}");
    let messages = report["message_count"].as_u64().unwrap();
    assert!(messages < full["message_count"].as_u64().unwrap());
}

#[test]
fn block_layout_reports_the_sample_rate() {
    let dir = tempfile::tempdir().unwrap();
    let toml = bridgetwin::scenario::DEFAULT_SCENARIO_TOML;
    assert!(toml.contains("layout = \"sample\""));
    let scenario = dir.path().join("block.toml");
    std::fs::write(
        &scenario,
        toml.replace("layout = \"sample\"", "layout = \"block\""),
    )
    .unwrap();
    let file = simulate(
        dir.path(),
        "run.mcap",
        Some(&scenario),
        &["--duration-s", "4"],
    );
    let report = inspect_json(&file);
    let accel: Vec<&Value> = channels(&report)
        .iter()
        .filter(|c| c["topic"].as_str().unwrap().starts_with("/sensors/accel/"))
        .collect();
    assert_eq!(accel.len(), 7);
    for c in accel {
        assert_eq!(c["schema"], "bridgetwin.v1.SampleBlock");
        let rate = c["sample_rate_hz"].as_f64().unwrap();
        assert!(relative_error(rate, 200.0) < 0.01, "{}: {rate}", c["topic"]);
        let samples = c["samples"].as_u64().unwrap();
        assert!(samples > c["message_count"].as_u64().unwrap(), "{c}");
    }
    let truth_blocks = channels(&report)
        .iter()
        .filter(|c| c["schema"] == "bridgetwin.v1.SensorTruthBlock")
        .count();
    assert_eq!(truth_blocks, 9);
}
