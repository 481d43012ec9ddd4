//! The guarded pass decompresses chunks on worker threads and hands records on in file
//! order: on a run of 22 chunks (more than the queue holds on any machine up to 8
//! workers: 4 per worker) every message comes out in the order the `mcap` crate's own
//! sequential `MessageStream` gives, with the same bytes; `read_run` keeps that order
//! per topic.

use std::collections::BTreeMap;

use bridgetwin::input::{read_records, read_run, End, Flow, ReadOptions};
use mcap::records::Record;

#[test]
fn the_parallel_pass_hands_on_every_message_in_file_order() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("run.mcap");
    let status = std::process::Command::new(env!("CARGO_BIN_EXE_bridgetwin"))
        .args(["simulate", "--duration-s", "60", "--quiet", "--out"])
        .arg(&path)
        .status()
        .unwrap();
    assert!(status.success());
    let bytes = std::fs::read(&path).unwrap();

    let mut reference = Vec::new();
    for message in mcap::MessageStream::new(&bytes).unwrap() {
        let m = message.unwrap();
        reference.push((m.channel.topic.clone(), m.log_time, m.data.into_owned()));
    }
    let mut ours = Vec::new();
    let mut chunks_seen = 0;
    let mut topics: BTreeMap<u16, String> = BTreeMap::new();
    let pass = read_records(&path, |record| {
        match record {
            Record::Channel(c) => {
                topics.insert(c.id, c.topic);
            }
            Record::Message { header, data } => {
                let topic = topics.get(&header.channel_id).cloned().unwrap_or_default();
                ours.push((topic, header.log_time, data.into_owned()));
            }
            Record::ChunkIndex(_) => chunks_seen += 1,
            _ => {}
        }
        Ok(Flow::Continue)
    })
    .unwrap();
    assert_eq!(pass.end, End::Complete);
    assert!(
        chunks_seen >= 20,
        "{chunks_seen} chunks: too few to fill the queue"
    );
    assert_eq!(ours.len(), reference.len());
    assert!(ours == reference, "messages out of order or changed");

    let run = read_run(std::slice::from_ref(&path), &ReadOptions::default()).unwrap();
    for (topic, data) in &run.topics {
        let log = data.table.i64s("log_time_ns").unwrap();
        assert!(
            log.windows(2).all(|w| w[0] <= w[1]),
            "{topic}: times out of order"
        );
    }
}
