//! Scenario syntax: malformed TOML, unknown keys and variants, wrong types, missing
//! fields, unreadable files, bad start times.

use super::harness::{
    Case,
    Edit::{Remove, Set, Text},
};

pub(super) fn syntax_cases() -> Vec<Case> {
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
            &["scenario.toml: sensors.3[A4].gain: unknown field `gain`"],
        ),
        Case::edit(
            "unknown key in a vehicle model",
            &[Set("vehicles.0.model.wings", "2")],
            &["scenario.toml: vehicles.0[1].model.wings: unknown field `wings`"],
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
                "scenario.toml: sensors.0[7].id: invalid type: integer `7`, expected a string",
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
            &["bridge = (no span) needs span_m (one span) or spans_m"],
        ),
        Case::edit(
            "missing table: [bridge]",
            &[Remove("bridge")],
            &["scenario.toml", "missing field `bridge`"],
        ),
        Case::edit(
            "missing field: vehicles[0].speed_m_s",
            &[Remove("vehicles.0.speed_m_s")],
            &["scenario.toml: vehicles.0[1]: missing field `speed_m_s`"],
        ),
        Case::edit(
            "unknown variant: sensor kind",
            &[Set("sensors.0.kind", "\"anemometer\"")],
            &["scenario.toml: sensors.0[A1].kind: unknown variant `anemometer`"],
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
