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

use std::path::Path;
use std::process::Command;

use sha2::{Digest, Sha256};

/// (scenario in examples/, or "" for the embedded default; simulated seconds, or 0 for
/// the scenario's own duration; SHA-256 of the output).
const PINNED: &[(&str, f64, &str)] = &[
    (
        "",
        0.0,
        "8cedce4b64ff01f9243741fe096078472fc8295238db955e4b5af25868819da2",
    ),
    (
        "ambient_monitoring",
        20.0,
        "4e89e190c698882fe05efe70179e3ee24af7aa292130bbd3b97715a157d97b96",
    ),
    (
        "ambient_monitoring",
        120.0,
        "a7a4eaee2f7bff6b913e732aa05a686d9746c8684a2501c7495077ff4be783c7",
    ),
    (
        "damage_onset",
        20.0,
        "b14df13c50a9f021453fe61bbf6f9f0ad641cd95aa47af81cc7adcdc86062f6e",
    ),
    (
        "day_of_traffic",
        20.0,
        "4b11f9770ed5108d52fb221f1c9ef148c909dda1ab84dbd1da6eacf2b55ebfe9",
    ),
    (
        "hour_of_traffic",
        20.0,
        "b4ded41c7ad0ad87bb13308d5088a945dfdae519f96bcd6636cd29b77bfd4717",
    ),
    (
        "hour_of_traffic",
        60.0,
        "874d8a9941a124e80207098ed0fe58c99c6e7987b0d1687fdf4fa3dbbbcf0b1c",
    ),
    (
        "moving_force",
        20.0,
        "4ff79da8b3fd2f68c5ec3d4d50ba0ae6073b212fc7483df2b7d3cf13e8c6676f",
    ),
    (
        "paper_case",
        20.0,
        "7d6168a594177bdd3a834f3885ef3579d54d3d2eb69c0900c8de8829138e60fc",
    ),
    (
        "two_trucks",
        20.0,
        "9c177a5ccf8f192a50d37d12fafa17b93c6f658028312d407b192ec885e3f3f7",
    ),
    (
        "two_trucks",
        40.0,
        "794da9b1eecfae1411807c2f0ab0c4c77a5f412e91876264d746393540251c4b",
    ),
    (
        "three_span_continuous",
        0.0,
        "9d22c5ebc632131939b687cd1c4e7a3b2875083a6d11250860223c495b4ca7af",
    ),
    (
        "three_span_hour_of_traffic",
        20.0,
        "17f1cf1e78da3f96667dd4bb5d23dc00bdf938a9c4168ba3aa66fb88625c2987",
    ),
    (
        "two_span_concrete",
        0.0,
        "ff2009cf7fde1d61e95caf5ce057dc3e751380e12b2ae9dd5cb797b066ffd9e9",
    ),
    (
        "three_span_concrete",
        0.0,
        "d9f72e1214d6db2978e68b6c7c81b1cfadd953b2f85a19eff50c9d5175a5e84c",
    ),
    (
        "steel_composite_three_span",
        0.0,
        "af8c6dfa5ebde38b392e59aa82a21dd2d2760095c33142dc72d4bba540a45342",
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
