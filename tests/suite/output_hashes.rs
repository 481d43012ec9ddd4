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

use std::path::Path;
use std::process::Command;

use sha2::{Digest, Sha256};

/// (scenario in examples/, or "" for the embedded default; simulated seconds, or 0 for
/// the scenario's own duration; SHA-256 of the output).
const PINNED: &[(&str, f64, &str)] = &[
    (
        "",
        0.0,
        "7f01666e56c4373b03858b051dd577a13ab9aa264c372be1ac894393b16b91a0",
    ),
    (
        "ambient_monitoring",
        20.0,
        "c1985da4e39c8917c4dc82d9fc660904ce7dff93f68b254455053b722b1d487d",
    ),
    (
        "ambient_monitoring",
        120.0,
        "c2a9656b78e3713221482765841bcc3c407c0557037d2b685ccc83a5bdb97993",
    ),
    (
        "damage_onset",
        20.0,
        "555ec783a923c11daab7f1d1e3fe8bcfb2d7ce4dd4b12853f971853697cdb8b9",
    ),
    (
        "day_of_traffic",
        20.0,
        "93272b0d30ce4d1d8eb9098abc354d282abbebbb1df2f1855b440b8d678fb53b",
    ),
    (
        "hour_of_traffic",
        20.0,
        "803842bcc377c9af0c7bc74edbdfeb9a9acdfc97867177ab39f17d6182a96a7d",
    ),
    (
        "hour_of_traffic",
        60.0,
        "4cdab44e48e116fa23e4835f342a236511708f7d310fc2b4898a18f3edfcee93",
    ),
    (
        "moving_force",
        20.0,
        "d204a547e2d177a690dd27c25ad11960b1fa996ccdec4294019ff0e58eddcac4",
    ),
    (
        "paper_case",
        20.0,
        "2e8405f4f521d6190aa1a4e91553517912d3a49a7d9e56b72e728014b759247a",
    ),
    (
        "two_trucks",
        20.0,
        "2314feba85053802e377f30a40eb3aee805ad93ccfeb913be6357be635adca15",
    ),
    (
        "two_trucks",
        40.0,
        "7355ea1a294c038183daa7e0e440780cfabc28d277686d5c10e09a1db73180f8",
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
