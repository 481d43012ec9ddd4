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
        "712ae4a07b7eb67dd5dc5f9b71577c2b8f7486ed989b5ef259269987acc4c4dc",
    ),
    (
        "ambient_monitoring",
        120.0,
        "95cf04786a6fe271824fc1dee50432be9bcedb99cf569f80507571bef024ccfc",
    ),
    (
        "damage_onset",
        20.0,
        "22c7571bf72fdc7012bedb8f496f80286489f7e6da9247013965daaa62876ac3",
    ),
    (
        "day_of_traffic",
        20.0,
        "8553d60864b64724626ea9e627f25b553910255d20e91deae1bfd4f17debf7fb",
    ),
    (
        "hour_of_traffic",
        20.0,
        "fe7d7548f656899dc6ec9e66df15c770fddbee70eecec5a8ca3e06b2d0cc813c",
    ),
    (
        "hour_of_traffic",
        60.0,
        "d56af8008aacff46867d9db5f797c34f4c4fe060362a1f05e734a9344b3ba34b",
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
        "14a35e97a8fd4abc2b94cd112f66e0319ab0aaf0db3efa237b47a1fbfb3b5f1a",
    ),
    (
        "two_trucks",
        40.0,
        "906015c65471d3fbe2b7611d681ff95d412fccfeea5509c67d0ebabdcc6a2e79",
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
