//! The scenario reference (`docs/scenario.md`) rendered from the JSON Schema: one section
//! per table, a row per key (type, unit, default, allowed values, description), a
//! sub-section per `kind` of a tagged table, and the values behind named choices
//! (presets, classes) where the schema lists them.

use std::collections::BTreeMap;
use std::fmt::Write;

use serde_json::{Map, Value};

use super::{CHOICES_KEY, REFERENCE_PATH, SCHEMA_PATH, UNIT_KEY};

/// Defaults longer than this go below the table instead of into its cell.
const LONG_DEFAULT_CHARS: usize = 40;

/// The reference for `schema` (the output of [`super::json_schema`]).
pub fn markdown(schema: &Value) -> String {
    let mut doc = Doc {
        root: schema,
        out: String::new(),
        sections: BTreeMap::new(),
    };
    doc.header();
    if let Some(root) = schema.as_object() {
        doc.table_section("", "## Top level", root);
    }
    doc.out
}

/// A view of one property: its own keywords (`description`, `default`, unit) and those
/// of the type it refers to (`$ref`, or `allOf: [$ref]` with siblings in draft-07).
struct Property<'a> {
    outer: &'a Map<String, Value>,
    inner: &'a Map<String, Value>,
    /// The definition the property refers to, if any.
    definition: Option<&'a str>,
}

/// How a property holds a table.
#[derive(Clone, Copy)]
enum Shape {
    /// `[path]`, or an inline table.
    Table,
    /// `[[path]]`, one table per item.
    ArrayOfTables,
    /// `[path.<name>]`, one table per key the user chooses.
    MapOfTables,
}

struct Doc<'a> {
    root: &'a Value,
    out: String,
    /// The path of the section already written for each definition, so that a type used
    /// in two places is described once.
    sections: BTreeMap<&'a str, String>,
}

impl<'a> Doc<'a> {
    fn header(&mut self) {
        let version = self.root["version"].as_str().unwrap_or("");
        let _ = write!(
            self.out,
            "# Scenario reference\n\n\
             Every key of a scenario file, generated from the scenario types of bridgetwin \
             {version} by `bridgetwin scenario docs > {REFERENCE_PATH}`; do not edit \
             (a test fails when this file and the code disagree). The same description \
             as a JSON Schema (draft-07) is `{SCHEMA_PATH}` (`bridgetwin scenario schema \
             > {SCHEMA_PATH}`).\n\n\
             Editor support: TOML editors that read JSON Schemas (Taplo, and with it the \
             Even Better TOML extension of VS Code; tombi) complete keys, show these descriptions \
             and flag unknown keys, wrong types and out-of-range values when the first \
             line of the scenario names the schema:\n\n\
             ```toml\n#:schema ../docs/scenario.schema.json\n```\n\n\
             (a path relative to the scenario file; every file in `examples/` starts so). \
             `bridgetwin scenario check FILE` checks the rest: what depends on other keys \
             or on the physics (a sensor on the span, a rate that divides the solver \
             rate, the first natural frequency).\n\n\
             Units are in the key names (`span_m`, `rate_hz`, `flexural_rigidity_n_m2`); \
             a tagged table is chosen by its `kind` key (`model = {{ kind = \
             \"finite_element\", elements = 50 }}`).\n"
        );
    }

    /// A definition by its `$ref` (`#/definitions/Name`).
    fn definition(&self, reference: &str) -> Option<(&'a str, &'a Map<String, Value>)> {
        let name = reference.strip_prefix("#/definitions/")?;
        let root: &'a Value = self.root;
        let (key, value) = root["definitions"].as_object()?.get_key_value(name)?;
        Some((key.as_str(), value.as_object()?))
    }

    fn property(&self, outer: &'a Map<String, Value>) -> Property<'a> {
        let reference = outer.get("$ref").and_then(Value::as_str).or_else(|| {
            match outer
                .get("allOf")
                .and_then(Value::as_array)
                .map(Vec::as_slice)
            {
                Some([only]) => only.get("$ref").and_then(Value::as_str),
                _ => None,
            }
        });
        match reference.and_then(|r| self.definition(r)) {
            Some((name, inner)) => Property {
                outer,
                inner,
                definition: Some(name),
            },
            None => Property {
                outer,
                inner: outer,
                definition: None,
            },
        }
    }

    /// `## [path]`, a table of its keys, then the sections of its sub-tables.
    /// `heading` (with its `#`s), the table's description, a row per key, then the sections
    /// of its sub-tables.
    fn table_section(&mut self, path: &str, heading: &str, table: &'a Map<String, Value>) {
        let _ = write!(self.out, "\n{heading}\n\n");
        // The root's description is the schema's own (generated, do not edit): the header
        // of the reference says it.
        if let Some(text) = description(table).filter(|_| !path.is_empty()) {
            let _ = write!(self.out, "{text}\n\n");
        }
        let required = required_keys(table);
        let Some(properties) = table.get("properties").and_then(Value::as_object) else {
            self.out.push_str("No keys.\n");
            return;
        };
        self.out
            .push_str("| key | type | unit | default | allowed | description |\n");
        self.out.push_str("|---|---|---|---|---|---|\n");
        let mut below = Vec::new();
        let mut nested = Vec::new();
        for (key, value) in properties {
            let Some(outer) = value.as_object() else {
                continue;
            };
            let property = self.property(outer);
            let full = join(path, key);
            let default = if required.contains(&key.as_str()) {
                "required".to_string()
            } else {
                match outer
                    .get("default")
                    .or_else(|| property.inner.get("default"))
                {
                    Some(value) => {
                        let shown = toml_value(value);
                        if shown.chars().count() > LONG_DEFAULT_CHARS {
                            below.push(format!("- `{full}` defaults to `{shown}`."));
                            "see below".to_string()
                        } else {
                            format!("`{shown}`")
                        }
                    }
                    None => String::new(),
                }
            };
            let kind = self.type_name(&property, &full);
            let _ = writeln!(
                self.out,
                "| `{key}` | {kind} | {} | {default} | {} | {} |",
                outer.get(UNIT_KEY).and_then(Value::as_str).unwrap_or(""),
                cell(&allowed(self, &property)),
                cell(
                    &description(outer)
                        .or(description(property.inner))
                        .or_else(|| (key == "kind").then(|| "Selects these keys.".into()))
                        .unwrap_or_default()
                ),
            );
            self.choices(&full, &property, &mut below);
            nested.push((full, property));
        }
        if !below.is_empty() {
            let _ = write!(self.out, "\n{}\n", below.join("\n"));
        }
        for (full, property) in nested {
            self.nested_section(&full, &property);
        }
    }

    /// The section of a sub-table, an array of tables or a tagged table at `path`.
    fn nested_section(&mut self, path: &str, property: &Property<'a>) {
        let Some((inner, definition, shape)) = self.table_of(property) else {
            return;
        };
        // The values of a map are tables under a key the user chooses.
        let path = match shape {
            Shape::MapOfTables => format!("{path}.<name>"),
            Shape::Table | Shape::ArrayOfTables => path.to_string(),
        };
        let path = path.as_str();
        if let Some(name) = definition {
            if self.sections.contains_key(name) {
                return;
            }
            self.sections.insert(name, path.to_string());
        }
        let title = match shape {
            Shape::ArrayOfTables => format!("`[[{path}]]`"),
            Shape::Table | Shape::MapOfTables => format!("`[{path}]`"),
        };
        if let Some(variants) = tagged_variants(inner) {
            let _ = write!(self.out, "\n## {title}\n\n");
            if let Some(text) = description(inner) {
                let _ = write!(self.out, "{text}\n\n");
            }
            let kinds: Vec<String> = variants.iter().map(|(k, _)| format!("`{k}`")).collect();
            let _ = writeln!(
                self.out,
                "Chosen by `kind`: {}. Each kind has its own keys:",
                kinds.join(", ")
            );
            for (kind, variant) in variants {
                let heading = format!("### `{path}` with `kind = \"{kind}\"`");
                self.table_section(path, &heading, variant);
            }
        } else {
            self.table_section(path, &format!("## {title}"), inner);
        }
    }

    /// The table a property holds (itself, its array's items, or a map's values), how it
    /// holds it, and the definition it comes from.
    fn table_of(
        &self,
        property: &Property<'a>,
    ) -> Option<(&'a Map<String, Value>, Option<&'a str>, Shape)> {
        let inner = property.inner;
        if is_table(inner) {
            return Some((inner, property.definition, Shape::Table));
        }
        let (held, shape) = match inner.get("type").and_then(Value::as_str) {
            Some("array") => (inner.get("items")?, Shape::ArrayOfTables),
            Some("object") => (inner.get("additionalProperties")?, Shape::MapOfTables),
            _ => return None,
        };
        let held = self.property(held.as_object()?);
        is_table(held.inner).then_some((held.inner, held.definition, shape))
    }

    /// The type column: `number`, `string`, `table`, `array of 2 numbers`, ...
    fn type_name(&self, property: &Property<'a>, path: &str) -> String {
        let inner = property.inner;
        if tagged_variants(inner).is_some() {
            return format!(
                "table (`kind`), see `[{}]`",
                self.section_of(property, path)
            );
        }
        match inner.get("type").and_then(Value::as_str) {
            // Named choices without a type of their own are strings (`oneOf` of constants).
            None if inner.contains_key("oneOf") || inner.contains_key("enum") => "string".into(),
            Some("object") if is_table(inner) => {
                format!("table, see `[{}]`", self.section_of(property, path))
            }
            Some("object") => match inner.get("additionalProperties").and_then(Value::as_object) {
                Some(values) => {
                    let value = self.property(values);
                    if is_table(value.inner) {
                        let section = self.section_of(&value, &format!("{path}.<name>"));
                        format!("tables by name, see `[{section}]`")
                    } else {
                        format!("table of {}", plural(&self.type_name(&value, path)))
                    }
                }
                None => "table".into(),
            },
            Some("array") => {
                let items = inner.get("items").and_then(Value::as_object);
                let item = items.map(|i| self.property(i));
                let of = match &item {
                    Some(item) if is_table(item.inner) || tagged_variants(item.inner).is_some() => {
                        let section = self.section_of(item, path);
                        format!("tables, see `[[{section}]]`")
                    }
                    Some(item) => plural(&self.type_name(item, path)),
                    None => "values".into(),
                };
                match (inner.get("minItems"), inner.get("maxItems")) {
                    (Some(min), Some(max)) if min == max => format!("array of {min} {of}"),
                    _ => format!("array of {of}"),
                }
            }
            Some(other) => other.into(),
            None => String::new(),
        }
    }

    /// The path of the section that describes the property's type: its own, or that of
    /// the first place the same type appeared.
    fn section_of(&self, property: &Property<'a>, path: &str) -> String {
        property
            .definition
            .and_then(|name| self.sections.get(name))
            .cloned()
            .unwrap_or_else(|| path.to_string())
    }

    /// The values behind the named choices of a property ([`CHOICES_KEY`]), as a list
    /// below the table.
    fn choices(&self, path: &str, property: &Property<'a>, below: &mut Vec<String>) {
        let Some(choices) = property
            .outer
            .get(CHOICES_KEY)
            .or_else(|| property.inner.get(CHOICES_KEY))
            .and_then(Value::as_object)
        else {
            return;
        };
        below.push(format!("- `{path}`, the values of each choice:"));
        for (name, values) in choices {
            let shown = match values.as_object() {
                Some(fields) => fields
                    .iter()
                    .map(|(k, v)| format!("{k} = {}", toml_value(v)))
                    .collect::<Vec<_>>()
                    .join(", "),
                None => toml_value(values),
            };
            below.push(format!("  - `{name}`: `{shown}`"));
        }
    }
}

/// The allowed-values column: enums, `kind` constants, numeric bounds, item counts,
/// patterns, formats, and the keys and values of a map.
fn allowed(doc: &Doc<'_>, property: &Property<'_>) -> String {
    let inner = property.inner;
    if let Some(variants) = tagged_variants(inner) {
        let kinds: Vec<String> = variants.iter().map(|(k, _)| format!("`{k}`")).collect();
        return format!("kind: {}", kinds.join(", "));
    }
    if let Some(values) = enum_values(inner) {
        return values;
    }
    if let Some(value) = inner.get("const") {
        return format!("`{}`", toml_value(value));
    }
    let mut parts = vec![bounds(inner)];
    match inner.get("type").and_then(Value::as_str) {
        Some("array") => {
            if let Some(items) = inner.get("items").and_then(Value::as_object) {
                let item = doc.property(items);
                match enum_values(item.inner) {
                    Some(values) => parts.push(format!("each {values}")),
                    None => parts.push(format!("each {}", bounds(item.inner))),
                }
            }
            let count = |key: &str| inner.get(key).and_then(Value::as_u64);
            match (count("minItems"), count("maxItems")) {
                // The type column says "array of N".
                (Some(min), Some(max)) if min == max => {}
                (Some(min), Some(max)) => parts.push(format!("{min} to {max} items")),
                (Some(min), None) => parts.push(format!("at least {min}")),
                (None, Some(max)) => parts.push(format!("at most {max}")),
                (None, None) => {}
            }
        }
        Some("object") => {
            if let Some(Value::Object(names)) = inner.get("propertyNames") {
                if let Some(values) = enum_values(names) {
                    parts.push(format!("keys {values}"));
                }
            }
            if let Some(Value::Object(values)) = inner.get("additionalProperties") {
                parts.push(format!("values {}", bounds(values)));
            }
        }
        _ => {}
    }
    match inner.get("pattern").and_then(Value::as_str) {
        Some(r"\S") => parts.push("not blank".into()),
        Some(pattern) => parts.push(format!("matches `{pattern}`")),
        None => {}
    }
    if inner.get("format").and_then(Value::as_str) == Some("date-time") {
        parts.push("RFC 3339 date-time".into());
    }
    parts.retain(|p| !p.is_empty() && p != "each " && p != "values ");
    parts.join("; ")
}

/// `"a"`, `"b"` of an `enum` or a `oneOf` of string constants, with their descriptions.
fn enum_values(schema: &Map<String, Value>) -> Option<String> {
    if let Some(Value::Array(values)) = schema.get("enum") {
        let shown: Vec<String> = values
            .iter()
            .map(|v| format!("`{}`", toml_value(v)))
            .collect();
        return Some(shown.join(", "));
    }
    let alternatives = schema.get("oneOf")?.as_array()?;
    let shown: Option<Vec<String>> = alternatives
        .iter()
        .map(|a| {
            let value = a.get("const").or_else(|| match a.get("enum") {
                Some(Value::Array(v)) if v.len() == 1 => v.first(),
                _ => None,
            })?;
            let text = a.get("description").and_then(Value::as_str);
            Some(match text {
                Some(text) => format!("`{}` ({})", toml_value(value), text.trim_end_matches('.')),
                None => format!("`{}`", toml_value(value)),
            })
        })
        .collect();
    shown.map(|s| s.join(", "))
}

/// `> 0`, `[1, 5000]`, `>= 0, < 1`: the numeric bounds of a schema.
fn bounds(schema: &Map<String, Value>) -> String {
    let num = |key: &str| schema.get(key).filter(|v| v.is_number()).map(toml_value);
    let low = num("exclusiveMinimum")
        .map(|v| (v, false))
        .or_else(|| num("minimum").map(|v| (v, true)));
    let high = num("exclusiveMaximum")
        .map(|v| (v, false))
        .or_else(|| num("maximum").map(|v| (v, true)));
    match (low, high) {
        (Some((lo, lo_in)), Some((hi, hi_in))) => format!(
            "{}{lo}, {hi}{}",
            if lo_in { "[" } else { "(" },
            if hi_in { "]" } else { ")" }
        ),
        (Some((lo, true)), None) => format!(">= {lo}"),
        (Some((lo, false)), None) => format!("> {lo}"),
        (None, Some((hi, true))) => format!("<= {hi}"),
        (None, Some((hi, false))) => format!("< {hi}"),
        (None, None) => String::new(),
    }
}

/// The variants of a `kind`-tagged table: `oneOf` of objects whose `kind` is a constant.
fn tagged_variants(schema: &Map<String, Value>) -> Option<Vec<(&str, &Map<String, Value>)>> {
    let alternatives = schema.get("oneOf")?.as_array()?;
    alternatives
        .iter()
        .map(|a| {
            let variant = a.as_object()?;
            let kind = variant
                .get("properties")?
                .get("kind")?
                .get("const")?
                .as_str()?;
            Some((kind, variant))
        })
        .collect()
}

fn is_table(schema: &Map<String, Value>) -> bool {
    schema.get("type").and_then(Value::as_str) == Some("object")
        && schema.contains_key("properties")
        || tagged_variants(schema).is_some()
}

fn required_keys(schema: &Map<String, Value>) -> Vec<&str> {
    match schema.get("required") {
        Some(Value::Array(keys)) => keys.iter().filter_map(Value::as_str).collect(),
        _ => Vec::new(),
    }
}

fn description(schema: &Map<String, Value>) -> Option<String> {
    schema
        .get("description")
        .and_then(Value::as_str)
        .map(|d| d.split_whitespace().collect::<Vec<_>>().join(" "))
}

/// Text fit for a table cell: one line, `|` escaped.
fn cell(text: &str) -> String {
    text.replace('|', "\\|")
}

fn plural(kind: &str) -> String {
    match kind {
        "" => "values".into(),
        k if k.ends_with('s') => k.into(),
        k => format!("{k}s"),
    }
}

fn join(path: &str, key: &str) -> String {
    if path.is_empty() {
        key.to_string()
    } else {
        format!("{path}.{key}")
    }
}

/// A JSON value as it is written in TOML: strings quoted, tables inline.
fn toml_value(value: &Value) -> String {
    match value {
        Value::String(s) => format!("\"{s}\""),
        Value::Array(items) => {
            let shown: Vec<String> = items.iter().map(toml_value).collect();
            format!("[{}]", shown.join(", "))
        }
        Value::Object(fields) => {
            let shown: Vec<String> = fields
                .iter()
                .map(|(k, v)| format!("{k} = {}", toml_value(v)))
                .collect();
            format!("{{ {} }}", shown.join(", "))
        }
        Value::Null => String::new(),
        other => other.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bounds_read_as_intervals() {
        let schema = |v: Value| v.as_object().cloned().unwrap();
        let b = |v: Value| bounds(&schema(v));
        assert_eq!(b(serde_json::json!({ "exclusiveMinimum": 0 })), "> 0");
        assert_eq!(b(serde_json::json!({ "minimum": 0 })), ">= 0");
        assert_eq!(
            b(serde_json::json!({ "minimum": 1, "maximum": 5000 })),
            "[1, 5000]"
        );
        assert_eq!(
            b(serde_json::json!({ "minimum": 0, "exclusiveMaximum": 1 })),
            "[0, 1)"
        );
        assert_eq!(b(serde_json::json!({ "type": "number" })), "");
    }

    #[test]
    fn values_are_written_as_toml() {
        let v = serde_json::json!({ "kind": "modal", "modes": 4, "band": [0.5, 30.0] });
        assert_eq!(
            toml_value(&v),
            "{ kind = \"modal\", modes = 4, band = [0.5, 30.0] }"
        );
    }
}
