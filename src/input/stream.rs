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
use std::sync::mpsc::Receiver;

use mcap::records::Record;
use mcap::sans_io::{LinearReadEvent, LinearReader, LinearReaderOptions};

use super::chunks::{chunk_records, workers, ChunkPool};
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
/// [`Damage`]. Chunks are decompressed and checked on worker threads ([`ChunkPool`])
/// while this thread reads on; a chunk's records are handed on only when its CRC holds.
pub fn read_records(
    path: &Path,
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
        let pool = ChunkPool::start(scope, workers());
        let mut pass = Visits {
            visit,
            file_bytes,
            messages: 0,
            records: 0,
            last_log_time_ns: None,
        };
        let end = pass.read(source, &pool, file_bytes).map_err(io_error)?;
        match end {
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

/// At most this many chunks per worker wait in the queue: enough to keep every worker
/// busy, few enough to bound memory (a chunk is about 1 MiB). The records between them
/// (a message index per channel after each chunk) wait with them.
const CHUNKS_QUEUED_PER_WORKER: usize = 4;

/// A record read, or a chunk being decompressed, waiting its turn.
enum Queued {
    Record(Record<'static>),
    Chunk {
        records: Receiver<std::result::Result<Vec<u8>, String>>,
        /// Bytes read when the chunk was: where its damage would be.
        end_byte: u64,
    },
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
        pool: &ChunkPool,
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
        let mut queue: VecDeque<Queued> = VecDeque::new();
        let (mut chunks, max_chunks) = (0usize, pool.workers() * CHUNKS_QUEUED_PER_WORKER);
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
                Ok(item) => {
                    chunks += usize::from(matches!(item, Queued::Chunk { .. }));
                    queue.push_back(item);
                }
                Err(reason) => {
                    found = Some(reason);
                    break;
                }
            }
            while chunks > max_chunks {
                let front = queue.pop_front();
                chunks -= usize::from(matches!(front, Some(Queued::Chunk { .. })));
                if let Step::End(end) = self.hand_on(front, read_bytes) {
                    return Ok(end);
                }
            }
        }
        while let Some(item) = queue.pop_front() {
            if let Step::End(end) = self.hand_on(Some(item), read_bytes) {
                return Ok(end);
            }
        }
        Ok(match found {
            None => End::Complete,
            Some(reason) => End::Damaged(self.damage(reason, read_bytes)),
        })
    }

    /// Hands on one queued item (a chunk: each of its records).
    fn hand_on(&mut self, item: Option<Queued>, read_bytes: u64) -> Step {
        match item {
            None => Step::Go,
            Some(Queued::Record(record)) => self.one(record, read_bytes),
            Some(Queued::Chunk { records, end_byte }) => {
                let records = records
                    .recv()
                    .unwrap_or_else(|_| Err("a chunk's decompression stopped".into()));
                let records = match records {
                    Ok(records) => records,
                    Err(reason) => return Step::End(End::Damaged(self.damage(reason, end_byte))),
                };
                for next in chunk_records(&records) {
                    let parsed = next.and_then(|(opcode, body)| {
                        check_record_lengths(opcode, body)?;
                        mcap::parse_record(opcode, body).map_err(|e| {
                            format!(
                                "record with opcode {opcode:#04x} in a chunk does not parse: {e}"
                            )
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
        }
    }

    fn one(&mut self, record: Record<'_>, at_byte: u64) -> Step {
        let log_time = match &record {
            Record::Message { header, .. } => Some(header.log_time),
            _ => None,
        };
        match (self.visit)(record) {
            Ok(flow) => {
                self.records += 1;
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
    pool: &ChunkPool,
    limit: usize,
    read_bytes: u64,
) -> std::result::Result<Queued, String> {
    check_record_lengths(opcode, data)?;
    let record = mcap::parse_record(opcode, data)
        .map_err(|e| format!("record with opcode {opcode:#04x} does not parse: {e}"))?;
    Ok(match record {
        Record::Chunk { header, data } => Queued::Chunk {
            records: pool.submit(&header, &data, limit),
            end_byte: read_bytes,
        },
        other => Queued::Record(other.into_owned()),
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
