//! The streaming MCAP writer used by the simulation loop.

use std::borrow::Cow;
use std::collections::BTreeMap;
use std::fs::{File, OpenOptions};
use std::io::{BufWriter, Cursor, Seek, Write};
use std::path::{Path, PathBuf};

use mcap::records::{MessageHeader, Metadata};
use mcap::{Attachment, WriteOptions, Writer};

use super::schema::self_contained_descriptor_set;
use super::topics::validate_topic;
use crate::error::{Error, Result};

/// Schema and message encoding of every channel.
const ENCODING: &str = "protobuf";

/// Options of [`McapSink`]. Plain data; `Default` gives the values documented per field.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SinkOptions {
    /// Replace an existing output file (at `finish`). Default: `false`, refuse it.
    pub force: bool,
    /// Target uncompressed chunk size, bytes. Default: 1 MiB, the `mcap` crate's default
    /// (Foxglove measured nothing to gain above it).
    pub chunk_size_bytes: u64,
}

impl Default for SinkOptions {
    fn default() -> Self {
        Self {
            force: false,
            chunk_size_bytes: WriteOptions::DEFAULT_CHUNK_SIZE,
        }
    }
}

/// A channel registered with [`McapSink::add_channel`]; valid only for that sink.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct ChannelId(usize);

#[derive(Debug)]
struct Channel {
    mcap_id: u16,
    topic: String,
    /// `prost::Name` of the channel's message type, checked on every write.
    package: &'static str,
    name: &'static str,
    /// Sequence number of the last message written (the first message gets 1).
    sequence: u32,
}

/// Where a file-backed sink writes (`partial`) and what it renames to on success (`target`).
#[derive(Debug)]
struct OutputPaths {
    partial: PathBuf,
    target: PathBuf,
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
/// [`finish`]: McapSink::finish
/// [`finish_partial`]: McapSink::finish_partial
pub struct McapSink<W: Write + Seek = BufWriter<File>> {
    writer: Writer<W>,
    /// Names the output in error messages.
    label: String,
    paths: Option<OutputPaths>,
    /// Schema id per fully qualified message name: one schema record per type.
    schemas: BTreeMap<String, u16>,
    channels: Vec<Channel>,
    /// Reused encode buffer: no allocation per message once it has grown.
    buffer: Vec<u8>,
    last_log_time_ns: u64,
}

impl McapSink<BufWriter<File>> {
    /// Starts writing `<path>.partial`. Fails, creating nothing, if `path` exists and
    /// `options.force` is false, or if `path` is a directory. A stale `.partial` from an
    /// earlier run is overwritten.
    pub fn create(path: &Path, options: SinkOptions) -> Result<Self> {
        let label = path.display().to_string();
        let fail = |reason: String| Error::Output {
            path: label.clone(),
            reason,
        };
        let file_name = path
            .file_name()
            .ok_or_else(|| fail("the output path has no file name".into()))?;
        if path.is_dir() {
            return Err(fail("is a directory".into()));
        }
        if let Ok(meta) = std::fs::symlink_metadata(path) {
            // Never rename a run over a device, FIFO, socket or symlink, even with force.
            if !meta.is_file() {
                return Err(fail("exists and is not a regular file".into()));
            }
            if !options.force {
                return Err(fail("already exists (use --force to overwrite)".into()));
            }
        }
        let mut partial_name = file_name.to_os_string();
        partial_name.push(".partial");
        let partial = path.with_file_name(partial_name);

        let file = OpenOptions::new()
            .write(true)
            .create(true)
            .truncate(true)
            .open(&partial)
            .map_err(|e| fail(format!("cannot create {}: {e}", partial.display())))?;
        let paths = OutputPaths {
            partial: partial.clone(),
            target: path.to_path_buf(),
        };
        Self::with_writer(BufWriter::new(file), &options, label.clone(), Some(paths)).inspect_err(
            |_| {
                // Nothing useful was written: leave no file behind.
                let _ = std::fs::remove_file(&partial);
            },
        )
    }

    /// Closes the file cleanly (summary, footer, `sync_all`) and renames `.partial` to the
    /// final name. Returns the final path.
    pub fn finish(self) -> Result<PathBuf> {
        let label = self.label.clone();
        let paths = self.close_file()?;
        std::fs::rename(&paths.partial, &paths.target).map_err(|e| Error::Output {
            path: label.clone(),
            reason: format!("cannot rename {}: {e}", paths.partial.display()),
        })?;
        // Make the rename itself durable (the directory entry), as `sync_all` did the data.
        if let Some(parent) = paths.target.parent() {
            // A bare file name has the empty path as parent: the current directory.
            let dir = if parent.as_os_str().is_empty() {
                Path::new(".")
            } else {
                parent
            };
            File::open(dir)
                .and_then(|d| d.sync_all())
                .map_err(|e| Error::Output {
                    path: label,
                    reason: format!("cannot sync directory {}: {e}", dir.display()),
                })?;
        }
        Ok(paths.target)
    }

    /// Closes the file cleanly like [`finish`](Self::finish) but keeps the `.partial` name:
    /// for an interrupted run whose data is valid but incomplete. Returns the `.partial` path.
    pub fn finish_partial(self) -> Result<PathBuf> {
        Ok(self.close_file()?.partial)
    }

    /// Gives up on a failed run: closes the file and deletes the `.partial`, so that bad
    /// input or a failed run leaves nothing behind.
    pub fn discard(self) {
        let partial = self.paths.as_ref().map(|p| p.partial.clone());
        drop(self);
        if let Some(partial) = partial {
            let _ = std::fs::remove_file(partial);
        }
    }

    fn close_file(self) -> Result<OutputPaths> {
        let label = self.label.clone();
        let fail = |reason: String| Error::Output {
            path: label.clone(),
            reason,
        };
        let (buffered, paths) = self.close()?;
        let file = buffered
            .into_inner()
            .map_err(|e| fail(format!("flush failed: {}", e.error())))?;
        file.sync_all()
            .map_err(|e| fail(format!("sync failed: {e}")))?;
        paths.ok_or_else(|| fail("file sink without paths (bug)".into()))
    }
}

impl McapSink<Cursor<Vec<u8>>> {
    /// A sink that writes into memory, for tests and tools; `options.force` is ignored.
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
    /// names it in errors. `options.force` is ignored.
    pub fn on_writer(out: W, options: &SinkOptions, label: &str) -> Result<Self> {
        Self::with_writer(out, options, label.to_owned(), None)
    }

    fn with_writer(
        out: W,
        options: &SinkOptions,
        label: String,
        paths: Option<OutputPaths>,
    ) -> Result<Self> {
        let writer = WriteOptions::new()
            .library(concat!("bridgetwin/", env!("CARGO_PKG_VERSION")))
            .chunk_size(Some(options.chunk_size_bytes))
            // No zstd worker threads: byte-identical output for identical input.
            .compression_threads(0)
            .create(out)
            .map_err(|e| Error::Output {
                path: label.clone(),
                reason: chain(&e),
            })?;
        Ok(Self {
            writer,
            label,
            paths,
            schemas: BTreeMap::new(),
            channels: Vec::new(),
            buffer: Vec::new(),
            last_log_time_ns: 0,
        })
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
                self.schemas.insert(full_name, id);
                id
            }
        };
        let mcap_id = self
            .writer
            .add_channel(schema_id, topic, ENCODING, &metadata)
            .map_err(|e| self.error(format!("channel {topic}: {}", chain(&e))))?;
        self.channels.push(Channel {
            mcap_id,
            topic: topic.to_owned(),
            package: M::PACKAGE,
            name: M::NAME,
            sequence: 0,
        });
        Ok(ChannelId(self.channels.len() - 1))
    }

    /// Writes one message with `log_time = publish_time = log_time_ns` (Unix-epoch ns,
    /// which must equal `message.timestamp`). Fails if `M` is not the channel's type, if
    /// `log_time_ns` is 0 or earlier than the previous message's.
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
        let Some(state) = self.channels.get_mut(channel.0) else {
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
        state.sequence = sequence;
        let header = MessageHeader {
            channel_id: state.mcap_id,
            sequence,
            log_time: log_time_ns,
            publish_time: log_time_ns,
        };
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
        self.last_log_time_ns = log_time_ns;
        Ok(())
    }

    /// Writes a metadata record (`bridgetwin`, `scenario`, `bridge_model`). Closes the
    /// current chunk: call at the start or end of a run.
    pub fn write_metadata(&mut self, name: &str, metadata: BTreeMap<String, String>) -> Result<()> {
        let record = Metadata {
            name: name.to_owned(),
            metadata,
        };
        self.writer
            .write_metadata(&record)
            .map_err(|e| self.error(format!("metadata {name}: {}", chain(&e))))
    }

    /// Attaches a file (scenario TOML, road profile CSV). `log_time_ns` is also used as the
    /// creation time, so output stays reproducible. Closes the current chunk.
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
            .map_err(|e| self.error(format!("attachment {name}: {}", chain(&e))))
    }

    /// Closes the current chunk and flushes it to the file, so that a run killed later
    /// stays readable up to here. Costs compression ratio if called very often.
    pub fn flush(&mut self) -> Result<()> {
        self.writer
            .flush()
            .map_err(|e| self.error(format!("flush failed: {}", chain(&e))))
    }

    /// Number of messages written on `channel` so far.
    pub fn message_count(&self, channel: ChannelId) -> u64 {
        self.channels
            .get(channel.0)
            .map_or(0, |c| u64::from(c.sequence))
    }

    /// Writes the summary and footer and hands back the underlying writer.
    fn close(mut self) -> Result<(W, Option<OutputPaths>)> {
        self.writer
            .finish()
            .map_err(|e| self.error(format!("finishing the MCAP failed: {}", chain(&e))))?;
        let mut out = self.writer.into_inner();
        out.flush().map_err(|e| Error::Output {
            path: self.label.clone(),
            reason: format!("flush failed: {e}"),
        })?;
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
fn chain(error: &dyn std::error::Error) -> String {
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
