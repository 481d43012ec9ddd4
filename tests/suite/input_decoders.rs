//! The readers decode every field of the output contract: for each message
//! type with a decoder, every field of its schema (from the descriptors embedded in the
//! binary, so a field added to a `.proto` is seen here) is a column of what the decoder
//! gives, by the naming rules of `tools/read_run.py`: a field by its name, a Timestamp
//! `f` as `f_ns`, a repeated or nested message `f` as `f.<field>`, a block's `values` as
//! the quantity's column. The few fields that are not columns are listed with the
//! reason. An empty topic still has its columns (`Decoder::empty_table`).

use std::collections::BTreeSet;

use prost::Message;
use prost_types::field_descriptor_proto::Type;
use prost_types::{DescriptorProto, FileDescriptorSet};

use bridgetwin::input::Decoder;
use bridgetwin::output::ALL_DESCRIPTORS;

/// Fields that are not columns, and why.
const NOT_COLUMNS: &[(&str, &str, &str)] = &[
    (
        "bridgetwin.v1.SampleBlock",
        "sample_period_ns",
        "gives each sample's time",
    ),
    (
        "bridgetwin.v1.SampleBlock",
        "quantity",
        "names the value column",
    ),
    (
        "bridgetwin.v1.SampleBlock",
        "unit",
        "is in the value column's name",
    ),
    (
        "bridgetwin.v1.SensorTruthBlock",
        "sample_period_ns",
        "gives each sample's time",
    ),
];

fn messages() -> Vec<(String, DescriptorProto)> {
    let set = FileDescriptorSet::decode(ALL_DESCRIPTORS).unwrap();
    let mut out = Vec::new();
    for file in set.file {
        let package = file.package().to_string();
        for message in file.message_type {
            out.push((format!("{package}.{}", message.name()), message));
        }
    }
    out
}

/// The column names a field must give.
fn expected_columns(
    all: &[(String, DescriptorProto)],
    message: &str,
    prefix: &str,
    field: &prost_types::FieldDescriptorProto,
) -> Vec<String> {
    let name = format!("{prefix}{}", field.name());
    if field.r#type() != Type::Message {
        if message == "bridgetwin.v1.SampleBlock" && field.name() == "values" {
            return vec!["acceleration_m_s2".into()];
        }
        return vec![name];
    }
    let type_name = field.type_name().trim_start_matches('.');
    if type_name == "google.protobuf.Timestamp" {
        return vec![format!("{name}_ns")];
    }
    if type_name.ends_with("Entry") {
        // A map: one column `name.<key>` per key, so none without messages (the map's
        // decoding is tested in `a_map_field_gives_a_column_per_key`).
        return vec![format!("map {message}.{}", field.name())];
    }
    let (_, nested) = all
        .iter()
        .find(|(n, _)| n == type_name)
        .unwrap_or_else(|| panic!("{message}.{}: type {type_name} not found", field.name()));
    nested
        .field
        .iter()
        .flat_map(|f| expected_columns(all, type_name, &format!("{name}."), f))
        .collect()
}

#[test]
fn every_schema_field_is_a_column() {
    let all = messages();
    let mut checked = 0;
    let mut decoders = 0;
    let mut maps = Vec::new();
    for (full_name, message) in &all {
        let Some(decoder) = Decoder::for_schema(full_name) else {
            continue;
        };
        decoders += 1;
        let table = decoder.empty_table(Some("m/s^2"));
        assert_eq!(table.rows, 0, "{full_name}");
        let columns: BTreeSet<&str> = table.columns.iter().map(|c| c.name.as_str()).collect();
        assert!(columns.contains("log_time_ns"), "{full_name}: {columns:?}");
        for field in &message.field {
            if NOT_COLUMNS
                .iter()
                .any(|(m, f, _)| m == full_name && *f == field.name())
            {
                continue;
            }
            for want in expected_columns(&all, full_name, "", field) {
                if let Some(map) = want.strip_prefix("map ") {
                    maps.push(map.to_string());
                    continue;
                }
                assert!(
                    columns.contains(want.as_str()),
                    "{full_name}.{}: no column {want}; columns {columns:?}",
                    field.name()
                );
                checked += 1;
            }
        }
    }
    assert_eq!(maps, ["bridgetwin.v1.VehicleTruth.parameters"]);
    // The 18 top-level bridgetwin.v1 messages (ContactPoint is nested in VehicleState)
    // and foxglove.Log (the events).
    assert_eq!(decoders, 19, "message types with a decoder");
    assert!(checked > 60, "{checked} fields checked");
}

#[test]
fn the_exceptions_are_real_fields() {
    let all = messages();
    for (message, field, _) in NOT_COLUMNS {
        let (_, m) = all.iter().find(|(n, _)| n == message).unwrap();
        assert!(
            m.field.iter().any(|f| f.name() == *field),
            "{message}.{field}"
        );
    }
}

#[test]
fn an_empty_block_topic_names_its_value_column_from_its_unit() {
    let block = Decoder::for_schema("bridgetwin.v1.SampleBlock").unwrap();
    for (unit, column) in [
        ("m/s^2", "acceleration_m_s2"),
        ("microstrain", "strain_microstrain"),
        ("m", "displacement_m"),
    ] {
        let table = block.empty_table(Some(unit));
        let names: Vec<&str> = table.columns.iter().map(|c| c.name.as_str()).collect();
        assert_eq!(names, ["log_time_ns", "timestamp_ns", column]);
    }
}

#[test]
fn a_map_field_gives_a_column_per_key() {
    use bridgetwin::input::TableBuilder;
    use bridgetwin::output::proto::v1::VehicleTruth;
    let vehicle = VehicleTruth {
        parameters: [
            ("sprung_mass_kg".to_string(), 17_500.0),
            ("k_tyre_n_m".to_string(), 1.75e6),
        ]
        .into_iter()
        .collect(),
        ..VehicleTruth::default()
    };
    let mut builder = TableBuilder::default();
    Decoder::for_schema("bridgetwin.v1.VehicleTruth")
        .unwrap()
        .decode(&vehicle.encode_to_vec(), 1, &mut builder)
        .unwrap();
    let table = builder.build();
    assert_eq!(
        table.f64s("parameters.sprung_mass_kg"),
        Some(&[17_500.0][..])
    );
    assert_eq!(table.f64s("parameters.k_tyre_n_m"), Some(&[1.75e6][..]));
}
