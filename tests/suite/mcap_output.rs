//! Round trip of `sink::McapSink`: every message type written, read back with the `mcap`
//! crate and decoded with `prost-reflect` from the schema record's own descriptor set, as
//! an independent reader would.

use std::collections::BTreeMap;
use std::io::{Seek, Write};

use bridgetwin::output::proto::{foxglove, v1};
use bridgetwin::output::{metadata, timestamp_from_ns, McapSink, SinkOptions, Topics};
use prost::Message;
use prost_reflect::{DescriptorPool, DynamicMessage, Value};

/// 2026-01-01T00:00:00Z, the default scenario start.
const START_NS: u64 = 1_767_225_600_000_000_000;
const PERIOD_NS: u64 = 5_000_000; // 200 Hz

/// What the fixture wrote: encoded messages per topic, in order.
type Written = BTreeMap<String, Vec<(u64, Vec<u8>)>>;

/// Writes every message type on its contract topic: a few seconds of a small run, merged
/// in time order as the simulation loop does. Returns what was written.
fn write_fixture<W: Write + Seek>(sink: &mut McapSink<W>) -> Written {
    let mut written = Written::new();
    let run_meta = metadata([("version", "test"), ("seed", "42")]);
    sink.write_metadata("bridgetwin", run_meta).unwrap();
    sink.write_metadata("scenario", metadata([("toml", "seed = 42\n")]))
        .unwrap();
    sink.write_metadata("bridge_model", metadata([("f1_hz", "4.1")]))
        .unwrap();

    let accel_meta = metadata([("unit", "m/s^2"), ("sample_rate_hz", "200")]);
    let accel = sink
        .add_channel::<v1::AccelerationSample>(&Topics::accel("A1").unwrap(), accel_meta)
        .unwrap();
    let strain = sink
        .add_channel::<v1::StrainSample>(&Topics::strain("S1").unwrap(), BTreeMap::new())
        .unwrap();
    let disp = sink
        .add_channel::<v1::DisplacementSample>(&Topics::disp("D1").unwrap(), BTreeMap::new())
        .unwrap();
    let block_topic = Topics::blocks(&Topics::accel("A1").unwrap()).unwrap();
    let block = sink
        .add_channel::<v1::SampleBlock>(&block_topic, BTreeMap::new())
        .unwrap();
    let truth = sink
        .add_channel::<v1::SensorTruth>(&Topics::truth_sensor("A1").unwrap(), BTreeMap::new())
        .unwrap();
    let truth_block_topic = Topics::blocks(&Topics::truth_sensor("A1").unwrap()).unwrap();
    let truth_block = sink
        .add_channel::<v1::SensorTruthBlock>(&truth_block_topic, BTreeMap::new())
        .unwrap();
    let axles = sink
        .add_channel::<v1::AxleLoads>(Topics::AXLE_LOADS, BTreeMap::new())
        .unwrap();
    let vehicles = sink
        .add_channel::<v1::VehicleTruth>(Topics::VEHICLES, BTreeMap::new())
        .unwrap();
    let bridge = sink
        .add_channel::<v1::BridgeState>(Topics::BRIDGE, BTreeMap::new())
        .unwrap();
    let wim = sink
        .add_channel::<v1::WimRecord>(&Topics::wim("W1").unwrap(), BTreeMap::new())
        .unwrap();
    let events = sink
        .add_channel::<foxglove::Log>(Topics::EVENTS, BTreeMap::new())
        .unwrap();

    // Records one message in `written` and the sink.
    macro_rules! put {
        ($channel:expr, $topic:expr, $t_ns:expr, $msg:expr) => {{
            let msg = $msg;
            sink.write($channel, $t_ns, &msg).unwrap();
            written
                .entry($topic.to_string())
                .or_default()
                .push(($t_ns, msg.encode_to_vec()));
        }};
    }

    for i in 0..400u64 {
        let t_ns = START_NS + i * PERIOD_NS;
        let ts = Some(timestamp_from_ns(t_ns));
        let x = (i as f64 * 0.1).sin();
        put!(
            accel,
            "/sensors/accel/A1",
            t_ns,
            v1::AccelerationSample {
                timestamp: ts,
                acceleration_m_s2: x,
            }
        );
        put!(
            strain,
            "/sensors/strain/S1",
            t_ns,
            v1::StrainSample {
                timestamp: ts,
                strain_microstrain: 10.0 * x,
            }
        );
        put!(
            disp,
            "/sensors/disp/D1",
            t_ns,
            v1::DisplacementSample {
                timestamp: ts,
                displacement_m: 1e-3 * x,
            }
        );
        put!(
            truth,
            "/truth/sensors/A1",
            t_ns,
            v1::SensorTruth {
                timestamp: ts,
                sensor_id: "A1".into(),
                displacement_m: 1e-3 * x,
                velocity_m_s: 1e-2 * x,
                acceleration_m_s2: x,
                strain_microstrain: 10.0 * x,
                moment_n_m: 1e6 * x,
                ..Default::default()
            }
        );
        if i.is_multiple_of(100) {
            put!(
                block,
                block_topic,
                t_ns,
                v1::SampleBlock {
                    timestamp: ts,
                    sample_period_ns: PERIOD_NS,
                    quantity: "acceleration".into(),
                    unit: "m/s^2".into(),
                    values: (0..100).map(|k| (k as f64 * 0.1).sin()).collect(),
                }
            );
            put!(
                truth_block,
                truth_block_topic,
                t_ns,
                v1::SensorTruthBlock {
                    timestamp: ts,
                    sample_period_ns: PERIOD_NS,
                    sensor_id: "A1".into(),
                    displacement_m: vec![1e-3; 100],
                    velocity_m_s: vec![0.0; 100],
                    acceleration_m_s2: vec![0.5; 100],
                    strain_microstrain: vec![3.0; 100],
                    moment_n_m: vec![1e5; 100],
                    rotation_rad: Vec::new(),
                    reaction_n: Vec::new(),
                    temperature_c: Vec::new(),
                }
            );
        }
        if i.is_multiple_of(10) {
            put!(
                axles,
                Topics::AXLE_LOADS,
                t_ns,
                v1::AxleLoads {
                    timestamp: ts,
                    axles: (0..2)
                        .map(|a| v1::AxleLoad {
                            vehicle_id: 7,
                            axle_index: a,
                            position_m: 20.0 * i as f64 * 5e-3 - 4.0 * a as f64,
                            force_n: 60e3 * (1.0 + 0.1 * x),
                            static_load_n: 60e3,
                            in_contact: true,
                            on_bridge: i > 100,
                        })
                        .collect(),
                }
            );
        }
        if i.is_multiple_of(50) {
            put!(
                bridge,
                Topics::BRIDGE,
                t_ns,
                v1::BridgeState {
                    timestamp: ts,
                    node_position_m: vec![0.0, 15.0, 30.0],
                    deflection_m: vec![0.0, 1e-3 * x, 0.0],
                    natural_frequency_hz: vec![4.1, 16.4],
                    damping_ratio: vec![0.02, 0.02],
                    modal_amplitude_m: vec![1e-3 * x, 0.0],
                    mode_shapes: if i == 0 {
                        vec![v1::ModeShape {
                            mode_number: 1,
                            natural_frequency_hz: 4.1,
                            amplitude: vec![0.0, 1.0, 0.0],
                        }]
                    } else {
                        Vec::new()
                    },
                    temperature_c: 20.0,
                    midspan_deflection_m: 1e-3 * x,
                    stiffness_ratio: Vec::new(),
                    air_temperature_c: 18.0,
                    support_reaction_n: vec![1e5 * (1.0 - x), 1e5 * x],
                    support_stiffness_ratio: Vec::new(),
                    support_settlement_m: Vec::new(),
                    damage_fraction: Vec::new(),
                }
            );
        }
        if i == 150 {
            put!(
                wim,
                "/wim/W1",
                t_ns,
                v1::WimRecord {
                    timestamp: ts,
                    station_id: "W1".into(),
                    vehicle_id: 7,
                    lane: 0,
                    speed_m_s: 20.1,
                    axle_count: 2,
                    axle_spacing_m: vec![4.0],
                    axle_load_n: vec![59e3, 61e3],
                    gross_weight_n: 120e3,
                    axle_pattern: "1-1".into(),
                    flags: vec!["low_speed".into()],
                    ..Default::default()
                }
            );
            put!(
                events,
                Topics::EVENTS,
                t_ns,
                foxglove::Log {
                    timestamp: ts,
                    level: foxglove::log::Level::Info as i32,
                    message: "vehicle 7 enters the bridge".into(),
                    name: "traffic".into(),
                    file: String::new(),
                    line: 0,
                }
            );
        }
        if i == 399 {
            let mut parameters = BTreeMap::new();
            parameters.insert("body_mass_kg".to_string(), 12e3);
            parameters.insert("suspension_stiffness_n_m".to_string(), 1e6);
            put!(
                vehicles,
                Topics::VEHICLES,
                t_ns,
                v1::VehicleTruth {
                    timestamp: ts,
                    vehicle_id: 7,
                    vehicle_class: "two_axle_truck".into(),
                    model: "half_car".into(),
                    lane: 0,
                    direction: v1::TravelDirection::IncreasingX as i32,
                    speed_m_s: 20.0,
                    entry_time: Some(timestamp_from_ns(START_NS + 500_000_000)),
                    exit_time: Some(timestamp_from_ns(START_NS + 1_700_000_000)),
                    axle_spacing_m: vec![4.0],
                    static_axle_load_n: vec![60e3, 60e3],
                    gross_weight_n: 120e3,
                    parameters,
                }
            );
        }
        if i == 200 {
            // A periodic flush mid-run must not disturb anything.
            sink.flush().unwrap();
        }
    }
    sink.attach(
        "scenario.toml",
        "application/toml",
        b"seed = 42\n",
        START_NS,
    )
    .unwrap();
    written
}

fn write_to_memory() -> (Vec<u8>, Written) {
    let mut sink = McapSink::in_memory(&SinkOptions::default()).unwrap();
    let written = write_fixture(&mut sink);
    (sink.finish_to_bytes().unwrap(), written)
}

/// Reads `bytes` as an independent reader and checks it against `written`.
fn check_file(bytes: &[u8], written: &Written) {
    let summary = mcap::Summary::read(bytes)
        .unwrap()
        .expect("a summary section");
    let stats = summary.stats.as_ref().expect("statistics");
    let total: usize = written.values().map(Vec::len).sum();
    assert_eq!(stats.message_count, total as u64);
    assert_eq!(stats.channel_count as usize, written.len());
    assert_eq!(stats.schema_count as usize, written.len()); // one type per topic here
    assert_eq!(stats.metadata_count, 3);
    assert_eq!(stats.attachment_count, 1);
    assert_eq!(stats.message_start_time, START_NS);
    assert_eq!(stats.message_end_time, START_NS + 399 * PERIOD_NS);
    for (id, channel) in &summary.channels {
        let count = stats.channel_message_counts.get(id).copied().unwrap_or(0);
        assert_eq!(
            count,
            written[&channel.topic].len() as u64,
            "{}",
            channel.topic
        );
    }
    assert_eq!(summary.channels[&1].metadata["unit"], "m/s^2");

    let names: Vec<String> = summary
        .metadata_indexes
        .iter()
        .map(|index| mcap::read::metadata(bytes, index).unwrap().name)
        .collect();
    assert_eq!(names, ["bridgetwin", "scenario", "bridge_model"]);
    let attachment = mcap::read::attachment(bytes, &summary.attachment_indexes[0]).unwrap();
    assert_eq!(
        (attachment.name.as_str(), &attachment.data[..]),
        ("scenario.toml", &b"seed = 42\n"[..])
    );

    let mut sequences: BTreeMap<String, u32> = BTreeMap::new();
    let mut read: Written = BTreeMap::new();
    let mut last_log_time = 0;
    let options = mcap::read::Options::ValidateChunkCrcs.into();
    for message in mcap::MessageStream::new_with_options(bytes, options).unwrap() {
        let message = message.unwrap();
        let topic = message.channel.topic.clone();
        assert!(
            message.log_time >= last_log_time,
            "log_time went backwards on {topic}"
        );
        last_log_time = message.log_time;
        assert_eq!(message.publish_time, message.log_time);
        let sequence = sequences.entry(topic.clone()).or_insert(0);
        *sequence += 1;
        assert_eq!(
            message.sequence, *sequence,
            "{topic}: sequence must count from 1"
        );

        let schema = message.channel.schema.as_ref().expect("a schema");
        assert_eq!(schema.encoding, "protobuf");
        assert_eq!(message.channel.message_encoding, "protobuf");
        let dynamic = decode_with_schema(&schema.name, &schema.data, &message.data);
        assert_eq!(
            dynamic.unknown_fields().count(),
            0,
            "{topic}: schema mismatch"
        );
        assert_eq!(timestamp_ns(&dynamic), message.log_time, "{topic}");
        read.entry(topic)
            .or_default()
            .push((message.log_time, message.data.to_vec()));
    }
    assert_eq!(&read, written);
}

/// Decodes `data` with nothing but the schema record: its name and descriptor set.
fn decode_with_schema(name: &str, descriptor_set: &[u8], data: &[u8]) -> DynamicMessage {
    let files = prost_types::FileDescriptorSet::decode(descriptor_set).unwrap();
    let mut file_names: Vec<&str> = files.file.iter().map(|f| f.name()).collect();
    let count = file_names.len();
    file_names.sort_unstable();
    file_names.dedup();
    assert_eq!(
        file_names.len(),
        count,
        "{name}: duplicate files in the descriptor set"
    );
    let pool = DescriptorPool::decode(descriptor_set).unwrap();
    let descriptor = pool
        .get_message_by_name(name)
        .expect("schema names its message");
    DynamicMessage::decode(descriptor, data).unwrap()
}

fn timestamp_ns(message: &DynamicMessage) -> u64 {
    let field = message
        .get_field_by_name("timestamp")
        .expect("timestamp field");
    let Value::Message(ts) = field.as_ref() else {
        panic!("timestamp is not a message");
    };
    let seconds = ts.get_field_by_name("seconds").unwrap().as_i64().unwrap();
    let nanos = ts.get_field_by_name("nanos").unwrap().as_i32().unwrap();
    seconds as u64 * 1_000_000_000 + nanos as u64
}

#[test]
fn every_message_type_round_trips() {
    let (bytes, written) = write_to_memory();
    assert_eq!(written.len(), 11);
    check_file(&bytes, &written);
}

#[test]
fn same_input_gives_identical_bytes() {
    let (first, _) = write_to_memory();
    let (second, _) = write_to_memory();
    assert!(first == second, "two runs differ");

    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("run.mcap");
    let mut sink = McapSink::create(&path, SinkOptions::default()).unwrap();
    write_fixture(&mut sink);
    sink.finish().unwrap();
    assert!(
        std::fs::read(&path).unwrap() == first,
        "file and memory output differ"
    );
}

#[test]
fn finish_renames_partial_file() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("run.mcap");
    let partial = dir.path().join("run.mcap.partial");
    let mut sink = McapSink::create(&path, SinkOptions::default()).unwrap();
    let written = write_fixture(&mut sink);
    assert!(partial.exists() && !path.exists());
    assert_eq!(sink.finish().unwrap(), path);
    assert!(path.exists() && !partial.exists());
    check_file(&std::fs::read(&path).unwrap(), &written);
}

#[test]
fn finish_partial_keeps_the_partial_name() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("run.mcap");
    let mut sink = McapSink::create(&path, SinkOptions::default()).unwrap();
    let written = write_fixture(&mut sink);
    let kept = sink.finish_partial().unwrap();
    assert_eq!(kept, dir.path().join("run.mcap.partial"));
    assert!(!path.exists());
    check_file(&std::fs::read(&kept).unwrap(), &written);
}

#[test]
fn existing_file_is_refused_without_force() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("run.mcap");
    std::fs::write(&path, b"keep me").unwrap();
    let err = McapSink::create(&path, SinkOptions::default())
        .err()
        .expect("must refuse an existing file");
    assert!(err.to_string().contains("already exists"), "{err}");
    assert_eq!(std::fs::read(&path).unwrap(), b"keep me");
    assert_eq!(
        std::fs::read_dir(dir.path()).unwrap().count(),
        1,
        "created a file"
    );

    let force = SinkOptions {
        force: true,
        ..SinkOptions::default()
    };
    let mut sink = McapSink::create(&path, force).unwrap();
    // The old file stays until the new one is complete.
    assert_eq!(std::fs::read(&path).unwrap(), b"keep me");
    let written = write_fixture(&mut sink);
    sink.finish().unwrap();
    check_file(&std::fs::read(&path).unwrap(), &written);
}

#[test]
fn bad_output_paths_create_nothing() {
    let dir = tempfile::tempdir().unwrap();
    assert!(McapSink::create(dir.path(), SinkOptions::default()).is_err());
    let missing_dir = dir.path().join("no/such/dir/run.mcap");
    assert!(McapSink::create(&missing_dir, SinkOptions::default()).is_err());
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
}

#[test]
fn dropped_sink_leaves_a_readable_partial_file() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("run.mcap");
    let mut sink = McapSink::create(&path, SinkOptions::default()).unwrap();
    let written = write_fixture(&mut sink);
    drop(sink);
    assert!(!path.exists());
    check_file(
        &std::fs::read(dir.path().join("run.mcap.partial")).unwrap(),
        &written,
    );
}

#[test]
fn flushed_data_survives_a_killed_run() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("run.mcap");
    let mut sink = McapSink::create(&path, SinkOptions::default()).unwrap();
    let channel = sink
        .add_channel::<v1::AccelerationSample>("/sensors/accel/A1", BTreeMap::new())
        .unwrap();
    for i in 0..100 {
        let t_ns = START_NS + i * PERIOD_NS;
        let msg = v1::AccelerationSample {
            timestamp: Some(timestamp_from_ns(t_ns)),
            acceleration_m_s2: 1.0,
        };
        sink.write(channel, t_ns, &msg).unwrap();
    }
    sink.flush().unwrap();
    // Read the file as a crash would leave it: no summary, no end magic.
    let bytes = std::fs::read(dir.path().join("run.mcap.partial")).unwrap();
    let options = mcap::read::Options::IgnoreEndMagic.into();
    let recovered = mcap::MessageStream::new_with_options(&bytes, options)
        .unwrap()
        .take_while(Result::is_ok)
        .count();
    assert_eq!(recovered, 100);
    sink.finish().unwrap();
}

#[test]
fn misuse_is_an_error_not_a_corrupt_file() {
    let mut sink = McapSink::in_memory(&SinkOptions::default()).unwrap();
    let accel = sink
        .add_channel::<v1::AccelerationSample>("/sensors/accel/A1", BTreeMap::new())
        .unwrap();
    let sample = |t_ns| v1::AccelerationSample {
        timestamp: Some(timestamp_from_ns(t_ns)),
        acceleration_m_s2: 0.0,
    };
    // Same topic twice, bad topic names.
    assert!(sink
        .add_channel::<v1::AccelerationSample>("/sensors/accel/A1", BTreeMap::new())
        .is_err());
    assert!(sink
        .add_channel::<v1::AccelerationSample>("/sensors/accel/A 1", BTreeMap::new())
        .is_err());
    // log_time 0, time going backwards, wrong message type.
    assert!(sink.write(accel, 0, &sample(0)).is_err());
    sink.write(accel, START_NS + 10, &sample(START_NS + 10))
        .unwrap();
    let err = sink.write(accel, START_NS, &sample(START_NS)).unwrap_err();
    assert!(err.to_string().contains("before the previous"), "{err}");
    let wrong = v1::StrainSample::default();
    assert!(sink.write(accel, START_NS + 20, &wrong).is_err());
    assert_eq!(sink.message_count(accel), 1);

    let bytes = sink.finish_to_bytes().unwrap();
    let read = mcap::MessageStream::new(&bytes).unwrap().count();
    assert_eq!(read, 1);
}

#[test]
fn channel_ids_from_another_sink_are_rejected() {
    let mut big = McapSink::in_memory(&SinkOptions::default()).unwrap();
    big.add_channel::<v1::StrainSample>("/a", BTreeMap::new())
        .unwrap();
    let foreign = big
        .add_channel::<v1::StrainSample>("/b", BTreeMap::new())
        .unwrap();
    let mut small = McapSink::in_memory(&SinkOptions::default()).unwrap();
    let msg = v1::StrainSample::default();
    assert!(small.write(foreign, START_NS, &msg).is_err());
}

/// A disk that fills up after `capacity` bytes: writes past it fail with ENOSPC, as on a
/// full file system (`/dev/full` fails every write, which cannot be opened as `.partial`).
struct FullDisk {
    inner: std::io::Cursor<Vec<u8>>,
    capacity: usize,
}

impl Write for FullDisk {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        if self.inner.position() as usize + buf.len() > self.capacity {
            return Err(std::io::Error::from_raw_os_error(28)); // ENOSPC
        }
        self.inner.write(buf)
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

impl Seek for FullDisk {
    fn seek(&mut self, pos: std::io::SeekFrom) -> std::io::Result<u64> {
        self.inner.seek(pos)
    }
}

#[test]
fn a_full_disk_is_an_error_naming_the_output() {
    // A run of the default scenario needs ~1.3 MB; the disk holds 200 kB.
    let resolved = bridgetwin::scenario::Scenario::default_scenario()
        .resolve()
        .unwrap();
    let prepared = bridgetwin::sim::prepare(&resolved).unwrap();
    let disk = FullDisk {
        inner: std::io::Cursor::new(Vec::new()),
        capacity: 200_000,
    };
    let mut sink = McapSink::on_writer(disk, &SinkOptions::default(), "full.mcap").unwrap();
    let mut recorder = bridgetwin::output::McapRecorder::new(&mut sink);
    let err = bridgetwin::sim::run(&resolved, &prepared, &mut recorder, &mut |_, _| {})
        .expect_err("the disk fills up");
    let text = err.to_string();
    assert!(
        text.contains("full.mcap") && text.contains("No space left on device"),
        "{text}"
    );
}
