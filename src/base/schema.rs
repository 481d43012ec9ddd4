//! Pieces of the scenario's JSON Schema that the `schemars` derive cannot state on its
//! own, for `#[schemars(transform = ...)]` at a field: strict bounds (`require_positive`
//! is `exclusiveMinimum`, which the derive's `range` has no form for), bounds on every
//! item of an array, and names a string must be one of, with the values behind each name
//! (vehicle presets). Inclusive bounds on a number are written at the field with
//! `#[schemars(range(min = .., max = ..))]`.
//!
//! The checks themselves stay in the `validate` functions beside each type; these only
//! describe them to an editor, so every bound here names the check it mirrors.

use schemars::Schema;
use serde::Serialize;
use serde_json::{Map, Value};

/// Annotation carrying a key's unit (read from its name by the scenario schema).
pub const UNIT_KEY: &str = "x-unit";

/// Annotation listing the values behind named choices (presets): `{ name: { key: value,
/// ... } }`, rendered as lists in the scenario reference.
pub const CHOICES_KEY: &str = "x-choices";

/// An id that becomes a topic segment (sensors, WIM stations, DAQ nodes): letters,
/// digits, `_` and `-`, as the checks of those ids accept.
pub const TOPIC_SEGMENT: &str = "^[A-Za-z0-9_-]+$";

/// `exclusiveMinimum: 0` on a number: the check `require_positive` (finite and > 0).
pub fn positive(schema: &mut Schema) {
    schema.insert("exclusiveMinimum".into(), 0.into());
}

/// `exclusiveMaximum: limit` on a number (`damping_ratio < 1`).
pub fn below(limit: f64) -> impl FnMut(&mut Schema) {
    move |schema: &mut Schema| {
        schema.insert("exclusiveMaximum".into(), limit.into());
    }
}

/// `exclusiveMinimum: limit` on a number (`gain_error > -1`).
pub fn above(limit: f64) -> impl FnMut(&mut Schema) {
    move |schema: &mut Schema| {
        schema.insert("exclusiveMinimum".into(), limit.into());
    }
}

/// [`positive`] on each item of an array (`axle_spacing_m = [4.5, 1.35]`).
pub fn positive_items(schema: &mut Schema) {
    on_items(schema, "exclusiveMinimum");
}

/// `minimum: 0` on each item of an array (`require_non_negative` per axle).
pub fn non_negative_items(schema: &mut Schema) {
    on_items(schema, "minimum");
}

fn on_items(schema: &mut Schema, bound: &str) {
    if let Some(items) = schema.get_mut("items").and_then(Value::as_object_mut) {
        items.insert(bound.into(), 0.into());
    }
}

/// An object that must have exactly one of the keys `names` (`oneOf` of `required`): a
/// bridge's `span_m` or `spans_m`.
pub fn exactly_one_key(names: &'static [&'static str]) -> impl FnMut(&mut Schema) {
    move |schema: &mut Schema| {
        let choices: Vec<Value> = names
            .iter()
            .map(|&n| serde_json::json!({ "required": [n] }))
            .collect();
        schema.insert("oneOf".into(), choices.into());
    }
}

/// A string that must be one of `names` (`enum`), for checks that look a name up in a
/// list (`COST323_CLASS_NAMES`).
pub fn one_of(names: &'static [&'static str]) -> impl FnMut(&mut Schema) {
    move |schema: &mut Schema| {
        schema.insert("enum".into(), names.into());
    }
}

/// A table whose keys must be among `names` (`propertyNames`): class shares by name.
pub fn keys_among(names: Vec<&'static str>) -> impl FnMut(&mut Schema) {
    move |schema: &mut Schema| {
        let names: Vec<Value> = names.iter().map(|&n| n.into()).collect();
        schema.insert("propertyNames".into(), serde_json::json!({ "enum": names }));
    }
}

/// [`one_of`] `names`, plus [`CHOICES_KEY`] with the values `lookup` gives each name (a
/// preset's parameters), so that the reference can show what a preset sets.
pub fn named_choices<T: Serialize>(
    names: &'static [&'static str],
    lookup: impl Fn(&str) -> Option<T>,
) -> impl FnMut(&mut Schema) {
    move |schema: &mut Schema| {
        let mut choices = Map::new();
        for &name in names {
            // A preset serializes to a table of plain numbers; a failure would be a bug in
            // the preset table, and it then only goes unlisted.
            if let Some(value) = lookup(name).and_then(|v| serde_json::to_value(v).ok()) {
                choices.insert(name.into(), value);
            }
        }
        schema.insert("enum".into(), names.into());
        schema.insert(CHOICES_KEY.into(), Value::Object(choices));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn item_bounds_land_on_the_items() {
        let mut schema = schemars::json_schema!({ "type": "array", "items": { "type": "number" } });
        positive_items(&mut schema);
        assert_eq!(schema.get("items").unwrap()["exclusiveMinimum"], 0);
        non_negative_items(&mut schema);
        assert_eq!(schema.get("items").unwrap()["minimum"], 0);
        let mut scalar = schemars::json_schema!({ "type": "number" });
        positive(&mut scalar);
        below(1.0)(&mut scalar);
        assert_eq!(scalar.get("exclusiveMinimum").unwrap(), 0);
        assert_eq!(scalar.get("exclusiveMaximum").unwrap(), 1.0);
    }

    #[test]
    fn choices_list_each_name_with_its_values() {
        let mut schema = schemars::json_schema!({ "type": "string" });
        named_choices(&["light", "heavy", "unknown"], |name| match name {
            "light" => Some(1.0),
            "heavy" => Some(2.0),
            _ => None,
        })(&mut schema);
        assert_eq!(
            schema.get("enum").unwrap(),
            &serde_json::json!(["light", "heavy", "unknown"])
        );
        assert_eq!(
            schema.get(CHOICES_KEY).unwrap(),
            &serde_json::json!({ "light": 1.0, "heavy": 2.0 })
        );
        let mut table = schemars::json_schema!({ "type": "object" });
        keys_among(vec!["car", "truck"])(&mut table);
        assert_eq!(
            table.get("propertyNames").unwrap(),
            &serde_json::json!({ "enum": ["car", "truck"] })
        );
    }
}
