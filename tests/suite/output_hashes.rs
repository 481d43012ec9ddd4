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
        "a9f4f3715c81604ee896ea178356d526b7ad1a277be569f3e0042bce936cfb18",
    ),
    (
        "ambient_monitoring",
        120.0,
        "7b057abbf8974864c83b663af41873722c84478e351f03f2431994a468328520",
    ),
    (
        "damage_onset",
        20.0,
        "555ec783a923c11daab7f1d1e3fe8bcfb2d7ce4dd4b12853f971853697cdb8b9",
    ),
    (
        "day_of_traffic",
        20.0,
        "ff388c11f9d6e066c906b49c2548f367ea38216dfeab8c4b2fc5722901143ab4",
    ),
    (
        "hour_of_traffic",
        20.0,
        "f74944da31735a460896c20323a126d3bf25681930551c1e7fdb6dfe9cfb35a7",
    ),
    (
        "hour_of_traffic",
        60.0,
        "bd7e42bc38ad6b1e5c4515e2d2cf3d552848d8b403977e1d0f2ec9e817db50b7",
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
