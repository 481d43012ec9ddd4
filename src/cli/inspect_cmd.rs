//! `bridgetwin inspect FILE [--json]`: what a run holds (channels, counts, rates, metadata,
//! attachments) and its headline truth (natural frequencies, damping, dynamic load
//! coefficients, WIM records, events), without opening Foxglove or Python.
//!
//! One streaming pass over the file ([`scan`]) feeds a [`Report`], which is printed as a
//! table ([`table`]) or as one JSON object with the same content.

mod scan;
mod table;
mod truth;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use serde::Serialize;

use scan::{ChannelScan, Scan};
use truth::rate_hz;

/// Arguments of `inspect`.
#[derive(Debug, clap::Args)]
pub struct InspectArgs {
    /// MCAP file written by `bridgetwin simulate` (a `.partial` file works too). For a
    /// split run, its base name (`day.mcap` for `day-0000.mcap`, ...) reads the first part.
    pub file: PathBuf,
    /// Print one JSON object instead of a table.
    #[arg(long)]
    pub json: bool,
}

/// Runs `inspect`.
pub fn run(args: &InspectArgs) -> Result<()> {
    let path = super::run_path::RunPath::find(&args.file)?;
    if let Some(note) = path.note() {
        eprintln!("{note}");
    }
    let report = inspect(path.first())?;
    let text = if args.json {
        serde_json::to_string_pretty(&report)? + "\n"
    } else {
        table::render(&report)
    };
    write_stdout(&text)?;
    match report.damage {
        // The figures above cover the intact part; the exit code says the file is not whole.
        Some(damage) => Err(Damaged {
            file: report.file,
            damage,
        }
        .into()),
        None => Ok(()),
    }
}

/// `inspect` read a damaged or cut-short file: it printed what the intact part holds and
/// exits with 3 (as `tools/read_run.py` does).
#[derive(Debug, thiserror::Error)]
#[error("{file} is damaged: {damage}")]
pub struct Damaged {
    pub file: String,
    pub damage: String,
}

/// Prints `text`; a closed pipe (`inspect run.mcap | head`) is not an error.
pub(super) fn write_stdout(text: &str) -> Result<()> {
    use std::io::Write as _;
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        other => other.context("writing to stdout"),
    }
}

/// Everything `inspect` reports. Times are Unix-epoch ns (`*_ns`) or UTC ISO-8601.
#[derive(Debug, Serialize)]
pub struct Report {
    pub file: String,
    pub file_size_bytes: u64,
    pub profile: String,
    pub library: String,
    /// Whether the file ends with a summary section holding statistics.
    pub has_summary: bool,
    /// What the reader of the numbers should know (no summary, damage, mismatches).
    pub notes: Vec<String>,
    /// Where the intact part of a damaged or cut-short file ends (`None`: whole).
    pub damage: Option<String>,
    pub start_time: Option<String>,
    pub end_time: Option<String>,
    pub start_time_ns: Option<u64>,
    pub end_time_ns: Option<u64>,
    pub duration_s: Option<f64>,
    pub message_count: u64,
    pub chunk_count: u64,
    pub channels: Vec<ChannelReport>,
    pub metadata: Vec<MetadataReport>,
    pub attachments: Vec<AttachmentReport>,
    pub truth: TruthReport,
}

/// One channel. Rates are (n - 1) / (last - first) over the channel's own messages.
#[derive(Debug, Serialize)]
pub struct ChannelReport {
    pub id: u16,
    pub topic: String,
    pub schema: String,
    pub message_count: u64,
    pub message_rate_hz: Option<f64>,
    /// Block layout only: samples inside the block messages, and their rate.
    pub samples: Option<u64>,
    pub sample_rate_hz: Option<f64>,
    pub first_time_ns: Option<u64>,
    pub last_time_ns: Option<u64>,
    /// The channel metadata as written (`unit`, `sample_rate_hz`, `position_m`, ...).
    pub metadata: BTreeMap<String, String>,
}

/// One metadata record (the `scenario` record's TOML included in full).
#[derive(Debug, Serialize)]
pub struct MetadataReport {
    pub name: String,
    pub entries: BTreeMap<String, String>,
}

/// One attachment, without its bytes.
#[derive(Debug, Serialize)]
pub struct AttachmentReport {
    pub name: String,
    pub media_type: String,
    pub size_bytes: u64,
}

/// The headline truth of the run.
#[derive(Debug, Serialize)]
pub struct TruthReport {
    /// f1, f2, f3 (as many as the file holds, at most three).
    pub natural_frequencies_hz: Vec<f64>,
    /// `/truth/bridge` or `bridge_model metadata`.
    pub frequency_source: Option<String>,
    /// Damping ratios of modes 1..3 (one value when only the metadata gives it).
    pub damping_ratios: Vec<f64>,
    pub axles: Vec<AxleReport>,
    /// WIM records per station (the topic's last segment).
    pub wim_records: BTreeMap<String, u64>,
    pub events: u64,
}

/// Tyre force of one axle while it is on the bridge (`/truth/axle_loads`).
#[derive(Debug, Serialize)]
pub struct AxleReport {
    pub vehicle_id: u32,
    pub axle_index: u32,
    pub static_load_n: f64,
    pub samples_on_bridge: u64,
    /// Max force on the bridge / static load; `None` if the axle never was on the bridge.
    pub dlc: Option<f64>,
    /// RMS of (force - static) / static on the bridge.
    pub rms_dynamic_ratio: Option<f64>,
}

/// The number of modes in the headline.
const HEADLINE_MODES: usize = 3;

/// Reads `path` and builds the report. Errors name the path.
pub fn inspect(path: &Path) -> Result<Report> {
    let file_size_bytes = std::fs::metadata(path)
        .with_context(|| format!("cannot inspect {}", path.display()))?
        .len();
    let scan = scan::scan_file(path)?;
    let header = scan.header.as_ref();
    let (start_ns, end_ns) = time_span(&scan);
    let channels = channel_reports(&scan);
    Ok(Report {
        file: path.display().to_string(),
        file_size_bytes,
        profile: header.map(|h| h.profile.clone()).unwrap_or_default(),
        library: header.map(|h| h.library.clone()).unwrap_or_default(),
        has_summary: scan.statistics.is_some(),
        notes: notes(&scan, &channels),
        damage: scan.stopped.clone(),
        start_time: start_ns.map(iso8601),
        end_time: end_ns.map(iso8601),
        start_time_ns: start_ns,
        end_time_ns: end_ns,
        duration_s: start_ns
            .zip(end_ns)
            .map(|(a, b)| b.saturating_sub(a) as f64 * 1e-9),
        message_count: scan
            .statistics
            .as_ref()
            .map_or(scan.messages, |s| s.message_count),
        chunk_count: scan
            .statistics
            .as_ref()
            .map_or(scan.chunks, |s| u64::from(s.chunk_count)),
        truth: truth_report(&scan, &channels),
        channels,
        metadata: scan
            .metadata
            .iter()
            .map(|m| MetadataReport {
                name: m.name.clone(),
                entries: m.metadata.clone(),
            })
            .collect(),
        attachments: scan
            .attachments
            .iter()
            .map(|a| AttachmentReport {
                name: a.name.clone(),
                media_type: a.media_type.clone(),
                size_bytes: a.size_bytes,
            })
            .collect(),
    })
}

/// First and last log time: the summary's statistics when present, else what the pass saw.
fn time_span(scan: &Scan) -> (Option<u64>, Option<u64>) {
    match &scan.statistics {
        Some(s) if s.message_count > 0 => (Some(s.message_start_time), Some(s.message_end_time)),
        _ => (scan.first_ns, scan.last_ns),
    }
}

/// Message counts come from the summary's statistics when present (the writer's own count),
/// else from the pass; rates always from the pass, whose counts and times go together.
fn channel_reports(scan: &Scan) -> Vec<ChannelReport> {
    scan.channels
        .iter()
        .map(|(&id, ch)| ChannelReport {
            id,
            topic: ch.topic.clone(),
            schema: ch.schema.clone(),
            message_count: summary_count(scan, id).unwrap_or(ch.messages),
            message_rate_hz: ch
                .first_ns
                .zip(ch.last_ns)
                .and_then(|(a, b)| rate_hz(ch.messages, a, b)),
            samples: ch.blocks.map(|b| b.samples),
            sample_rate_hz: ch.blocks.and_then(|b| b.sample_rate_hz()),
            first_time_ns: ch.first_ns,
            last_time_ns: ch.last_ns,
            metadata: ch.metadata.clone(),
        })
        .collect()
}

fn summary_count(scan: &Scan, channel_id: u16) -> Option<u64> {
    let stats = scan.statistics.as_ref()?;
    Some(
        stats
            .channel_message_counts
            .get(&channel_id)
            .copied()
            .unwrap_or(0),
    )
}

/// Warnings about the file: missing summary, damage, counts that disagree.
fn notes(scan: &Scan, channels: &[ChannelReport]) -> Vec<String> {
    let mut notes = Vec::new();
    if let Some(event) = &scan.truth.stop_event {
        notes.push(format!(
            "the output of a stopped run, not of the whole scenario: {event}"
        ));
    }
    if scan.summary_cut_short {
        notes.push(
            "summary section cut short (truncated file?): counts from a linear scan of the messages"
                .to_string(),
        );
    } else if scan.statistics.is_none() {
        notes.push(
            "no summary section (interrupted run?): counts from a linear scan of the messages"
                .to_string(),
        );
    }
    if let Some(why) = &scan.stopped {
        notes.push(format!(
            "the scan stopped early ({why}); the figures cover the records before that point"
        ));
    }
    if scan.orphan_messages > 0 {
        notes.push(format!(
            "{} messages on undeclared channels",
            scan.orphan_messages
        ));
    }
    if scan.undecodable_messages > 0 {
        notes.push(format!(
            "{} messages failed to decode",
            scan.undecodable_messages
        ));
    }
    notes.extend(count_mismatches(scan, channels));
    notes
}

/// Channels whose summary count differs from the messages the pass found.
fn count_mismatches<'a>(
    scan: &'a Scan,
    channels: &'a [ChannelReport],
) -> impl Iterator<Item = String> + 'a {
    let has_summary = scan.statistics.is_some();
    channels.iter().filter_map(move |c| {
        let found = scan
            .channels
            .get(&c.id)
            .map_or(0, |ch: &ChannelScan| ch.messages);
        (has_summary && found != c.message_count).then(|| {
            format!(
                "{}: the summary counts {} messages, the scan found {found}",
                c.topic, c.message_count
            )
        })
    })
}

fn truth_report(scan: &Scan, channels: &[ChannelReport]) -> TruthReport {
    let (natural_frequencies_hz, frequency_source) = frequencies(scan);
    TruthReport {
        natural_frequencies_hz,
        frequency_source,
        damping_ratios: damping_ratios(scan),
        axles: scan
            .truth
            .axles
            .iter()
            .map(|(&(vehicle_id, axle_index), a)| AxleReport {
                vehicle_id,
                axle_index,
                static_load_n: a.static_load_n,
                samples_on_bridge: a.samples_on_bridge,
                dlc: a.dlc(),
                rms_dynamic_ratio: a.rms_dynamic_ratio(),
            })
            .collect(),
        wim_records: channels
            .iter()
            .filter_map(|c| Some((c.topic.strip_prefix("/wim/")?.to_string(), c.message_count)))
            .collect(),
        events: channels
            .iter()
            .filter(|c| c.topic == "/events")
            .map(|c| c.message_count)
            .sum(),
    }
}

/// f1..f3 from the first `/truth/bridge` message, else from the `bridge_model` metadata.
fn frequencies(scan: &Scan) -> (Vec<f64>, Option<String>) {
    if let Some((f, _)) = scan.truth.modal.as_ref().filter(|(f, _)| !f.is_empty()) {
        let f = f.iter().copied().take(HEADLINE_MODES).collect();
        return (f, Some("/truth/bridge".to_string()));
    }
    match bridge_model_values(scan, "natural_frequencies_hz") {
        Some(f) if !f.is_empty() => (
            f.into_iter().take(HEADLINE_MODES).collect(),
            Some("bridge_model metadata".to_string()),
        ),
        _ => (Vec::new(), None),
    }
}

/// Damping ratios of modes 1..3 from `/truth/bridge`, else the `bridge_model` target ratio.
fn damping_ratios(scan: &Scan) -> Vec<f64> {
    match scan.truth.modal.as_ref().filter(|(_, z)| !z.is_empty()) {
        Some((_, z)) => z.iter().copied().take(HEADLINE_MODES).collect(),
        None => bridge_model_values(scan, "damping_ratio").unwrap_or_default(),
    }
}

/// A comma-separated list of numbers under `key` of the `bridge_model` metadata record.
fn bridge_model_values(scan: &Scan, key: &str) -> Option<Vec<f64>> {
    let record = scan.metadata.iter().find(|m| m.name == "bridge_model")?;
    let text = record.metadata.get(key)?;
    text.split(',').map(|v| v.trim().parse().ok()).collect()
}

/// Unix-epoch ns as UTC ISO-8601 (fractional seconds only when present).
fn iso8601(time_ns: u64) -> String {
    let secs = (time_ns / 1_000_000_000) as i64;
    let nanos = (time_ns % 1_000_000_000) as u32;
    chrono::DateTime::from_timestamp(secs, nanos)
        .map(|t| t.to_rfc3339_opts(chrono::SecondsFormat::AutoSi, true))
        .unwrap_or_else(|| format!("{time_ns} ns"))
}
