//! Readers of untrusted files never crash: 1200 corrupted variants of a
//! run (byte flips anywhere, flips aimed at the header, the chunks and the summary,
//! truncations, zeroed and garbage ranges) go to each reader: `inspect`, `simulate --from`
//! (its scenario read) and the input layer's `read_run` (the Python package's reader). Each
//! must return, never panic or abort (a corrupted length once made `inspect` ask for 71 PB
//! and abort: lengths are now checked against the file before any allocation). A variant
//! that is not the file must be reported as damaged or refused by `inspect` and `read_run`,
//! never read as whole: chunk, data-section and summary CRCs are all checked. `simulate
//! --from` reads only the records before the first message (the scenario), so damage past
//! them is not its concern; it must refuse what it cannot read and never panic.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

use bridgetwin::cli::from_mcap::scenario_from_mcap;
use bridgetwin::cli::inspect_cmd::inspect;
use bridgetwin::input::{read_run, ReadOptions};

/// A short default run (two layouts would only repeat the same records).
fn original(dir: &Path) -> Vec<u8> {
    std::fs::read(crate::common::simulate_default_file(dir, 1.5)).unwrap()
}

/// How one variant was damaged.
#[derive(Debug, Clone)]
enum Change {
    Flip { at: usize, mask: u8 },
    Truncate { len: usize },
    Zero { at: usize, len: usize },
    Garbage { at: usize, len: usize },
}

fn apply(bytes: &[u8], change: &Change, rng: &mut ChaCha8Rng) -> Vec<u8> {
    let mut v = bytes.to_vec();
    match *change {
        Change::Flip { at, mask } => v[at] ^= mask,
        Change::Truncate { len } => v.truncate(len),
        Change::Zero { at, len } => v[at..(at + len).min(bytes.len())].fill(0),
        Change::Garbage { at, len } => {
            for b in &mut v[at..(at + len).min(bytes.len())] {
                *b = rng.random();
            }
        }
    }
    v
}

/// 1200 changes: 300 flips anywhere, 150 each in the header (first 64 bytes), the chunks
/// and the summary (the last 15 %), 150 truncations, 150 zeroed and 150 garbage ranges.
fn changes(len: usize, rng: &mut ChaCha8Rng) -> Vec<Change> {
    let mask = |rng: &mut ChaCha8Rng| 1u8 << rng.random_range(0..8);
    let summary_start = len - len * 15 / 100;
    let mut out = Vec::new();
    for _ in 0..300 {
        out.push(Change::Flip {
            at: rng.random_range(0..len),
            mask: mask(rng),
        });
    }
    for (lo, hi) in [(0, 64), (64, summary_start), (summary_start, len)] {
        for _ in 0..150 {
            out.push(Change::Flip {
                at: rng.random_range(lo..hi),
                mask: mask(rng),
            });
        }
    }
    for _ in 0..150 {
        out.push(Change::Truncate {
            len: rng.random_range(0..len),
        });
    }
    for _ in 0..150 {
        out.push(Change::Zero {
            at: rng.random_range(0..len),
            len: rng.random_range(1..4096),
        });
    }
    for _ in 0..150 {
        out.push(Change::Garbage {
            at: rng.random_range(0..len),
            len: rng.random_range(1..4096),
        });
    }
    out
}

/// What a reader made of a variant.
#[derive(Debug, PartialEq, Eq, Clone, Copy)]
enum Verdict {
    /// Read as a whole file.
    Whole,
    /// Read up to reported damage.
    Damaged,
    /// Refused with an error.
    Refused,
    /// Panicked (a defect).
    Panicked,
}

fn verdict(f: impl FnOnce() -> Verdict) -> Verdict {
    catch_unwind(AssertUnwindSafe(f)).unwrap_or(Verdict::Panicked)
}

fn by_inspect(path: &Path) -> Verdict {
    match inspect(path) {
        Ok(report) if report.damage.is_some() => Verdict::Damaged,
        Ok(_) => Verdict::Whole,
        Err(_) => Verdict::Refused,
    }
}

fn by_read_run(path: &Path) -> Verdict {
    match read_run(&[path.to_path_buf()], &ReadOptions::default()) {
        Ok(run) if run.damage().next().is_some() => Verdict::Damaged,
        Ok(_) => Verdict::Whole,
        Err(_) => Verdict::Refused,
    }
}

fn by_from(path: &Path) -> Verdict {
    match scenario_from_mcap(path) {
        Ok(_) => Verdict::Whole,
        Err(_) => Verdict::Refused,
    }
}

#[test]
fn corrupted_runs_are_reported_never_crash_the_readers() {
    let dir = tempfile::tempdir().unwrap();
    let bytes = original(dir.path());
    let mut rng = ChaCha8Rng::seed_from_u64(16);
    let all = changes(bytes.len(), &mut rng);
    assert_eq!(all.len(), 1200);
    let path: PathBuf = dir.path().join("variant.mcap");
    let mut panics = Vec::new();
    let mut whole_but_changed = Vec::new();
    let mut counts = std::collections::BTreeMap::new();
    for change in &all {
        let variant = apply(&bytes, change, &mut rng);
        std::fs::write(&path, &variant).unwrap();
        let verdicts = [
            ("inspect", verdict(|| by_inspect(&path))),
            ("read_run", verdict(|| by_read_run(&path))),
            ("simulate --from", verdict(|| by_from(&path))),
        ];
        for (reader, v) in verdicts {
            *counts.entry((reader, format!("{v:?}"))).or_insert(0u32) += 1;
            if v == Verdict::Panicked {
                panics.push(format!("{reader}: {change:?}"));
            }
            if v == Verdict::Whole && variant != bytes && reader != "simulate --from" {
                whole_but_changed.push(format!("{reader}: {change:?}"));
            }
        }
    }
    println!("{counts:#?}");
    assert!(
        panics.is_empty(),
        "{} panics: {:#?}",
        panics.len(),
        &panics[..panics.len().min(20)]
    );
    assert!(
        whole_but_changed.is_empty(),
        "{} variants read as whole although changed: {:#?}",
        whole_but_changed.len(),
        &whole_but_changed[..whole_but_changed.len().min(20)]
    );
    // Every kind of damage was met: the test exercises each verdict.
    for (reader, v) in [
        ("inspect", "Damaged"),
        ("inspect", "Refused"),
        ("read_run", "Damaged"),
    ] {
        assert!(
            counts.get(&(reader, v.to_string())).copied().unwrap_or(0) > 0,
            "{reader} never {v}"
        );
    }
}

/// The command line's exit codes: 0 for the whole file, 3 for one read up to its damage
/// (the report printed), 1 for one that is no MCAP file at all.
#[test]
fn inspect_exits_3_on_damage_and_1_on_garbage() {
    let dir = tempfile::tempdir().unwrap();
    let bytes = original(dir.path());
    let inspect_exit = |name: &str, data: &[u8]| {
        let path = dir.path().join(name);
        std::fs::write(&path, data).unwrap();
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_bridgetwin"))
            .arg("inspect")
            .arg(&path)
            .output()
            .unwrap();
        (
            o.status.code(),
            String::from_utf8_lossy(&o.stdout).into_owned(),
            String::from_utf8_lossy(&o.stderr).into_owned(),
        )
    };
    let (code, _, _) = inspect_exit("whole.mcap", &bytes);
    assert_eq!(code, Some(0));
    let (code, stdout, stderr) = inspect_exit("cut.mcap", &bytes[..bytes.len() * 2 / 3]);
    assert_eq!(code, Some(3), "{stderr}");
    assert!(
        stdout.contains("channels"),
        "the report of the intact part: {stdout}"
    );
    assert!(
        stderr.contains("cut.mcap is damaged") && stderr.contains("intact part ends"),
        "{stderr}"
    );
    let mut flipped = bytes.clone();
    let at = bytes.len() - 200;
    flipped[at] ^= 0x10;
    let (code, _, stderr) = inspect_exit("summary_flip.mcap", &flipped);
    assert_eq!(code, Some(3), "a flip in the summary: {stderr}");
    let (code, _, stderr) = inspect_exit("garbage.mcap", b"not an mcap file at all");
    assert_eq!(code, Some(1), "{stderr}");
}

/// Found by fuzzing the readers (tests/fuzz, `mcap_readers`): a flipped byte in the
/// length of a metadata value made the `mcap` crate's parser reserve 4 GB for a record of
/// a few kB. The lengths inside every record are now checked against the record before
/// it is parsed: the damage is reported as a corrupted length, with nothing reserved.
#[test]
fn a_corrupted_length_inside_a_record_is_damage_not_an_allocation() {
    let dir = tempfile::tempdir().unwrap();
    let mut bytes = original(dir.path());
    // The `scenario` metadata record's map: key "toml", then the value's u32 length.
    let key = b"\x04\x00\x00\x00toml";
    let at = bytes
        .windows(key.len())
        .position(|w| w == key)
        .expect("the scenario metadata's toml key")
        + key.len();
    bytes[at..at + 4].copy_from_slice(&0xFF00_0005u32.to_le_bytes());
    let path = dir.path().join("long_value.mcap");
    std::fs::write(&path, &bytes).unwrap();
    let run = read_run(std::slice::from_ref(&path), &ReadOptions::default()).unwrap();
    let (_, damage) = run.damage().next().expect("reported as damaged");
    assert!(
        damage.reason.contains("claims 4278190085 bytes")
            && damage.reason.contains("corrupted length"),
        "{damage}"
    );
    let report = inspect(&path).unwrap();
    assert!(report.damage.unwrap().contains("corrupted length"));
    assert!(scenario_from_mcap(&path).is_err());
}
