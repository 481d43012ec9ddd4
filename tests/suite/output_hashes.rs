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
//! - every example: its first line is now the `#:schema ../docs/scenario.schema.json`
//!   directive for TOML editors, and a run stores its source TOML as an attachment, so
//!   the attachment (and only it) gained that line; the default run is unchanged.
//! - the examples with ambient excitation or model rebuilds (ambient_monitoring,
//!   damage_onset, day_of_traffic, hour_of_traffic): the ambient calibration projects the
//!   damping matrix on the modes with the band product of the finite-element model, which
//!   is now stored as a band, instead of a dense product: the same sum in another order,
//!   so the damping ratios, and the ambient loads scaled by them, move at round-off.
//! - every example with a rough road (all but damage_onset and moving_force): the road
//!   profile's inverse FFT is the scalar one on every CPU (it picked AVX or SSE code at
//!   run time, so its round-off, and a run's bytes, depended on the machine): the
//!   profiles move at round-off.
//! - every run in which a vehicle is on the bridge within the pinned duration: the contact
//!   systems' small LU is the project's own partial-pivoting elimination instead of a
//!   linear-algebra crate's (the same pivots, another order of the sums): the contact
//!   forces, and everything downstream, move at round-off.
//! - three_span_continuous: the 3D scene's exaggeration is scaled by the longest span's
//!   expected deflection, not the whole girder's (the metadata's `expected_peak_m` and the
//!   drawn factor changed; no data message).
//! - every run: the schemas gain the inclinometer and load-cell messages, the truth
//!   streams' `rotation_rad` and `reaction_n` (zero, so not encoded, for the other kinds)
//!   and `/truth/bridge`'s `support_reaction_n` (the reactions of the supports, on every
//!   deflected shape); every other value is unchanged (checked by decoding a run of each
//!   version), and the sensors' `sign` metadata is per kind.

use std::path::Path;
use std::process::Command;

use sha2::{Digest, Sha256};

/// (scenario in examples/, or "" for the embedded default; simulated seconds, or 0 for
/// the scenario's own duration; SHA-256 of the output).
const PINNED: &[(&str, f64, &str)] = &[
    (
        "",
        0.0,
        "8ad141b05e43fd1ba0b81063df013d725aa97f1d24d6d3a635c97765d70382d8",
    ),
    (
        "ambient_monitoring",
        20.0,
        "c5d54b82946cf2a20bee333bacf6b8d19707b580db359b3fbc8f1e6838840f58",
    ),
    (
        "ambient_monitoring",
        120.0,
        "1a69d774ca3f691ee7fc5141e72ec3ee3290922e8958b7689e197fe2d4e129c5",
    ),
    (
        "damage_onset",
        20.0,
        "78201ea8b1f1333ac0142d09d7a2da0991cc67886835d8d8012f085a23ad1528",
    ),
    (
        "day_of_traffic",
        20.0,
        "35a713126a997b7916899dd5f103174a06b93bb5d3c2e700a0a321354e7290a9",
    ),
    (
        "hour_of_traffic",
        20.0,
        "d2fd7b3909ba55b6bbfb9e5d1744a6cbb47f5b0914935af75de8cc2cf82715a2",
    ),
    (
        "hour_of_traffic",
        60.0,
        "1afffd373c02ee9f2c18ffcb9598969468b12d2239d2e390bb4e5ee14b74b4a6",
    ),
    (
        "moving_force",
        20.0,
        "6df4b0025dc223cec1d40ad610bd36c5d515bfcd36124dedb423df7dbd18918e",
    ),
    (
        "paper_case",
        20.0,
        "44376d7832770c4cb4bbb377490d50eb663fed920133a4f4648cab57beea9c40",
    ),
    (
        "two_trucks",
        20.0,
        "11f08b5970f29a70a7d1bf5b972c25dd3c43d179ac6c9ffe54bddc9e6ff0c407",
    ),
    (
        "two_trucks",
        40.0,
        "9921d024681632184a6eeba20781a675ad01e535cf0b290efdeba4809987286d",
    ),
    (
        "three_span_continuous",
        0.0,
        "3c9e00e30fdb2e86fd8d6683ab988add3c43a476dc6c08a69771641d6d0efaea",
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
