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
//! - every run: the `BridgeState` schema gains `support_stiffness_ratio` and
//!   `support_settlement_m` (`[[support_condition]]`; empty otherwise); no value changed.
//! - every run: the schemas gain the thermometer's `TemperatureSample` and the truth
//!   streams' `temperature_c` (zero, not encoded, for the other kinds); no value changed.
//! - every run with a vehicle on the bridge: the coupled step is restructured for speed
//!   (each vehicle block's prediction is one precomputed product, its contact system off
//!   the span a precomputed inverse, the group on the span solved through the tyres on
//!   the span only, the tyre-force part of the bridge history fused): the same equations
//!   with other sums, so the states move at round-off (every verification row holds).
//! - every run on a flat road with no shape (smooth): the road profile attachment is its
//!   two end points, not a 0.05 m grid of zeros, and the road's description prints its
//!   ends to the millimetre.

use std::path::Path;
use std::process::Command;

use sha2::{Digest, Sha256};

/// (scenario in examples/, or "" for the embedded default; simulated seconds, or 0 for
/// the scenario's own duration; SHA-256 of the output).
const PINNED: &[(&str, f64, &str)] = &[
    (
        "railway_bridge",
        20.0,
        "142beca910820d7ac3413d40af0acca3314c922946ccc7d9bc117d6033692adb",
    ),
    (
        "long_train_three_spans",
        3.0,
        "87d9ccba27041b4758b17675fd37e4f75340b4386f5cdbc2dc09efebb7b9504d",
    ),
    (
        "",
        0.0,
        "c7b773c861ac8cd5b757aeef8f9ff31c18f7cdcd273521af9fbd49f53f2fb0f1",
    ),
    (
        "ambient_monitoring",
        20.0,
        "a318f02a99381935a12074cdfe9d6b93fc9a7fb7b8fbc206096864ea99afd975",
    ),
    (
        "ambient_monitoring",
        120.0,
        "f069705184296722dcf4d6d8047c8909dd7a003c59b63c7b5862cb23ad3de650",
    ),
    (
        "damage_onset",
        20.0,
        "9ab580408d0bdab681a418126b77d927435b82b5ef4594799cc91dc42846e368",
    ),
    (
        "bwim_calibration",
        20.0,
        "1f7f91456a8ee578ae0d27c744fb290c385d252b72957c81f5b72cac5a093b04",
    ),
    (
        "bwim_hour_of_traffic",
        20.0,
        "d5c0706f3ece1c12788433885cb72d06aa9c3e149f346e9ec8f84fb52113d2cf",
    ),
    (
        "drive_by",
        20.0,
        "bd9c5e18a17fbaedbe79be1cfdc60f25b23685b9508d2f280cd6949d0ad88a61",
    ),
    (
        "frequency_tracking",
        20.0,
        "bef2da349f9781be2d388c07c99b621fdd185bde7e50157373a2eae894761617",
    ),
    (
        "day_of_traffic",
        20.0,
        "c5655682c9b66f0c76f028d1beaa56dc751981760882e7b5772180911eb83a40",
    ),
    (
        "hour_of_traffic",
        20.0,
        "fef0f9f2069017984e6a956d765f7363074fe1fb0ce5e39e628919a3f9cc0702",
    ),
    (
        "hour_of_traffic",
        60.0,
        "8d16a1287509c96b009440233d394b3f31d401644f0a0826bcab3f570bbc6c2d",
    ),
    (
        "moving_force",
        20.0,
        "ff359ebbb649d35a4edc116f50238192f6794d4b360b549a08f9b8056c9f7d91",
    ),
    (
        "paper_case",
        20.0,
        "0b1b7bbfefc51c98be152e032565dcc79d358605cbb7e548bf3dcbf36d05883b",
    ),
    (
        "two_trucks",
        20.0,
        "e9b257106cfbcc6e82e19f431e618a033ebe90009893ab71899542f0f06cff13",
    ),
    (
        "two_trucks",
        40.0,
        "3bec4850665d171d02e870499c448f56fe4cb38ba3846c17586e6490f3f68eba",
    ),
    (
        "three_span_continuous",
        0.0,
        "6ff40184387ad5d13f18aa2f2fe74ffcbac1b7ccdf2762a1c8fafebb3da36207",
    ),
    (
        "three_span_hour_of_traffic",
        20.0,
        "734c9cb3ede24563924443882fd0b463d6fa1c1b5e10e7cb57a92098e8f5c540",
    ),
    (
        "two_span_concrete",
        0.0,
        "2c9c0f7235fddaa3dacb3176f6b75f7772486dbbd86775d017b18d20a5e20998",
    ),
    (
        "three_span_concrete",
        0.0,
        "ad963e5c81c1c5c01a186d49e14ad2d90fe0e87d1013d195f839aa8d84dccef9",
    ),
    (
        "steel_composite_three_span",
        0.0,
        "e26f7d2f1557e3b73db058c0dbabd58fda3a20b3560bf0f9b7840e47d67cd239",
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
