//! One pass over the records of an MCAP file that nothing in the file can crash: every
//! length the file states is checked against what the file can hold before anything is
//! allocated for it, chunks are checked against their CRC before any record inside them is
//! handed on, the data and summary sections against theirs, and damage ends the pass with
//! a [`Damage`] that says where the intact part ends instead of an error that loses what
//! was read.
//!
//! The pass is the `mcap` crate's sans-io linear reader: it works the same on a complete
//! file and on the `.partial` file of a killed run (no summary, last chunk cut short).

use std::fs::File;
use std::io::{BufReader, ErrorKind, Read};
use std::path::Path;

use mcap::records::Record;
use mcap::sans_io::{LinearReadEvent, LinearReader, LinearReaderOptions};

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
/// `visit`. A visitor's `Err(reason)` counts as damage at that record (a message that
/// does not decode). Fails only when the file cannot be opened or read, or holds no MCAP
/// header at all (bad magic, empty, garbage); every later problem is a [`Damage`].
pub fn read_records(
    path: &Path,
    mut visit: impl FnMut(Record<'_>) -> std::result::Result<Flow, String>,
) -> Result<Pass> {
    let label = path.display().to_string();
    let io_error = |e: std::io::Error| Error::File {
        path: label.clone(),
        reason: e.to_string(),
    };
    let file = File::open(path).map_err(io_error)?;
    let file_bytes = file.metadata().map_err(io_error)?.len();
    let mut source = BufReader::with_capacity(1 << 20, file);
    let mut reader = LinearReader::new_with_options(
        LinearReaderOptions::default()
            .with_prevalidate_chunk_crcs(true)
            // The data section CRC covers everything outside chunks too (the metadata and
            // the attachments); the summary CRC the channel and statistics records the
            // summary repeats. Both are checked when the writer wrote them (non-zero).
            .with_validate_data_section_crc(true)
            .with_validate_summary_section_crc(true)
            .with_record_length_limit(record_limit_bytes(file_bytes)),
    );
    let mut read_bytes = 0u64;
    let mut messages = 0u64;
    let mut last_log_time_ns = None;
    let mut records = 0u64;
    let damage = |reason: String, read_bytes, messages, last_log_time_ns| Damage {
        at_byte: read_bytes,
        file_bytes,
        messages_before: messages,
        last_log_time_ns,
        reason,
    };
    while let Some(event) = reader.next_event() {
        let reason = match event {
            Ok(LinearReadEvent::ReadRequest(want)) => {
                let step = want.clamp(1, READ_STEP_BYTES);
                let got = read_some(&mut source, reader.insert(step)).map_err(io_error)?;
                reader.notify_read(got);
                read_bytes += got as u64;
                continue;
            }
            Ok(LinearReadEvent::Record { opcode, data }) => {
                let parsed = check_record_lengths(opcode, data)
                    .and_then(|()| mcap::parse_record(opcode, data).map_err(|e| e.to_string()));
                match parsed {
                    Ok(record) => {
                        if let Record::Message { header, .. } = &record {
                            messages += 1;
                            last_log_time_ns = Some(header.log_time);
                        }
                        records += 1;
                        match visit(record) {
                            Ok(Flow::Continue) => continue,
                            Ok(Flow::Stop) => {
                                return Ok(Pass {
                                    end: End::Stopped,
                                    file_bytes,
                                    messages,
                                })
                            }
                            Err(reason) => reason,
                        }
                    }
                    Err(e) => format!("record with opcode {opcode:#04x} does not parse: {e}"),
                }
            }
            Err(e) => describe(&e, read_bytes, file_bytes),
        };
        if records == 0 {
            return Err(Error::File {
                path: label,
                reason: format!("not an MCAP file ({reason})"),
            });
        }
        let found = damage(reason, read_bytes, messages, last_log_time_ns);
        return Ok(Pass {
            end: End::Damaged(found),
            file_bytes,
            messages,
        });
    }
    Ok(Pass {
        end: End::Complete,
        file_bytes,
        messages,
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
