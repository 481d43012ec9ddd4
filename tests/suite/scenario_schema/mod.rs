//! The scenario reference, generated from the code: the committed JSON Schema
//! (`docs/scenario.schema.json`) and Markdown reference (`docs/scenario.md`) are what the
//! code generates now, every scenario the repository ships validates against the schema,
//! and the schema rejects what the loader rejects key by key (types, names, bounds).
//! The bad-input catalogue's own schema check is in `tests/suite/bad_input/`.

pub(crate) mod schema;

use std::path::{Path, PathBuf};

use bridgetwin::app::sweep::Plan;
use bridgetwin::scenario::schema::{
    json_schema, json_text, reference_text, REFERENCE_PATH, SCHEMA_PATH,
};
use bridgetwin::scenario::DEFAULT_SCENARIO_TOML;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// The committed file at `relative`, compared with what the code generates; on a
/// difference the message says how to regenerate it.
fn assert_current(relative: &str, generated: &str, command: &str) {
    let committed = std::fs::read_to_string(root().join(relative)).unwrap_or_default();
    if committed != generated {
        let line = committed
            .lines()
            .zip(generated.lines())
            .position(|(a, b)| a != b)
            .unwrap_or_else(|| committed.lines().count().min(generated.lines().count()));
        panic!(
            "{relative} is not what the code generates (first difference at line {}); \
             regenerate it with\n    cargo run --release -- {command} > {relative}\nand \
             commit it",
            line + 1
        );
    }
}

#[test]
fn the_committed_schema_and_reference_are_current() {
    assert_current(SCHEMA_PATH, &json_text(), "scenario schema");
    assert_current(REFERENCE_PATH, &reference_text(), "scenario docs");
}

#[test]
fn the_cli_prints_the_schema_and_the_reference() {
    for (command, expected) in [("schema", json_text()), ("docs", reference_text())] {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_bridgetwin"))
            .args(["scenario", command])
            .output()
            .expect("bridgetwin runs");
        assert!(out.status.success(), "scenario {command} failed");
        assert_eq!(
            String::from_utf8_lossy(&out.stdout),
            expected,
            "scenario {command}"
        );
    }
}

/// Every file of `dir` ending in `.toml`, sorted.
fn toml_files(dir: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .expect("folder readable")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    files
}

fn assert_valid(label: &str, text: &str, validator: &jsonschema::Validator) {
    let json = schema::toml_to_json(text).unwrap_or_else(|| panic!("{label}: not TOML"));
    let errors = schema::error_paths(validator, &json);
    let messages: Vec<String> = validator
        .iter_errors(&json)
        .map(|e| format!("{}: {e}", e.instance_path()))
        .collect();
    assert!(
        errors.is_empty(),
        "{label} does not validate against the schema at {errors:?}:\n{}",
        messages.join("\n")
    );
}

#[test]
fn every_example_and_the_default_scenario_validate() {
    let validator = schema::validator();
    assert_valid("the default scenario", DEFAULT_SCENARIO_TOML, &validator);
    let examples = toml_files(&root().join("examples"));
    assert!(examples.len() >= 7, "examples/ lists {examples:?}");
    for path in &examples {
        let text = std::fs::read_to_string(path).expect("example readable");
        assert_valid(&path.display().to_string(), &text, &validator);
    }
}

#[test]
fn every_run_of_the_example_sweeps_validates() {
    // A sweep plan is not a scenario; the scenarios it expands into are.
    let validator = schema::validator();
    let plans = toml_files(&root().join("examples/sweeps"));
    assert!(!plans.is_empty());
    for path in &plans {
        let (plan, base) = Plan::from_file(path).expect("plan reads");
        let expanded = plan.expand(&base).expect("plan expands");
        assert!(!expanded.runs.is_empty());
        for run in &expanded.runs {
            let label = format!("{} run {}", path.display(), run.id);
            assert_valid(&label, &run.toml, &validator);
        }
    }
}

#[test]
fn every_example_names_the_schema_for_editors() {
    // Taplo and tombi read the `#:schema` directive from the first lines of a file.
    for path in toml_files(&root().join("examples")) {
        let text = std::fs::read_to_string(&path).expect("example readable");
        assert_eq!(
            text.lines().next(),
            Some(format!("#:schema ../{SCHEMA_PATH}").as_str()),
            "{} does not start with the #:schema directive",
            path.display()
        );
    }
    let directive_target = root().join(SCHEMA_PATH);
    assert!(directive_target.is_file(), "{SCHEMA_PATH} is missing");
}

/// The default scenario with a duration (which `[traffic]` needs) and `path` set to the
/// TOML value `literal`.
fn edited(path: &str, literal: &str) -> serde_json::Value {
    let mut json = schema::toml_to_json(DEFAULT_SCENARIO_TOML).expect("default parses");
    json["duration_s"] = 60.0.into();
    let value: toml::Table = format!("v = {literal}").parse().expect("literal parses");
    let value = serde_json::to_value(&value["v"]).expect("converts");
    let mut node = &mut json;
    let segments: Vec<&str> = path.split('.').collect();
    let (last, parents) = segments.split_last().expect("a path");
    for segment in parents {
        node = match segment.parse::<usize>() {
            Ok(i) => &mut node[i],
            Err(_) => &mut node[*segment],
        };
    }
    match last.parse::<usize>() {
        Ok(i) => node[i] = value,
        Err(_) => node[*last] = value,
    }
    json
}

#[test]
fn the_schema_states_the_bounds_the_loader_checks() {
    // One value just inside and one just outside each kind of bound: a bound written on
    // the wrong side, or not written, fails here. (The bad-input catalogue checks the
    // rejections of the loader's own cases.)
    let validator = schema::validator();
    let cases: &[(&str, &str, &str)] = &[
        // (path, accepted, rejected)
        ("bridge.span_m", "0.5", "0.0"),
        ("bridge.span_m", "10000.0", "10001.0"),
        ("bridge.damping_ratio", "0.0", "1.0"),
        ("solver.dt_s", "0.1", "0.2"),
        ("solver.newmark.gamma", "0.5", "0.49"),
        ("solver.newmark.beta", "0.5", "0.0"),
        ("bridge.model.elements", "20000", "20001"),
        ("vehicles.0.speed_m_s", "100.0", "100.5"),
        ("vehicles.0.direction", "-1", "0"),
        ("vehicles.0.model.preset", "\"vbi2d_e01\"", "\"vbi2d_e02\""),
        ("vehicles.0.model.axle_mass_kg", "[1.0, 2.0]", "[1.0, 0.0]"),
        ("vehicles.0.model.tyre_damping_n_s_m", "[0.0, 0.0]", "[0.0, -1.0]"),
        ("vehicles.0.model.axle_mass_kg", "[1.0, 2.0]", "[1.0, 2.0, 3.0]"),
        ("sensors.0.id", "\"A_1-x\"", "\"A.1\""),
        ("sensors.0.rate_hz", "1.0", "0.0"),
        ("sensors.0.preset", "\"mems_lownoise\"", "\"mems\""),
        ("sensors.0.chain", "{ gain_error = -0.9 }", "{ gain_error = -1.0 }"),
        ("sensors.0.chain", "{ adc = { bits = 32 } }", "{ adc = { bits = 33 } }"),
        ("sensors.0.faults", "{ loss = { kind = \"random\", probability = 1.0 } }",
         "{ loss = { kind = \"random\", probability = 1.1 } }"),
        ("wim_stations.0.position_m", "-1.0", "0.0"),
        ("wim_stations.0.model", "{ kind = \"cost323\", class = \"D+(20)\" }",
         "{ kind = \"cost323\", class = \"D(20)\" }"),
        ("output.block_samples", "1", "0"),
        ("output.axle_load_rate_hz", "0.001", "1e-7"),
        ("output.split_every_s", "1.0", "0.5"),
        ("start_time", "\"2026-06-01T12:00:00+02:00\"", "\"2026-06-01 noon\""),
        ("traffic", "{ lanes = [{ flow_per_hour = 0.0 }] }", "{ lanes = [] }"),
        ("traffic", "{ lanes = [{ flow_per_hour = 1.0 }], classes = { car = 1.0 } }",
         "{ lanes = [{ flow_per_hour = 1.0 }], classes = { bus = 1.0 } }"),
        ("traffic", "{ lanes = [{ flow_per_hour = 1.0, direction = -1 }] }",
         "{ lanes = [{ flow_per_hour = 1.0, direction = 2 }] }"),
        ("environment", "{ temperature = { kind = \"daily\", mean_c = 5.0, amplitude_c = 0.0 } }",
         "{ temperature = { kind = \"daily\", mean_c = 5.0, amplitude_c = 1.0, peak_hour = 24.0 } }"),
        ("damage", "[{ start_m = 1.0, end_m = 2.0, reduction = 0.5, onset_s = 0.0 }]",
         "[{ start_m = 1.0, end_m = 2.0, reduction = 1.0, onset_s = 0.0 }]"),
        ("daq_nodes", "[{ id = \"N1\", clock = { drift_ppm = -1000.0 } }]",
         "[{ id = \"N1\", clock = { drift_ppm = -1001.0 } }]"),
    ];
    let mut wrong = Vec::new();
    for &(path, accepted, rejected) in cases {
        let ok = schema::error_paths(&validator, &edited(path, accepted));
        if !ok.is_empty() {
            wrong.push(format!("{path} = {accepted} is rejected at {ok:?}"));
        }
        if schema::error_paths(&validator, &edited(path, rejected)).is_empty() {
            wrong.push(format!("{path} = {rejected} is accepted"));
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

#[test]
fn traffic_needs_a_duration_in_the_schema_too() {
    let validator = schema::validator();
    let mut json = edited("traffic", "{ lanes = [{ flow_per_hour = 100.0 }] }");
    assert!(schema::error_paths(&validator, &json).is_empty());
    json.as_object_mut().expect("a table").remove("duration_s");
    assert_eq!(schema::error_paths(&validator, &json), ["duration_s"]);
}

#[test]
fn the_schema_is_a_self_contained_draft_07_document() {
    let schema = json_schema();
    assert!(
        jsonschema::meta::is_valid(&schema),
        "not a valid JSON Schema"
    );
    // Editors resolve only local references: every `$ref` points into `definitions`.
    let text = json_text();
    for (at, _) in text.match_indices("\"$ref\": \"") {
        let target = &text[at + 9..];
        assert!(
            target.starts_with("#/definitions/"),
            "{}",
            &target[..40.min(target.len())]
        );
    }
    let definitions = schema["definitions"].as_object().expect("definitions");
    assert!(definitions.len() >= 30, "{} definitions", definitions.len());
}
