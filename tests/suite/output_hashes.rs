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

use std::path::Path;
use std::process::Command;

use sha2::{Digest, Sha256};

/// (scenario in examples/, or "" for the embedded default; simulated seconds, or 0 for
/// the scenario's own duration; SHA-256 of the output).
const PINNED: &[(&str, f64, &str)] = &[
    (
        "railway_bridge",
        20.0,
        "50b6c8d4fdf5911de8fb25aee92ddb220d04b6c4443eaaac4f6b28a5652f55b3",
    ),
    (
        "",
        0.0,
        "bdbe2816742cb617e9f82ae9fc960fa59217d680d61749526b2f3536c27ac23f",
    ),
    (
        "ambient_monitoring",
        20.0,
        "1913901a7716bf2371727cddd1315b9ab006a0f33e0b486df827a879a8cbbfeb",
    ),
    (
        "ambient_monitoring",
        120.0,
        "4f6843229e2a6ba2f54e34512b05333d015e4b0a61d4a0787b782c6ed8a5ada9",
    ),
    (
        "damage_onset",
        20.0,
        "5b0ba0ee58e0e793062b9757f28d6d55b55d9129a6d20e7631f6f329483403f3",
    ),
    (
        "bwim_calibration",
        20.0,
        "c4607c4a47e28c4ab3dc8a5a7aed6cb90969a59883072bf7ba8fb98de8393759",
    ),
    (
        "bwim_hour_of_traffic",
        20.0,
        "603f09e815bae15bc4a78f7d9770f3fc34ea7e20bd5c965d6d1d1a1ff79d802e",
    ),
    (
        "drive_by",
        20.0,
        "e22c831e885b8f0752b83397371ca8a14eec23824a66c1a411ee954363e1b5b0",
    ),
    (
        "frequency_tracking",
        20.0,
        "595f6e3520493817dfb71372a06a2bbbca887baf3bd14df717d8fea4e630f718",
    ),
    (
        "day_of_traffic",
        20.0,
        "4642ea8e9342f2705edaa39a3562963197770ce9a061e58fcac417c3a3eb6a50",
    ),
    (
        "hour_of_traffic",
        20.0,
        "b803266a0a691aa6bcf4c45c2d4f6e1ba1b2693e41869daedcc34488f722c2bc",
    ),
    (
        "hour_of_traffic",
        60.0,
        "b36f92448cba4163ed2924e255cd4874e16830da5925e710f21b44ad3b6865bd",
    ),
    (
        "moving_force",
        20.0,
        "6405ac02e41404460b133234707a1bb7689c05ae070378c21d0ce85e984549e8",
    ),
    (
        "paper_case",
        20.0,
        "ab4864c076cf2c9c3bdb48f96d3974ccd71158bd25b6a65850be35c842771aa3",
    ),
    (
        "two_trucks",
        20.0,
        "65ddab5118d0ea5eaf56292e40a3ea98499604bd5e967e06e139802f4d57b23a",
    ),
    (
        "two_trucks",
        40.0,
        "3e0d30783bc535caf00e5831d91eff91bd1ef37c5e531179b7f29c7148781ead",
    ),
    (
        "three_span_continuous",
        0.0,
        "3fd08aa28b86698e1ecee2064a0d769f438ff83c42864f7dcbbbec230d8e074a",
    ),
    (
        "three_span_hour_of_traffic",
        20.0,
        "a9f8f0f498ce74f35de2db862d30d4cf45d9b08eeb79046cfa30d3294e970819",
    ),
    (
        "two_span_concrete",
        0.0,
        "69ada98d714ebd6b8a6c0b5b1ac436ec836279ec4d820bbd3b5c6f9dede88d6e",
    ),
    (
        "three_span_concrete",
        0.0,
        "73359022fdcb713d922137c07c16eead77c3fa390081777e4e3821ec937763a0",
    ),
    (
        "steel_composite_three_span",
        0.0,
        "af15be18cac213f16d832f4f4b3dbeee550ce61e52ed6a5c04e9dcbfb10bab6c",
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
