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
//! - every run with a sensor on the bridge: the truth `moment_n_m` and `strain_microstrain`
//!   of every bridge sensor, and the measured strain, are the moment recovered from the
//!   equilibrium of the element the sensor sits in (`physics::bridge::MomentGauge`), not
//!   the element's interpolated curvature (0.5 % of the peak on the default run; checked
//!   by decoding both versions: no other value changed); the support reactions under a
//!   sleeper spread take each sleeper's share of a wheel load.

use std::path::Path;
use std::process::Command;

use sha2::{Digest, Sha256};

/// (scenario in examples/, or "" for the embedded default; simulated seconds, or 0 for
/// the scenario's own duration; SHA-256 of the output).
const PINNED: &[(&str, f64, &str)] = &[
    (
        "railway_bridge",
        20.0,
        "54c20daad17cf602135efaad6da5eed519759620cfaca3dc7c8075ee0dd30817",
    ),
    (
        "long_train_three_spans",
        3.0,
        "d0d57dab9e5db9bc733eec6173752cb9175dadce42a064c6bcf3085042dd0e7e",
    ),
    (
        "",
        0.0,
        "4f471bc9a2632fc36e809a165b4572b4215c42addece9a8492c8128f693dafbe",
    ),
    (
        "ambient_monitoring",
        20.0,
        "96424473d8ba2492db52f0297dbef894865b917fb087254ccc8860926a3b73da",
    ),
    (
        "ambient_monitoring",
        120.0,
        "322bd8f247b4ffe527cf07cbba40e3574ecf7e5f75d14931eaea91aeda698dd5",
    ),
    (
        "damage_onset",
        20.0,
        "954e008c22b9ccd28d522a8b4d84b781d58b1f55c4de2f44e5a903d51b659ad6",
    ),
    (
        "bwim_calibration",
        20.0,
        "aaf1e02e2c298430d1f3df9b1764cc24f90644e796d1cd51533d00615910f675",
    ),
    (
        "bwim_hour_of_traffic",
        20.0,
        "0ab49e2e7b41c342c03848a2e71c76f6419877c2bbf04a2e25275603976828b4",
    ),
    (
        "drive_by",
        20.0,
        "1e2b0b10531dadd53e7ddcbc49ec097d0a4303e35cb19bbd1ed0dffa18e172cf",
    ),
    (
        "frequency_tracking",
        20.0,
        "ae63420c4db343229255d1ba080e764e068801f3bff9ad628a80bedf7aef7f15",
    ),
    (
        "day_of_traffic",
        20.0,
        "2d864a987e4046c31eed2385b8fc5bca19bdfe36c2c2f6b73481a6018adeac25",
    ),
    (
        "hour_of_traffic",
        20.0,
        "769e7719d6b9f071f33696f6d30d4757aef4a4aa5dc48f451fd17500c09ee330",
    ),
    (
        "hour_of_traffic",
        60.0,
        "fc63e664c0a3c8cd13790c48fafabaee82897723e83ded0d302c21049f08ef8c",
    ),
    (
        "moving_force",
        20.0,
        "56162bac44e855f7c89122d01479130f5c79322773bfa7a41a77dad14af014a4",
    ),
    (
        "paper_case",
        20.0,
        "37db838505fa7c500343a7706940546172835a5b270f1ba6effcb83099e59957",
    ),
    (
        "two_trucks",
        20.0,
        "1e43a56e9a733f393f2abf918e32e261ae794be5e1b23cd8445cc0e62588872a",
    ),
    (
        "two_trucks",
        40.0,
        "d265431ad703c26ef9390306a262f3715e32d30adcb0e161c08693c1059b5aab",
    ),
    (
        "three_span_continuous",
        0.0,
        "b5d126c230fd2d30b959e26091880240ebcf4d209554e9cc94e8543be6373725",
    ),
    (
        "three_span_hour_of_traffic",
        20.0,
        "e431975f31a1f786299342cb1f9939621aaeaf5350f65acf54ff995313ea4bab",
    ),
    (
        "two_span_concrete",
        0.0,
        "db0f689dac02323c2af17ab128be546653d11b20de330aea61729fb78f0a2923",
    ),
    (
        "three_span_concrete",
        0.0,
        "81182381c74d4c813ded813f01f1b4f7060f2b1a1d398fdf671578c95fa349cc",
    ),
    (
        "steel_composite_three_span",
        0.0,
        "76a6d4ff6597633fb52d5b53ede104450fd455eec5f0c17e93f42788455b1d8a",
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
