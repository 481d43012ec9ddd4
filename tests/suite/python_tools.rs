//! The Python tools (`tools/check_mcap.py`, `read_run.py`, `compare_runs.py`,
//! `oma_check.py`) must fail on what is wrong: a corrupt file, a cut file, a killed run
//! that kept no message, a file without sensor topics, two runs that differ. Each is fed
//! here, beside a good file that must pass, so that a tool that passes everything fails
//! this test.
//!
//! Every tool (those, `bwim_check.py`, `driveby_check.py`, `frequency_tracking.py`,
//! `plot_run.py`, and the studies `bwim_study.py` and `driveby_study.py`, whose input is
//! the bridgetwin binary) is also fed an empty file, a truncated one, the wrong file (not
//! an MCAP file, or the run of another example than the one the tool is made for) and a
//! missing one: each must exit 2 with one line on stderr that names the file and says
//! what is wrong with it, and no traceback (`tools/bad_input.py`). A crash exits 1 in
//! Python, the status of a check that failed: this is what keeps the two apart.
//!
//! They need a Python with the `mcap` packages (`tools/requirements.txt`; `plot_run.py`
//! also the bridgetwin package), named by `BRIDGETWIN_PYTHON` (`.ci/run` sets it to its
//! venv). Without it every test here fails in CI (`CI` or `BRIDGETWIN_REQUIRE_PYTHON`
//! set), and elsewhere says `SKIPPED` on stderr, uncaptured, and does nothing else.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::OnceLock;

use crate::common::{skip, BIN};

/// Whether a missing Python fails the tests instead of skipping them: in CI (`CI` set,
/// as CI runners set it) or when `BRIDGETWIN_REQUIRE_PYTHON` is set (`.ci/run` sets it).
fn python_required() -> bool {
    ["CI", "BRIDGETWIN_REQUIRE_PYTHON"]
        .iter()
        .any(|v| std::env::var_os(v).is_some_and(|x| !x.is_empty() && x != "0" && x != "false"))
}

/// The Python named by `BRIDGETWIN_PYTHON`, or `None` after a loud skip of `test`;
/// panics instead of skipping when the Python is required (`python_required`).
fn python(test: &str) -> Option<PathBuf> {
    match std::env::var_os("BRIDGETWIN_PYTHON") {
        Some(python) => Some(PathBuf::from(python)),
        None if python_required() => panic!(
            "python_tools::{test}: BRIDGETWIN_PYTHON is not set (a Python with tools/requirements.txt), \
             and CI or BRIDGETWIN_REQUIRE_PYTHON is: the Python tools must be tested here"
        ),
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
        .env("MPLBACKEND", "Agg")
        // The one-line report of a tool's own failure, not the traceback it can print.
        .env_remove("BRIDGETWIN_TOOLS_TRACEBACK")
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
    /// A file of 0 bytes.
    empty: PathBuf,
    /// A path where there is no file.
    missing: PathBuf,
    /// A scenario's TOML text under an `.mcap` name.
    not_mcap: PathBuf,
    /// The first 3 s of the examples some tools are made for (`bwim_calibration`,
    /// `drive_by`, `frequency_tracking`): enough to get past the checks on the file.
    examples: Vec<(&'static str, PathBuf)>,
    /// Wrong bridgetwin binaries for the studies: empty, cut, not a program (a run's
    /// file marked executable); all executable.
    empty_bin: PathBuf,
    cut_bin: PathBuf,
    data_bin: PathBuf,
}

impl Files {
    fn example(&self, name: &str) -> &Path {
        &self
            .examples
            .iter()
            .find(|(n, _)| *n == name)
            .expect("example run")
            .1
    }
}

/// Writes `bytes` to `path`, executable.
#[cfg(unix)]
fn write_executable(path: &Path, bytes: &[u8]) {
    use std::os::unix::fs::PermissionsExt;
    std::fs::write(path, bytes).unwrap();
    std::fs::set_permissions(path, std::fs::Permissions::from_mode(0o755)).unwrap();
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
        let empty = d.join("empty.mcap");
        std::fs::write(&empty, b"").unwrap();
        let missing = d.join("missing.mcap");
        let not_mcap = d.join("scenario.mcap");
        std::fs::write(&not_mcap, bridgetwin::scenario::DEFAULT_SCENARIO_TOML).unwrap();
        let examples = ["bwim_calibration", "drive_by", "frequency_tracking"]
            .into_iter()
            .map(|name| {
                let scenario =
                    Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("examples/{name}.toml"));
                (
                    name,
                    simulate(d, &format!("{name}.mcap"), &[], Some(&scenario)),
                )
            })
            .collect();
        let binary = std::fs::read(BIN).expect("the bridgetwin binary");
        let (empty_bin, cut_bin, data_bin) =
            (d.join("empty_bin"), d.join("cut_bin"), d.join("data_bin"));
        write_executable(&empty_bin, b"");
        // Its first 64 KiB: the ELF header is whole, the code it maps is not.
        write_executable(&cut_bin, &binary[..65536]);
        write_executable(&data_bin, &bytes);
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
            empty,
            missing,
            not_mcap,
            examples,
            empty_bin,
            cut_bin,
            data_bin,
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
    // Read, and found wrong: 1.
    for bad in [&f.corrupt, &f.no_sensors] {
        expect_exit(&py, "check_mcap.py", &[bad], 1);
    }
    // Cut short (no footer): nothing to check, 2 (one line, checked below).
    for bad in [&f.cut, &f.empty_partial] {
        expect_exit(&py, "check_mcap.py", &[bad], 2);
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
    // Nothing intact to read: 2 (a 3 s run is one chunk, so its first half holds no
    // intact message). Nothing measured: 1. Damaged with an intact part: 3, or 2 when
    // the flipped bytes come before the first intact message.
    expect_exit(&py, "read_run.py", &[&f.cut, topic], 2);
    expect_exit(&py, "read_run.py", &[&f.cut], 2);
    expect_exit(&py, "read_run.py", &[&f.empty_partial], 2);
    expect_exit(&py, "read_run.py", &[&f.empty_partial, topic], 2);
    expect_exit(&py, "read_run.py", &[&f.no_sensors], 1);
    expect_exit(&py, "read_run.py", &[&f.no_sensors, topic], 1);
    let corrupt = tool(&py, "read_run.py", &[&f.corrupt]);
    assert!(
        matches!(corrupt.status.code(), Some(2) | Some(3)),
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
    expect_exit(&py, "compare_runs.py", &[&f.good, &f.cut], 2);
    expect_exit(&py, "compare_runs.py", &[&f.no_sensors, &f.no_sensors], 1);
    expect_exit(
        &py,
        "compare_runs.py",
        &[&f.empty_partial, &f.empty_partial],
        2,
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

/// One run of a tool on an input it must refuse: `args`, the file the line must name and
/// the words it must say.
struct Refusal<'a> {
    tool: &'a str,
    args: Vec<&'a Path>,
    file: &'a Path,
    says: &'a str,
}

impl<'a> Refusal<'a> {
    fn new(tool: &'a str, args: &[&'a Path], file: &'a Path, says: &'a str) -> Self {
        Refusal {
            tool,
            args: args.to_vec(),
            file,
            says,
        }
    }
}

/// Runs every refusal (at once: each is a Python start-up, a fraction of a second of
/// imports) and asserts of each: exit 2, exactly one line on stderr, which names the file
/// and says `says`, and no traceback. All failures are reported together.
fn expect_refusals(python: &Path, refusals: &[Refusal]) {
    let outputs: Vec<Output> = std::thread::scope(|scope| {
        let running: Vec<_> = refusals
            .iter()
            .map(|r| scope.spawn(move || tool(python, r.tool, &r.args)))
            .collect();
        running.into_iter().map(|h| h.join().unwrap()).collect()
    });
    let mut wrong = Vec::new();
    for (r, output) in refusals.iter().zip(&outputs) {
        let stderr = String::from_utf8_lossy(&output.stderr);
        let lines: Vec<&str> = stderr.lines().filter(|l| !l.trim().is_empty()).collect();
        let file = r.file.display().to_string();
        let ok = output.status.code() == Some(2)
            && lines.len() == 1
            && lines[0].contains(&file)
            && lines[0].contains(r.says)
            && !stderr.contains("Traceback");
        if !ok {
            wrong.push(format!(
                "{} {:?}: expected exit 2 and one line naming {file} that says {:?}; {}",
                r.tool,
                r.args,
                r.says,
                describe(output)
            ));
        }
    }
    assert!(
        wrong.is_empty(),
        "{} of {} refusals wrong:\n{}",
        wrong.len(),
        refusals.len(),
        wrong.join("\n")
    );
}

/// The four files every tool reading a run must refuse, with what its line must say.
fn bad_files(f: &Files) -> [(&Path, &'static str); 4] {
    [
        (&f.empty, "empty (0 bytes)"),
        (&f.cut, "truncated"),
        (&f.missing, "no such file"),
        (&f.not_mcap, "not an MCAP file"),
    ]
}

#[test]
fn the_file_checkers_refuse_empty_truncated_wrong_and_missing_files_in_one_line() {
    let Some(py) = python("the_file_checkers_refuse") else {
        return;
    };
    let f = files();
    let mut refusals = Vec::new();
    for (bad, says) in bad_files(f) {
        for name in ["check_mcap.py", "read_run.py", "oma_check.py"] {
            refusals.push(Refusal::new(name, &[bad], bad, says));
        }
        // Either file of the pair.
        refusals.push(Refusal::new("compare_runs.py", &[&f.good, bad], bad, says));
        refusals.push(Refusal::new("compare_runs.py", &[bad, &f.good], bad, says));
    }
    // The wrong run for the modal analysis: no accelerometer, or one only (drive_by's
    // bridge has a single one at midspan).
    let hint = "is it the ambient_monitoring example?";
    refusals.push(Refusal::new(
        "oma_check.py",
        &[&f.no_sensors],
        &f.no_sensors,
        hint,
    ));
    let drive_by = f.example("drive_by");
    refusals.push(Refusal::new("oma_check.py", &[drive_by], drive_by, hint));
    // A record too short for the analysis (3 s, 301 samples), said before pyoma2 fails
    // on it (it raised LinAlgError or ValueError, exit 1 as a failed check would).
    refusals.push(Refusal::new(
        "oma_check.py",
        &[&f.good],
        &f.good,
        "too short",
    ));
    expect_refusals(&py, &refusals);
}

#[test]
fn the_method_checks_refuse_empty_truncated_missing_files_and_other_examples_runs() {
    let Some(py) = python("the_method_checks_refuse") else {
        return;
    };
    let f = files();
    let tools = [
        ("bwim_check.py", "bwim_calibration"),
        ("driveby_check.py", "drive_by"),
        ("frequency_tracking.py", "frequency_tracking"),
    ];
    let hints: Vec<String> = tools
        .iter()
        .map(|(_, example)| format!("is it the {example} example?"))
        .collect();
    let mut refusals = Vec::new();
    for ((name, _), hint) in tools.iter().zip(&hints) {
        for (bad, says) in bad_files(f) {
            refusals.push(Refusal::new(name, &[bad], bad, says));
        }
        // The default scenario's run: a strain gauge at midspan only, no vehicle
        // instrument, no thermometer.
        refusals.push(Refusal::new(name, &[&f.good], &f.good, hint));
    }
    // B-WIM with a missing or unreadable calibration file: the file is named.
    let bwim = f.example("bwim_calibration");
    let option = Path::new("--calibration-from");
    refusals.push(Refusal::new(
        "bwim_check.py",
        &[bwim, option, &f.missing],
        &f.missing,
        "no such calibration file",
    ));
    refusals.push(Refusal::new(
        "bwim_check.py",
        &[bwim, option, &f.not_mcap],
        &f.not_mcap,
        "not a calibration file",
    ));
    expect_refusals(&py, &refusals);
    // Each tool's own example gets past those checks: 3 s of it hold no vehicle crossing,
    // no training period, so it is refused too, but for what its data lack, not as the
    // wrong example (a check that refused every file would pass the loop above).
    for ((name, example), hint) in tools.iter().zip(&hints) {
        let output = tool(&py, name, &[f.example(example)]);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(
            output.status.code() == Some(2)
                && stderr.lines().count() == 1
                && !stderr.contains(hint.as_str())
                && !stderr.contains("Traceback"),
            "{name} on 3 s of its own example: {}",
            describe(&output)
        );
    }
}

#[test]
fn plot_run_refuses_empty_truncated_wrong_and_missing_files_in_one_line() {
    let Some(py) = python("plot_run") else {
        return;
    };
    // plot_run.py is the package's overview: it needs the package in that Python (CI
    // installs it before the suite).
    let has_package = Command::new(&py)
        .args(["-c", "import bridgetwin"])
        .output()
        .is_ok_and(|o| o.status.success());
    if !has_package {
        assert!(
            !python_required(),
            "the bridgetwin package is not installed in {} (pip install ./python)",
            py.display()
        );
        skip(
            "python_tools::plot_run",
            "the bridgetwin package is not installed in BRIDGETWIN_PYTHON",
        );
        return;
    }
    let f = files();
    let mut refusals = Vec::new();
    for (bad, says) in bad_files(f) {
        refusals.push(Refusal::new("plot_run.py", &[bad], bad, says));
    }
    refusals.push(Refusal::new(
        "plot_run.py",
        &[&f.no_sensors],
        &f.no_sensors,
        "nothing to draw",
    ));
    expect_refusals(&py, &refusals);
}

#[test]
fn the_studies_refuse_a_missing_empty_cut_or_wrong_binary_in_one_line() {
    let Some(py) = python("the_studies_refuse") else {
        return;
    };
    let f = files();
    let out = tempfile::tempdir().expect("temporary folder");
    let bins: [(&Path, &str); 4] = [
        (&f.missing, "no such bridgetwin binary"),
        (&f.empty_bin, "empty (0 bytes)"),
        (&f.cut_bin, "truncated copy"),
        (&f.data_bin, "not a program"),
    ];
    let out_flag = Path::new("--out");
    let mut refusals = Vec::new();
    for (bin, says) in bins {
        refusals.push(Refusal::new(
            "bwim_study.py",
            &[Path::new("--bin"), bin, out_flag, out.path()],
            bin,
            says,
        ));
        refusals.push(Refusal::new(
            "driveby_study.py",
            &[Path::new("--bt"), bin, out_flag, out.path()],
            bin,
            says,
        ));
    }
    expect_refusals(&py, &refusals);
    // The same check takes the real binary (so the refusals are not of everything).
    let taken = Command::new(&py)
        .arg("-c")
        .arg("import sys; sys.path.insert(0, sys.argv[1]); import bad_input; print(bad_input.check_binary(sys.argv[2]))")
        .arg(Path::new(env!("CARGO_MANIFEST_DIR")).join("tools"))
        .arg(BIN)
        .output()
        .expect("python runs");
    assert!(taken.status.success(), "{}", describe(&taken));
}
