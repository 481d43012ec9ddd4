//! One streaming pass over an MCAP file, in file order, through the input layer's guarded
//! pass (`crate::input::read_records`: the `mcap` crate's sans-io reader with every length
//! checked against the file), which decompresses chunks as it goes. Memory is bounded by one chunk however long
//! the run, and the same pass serves a complete file and one without a summary (a killed
//! run's `.partial`, whose last chunk is cut short: the messages before the cut are still
//! read). The summary only adds the writer's own statistics.
//!
//! The truth needs every `/truth/axle_loads` message, which sit in every chunk, so a full
//! pass is needed anyway; reading the summary first would only add a second pass.

use std::collections::{BTreeMap, HashMap};
use std::path::Path;

use anyhow::{bail, Result};
use mcap::records::{Channel, Header, MessageHeader, Metadata, Record, Statistics};

use crate::input::{read_records, Flow};

use super::truth::{BlockStats, TruthScan};

/// What one channel declared and carried.
#[derive(Debug, Default)]
pub(super) struct ChannelScan {
    pub topic: String,
    pub schema: String,
    pub metadata: BTreeMap<String, String>,
    pub messages: u64,
    pub first_ns: Option<u64>,
    pub last_ns: Option<u64>,
    /// Block layout only: the samples inside the messages.
    pub blocks: Option<BlockStats>,
}

/// An attachment without its bytes.
#[derive(Debug)]
pub(super) struct AttachmentInfo {
    pub name: String,
    pub media_type: String,
    pub size_bytes: u64,
}

/// Everything the pass found.
#[derive(Debug, Default)]
pub(super) struct Scan {
    pub header: Option<Header>,
    pub channels: BTreeMap<u16, ChannelScan>,
    pub metadata: Vec<Metadata>,
    pub attachments: Vec<AttachmentInfo>,
    /// The summary's statistics record, if the file has a complete summary.
    pub statistics: Option<Statistics>,
    /// A statistics record was read but the file ends before its footer.
    pub summary_cut_short: bool,
    /// Complete chunks, counted by the message index records that follow each one.
    pub chunks: u64,
    pub messages: u64,
    pub first_ns: Option<u64>,
    pub last_ns: Option<u64>,
    /// Why the pass ended before the end magic (truncated file, corrupt record).
    pub stopped: Option<String>,
    /// Messages on a channel never declared before them.
    pub orphan_messages: u64,
    /// Messages of a decoded schema that failed to decode.
    pub undecodable_messages: u64,
    pub truth: TruthScan,
    schemas: HashMap<u16, String>,
    /// The previous record was a message index (a run of them closes a chunk).
    after_message_index: bool,
}

/// Reads `path` from start to end through the input layer's guarded pass (no length in the
/// file can make it allocate more than the file holds; chunk CRCs checked first). Fails
/// only when nothing MCAP-like could be read (missing file, I/O error, bad magic); damage
/// after the header ends the pass with `stopped` set to where the intact part ends.
pub(super) fn scan_file(path: &Path) -> Result<Scan> {
    let mut scan = Scan::default();
    let pass = read_records(path, |record| {
        scan.record(record);
        Ok(Flow::Continue)
    })?;
    if let Some(damage) = pass.damage() {
        scan.stopped = Some(damage.to_string());
    }
    if scan.header.is_none() {
        let why = scan.stopped.as_deref().unwrap_or("no header record");
        bail!("{}: not an MCAP file ({why})", path.display());
    }
    if scan.stopped.is_some() {
        // Without its footer the summary cannot be trusted to be whole.
        scan.summary_cut_short = scan.statistics.take().is_some();
    }
    Ok(scan)
}

impl Scan {
    /// A record of the file, or of a chunk (the reader opens chunks itself).
    fn record(&mut self, record: Record<'_>) {
        let is_message_index = matches!(record, Record::MessageIndex(_));
        if is_message_index && !self.after_message_index {
            self.chunks += 1;
        }
        self.after_message_index = is_message_index;
        match record {
            Record::Header(h) => self.header = Some(h),
            Record::Schema { header, .. } => {
                self.schemas.insert(header.id, header.name);
            }
            Record::Channel(c) => self.channel(c),
            Record::Message { header, data } => self.message(&header, &data),
            Record::Metadata(m) => self.metadata.push(m),
            Record::Attachment { header, data, .. } => self.attachments.push(AttachmentInfo {
                name: header.name,
                media_type: header.media_type,
                size_bytes: data.len() as u64,
            }),
            Record::Statistics(s) => self.statistics = Some(s),
            _ => {}
        }
    }

    /// Keeps the first declaration (the summary repeats every channel).
    fn channel(&mut self, c: Channel) {
        let schema = self.schemas.get(&c.schema_id).cloned().unwrap_or_default();
        self.channels.entry(c.id).or_insert_with(|| ChannelScan {
            topic: c.topic,
            schema,
            metadata: c.metadata,
            ..Default::default()
        });
    }

    fn message(&mut self, header: &MessageHeader, data: &[u8]) {
        let t = header.log_time;
        self.messages += 1;
        widen(&mut self.first_ns, &mut self.last_ns, t);
        let Some(ch) = self.channels.get_mut(&header.channel_id) else {
            self.orphan_messages += 1;
            return;
        };
        ch.messages += 1;
        widen(&mut ch.first_ns, &mut ch.last_ns, t);
        if self
            .truth
            .message(&ch.schema, t, data, &mut ch.blocks)
            .is_err()
        {
            self.undecodable_messages += 1;
        }
    }
}

/// Extends the time range `first..last` to include `t_ns`.
fn widen(first: &mut Option<u64>, last: &mut Option<u64>, t_ns: u64) {
    *first = Some(first.map_or(t_ns, |f| f.min(t_ns)));
    *last = Some(last.map_or(t_ns, |l| l.max(t_ns)));
}
