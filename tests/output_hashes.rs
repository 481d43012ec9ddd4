//! The bytes of the default run and of every example (short durations) are pinned: a
//! refactor must not change what a user's dataset contains. Each hash is the SHA-256 of
//! the file `bridgetwin simulate` writes.
//!
//! When an output change is intended (a new field, a fixed value), update the hash of
//! every affected row here, in the same commit, and say in its message what changed and
//! why. History of intended changes:
//! - the runs of 60 s and more: chunks now close every 60 s of simulated time instead of
//!   every 2 s of wall time (the messages are the same; only the chunk boundaries moved).
//! - every example: its first line is now the `#:schema ../docs/scenario.schema.json`
//!   directive for TOML editors, and a run stores its source TOML as an attachment, so
//!   the attachment (and only it) gained that line; the default run is unchanged. The
//!   examples without the line give the earlier hashes.

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
        "bcc2c0d6bd9101e611b917a2c5cc66cd24707bb944e5bf11dc266c9d77415cb3",
    ),
    (
        "ambient_monitoring",
        120.0,
        "5182520f540ddd2a7faa923301c382816fd2fe5ea8e30b61d4ecf9b9a45a37d7",
    ),
    (
        "damage_onset",
        20.0,
        "22c7571bf72fdc7012bedb8f496f80286489f7e6da9247013965daaa62876ac3",
    ),
    (
        "day_of_traffic",
        20.0,
        "32b310c2cbbfe4eb1549a5e4a516ac5a6424e498b4d69809892a80e39b20978a",
    ),
    (
        "hour_of_traffic",
        20.0,
        "6af7c73fd8997bb89541eadfc60e1347141eb93b44539015393e9437375413ec",
    ),
    (
        "hour_of_traffic",
        60.0,
        "b12966187fcc066b3f4c6e29ad9858a53879029330327ffeaa21b8467506533d",
    ),
    (
        "moving_force",
        20.0,
        "9f318c29b08a237849614a2c2eb616733346f740c1cb3cb635c1bb9f528d0f44",
    ),
    (
        "paper_case",
        20.0,
        "439ed4c58fef675d84963342aa42b28fb1c085376b65344fc2c87fba4ce1e8f5",
    ),
    (
        "two_trucks",
        20.0,
        "b4c923a289a97e5550772a78c716e19475d78c876d5b364daa1912f09fa401cf",
    ),
    (
        "two_trucks",
        40.0,
        "98c94dd16ab42c4740661ccc6e3c2ea5d28ac3342b324aaf79b91d6766ce351c",
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
