//! The human-readable form of a [`Report`]: short sections, one line per item, long
//! metadata values (the scenario TOML) reduced to their line count.

use std::fmt::Write;

use super::{ChannelReport, Report, TruthReport};

/// The report as text, ready to print.
pub(super) fn render(r: &Report) -> String {
    let mut out = String::new();
    // Writing to a String cannot fail.
    let _ = overview(&mut out, r)
        .and_then(|()| channels(&mut out, &r.channels))
        .and_then(|()| metadata(&mut out, r))
        .and_then(|()| attachments(&mut out, r))
        .and_then(|()| truth(&mut out, &r.truth));
    out
}

fn overview(out: &mut String, r: &Report) -> std::fmt::Result {
    writeln!(
        out,
        "file        {} ({} B, {:.2} MiB)",
        r.file,
        r.file_size_bytes,
        r.file_size_bytes as f64 / 1048576.0
    )?;
    writeln!(
        out,
        "mcap        profile {:?}, library {:?}",
        r.profile, r.library
    )?;
    match (&r.start_time, &r.end_time, r.duration_s) {
        (Some(a), Some(b), Some(d)) => writeln!(out, "time        {a} .. {b} ({d:.3} s)")?,
        _ => writeln!(out, "time        (no messages)")?,
    }
    writeln!(
        out,
        "messages    {} in {} chunks{}",
        r.message_count,
        r.chunk_count,
        if r.has_summary {
            ""
        } else {
            " (complete chunks; linear scan)"
        }
    )?;
    for note in &r.notes {
        writeln!(out, "note        {note}")?;
    }
    Ok(())
}

fn channels(out: &mut String, channels: &[ChannelReport]) -> std::fmt::Result {
    let topic_w = width(channels.iter().map(|c| c.topic.len()), "topic");
    let schema_w = width(channels.iter().map(|c| c.schema.len()), "schema");
    let unit_w = width(
        channels
            .iter()
            .filter_map(|c| Some(c.metadata.get("unit")?.len())),
        "unit",
    );
    writeln!(out, "\nchannels")?;
    writeln!(
        out,
        "  {:<topic_w$} {:<schema_w$} {:>8} {:>9} {:>8} {:>9}  {:<unit_w$} {:>9} {:>10}",
        "topic",
        "schema",
        "messages",
        "rate_Hz",
        "samples",
        "sample_Hz",
        "unit",
        "meta_Hz",
        "position_m"
    )?;
    for c in channels {
        let meta = |key: &str| c.metadata.get(key).map_or("-", String::as_str);
        writeln!(
            out,
            "  {:<topic_w$} {:<schema_w$} {:>8} {:>9} {:>8} {:>9}  {:<unit_w$} {:>9} {:>10}",
            c.topic,
            c.schema,
            c.message_count,
            fixed(c.message_rate_hz, 2),
            c.samples.map_or("-".to_string(), |n| n.to_string()),
            fixed(c.sample_rate_hz, 2),
            meta("unit"),
            meta("sample_rate_hz"),
            meta("position_m"),
        )?;
    }
    Ok(())
}

fn metadata(out: &mut String, r: &Report) -> std::fmt::Result {
    writeln!(out, "\nmetadata")?;
    for m in &r.metadata {
        writeln!(out, "  {}", m.name)?;
        for (key, value) in &m.entries {
            if value.contains('\n') {
                writeln!(out, "    {key} = ({} lines)", value.lines().count())?;
            } else {
                writeln!(out, "    {key} = {value}")?;
            }
        }
    }
    Ok(())
}

fn attachments(out: &mut String, r: &Report) -> std::fmt::Result {
    writeln!(out, "\nattachments")?;
    let name_w = width(r.attachments.iter().map(|a| a.name.len()), "name");
    for a in &r.attachments {
        writeln!(
            out,
            "  {:<name_w$} {:<18} {:>10} B",
            a.name, a.media_type, a.size_bytes
        )?;
    }
    Ok(())
}

fn truth(out: &mut String, t: &TruthReport) -> std::fmt::Result {
    writeln!(out, "\ntruth")?;
    let f: Vec<String> = (t.natural_frequencies_hz.iter().enumerate())
        .map(|(k, f)| format!("f{} = {f:.4} Hz", k + 1))
        .collect();
    match &t.frequency_source {
        Some(source) => writeln!(out, "  {} (from {source})", f.join(", "))?,
        None => writeln!(out, "  natural frequencies: not in the file")?,
    }
    let z: Vec<String> = t.damping_ratios.iter().map(|z| format!("{z:.4}")).collect();
    writeln!(out, "  damping ratios: {}", or_none(&z.join(", ")))?;
    for a in &t.axles {
        writeln!(
            out,
            "  vehicle {} axle {}: DLC (max/static on the bridge) {}, RMS (F - static)/static {} \
             (static {:.0} N, {} samples on the bridge)",
            a.vehicle_id,
            a.axle_index,
            fixed(a.dlc, 3),
            fixed(a.rms_dynamic_ratio, 3),
            a.static_load_n,
            a.samples_on_bridge
        )?;
    }
    for (station, n) in &t.wim_records {
        writeln!(out, "  WIM records at station {station}: {n}")?;
    }
    writeln!(out, "  events: {}", t.events)
}

/// Column width: the longest entry, at least the heading.
fn width(lengths: impl Iterator<Item = usize>, heading: &str) -> usize {
    lengths.max().unwrap_or(0).max(heading.len())
}

/// A number with `decimals` decimals, or `-` when absent or not finite.
fn fixed(value: Option<f64>, decimals: usize) -> String {
    match value {
        Some(v) if v.is_finite() => format!("{v:.decimals$}"),
        _ => "-".to_string(),
    }
}

fn or_none(text: &str) -> &str {
    if text.is_empty() {
        "not in the file"
    } else {
        text
    }
}
