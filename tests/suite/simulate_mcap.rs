//! The file `simulate` writes, read back independently: every message decoded through the
//! schema embedded in the file (prost-reflect, not the crate's generated types), the
//! summary statistics against what was read, and the block layout against the sample
//! layout.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

use prost_reflect::{DescriptorPool, DynamicMessage, ReflectMessage, Value};

/// Runs `simulate` on the default scenario with `[output]` lines added.
fn simulate(dir: &Path, name: &str, output_lines: &str) -> PathBuf {
    let text =
        bridgetwin::scenario::DEFAULT_SCENARIO_TOML.replace("layout = \"sample\"", output_lines);
    let scenario = dir.join(format!("{name}.toml"));
    std::fs::write(&scenario, text).unwrap();
    let out = dir.join(format!("{name}.mcap"));
    crate::common::simulate_file(Some(&scenario), &out, 6.0);
    out
}

/// A decoded message with its topic, schema name and log time.
struct Decoded {
    topic: String,
    log_time: u64,
    message: DynamicMessage,
}

/// Decodes every message through its own schema record; checks the summary statistics
/// and that `timestamp` equals `log_time` and log times never decrease.
fn decode_file(path: &Path) -> Vec<Decoded> {
    let bytes = std::fs::read(path).unwrap();
    let summary = mcap::Summary::read(&bytes)
        .unwrap()
        .expect("the file has a summary section");
    let mut pools: BTreeMap<u16, DescriptorPool> = BTreeMap::new();
    let mut decoded = Vec::new();
    let mut counts: BTreeMap<u16, u64> = BTreeMap::new();
    for message in mcap::MessageStream::new(&bytes).unwrap() {
        let message = message.unwrap();
        let schema = message
            .channel
            .schema
            .as_ref()
            .expect("every channel has a schema");
        assert_eq!(schema.encoding, "protobuf");
        assert_eq!(message.channel.message_encoding, "protobuf");
        let pool = pools
            .entry(schema.id)
            .or_insert_with(|| DescriptorPool::decode(&*schema.data).unwrap());
        let descriptor = pool
            .get_message_by_name(&schema.name)
            .unwrap_or_else(|| panic!("{} is in its own descriptor set", schema.name));
        let dynamic = DynamicMessage::decode(descriptor, &*message.data).unwrap();
        assert_eq!(
            timestamp_ns(&dynamic),
            message.log_time,
            "{}: timestamp field vs log_time",
            message.channel.topic
        );
        if let Some(last) = decoded.last() {
            let last: &Decoded = last;
            assert!(last.log_time <= message.log_time, "log time decreased");
        }
        *counts.entry(message.channel.id).or_default() += 1;
        decoded.push(Decoded {
            topic: message.channel.topic.clone(),
            log_time: message.log_time,
            message: dynamic,
        });
    }
    let stats = summary.stats.expect("statistics record");
    assert_eq!(stats.message_count, decoded.len() as u64);
    assert_eq!(stats.channel_message_counts, counts);
    assert_eq!(stats.message_start_time, decoded[0].log_time);
    assert_eq!(stats.message_end_time, decoded.last().unwrap().log_time);
    decoded
}

fn timestamp_ns(message: &DynamicMessage) -> u64 {
    if message.descriptor().full_name() == "foxglove.SceneUpdate" {
        // Foxglove's schema has no timestamp of its own: every entity and deletion has
        // one, and they must all agree.
        let mut stamps = Vec::new();
        for list in ["entities", "deletions"] {
            let Some(Value::List(items)) = message.get_field_by_name(list).map(|v| v.into_owned())
            else {
                panic!("SceneUpdate.{list} is not a list");
            };
            for item in items {
                stamps.push(timestamp_ns(item.as_message().expect("a message")));
            }
        }
        assert!(!stamps.is_empty(), "a scene update with no entity");
        assert!(stamps.iter().all(|&t| t == stamps[0]), "{stamps:?}");
        return stamps[0];
    }
    let Some(Value::Message(ts)) = message
        .get_field_by_name("timestamp")
        .map(|v| v.into_owned())
    else {
        panic!("{} has no timestamp", message.descriptor().full_name());
    };
    let seconds = ts.get_field_by_name("seconds").unwrap().as_i64().unwrap();
    let nanos = ts.get_field_by_name("nanos").unwrap().as_i32().unwrap();
    seconds as u64 * 1_000_000_000 + nanos as u64
}

fn f64_field(message: &DynamicMessage, name: &str) -> f64 {
    message.get_field_by_name(name).unwrap().as_f64().unwrap()
}

fn f64_list(message: &DynamicMessage, name: &str) -> Vec<f64> {
    match message.get_field_by_name(name).unwrap().into_owned() {
        Value::List(values) => values.iter().map(|v| v.as_f64().unwrap()).collect(),
        other => panic!("{name} is not a list: {other:?}"),
    }
}

/// (time ns, value) series of one field of one topic; block messages are expanded.
fn series(messages: &[Decoded], topic: &str, field: &str, block_field: &str) -> Vec<(u64, f64)> {
    let mut out = Vec::new();
    for d in messages.iter().filter(|d| d.topic == topic) {
        let m = &d.message;
        if m.descriptor()
            .get_field_by_name("sample_period_ns")
            .is_some()
        {
            let period = m
                .get_field_by_name("sample_period_ns")
                .unwrap()
                .as_u64()
                .unwrap();
            for (i, v) in f64_list(m, block_field).into_iter().enumerate() {
                out.push((d.log_time + i as u64 * period, v));
            }
        } else {
            out.push((d.log_time, f64_field(m, field)));
        }
    }
    out
}

#[test]
fn every_message_of_both_layouts_decodes_through_its_embedded_schema() {
    let dir = tempfile::tempdir().unwrap();
    for (name, lines) in [
        ("sample", "layout = \"sample\""),
        ("block", "layout = \"block\""),
    ] {
        let decoded = decode_file(&simulate(dir.path(), name, lines));
        let topics: std::collections::BTreeSet<&str> =
            decoded.iter().map(|d| d.topic.as_str()).collect();
        for topic in [
            "/sensors/accel/A1",
            "/sensors/strain/S1",
            "/sensors/disp/D1",
            "/truth/sensors/A4",
            "/truth/axle_loads",
            "/truth/vehicles",
            "/truth/bridge",
            "/wim/WIM1",
            "/events",
        ] {
            assert!(topics.contains(topic), "{name}: {topic} missing");
        }
    }
}

#[test]
fn block_layout_carries_exactly_the_samples_of_the_sample_layout() {
    // Same scenario and seed: the blocks must expand to the same instants and the same
    // values, bit for bit, for the measured and the truth streams; the other topics are
    // identical message by message.
    let dir = tempfile::tempdir().unwrap();
    let sample = decode_file(&simulate(dir.path(), "sample", "layout = \"sample\""));
    let block = decode_file(&simulate(
        dir.path(),
        "block",
        "layout = \"block\"\nblock_samples = 64\n",
    ));
    let pairs = [
        ("/sensors/accel/A3", "acceleration_m_s2", "values"),
        ("/sensors/strain/S1", "strain_microstrain", "values"),
        ("/sensors/disp/D1", "displacement_m", "values"),
        (
            "/truth/sensors/A3",
            "acceleration_m_s2",
            "acceleration_m_s2",
        ),
        ("/truth/sensors/A3", "velocity_m_s", "velocity_m_s"),
        ("/truth/sensors/S1", "moment_n_m", "moment_n_m"),
        ("/truth/sensors/D1", "displacement_m", "displacement_m"),
    ];
    for (topic, field, block_field) in pairs {
        let a = series(&sample, topic, field, field);
        let b = series(&block, topic, field, block_field);
        assert_eq!(a.len(), b.len(), "{topic}");
        assert!(a.len() > 500, "{topic}: {} samples", a.len());
        assert_eq!(a, b, "{topic}.{field}");
        let blocks = block.iter().filter(|d| d.topic == topic).count();
        assert_eq!(blocks, a.len().div_ceil(64), "{topic}: block count");
    }
    for topic in ["/truth/axle_loads", "/truth/bridge", "/wim/WIM1", "/events"] {
        let a: Vec<_> = sample.iter().filter(|d| d.topic == topic).collect();
        let b: Vec<_> = block.iter().filter(|d| d.topic == topic).collect();
        assert_eq!(a.len(), b.len(), "{topic}");
        for (x, y) in a.iter().zip(&b) {
            // Compared as bytes: the two DynamicMessages come from different pools.
            let bytes = |d: &Decoded| prost::Message::encode_to_vec(&d.message);
            assert_eq!((x.log_time, bytes(x)), (y.log_time, bytes(y)), "{topic}");
        }
    }
}

/// Peak resident memory the binary reports with `--timings` (MiB).
fn peak_memory_mib(dir: &Path, duration_s: &str) -> f64 {
    let out = dir.join(format!("run{duration_s}.mcap"));
    let output = Command::new(env!("CARGO_BIN_EXE_bridgetwin"))
        .arg("simulate")
        .arg("--out")
        .arg(&out)
        .args(["--duration-s", duration_s, "--timings"])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    let line = stderr
        .lines()
        .find(|l| l.starts_with("peak memory"))
        .unwrap_or_else(|| panic!("no peak memory line in {stderr}"));
    line.split_whitespace()
        .rev()
        .nth(1)
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("cannot parse {line:?}"))
}

#[test]
#[cfg(target_os = "linux")]
fn peak_memory_does_not_grow_with_duration() {
    // 15x the duration (and the messages): everything is streamed, so the peak stays
    // put. The allowance (10 % + 2 MiB) covers the allocator's noise and the MCAP
    // summary's chunk index, which grows by ~100 B per chunk.
    let dir = tempfile::tempdir().unwrap();
    let short = peak_memory_mib(dir.path(), "20");
    let long = peak_memory_mib(dir.path(), "300");
    assert!(
        long <= 1.1 * short + 2.0,
        "peak memory {long:.1} MiB for 300 s vs {short:.1} MiB for 20 s"
    );
}
