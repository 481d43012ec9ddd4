//! The files behind a file-backed [`McapSink`](super::McapSink): the `.partial` file
//! renamed when complete, and the parts of a run split by simulated time (their windows,
//! names, target checks and the records each part repeats).

use std::collections::BTreeMap;
use std::fs::{File, OpenOptions};
use std::io::{BufWriter, Seek, Write};
use std::path::{Path, PathBuf};

use mcap::records::Metadata;
use mcap::{Attachment, WriteOptions, Writer};

use super::writer::{chain, SinkOptions, ENCODING, SPLIT_METADATA};
use crate::error::{Error, Result};

/// The time windows of a split run, from [`SinkOptions`].
#[derive(Debug, Clone, Copy)]
pub(super) struct Split {
    pub(super) start_ns: u64,
    pub(super) every_ns: u64,
    pub(super) end_ns: Option<u64>,
    /// `ceil((end - start) / every)`, at least 1, when the end is known.
    pub(super) parts_total: Option<u64>,
}

impl Split {
    /// `None` unless `options.split_every_ns` asks for parts; an error if it is 0.
    pub(super) fn from_options(options: &SinkOptions, label: &str) -> Result<Option<Split>> {
        let Some(every_ns) = options.split_every_ns else {
            return Ok(None);
        };
        if every_ns == 0 {
            return Err(Error::Output {
                path: label.to_owned(),
                reason: "split_every_ns = 0 must be positive".into(),
            });
        }
        let start_ns = options.split_start_ns;
        let end_ns = options.split_end_ns;
        let parts_total = end_ns.map(|end| end.saturating_sub(start_ns).div_ceil(every_ns).max(1));
        Ok(Some(Split {
            start_ns,
            every_ns,
            end_ns,
            parts_total,
        }))
    }

    /// Log time where part `part` begins (saturated: such a part never begins).
    pub(super) fn start_of(&self, part: u64) -> u64 {
        part.saturating_mul(self.every_ns)
            .saturating_add(self.start_ns)
    }

    /// Log time from which messages go to the part after `part`; `u64::MAX` for the last.
    pub(super) fn next_after(&self, part: u64) -> u64 {
        match self.parts_total {
            Some(total) if part + 1 >= total => u64::MAX,
            _ => self.start_of(part + 1),
        }
    }

    /// The `split` metadata record of part `part`.
    pub(super) fn metadata(&self, part: u64) -> BTreeMap<String, String> {
        let end_ns = match (self.parts_total, self.end_ns) {
            (Some(total), Some(end_ns)) if part + 1 >= total => end_ns,
            _ => self.start_of(part + 1),
        };
        let mut record = BTreeMap::from([
            ("part".to_string(), part.to_string()),
            ("part_start_ns".to_string(), self.start_of(part).to_string()),
            ("part_end_ns".to_string(), end_ns.to_string()),
            (
                "split_every_s".to_string(),
                (self.every_ns as f64 / 1e9).to_string(),
            ),
        ]);
        if let Some(total) = self.parts_total {
            record.insert("parts_total".to_string(), total.to_string());
        }
        record
    }
}

/// Checks what [`McapSink::create`](super::McapSink::create) checks before it writes anything (a file name; for
/// a split run, not a directory; every target absent unless `options.force`), without
/// creating a file: so that a caller can refuse a run for other reasons (too little
/// space) after the errors a user should see first.
pub fn check_output(path: &Path, options: &SinkOptions) -> Result<()> {
    check_targets(path, options).map(drop)
}

/// [`check_output`], returning the split and the first file's target.
pub(super) fn check_targets(
    path: &Path,
    options: &SinkOptions,
) -> Result<(Option<Split>, PathBuf)> {
    let label = path.display().to_string();
    if path.file_name().is_none() {
        return Err(Error::Output {
            path: label,
            reason: "the output path has no file name".into(),
        });
    }
    let split = Split::from_options(options, &label)?;
    let target = match split {
        None => path.to_path_buf(),
        // `--out` is only the pattern of the parts' names, but a directory is a mistake.
        Some(_) if path.is_dir() => {
            return Err(Error::Output {
                path: label,
                reason: "is a directory".into(),
            });
        }
        Some(_) => part_path(path, 0),
    };
    check_target(&target, options.force)?;
    // Fail now rather than hours into the run.
    for part in 1..split.and_then(|s| s.parts_total).unwrap_or(1) {
        check_target(&part_path(path, part), options.force)?;
    }
    Ok((split, target))
}

/// The files of a sink made by [`McapSink::create`].
#[derive(Debug)]
pub(super) struct OutputPaths {
    /// The file being written, `<target>.partial`, renamed to `target` when complete.
    pub(super) partial: PathBuf,
    pub(super) target: PathBuf,
    /// The rotation state of a split run.
    pub(super) parts: Option<Parts>,
}

/// What a split sink needs to start the next part, and the parts it completed.
#[derive(Debug)]
pub(super) struct Parts {
    pub(super) split: Split,
    /// The path given to `create`, from which the parts are named.
    pub(super) out: PathBuf,
    pub(super) force: bool,
    pub(super) chunk_size_bytes: u64,
    /// Index of the part being written.
    pub(super) current: u64,
    /// Completed parts, renamed to their final names, in order.
    pub(super) done: Vec<PathBuf>,
    /// The records every part repeats at its start, in the order of the first part.
    pub(super) replay: Vec<Replay>,
    /// The previous part, being synced to disk and renamed on a background thread.
    pub(super) closing: Option<Closing>,
}

/// A finished part whose `sync_all` and rename run on their own thread: syncing an
/// hour of data takes seconds, and the time loop should not wait for it (the writer's
/// queue would fill and hold its batches for the rest of the run).
#[derive(Debug)]
pub(super) struct Closing {
    pub(super) handle: std::thread::JoinHandle<Result<()>>,
    pub(super) partial: PathBuf,
    pub(super) target: PathBuf,
}

impl Closing {
    /// Syncs `file` (the complete part, flushed) and renames `partial` to `target`, on a
    /// new thread.
    pub(super) fn start(file: File, partial: PathBuf, target: PathBuf, label: String) -> Self {
        let (from, to) = (partial.clone(), target.clone());
        let handle = std::thread::spawn(move || {
            sync_file(&file, &label)?;
            publish(&from, &to, &label)
        });
        Self {
            handle,
            partial,
            target,
        }
    }
}

impl Parts {
    /// Waits for the part being closed in the background: on success it joins `done`;
    /// on failure its `.partial` is deleted (it may not be on disk whole) and the error
    /// returned.
    pub(super) fn settle(&mut self) -> Result<()> {
        let Some(closing) = self.closing.take() else {
            return Ok(());
        };
        let outcome = closing.handle.join().unwrap_or_else(|_| {
            Err(Error::Output {
                path: closing.target.display().to_string(),
                reason: "the thread closing this part panicked".into(),
            })
        });
        match outcome {
            Ok(()) => {
                self.done.push(closing.target);
                Ok(())
            }
            Err(e) => {
                let _ = std::fs::remove_file(&closing.partial);
                Err(e)
            }
        }
    }
}

/// A record written before the first message, repeated at the start of every part.
#[derive(Debug)]
pub(super) enum Replay {
    Schema {
        id: u16,
        name: String,
        data: Vec<u8>,
    },
    Channel {
        id: u16,
        schema_id: u16,
        topic: String,
        metadata: BTreeMap<String, String>,
    },
    Metadata(Metadata),
    Attachment(Attachment<'static>),
}

/// `day.mcap` -> `day-0003.mcap`, `day` -> `day-0003`: the part number (4 digits, more
/// from part 10000 on) before the extension.
pub fn part_path(out: &Path, part: u64) -> PathBuf {
    let mut name = out.file_stem().unwrap_or_default().to_os_string();
    name.push(format!("-{part:04}"));
    if let Some(extension) = out.extension() {
        name.push(".");
        name.push(extension);
    }
    out.with_file_name(name)
}

/// The parts of a split run written with `--out out`: `out-0000.mcap`, `out-0001.mcap`,
/// ... as far as they go without a gap, then the `.partial` of the next part if a run was
/// interrupted there. Empty if `out` was not split.
pub fn existing_parts(out: &Path) -> Vec<PathBuf> {
    let mut parts = Vec::new();
    for part in 0.. {
        let path = part_path(out, part);
        if path.is_file() {
            parts.push(path);
            continue;
        }
        let mut partial = path.into_os_string();
        partial.push(".partial");
        let partial = PathBuf::from(partial);
        if partial.is_file() {
            parts.push(partial);
        }
        break;
    }
    parts
}

/// Refuses to write over `target` unless `force`, and never over a directory, device,
/// FIFO, socket or symlink. The error names `target`.
pub(super) fn check_target(target: &Path, force: bool) -> Result<()> {
    let fail = |reason: &str| Error::Output {
        path: target.display().to_string(),
        reason: reason.to_owned(),
    };
    if target.is_dir() {
        return Err(fail("is a directory"));
    }
    if let Ok(meta) = std::fs::symlink_metadata(target) {
        // Never rename a run over a device, FIFO, socket or symlink, even with force.
        if !meta.is_file() {
            return Err(fail("exists and is not a regular file"));
        }
        if !force {
            return Err(fail("already exists (use --force to overwrite)"));
        }
    }
    // An interrupted run keeps its data under the `.partial` name: a new run would
    // truncate it, so it is protected like a finished file.
    let partial = partial_path(target);
    if !force && std::fs::symlink_metadata(&partial).is_ok() {
        return Err(fail(&format!(
            "an interrupted run's data is kept in {} (use --force to overwrite it, or \
             move it away)",
            partial.display()
        )));
    }
    Ok(())
}

/// `<target>.partial`: where a run writes until it is complete.
pub(crate) fn partial_path(target: &Path) -> PathBuf {
    let mut name = target.file_name().unwrap_or_default().to_os_string();
    name.push(".partial");
    target.with_file_name(name)
}

/// Creates (or truncates a stale) `<target>.partial`; returns it and its path.
pub(super) fn open_partial(target: &Path) -> Result<(BufWriter<File>, PathBuf)> {
    let partial = partial_path(target);
    let file = OpenOptions::new()
        .write(true)
        .create(true)
        .truncate(true)
        .open(&partial)
        .map_err(|e| Error::Output {
            path: target.display().to_string(),
            reason: format!("cannot create {}: {e}", partial.display()),
        })?;
    Ok((BufWriter::new(file), partial))
}

/// A fresh MCAP writer (header written) with the options every bridgetwin file shares.
pub(super) fn new_writer<W: Write + Seek>(
    out: W,
    chunk_size_bytes: u64,
    label: &str,
) -> Result<Writer<W>> {
    WriteOptions::new()
        .library(concat!("bridgetwin/", env!("CARGO_PKG_VERSION")))
        .chunk_size(Some(chunk_size_bytes))
        // No zstd worker threads: byte-identical output for identical input.
        .compression_threads(0)
        .create(out)
        .map_err(|e| Error::Output {
            path: label.to_owned(),
            reason: chain(&e),
        })
}

/// Writes the summary and footer and hands back the writer's output, flushed.
pub(super) fn finish_writer<W: Write + Seek>(mut writer: Writer<W>, label: &str) -> Result<W> {
    let fail = |reason: String| Error::Output {
        path: label.to_owned(),
        reason,
    };
    writer
        .finish()
        .map_err(|e| fail(format!("finishing the MCAP failed: {}", chain(&e))))?;
    let mut out = writer.into_inner();
    out.flush()
        .map_err(|e| fail(format!("flush failed: {e}")))?;
    Ok(out)
}

/// Flushes a finished file's buffer and syncs the file to disk.
pub(super) fn sync(buffered: BufWriter<File>, label: &str) -> Result<()> {
    sync_file(&flush_file(buffered, label)?, label)
}

/// Flushes a finished file's buffer, returning the file.
pub(super) fn flush_file(buffered: BufWriter<File>, label: &str) -> Result<File> {
    buffered.into_inner().map_err(|e| Error::Output {
        path: label.to_owned(),
        reason: format!("flush failed: {}", e.error()),
    })
}

/// Syncs a flushed file to disk.
fn sync_file(file: &File, label: &str) -> Result<()> {
    file.sync_all().map_err(|e| Error::Output {
        path: label.to_owned(),
        reason: format!("sync failed: {e}"),
    })
}

/// Renames a complete file from `partial` to `target`, and makes the rename itself durable
/// (the directory entry), as `sync` did the data.
pub(super) fn publish(partial: &Path, target: &Path, label: &str) -> Result<()> {
    let fail = |reason: String| Error::Output {
        path: label.to_owned(),
        reason,
    };
    std::fs::rename(partial, target)
        .map_err(|e| fail(format!("cannot rename {}: {e}", partial.display())))?;
    if let Some(parent) = target.parent() {
        // A bare file name has the empty path as parent: the current directory.
        let dir = if parent.as_os_str().is_empty() {
            Path::new(".")
        } else {
            parent
        };
        File::open(dir)
            .and_then(|d| d.sync_all())
            .map_err(|e| fail(format!("cannot sync directory {}: {e}", dir.display())))?;
    }
    Ok(())
}

/// Writes what opens part `part` of a split run: its `split` metadata record, then the
/// first part's metadata, attachments, schemas and channels, in their order and with
/// their ids.
pub(super) fn write_part_start<W: Write + Seek>(
    writer: &mut Writer<W>,
    parts: &Parts,
    part: u64,
    label: &str,
) -> Result<()> {
    let fail = |what: &str, e: mcap::McapError| Error::Output {
        path: label.to_owned(),
        reason: format!("{what}: {}", chain(&e)),
    };
    let split = Metadata {
        name: SPLIT_METADATA.to_owned(),
        metadata: parts.split.metadata(part),
    };
    writer
        .write_metadata(&split)
        .map_err(|e| fail("metadata split", e))?;
    for record in &parts.replay {
        match record {
            Replay::Schema { id, name, data } => writer
                .add_schema_with_id(*id, name, ENCODING, data)
                .map(drop)
                .map_err(|e| fail(&format!("schema {name}"), e))?,
            Replay::Channel {
                id,
                schema_id,
                topic,
                metadata,
            } => writer
                .add_channel_with_id(*id, *schema_id, topic, ENCODING, metadata)
                .map(drop)
                .map_err(|e| fail(&format!("channel {topic}"), e))?,
            Replay::Metadata(record) => writer
                .write_metadata(record)
                .map_err(|e| fail(&format!("metadata {}", record.name), e))?,
            Replay::Attachment(attachment) => writer
                .attach(attachment)
                .map_err(|e| fail(&format!("attachment {}", attachment.name), e))?,
        }
    }
    Ok(())
}
