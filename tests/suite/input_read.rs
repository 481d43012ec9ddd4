//! The guarded pass decompresses chunks on worker threads and hands records on in file
//! order: on a run of 22 chunks, with 1, 2 and 8 workers (the queue waits at 4 chunks per
//! worker), every message comes out in the order the `mcap` crate's own sequential
//! `MessageStream` gives, with the same bytes; a damaged chunk in the middle ends the pass
//! after exactly the chunks before it; a visitor's stop ends it at once.

use std::collections::BTreeMap;

use std::path::{Path, PathBuf};

use bridgetwin::input::{read_records_with, read_run, End, Flow, ReadOptions};
use mcap::records::Record;

/// A 60 s default run: 22 chunks.
fn sixty_seconds(dir: &Path) -> PathBuf {
    crate::common::simulate_default_file(dir, 60.0)
}

type Messages = Vec<(String, u64, Vec<u8>)>;

/// Every message as the pass hands it on, with how the pass ended and the chunks seen.
fn ours(path: &Path, workers: usize, stop_after: Option<usize>) -> (Messages, End, usize) {
    let mut out = Vec::new();
    let mut chunks = 0;
    let mut topics: BTreeMap<u16, String> = BTreeMap::new();
    let pass = read_records_with(path, workers, |record| {
        match record {
            Record::Channel(c) => {
                topics.insert(c.id, c.topic);
            }
            Record::Message { header, data } => {
                let topic = topics.get(&header.channel_id).cloned().unwrap_or_default();
                out.push((topic, header.log_time, data.into_owned()));
                if Some(out.len()) == stop_after {
                    return Ok(Flow::Stop);
                }
            }
            Record::ChunkIndex(_) => chunks += 1,
            _ => {}
        }
        Ok(Flow::Continue)
    })
    .unwrap();
    (out, pass.end, chunks)
}

/// The mcap crate's sequential reading of the same bytes.
fn reference(bytes: &[u8]) -> Messages {
    mcap::MessageStream::new(bytes)
        .unwrap()
        .map(|m| {
            let m = m.unwrap();
            (m.channel.topic.clone(), m.log_time, m.data.into_owned())
        })
        .collect()
}

#[test]
fn the_parallel_pass_hands_on_every_message_in_file_order() {
    let dir = tempfile::tempdir().unwrap();
    let path = sixty_seconds(dir.path());
    let expected = reference(&std::fs::read(&path).unwrap());
    // One worker: the queue (4 chunks) fills and waits; eight: 22 chunks all in flight.
    for workers in [1, 2, 8] {
        let (got, end, chunks) = ours(&path, workers, None);
        assert_eq!(end, End::Complete);
        assert!(chunks >= 20, "{chunks} chunks: too few to fill the queue");
        assert_eq!(got.len(), expected.len(), "{workers} workers");
        assert!(
            got == expected,
            "{workers} workers: messages out of order or changed"
        );
    }
    let run = read_run(std::slice::from_ref(&path), &ReadOptions::default()).unwrap();
    for (topic, data) in &run.topics {
        let log = data.table.i64s("log_time_ns").unwrap();
        assert!(
            log.windows(2).all(|w| w[0] <= w[1]),
            "{topic}: times out of order"
        );
    }
}

#[test]
fn a_damaged_chunk_in_the_middle_ends_the_pass_after_the_chunks_before_it() {
    let dir = tempfile::tempdir().unwrap();
    let path = sixty_seconds(dir.path());
    let mut bytes = std::fs::read(&path).unwrap();
    let summary = mcap::Summary::read(&bytes).unwrap().unwrap();
    let mut chunks: Vec<_> = summary
        .chunk_indexes
        .iter()
        .map(|c| (c.chunk_start_offset, c.chunk_length))
        .collect();
    chunks.sort();
    let (start, length) = chunks[chunks.len() / 2];
    let (next_start, _) = chunks[chunks.len() / 2 + 1];
    // A byte of the compressed records, past the chunk's header.
    bytes[(start + length * 3 / 4) as usize] ^= 0x40;
    // The messages of the chunks before the damaged one, by the mcap crate's own chunk
    // reader on the undamaged bytes.
    let before = std::fs::read(&path).unwrap();
    let intact_count: usize = summary
        .chunk_indexes
        .iter()
        .filter(|c| c.chunk_start_offset < start)
        .map(|c| summary.stream_chunk(&before, c).unwrap().count())
        .sum();
    let intact = reference(&before)[..intact_count].to_vec();
    assert!(
        intact_count > 1000,
        "{intact_count} messages before the damage"
    );
    let damaged = dir.path().join("damaged.mcap");
    std::fs::write(&damaged, &bytes).unwrap();
    for workers in [1, 8] {
        let (got, end, _) = ours(&damaged, workers, None);
        let End::Damaged(d) = end else {
            panic!("{workers} workers: {end:?}")
        };
        assert!(
            got == intact,
            "{workers} workers: not the messages of the chunks before"
        );
        assert_eq!(d.messages_before, intact.len() as u64);
        assert!(
            (start + length..=next_start + 64).contains(&d.at_byte),
            "{workers} workers: damage at {} for the chunk at {start}..{}",
            d.at_byte,
            start + length
        );
    }
}

#[test]
fn a_visitor_that_stops_ends_the_pass_at_once() {
    let dir = tempfile::tempdir().unwrap();
    let path = sixty_seconds(dir.path());
    let expected = reference(&std::fs::read(&path).unwrap());
    for workers in [1, 8] {
        let (got, end, _) = ours(&path, workers, Some(1000));
        assert_eq!(end, End::Stopped);
        assert!(got[..] == expected[..1000]);
    }
}
