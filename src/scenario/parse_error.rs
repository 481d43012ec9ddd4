//! Parse errors of a scenario file: `source: path: message`, the path naming listed items
//! by position and id (`sensors.2[A3].rate_hz`), then the toml crate's location, source
//! line and caret on their own lines.

use crate::base::tagged;
use crate::error::{item_path, Error};

/// A TOML error as `source: path: message`, then the toml crate's location, source line
/// and caret on their own lines. `path` is the dotted path where the error occurred
/// (`vehicles.0.model`); a `kind`-tagged enum's message carries the rest of it
/// (`wings`), joined here into `vehicles.0.model.wings`.
pub(super) fn toml_error(
    source: &str,
    path: &str,
    error: &toml::de::Error,
    document: Option<&toml::Table>,
) -> Error {
    let raw_message = error.message().trim_end();
    let (inner_path, message) = tagged::split_path(raw_message);
    let path = tagged::join_path(path, inner_path.unwrap_or(""));
    let path = match document {
        Some(table) => with_item_id(&path, table),
        None => path,
    };
    // The toml crate prints the location and the caret, then the message: the message
    // goes to the first line, after the path.
    let shown = error.to_string();
    let context = shown
        .trim_end()
        .strip_suffix(raw_message)
        .unwrap_or(&shown)
        .trim_end();
    let head = if path.is_empty() {
        message.to_string()
    } else {
        format!("{path}: {message}")
    };
    Error::File {
        path: source.to_string(),
        reason: if context.is_empty() {
            head
        } else {
            format!("{head}\n{context}")
        },
    }
}

/// The lists whose items have an `id`, named in error paths by [`item_path`].
const LISTS_WITH_IDS: [&str; 4] = ["sensors", "daq_nodes", "wim_stations", "vehicles"];

/// `path` with the id of the listed item it starts with, as the resolver's messages name
/// items: `sensors.2.rate_hz` -> `sensors.2[A1].rate_hz` when `[[sensors]]` number 2 has
/// `id = "A1"`. Unchanged when the path starts elsewhere or the item has no id.
fn with_item_id(path: &str, document: &toml::Table) -> String {
    let mut parts = path.splitn(3, '.');
    let (Some(list), Some(index)) = (parts.next(), parts.next()) else {
        return path.to_string();
    };
    let Ok(i) = index.parse::<usize>() else {
        return path.to_string();
    };
    if !LISTS_WITH_IDS.contains(&list) {
        return path.to_string();
    }
    let id = document
        .get(list)
        .and_then(|items| items.get(i))
        .and_then(|item| item.get("id"))
        .and_then(|id| match id {
            toml::Value::String(s) => Some(s.clone()),
            toml::Value::Integer(n) => Some(n.to_string()),
            _ => None,
        });
    let head = item_path(list, i, id.as_deref());
    match parts.next() {
        Some(rest) => format!("{head}.{rest}"),
        None => head,
    }
}

#[cfg(test)]
mod tests {
    use crate::scenario::{Scenario, DEFAULT_SCENARIO_TOML};

    fn parse_error(text: &str) -> String {
        Scenario::from_toml(text, "s.toml").unwrap_err().to_string()
    }

    #[test]
    fn errors_name_the_dotted_path_inside_tagged_enums() {
        let text = DEFAULT_SCENARIO_TOML.replace(
            r#"model = { kind = "half_car", preset = "two_axle_truck" }"#,
            r#"model = { kind = "half_car", preset = "two_axle_truck", wings = 2 }"#,
        );
        assert_ne!(text, DEFAULT_SCENARIO_TOML);
        let msg = parse_error(&text);
        assert!(
            msg.starts_with("s.toml: vehicles.0[1].model.wings: unknown field `wings`, expected"),
            "{msg}"
        );
        // A tagged enum inside a tagged enum (a road feature in an ISO 8608 profile).
        let text = DEFAULT_SCENARIO_TOML.replace(
            r#"profile = { kind = "iso8608", class = "A" }"#,
            r#"profile = { kind = "iso8608", class = "A", features = [{ kind = "step", position_m = 1.0, height_m = "up" }] }"#,
        );
        assert_ne!(text, DEFAULT_SCENARIO_TOML);
        let msg = parse_error(&text);
        assert!(
            msg.starts_with(
                "s.toml: road.profile.features.0.height_m: invalid type: string \"up\", expected f64"
            ),
            "{msg}"
        );
    }

    #[test]
    fn parse_errors_name_listed_items_by_index_and_id() {
        // The default's first sensor is A1.
        let text = DEFAULT_SCENARIO_TOML.replacen("rate_hz = 200.0", "rate_hz = \"fast\"", 1);
        assert_ne!(text, DEFAULT_SCENARIO_TOML);
        let msg = parse_error(&text);
        assert!(
            msg.starts_with("s.toml: sensors.0[A1].rate_hz: invalid type"),
            "{msg}"
        );
        // Items without an id, and paths outside the lists, keep the plain dotted path.
        let mut table: toml::Table = toml::from_str(DEFAULT_SCENARIO_TOML).unwrap();
        let vehicle = table["vehicles"].as_array_mut().unwrap()[0]
            .as_table_mut()
            .unwrap();
        vehicle.remove("id");
        vehicle.insert("wings".into(), toml::Value::Integer(2));
        let msg = parse_error(&toml::to_string(&table).unwrap());
        assert!(
            msg.starts_with("s.toml: vehicles.0.wings: unknown field"),
            "{msg}"
        );
        vehicle_with_id_is_named(&mut table);
    }

    fn vehicle_with_id_is_named(table: &mut toml::Table) {
        let vehicle = table["vehicles"].as_array_mut().unwrap()[0]
            .as_table_mut()
            .unwrap();
        vehicle.insert("id".into(), toml::Value::Integer(7));
        let msg = parse_error(&toml::to_string(&*table).unwrap());
        assert!(
            msg.starts_with("s.toml: vehicles.0[7].wings: unknown field"),
            "{msg}"
        );
    }

    #[test]
    fn toml_errors_keep_the_source_line_and_caret_on_their_own_lines() {
        let text = DEFAULT_SCENARIO_TOML.replace("span_m = 30.0", "span_m = \"thirty\"");
        assert_ne!(text, DEFAULT_SCENARIO_TOML);
        let msg = parse_error(&text);
        let lines: Vec<&str> = msg.lines().collect();
        assert!(
            lines[0].starts_with("s.toml: bridge.span_m: invalid type: string \"thirty\""),
            "{msg}"
        );
        assert!(lines[1].starts_with("TOML parse error at line "), "{msg}");
        // `N | span_m = "thirty"` then the caret under the value.
        let source = lines
            .iter()
            .position(|l| l.ends_with("| span_m = \"thirty\""));
        let source = source.unwrap_or_else(|| panic!("no source line: {msg}"));
        let caret = lines[source + 1];
        let column = lines[source].find("\"thirty\"").unwrap();
        assert_eq!(caret.find('^'), Some(column), "{msg}");
        // The message is not repeated under the caret.
        assert_eq!(msg.matches("invalid type").count(), 1, "{msg}");

        // A syntax error: no path, the same layout.
        let msg = parse_error(&DEFAULT_SCENARIO_TOML.replace("span_m = 30.0", "span_m = = 30.0"));
        let lines: Vec<&str> = msg.lines().collect();
        assert!(!lines[0].contains("TOML parse error"), "{msg}");
        assert!(lines[1].starts_with("TOML parse error at line "), "{msg}");
        assert!(
            lines.iter().any(|l| l.ends_with("| span_m = = 30.0")),
            "{msg}"
        );
        assert!(lines.iter().any(|l| l.trim_end().ends_with('^')), "{msg}");
    }

    #[test]
    fn empty_file_is_named() {
        let e = Scenario::from_toml(" \n# nothing\n", "s.toml").err();
        // A comment-only file is a TOML document without [bridge]: still an error.
        assert!(e.is_some());
        let msg = Scenario::from_toml("\n  \n", "s.toml")
            .unwrap_err()
            .to_string();
        assert!(msg.starts_with("s.toml: is empty"), "{msg}");
    }
}
