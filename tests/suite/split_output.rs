//! `output.split_every_s`: one run written as several complete MCAP files. The binary's
//! parts equal the unsplit run cut at the boundaries, are byte-reproducible and refuse to
//! overwrite; the sink's rotation keeps completed parts on an interrupted or failed run.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use bridgetwin::output::proto::foxglove::Log;
use bridgetwin::output::{timestamp_from_ns, McapSink, SinkOptions, Topics};
use bridgetwin::scenario::Scenario;
use mcap::records::Record;

/// 2026-01-01T00:00:00Z, the default scenario start.
const START_NS: u64 = 1_767_225_600_000_000_000;
const NS_PER_S: u64 = 1_000_000_000;
/// The binary's runs: 5 s of the default scenario in parts of 2 s, so the last part is
/// shorter than the others and holds the closing instant t = 5 s.
const DURATION_S: u64 = 5;
const SPLIT_S: u64 = 2;
const PARTS: u64 = 3;

/// One message as the concatenation test compares them.
#[derive(Debug, PartialEq, Eq)]
struct Msg {
    topic: String,
    sequence: u32,
    log_time: u64,
    data: Vec<u8>,
}

/// The default scenario, `DURATION_S` long, split every `split_s` (or not), as a TOML file
/// in `dir`.
fn scenario_file(dir: &Path, split_s: Option<u64>) -> PathBuf {
    let mut s = Scenario::default_scenario();
    s.duration_s = Some(DURATION_S as f64);
    s.output.split_every_s = split_s.map(|t| t as f64);
    let path = dir.join(match split_s {
        Some(_) => "split.toml",
        None => "whole.toml",
    });
    std::fs::write(&path, s.to_toml()).unwrap();
    path
}

fn simulate(scenario: &Path, out: &Path, force: bool) -> Output {
    let mut command = Command::new(env!("CARGO_BIN_EXE_bridgetwin"));
    command.arg("simulate").arg(scenario).arg("--out").arg(out);
    if force {
        command.arg("--force");
    }
    command.output().unwrap()
}

fn part(dir: &Path, k: u64) -> PathBuf {
    dir.join(format!("run-{k:04}.mcap"))
}

/// Files in `dir` whose name ends with `.partial`.
fn partials(dir: &Path) -> Vec<PathBuf> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.to_string_lossy().ends_with(".partial"))
        .collect()
}

fn messages(bytes: &[u8]) -> Vec<Msg> {
    mcap::MessageStream::new(bytes)
        .unwrap()
        .map(|m| {
            let m = m.unwrap();
            Msg {
                topic: m.channel.topic.clone(),
                sequence: m.sequence,
                log_time: m.log_time,
                data: m.data.into_owned(),
            }
        })
        .collect()
}

/// (id, topic, schema name, metadata) of every channel in the summary, by id.
fn channels(summary: &mcap::Summary) -> Vec<(u16, String, String, BTreeMap<String, String>)> {
    let mut out: Vec<_> = summary
        .channels
        .values()
        .map(|c| {
            let schema = c.schema.as_ref().map_or(String::new(), |s| s.name.clone());
            (c.id, c.topic.clone(), schema, c.metadata.clone())
        })
        .collect();
    out.sort();
    out
}

/// Metadata records by name, and attachment names, read from the start of the file.
fn records(bytes: &[u8]) -> (BTreeMap<String, BTreeMap<String, String>>, Vec<String>) {
    let (mut metadata, mut attachments) = (BTreeMap::new(), Vec::new());
    for record in mcap::read::LinearReader::new(bytes).unwrap() {
        match record.unwrap() {
            Record::Metadata(m) => {
                assert!(
                    metadata.insert(m.name.clone(), m.metadata).is_none(),
                    "metadata {} twice",
                    m.name
                );
            }
            Record::Attachment { header, .. } => attachments.push(header.name),
            _ => {}
        }
    }
    (metadata, attachments)
}

#[test]
fn the_parts_are_complete_files_that_concatenate_to_the_unsplit_run() {
    let dir = tempfile::tempdir().unwrap();
    let whole = dir.path().join("whole.mcap");
    let out = simulate(&scenario_file(dir.path(), None), &whole, false);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let whole_bytes = std::fs::read(&whole).unwrap();
    let whole_summary = mcap::Summary::read(&whole_bytes).unwrap().unwrap();
    let (whole_metadata, whole_attachments) = records(&whole_bytes);
    assert!(!whole_metadata.contains_key("split"));

    let out = simulate(
        &scenario_file(dir.path(), Some(SPLIT_S)),
        &dir.path().join("run.mcap"),
        false,
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(stderr.contains("run-0000.mcap .. "), "{stderr}");
    assert!(stderr.contains("run-0002.mcap (3 files, "), "{stderr}");
    assert!(!dir.path().join("run.mcap").exists());
    assert!(!part(dir.path(), PARTS).exists(), "one part too many");
    assert!(
        partials(dir.path()).is_empty(),
        "{:?}",
        partials(dir.path())
    );

    let mut joined = Vec::new();
    for k in 0..PARTS {
        let bytes = std::fs::read(part(dir.path(), k)).unwrap();
        let summary = mcap::Summary::read(&bytes)
            .unwrap()
            .expect("each part has a summary");
        // Every channel, with the same id, schema and metadata as in the unsplit file.
        assert_eq!(channels(&summary), channels(&whole_summary), "part {k}");
        let (metadata, attachments) = records(&bytes);
        assert_eq!(attachments, whole_attachments, "part {k}");
        for name in ["bridgetwin", "bridge_model"] {
            assert_eq!(metadata[name], whole_metadata[name], "part {k}: {name}");
        }
        // The scenario record differs from the unsplit run's by split_every_s only.
        assert!(metadata["scenario"]["toml"].contains("split_every_s = 2.0"));
        let split = &metadata["split"];
        let start = START_NS + k * SPLIT_S * NS_PER_S;
        let end = match k + 1 == PARTS {
            true => START_NS + DURATION_S * NS_PER_S,
            false => start + SPLIT_S * NS_PER_S,
        };
        let expected: BTreeMap<String, String> = [
            ("part", k.to_string()),
            ("parts_total", PARTS.to_string()),
            ("part_start_ns", start.to_string()),
            ("part_end_ns", end.to_string()),
            ("split_every_s", SPLIT_S.to_string()),
        ]
        .into_iter()
        .map(|(key, value)| (key.to_string(), value))
        .collect();
        assert_eq!(split, &expected, "part {k}");

        let part_messages = messages(&bytes);
        assert_eq!(
            summary.stats.unwrap().message_count,
            part_messages.len() as u64
        );
        assert!(!part_messages.is_empty(), "part {k}");
        for m in &part_messages {
            // [start, end), the last part's window closed: it holds t = duration.
            let inside =
                m.log_time >= start && (m.log_time < end || (k + 1 == PARTS && m.log_time == end));
            assert!(inside, "part {k}: {} at {}", m.topic, m.log_time);
        }
        if k + 1 == PARTS {
            assert!(part_messages.iter().any(|m| m.log_time == end));
        }
        joined.extend(part_messages);
    }
    let whole_messages = messages(&whole_bytes);
    assert_eq!(joined.len(), whole_messages.len());
    // Sequence numbers run on across parts: the messages are equal, numbers included.
    assert!(
        joined == whole_messages,
        "the parts differ from the unsplit run"
    );
}

#[test]
fn the_same_seed_gives_the_same_parts_byte_for_byte() {
    let dir = tempfile::tempdir().unwrap();
    let scenario = scenario_file(dir.path(), Some(SPLIT_S));
    let (a, b) = (dir.path().join("a"), dir.path().join("b"));
    for d in [&a, &b] {
        std::fs::create_dir(d).unwrap();
        let out = simulate(&scenario, &d.join("run.mcap"), false);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    for k in 0..PARTS {
        let first = std::fs::read(part(&a, k)).unwrap();
        assert!(
            first == std::fs::read(part(&b, k)).unwrap(),
            "part {k} differs"
        );
    }
    assert!(!part(&a, PARTS).exists() && !part(&b, PARTS).exists());
}

#[test]
fn an_existing_later_part_needs_force_and_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let scenario = scenario_file(dir.path(), Some(SPLIT_S));
    let taken = part(dir.path(), 1);
    std::fs::write(&taken, b"an earlier run").unwrap();
    let out = simulate(&scenario, &dir.path().join("run.mcap"), false);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(matches!(out.status.code(), Some(1 | 2)), "{stderr}");
    assert!(stderr.contains(&*taken.to_string_lossy()), "{stderr}");
    assert!(stderr.contains("--force"), "{stderr}");
    assert!(
        partials(dir.path()).is_empty(),
        "{:?}",
        partials(dir.path())
    );
    assert!(!part(dir.path(), 0).exists());
    assert_eq!(std::fs::read(&taken).unwrap(), b"an earlier run");

    let out = simulate(&scenario, &dir.path().join("run.mcap"), true);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let bytes = std::fs::read(&taken).unwrap();
    assert!(mcap::Summary::read(&bytes).unwrap().is_some());
}

// The sink alone: parts cut by the messages' log times, without a known end.

/// A split file sink on `dir/log.mcap`, parts of 1 s from `START_NS`, end unknown, with
/// one `/events` channel.
fn log_sink(dir: &Path) -> (McapSink, bridgetwin::output::ChannelId) {
    let options = SinkOptions {
        split_every_ns: Some(NS_PER_S),
        split_start_ns: START_NS,
        ..SinkOptions::default()
    };
    let mut sink = McapSink::create(&dir.join("log.mcap"), options).unwrap();
    let run = bridgetwin::output::metadata([("seed", "1")]);
    sink.write_metadata("bridgetwin", run).unwrap();
    sink.attach("note.txt", "text/plain", b"hello", START_NS)
        .unwrap();
    let events = sink
        .add_channel::<Log>(Topics::EVENTS, BTreeMap::new())
        .unwrap();
    (sink, events)
}

fn log_at(sink: &mut McapSink, channel: bridgetwin::output::ChannelId, t_ns: u64) {
    let msg = Log {
        timestamp: Some(timestamp_from_ns(t_ns)),
        message: format!("at {t_ns}"),
        ..Log::default()
    };
    sink.write(channel, t_ns, &msg).unwrap();
}

#[test]
fn a_window_without_messages_still_gets_its_part_and_flushes_work_in_every_part() {
    let dir = tempfile::tempdir().unwrap();
    let (mut sink, events) = log_sink(dir.path());
    log_at(&mut sink, events, START_NS + NS_PER_S / 2);
    sink.flush().unwrap();
    // Parts 1 and 2 pass without a message; part 3 gets one, flushed mid-part.
    log_at(&mut sink, events, START_NS + 3 * NS_PER_S + 1);
    sink.flush().unwrap();
    log_at(&mut sink, events, START_NS + 3 * NS_PER_S + 2);
    assert_eq!(sink.parts().unwrap().len(), 3);
    let paths = sink.finish_parts().unwrap();
    let expected: Vec<PathBuf> = (0..4)
        .map(|k| dir.path().join(format!("log-{k:04}.mcap")))
        .collect();
    assert_eq!(paths, expected);
    for (k, path) in paths.iter().enumerate() {
        let bytes = std::fs::read(path).unwrap();
        let summary = mcap::Summary::read(&bytes).unwrap().unwrap();
        assert_eq!(summary.channels.len(), 1, "part {k}");
        let (metadata, attachments) = records(&bytes);
        assert_eq!(metadata["split"]["part"], k.to_string());
        assert!(
            !metadata["split"].contains_key("parts_total"),
            "unknown end"
        );
        assert_eq!(metadata["bridgetwin"]["seed"], "1");
        assert_eq!(attachments, ["note.txt"]);
        let sequences: Vec<u32> = messages(&bytes).iter().map(|m| m.sequence).collect();
        let want: &[u32] = match k {
            0 => &[1],
            3 => &[2, 3],
            _ => &[],
        };
        assert_eq!(sequences, want, "part {k}");
    }
}

#[test]
fn an_interrupted_split_run_keeps_its_parts_and_the_current_partial() {
    let dir = tempfile::tempdir().unwrap();
    let (mut sink, events) = log_sink(dir.path());
    log_at(&mut sink, events, START_NS + 1);
    log_at(&mut sink, events, START_NS + NS_PER_S + 1);
    assert_eq!(sink.parts().unwrap(), [dir.path().join("log-0000.mcap")]);
    let partial = sink.finish_partial().unwrap();
    assert_eq!(partial, dir.path().join("log-0001.mcap.partial"));
    for path in [dir.path().join("log-0000.mcap"), partial] {
        let bytes = std::fs::read(&path).unwrap();
        assert!(mcap::Summary::read(&bytes).unwrap().is_some(), "{path:?}");
        assert_eq!(messages(&bytes).len(), 1, "{path:?}");
    }
}

#[test]
fn a_failed_split_run_deletes_only_the_current_partial() {
    let dir = tempfile::tempdir().unwrap();
    let (mut sink, events) = log_sink(dir.path());
    log_at(&mut sink, events, START_NS + 1);
    log_at(&mut sink, events, START_NS + NS_PER_S + 1);
    sink.discard();
    assert!(
        partials(dir.path()).is_empty(),
        "{:?}",
        partials(dir.path())
    );
    let bytes = std::fs::read(dir.path().join("log-0000.mcap")).unwrap();
    assert_eq!(messages(&bytes).len(), 1);
}

#[test]
fn a_part_whose_target_exists_fails_when_it_is_due_and_names_it() {
    // The end is unknown, so `create` cannot check part 1 in advance.
    let dir = tempfile::tempdir().unwrap();
    let taken = dir.path().join("log-0001.mcap");
    std::fs::write(&taken, b"keep me").unwrap();
    let (mut sink, events) = log_sink(dir.path());
    log_at(&mut sink, events, START_NS + 1);
    let msg = Log::default();
    let err = sink
        .write(events, START_NS + NS_PER_S, &msg)
        .expect_err("log-0001.mcap exists");
    let text = err.to_string();
    assert!(
        text.contains(&*taken.to_string_lossy()) && text.contains("--force"),
        "{text}"
    );
    sink.discard();
    assert!(
        partials(dir.path()).is_empty(),
        "{:?}",
        partials(dir.path())
    );
    assert_eq!(std::fs::read(&taken).unwrap(), b"keep me");
}

#[test]
fn only_a_file_sink_can_split() {
    let options = SinkOptions {
        split_every_ns: Some(NS_PER_S),
        ..SinkOptions::default()
    };
    let err = McapSink::in_memory(&options)
        .err()
        .expect("no file names to split into");
    assert!(err.to_string().contains("split"), "{err}");
    let dir = tempfile::tempdir().unwrap();
    let zero = SinkOptions {
        split_every_ns: Some(0),
        ..SinkOptions::default()
    };
    assert!(McapSink::create(&dir.path().join("x.mcap"), zero).is_err());
    assert!(partials(dir.path()).is_empty());
}
