//! The import rule of the layers (`src/lib.rs`, docs/code.md): a module uses only the
//! layers below it. Every `crate::<layer>` path in `src/` (code, not comments) is checked
//! against the table below; an upward or sideways import fails with the file, the line and
//! the rule it breaks. Inside `physics`, the sub-layers have their own table: the bridge
//! and the vehicles meet only in the solver.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The layers, bottom to top: each may use the layers below it, except the pairs in
/// [`APART`].
const ORDER: &[&str] = &[
    "error",
    "base",
    "record",
    "physics",
    "measurement",
    "scenario",
    "sim",
    "output",
    "input",
    "app",
    "studies",
    "cli",
];

/// (layer, lower layer) pairs that stay apart: physics emits no records, measurement
/// takes plain numbers from physics, the output sees records and the manifest only, and
/// the input (runs read back) sees the file format alone.
const APART: &[(&str, &str)] = &[
    ("physics", "record"),
    ("measurement", "physics"),
    ("output", "physics"),
    ("output", "measurement"),
    ("output", "scenario"),
    ("output", "sim"),
    ("input", "physics"),
    ("input", "measurement"),
    ("input", "scenario"),
    ("input", "sim"),
];

/// Each layer and the layers it may use.
fn layer_rules() -> BTreeMap<&'static str, Vec<&'static str>> {
    ORDER
        .iter()
        .enumerate()
        .map(|(i, &layer)| {
            let below = ORDER[..i]
                .iter()
                .copied()
                .filter(|&lower| !APART.contains(&(layer, lower)))
                .collect();
            (layer, below)
        })
        .collect()
}

/// Inside `physics`: each sub-layer and the sub-layers it may use.
const PHYSICS: &[(&str, &[&str])] = &[
    ("linalg", &[]),
    ("bridge", &["linalg"]),
    ("road", &[]),
    ("vehicle", &[]),
    ("solver", &["linalg", "bridge", "road", "vehicle"]),
    ("environment", &["bridge"]),
    // The ambient calibration is checked by integrating the bridge (a unit test).
    ("excitation", &["linalg", "bridge", "solver"]),
    ("traffic", &["vehicle"]),
];

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).expect("src is readable") {
        let path = entry.expect("entry").path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The code of a line without its `//` comment (string literals holding `//` are rare in
/// this crate and never hold a `crate::` path).
fn code_of(line: &str) -> &str {
    match line.find("//") {
        Some(i) => &line[..i],
        None => line,
    }
}

/// Every `crate::a::b` in `code`, as (a, b).
fn crate_paths(code: &str) -> Vec<(String, String)> {
    let mut out = Vec::new();
    let mut rest = code;
    while let Some(i) = rest.find("crate::") {
        let before = rest[..i].chars().last();
        rest = &rest[i + "crate::".len()..];
        if before.is_some_and(|c| c.is_alphanumeric() || c == '_') {
            continue; // `bridgetwin_crate::` or the like
        }
        let ident = |s: &str| -> String {
            s.chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_')
                .collect()
        };
        let first = ident(rest);
        let second = rest
            .strip_prefix(&format!("{first}::"))
            .map(ident)
            .unwrap_or_default();
        out.push((first, second));
    }
    out
}

/// (layer, sub-layer) of a file under `src/`: `src/physics/solver/x.rs` ->
/// ("physics", "solver"); `src/error.rs` -> ("error", "").
fn place(src: &Path, file: &Path) -> (String, String) {
    let rel = file.strip_prefix(src).expect("under src");
    let parts: Vec<String> = rel
        .iter()
        .map(|p| p.to_string_lossy().trim_end_matches(".rs").to_string())
        .collect();
    let layer = parts[0].clone();
    let sub = parts.get(1).cloned().unwrap_or_default();
    (layer, sub)
}

/// The violations of the rules in the files under `src`.
fn violations(src: &Path) -> Vec<String> {
    let layers = layer_rules();
    let physics: BTreeMap<&str, &[&str]> = PHYSICS.iter().copied().collect();
    let mut files = Vec::new();
    rust_files(src, &mut files);
    files.sort();
    let mut out = Vec::new();
    for file in &files {
        let (layer, sub) = place(src, file);
        // `crate::Result` and `crate::Error` are the error module's, re-exported at the root.
        let layer_of = |first: String| match first.as_str() {
            "Result" | "Error" => "error".to_string(),
            _ => first,
        };
        if matches!(layer.as_str(), "lib" | "main") {
            continue; // the crate root declares the layers; the binary calls the cli
        }
        let Some(allowed) = layers.get(layer.as_str()) else {
            out.push(format!(
                "{}: `src/{layer}` is not a layer of tests/suite/layers.rs (add it to ORDER)",
                file.display()
            ));
            continue;
        };
        let text = std::fs::read_to_string(file).expect("readable");
        for (n, line) in text.lines().enumerate() {
            for (used, used_sub) in crate_paths(code_of(line)) {
                let used = layer_of(used);
                let at = format!("{}:{}", file.display(), n + 1);
                if used == layer {
                    if layer == "physics" && !sub.is_empty() && !used_sub.is_empty() {
                        let ok = used_sub == sub
                            || physics
                                .get(sub.as_str())
                                .is_some_and(|a| a.contains(&used_sub.as_str()));
                        if !ok {
                            out.push(format!(
                                "{at}: physics::{sub} uses physics::{used_sub}, which it may not \
                                 (allowed: {:?})",
                                physics.get(sub.as_str())
                            ));
                        }
                    }
                    continue;
                }
                if !allowed.contains(&used.as_str()) {
                    out.push(format!(
                        "{at}: {layer} uses {used}, which it may not (allowed: {allowed:?})"
                    ));
                }
            }
        }
    }
    out
}

#[test]
fn imports_run_down_the_layers() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let found = violations(&src);
    assert!(found.is_empty(), "upward imports:\n{}", found.join("\n"));
}

#[test]
fn an_upward_import_is_found() {
    // Negative control: a copy of the tree's shape with one output module importing the
    // time loop, and the traffic generator importing the bridge.
    let dir = tempfile::tempdir().unwrap();
    let src = dir.path().join("src");
    for (path, text) in [
        (
            "output/recorder.rs",
            "use crate::record::Record;\nuse crate::sim::run;\n",
        ),
        (
            "physics/traffic/arrivals.rs",
            "use crate::physics::bridge::BeamProperties;\n",
        ),
        (
            "physics/solver/coupled.rs",
            "use crate::physics::bridge::BridgeModel; // fine\n",
        ),
        (
            "sim/mod.rs",
            "// crate::cli is only named in a comment\nuse crate::physics::road;\n",
        ),
    ] {
        let file = src.join(path);
        std::fs::create_dir_all(file.parent().unwrap()).unwrap();
        std::fs::write(&file, text).unwrap();
    }
    let found = violations(&src);
    assert_eq!(found.len(), 2, "{found:#?}");
    assert!(found[0].contains("output uses sim"), "{found:#?}");
    assert!(
        found[1].contains("physics::traffic uses physics::bridge"),
        "{found:#?}"
    );
}

#[test]
fn every_file_of_the_suite_is_one_of_its_modules() {
    // The suite is one binary: a file in tests/suite/ that main.rs does not declare is
    // never compiled, and its tests would pass by not existing.
    let suite = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/suite");
    let main = std::fs::read_to_string(suite.join("main.rs")).expect("main.rs");
    let mut undeclared = Vec::new();
    for entry in std::fs::read_dir(&suite).expect("tests/suite") {
        let path = entry.expect("entry").path();
        let name = match (path.is_dir(), path.extension()) {
            (true, _) if path.join("mod.rs").is_file() => path.file_name(),
            (false, Some(ext)) if ext == "rs" => path.file_stem(),
            _ => continue,
        };
        let name = name.expect("a name").to_string_lossy().into_owned();
        if name != "main" && !main.lines().any(|l| l.trim() == format!("mod {name};")) {
            undeclared.push(name);
        }
    }
    assert!(
        undeclared.is_empty(),
        "not declared in tests/suite/main.rs: {undeclared:?}"
    );
    // And no test file outside the suite (each would be a binary of its own).
    let stray: Vec<_> = std::fs::read_dir(suite.parent().expect("tests"))
        .expect("tests")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "rs"))
        .collect();
    assert!(
        stray.is_empty(),
        "test files outside tests/suite: {stray:?}"
    );
}
