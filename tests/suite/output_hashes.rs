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

use std::path::Path;
use std::process::Command;

use sha2::{Digest, Sha256};

/// (scenario in examples/, or "" for the embedded default; simulated seconds, or 0 for
/// the scenario's own duration; SHA-256 of the output).
const PINNED: &[(&str, f64, &str)] = &[
    (
        "",
        0.0,
        "87890a25d526704a681b76e82fc23bfa4a6dfe4044f1d003f2fc167573fdb2b3",
    ),
    (
        "ambient_monitoring",
        20.0,
        "fe061ff113551ba67a7373191dd65590a8c878394bebad9e4341c7a32eaf34ae",
    ),
    (
        "ambient_monitoring",
        120.0,
        "a95d6c243ea5b4b6e4c931f75a41dc4efc4f2b1c4c9f9c195c750768a5505b46",
    ),
    (
        "damage_onset",
        20.0,
        "7a4e77da865ddd50ee31de6e4de52907f9825e68ba87a2a4ef02946670f0b5bd",
    ),
    (
        "day_of_traffic",
        20.0,
        "a78899a5abb523a35a2151f58755d627fb1c74d1751ca5d0d2790cf895c89261",
    ),
    (
        "hour_of_traffic",
        20.0,
        "25742aaae043f0b4fa159c7a847f4c8e57a3082225f425635d2b0857171401cb",
    ),
    (
        "hour_of_traffic",
        60.0,
        "0b1e701fa2bfee1a125443c8e37779fe5f59a16a871c679ffb775894695839c2",
    ),
    (
        "moving_force",
        20.0,
        "9c4076fe1d9a5a3d3b0014dc653d323a2b1bd27b506d785dc66945619b5ea91e",
    ),
    (
        "paper_case",
        20.0,
        "d4dca82a02aa417871ed8e138807f2e214452917c01f8686b7daea3e205be3c2",
    ),
    (
        "two_trucks",
        20.0,
        "eb6a302ca4f5082a439c467a8e3e21cf6989c0e51dbe602787c6d9734e11b5be",
    ),
    (
        "two_trucks",
        40.0,
        "dcfde7ec6cde30e3781e582d57d6efa347b92488067aefc9c6bc4c4de529526f",
    ),
    (
        "three_span_continuous",
        0.0,
        "3028e511da66daa1d98b66119f3b91fc47d5648aa026bebd01fbdbf9fb47d049",
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
