//! The size of a run's MCAP output, estimated before the run from its manifest and the
//! loop's [`RecordForecast`] (docs/output.md, "The estimate before a run").
//!
//! - **Messages and payloads** come from the real recorder and encoders: a probe feeds a
//!   few representative records of every kind (a full block per sensor, the scene's
//!   every-so-many shapes) through an [`McapRecorder`] into memory and reads what each
//!   channel received; each channel's count and payload bytes are then scaled by how many
//!   records of that kind the forecast expects.
//! - **Compression**: each channel's message records (31-byte header + payload) times the
//!   ratio measured for its message type on the examples ([`compression_ratio`]).
//! - **Framing**: the 16-byte index entry of every message (written uncompressed), the
//!   chunk records and their indexes (chunks close at the chunk size and at every flush),
//!   and, per file, what an empty run of this manifest writes (header, metadata records,
//!   attachments, schemas, channels, summary), measured by writing one.

use std::io::Cursor;

use super::{McapRecorder, McapSink, SinkOptions};
use crate::error::Result;
use crate::record::{Layout, Quantities, Record, RecordForecast, Recorder, RunManifest};

/// What a sink has written on one channel (see `McapSink::channel_totals`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub(super) struct ChannelTotals {
    pub topic: String,
    /// Fully qualified message name (`bridgetwin.v1.SensorTruth`).
    pub schema: String,
    pub messages: u64,
    /// Encoded message bytes (the payloads, without the MCAP record around them).
    pub payload_bytes: u64,
}

/// The expected output of one channel.
#[derive(Debug, Clone, PartialEq)]
pub struct ChannelEstimate {
    pub topic: String,
    pub schema: String,
    pub messages: f64,
    /// What the messages hold, apart from those of a bridge at rest.
    pub content: Content,
    /// Message records before compression (header + payload), bytes.
    pub uncompressed_bytes: f64,
    /// Of them, the records of a bridge at rest.
    pub uncompressed_rest_bytes: f64,
    /// Its share of the files: compressed records plus their index entries, bytes.
    pub bytes: f64,
}

/// The expected output of a run: messages and bytes on disk.
#[derive(Debug, Clone, PartialEq)]
pub struct OutputEstimate {
    /// Per channel, in registration order.
    pub channels: Vec<ChannelEstimate>,
    /// Messages in all files (rounded).
    pub messages: u64,
    /// Bytes of all files together (rounded).
    pub bytes: u64,
    /// Files written: 1, or the parts of a split run.
    pub files: u64,
}

/// Bytes of an MCAP message record around its payload: opcode, record length, channel
/// id, sequence, log time, publish time.
const MESSAGE_RECORD_HEADER_BYTES: f64 = 31.0;
/// Each message's entry in its chunk's message index (log time, offset), uncompressed.
const MESSAGE_INDEX_ENTRY_BYTES: f64 = 16.0;
/// A chunk record without its data (opcode, length, time range, sizes, CRC, "zstd",
/// records length), and its chunk index in the summary (the same fields and offsets).
const CHUNK_FIXED_BYTES: f64 = 53.0 + 77.0;
/// Per channel present in a chunk: the message index record's header (opcode, length,
/// channel, array length) and the channel's offset in the chunk index.
const CHUNK_CHANNEL_BYTES: f64 = 15.0 + 10.0;
/// Per channel with messages, per file: its count in the statistics record.
const STATISTICS_CHANNEL_BYTES: f64 = 10.0;
/// The `split` metadata record at the start of each part (name and five values).
const SPLIT_METADATA_BYTES: f64 = 200.0;

/// What a channel's messages hold, as far as their compression goes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Content {
    /// Numbers with full mantissas (a response, noise).
    Values,
    /// A measured stream through an ADC: multiples of its LSB, low mantissa bits zero.
    AdcCounts,
    /// A bridge at rest: every number zero (left out of per-sample messages, runs of
    /// zeros in arrays).
    Zeros,
}

/// Compressed over uncompressed bytes of chunks holding messages of type `schema` with
/// `content`: zstd at the writer's level on the message records (31-byte header +
/// payload) in file order. Measured with `examples/compression_ratios.rs` on the
/// examples (docs/output.md gives the runs, the commands and the table); a type not
/// measured counts as incompressible.
pub fn compression_ratio(schema: &str, content: Content) -> f64 {
    let name = schema.rsplit('.').next().unwrap_or(schema);
    match (name, content) {
        ("SensorTruth", Content::Zeros) => 0.05,
        ("SensorTruthBlock", Content::Zeros) => 0.012,
        ("BridgeState", Content::Zeros) => 0.03,
        ("SceneUpdate", Content::Zeros) => 0.01,
        ("AccelerationSample" | "StrainSample" | "DisplacementSample", Content::AdcCounts) => 0.2,
        ("SampleBlock", Content::AdcCounts) => 0.33,
        ("AccelerationSample" | "StrainSample" | "DisplacementSample", _) => 0.33,
        ("SampleBlock", _) => 0.84,
        ("SensorTruth", _) => 0.46,
        ("SensorTruthBlock", _) => 0.93,
        ("AxleLoads", _) => 0.38,
        ("BridgeState", _) => 0.45,
        ("SceneUpdate", _) => 0.03,
        ("VehicleTruth", _) => 0.25,
        ("WimRecord", _) => 0.6,
        ("FaultInterval", _) => 0.6,
        ("Log", _) => 0.5,
        // Full-precision doubles of a moving vehicle: little to gain.
        ("VehicleState", _) => 0.8,
        ("GnssFix", _) => 0.55,
        ("AxleDetection" | "AxleDetectionTruth", _) => 0.5,
        _ => 1.0,
    }
}

/// How the files are cut: the sink's options (chunk size, split) and the recorder's
/// flush interval.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FileShape {
    pub chunk_size_bytes: u64,
    /// Chunks close every this much simulated time (ns); `None`: at the chunk size only.
    pub flush_every_ns: Option<u64>,
    /// One file per this much simulated time (ns); `None`: one file.
    pub split_every_ns: Option<u64>,
}

impl FileShape {
    /// The shape of files written with `options` and flushed every `flush_every_ns`.
    pub fn new(options: &SinkOptions, flush_every_ns: Option<u64>) -> Self {
        FileShape {
            chunk_size_bytes: options.chunk_size_bytes,
            flush_every_ns,
            split_every_ns: options.split_every_ns,
        }
    }
}

/// The expected output of a run described by `manifest` that emits `forecast`, written
/// in files of `shape`. Deterministic: the same inputs give the same figures anywhere.
pub fn estimate_output(
    manifest: &RunManifest,
    forecast: &RecordForecast,
    shape: &FileShape,
) -> Result<OutputEstimate> {
    let empty_file_bytes = empty_run_bytes(manifest)? as f64;
    let mut channels = probe(manifest, forecast)?;
    let duration_ns = forecast.duration_ns.max(1);
    let files = shape
        .split_every_ns
        .map_or(1, |every| duration_ns.div_ceil(every.max(1)).max(1));
    let flushes = shape
        .flush_every_ns
        .map_or(1, |every| duration_ns.div_ceil(every.max(1)).max(1));
    let uncompressed: f64 = channels.iter().map(|c| c.uncompressed_bytes).sum();
    // Each stretch between flushes (or part boundaries) fills its chunks to the size.
    let stretches = flushes.max(files) as f64;
    let chunk_bytes = shape.chunk_size_bytes.max(1) as f64;
    let chunks = stretches * (uncompressed / stretches / chunk_bytes).ceil().max(1.0);
    let mut messages = 1.0; // the modal state at the start, in the empty run's bytes
    let mut bytes = files as f64 * empty_file_bytes + chunks * CHUNK_FIXED_BYTES;
    if shape.split_every_ns.is_some() {
        bytes += files as f64 * SPLIT_METADATA_BYTES;
    }
    for c in &mut channels {
        let moving = c.uncompressed_bytes - c.uncompressed_rest_bytes;
        c.bytes = compression_ratio(&c.schema, c.content) * moving
            + compression_ratio(&c.schema, Content::Zeros) * c.uncompressed_rest_bytes
            + MESSAGE_INDEX_ENTRY_BYTES * c.messages;
        bytes += c.bytes + CHUNK_CHANNEL_BYTES * c.messages.min(chunks);
        if c.messages > 0.0 {
            bytes += STATISTICS_CHANNEL_BYTES * files as f64;
        }
        messages += c.messages;
    }
    Ok(OutputEstimate {
        channels,
        messages: messages.round() as u64,
        bytes: bytes.round() as u64,
        files,
    })
}

/// Bytes of a file holding the manifest's run without a record: header, metadata
/// records, attachments, schemas, channels, the modal state at the start, summary.
fn empty_run_bytes(manifest: &RunManifest) -> Result<usize> {
    let mut sink = McapSink::in_memory(&SinkOptions::default())?;
    let mut recorder = McapRecorder::new(&mut sink);
    recorder.begin(manifest)?;
    recorder.finish()?;
    Ok(sink.finish_to_bytes()?.len())
}

/// Per channel, the messages and uncompressed bytes the forecast's records become.
fn probe(manifest: &RunManifest, forecast: &RecordForecast) -> Result<Vec<ChannelEstimate>> {
    let mut sink = McapSink::in_memory(&SinkOptions::default())?;
    let mut recorder = McapRecorder::new(&mut sink);
    recorder.begin(manifest)?;
    let totals = recorder.sink().channel_totals();
    let mut probe = Probe {
        recorder,
        t_ns: 0,
        sums: vec![Sums::default(); totals.len()],
        adc: vec![false; totals.len()],
    };
    let blocked = manifest.layout == Layout::Block;
    // Two full blocks per sensor (one sample would do in the sample layout; two blocks
    // give the per-sample cost of a block message exactly).
    let copies = 2 * manifest.block_samples.max(1) as u64;
    for (index, (sensor, expected)) in manifest.sensors.iter().zip(&forecast.sensors).enumerate() {
        let period_ns = sensor.rate.period_ns_rounded().max(1);
        // A node clock's stamp differs from the true instant: the truth message then
        // carries the node's stamp too.
        let stamp_offset_ns = if sensor.clock.is_some() { 1_000 } else { 0 };
        let sample = |t_ns: u64, measured: Option<f64>, truth| Record::Sensor {
            sensor: index,
            t_ns,
            stamp_ns: t_ns as i64 + stamp_offset_ns,
            measured,
            truth,
        };
        let zero = Quantities::default();
        let moving = expected.samples as f64 - expected.lost_samples - expected.rest_samples;
        let kept = probe.feed(
            copies,
            |t| sample(t, Some(expected.measured), expected.truth),
            period_ns,
        )?;
        let lost = probe.feed(copies, |t| sample(t, None, expected.truth), period_ns)?;
        let rest = probe.feed(
            copies,
            |t| sample(t, Some(expected.rest_measured), zero),
            period_ns,
        )?;
        // The channels a lost sample still writes hold the truth; the others the
        // measured stream.
        let truth: Vec<bool> = lost.iter().map(|d| d.messages > 0.0).collect();
        let scale = |n: f64| n / copies as f64;
        probe.add(&kept, scale(moving.max(0.0)), &|_| false);
        probe.add(&lost, scale(expected.lost_samples), &|_| false);
        probe.add(&rest, scale(expected.rest_samples), &|c| truth[c]);
        let quantized = sensor.chain.iter().any(|(name, _)| name == "adc_lsb");
        for (c, d) in kept.iter().enumerate() {
            let measured = d.messages > 0.0 && !truth[c];
            probe.adc[c] |= measured && quantized;
            if measured && blocked && expected.interruptions > 0.0 {
                // An interruption cuts a measured block in two: one more message with
                // the block's header but no more values.
                let values = copies as f64 / d.messages;
                let header = (d.payload_bytes / d.messages - 8.0 * values).max(0.0);
                probe.sums[c].messages += expected.interruptions;
                probe.sums[c].payload_bytes += expected.interruptions * header;
            }
        }
        let preview = |t_ns: u64| Record::Preview {
            sensor: index,
            t_ns,
            stamp_ns: t_ns as i64 + stamp_offset_ns,
            measured: Some(expected.measured),
            truth: expected.measured,
        };
        let previews = probe.feed(8, preview, period_ns)?;
        probe.add(&previews, expected.preview_samples as f64 / 8.0, &|_| false);
    }
    // A scene update draws the vehicles of the latest axle-load record: give it the
    // typical view before the shapes (that record is not counted).
    let scene_every = manifest.scene.map_or(1, |s| s.every_shapes.max(1));
    for expected in &forecast.records {
        let is_shape = matches!(expected.record, Record::BridgeShape { .. });
        if is_shape && manifest.scene.is_some() {
            let view = Record::AxleLoads {
                t_ns: 0,
                axles: forecast.scene_axles.clone(),
            };
            probe.feed(1, |t| at(&view, t), 1)?;
        }
        let copies = if is_shape { scene_every } else { 1 };
        let written = probe.feed(copies, |t| at(&expected.record, t), 1)?;
        let at_rest = expected.at_rest;
        probe.add(&written, expected.count / copies as f64, &|_| at_rest);
    }
    probe.recorder.finish()?;
    Ok(totals
        .into_iter()
        .zip(probe.sums.iter().zip(&probe.adc))
        .map(|(t, (sums, &adc))| ChannelEstimate {
            topic: t.topic,
            schema: t.schema,
            messages: sums.messages,
            content: if adc {
                Content::AdcCounts
            } else {
                Content::Values
            },
            uncompressed_bytes: sums.payload_bytes + MESSAGE_RECORD_HEADER_BYTES * sums.messages,
            uncompressed_rest_bytes: sums.rest_payload_bytes
                + MESSAGE_RECORD_HEADER_BYTES * sums.rest_messages,
            bytes: 0.0,
        })
        .collect())
}

/// Messages and payload bytes of one channel (all, and those of a bridge at rest).
#[derive(Debug, Clone, Copy, Default)]
struct Sums {
    messages: f64,
    payload_bytes: f64,
    rest_messages: f64,
    rest_payload_bytes: f64,
}

/// A recorder writing into memory, and what the forecast's records add up to per channel.
struct Probe<'a> {
    recorder: McapRecorder<'a, Cursor<Vec<u8>>>,
    /// Run-relative time of the probe's last record (ns): records go in time order.
    t_ns: u64,
    sums: Vec<Sums>,
    /// Channels of a measured stream through an ADC.
    adc: Vec<bool>,
}

/// What some records wrote on one channel.
#[derive(Debug, Clone, Copy)]
struct Delta {
    messages: f64,
    payload_bytes: f64,
}

impl Probe<'_> {
    /// Records `copies` records made by `make(t_ns)`, `spacing_ns` apart; returns what
    /// they wrote on each channel.
    fn feed(
        &mut self,
        copies: u64,
        make: impl Fn(u64) -> Record,
        spacing_ns: u64,
    ) -> Result<Vec<Delta>> {
        let before = self.recorder.sink().channel_totals();
        let start_ns = self.t_ns + 1_000_000;
        for k in 0..copies {
            self.t_ns = start_ns + k * spacing_ns;
            self.recorder.record(make(self.t_ns))?;
        }
        let after = self.recorder.sink().channel_totals();
        Ok(after
            .iter()
            .zip(&before)
            .map(|(a, b)| Delta {
                messages: (a.messages - b.messages) as f64,
                payload_bytes: (a.payload_bytes - b.payload_bytes) as f64,
            })
            .collect())
    }

    /// Adds `deltas` times `scale` to the sums; on the channels where `at_rest(c)`, as
    /// records of a bridge at rest.
    fn add(&mut self, deltas: &[Delta], scale: f64, at_rest: &dyn Fn(usize) -> bool) {
        for (c, (sums, d)) in self.sums.iter_mut().zip(deltas).enumerate() {
            sums.messages += scale * d.messages;
            sums.payload_bytes += scale * d.payload_bytes;
            if at_rest(c) {
                sums.rest_messages += scale * d.messages;
                sums.rest_payload_bytes += scale * d.payload_bytes;
            }
        }
    }
}

/// `record` at run-relative time `t_ns`.
fn at(record: &Record, t_ns: u64) -> Record {
    let mut record = record.clone();
    match &mut record {
        Record::Sensor { t_ns: t, .. }
        | Record::Preview { t_ns: t, .. }
        | Record::Fault { t_ns: t, .. }
        | Record::AxleLoads { t_ns: t, .. }
        | Record::BridgeShape { t_ns: t, .. }
        | Record::Vehicle { t_ns: t, .. }
        | Record::Wim { t_ns: t, .. }
        | Record::Event { t_ns: t, .. }
        | Record::Gnss { t_ns: t, .. }
        | Record::AxleHit { t_ns: t, .. }
        | Record::VehicleState { t_ns: t, .. } => *t = t_ns,
    }
    record
}
