//! The bad-input catalogue: every case runs the `bridgetwin` binary in a fresh temporary
//! folder on one bad scenario, argument or output path, and checks that
//!
//! - the exit code is 1 (error) or 2 (usage), the one the case expects, without a panic;
//! - stderr names the field path (`bridge.span_m`, `sensors.2.rate_hz`) or the file, and
//!   the offending value (the case's expected substrings, e.g. `bridge.span_m = NaN`);
//! - nothing is left behind: no `X.mcap`, no `X.mcap.partial`, no new file or folder, and
//!   every input (an existing output file included) is unchanged.
//!
//! Scenarios are the default scenario (`bridgetwin scenario show`) with edits, either on the
//! text or on the parsed `toml::Table` by path (`sensors.2.rate_hz`). Cases that would
//! simulate if the input were (wrongly) accepted are capped at 0.5 s of simulated time.
//! A failing case prints its name, the command and the full stderr; `BAD_INPUT_SHOW=1`
//! prints every case's stderr.

use std::collections::BTreeMap;
use std::io::Read;
use std::os::unix::fs::{FileTypeExt, PermissionsExt};
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use bridgetwin::scenario::DEFAULT_SCENARIO_TOML;

#[path = "support/schema.rs"]
mod schema;

#[path = "support/bad_input_schema.rs"]
mod bad_input_schema;

const BIN: &str = env!("CARGO_BIN_EXE_bridgetwin");

/// A run that has not exited by then has been accepted and is simulating: a failure.
const TIMEOUT: Duration = Duration::from_secs(20);

/// One edit of the default scenario.
enum Edit {
    /// Sets a value by path (`sensors.2.rate_hz`; an index one past the end appends),
    /// given as a TOML literal (`nan`, `"A/2"`, `[1.0, 2.0]`, `{ kind = "smooth" }`).
    Set(&'static str, &'static str),
    /// Removes the key or array element at a path.
    Remove(&'static str),
    /// Replaces the first occurrence of a text (which must occur) in the scenario text.
    Text(&'static str, &'static str),
}
use Edit::{Remove, Set, Text};

/// A folder the case creates before the run.
struct Folder {
    name: &'static str,
    mode: u32,
}

struct Case {
    name: String,
    /// Written to `scenario.toml` when given.
    scenario: Option<Vec<u8>>,
    /// Other input files (a road CSV, an existing output).
    files: Vec<(&'static str, Vec<u8>)>,
    folders: Vec<Folder>,
    /// Arguments after the binary.
    args: Vec<String>,
    /// Expected exit code and substrings of stderr.
    exit: i32,
    expect: Vec<String>,
    /// Another acceptable outcome (exit code, substrings), for behaviour that is being
    /// changed elsewhere (documented at the case).
    or_else: Option<(i32, Vec<String>)>,
    /// The output path given to `--out` (relative to the folder, or absolute).
    out: String,
    /// Skip unless a probe file cannot be created in this folder (root writes anywhere).
    needs_unwritable: Option<&'static str>,
}

fn edited(edits: &[Edit]) -> String {
    let mut text = DEFAULT_SCENARIO_TOML.to_string();
    for edit in edits {
        match *edit {
            Text(from, to) => {
                assert!(
                    text.contains(from),
                    "text edit: `{from}` not in the scenario"
                );
                text = text.replacen(from, to, 1);
            }
            Set(path, literal) => {
                let mut table: toml::Table = toml::from_str(&text).expect("scenario parses");
                let mut holder: toml::Table =
                    toml::from_str(&format!("v = {literal}")).expect("literal parses");
                let value = holder.remove("v").expect("literal value");
                set_path(&mut table, path, Some(value));
                text = toml::to_string(&table).expect("serializes");
            }
            Remove(path) => {
                let mut table: toml::Table = toml::from_str(&text).expect("scenario parses");
                set_path(&mut table, path, None);
                text = toml::to_string(&table).expect("serializes");
            }
        }
    }
    text
}

/// Sets (or with `None` removes) the value at a dotted path; numeric segments index arrays.
fn set_path(table: &mut toml::Table, path: &str, value: Option<toml::Value>) {
    let segments: Vec<&str> = path.split('.').collect();
    let (last, parents) = segments.split_last().expect("non-empty path");
    let mut node = toml::Value::Table(std::mem::take(table));
    {
        let mut cursor = &mut node;
        for seg in parents {
            cursor = match cursor {
                toml::Value::Table(t) => t
                    .entry(seg.to_string())
                    .or_insert_with(|| toml::Value::Table(toml::Table::new())),
                toml::Value::Array(a) => {
                    let i: usize = seg.parse().expect("array index");
                    &mut a[i]
                }
                _ => panic!("{path}: `{seg}` is not inside a table or array"),
            };
        }
        match (cursor, value) {
            (toml::Value::Table(t), Some(v)) => {
                t.insert(last.to_string(), v);
            }
            (toml::Value::Table(t), None) => {
                assert!(t.remove(*last).is_some(), "{path}: nothing to remove");
            }
            (toml::Value::Array(a), v) => {
                let i: usize = last.parse().expect("array index");
                match v {
                    Some(v) if i == a.len() => a.push(v),
                    Some(v) => a[i] = v,
                    None => {
                        a.remove(i);
                    }
                }
            }
            _ => panic!("{path}: parent is not a table or array"),
        }
    }
    if let toml::Value::Table(t) = node {
        *table = t;
    }
}

fn strings(items: &[&str]) -> Vec<String> {
    items.iter().map(|s| s.to_string()).collect()
}

/// `simulate scenario.toml --out OUT --duration-s 0.5`.
fn sim_args(out: &str) -> Vec<String> {
    strings(&[
        "simulate",
        "scenario.toml",
        "--out",
        out,
        "--duration-s",
        "0.5",
    ])
}

impl Case {
    /// The default scenario with `edits`, simulated (capped at 0.5 s); exit code 1.
    fn edit(name: &str, edits: &[Edit], expect: &[&str]) -> Case {
        Case::raw(name, edited(edits).into_bytes(), expect)
    }

    /// A scenario file with these bytes.
    fn raw(name: &str, scenario: Vec<u8>, expect: &[&str]) -> Case {
        Case {
            name: name.to_string(),
            scenario: Some(scenario),
            files: Vec::new(),
            folders: Vec::new(),
            args: sim_args("run.mcap"),
            exit: 1,
            expect: strings(expect),
            or_else: None,
            out: "run.mcap".into(),
            needs_unwritable: None,
        }
    }

    /// No scenario file (the embedded default) and these arguments.
    fn args(name: &str, args: &[&str], exit: i32, expect: &[&str]) -> Case {
        let out = args
            .iter()
            .position(|a| *a == "--out")
            .and_then(|i| args.get(i + 1))
            .unwrap_or(&"run.mcap")
            .to_string();
        Case {
            name: name.to_string(),
            scenario: None,
            files: Vec::new(),
            folders: Vec::new(),
            args: args.iter().map(|s| s.to_string()).collect(),
            exit,
            expect: strings(expect),
            or_else: None,
            out,
            needs_unwritable: None,
        }
    }

    /// Without `--duration-s 0.5`, for cases about the scenario's own duration.
    fn full_duration(mut self) -> Case {
        self.args.truncate(self.args.len() - 2);
        self
    }

    fn with_args(mut self, args: &[&str]) -> Case {
        self.args = args.iter().map(|s| s.to_string()).collect();
        self
    }

    /// Writes to `out` instead of `run.mcap`.
    fn writing_to(mut self, out: &str) -> Case {
        let i = self.args.iter().position(|a| a == "--out").expect("--out");
        self.args[i + 1] = out.to_string();
        self.out = out.to_string();
        self
    }

    /// Another acceptable outcome.
    fn or_else(mut self, exit: i32, expect: &[&str]) -> Case {
        self.or_else = Some((exit, strings(expect)));
        self
    }

    /// Skipped when `folder` turns out to be writable.
    fn needs_unwritable(mut self, folder: &'static str) -> Case {
        self.needs_unwritable = Some(folder);
        self
    }

    fn file(mut self, name: &'static str, content: &[u8]) -> Case {
        self.files.push((name, content.to_vec()));
        self
    }

    fn folder(mut self, name: &'static str, mode: u32) -> Case {
        self.folders.push(Folder { name, mode });
        self
    }
}

/// Every file and folder under `dir`, relative, with file contents.
fn snapshot(dir: &Path) -> BTreeMap<String, Option<Vec<u8>>> {
    fn walk(root: &Path, dir: &Path, out: &mut BTreeMap<String, Option<Vec<u8>>>) {
        for entry in std::fs::read_dir(dir).expect("read_dir").flatten() {
            let path = entry.path();
            let rel = path.strip_prefix(root).unwrap().display().to_string();
            if path.is_dir() {
                out.insert(format!("{rel}/"), None);
                walk(root, &path, out);
            } else {
                out.insert(rel, std::fs::read(&path).ok());
            }
        }
    }
    let mut out = BTreeMap::new();
    walk(dir, dir, &mut out);
    out
}

enum Outcome {
    Pass,
    Skipped(String),
}

fn run_case(case: &Case) -> Result<Outcome, String> {
    let tmp = tempfile::tempdir().map_err(|e| format!("tempdir: {e}"))?;
    let dir = tmp.path();
    if let Some(bytes) = &case.scenario {
        std::fs::write(dir.join("scenario.toml"), bytes).unwrap();
    }
    for (name, bytes) in &case.files {
        std::fs::write(dir.join(name), bytes).unwrap();
    }
    for f in &case.folders {
        let path = dir.join(f.name);
        std::fs::create_dir(&path).unwrap();
        std::fs::set_permissions(&path, std::fs::Permissions::from_mode(f.mode)).unwrap();
    }
    if let Some(name) = case.needs_unwritable {
        let probe = dir.join(name).join("probe");
        if std::fs::write(&probe, b"x").is_ok() {
            let _ = std::fs::remove_file(&probe);
            return Ok(Outcome::Skipped(format!(
                "{name}/ is writable anyway (running as root)"
            )));
        }
    }
    let before = snapshot(dir);

    let mut child = Command::new(BIN)
        .args(&case.args)
        .current_dir(dir)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| format!("cannot start {BIN}: {e}"))?;
    let mut pipe = child.stderr.take().expect("piped stderr");
    let reader = std::thread::spawn(move || {
        let mut text = String::new();
        let _ = pipe.read_to_string(&mut text);
        text
    });
    let started = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().map_err(|e| e.to_string())? {
            break Some(status);
        }
        if started.elapsed() > TIMEOUT {
            let _ = child.kill();
            let _ = child.wait();
            break None;
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    let stderr = reader.join().unwrap_or_default();
    // The folder must be writable again for the checks and the clean-up.
    for f in &case.folders {
        let _ = std::fs::set_permissions(dir.join(f.name), std::fs::Permissions::from_mode(0o755));
    }
    let fail = |what: String| {
        Err(format!(
            "{what}\n  command: bridgetwin {}\n  --- stderr ---\n{stderr}  --------------",
            case.args.join(" ")
        ))
    };
    let Some(status) = status else {
        return fail(format!(
            "still running after {TIMEOUT:?}: the input was accepted"
        ));
    };
    let code = status.code();
    if std::env::var_os("BAD_INPUT_SHOW").is_some() {
        eprintln!("[{}] exit {code:?}: {}", case.name, stderr.trim_end());
    }

    let matches = |exit: i32, expect: &[String]| {
        code == Some(exit) && expect.iter().all(|e| stderr.contains(e))
    };
    if !matches!(code, Some(1) | Some(2)) {
        return fail(format!("exit code {code:?}, expected 1 or 2"));
    }
    let primary = matches(case.exit, &case.expect);
    let alternative = case
        .or_else
        .as_ref()
        .is_some_and(|(exit, expect)| matches(*exit, expect));
    if !primary && !alternative {
        let missing: Vec<&String> = case
            .expect
            .iter()
            .filter(|e| !stderr.contains(e.as_str()))
            .collect();
        return fail(format!(
            "exit code {code:?} (expected {}), missing in stderr: {missing:?}",
            case.exit
        ));
    }
    if stderr.contains("panicked") || !stderr.contains("error") {
        return fail("stderr is not an error message (or a panic)".into());
    }

    let after = snapshot(dir);
    if after != before {
        let added: Vec<&String> = after.keys().filter(|k| !before.contains_key(*k)).collect();
        let removed: Vec<&String> = before.keys().filter(|k| !after.contains_key(*k)).collect();
        let changed: Vec<&String> = before
            .keys()
            .filter(|k| after.get(*k).is_some_and(|v| v != &before[*k]))
            .collect();
        return fail(format!(
            "the folder changed: added {added:?}, removed {removed:?}, changed {changed:?}"
        ));
    }
    let out = if Path::new(&case.out).is_absolute() {
        Path::new(&case.out).to_path_buf()
    } else {
        dir.join(&case.out)
    };
    let partial = format!("{}.partial", out.display());
    if Path::new(&partial).exists() {
        return fail(format!("{partial} was left behind"));
    }
    if out.is_file() && !before.contains_key(&case.out) {
        return fail(format!("{} was written", out.display()));
    }
    Ok(Outcome::Pass)
}

/// Runs every case and fails with the report of all failing cases.
fn run_all(class: &str, cases: &[Case]) {
    let mut failures = Vec::new();
    let mut skipped = Vec::new();
    for case in cases {
        match run_case(case) {
            Ok(Outcome::Pass) => {}
            Ok(Outcome::Skipped(why)) => skipped.push(format!("{}: {why}", case.name)),
            Err(report) => failures.push(format!("case `{}`: {report}", case.name)),
        }
    }
    eprintln!(
        "{class}: {} cases, {} failed, {} skipped {skipped:?}",
        cases.len(),
        failures.len(),
        skipped.len()
    );
    assert!(
        failures.is_empty(),
        "{} of {} {class} cases failed:\n\n{}",
        failures.len(),
        cases.len(),
        failures.join("\n\n")
    );
}

fn syntax_cases() -> Vec<Case> {
    let mut garbage: Vec<u8> = (0..=255u8).rev().collect();
    garbage.extend_from_slice(b"\xc3\x28[bridge]\n");
    vec![
        Case::edit(
            "malformed: two equals signs",
            &[Text("span_m = 30.0", "span_m = = 30.0")],
            &[
                "scenario.toml",
                "TOML parse error",
                "\n",
                "span_m = = 30.0",
                "^",
            ],
        ),
        Case::edit(
            "malformed: unclosed table header",
            &[Text("[solver]", "[solver\n")],
            &["scenario.toml", "TOML parse error", "[solver"],
        ),
        Case::edit(
            "malformed: unterminated string",
            &[Text("id = \"A1\"", "id = \"A1")],
            &["scenario.toml", "TOML parse error", "id = \"A1"],
        ),
        Case::edit(
            "unknown key at the top level",
            &[Text("seed = 42", "seed = 42\nseeed = 43")],
            &["scenario.toml: seeed: unknown field `seeed`"],
        ),
        Case::edit(
            "unknown key in [bridge]",
            &[Set("bridge.colour", "\"red\"")],
            &["scenario.toml: bridge.colour: unknown field `colour`"],
        ),
        Case::edit(
            "unknown key in a sensor",
            &[Set("sensors.3.gain", "2.0")],
            &["scenario.toml: sensors.3.gain: unknown field `gain`"],
        ),
        Case::edit(
            "unknown key in a vehicle model",
            &[Set("vehicles.0.model.wings", "2")],
            &["scenario.toml: vehicles.0.model.wings: unknown field `wings`"],
        ),
        Case::edit(
            "unknown key in the road profile",
            &[Set("road.profile.clas", "\"B\"")],
            &["scenario.toml: road.profile.clas: unknown field `clas`"],
        ),
        Case::edit(
            "unknown table",
            &[Text("[output]", "[outputs]")],
            &["scenario.toml: outputs: unknown field `outputs`"],
        ),
        Case::edit(
            "wrong type: string for a number",
            &[Set("bridge.span_m", "\"thirty\"")],
            &[
                "scenario.toml: bridge.span_m: invalid type: string \"thirty\", expected f64",
                "span_m = \"thirty\"",
                "^",
            ],
        ),
        Case::edit(
            "wrong type: integer for a string",
            &[Set("sensors.0.id", "7")],
            &[
                "scenario.toml: sensors.0.id: invalid type: integer `7`, expected a string",
                "id = 7",
            ],
        ),
        Case::edit(
            "wrong type: integer for the sensor list",
            &[Set("sensors", "5")],
            &[
                "scenario.toml: sensors: invalid type: integer `5`",
                "sensors = 5",
            ],
        ),
        Case::edit(
            "wrong type: negative seed",
            &[Set("seed", "-1")],
            &["scenario.toml: seed: ", "seed = -1", "expected u64"],
        ),
        Case::edit(
            "missing field: bridge.span_m",
            &[Remove("bridge.span_m")],
            &["scenario.toml: bridge: missing field `span_m`", "[bridge]"],
        ),
        Case::edit(
            "missing table: [bridge]",
            &[Remove("bridge")],
            &["scenario.toml", "missing field `bridge`"],
        ),
        Case::edit(
            "missing field: vehicles[0].speed_m_s",
            &[Remove("vehicles.0.speed_m_s")],
            &["scenario.toml: vehicles.0: missing field `speed_m_s`"],
        ),
        Case::edit(
            "unknown variant: sensor kind",
            &[Set("sensors.0.kind", "\"thermometer\"")],
            &["scenario.toml: sensors.0.kind: unknown variant `thermometer`"],
        ),
        Case::edit(
            "unknown variant: contact law",
            &[Set("solver.contact", "\"sticky\"")],
            &["scenario.toml: solver.contact: unknown variant `sticky`"],
        ),
        Case::raw("empty file", Vec::new(), &["scenario.toml", "is empty"]),
        Case::raw(
            "whitespace only",
            b"\n   \n\t\n".to_vec(),
            &["scenario.toml", "is empty"],
        ),
        // The CLI reads with read_to_string ("stream did not contain valid UTF-8");
        // Scenario::from_file also gives the offset of the first bad byte.
        Case::raw(
            "binary garbage (not UTF-8)",
            garbage,
            &["scenario.toml", "UTF-8"],
        ),
        Case::raw(
            "control characters (UTF-8, not TOML)",
            b"\x00\x01\x02\x7f{{}}=[[".to_vec(),
            &["scenario.toml", "TOML parse error"],
        ),
        Case::args(
            "scenario file does not exist",
            &["simulate", "missing.toml", "--out", "run.mcap"],
            1,
            &["missing.toml", "No such file or directory"],
        ),
        Case::args(
            "scenario path is a directory",
            &["simulate", "adir", "--out", "run.mcap"],
            1,
            &["adir", "directory"],
        )
        .folder("adir", 0o755),
        Case::edit(
            "start_time not RFC 3339",
            &[Set("start_time", "\"yesterday\"")],
            &["start_time = \"yesterday\"", "RFC 3339"],
        ),
        Case::edit(
            "start_time beyond 64-bit nanoseconds",
            &[Set("start_time", "\"9999-12-31T23:59:59Z\"")],
            &["start_time = \"9999-12-31T23:59:59Z\"", "2262"],
        ),
        Case::edit(
            "start_time before 1970",
            &[Set("start_time", "\"1969-07-20T20:17:00Z\"")],
            &["start_time = \"1969-07-20T20:17:00Z\"", "after 1970"],
        ),
    ]
}

const CSV_HEADER: &str = "x_m,elevation_m\n";

fn road_csv(rows: &str) -> Vec<u8> {
    format!("{CSV_HEADER}{rows}").into_bytes()
}

const CSV_ROAD: Edit = Set("road.profile", "{ kind = \"csv\", path = \"road.csv\" }");

fn physics_cases() -> Vec<Case> {
    let mut cases = Vec::new();
    // Zero, negative, NaN and infinite values of the physical parameters.
    let numbers = [
        ("0.0", "0", "zero"),
        ("-1.0", "-1", "negative"),
        ("nan", "NaN", "NaN"),
        ("inf", "inf", "infinite"),
    ];
    let fields = [
        "bridge.span_m",
        "bridge.flexural_rigidity_n_m2",
        "bridge.mass_per_length_kg_m",
        "solver.dt_s",
        "vehicles.0.speed_m_s",
        "duration_s",
    ];
    for path in fields {
        for (literal, shown, label) in numbers {
            let expect = format!("{path} = {shown} ");
            let case = Case::edit(
                &format!("{path} {label}"),
                &[Set(path, literal)],
                &[&expect],
            );
            cases.push(if path == "duration_s" {
                case.full_duration()
            } else {
                case
            });
        }
    }
    for (literal, shown) in [
        ("-0.1", "-0.1"),
        ("1.0", "1"),
        ("nan", "NaN"),
        ("inf", "inf"),
    ] {
        let expect = format!("bridge.damping_ratio = {shown} must be in [0, 1)");
        cases.push(Case::edit(
            &format!("bridge.damping_ratio = {literal}"),
            &[Set("bridge.damping_ratio", literal)],
            &[&expect],
        ));
    }
    cases.extend([
        Case::edit(
            "span absurdly small (f1 overflows)",
            &[Set("bridge.span_m", "1e-300")],
            &["bridge.span_m = 1e-300 gives a first natural frequency f1 = inf Hz"],
        ),
        Case::edit(
            "span absurdly large",
            &[Set("bridge.span_m", "1e300")],
            &["bridge.span_m = 1e300 must be at most 10000 m"],
        ),
        Case::edit(
            "EI off by 90 orders of magnitude",
            &[Set("bridge.flexural_rigidity_n_m2", "5.629e100")],
            &["bridge.flexural_rigidity_n_m2 = 5.629e100 gives a first natural frequency"],
        ),
        Case::edit(
            "mass per length absurdly small",
            &[Set("bridge.mass_per_length_kg_m", "1e-300")],
            &["bridge.mass_per_length_kg_m = 1e-300 gives a first natural frequency"],
        ),
        Case::edit(
            "dt above 0.1 s",
            &[Set("solver.dt_s", "0.5")],
            &["solver.dt_s = 0.5 must be a whole number of nanoseconds in (0, 0.1] s"],
        ),
        Case::edit(
            "dt not a whole number of nanoseconds",
            &[Set("solver.dt_s", "1.5e-10")],
            &["solver.dt_s = 0.00000000015 must be a whole number of nanoseconds"],
        ),
        Case::edit(
            "time step too coarse for the sensor rates",
            &[Set("solver.dt_s", "0.01")],
            &["sensors.0.rate_hz = 200 must not exceed the solver rate", "solver.dt_s = 0.01"],
        ),
        Case::edit(
            "speed above 100 m/s",
            &[Set("vehicles.0.speed_m_s", "150.0")],
            &["vehicles.0.speed_m_s = 150 must be at most 100 m/s"],
        ),
        Case::edit(
            "speed so low that the default duration exceeds 30 days",
            &[Set("vehicles.0.speed_m_s", "1e-5")],
            &["vehicles.0.speed_m_s = 0.00001 makes the default duration"],
        )
        .full_duration(),
        Case::edit(
            "duration above 30 days",
            &[Set("duration_s", "1e12")],
            &["duration_s = 1000000000000 must be at most 30 days"],
        )
        .full_duration(),
        Case::edit(
            "too many steps: dt = 10 us over 1e6 s",
            &[Set("solver.dt_s", "1e-5"), Set("duration_s", "1e6"), Remove("sensors")],
            &["duration_s = 1000000 with solver.dt_s = 0.00001 needs 100000000000 solver steps"],
        )
        .full_duration(),
        Case::edit(
            "too many steps: dt = 1 ns over the default duration",
            &[Set("solver.dt_s", "1e-9"), Remove("sensors")],
            &["solver.dt_s = 0.000000001 over the default duration", "solver steps"],
        )
        .full_duration(),
        Case::edit(
            "Newmark gamma below 0.5",
            &[Set("solver.newmark", "{ gamma = 0.3, beta = 0.25 }")],
            &["solver.newmark.gamma = 0.3"],
        ),
        Case::edit(
            "entry time negative",
            &[Set("vehicles.0.entry_time_s", "-1.0")],
            &["vehicles.0.entry_time_s = -1 "],
        ),
        Case::edit(
            "entry time beyond 30 days",
            &[Set("vehicles.0.entry_time_s", "1e300")],
            &["vehicles.0.entry_time_s = 1e300 must be at most 30 days"],
        ),
        // Sensors.
        Case::edit(
            "sensor beyond the span",
            &[Set("sensors.6.position_m", "31.0")],
            &["sensors.6.position_m = 31 must lie on the span [0, 30] m"],
        ),
        Case::edit(
            "sensor before the span",
            &[Set("sensors.0.position_m", "-0.5")],
            &["sensors.0.position_m = -0.5 must lie on the span"],
        ),
        Case::edit(
            "sensor position NaN",
            &[Set("sensors.2.position_m", "nan")],
            &["sensors.2.position_m = NaN must lie on the span"],
        ),
        Case::edit(
            "sensor rate above the solver rate",
            &[Set("sensors.2.rate_hz", "5000.0")],
            &["sensors.2.rate_hz = 5000 must not exceed the solver rate 1/dt = 1000 Hz"],
        ),
        Case::edit(
            "sensor rate zero",
            &[Set("sensors.1.rate_hz", "0.0")],
            &["sensors.1.rate_hz = 0 must be a finite number > 0"],
        ),
        Case::edit(
            "sensor rate NaN",
            &[Set("sensors.1.rate_hz", "nan")],
            &["sensors.1.rate_hz = NaN"],
        ),
        Case::edit(
            "sensor rate far below the solver rate (anti-alias kernel too long)",
            &[Set("sensors.3.rate_hz", "0.01")],
            &["sensors.3.rate_hz = 0.01 is too far below the solver rate 1000 Hz"],
        ),
        Case::edit(
            "duplicate sensor id",
            &[Set("sensors.1.id", "\"A1\"")],
            &["sensors.1.id = \"A1\" is used twice"],
        ),
        Case::edit(
            "sensor id with a slash",
            &[Set("sensors.4.id", "\"A/5\"")],
            &["sensors.4.id = \"A/5\" must be letters, digits, _ or -"],
        ),
        Case::edit(
            "sensor id with a space",
            &[Set("sensors.4.id", "\"A 5\"")],
            &["sensors.4.id = \"A 5\" must be letters"],
        ),
        Case::edit(
            "sensor id empty",
            &[Set("sensors.0.id", "\"\"")],
            &["sensors.0.id = \"\" must be letters"],
        ),
        Case::edit(
            "sensor id not ASCII",
            &[Set("sensors.0.id", "\"Ä1\"")],
            &["sensors.0.id = \"Ä1\" must be letters"],
        ),
        Case::edit(
            "sensor noise density negative",
            &[Set("sensors.5.noise_density", "-1e-6")],
            &["sensors.5.noise_density = -0.000001"],
        ),
        Case::edit(
            "sensor noise density overflowing",
            &[Set("sensors.5.noise_density", "1e308")],
            &["sensors.5.noise_density = 1e308 gives a per-sample noise sigma of inf"],
        ),
        Case::edit(
            "gauge depth on an accelerometer",
            &[Set("sensors.0.gauge_depth_m", "0.5")],
            &["sensors.0.gauge_depth_m = 0.5 applies to strain gauges only"],
        ),
        Case::edit(
            "gauge depth negative",
            &[Set("sensors.7.gauge_depth_m", "-0.8")],
            &["sensors.7.gauge_depth_m = -0.8 "],
        ),
        // WIM stations.
        Case::edit(
            "WIM station on the bridge",
            &[Set("wim_stations.0.position_m", "5.0")],
            &["wim_stations.0.position_m = 5 must lie on the approach, in (-100, 0) m"],
        ),
        Case::edit(
            "WIM station before the approach",
            &[Set("wim_stations.0.position_m", "-150.0")],
            &["wim_stations.0.position_m = -150 must lie on the approach"],
        ),
        Case::edit(
            "WIM stations with the same id",
            &[Set("wim_stations.1", "{ id = \"WIM1\", position_m = -50.0 }")],
            &["wim_stations.1.id = \"WIM1\" is used twice"],
        ),
        Case::edit(
            "WIM station id with a dot",
            &[Set("wim_stations.0.id", "\"WIM.1\"")],
            &["wim_stations.0.id = \"WIM.1\" must be letters"],
        ),
        // Vehicles.
        Case::edit(
            "unknown vehicle preset",
            &[Set("vehicles.0.model.preset", "\"three_axle_truck\"")],
            &["vehicles.0.model.preset = \"three_axle_truck\" is not a preset"],
        ),
        Case::edit(
            "preset override negative",
            &[Set("vehicles.0.model.body_mass_kg", "-100.0")],
            &["vehicles.0.model.body_mass_kg = -100 must be a finite number > 0"],
        ),
        Case::edit(
            "preset override pair with a negative entry",
            &[Set("vehicles.0.model.tyre_stiffness_n_m", "[3.0e6, -1.0]")],
            &["vehicles.0.model.tyre_stiffness_n_m.1 = -1 "],
        ),
        Case::edit(
            "centre of gravity outside the wheelbase",
            &[Set("vehicles.0.model.cg_behind_front_m", "9.0")],
            &["vehicles.0.model.cg_behind_front_m = 9 must lie between the axles"],
        ),
        Case::edit(
            "half car without preset and fields",
            &[Set("vehicles.0.model", "{ kind = \"half_car\", body_mass_kg = 1000.0 }")],
            &["vehicles.0.model.pitch_inertia_kg_m2 = (missing)"],
        ),
        Case::edit(
            "moving force: spacings do not match loads",
            &[Set(
                "vehicles.0.model",
                "{ kind = \"moving_force\", axle_loads_n = [1e5, 1e5], axle_spacing_m = [] }",
            )],
            &["vehicles.0.model.axle_spacing_m = [] must have 1 entries"],
        ),
        Case::edit(
            "moving force: negative load",
            &[Set(
                "vehicles.0.model",
                "{ kind = \"moving_force\", axle_loads_n = [-1e5] }",
            )],
            &["vehicles.0.model.axle_loads_n.0 = -100000 "],
        ),
        Case::edit(
            "two vehicles with the same id",
            &[Set(
                "vehicles.1",
                "{ id = 1, model = { kind = \"half_car\", preset = \"vbi2d_e01\" }, speed_m_s = 10.0 }",
            )],
            &["vehicles.1.id = 1 is used twice"],
        ),
        // Road.
        Case::edit(
            "approach shorter than the wheelbase",
            &[Set("road.approach_m", "3.0"), Set("wim_stations.0.position_m", "-1.0")],
            &["road.approach_m = 3 must be longer than vehicle 0's wheelbase 4.27 m"],
        ),
        Case::edit(
            "approach zero",
            &[Set("road.approach_m", "0.0")],
            &["road.approach_m = 0 "],
        ),
        Case::edit(
            "exit negative",
            &[Set("road.exit_m", "-1.0")],
            &["road.exit_m = -1 "],
        ),
        Case::edit(
            "approach beyond 100 km",
            &[Set("road.approach_m", "1e300")],
            &["road.approach_m = 1e300 must be at most 100000 m"],
        ),
        Case::edit(
            "unknown road class",
            &[Set("road.profile.class", "\"Z\"")],
            &["scenario.toml: road.profile.class: unknown variant `Z`"],
        ),
        Case::edit(
            "unknown road kind",
            &[Set("road.profile.kind", "\"gravel\"")],
            &["scenario.toml: road.profile.kind: unknown variant `gravel`"],
        ),
        Case::edit(
            "ISO 8608 without class or G_d",
            &[Set("road.profile", "{ kind = \"iso8608\" }")],
            &["road.profile.class = (missing)"],
        ),
        Case::edit(
            "ISO 8608 band inverted",
            &[Set("road.profile.n1_cycles_m", "5.0")],
            &["road.profile.n1_cycles_m = 5 must be less than n2_cycles_m = 4"],
        ),
        Case::edit(
            "ISO 8608 G_d beyond any road",
            &[Set("road.profile.gd_n0_m3", "1e300")],
            &["road.profile.gd_n0_m3 = 1e300 is beyond any road"],
        ),
        Case::edit("road CSV missing", &[CSV_ROAD], &["road.csv", "No such file or directory"]),
        Case::edit(
            "road CSV path empty",
            &[Set("road.profile", "{ kind = \"csv\", path = \"\" }")],
            &["road.profile.path = \"\" must name a CSV file"],
        ),
        Case::edit(
            "road CSV non-numeric elevation",
            &[CSV_ROAD],
            &["road.csv: line 3: elevation_m = `abc` is not a number"],
        )
        .file("road.csv", &road_csv("-200,0\n-100,abc\n200,0\n")),
        Case::edit(
            "road CSV NaN x",
            &[CSV_ROAD],
            &["road.csv: line 3: x_m = NaN is not finite"],
        )
        .file("road.csv", &road_csv("-200,0\nNaN,0\n200,0\n")),
        Case::edit(
            "road CSV x not increasing",
            &[CSV_ROAD],
            &["road.csv: line 4: x_m = -150 is not greater than the previous x_m = -100"],
        )
        .file("road.csv", &road_csv("-200,0\n-100,0\n-150,0\n200,0\n")),
        Case::edit(
            "road CSV row with a missing field",
            &[CSV_ROAD],
            &["road.csv: line 3: expected 2 fields as in the header, found 1"],
        )
        .file("road.csv", &road_csv("-200,0\n-100\n200,0\n")),
        Case::edit(
            "road CSV header without x_m",
            &[CSV_ROAD],
            &["road.csv: line 1: header has no column `x_m`"],
        )
        .file("road.csv", b"x,z\n-200,0\n200,0\n"),
        Case::edit(
            "road CSV too short for the run",
            &[CSV_ROAD],
            &["road.csv: the profile covers [-10, 10] m but the simulation needs"],
        )
        .file("road.csv", &road_csv("-10,0\n10,0\n")),
        // Bridge model and damage regions.
        Case::edit(
            "stiffness region beyond the span",
            &[Set(
                "bridge.stiffness_regions",
                "[{ start_m = 25.0, end_m = 35.0, ei_factor = 0.5 }]",
            )],
            &["bridge.stiffness_regions.0.end_m = 35 must lie in (25, 30] m"],
        ),
        Case::edit(
            "stiffness region before the span",
            &[Set(
                "bridge.stiffness_regions",
                "[{ start_m = -5.0, end_m = 5.0, ei_factor = 0.5 }]",
            )],
            &["bridge.stiffness_regions.0.start_m = -5 must lie on the span [0, 30] m"],
        ),
        Case::edit(
            "stiffness region with EI factor zero",
            &[Set(
                "bridge.stiffness_regions",
                "[{ start_m = 5.0, end_m = 10.0, ei_factor = 0.0 }]",
            )],
            &["bridge.stiffness_regions.0.ei_factor = 0 "],
        ),
        Case::edit(
            "model with zero elements",
            &[Set("bridge.model.elements", "0")],
            &["bridge.model.elements = 0 must be between 1 and 5000"],
        ),
        // Output options.
        Case::edit(
            "block_samples zero",
            &[Set("output.layout", "\"block\""), Set("output.block_samples", "0")],
            &["output.block_samples = 0 must be in 1..=100000"],
        ),
        Case::edit(
            "axle-load rate does not divide the solver rate",
            &[Set("output.axle_load_rate_hz", "300.0")],
            &["output.axle_load_rate_hz = 300 must divide the solver rate 1000 Hz"],
        ),
        Case::edit(
            "bridge-state rate above the solver rate",
            &[Set("output.bridge_state_rate_hz", "3000.0")],
            &["output.bridge_state_rate_hz = 3000 must divide the solver rate 1000 Hz"],
        ),
        Case::edit(
            "bridge-state rate NaN",
            &[Set("output.bridge_state_rate_hz", "nan")],
            &["output.bridge_state_rate_hz = NaN "],
        ),
        Case::edit(
            "axle-load rate below one message in 30 days",
            &[Set("output.axle_load_rate_hz", "1e-12")],
            &["output.axle_load_rate_hz = 0.000000000001 is too low"],
        ),
    ]);
    cases
}

fn output_cases() -> Vec<Case> {
    let ok = || edited(&[]).into_bytes();
    vec![
        Case::raw(
            "output folder does not exist",
            ok(),
            &["nodir/run.mcap", "No such file or directory"],
        )
        .writing_to("nodir/run.mcap"),
        Case::raw(
            "output folder not writable",
            ok(),
            &["ro/run.mcap", "Permission denied"],
        )
        .writing_to("ro/run.mcap")
        .folder("ro", 0o555)
        .needs_unwritable("ro"),
        Case::raw(
            "output exists, no --force (kept unchanged)",
            ok(),
            &["run.mcap", "already exists"],
        )
        .file("run.mcap", b"an earlier run: must be kept byte for byte"),
        // /dev/full exists, so without --force the run stops before writing.
        Case::args(
            "output /dev/full",
            &["simulate", "--out", "/dev/full", "--duration-s", "0.5"],
            1,
            &["/dev/full"],
        ),
        // With --force: a device is never replaced by a run.
        Case::args(
            "output /dev/full with --force",
            &[
                "simulate",
                "--out",
                "/dev/full",
                "--force",
                "--duration-s",
                "0.5",
            ],
            1,
            &["/dev/full", "exists and is not a regular file"],
        ),
        Case::raw(
            "output path is a directory",
            ok(),
            &["writing outdir: is a directory"],
        )
        .writing_to("outdir")
        .folder("outdir", 0o755),
        Case::raw(
            "output path is the current directory",
            ok(),
            &["writing .:"],
        )
        .writing_to("."),
        Case::raw(
            "output folder is a file",
            ok(),
            &["afile/run.mcap", "Not a directory"],
        )
        .writing_to("afile/run.mcap")
        .file("afile", b"not a folder"),
    ]
}

fn cli_cases() -> Vec<Case> {
    let sim = |extra: &[&'static str]| -> Vec<&'static str> {
        let mut a = vec!["simulate", "--out", "run.mcap"];
        a.extend_from_slice(extra);
        a
    };
    vec![
        Case::args(
            "unknown flag",
            &sim(&["--bogus", "--duration-s", "0.5"]),
            2,
            &["--bogus"],
        ),
        Case::args(
            "--seed not a number",
            &sim(&["--seed", "abc", "--duration-s", "0.5"]),
            2,
            &["--seed", "'abc'"],
        ),
        Case::args(
            "--seed negative",
            &sim(&["--seed=-1", "--duration-s", "0.5"]),
            2,
            &["--seed", "'-1'"],
        ),
        Case::args(
            "--seed beyond u64",
            &sim(&["--seed", "18446744073709551616", "--duration-s", "0.5"]),
            2,
            &["--seed", "18446744073709551616"],
        ),
        // clap takes `-1` after a flag for another flag: a usage error naming `-1` but not
        // `--duration-s`. With `allow_negative_numbers` on the argument it becomes the
        // validation error `duration_s = -1` (exit 1), the alternative accepted here.
        Case::args(
            "--duration-s -1",
            &sim(&["--duration-s", "-1"]),
            2,
            &["'-1'"],
        )
        .or_else(1, &["duration_s = -1 "]),
        Case::args(
            "--duration-s=-1",
            &sim(&["--duration-s=-1"]),
            1,
            &["duration_s = -1 must be a finite number > 0"],
        ),
        Case::args(
            "--duration-s nan",
            &sim(&["--duration-s", "nan"]),
            1,
            &["duration_s = NaN must be a finite number > 0"],
        ),
        Case::args(
            "--duration-s inf",
            &sim(&["--duration-s", "inf"]),
            1,
            &["duration_s = inf must be a finite number > 0"],
        ),
        Case::args(
            "--duration-s 0",
            &sim(&["--duration-s", "0"]),
            1,
            &["duration_s = 0 must be a finite number > 0"],
        ),
        Case::args(
            "--duration-s not a number",
            &sim(&["--duration-s", "ten"]),
            2,
            &["--duration-s", "'ten'"],
        ),
        Case::args(
            "--duration-s beyond 30 days",
            &sim(&["--duration-s", "1e7"]),
            1,
            &["duration_s = 10000000 must be at most 30 days"],
        ),
        Case::args(
            "--out missing",
            &["simulate", "--duration-s", "0.5"],
            2,
            &["--out"],
        ),
        Case::args("unknown command", &["frobnicate"], 2, &["'frobnicate'"]),
        Case::raw(
            "scenario check on a bad scenario",
            edited(&[Set("bridge.span_m", "0.0")]).into_bytes(),
            &["bridge.span_m = 0 must be a finite number > 0"],
        )
        .with_args(&["scenario", "check", "scenario.toml"]),
    ]
}

/// Issue 5: sensor presets and chains, DAQ nodes, faults, ambient excitation, WIM models.
fn monitoring_cases() -> Vec<Case> {
    const LOWNOISE: Edit = Set("sensors.0.preset", "\"mems_lownoise\"");
    const NODE: Edit = Set(
        "daq_nodes",
        "[{ id = \"N1\", clock = { drift_ppm = 20.0 } }]",
    );
    vec![
        Case::edit(
            "unknown sensor preset",
            &[Set("sensors.0.preset", "\"mems_fancy\"")],
            &["unknown variant `mems_fancy`", "mems_lownoise"],
        ),
        Case::edit(
            "accelerometer preset on a strain gauge",
            &[Set("sensors.7.preset", "\"mems_lownoise\"")],
            &["sensors.7.preset", "mems_lownoise"],
        ),
        Case::edit(
            "negative chain noise density",
            &[LOWNOISE, Set("sensors.0.chain.noise_density", "-1.0")],
            &["sensors.0.chain.noise_density = -1"],
        ),
        Case::edit(
            "rate not supported by the preset",
            &[
                Set("solver.dt_s", "0.0001"),
                LOWNOISE,
                Set("sensors.0.rate_hz", "5000.0"),
            ],
            &["sensors.0.rate_hz = 5000", "mems_lownoise"],
        ),
        Case::edit(
            "ADC with 40 bits",
            &[
                LOWNOISE,
                Set("sensors.0.chain.adc", "{ bits = 40, range = 1.0 }"),
            ],
            &["sensors.0.chain.adc.bits = 40"],
        ),
        Case::edit(
            "clock drift beyond 1000 ppm",
            &[
                Set(
                    "daq_nodes",
                    "[{ id = \"N1\", clock = { drift_ppm = 2000.0 } }]",
                ),
                Set("sensors.0.daq_node", "\"N1\""),
            ],
            &["daq_nodes.0.clock.drift_ppm = 2000"],
        ),
        Case::edit(
            "sensor on an unknown DAQ node",
            &[NODE, Set("sensors.0.daq_node", "\"N9\"")],
            &["sensors.0.daq_node = \"N9\" is not a [[daq_nodes]] id"],
        ),
        Case::edit(
            "clocked sensor at the solver rate",
            &[
                NODE,
                Set("sensors.0.daq_node", "\"N1\""),
                Set("sensors.0.rate_hz", "1000.0"),
            ],
            &["sensors.0.rate_hz = 1000 must be at most half the solver rate"],
        ),
        Case::edit(
            "loss probability above 1",
            &[Set(
                "sensors.0.faults",
                "{ loss = { kind = \"random\", probability = 1.5 } }",
            )],
            &["sensors.0.faults.loss.probability = 1.5"],
        ),
        Case::edit(
            "negative spike rate",
            &[Set(
                "sensors.0.faults",
                "{ spikes = { rate_per_hour = -1.0, amplitude = 1.0 } }",
            )],
            &["sensors.0.faults.spikes.rate_per_hour = -1"],
        ),
        Case::edit(
            "ambient target negative",
            &[Set("ambient", "{ target_rms_m_s2 = -1.0 }")],
            &["ambient.target_rms_m_s2 = -1"],
        ),
        Case::edit(
            "ambient band above the Nyquist frequency",
            &[Set(
                "ambient",
                "{ target_rms_m_s2 = 0.01, band_hz = [1.0, 600.0] }",
            )],
            &["ambient.band_hz", "600"],
        ),
        Case::edit(
            "unknown COST 323 class",
            &[Set(
                "wim_stations.0.model",
                "{ kind = \"cost323\", class = \"E(30)\" }",
            )],
            &["wim_stations.0.model.class = \"E(30)\"", "B+(7)"],
        ),
        Case::edit(
            "negative WIM noise",
            &[Set(
                "wim_stations.0.model",
                "{ kind = \"physics\", noise_rel = -0.1 }",
            )],
            &["wim_stations.0.model.noise_rel = -0.1"],
        ),
    ]
}

/// Issue 6: generated traffic.
fn traffic_cases() -> Vec<Case> {
    const DURATION: Edit = Set("duration_s", "60.0");
    vec![
        Case::edit(
            "negative lane flow",
            &[DURATION, Set("traffic", "{ lanes = [{ flow_per_hour = -5.0 }] }")],
            &["traffic.lanes.0.flow_per_hour = -5"],
        ),
        Case::edit(
            "class shares not summing to 1",
            &[
                DURATION,
                Set(
                    "traffic",
                    "{ lanes = [{ flow_per_hour = 100.0 }], classes = { car = 0.5, truck_2axle = 0.2 } }",
                ),
            ],
            &["traffic.classes"],
        ),
        Case::edit(
            "unknown traffic class",
            &[
                DURATION,
                Set(
                    "traffic",
                    "{ lanes = [{ flow_per_hour = 100.0 }], classes = { car = 0.5, hovercraft = 0.5 } }",
                ),
            ],
            &["hovercraft"],
        ),
        Case::edit(
            "traffic without a duration",
            &[Set("traffic", "{ lanes = [{ flow_per_hour = 100.0 }] }")],
            &["duration_s = (missing) is required with [traffic]"],
        )
        .full_duration(),
        Case::edit(
            "vehicle direction 2",
            &[Set("vehicles.0.direction", "2")],
            &["vehicles.0.direction = 2 must be 1 (towards +x) or -1"],
        ),
    ]
}

/// Issue 6: temperature and damage.
fn condition_cases() -> Vec<Case> {
    const CSV_AIR: Edit = Set(
        "environment",
        "{ temperature = { kind = \"csv\", path = \"air.csv\" } }",
    );
    vec![
        Case::edit(
            "temperature CSV with a word for a value",
            &[CSV_AIR],
            &["air.csv", "line 3", "abc"],
        )
        .file("air.csv", b"time_s,temperature_c\n0,20\n60,abc\n"),
        Case::edit(
            "temperature CSV with the wrong header",
            &[CSV_AIR],
            &["air.csv", "time_s,temperature_c"],
        )
        .file("air.csv", b"t,T\n0,20\n60,21\n"),
        Case::edit(
            "temperature CSV going back in time",
            &[CSV_AIR],
            &["air.csv", "line 4"],
        )
        .file("air.csv", b"time_s,temperature_c\n0,20\n60,21\n30,22\n"),
        Case::edit("temperature CSV missing", &[CSV_AIR], &["air.csv"]),
        Case::edit(
            "damage region beyond the span",
            &[Set(
                "damage",
                "[{ start_m = 20.0, end_m = 40.0, reduction = 0.2, onset_s = 0.1 }]",
            )],
            &["damage.0.end_m = 40"],
        ),
        Case::edit(
            "damage reduction of 1",
            &[Set(
                "damage",
                "[{ start_m = 10.0, end_m = 12.0, reduction = 1.0, onset_s = 0.1 }]",
            )],
            &["damage.0.reduction = 1", "(0, 1)"],
        ),
        Case::edit(
            "damage reduction negative",
            &[Set(
                "damage",
                "[{ start_m = 10.0, end_m = 12.0, reduction = -0.1, onset_s = 0.1 }]",
            )],
            &["damage.0.reduction = -0.1"],
        ),
        Case::edit(
            "negative thermal lag",
            &[Set("environment", "{ lag_s = -3.0 }")],
            &["environment.lag_s = -3"],
        ),
        Case::edit(
            "damage on a modal model",
            &[
                Set("bridge.model", "{ kind = \"modal\", modes = 4 }"),
                Set(
                    "damage",
                    "[{ start_m = 10.0, end_m = 12.0, reduction = 0.2, onset_s = 0.1 }]",
                ),
            ],
            &["bridge.model", "modal"],
        ),
    ]
}

#[test]
fn traffic() {
    run_all("traffic", &traffic_cases());
}

#[test]
fn condition() {
    run_all("condition", &condition_cases());
}

#[test]
fn monitoring() {
    run_all("monitoring", &monitoring_cases());
}

#[test]
fn scenario_syntax() {
    run_all("scenario syntax", &syntax_cases());
}

#[test]
fn physics() {
    run_all("physics", &physics_cases());
}

#[test]
fn output() {
    run_all("output", &output_cases());
    // The device is still the device.
    let meta = std::fs::metadata("/dev/full").expect("/dev/full");
    assert!(meta.file_type().is_char_device());
    assert!(!Path::new("/dev/full.partial").exists());
}

#[test]
fn cli() {
    run_all("CLI", &cli_cases());
}

/// Every case of the catalogue.
fn all_cases() -> Vec<Case> {
    [
        syntax_cases(),
        physics_cases(),
        output_cases(),
        cli_cases(),
        monitoring_cases(),
        traffic_cases(),
        condition_cases(),
    ]
    .into_iter()
    .flatten()
    .collect()
}

#[test]
fn the_schema_rejects_every_case_it_can_see() {
    // Editors validate with the scenario's JSON Schema; see support/bad_input_schema.rs
    // for the cases it accepts and why.
    let cases = all_cases();
    let views: Vec<bad_input_schema::CaseView> = cases
        .iter()
        .map(|c| bad_input_schema::CaseView {
            name: &c.name,
            scenario: c.scenario.as_deref(),
            expect: &c.expect,
        })
        .collect();
    let report = bad_input_schema::disagreements(&views, &edited(&[]));
    assert!(report.is_empty(), "{}", report.join("\n"));
}

#[test]
fn the_catalogue_has_at_least_45_cases() {
    let counts = [
        ("scenario syntax", syntax_cases().len()),
        ("physics", physics_cases().len()),
        ("output", output_cases().len()),
        ("CLI", cli_cases().len()),
        ("monitoring", monitoring_cases().len()),
        ("traffic", traffic_cases().len()),
        ("condition", condition_cases().len()),
    ];
    let total: usize = counts.iter().map(|c| c.1).sum();
    eprintln!("bad-input cases: {counts:?}, total {total}");
    assert!(total >= 45, "{counts:?}");
    let mut names = std::collections::BTreeSet::new();
    for case in syntax_cases()
        .iter()
        .chain(&physics_cases())
        .chain(&output_cases())
        .chain(&cli_cases())
        .chain(&monitoring_cases())
        .chain(&traffic_cases())
        .chain(&condition_cases())
    {
        assert!(
            names.insert(case.name.clone()),
            "duplicate case {}",
            case.name
        );
    }
}
