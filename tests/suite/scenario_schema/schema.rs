//! The scenario's JSON Schema as a TOML editor applies it: the scenario parsed as TOML,
//! turned into JSON (as Taplo and tombi do), validated by a draft-07 validator with
//! format checks on (`start_time` is a `date-time`). Shared by `tests/suite/scenario_schema/`
//! and the schema check of the bad-input catalogue (`tests/suite/bad_input/`).

#![allow(dead_code)] // each test binary uses part of it

use jsonschema::error::ValidationErrorKind;
use jsonschema::{ValidationError, Validator};
use serde_json::Value;

/// A validator of the schema `bridgetwin scenario schema` prints.
pub fn validator() -> Validator {
    let schema = bridgetwin::scenario::schema::json_schema();
    jsonschema::draft7::options()
        .should_validate_formats(true)
        .build(&schema)
        .expect("the scenario schema is a valid draft-07 schema")
}

/// A TOML document as JSON, or `None` when it is not TOML. NaN and infinities have no
/// JSON form: serde_json turns them into `null`, which the schema rejects as "not a
/// number", as an editor does.
pub fn toml_to_json(text: &str) -> Option<Value> {
    let table: toml::Table = text.parse().ok()?;
    Some(serde_json::to_value(table).expect("a TOML table converts to JSON"))
}

/// Where the schema finds `instance` wrong, as dotted scenario paths (`bridge.span_m`,
/// `sensors.0.gain` for an unknown key, `vehicles.0.model.wings` inside a `kind`-tagged
/// table); empty when it is valid.
pub fn error_paths(validator: &Validator, instance: &Value) -> Vec<String> {
    let mut paths: Vec<String> = validator
        .iter_errors(instance)
        .flat_map(|e| leaf_paths(&e))
        .collect();
    paths.sort();
    paths.dedup();
    paths
}

fn dotted(error: &ValidationError<'_>) -> String {
    let segments: Vec<String> = error
        .instance_path()
        .iter()
        .map(|s| s.to_string())
        .collect();
    segments.join(".")
}

fn join(path: &str, key: &str) -> String {
    if path.is_empty() {
        key.to_string()
    } else {
        format!("{path}.{key}")
    }
}

/// The paths an error points at, down to the key: an unknown or missing key is named, and
/// a failed `oneOf` of `kind`-tagged tables is followed into the variant its `kind` names
/// (its errors are the table's), or reported at `kind` when no variant has that name.
fn leaf_paths(error: &ValidationError<'_>) -> Vec<String> {
    let path = dotted(error);
    match error.kind() {
        ValidationErrorKind::AdditionalProperties { unexpected } => {
            unexpected.iter().map(|key| join(&path, key)).collect()
        }
        ValidationErrorKind::Required { property } => {
            vec![join(&path, property.as_str().unwrap_or_default())]
        }
        ValidationErrorKind::PropertyNames { error } => match error.instance().as_str() {
            Some(key) => vec![join(&path, key)],
            None => vec![path],
        },
        ValidationErrorKind::OneOfNotValid { context } => {
            let kind_path = join(&path, "kind");
            let kind_failed = |branch: &Vec<ValidationError<'static>>| {
                branch.iter().any(|e| dotted(e) == kind_path)
            };
            let chosen: Vec<&Vec<ValidationError<'static>>> =
                context.iter().filter(|b| !kind_failed(b)).collect();
            match chosen.as_slice() {
                [branch] => branch.iter().flat_map(|e| leaf_paths(e)).collect(),
                [] if error.instance().get("kind").is_some() => vec![kind_path],
                _ => vec![path],
            }
        }
        _ => vec![path],
    }
}
