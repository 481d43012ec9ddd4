//! The streaming MCAP writer used by the simulation loop, and the splitting of a long run
//! into one file per stretch of simulated time.

use std::borrow::Cow;
use std::collections::BTreeMap;
use std::fs::File;
use std::io::{BufWriter, Cursor, Seek, Write};
use std::path::{Path, PathBuf};

use mcap::records::{MessageHeader, Metadata};
use mcap::{Attachment, WriteOptions, Writer};

use super::estimate::ChannelTotals;
use super::parts::{
    check_target, check_targets, finish_writer, flush_file, new_writer, open_partial, part_path,
    publish, sync, write_part_start, Closing, OutputPaths, Parts, Replay,
};
use super::schema::self_contained_descriptor_set;
use super::topics::validate_topic;
use crate::error::{Error, Result};

/// Schema and message encoding of every channel.
pub(super) const ENCODING: &str = "protobuf";

/// The metadata record that describes each part of a split run.
pub(super) const SPLIT_METADATA: &str = "split";

/// Options of [`McapSink`]. Plain data; `Default` gives the values documented per field.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SinkOptions {
    /// Replace an existing output file (at `finish`). Default: `false`, refuse it.
    pub force: bool,
    /// Target uncompressed chunk size, bytes. Default: 1 MiB, the `mcap` crate's default
    /// (Foxglove measured nothing to gain above it).
    pub chunk_size_bytes: u64,
    /// Starts a new file every this much log time, ns (> 0): [`McapSink::create`] with
    /// `day.mcap` then writes `day-0000.mcap`, `day-0001.mcap`, ... (see [`McapSink`]).
    /// Default: `None`, one file. Only `create` splits: `in_memory` and `on_writer` refuse
    /// it. `sweep` leaves it unset: one file per run, whatever the scenario says.
    pub split_every_ns: Option<u64>,
    /// Where part 0 begins, Unix-epoch ns: the scenario start. Default: 0. Used only with
    /// `split_every_ns`.
    pub split_start_ns: u64,
    /// The run's last log time (`start + duration`), Unix-epoch ns, if known. Default:
    /// `None`. With it the number of parts is known in advance: `create` checks every
    /// part's target at once, each part records `parts_total`, the last part also holds
    /// the closing instant (instead of a file of its own), and `finish` writes every part,
    /// empty ones too. Used only with `split_every_ns`.
    pub split_end_ns: Option<u64>,
}

impl Default for SinkOptions {
    fn default() -> Self {
        Self {
            force: false,
            chunk_size_bytes: WriteOptions::DEFAULT_CHUNK_SIZE,
            split_every_ns: None,
            split_start_ns: 0,
            split_end_ns: None,
        }
    }
}

/// A channel registered with [`McapSink::add_channel`]; valid only for that sink.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct ChannelId(usize);

#[derive(Debug)]
pub(super) struct Channel {
    mcap_id: u16,
    topic: String,
    /// `prost::Name` of the channel's message type, checked on every write.
    package: &'static str,
    name: &'static str,
    /// Sequence number of the last message written (the first message gets 1). It runs on
    /// across the parts of a split run.
    sequence: u32,
    /// Encoded message bytes written (payloads only), for the estimate's probe.
    payload_bytes: u64,
}

/// Streams protobuf messages into an MCAP file (zstd chunks, all indexes and statistics).
///
/// A file sink writes to `<path>.partial` and renames it to `<path>` in [`finish`]; a run
/// that stops early can keep its data under the `.partial` name with [`finish_partial`].
/// **Dropped without either**, the sink leaves the `.partial` file in place: the `mcap`
/// writer's own `Drop` tries to close it (errors discarded), so it is usually readable,
/// and it is never deleted, so that a crashed run can be inspected.
///
/// Messages must arrive in non-decreasing `log_time` across all channels (the caller
/// merges its sources); `log_time = publish_time`, which must equal the message's
/// `timestamp` field.
///
/// # Split runs
/// With [`SinkOptions::split_every_ns`], `create("day.mcap")` writes `day-0000.mcap`,
/// `day-0001.mcap`, ...: part `k` holds the messages with log time in
/// `[start + k every, start + (k + 1) every)`; the first part also takes any message
/// before `start`, and when the run's end is known the last part takes everything from
/// its start on, the closing instant `start + duration` included (so a 24 h run split
/// hourly gives 24 files, not 24 and a 25th with one instant in it).
///
/// - Each part is a complete MCAP: the sink remembers the schemas and channels it
///   registered and the metadata and attachments written before the first message, and
///   repeats them at the start of every part (same order, same channel ids), after a
///   `split` metadata record (`part`, `parts_total` when known, `part_start_ns`,
///   `part_end_ns`, `split_every_s`). Metadata and attachments written after the first
///   message go into the current part only. A part is cut when `write` gets its first
///   message at or past the next boundary; a window without messages still gets its
///   (empty) part.
/// - Sequence numbers run on across parts: a message keeps the number it has in the
///   unsplit run, so concatenated parts equal that run and a gap still means a lost
///   message, not a new file.
/// - Memory stays flat: the `mcap` writer keeps an index entry per chunk until its file
///   ends, and each part's writer is dropped with its part.
/// - The part being written is `day-000k.mcap.partial`, renamed when complete. Every
///   part's target is checked when the part is created (and all of them at `create` when
///   the end is known): without `force` an existing one is an error naming it.
///   [`finish_partial`] closes the current part and keeps its `.partial` name;
///   [`discard`] deletes only the current `.partial`: the completed parts are whole,
///   valid files and stay. [`parts`] lists the completed parts; [`finish_parts`] all.
///
/// [`finish`]: McapSink::finish
/// [`finish_partial`]: McapSink::finish_partial
/// [`finish_parts`]: McapSink::finish_parts
/// [`discard`]: McapSink::discard
/// [`parts`]: McapSink::parts
pub struct McapSink<W: Write + Seek = BufWriter<File>> {
    writer: Writer<W>,
    /// Names the output (the part being written) in error messages.
    label: String,
    paths: Option<OutputPaths>,
    /// Schema id per fully qualified message name: one schema record per type.
    schemas: BTreeMap<String, u16>,
    channels: Vec<Channel>,
    /// Reused encode buffer: no allocation per message once it has grown.
    buffer: Vec<u8>,
    last_log_time_ns: u64,
    /// Log time from which `write` starts the next part: `u64::MAX` unless split, so the
    /// check costs one comparison per message.
    next_part_ns: u64,
    /// Closes the current part and opens the next (split file sinks only): a function of
    /// the file sink's concrete type, called from the generic `write`.
    start_next_part: Option<fn(&mut Self) -> Result<()>>,
}

impl McapSink<BufWriter<File>> {
    /// Starts writing `<path>.partial` (split: `<stem>-0000.<ext>.partial`). Fails,
    /// creating nothing, if the target exists and `options.force` is false, or if `path`
    /// is a directory. A stale `.partial` from an earlier run is overwritten.
    pub fn create(path: &Path, options: SinkOptions) -> Result<Self> {
        let (split, target) = check_targets(path, &options)?;
        let label = target.display().to_string();
        let (out, partial) = open_partial(&target)?;
        let parts = split.map(|split| Parts {
            split,
            out: path.to_path_buf(),
            force: options.force,
            chunk_size_bytes: options.chunk_size_bytes,
            current: 0,
            done: Vec::new(),
            closing: None,
            replay: Vec::new(),
        });
        let paths = OutputPaths {
            partial: partial.clone(),
            target,
            parts,
        };
        Self::with_writer(out, &options, label, Some(paths))
            .and_then(|mut sink| {
                if let Some(parts) = sink.paths.as_ref().and_then(|p| p.parts.as_ref()) {
                    sink.next_part_ns = parts.split.next_after(0);
                    sink.start_next_part = Some(Self::start_next_part);
                    write_part_start(&mut sink.writer, parts, 0, &sink.label)?;
                }
                Ok(sink)
            })
            .inspect_err(|_| {
                // Nothing useful was written: leave no file behind.
                let _ = std::fs::remove_file(&partial);
            })
    }

    /// Closes the file cleanly (summary, footer, `sync_all`) and renames `.partial` to the
    /// final name. Returns the final path: of a split run, the last part's (the others:
    /// [`finish_parts`](Self::finish_parts)).
    pub fn finish(self) -> Result<PathBuf> {
        let label = self.label.clone();
        self.finish_parts()?.pop().ok_or_else(|| Error::Output {
            path: label,
            reason: "no file written (bug)".into(),
        })
    }

    /// Like [`finish`](Self::finish), returning every file written, in order: the one
    /// file, or all the parts. When the run's end is known, first writes the parts still
    /// to come (empty), so that there are `parts_total` of them.
    pub fn finish_parts(mut self) -> Result<Vec<PathBuf>> {
        while let Some(parts) = self.paths.as_ref().and_then(|p| p.parts.as_ref()) {
            match parts.split.parts_total {
                Some(total) if parts.current + 1 < total => self.start_next_part()?,
                _ => break,
            }
        }
        self.settle()?;
        let label = self.label.clone();
        let paths = self.close_file()?;
        publish(&paths.partial, &paths.target, &label)?;
        let mut written = paths.parts.map(|p| p.done).unwrap_or_default();
        written.push(paths.target);
        Ok(written)
    }

    /// Closes the file cleanly like [`finish`](Self::finish) but keeps the `.partial` name:
    /// for an interrupted run whose data is valid but incomplete. Returns the `.partial` path
    /// (of a split run: the current part's; the completed parts keep their final names,
    /// see [`parts`](Self::parts)).
    pub fn finish_partial(mut self) -> Result<PathBuf> {
        self.settle()?;
        Ok(self.close_file()?.partial)
    }

    /// Gives up on a failed run: closes the file and deletes the `.partial`, so that bad
    /// input or a failed run leaves nothing behind. Of a split run only the current part's
    /// `.partial` goes: the completed parts are whole, valid files and stay.
    pub fn discard(mut self) {
        // A previous part still closing is whole: let it finish (its own failure deletes
        // its `.partial`).
        let _ = self.settle();
        let partial = self.paths.as_ref().map(|p| p.partial.clone());
        drop(self);
        if let Some(partial) = partial {
            let _ = std::fs::remove_file(partial);
        }
    }

    /// The completed parts of a split run so far (synced and renamed to their final
    /// names), in order; empty for a single file. Waits for the part just finished, whose
    /// sync runs in the background (a failed sync leaves it out, deletes its
    /// `.partial` and is the error returned).
    pub fn parts(&mut self) -> Result<&[PathBuf]> {
        self.settle()?;
        Ok(self
            .paths
            .as_ref()
            .and_then(|p| p.parts.as_ref())
            .map_or(&[], |p| p.done.as_slice()))
    }

    fn close_file(self) -> Result<OutputPaths> {
        let label = self.label.clone();
        let (buffered, paths) = self.close()?;
        sync(buffered, &label)?;
        paths.ok_or_else(|| Error::Output {
            path: label,
            reason: "file sink without paths (bug)".into(),
        })
    }

    /// Ends the current part and continues in the next. In this order: the part closed
    /// before is waited for ([`Parts::settle`]); the next part's target is checked and its
    /// `.partial` created with a bare MCAP header (if that fails, the current part is
    /// still open, and the failed run's `discard` deletes it); the current part gets its
    /// summary and footer (if that fails, its `.partial` is deleted here: it is not a
    /// complete file) and is synced and renamed on a background thread ([`Closing`]);
    /// then the first part's records are repeated in the new one. Closing before filling the next keeps one chunk buffer and one zstd
    /// context alive at a time: the peak memory of a rotation is that of a single file.
    fn start_next_part(&mut self) -> Result<()> {
        self.settle()?;
        let Some(parts) = self.paths.as_ref().and_then(|p| p.parts.as_ref()) else {
            return Err(self.error("not a split file sink (bug)".into()));
        };
        let next = parts.current + 1;
        let target = part_path(&parts.out, next);
        check_target(&target, parts.force)?;
        let label = target.display().to_string();
        let (out, partial) = open_partial(&target)?;
        let writer = match new_writer(out, parts.chunk_size_bytes, &label) {
            Ok(writer) => writer,
            Err(e) => {
                let _ = std::fs::remove_file(&partial);
                return Err(e);
            }
        };
        let previous = std::mem::replace(&mut self.writer, writer);
        let previous_label = std::mem::replace(&mut self.label, label);
        let Some(OutputPaths {
            partial: current_partial,
            target: current_target,
            parts: Some(parts),
        }) = self.paths.as_mut()
        else {
            return Err(self.error("not a split file sink (bug)".into()));
        };
        let previous_partial = std::mem::replace(current_partial, partial);
        let previous_target = std::mem::replace(current_target, target);
        parts.current = next;
        self.next_part_ns = parts.split.next_after(next);
        let file = match finish_writer(previous, &previous_label)
            .and_then(|buffered| flush_file(buffered, &previous_label))
        {
            Ok(file) => file,
            Err(e) => {
                let _ = std::fs::remove_file(&previous_partial);
                return Err(e);
            }
        };
        parts.closing = Some(Closing::start(
            file,
            previous_partial,
            previous_target,
            previous_label,
        ));
        write_part_start(&mut self.writer, parts, next, &self.label)
    }

    /// Waits for the previous part of a split run to be synced and renamed (nothing to
    /// wait for otherwise).
    fn settle(&mut self) -> Result<()> {
        match self.paths.as_mut().and_then(|p| p.parts.as_mut()) {
            Some(parts) => parts.settle(),
            None => Ok(()),
        }
    }
}

impl McapSink<Cursor<Vec<u8>>> {
    /// A sink that writes into memory, for tests and tools; `options.force` is ignored.
    /// It cannot split: `options.split_every_ns` is an error.
    pub fn in_memory(options: &SinkOptions) -> Result<Self> {
        Self::with_writer(Cursor::new(Vec::new()), options, "<memory>".into(), None)
    }

    /// Closes the MCAP and returns its bytes.
    pub fn finish_to_bytes(self) -> Result<Vec<u8>> {
        Ok(self.close()?.0.into_inner())
    }
}

impl<W: Write + Seek> McapSink<W> {
    /// A sink on any seekable writer (a socket-backed buffer, a test double); `label`
    /// names it in errors. `options.force` is ignored; `options.split_every_ns` is an
    /// error (splitting needs file names).
    pub fn on_writer(out: W, options: &SinkOptions, label: &str) -> Result<Self> {
        Self::with_writer(out, options, label.to_owned(), None)
    }

    /// Closes the MCAP of a sink made by [`McapSink::on_writer`] and hands back its writer.
    pub fn finish_to_writer(self) -> Result<W> {
        Ok(self.close()?.0)
    }

    fn with_writer(
        out: W,
        options: &SinkOptions,
        label: String,
        paths: Option<OutputPaths>,
    ) -> Result<Self> {
        if paths.is_none() && options.split_every_ns.is_some() {
            return Err(Error::Output {
                path: label,
                reason: "only a file sink (McapSink::create) can split its output".into(),
            });
        }
        let writer = new_writer(out, options.chunk_size_bytes, &label)?;
        Ok(Self {
            writer,
            label,
            paths,
            schemas: BTreeMap::new(),
            channels: Vec::new(),
            buffer: Vec::new(),
            last_log_time_ns: 0,
            next_part_ns: u64::MAX,
            start_next_part: None,
        })
    }

    /// The rotation state of a split sink, to record what every part repeats.
    fn parts_mut(&mut self) -> Option<&mut Parts> {
        self.paths.as_mut().and_then(|p| p.parts.as_mut())
    }

    /// Registers `topic` carrying messages of type `M`. The schema record (fully qualified
    /// name, self-contained descriptor set) is written once per type. `metadata` should
    /// give units, sample rate, sensor position and model. A topic can be added once.
    pub fn add_channel<M: prost::Name>(
        &mut self,
        topic: &str,
        metadata: BTreeMap<String, String>,
    ) -> Result<ChannelId> {
        validate_topic(topic)?;
        if self.channels.iter().any(|c| c.topic == topic) {
            return Err(self.error(format!("topic {topic} was already added")));
        }
        let full_name = M::full_name();
        let schema_id = match self.schemas.get(&full_name) {
            Some(&id) => id,
            None => {
                let data = self_contained_descriptor_set(&full_name)?;
                let id = self
                    .writer
                    .add_schema(&full_name, ENCODING, &data)
                    .map_err(|e| self.error(format!("schema {full_name}: {}", chain(&e))))?;
                if let Some(parts) = self.parts_mut() {
                    parts.replay.push(Replay::Schema {
                        id,
                        name: full_name.clone(),
                        data,
                    });
                }
                self.schemas.insert(full_name, id);
                id
            }
        };
        let mcap_id = self
            .writer
            .add_channel(schema_id, topic, ENCODING, &metadata)
            .map_err(|e| self.error(format!("channel {topic}: {}", chain(&e))))?;
        if let Some(parts) = self.parts_mut() {
            parts.replay.push(Replay::Channel {
                id: mcap_id,
                schema_id,
                topic: topic.to_owned(),
                metadata,
            });
        }
        self.channels.push(Channel {
            mcap_id,
            topic: topic.to_owned(),
            package: M::PACKAGE,
            name: M::NAME,
            sequence: 0,
            payload_bytes: 0,
        });
        Ok(ChannelId(self.channels.len() - 1))
    }

    /// Writes one message with `log_time = publish_time = log_time_ns` (Unix-epoch ns,
    /// which must equal `message.timestamp`). Fails if `M` is not the channel's type, if
    /// `log_time_ns` is 0 or earlier than the previous message's. In a split run, a
    /// message at or past the next boundary first closes the current part and opens the
    /// next.
    pub fn write<M: prost::Message + prost::Name>(
        &mut self,
        channel: ChannelId,
        log_time_ns: u64,
        message: &M,
    ) -> Result<()> {
        if log_time_ns == 0 {
            return Err(self.error("log_time_ns = 0 (timestamps are Unix-epoch ns)".into()));
        }
        if log_time_ns < self.last_log_time_ns {
            return Err(self.error(format!(
                "log_time_ns = {log_time_ns} is before the previous message's {} \
                 (messages must be merged in time order)",
                self.last_log_time_ns
            )));
        }
        let Some(state) = self.channels.get(channel.0) else {
            return Err(self.error(format!("{channel:?} is not a channel of this sink")));
        };
        if state.package != M::PACKAGE || state.name != M::NAME {
            let reason = format!(
                "{} carries {}.{}, not {}",
                state.topic,
                state.package,
                state.name,
                M::full_name()
            );
            return Err(self.error(reason));
        }
        let Some(sequence) = state.sequence.checked_add(1) else {
            let reason = format!("{}: more than u32::MAX messages", state.topic);
            return Err(self.error(reason));
        };
        let header = MessageHeader {
            channel_id: state.mcap_id,
            sequence,
            log_time: log_time_ns,
            publish_time: log_time_ns,
        };
        if log_time_ns >= self.next_part_ns {
            self.start_parts_until(log_time_ns)?;
        }
        self.buffer.clear();
        // Encoding into a Vec cannot fail: it grows as needed.
        message
            .encode(&mut self.buffer)
            .map_err(|e| Error::Output {
                path: self.label.clone(),
                reason: chain(&e),
            })?;
        self.writer
            .write_to_known_channel(&header, &self.buffer)
            .map_err(|e| Error::Output {
                path: self.label.clone(),
                reason: chain(&e),
            })?;
        if let Some(state) = self.channels.get_mut(channel.0) {
            state.sequence = sequence;
            state.payload_bytes += self.buffer.len() as u64;
        }
        self.last_log_time_ns = log_time_ns;
        Ok(())
    }

    /// Starts parts until the one that holds `log_time_ns` (several if whole windows had
    /// no message: each still gets its part).
    fn start_parts_until(&mut self, log_time_ns: u64) -> Result<()> {
        let Some(start_next_part) = self.start_next_part else {
            return Err(self.error("a part boundary without a split file sink (bug)".into()));
        };
        while log_time_ns >= self.next_part_ns {
            start_next_part(self)?;
        }
        Ok(())
    }

    /// Writes a metadata record (`bridgetwin`, `scenario`, `bridge_model`). Closes the
    /// current chunk: call at the start or end of a run. Of a split run, the records
    /// written before the first message are repeated in every part.
    pub fn write_metadata(&mut self, name: &str, metadata: BTreeMap<String, String>) -> Result<()> {
        let record = Metadata {
            name: name.to_owned(),
            metadata,
        };
        self.writer
            .write_metadata(&record)
            .map_err(|e| self.error(format!("metadata {name}: {}", chain(&e))))?;
        let before_messages = self.last_log_time_ns == 0;
        if let Some(parts) = self.parts_mut().filter(|_| before_messages) {
            parts.replay.push(Replay::Metadata(record));
        }
        Ok(())
    }

    /// Attaches a file (scenario TOML, road profile CSV). `log_time_ns` is also used as the
    /// creation time, so output stays reproducible. Closes the current chunk. Of a split
    /// run, the attachments written before the first message are repeated in every part.
    pub fn attach(
        &mut self,
        name: &str,
        media_type: &str,
        data: &[u8],
        log_time_ns: u64,
    ) -> Result<()> {
        let attachment = Attachment {
            log_time: log_time_ns,
            create_time: log_time_ns,
            name: name.to_owned(),
            media_type: media_type.to_owned(),
            data: Cow::Borrowed(data),
        };
        self.writer
            .attach(&attachment)
            .map_err(|e| self.error(format!("attachment {name}: {}", chain(&e))))?;
        let before_messages = self.last_log_time_ns == 0;
        if let Some(parts) = self.parts_mut().filter(|_| before_messages) {
            let owned = Attachment {
                data: Cow::Owned(data.to_vec()),
                ..attachment
            };
            parts.replay.push(Replay::Attachment(owned));
        }
        Ok(())
    }

    /// Closes the current chunk and flushes it to the file, so that a run killed later
    /// stays readable up to here. Costs compression ratio if called very often.
    pub fn flush(&mut self) -> Result<()> {
        self.writer
            .flush()
            .map_err(|e| self.error(format!("flush failed: {}", chain(&e))))
    }

    /// Number of messages written on `channel` so far (over all parts of a split run).
    pub fn message_count(&self, channel: ChannelId) -> u64 {
        self.channels
            .get(channel.0)
            .map_or(0, |c| u64::from(c.sequence))
    }

    /// Messages and payload bytes written on each channel so far, in registration order.
    pub(super) fn channel_totals(&self) -> Vec<ChannelTotals> {
        self.channels
            .iter()
            .map(|c| ChannelTotals {
                topic: c.topic.clone(),
                schema: format!("{}.{}", c.package, c.name),
                messages: u64::from(c.sequence),
                payload_bytes: c.payload_bytes,
            })
            .collect()
    }

    /// Writes the summary and footer and hands back the underlying writer.
    fn close(self) -> Result<(W, Option<OutputPaths>)> {
        let out = finish_writer(self.writer, &self.label)?;
        Ok((out, self.paths))
    }

    fn error(&self, reason: String) -> Error {
        Error::Output {
            path: self.label.clone(),
            reason,
        }
    }
}

/// An error with its causes ("I/O error from writing: No space left on device"): the
/// MCAP writer's own message hides the OS error in its source.
pub(super) fn chain(error: &dyn std::error::Error) -> String {
    let mut text = error.to_string();
    let mut source = error.source();
    while let Some(cause) = source {
        let cause_text = cause.to_string();
        if !text.contains(&cause_text) {
            text.push_str(": ");
            text.push_str(&cause_text);
        }
        source = cause.source();
    }
    text
}
