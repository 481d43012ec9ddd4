//! One pass over the records of an MCAP file that nothing in the file can crash: every
//! length the file states is checked against what the file can hold before anything is
//! allocated for it, chunks are checked against their CRC before any record inside them is
//! handed on, the data and summary sections against theirs, and damage ends the pass with
//! a [`Damage`] that says where the intact part ends instead of an error that loses what
//! was read.
//!
//! The pass is the `mcap` crate's sans-io linear reader: it works the same on a complete
//! file and on the `.partial` file of a killed run (no summary, last chunk cut short).

use std::collections::VecDeque;
use std::fs::File;
use std::io::{BufReader, ErrorKind, Read};
use std::path::Path;
use std::sync::mpsc::{Receiver, TryRecvError};

use mcap::records::Record;
use mcap::sans_io::{LinearReadEvent, LinearReader, LinearReaderOptions};

use super::chunks::{chunk_records, default_workers, ChunkPool, ChunkRecords};
use super::record_lengths::check_record_lengths;
use crate::error::{Error, Result};

/// The largest record (or decompressed chunk) a file of `file_len` bytes may hold: the
/// file itself, but at least 16 MiB, so that a small file may still hold a chunk that
/// compressed well (the writer's chunks are 1 MiB before compression). No length read from
/// a file makes the reader allocate more than this.
pub fn record_limit_bytes(file_len: u64) -> usize {
    const FLOOR_BYTES: u64 = 16 << 20;
    usize::try_from(file_len.max(FLOOR_BYTES)).unwrap_or(usize::MAX)
}

/// Bytes read from the file per request at most: the reader's buffer grows only with
/// bytes that really arrived, however large a length it was asked to load.
const READ_STEP_BYTES: usize = 4 << 20;

/// What a visitor wants after a record.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Flow {
    Continue,
    /// The visitor has what it needs: end the pass (not damage).
    Stop,
}

/// Where and why a pass ended before the end of the file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Damage {
    /// The damage lies at or before this byte offset (the bytes read when it was found).
    pub at_byte: u64,
    /// The file's size.
    pub file_bytes: u64,
    /// Messages handed on before the damage.
    pub messages_before: u64,
    /// Log time of the last message handed on (Unix-epoch ns).
    pub last_log_time_ns: Option<u64>,
    /// What the reader found.
    pub reason: String,
}

impl std::fmt::Display for Damage {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{}; the intact part ends at or before byte {} of {} ({} messages",
            self.reason, self.at_byte, self.file_bytes, self.messages_before
        )?;
        match self.last_log_time_ns {
            Some(t) => write!(f, ", the last at log time {t} ns)"),
            None => write!(f, ")"),
        }
    }
}

/// How a pass ended.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum End {
    /// The end magic was read: the file is whole.
    Complete,
    /// The visitor stopped the pass.
    Stopped,
    /// The file is damaged or cut short after the header.
    Damaged(Damage),
}

/// The outcome of a pass.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Pass {
    pub end: End,
    pub file_bytes: u64,
    pub messages: u64,
}

impl Pass {
    pub fn damage(&self) -> Option<&Damage> {
        match &self.end {
            End::Damaged(d) => Some(d),
            _ => None,
        }
    }
}

/// Reads the file at `path` record by record, inside chunks too, handing each record to
/// `visit`, in file order. A visitor's `Err(reason)` counts as damage at that record (a
/// message that does not decode). Fails only when the file cannot be opened or read, or
/// holds no MCAP header at all (bad magic, empty, garbage); every later problem is a
/// [`Damage`]. Chunks are decompressed and checked on worker threads ([`ChunkPool`], one
/// per core up to 8) while this thread reads on; a chunk's records are handed on only
/// when its CRC holds.
pub fn read_records(
    path: &Path,
    visit: impl FnMut(Record<'_>) -> std::result::Result<Flow, String>,
) -> Result<Pass> {
    read_records_with(path, default_workers(), visit)
}

/// [`read_records`] with `workers` decompression threads (at least one).
pub fn read_records_with(
    path: &Path,
    workers: usize,
    visit: impl FnMut(Record<'_>) -> std::result::Result<Flow, String>,
) -> Result<Pass> {
    let label = path.display().to_string();
    let io_error = |e: std::io::Error| Error::File {
        path: label.clone(),
        reason: e.to_string(),
    };
    let file = File::open(path).map_err(io_error)?;
    let file_bytes = file.metadata().map_err(io_error)?.len();
    let source = BufReader::with_capacity(1 << 20, file);
    std::thread::scope(|scope| {
        let pool = ChunkPool::start(scope, workers);
        let mut pass = Visits {
            visit,
            file_bytes,
            messages: 0,
            records: 0,
            last_log_time_ns: None,
        };
        let end = pass.read(source, &pool, file_bytes);
        pool.finish();
        match end.map_err(io_error)? {
            End::Damaged(d) if pass.records == 0 => Err(Error::File {
                path: label.clone(),
                reason: format!("not an MCAP file ({})", d.reason),
            }),
            end => Ok(Pass {
                end,
                file_bytes,
                messages: pass.messages,
            }),
        }
    })
}

/// The queue waits for its oldest chunk when it holds more than this many chunks per
/// worker, or more than [`QUEUE_BUDGET_BYTES`] of them (their stated sizes, compressed and
/// decompressed): enough to keep every worker busy, little enough to bound memory
/// whatever sizes a damaged file's chunks claim (a chunk is about 1 MiB). Anything ready
/// is handed on at once, so a visitor that stops early stops the pass early.
const CHUNKS_QUEUED_PER_WORKER: usize = 4;
const QUEUE_BUDGET_BYTES: u64 = 64 << 20;

/// A record read, or a chunk being decompressed, waiting its turn.
enum Queued {
    Record {
        record: Record<'static>,
        /// Bytes read when the record was: where its damage would be.
        at_byte: u64,
    },
    Chunk {
        records: Receiver<ChunkRecords>,
        ready: Option<ChunkRecords>,
        end_byte: u64,
        /// Its stated size, compressed and decompressed (the budget's share).
        bytes: u64,
    },
}

/// The queue of a pass and what it holds.
#[derive(Default)]
struct Queue {
    items: VecDeque<Queued>,
    chunks: usize,
    bytes: u64,
}

impl Queue {
    fn push(&mut self, item: Queued) {
        if let Queued::Chunk { bytes, .. } = &item {
            self.chunks += 1;
            self.bytes += bytes;
        }
        self.items.push_back(item);
    }

    /// The oldest item if it can be handed on: a record, or a chunk that is ready, or,
    /// when the queue is over its budget or `wait` is set, the oldest chunk once it is.
    fn pop_ready(&mut self, max_chunks: usize, wait: bool) -> Option<Queued> {
        let over = self.chunks > max_chunks || self.bytes > QUEUE_BUDGET_BYTES;
        if let Queued::Chunk { records, ready, .. } = self.items.front_mut()? {
            if ready.is_none() {
                let result = if over || wait {
                    records.recv().map_err(|_| ())
                } else {
                    match records.try_recv() {
                        Ok(r) => Ok(r),
                        Err(TryRecvError::Empty) => return None,
                        Err(TryRecvError::Disconnected) => Err(()),
                    }
                };
                *ready =
                    Some(result.unwrap_or_else(|()| Err("a chunk's decompression stopped".into())));
            }
        }
        let item = self.items.pop_front()?;
        if let Queued::Chunk { bytes, .. } = &item {
            self.chunks -= 1;
            self.bytes -= bytes;
        }
        Some(item)
    }
}

/// What is handed on, and the counts the damage report needs.
struct Visits<V> {
    visit: V,
    file_bytes: u64,
    messages: u64,
    records: u64,
    last_log_time_ns: Option<u64>,
}

/// After a queued item: go on, or end the pass.
enum Step {
    Go,
    End(End),
}

impl<V: FnMut(Record<'_>) -> std::result::Result<Flow, String>> Visits<V> {
    /// The linear pass: records outside chunks are queued as they come, chunks go to the
    /// pool; the queue is handed on in order. An I/O error is the only `Err`.
    fn read(
        &mut self,
        mut source: impl Read,
        pool: &ChunkPool<'_>,
        file_bytes: u64,
    ) -> std::io::Result<End> {
        let limit = record_limit_bytes(file_bytes);
        let mut reader = LinearReader::new_with_options(
            LinearReaderOptions::default()
                .with_emit_chunks(true)
                // The data section CRC covers everything outside chunks too (the metadata
                // and the attachments); the summary CRC the channel and statistics records
                // the summary repeats. Both are checked when the writer wrote them.
                .with_validate_data_section_crc(true)
                .with_validate_summary_section_crc(true)
                .with_record_length_limit(limit),
        );
        let max_chunks = pool.workers() * CHUNKS_QUEUED_PER_WORKER;
        let mut queue = Queue::default();
        let mut read_bytes = 0u64;
        let mut found: Option<String> = None;
        while let Some(event) = reader.next_event() {
            let queued = match event {
                Ok(LinearReadEvent::ReadRequest(want)) => {
                    let step = want.clamp(1, READ_STEP_BYTES);
                    let got = read_some(&mut source, reader.insert(step))?;
                    reader.notify_read(got);
                    read_bytes += got as u64;
                    continue;
                }
                Ok(LinearReadEvent::Record { opcode, data }) => {
                    queue_record(opcode, data, pool, limit, read_bytes)
                }
                Err(e) => Err(describe(&e, read_bytes, file_bytes)),
            };
            match queued {
                Ok(item) => queue.push(item),
                Err(reason) => {
                    found = Some(reason);
                    break;
                }
            }
            while let Some(item) = queue.pop_ready(max_chunks, false) {
                if let Step::End(end) = self.hand_on(item) {
                    return Ok(end);
                }
            }
        }
        while let Some(item) = queue.pop_ready(max_chunks, true) {
            if let Step::End(end) = self.hand_on(item) {
                return Ok(end);
            }
        }
        Ok(match found {
            None => End::Complete,
            Some(reason) => End::Damaged(self.damage(reason, read_bytes)),
        })
    }

    /// Hands on one queued item (a chunk: each of its records).
    fn hand_on(&mut self, item: Queued) -> Step {
        let (records, end_byte) = match item {
            Queued::Record { record, at_byte } => return self.one(record, at_byte),
            Queued::Chunk {
                ready, end_byte, ..
            } => (ready, end_byte),
        };
        let records = match records {
            Some(Ok(records)) => records,
            Some(Err(reason)) => return Step::End(End::Damaged(self.damage(reason, end_byte))),
            None => unreachable!("a chunk is handed on once ready"),
        };
        for next in chunk_records(&records) {
            let parsed = next.and_then(|(opcode, body)| {
                check_record_lengths(opcode, body)?;
                mcap::parse_record(opcode, body).map_err(|e| {
                    format!("record with opcode {opcode:#04x} in a chunk does not parse: {e}")
                })
            });
            let step = match parsed {
                Ok(record) => self.one(record, end_byte),
                Err(reason) => Step::End(End::Damaged(self.damage(reason, end_byte))),
            };
            if let Step::End(end) = step {
                return Step::End(end);
            }
        }
        Step::Go
    }

    fn one(&mut self, record: Record<'_>, at_byte: u64) -> Step {
        let log_time = match &record {
            Record::Message { header, .. } => Some(header.log_time),
            _ => None,
        };
        // Counted before the visit: a file whose header the visitor refuses is damaged,
        // not "no MCAP file".
        self.records += 1;
        match (self.visit)(record) {
            Ok(flow) => {
                if let Some(t) = log_time {
                    self.messages += 1;
                    self.last_log_time_ns = Some(t);
                }
                match flow {
                    Flow::Continue => Step::Go,
                    Flow::Stop => Step::End(End::Stopped),
                }
            }
            Err(reason) => Step::End(End::Damaged(self.damage(reason, at_byte))),
        }
    }

    fn damage(&self, reason: String, at_byte: u64) -> Damage {
        Damage {
            at_byte,
            file_bytes: self.file_bytes,
            messages_before: self.messages,
            last_log_time_ns: self.last_log_time_ns,
            reason,
        }
    }
}

/// A record of the linear pass, queued: a chunk goes to the pool (its header and the
/// lengths inside checked first), any other record is parsed.
fn queue_record(
    opcode: u8,
    data: &[u8],
    pool: &ChunkPool<'_>,
    limit: usize,
    read_bytes: u64,
) -> std::result::Result<Queued, String> {
    check_record_lengths(opcode, data)?;
    let record = mcap::parse_record(opcode, data)
        .map_err(|e| format!("record with opcode {opcode:#04x} does not parse: {e}"))?;
    Ok(match record {
        Record::Chunk { header, data } => Queued::Chunk {
            bytes: header.uncompressed_size.min(limit as u64) + data.len() as u64,
            records: pool.submit(&header, &data, limit),
            ready: None,
            end_byte: read_bytes,
        },
        other => Queued::Record {
            record: other.into_owned(),
            at_byte: read_bytes,
        },
    })
}

/// The reader's error in words a user can act on.
fn describe(e: &mcap::McapError, read_bytes: u64, file_bytes: u64) -> String {
    match e {
        mcap::McapError::UnexpectedEof if read_bytes >= file_bytes => {
            "the file is cut short: it ends before its footer (an interrupted run or a partial \
             copy)"
                .to_string()
        }
        // The streaming writer puts a chunk's length in place when the chunk is done:
        // until then the field holds all ones.
        mcap::McapError::RecordTooLarge { opcode: 0x06, len } if *len == u64::MAX => {
            "the file ends in a chunk its writer never finished (its length is still the \
             placeholder): the output of a killed run, or a copy of a run still writing"
                .to_string()
        }
        mcap::McapError::RecordTooLarge { opcode, len } => format!(
            "a record (opcode {opcode:#04x}) claims {len} bytes, more than the file can hold \
             (corrupted length)"
        ),
        mcap::McapError::ChunkTooLarge(len) => {
            format!("a chunk claims {len} bytes, more than the file can hold (corrupted length)")
        }
        other => other.to_string(),
    }
}

/// `read` that retries when interrupted by a signal.
fn read_some(source: &mut impl Read, buf: &mut [u8]) -> std::io::Result<usize> {
    loop {
        match source.read(buf) {
            Err(e) if e.kind() == ErrorKind::Interrupted => continue,
            other => return other,
        }
    }
}
