//! What Foxglove reads from a run: the layout `bridgetwin layout` builds for every
//! example names only topics the file holds and fields their schemas have, and the 3D
//! scene on `/scene` decodes with its embedded schema and holds the bridge, the vehicles
//! at their axles and the sensors (`docs/output.md` sections 3 and 14).
//!
//! The checks read the file with the `mcap` crate and the schemas with `prost-reflect`,
//! independently of the layout builder's own reading.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

use bridgetwin::output::layout::{layout_for_file, LayoutOptions};
use prost_reflect::{DescriptorPool, DynamicMessage, Kind, MessageDescriptor, Value};
use serde_json::Value as Json;

/// Simulates `example` (empty: the default scenario) over `duration_s` into `dir` and
/// returns the file written (the first part of an hourly run).
fn simulate(dir: &Path, example: &str, duration_s: f64) -> PathBuf {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let name = if example.is_empty() {
        "default"
    } else {
        example
    };
    let out = dir.join(format!("{name}.mcap"));
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_bridgetwin"));
    cmd.arg("simulate");
    if !example.is_empty() {
        cmd.arg(root.join("examples").join(format!("{example}.toml")));
    }
    cmd.args(["--duration-s", &duration_s.to_string()]);
    cmd.arg("--out").arg(&out).arg("--force");
    let done = cmd.output().expect("bridgetwin runs");
    assert!(
        done.status.success(),
        "{name}: {}",
        String::from_utf8_lossy(&done.stderr)
    );
    let part = dir.join(format!("{name}-0000.mcap"));
    if part.exists() {
        part
    } else {
        out
    }
}

/// Every example's name (file stem), sorted.
fn examples() -> Vec<String> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .map(|p| p.file_stem().unwrap().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

/// A channel of a file: its message descriptor and message count.
struct Channel {
    descriptor: MessageDescriptor,
    messages: u64,
}

/// The channels of `path` by topic, each with the message type of its embedded schema.
fn channels(bytes: &[u8]) -> BTreeMap<String, Channel> {
    let summary = mcap::Summary::read(bytes).unwrap().expect("a summary");
    let stats = summary.stats.expect("statistics");
    summary
        .channels
        .values()
        .map(|c| {
            let schema = c.schema.as_ref().expect("a schema");
            let pool = DescriptorPool::decode(&*schema.data).unwrap();
            let descriptor = pool.get_message_by_name(&schema.name).unwrap();
            let messages = stats
                .channel_message_counts
                .get(&c.id)
                .copied()
                .unwrap_or(0);
            (
                c.topic.clone(),
                Channel {
                    descriptor,
                    messages,
                },
            )
        })
        .collect()
}

/// Checks one Foxglove message path (`/topic.field[:]{f==1}.sub.@negative`) against the
/// file's channels: the topic exists and holds messages, every field exists in its
/// message type, `[...]` follows a repeated field, filters name fields of the element,
/// the path ends on a number and a modifier, if any, is the last part.
fn check_path(path: &str, channels: &BTreeMap<String, Channel>) -> Result<(), String> {
    let (topic, mut rest) = path.split_at(path.find(['.', '[', '{']).unwrap_or(path.len()));
    let channel = channels.get(topic).ok_or(format!("no topic {topic}"))?;
    if channel.messages == 0 {
        return Err(format!("{topic} holds no message"));
    }
    let mut message = Some(channel.descriptor.clone());
    let mut kind = None;
    let mut repeated = false;
    while !rest.is_empty() {
        if let Some(after) = rest.strip_prefix(".@") {
            let known = ["negative", "abs", "derivative"];
            if !known.contains(&after) {
                return Err(format!("unknown modifier .@{after}"));
            }
            break;
        } else if let Some(after) = rest.strip_prefix('.') {
            let end = after.find(['.', '[', '{']).unwrap_or(after.len());
            let name = &after[..end];
            let m = message
                .as_ref()
                .ok_or(format!("{name}: not inside a message"))?;
            let field = m
                .get_field_by_name(name)
                .ok_or(format!("{} has no field {name}", m.full_name()))?;
            repeated = field.is_list();
            kind = Some(field.kind());
            message = field.kind().as_message().cloned();
            rest = &after[end..];
        } else if let Some(after) = rest.strip_prefix('[') {
            if !repeated {
                return Err(format!(
                    "[...] after a field that is not repeated in {path}"
                ));
            }
            repeated = false;
            let end = after.find(']').ok_or("unclosed [")?;
            rest = &after[end + 1..];
        } else if let Some(after) = rest.strip_prefix('{') {
            let end = after.find('}').ok_or("unclosed {")?;
            let name = after[..end].split("==").next().unwrap_or("");
            let m = message.as_ref().ok_or("a filter outside a message")?;
            if m.get_field_by_name(name).is_none() {
                return Err(format!(
                    "filter on {name}: {} has no such field",
                    m.full_name()
                ));
            }
            rest = &after[end + 1..];
        } else {
            return Err(format!("cannot parse {rest:?}"));
        }
    }
    let numeric = matches!(
        kind,
        Some(Kind::Double | Kind::Float | Kind::Uint32 | Kind::Int32 | Kind::Uint64 | Kind::Int64)
    );
    if !numeric {
        return Err(format!("{path} does not end on a number ({kind:?})"));
    }
    Ok(())
}

/// Every topic a panel of `layout` names, with the check it failed, if any.
fn check_layout(layout: &Json, channels: &BTreeMap<String, Channel>) -> Vec<String> {
    let mut problems = Vec::new();
    let configs = layout["configById"].as_object().expect("configById");
    let topic_of = |topic: &str, schema: &str| -> Result<(), String> {
        let c = channels.get(topic).ok_or(format!("no topic {topic}"))?;
        if c.descriptor.full_name() != schema {
            return Err(format!(
                "{topic} is {}, not {schema}",
                c.descriptor.full_name()
            ));
        }
        if c.messages == 0 {
            return Err(format!("{topic} holds no message"));
        }
        Ok(())
    };
    for (id, config) in configs {
        let outcome = match id.split('!').next().unwrap_or("") {
            "Plot" => config["paths"]
                .as_array()
                .expect("paths")
                .iter()
                .try_for_each(|p| check_path(p["value"].as_str().expect("value"), channels)),
            "RosOut" => topic_of(
                config["topicToRender"].as_str().unwrap_or(""),
                "foxglove.Log",
            ),
            "Table" => {
                let path = config["topicPath"].as_str().unwrap_or("");
                topic_of(path, "bridgetwin.v1.WimRecord")
            }
            "3D" => config["topics"]
                .as_object()
                .expect("topics")
                .keys()
                .try_for_each(|t| topic_of(t, "foxglove.SceneUpdate")),
            other => Err(format!("unexpected panel type {other}")),
        };
        if let Err(e) = outcome {
            problems.push(format!("{id}: {e}"));
        }
    }
    // Every panel placed in the mosaic has a configuration, and the other way round.
    fn leaves(node: &Json, out: &mut Vec<String>) {
        match node {
            Json::String(id) => out.push(id.clone()),
            Json::Object(split) => {
                leaves(&split["first"], out);
                leaves(&split["second"], out);
            }
            _ => out.push(format!("{node:?}")),
        }
    }
    let mut placed = Vec::new();
    leaves(&layout["layout"], &mut placed);
    placed.sort();
    // Sorted: the key order of a JSON object is not part of the layout (serde_json keeps
    // insertion order when another crate enables its `preserve_order`).
    let mut configured: Vec<String> = configs.keys().cloned().collect();
    configured.sort();
    if placed != configured {
        problems.push(format!("mosaic {placed:?} vs configured {configured:?}"));
    }
    problems
}

/// Panel ids of `layout`, sorted.
fn panel_ids(layout: &Json) -> Vec<String> {
    layout["configById"]
        .as_object()
        .unwrap()
        .keys()
        .cloned()
        .collect()
}

#[test]
fn the_layout_of_every_example_names_only_topics_and_fields_of_its_file() {
    let dir = tempfile::tempdir().unwrap();
    let names = examples();
    assert!(names.len() >= 7, "{names:?}");
    // The default run crosses a vehicle in its own duration; the examples run 20 s (the
    // ambient one 70 s, so that its first truck, at 60 s, is on the bridge).
    let runs = std::iter::once((String::new(), 20.0)).chain(names.iter().map(|n| {
        let duration = if n == "ambient_monitoring" {
            70.0
        } else {
            20.0
        };
        (n.clone(), duration)
    }));
    for (example, duration_s) in runs {
        let file = simulate(dir.path(), &example, duration_s);
        let bytes = std::fs::read(&file).unwrap();
        let channels = channels(&bytes);
        let layout = layout_for_file(&file, &LayoutOptions::default())
            .unwrap_or_else(|e| panic!("{example}: {e}"));
        let problems = check_layout(&layout.json, &channels);
        assert!(problems.is_empty(), "{example}: {problems:#?}");
        let ids = panel_ids(&layout.json);
        // Every run has sensors, the shape, the events and the scene.
        for id in ["3D!scene", "Plot!shape", "RosOut!events"] {
            assert!(ids.iter().any(|i| i == id), "{example}: {id} in {ids:?}");
        }
        assert!(
            ids.iter().any(|i| i == "Plot!accel" || i == "Plot!disp"),
            "{example}: {ids:?}"
        );
        // A station that has recorded nothing yet gets no table (it would stay empty).
        let has_wim = channels
            .iter()
            .any(|(t, c)| t.starts_with("/wim/") && c.messages > 0);
        assert_eq!(
            ids.iter().any(|i| i.starts_with("Table!wim")),
            has_wim,
            "{example}"
        );
        // Block-layout runs are plotted from their preview, sample-layout runs from their
        // sensor topics; either way both measured and truth.
        let block = channels.keys().any(|t| t.starts_with("/preview/"));
        let accel = &layout.json["configById"]["Plot!accel"];
        if let Some(paths) = accel["paths"].as_array() {
            let values: Vec<&str> = paths.iter().map(|p| p["value"].as_str().unwrap()).collect();
            let (measured, truth) = match block {
                true => ("/preview/accel/", "/preview/truth/"),
                false => ("/sensors/accel/", "/truth/sensors/"),
            };
            assert!(
                values.iter().any(|v| v.starts_with(measured)),
                "{example}: {values:?}"
            );
            assert!(
                values.iter().any(|v| v.starts_with(truth)),
                "{example}: {values:?}"
            );
        }
        // The shape is plotted by index in a fixed range around the run's peak.
        let shape = &layout.json["configById"]["Plot!shape"];
        assert_eq!(shape["xAxisVal"], "index", "{example}");
        let (lo, hi) = (shape["minYValue"].as_f64(), shape["maxYValue"].as_f64());
        assert!(
            matches!((lo, hi), (Some(lo), Some(hi)) if lo < 0.0 && hi > 0.0),
            "{example}"
        );
    }
}

#[test]
fn a_wrong_path_fails_the_check() {
    // The checker itself must catch a missing topic, a missing field, a filter on a field
    // the element lacks, and a path ending on a message.
    let dir = tempfile::tempdir().unwrap();
    let file = simulate(dir.path(), "", 5.0);
    let channels = channels(&std::fs::read(&file).unwrap());
    assert!(check_path(
        "/truth/axle_loads.axles[:]{vehicle_id==1}.force_n",
        &channels
    )
    .is_ok());
    for bad in [
        "/truth/nothing.force_n",
        "/truth/axle_loads.axles[:].forces_n",
        "/truth/axle_loads.axles[:]{vehicle==1}.force_n",
        "/truth/axle_loads.axles[:]",
        "/truth/bridge.midspan_deflection_m[:]",
        "/truth/bridge.deflection_m[:].@negate",
    ] {
        assert!(check_path(bad, &channels).is_err(), "{bad} passed");
    }
}

#[test]
fn layout_command_writes_json_and_names_a_missing_vehicle() {
    let dir = tempfile::tempdir().unwrap();
    let file = simulate(dir.path(), "two_trucks", 20.0);
    let run = |args: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_bridgetwin"))
            .arg("layout")
            .arg(&file)
            .args(args)
            .output()
            .unwrap()
    };
    let out = run(&[]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let layout: Json = serde_json::from_slice(&out.stdout).unwrap();
    let ids = panel_ids(&layout);
    assert!(ids.contains(&"Plot!axles_0".to_string()), "{ids:?}");
    let title = layout["configById"]["Plot!axles_1"]["foxglovePanelTitle"]
        .as_str()
        .unwrap();
    assert!(title.starts_with("Vehicle 2:"), "{title}");
    let chosen_path = dir.path().join("chosen.json");
    let chosen = run(&["--vehicle", "2", "--out", chosen_path.to_str().unwrap()]);
    assert!(chosen.status.success());
    let chosen: Json = serde_json::from_slice(&std::fs::read(&chosen_path).unwrap()).unwrap();
    let ids = panel_ids(&chosen);
    assert!(
        ids.contains(&"Plot!axles_0".to_string()) && !ids.contains(&"Plot!axles_1".to_string())
    );
    let title = chosen["configById"]["Plot!axles_0"]["foxglovePanelTitle"]
        .as_str()
        .unwrap();
    assert!(title.starts_with("Vehicle 2:"), "{title}");
    let out = run(&["--vehicle", "99"]);
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("--vehicle = 99") && stderr.contains("1, 2"),
        "{stderr}"
    );
}

/// Every `/scene` message of `bytes`, decoded with the file's schema, with its log time.
fn scene_messages(bytes: &[u8]) -> Vec<(u64, DynamicMessage)> {
    let mut out = Vec::new();
    for message in mcap::MessageStream::new(bytes).unwrap() {
        let message = message.unwrap();
        if message.channel.topic != "/scene" {
            continue;
        }
        let schema = message.channel.schema.as_ref().unwrap();
        assert_eq!(schema.name, "foxglove.SceneUpdate");
        let pool = DescriptorPool::decode(&*schema.data).unwrap();
        let descriptor = pool.get_message_by_name(&schema.name).unwrap();
        out.push((
            message.log_time,
            DynamicMessage::decode(descriptor, &*message.data).unwrap(),
        ));
    }
    out
}

fn list(message: &DynamicMessage, field: &str) -> Vec<Value> {
    match message.get_field_by_name(field).map(|v| v.into_owned()) {
        Some(Value::List(items)) => items,
        other => panic!("{field}: {other:?}"),
    }
}

fn message_field(message: &DynamicMessage, field: &str) -> DynamicMessage {
    match message.get_field_by_name(field).map(|v| v.into_owned()) {
        Some(Value::Message(m)) => m,
        other => panic!("{field}: {other:?}"),
    }
}

fn f64_of(message: &DynamicMessage, field: &str) -> f64 {
    message.get_field_by_name(field).unwrap().as_f64().unwrap()
}

fn str_of(message: &DynamicMessage, field: &str) -> String {
    message
        .get_field_by_name(field)
        .unwrap()
        .as_str()
        .unwrap()
        .to_string()
}

/// The x of a primitive's pose.
fn pose_x(primitive: &DynamicMessage) -> f64 {
    f64_of(
        &message_field(&message_field(primitive, "pose"), "position"),
        "x",
    )
}

#[test]
fn scene_messages_decode_and_hold_the_bridge_the_vehicles_and_the_sensors() {
    let dir = tempfile::tempdir().unwrap();
    let file = simulate(dir.path(), "", 8.0);
    let bytes = std::fs::read(&file).unwrap();
    let summary = mcap::Summary::read(&bytes).unwrap().unwrap();
    let scene_channel = summary
        .channels
        .values()
        .find(|c| c.topic == "/scene")
        .unwrap();
    let factor: f64 = scene_channel.metadata["exaggeration"].parse().unwrap();
    assert!(factor >= 1.0);
    // The truth the scene is drawn from, by log time.
    let mut shapes = BTreeMap::new();
    let mut axles: BTreeMap<u64, Vec<(u32, u32, f64)>> = BTreeMap::new();
    let mut sensors = 0;
    for c in summary.channels.values() {
        sensors += usize::from(c.topic.starts_with("/truth/sensors/"));
    }
    for message in mcap::MessageStream::new(&bytes).unwrap() {
        let message = message.unwrap();
        let t = message.log_time;
        match message.channel.topic.as_str() {
            "/truth/bridge" => {
                let state: bridgetwin::output::proto::v1::BridgeState =
                    prost::Message::decode(&*message.data).unwrap();
                shapes.insert(t, state);
            }
            "/truth/axle_loads" => {
                let loads: bridgetwin::output::proto::v1::AxleLoads =
                    prost::Message::decode(&*message.data).unwrap();
                let list = loads
                    .axles
                    .iter()
                    .map(|a| (a.vehicle_id, a.axle_index, a.position_m));
                axles.insert(t, list.collect());
            }
            _ => {}
        }
    }
    let scenes = scene_messages(&bytes);
    // Every second deflected shape (20 Hz shapes, 10 Hz scene), the modal state at the
    // start not counted: 8 s -> shapes at 0, 0.05, ..., 8 s = 161, scenes 81.
    assert_eq!(scenes.len(), 81);
    let mut vehicles_seen = 0;
    for (t, scene) in &scenes {
        let deletions = list(scene, "deletions");
        assert_eq!(deletions.len(), 1, "the whole scene is replaced each time");
        let entities: BTreeMap<String, DynamicMessage> = list(scene, "entities")
            .into_iter()
            .map(|e| {
                let e = e.as_message().unwrap().clone();
                (str_of(&e, "id"), e)
            })
            .collect();
        for e in entities.values() {
            assert_eq!(str_of(e, "frame_id"), "bridge");
        }
        // The deck: two points per shape node, at -factor x the deflection of the shape
        // of the same instant (rounded to 1/1024 m: half a step at most).
        let deck = &entities["deck"];
        let triangles = list(deck, "triangles");
        let points = list(triangles[0].as_message().unwrap(), "points");
        let shape = shapes.range(..=*t).next_back().unwrap().1;
        assert_eq!(points.len(), 2 * shape.deflection_m.len(), "t = {t}");
        for (i, w) in shape.deflection_m.iter().enumerate() {
            let p = points[2 * i].as_message().unwrap();
            assert_eq!(f64_of(p, "x"), shape.node_position_m[i]);
            let drawn = -factor * w;
            assert!(
                (f64_of(p, "z") - drawn).abs() <= 0.5 / 1024.0 + 1e-12,
                "node {i}"
            );
        }
        let metadata = list(deck, "metadata");
        let key = |kv: &Value| str_of(kv.as_message().unwrap(), "key");
        assert!(metadata.iter().any(|kv| key(kv) == "exaggeration"));
        assert_eq!(list(&entities["supports"], "cylinders").len(), 2);
        assert_eq!(list(&entities["sensors"], "spheres").len(), sensors);
        // Each vehicle near the bridge stands at its axles of the same instant.
        let now = axles
            .range(..=*t)
            .next_back()
            .map(|(_, a)| a.clone())
            .unwrap_or_default();
        let mut by_vehicle: BTreeMap<u32, Vec<f64>> = BTreeMap::new();
        for (vehicle, _, x) in now {
            by_vehicle.entry(vehicle).or_default().push(x);
        }
        for (vehicle, xs) in by_vehicle {
            let near = xs.iter().any(|&x| (-15.0..=45.0).contains(&x));
            let Some(entity) = entities.get(&format!("vehicle/{vehicle}")) else {
                assert!(!near, "vehicle {vehicle} near the bridge at {t} not drawn");
                continue;
            };
            vehicles_seen += 1;
            let wheels: Vec<f64> = list(entity, "cylinders")
                .iter()
                .map(|c| pose_x(c.as_message().unwrap()))
                .collect();
            assert_eq!(wheels, xs, "vehicle {vehicle} at {t}");
            assert_eq!(list(entity, "cubes").len(), 1, "one body");
        }
    }
    assert!(
        vehicles_seen > 10,
        "the default truck crosses: {vehicles_seen}"
    );
}
