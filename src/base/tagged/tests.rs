use serde::{Deserialize, Serialize};

use super::*;

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(remote = "Self", rename_all = "snake_case", deny_unknown_fields)]
enum Shape {
    Flat,
    Ramp {
        length_m: f64,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        height_m: Option<f64>,
    },
    Nested(Inner),
}
kind_tagged!(Shape);

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct Inner {
    parts: Vec<Shape>,
}

#[derive(Debug, PartialEq, Serialize, Deserialize)]
struct Doc {
    shape: Shape,
}

/// The path `serde_path_to_error` gives plus the one this module adds, and the message.
fn failure(text: &str) -> (String, String) {
    let de = toml::Deserializer::parse(text).unwrap();
    let e = serde_path_to_error::deserialize::<_, Doc>(de).unwrap_err();
    let (inner, message) = split_path(e.inner().message());
    (
        join_path(&dotted(e.path()), inner.unwrap_or("")),
        message.to_string(),
    )
}

#[test]
fn every_kind_of_variant_round_trips_with_kind_first() {
    let doc = Doc {
        shape: Shape::Nested(Inner {
            parts: vec![
                Shape::Flat,
                Shape::Ramp {
                    length_m: 2.0,
                    height_m: None,
                },
                Shape::Ramp {
                    length_m: 3.0,
                    height_m: Some(0.5),
                },
            ],
        }),
    };
    let text = toml::to_string(&doc).unwrap();
    assert_eq!(toml::from_str::<Doc>(&text).unwrap(), doc);
    // The same table serde's `#[serde(tag = "kind")]` writes: the tag first, then
    // the fields in order, skipped fields left out.
    let ramp = toml::to_string(&Doc {
        shape: Shape::Ramp {
            length_m: 3.0,
            height_m: Some(0.5),
        },
    })
    .unwrap();
    assert_eq!(
        ramp,
        "[shape]\nkind = \"ramp\"\nlength_m = 3.0\nheight_m = 0.5\n"
    );
    let flat = toml::to_string(&Doc { shape: Shape::Flat }).unwrap();
    assert_eq!(flat, "[shape]\nkind = \"flat\"\n");
}

#[test]
fn errors_inside_a_variant_name_the_full_path() {
    let (path, message) = failure("shape = { kind = \"ramp\", length_m = 1.0, wings = 2 }");
    assert_eq!(path, "shape.wings");
    assert!(
        message.starts_with("unknown field `wings`, expected"),
        "{message}"
    );
    let (path, message) = failure("shape = { kind = \"ramp\", length_m = \"long\" }");
    assert_eq!(path, "shape.length_m");
    assert!(
        message.starts_with("invalid type: string \"long\""),
        "{message}"
    );
    // Through a newtype variant, a list and a second tagged enum.
    let (path, message) = failure(
        "[shape]\nkind = \"nested\"\nparts = [{ kind = \"flat\" }, \
         { kind = \"ramp\", length_m = 1.0, height_m = [] }]",
    );
    assert_eq!(path, "shape.parts.1.height_m");
    assert!(message.starts_with("invalid type: sequence"), "{message}");
    let (path, message) = failure("[shape]\nkind = \"nested\"\npart = []");
    assert_eq!(path, "shape.part");
    assert!(message.starts_with("unknown field `part`"), "{message}");
}

#[test]
fn tag_errors_name_the_table() {
    let (path, message) = failure("shape = { kind = \"gravel\" }");
    assert_eq!(path, "shape.kind");
    assert!(message.starts_with("unknown variant `gravel`, expected one of `flat`"));
    let (path, message) = failure("shape = { length_m = 1.0 }");
    assert_eq!(
        (path.as_str(), message.as_str()),
        ("shape", "missing field `kind`")
    );
    let (path, message) = failure("shape = { kind = 3 }");
    assert_eq!(path, "shape.kind");
    assert!(
        message.starts_with("invalid type: integer `3`"),
        "{message}"
    );
    let (_, message) = failure("shape = \"flat\"");
    assert!(
        message.starts_with("invalid type: string \"flat\""),
        "{message}"
    );
    let (path, message) = failure("shape = { kind = \"ramp\" }");
    assert_eq!(path, "shape");
    assert_eq!(message, "missing field `length_m`");
}

#[test]
fn a_unit_variant_rejects_other_keys() {
    // Serde's internal tagging would accept and drop `colour` here.
    let (path, message) = failure("shape = { kind = \"flat\", colour = \"red\" }");
    assert_eq!(path, "shape.colour");
    assert!(message.starts_with("unknown field `colour`"), "{message}");
}

#[test]
fn messages_of_other_errors_have_no_path() {
    assert_eq!(split_path("invalid type: map"), (None, "invalid type: map"));
    assert_eq!(split_path("at `a.b`: bad"), (Some("a.b"), "bad"));
    assert_eq!(join_path("", "a"), "a");
    assert_eq!(join_path("a", ""), "a");
    assert_eq!(join_path("a", "b.c"), "a.b.c");
}
