//! The harness of the catalogue: a case is a scenario (the default with edits, or raw
//! bytes), input files and folders, arguments, and the expected exit code and stderr
//! fragments; [`run_all`] runs the binary on each in a fresh folder and checks the outcome.

use std::collections::BTreeMap;
use std::io::Read;
use std::os::unix::fs::PermissionsExt;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use bridgetwin::scenario::DEFAULT_SCENARIO_TOML;

use crate::common::{skip, BIN};

/// A run that has not exited by then has been accepted and is simulating: a failure.
const TIMEOUT: Duration = Duration::from_secs(20);

/// One edit of the default scenario.
pub(super) enum Edit {
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

pub(super) struct Case {
    pub(super) name: String,
    /// Written to `scenario.toml` when given.
    pub(super) scenario: Option<Vec<u8>>,
    /// Other input files (a road CSV, an existing output).
    files: Vec<(&'static str, Vec<u8>)>,
    folders: Vec<Folder>,
    /// Arguments after the binary.
    args: Vec<String>,
    /// Expected exit code and substrings of stderr.
    exit: i32,
    pub(super) expect: Vec<String>,
    /// Another acceptable outcome (exit code, substrings), for behaviour that is being
    /// changed elsewhere (documented at the case).
    or_else: Option<(i32, Vec<String>)>,
    /// The output path given to `--out` (relative to the folder, or absolute).
    out: String,
    /// Skip unless a probe file cannot be created in this folder (root writes anywhere).
    needs_unwritable: Option<&'static str>,
    /// Environment variables set for the run.
    env: Vec<(&'static str, &'static str)>,
}

pub(super) fn edited(edits: &[Edit]) -> String {
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
    pub(super) fn edit(name: &str, edits: &[Edit], expect: &[&str]) -> Case {
        Case::raw(name, edited(edits).into_bytes(), expect)
    }

    /// A scenario file with these bytes.
    pub(super) fn raw(name: &str, scenario: Vec<u8>, expect: &[&str]) -> Case {
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
            env: Vec::new(),
        }
    }

    /// No scenario file (the embedded default) and these arguments.
    pub(super) fn args(name: &str, args: &[&str], exit: i32, expect: &[&str]) -> Case {
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
            env: Vec::new(),
        }
    }

    /// Without `--duration-s 0.5`, for cases about the scenario's own duration.
    pub(super) fn full_duration(mut self) -> Case {
        self.args.truncate(self.args.len() - 2);
        self
    }

    pub(super) fn with_args(mut self, args: &[&str]) -> Case {
        self.args = args.iter().map(|s| s.to_string()).collect();
        self
    }

    /// Writes to `out` instead of `run.mcap`.
    pub(super) fn writing_to(mut self, out: &str) -> Case {
        let i = self.args.iter().position(|a| a == "--out").expect("--out");
        self.args[i + 1] = out.to_string();
        self.out = out.to_string();
        self
    }

    /// Another acceptable outcome.
    pub(super) fn or_else(mut self, exit: i32, expect: &[&str]) -> Case {
        self.or_else = Some((exit, strings(expect)));
        self
    }

    /// Skipped when `folder` turns out to be writable.
    pub(super) fn needs_unwritable(mut self, folder: &'static str) -> Case {
        self.needs_unwritable = Some(folder);
        self
    }

    /// Runs with the environment variable `name` set to `value`.
    pub(super) fn env(mut self, name: &'static str, value: &'static str) -> Case {
        self.env.push((name, value));
        self
    }

    pub(super) fn file(mut self, name: &'static str, content: &[u8]) -> Case {
        self.files.push((name, content.to_vec()));
        self
    }

    pub(super) fn folder(mut self, name: &'static str, mode: u32) -> Case {
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
        .envs(case.env.iter().copied())
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
pub(super) fn run_all(class: &str, cases: &[Case]) {
    let mut failures = Vec::new();
    let mut skipped = Vec::new();
    for case in cases {
        match run_case(case) {
            Ok(Outcome::Pass) => {}
            Ok(Outcome::Skipped(why)) => skipped.push(format!("{}: {why}", case.name)),
            Err(report) => failures.push(format!("case `{}`: {report}", case.name)),
        }
    }
    for why in &skipped {
        skip(&format!("bad input, {class}"), why);
    }
    eprintln!(
        "{class}: {} cases, {} failed, {} skipped",
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
