//! The Python tools (`tools/check_mcap.py`, `read_run.py`, `compare_runs.py`,
//! `oma_check.py`) must fail on what is wrong: a corrupt file, a cut file, a killed run
//! that kept no message, a file without sensor topics, two runs that differ. Each is fed
//! here, beside a good file that must pass, so that a tool that passes everything fails
//! this test.
//!
//! They need a Python with the `mcap` packages (`tools/requirements.txt`), named by
//! `BRIDGETWIN_PYTHON` (`.ci/run` sets it to its venv). Without it every test here says
//! `SKIPPED` on stderr, uncaptured, and does nothing else.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::OnceLock;

use crate::common::{skip, BIN};

/// The Python named by `BRIDGETWIN_PYTHON`, or `None` after a loud skip of `test`.
fn python(test: &str) -> Option<PathBuf> {
    match std::env::var_os("BRIDGETWIN_PYTHON") {
        Some(python) => Some(PathBuf::from(python)),
        None => {
            skip(
                &format!("python_tools::{test}"),
                "BRIDGETWIN_PYTHON is not set (a Python with tools/requirements.txt)",
            );
            None
        }
    }
}

/// Runs `tools/<tool>` with `args`.
fn tool(python: &Path, tool: &str, args: &[&Path]) -> Output {
    let script = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tools")
        .join(tool);
    Command::new(python)
        .arg(&script)
        .args(args)
        .env("TQDM_DISABLE", "1")
        .output()
        .unwrap_or_else(|e| panic!("cannot run {}: {e}", python.display()))
}

fn describe(output: &Output) -> String {
    format!(
        "exit {:?}\n--- stdout ---\n{}--- stderr ---\n{}",
        output.status.code(),
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    )
}

/// Asserts the exit code of a run of a tool.
fn expect_exit(python: &Path, name: &str, args: &[&Path], code: i32) {
    let output = tool(python, name, args);
    assert_eq!(
        output.status.code(),
        Some(code),
        "{name} {args:?}: {}",
        describe(&output)
    );
}

/// The files the tests feed the tools, made once per run of the suite.
struct Files {
    _dir: tempfile::TempDir,
    /// The default scenario, 3 s.
    good: PathBuf,
    /// A byte copy of `good`.
    copy: PathBuf,
    /// The same run with another seed.
    other: PathBuf,
    /// `good` with 64 bytes in the middle inverted.
    corrupt: PathBuf,
    /// The first half of `good` (no summary, no footer, inside its only chunk).
    cut: PathBuf,
    /// The first 200 bytes: what a run killed before its first flush leaves.
    empty_partial: PathBuf,
    /// The default scenario without sensors.
    no_sensors: PathBuf,
    /// The ambient example (block layout, previews, sensors on DAQ node clocks), 3 s.
    clocked: PathBuf,
}

fn simulate(dir: &Path, name: &str, extra: &[&str], scenario: Option<&Path>) -> PathBuf {
    let out = dir.join(name);
    let mut command = Command::new(BIN);
    command.arg("simulate");
    if let Some(path) = scenario {
        command.arg(path);
    }
    let output = command
        .args(["--duration-s", "3", "--out"])
        .arg(&out)
        .args(extra)
        .output()
        .expect("bridgetwin runs");
    assert!(output.status.success(), "{}", describe(&output));
    out
}

fn files() -> &'static Files {
    static FILES: OnceLock<Files> = OnceLock::new();
    FILES.get_or_init(|| {
        let dir = tempfile::tempdir().expect("temporary folder");
        let d = dir.path();
        let good = simulate(d, "good.mcap", &[], None);
        let other = simulate(d, "other.mcap", &["--seed", "7"], None);
        let bytes = std::fs::read(&good).expect("good run");
        let copy = d.join("copy.mcap");
        std::fs::write(&copy, &bytes).unwrap();
        let mut flipped = bytes.clone();
        let middle = bytes.len() / 2;
        for b in &mut flipped[middle..middle + 64] {
            *b = !*b;
        }
        let corrupt = d.join("corrupt.mcap");
        std::fs::write(&corrupt, &flipped).unwrap();
        let cut = d.join("cut.mcap.partial");
        std::fs::write(&cut, &bytes[..middle]).unwrap();
        let empty_partial = d.join("empty.mcap.partial");
        std::fs::write(&empty_partial, &bytes[..200]).unwrap();
        let mut table: toml::Table =
            toml::from_str(bridgetwin::scenario::DEFAULT_SCENARIO_TOML).expect("default parses");
        table.remove("sensors");
        let scenario = d.join("no_sensors.toml");
        std::fs::write(&scenario, toml::to_string(&table).unwrap()).unwrap();
        let no_sensors = simulate(d, "no_sensors.mcap", &[], Some(&scenario));
        let ambient =
            Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/ambient_monitoring.toml");
        let clocked = simulate(d, "clocked.mcap", &[], Some(&ambient));
        Files {
            _dir: dir,
            good,
            copy,
            other,
            corrupt,
            cut,
            empty_partial,
            no_sensors,
            clocked,
        }
    })
}

#[test]
fn check_mcap_passes_a_good_file_and_fails_damaged_ones_and_one_without_sensors() {
    let Some(py) = python("check_mcap") else {
        return;
    };
    let f = files();
    expect_exit(&py, "check_mcap.py", &[&f.good], 0);
    // Node-clock stamps on the measured and the preview topics, true time on the truth.
    expect_exit(&py, "check_mcap.py", &[&f.clocked], 0);
    for bad in [&f.corrupt, &f.cut, &f.empty_partial, &f.no_sensors] {
        expect_exit(&py, "check_mcap.py", &[bad], 1);
    }
}

#[test]
fn read_run_reads_a_good_file_and_says_when_a_file_is_damaged_or_empty() {
    let Some(py) = python("read_run") else {
        return;
    };
    let f = files();
    let topic = Path::new("/sensors/accel/A4");
    expect_exit(&py, "read_run.py", &[&f.good], 0);
    expect_exit(&py, "read_run.py", &[&f.good, topic], 0);
    // Nothing read, or nothing measured: 1 (a 3 s run is one chunk, so its first half
    // holds no intact message). Damaged with an intact part: 3, or 1 (flipped bytes).
    expect_exit(&py, "read_run.py", &[&f.cut, topic], 1);
    expect_exit(&py, "read_run.py", &[&f.cut], 1);
    expect_exit(&py, "read_run.py", &[&f.empty_partial], 1);
    expect_exit(&py, "read_run.py", &[&f.empty_partial, topic], 1);
    expect_exit(&py, "read_run.py", &[&f.no_sensors], 1);
    expect_exit(&py, "read_run.py", &[&f.no_sensors, topic], 1);
    let corrupt = tool(&py, "read_run.py", &[&f.corrupt]);
    assert!(
        matches!(corrupt.status.code(), Some(1) | Some(3)),
        "{}",
        describe(&corrupt)
    );
}

#[test]
fn compare_runs_finds_equal_runs_equal_and_every_other_pair_different() {
    let Some(py) = python("compare_runs") else {
        return;
    };
    let f = files();
    expect_exit(&py, "compare_runs.py", &[&f.good, &f.copy], 0);
    expect_exit(&py, "compare_runs.py", &[&f.good, &f.other], 1);
    expect_exit(&py, "compare_runs.py", &[&f.good, &f.corrupt], 1);
    expect_exit(&py, "compare_runs.py", &[&f.good, &f.cut], 1);
    expect_exit(&py, "compare_runs.py", &[&f.no_sensors, &f.no_sensors], 1);
    expect_exit(
        &py,
        "compare_runs.py",
        &[&f.empty_partial, &f.empty_partial],
        1,
    );
}

#[test]
fn oma_check_refuses_files_it_cannot_identify_from() {
    // The identification itself is checked in .ci/run on the ambient example (minutes of
    // data); here the inputs on which it must stop before scoring anything.
    let Some(py) = python("oma_check") else {
        return;
    };
    let f = files();
    for bad in [&f.corrupt, &f.empty_partial, &f.no_sensors] {
        expect_exit(&py, "oma_check.py", &[bad], 2);
    }
}

#[test]
fn oma_check_picks_its_poles_without_the_truth() {
    // The pole picking must not read /truth/bridge: the source of `identify` names no
    // truth, and `main` reads the truth only after `identify` has returned.
    let source =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/tools/oma_check.py"))
            .expect("oma_check.py");
    let body = source
        .split("\ndef identify(")
        .nth(1)
        .and_then(|rest| rest.split("\ndef ").next())
        .expect("identify()");
    for word in [
        "truth_modes",
        "TRUTH_BRIDGE",
        "/truth/",
        "natural_frequency",
    ] {
        assert!(!body.contains(word), "identify() uses `{word}`");
    }
    let main = source.split("\ndef main(").nth(1).expect("main()");
    let identified = main.find("identify(").expect("main calls identify");
    let truth = main.find("truth_modes(").expect("main reads the truth");
    assert!(
        identified < truth,
        "main reads the truth before the identification"
    );
}
