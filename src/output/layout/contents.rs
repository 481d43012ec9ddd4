//! What a layout is built from: a run file's channels (topic, schema, channel metadata,
//! message count), its time range, the span from the `bridge_model` metadata, the peak of
//! the deflected shape and the vehicles that crossed. One streaming pass in file order
//! through the `mcap` crate's sans-io reader: memory stays bounded by one chunk, and a
//! file without a summary (an interrupted run's `.partial`) reads up to its last chunk.

use std::collections::BTreeMap;
use std::fs::File;
use std::io::{BufReader, ErrorKind, Read};
use std::path::Path;

use mcap::records::Record as McapRecord;
use mcap::sans_io::{LinearReadEvent, LinearReader};
use prost::{Message, Name};

use crate::error::{Error, Result};
use crate::output::proto::v1::{BridgeState, VehicleTruth};
use crate::output::{ns_from_timestamp, Topics};

/// One channel of the file.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ChannelInfo {
    pub topic: String,
    /// Fully qualified schema name (`bridgetwin.v1.AxleLoads`).
    pub schema: String,
    pub metadata: BTreeMap<String, String>,
    pub messages: u64,
}

/// A vehicle of `/truth/vehicles`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VehicleInfo {
    pub vehicle_id: u32,
    pub axles: usize,
    /// When its front axle reached the bridge and its rear axle left it (Unix-epoch ns).
    pub entry_ns: Option<u64>,
    pub exit_ns: Option<u64>,
}

/// Everything a layout needs from a run file.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct RunContents {
    /// By topic.
    pub channels: BTreeMap<String, ChannelInfo>,
    /// Log times of the first and last message (Unix-epoch ns).
    pub first_ns: Option<u64>,
    pub last_ns: Option<u64>,
    /// `span_m` of the `bridge_model` metadata record.
    pub span_m: Option<f64>,
    /// Largest |deflection| of any node in any `/truth/bridge` message (m).
    pub peak_deflection_m: f64,
    /// Shape nodes per `/truth/bridge` message (0 without the topic).
    pub shape_nodes: usize,
    /// In file order (the order they left the bridge).
    pub vehicles: Vec<VehicleInfo>,
    /// Why the pass ended before the end of the file (a cut-off `.partial`), if it did.
    pub stopped: Option<String>,
}

impl RunContents {
    /// Reads `path` from start to end; a cut-off tail ends the pass quietly.
    pub fn read(path: &Path) -> Result<RunContents> {
        let error = |reason: String| Error::File {
            path: path.display().to_string(),
            reason,
        };
        let file = File::open(path).map_err(|e| error(e.to_string()))?;
        let mut source = BufReader::with_capacity(1 << 20, file);
        let mut reader = LinearReader::new();
        let mut pass = Pass::default();
        while let Some(event) = reader.next_event() {
            match event {
                Ok(LinearReadEvent::ReadRequest(want)) => {
                    let got = read_some(&mut source, reader.insert(want))
                        .map_err(|e| error(e.to_string()))?;
                    reader.notify_read(got);
                }
                Ok(LinearReadEvent::Record { opcode, data }) => {
                    match mcap::parse_record(opcode, data) {
                        Ok(record) => pass.record(record),
                        Err(e) if pass.header_seen => {
                            pass.contents.stopped = Some(e.to_string());
                            break;
                        }
                        Err(e) => return Err(error(format!("not an MCAP file ({e})"))),
                    }
                }
                // Damage after the header (a killed run's cut chunk): keep what was read.
                Err(e) if pass.header_seen => {
                    pass.contents.stopped = Some(e.to_string());
                    break;
                }
                Err(e) => return Err(error(format!("not an MCAP file ({e})"))),
            }
        }
        if !pass.header_seen {
            return Err(error("not an MCAP file (no header record)".into()));
        }
        Ok(pass.contents)
    }
}

/// The state of one pass.
#[derive(Default)]
struct Pass {
    contents: RunContents,
    schemas: BTreeMap<u16, String>,
    /// Topic by channel id.
    topics: BTreeMap<u16, String>,
    header_seen: bool,
}

impl Pass {
    fn record(&mut self, record: McapRecord<'_>) {
        match record {
            McapRecord::Header(_) => self.header_seen = true,
            McapRecord::Schema { header, .. } => {
                self.schemas.insert(header.id, header.name);
            }
            McapRecord::Channel(c) => {
                let schema = self.schemas.get(&c.schema_id).cloned().unwrap_or_default();
                self.topics.insert(c.id, c.topic.clone());
                // The summary repeats every channel: keep the first declaration.
                self.contents
                    .channels
                    .entry(c.topic.clone())
                    .or_insert(ChannelInfo {
                        topic: c.topic,
                        schema,
                        metadata: c.metadata,
                        messages: 0,
                    });
            }
            McapRecord::Metadata(m) if m.name == "bridge_model" => {
                self.contents.span_m = m.metadata.get("span_m").and_then(|v| v.parse().ok());
            }
            McapRecord::Message { header, data } => {
                self.message(header.channel_id, header.log_time, &data)
            }
            _ => {}
        }
    }

    fn message(&mut self, channel_id: u16, log_time: u64, data: &[u8]) {
        let c = &mut self.contents;
        c.first_ns = Some(c.first_ns.map_or(log_time, |t| t.min(log_time)));
        c.last_ns = Some(c.last_ns.map_or(log_time, |t| t.max(log_time)));
        let Some(channel) = self
            .topics
            .get(&channel_id)
            .and_then(|topic| c.channels.get_mut(topic))
        else {
            return;
        };
        channel.messages += 1;
        if channel.topic == Topics::BRIDGE && channel.schema == BridgeState::full_name() {
            if let Ok(state) = BridgeState::decode(data) {
                c.shape_nodes = c.shape_nodes.max(state.deflection_m.len());
                let peak = state
                    .deflection_m
                    .iter()
                    .fold(0.0f64, |m, w| m.max(w.abs()));
                c.peak_deflection_m = c.peak_deflection_m.max(peak);
            }
        } else if channel.topic == Topics::VEHICLES && channel.schema == VehicleTruth::full_name() {
            if let Ok(v) = VehicleTruth::decode(data) {
                c.vehicles.push(VehicleInfo {
                    vehicle_id: v.vehicle_id,
                    axles: v.static_axle_load_n.len(),
                    entry_ns: v.entry_time.as_ref().and_then(ns_from_timestamp),
                    exit_ns: v.exit_time.as_ref().and_then(ns_from_timestamp),
                });
            }
        }
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
