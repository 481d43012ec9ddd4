//! The bytes of the default run and of every example (short durations) are pinned: a
//! refactor must not change what a user's dataset contains. Each hash is the SHA-256 of
//! the file `bridgetwin simulate` writes.
//!
//! When an output change is intended (a new field, a fixed value), update the hash of
//! every affected row here, in the same commit, and say in its message what changed and
//! why. History of intended changes:
//! - the runs of 60 s and more: chunks now close every 60 s of simulated time instead of
//!   every 2 s of wall time (the messages are the same; only the chunk boundaries moved).
//! - the block-layout examples (ambient_monitoring, day_of_traffic, hour_of_traffic,
//!   two_trucks): they now carry the `/preview/...` channels (25 Hz); every other message
//!   is unchanged.
//! - the examples with sensors on DAQ node clocks (ambient_monitoring, day_of_traffic,
//!   hour_of_traffic): the measured preview channels' metadata names the node
//!   (`daq_node`, `timestamps`); no message changed.
//! - every run: the 3D scene on `/scene` (on by default at 10 Hz) and a first `/events`
//!   line saying what the run holds; every other message is unchanged (chunk boundaries
//!   move with the added bytes).

use std::path::Path;
use std::process::Command;

use sha2::{Digest, Sha256};

/// (scenario in examples/, or "" for the embedded default; simulated seconds, or 0 for
/// the scenario's own duration; SHA-256 of the output).
const PINNED: &[(&str, f64, &str)] = &[
    (
        "",
        0.0,
        "5ad9e87507d81682eedcc01867f9e929933f252250e75abab10a9333b6506944",
    ),
    (
        "ambient_monitoring",
        20.0,
        "11419dcee5286f65f574abf36cf43aaf7a3100c272d413fb000be435c9aa0705",
    ),
    (
        "ambient_monitoring",
        120.0,
        "fba8374a0e6db4e45c66cdc75c21f96756ad432cb7d79f0b00fd47d772f5d621",
    ),
    (
        "damage_onset",
        20.0,
        "f3fa722f5aaa698dd15f98f38ce46c5874c6562a6c804e35bc2bedddb325cf98",
    ),
    (
        "day_of_traffic",
        20.0,
        "d8681c297c1e8a9728b28f1e5d5d9edc9b0e486304716b07b9e247eb67a5442c",
    ),
    (
        "hour_of_traffic",
        20.0,
        "10b563c873785a3929fbd58648db11fe96c00e6ccbbbcdb615664ecec8f279e3",
    ),
    (
        "hour_of_traffic",
        60.0,
        "ee3cece34dda7f879ebe93935096785096c0cb1208b87087991d30393d30a043",
    ),
    (
        "moving_force",
        20.0,
        "d22e6c04224a913eb4a3f681bd55b661b06049288fb8466b8266c1ab36a76d47",
    ),
    (
        "paper_case",
        20.0,
        "f1ce176f9de97672e0912890a62746181a98b3d55ab1e8650ed8a8d685d19544",
    ),
    (
        "two_trucks",
        20.0,
        "bbfeac6b49a7ee74c3b839e3aa00e466b1374d68eb06158f05ffc8afa9dd0d0d",
    ),
    (
        "two_trucks",
        40.0,
        "da4adaa9e6ff7f6fec3c37d4d1e9fcabcc1b796f874eecdd1af5ff9c1a8adf3a",
    ),
];

/// The SHA-256 of what `simulate` writes for `example` over `duration_s`.
fn output_hash(dir: &Path, example: &str, duration_s: f64) -> String {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let out = dir.join(format!(
        "{}.mcap",
        if example.is_empty() {
            "default"
        } else {
            example
        }
    ));
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_bridgetwin"));
    // The pins hold for every build: the run records "unknown" for the source revision
    // instead of the build's, which changes with every commit.
    cmd.env("BRIDGETWIN_RUN_REVISION", "unknown");
    cmd.arg("simulate");
    if !example.is_empty() {
        cmd.arg(root.join("examples").join(format!("{example}.toml")));
    }
    if duration_s > 0.0 {
        cmd.args(["--duration-s", &duration_s.to_string()]);
    }
    cmd.arg("--out").arg(&out).arg("--force");
    let done = cmd.output().expect("bridgetwin runs");
    assert!(
        done.status.success(),
        "{example}: {}",
        String::from_utf8_lossy(&done.stderr)
    );
    // The hourly examples write `name-0000.mcap`: one part within an hour.
    let part = dir.join(format!("{example}-0000.mcap"));
    let written = if part.exists() { part } else { out };
    let bytes = std::fs::read(&written).expect("output readable");
    std::fs::remove_file(&written).expect("removable");
    format!("{:x}", Sha256::digest(&bytes))
}

#[test]
fn the_default_run_and_every_example_keep_their_bytes() {
    let dir = tempfile::tempdir().unwrap();
    let mut changed = Vec::new();
    for &(example, duration_s, pinned) in PINNED {
        let got = output_hash(dir.path(), example, duration_s);
        if got != pinned {
            changed.push(format!(
                "{:?} over {duration_s} s: {got} (pinned {pinned})",
                example
            ));
        }
    }
    assert!(
        changed.is_empty(),
        "outputs changed (update PINNED only for an intended change):\n{}",
        changed.join("\n")
    );
}

#[test]
fn every_example_is_pinned() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "toml") {
            let name = path.file_stem().unwrap().to_string_lossy().into_owned();
            assert!(
                PINNED.iter().any(|p| p.0 == name),
                "examples/{name}.toml has no pinned output hash"
            );
        }
    }
}
