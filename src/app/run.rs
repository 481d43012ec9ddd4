//! One run written as one MCAP file: metadata, attachments, modal state and the records
//! of the simulation. Shared by `simulate` and `sweep`.

use std::collections::BTreeMap;
use std::io::{Seek, Write};
use std::time::{Duration, Instant};

use crate::error::Result;
use crate::output::{McapRecorder, McapSink};
use crate::scenario::Resolved;
use crate::sim::{Control, Prepared, RunSummary};

/// What a finished (or stopped) run reports.
#[derive(Debug)]
pub struct Written {
    pub summary: RunSummary,
    pub messages: u64,
    /// Wall time of the time loop (physics, sensors and writing), s.
    pub loop_s: f64,
    /// Wall time spent encoding and writing within the loop, s.
    pub write_s: f64,
}

/// Where the records are encoded and written.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WriterThread {
    /// On the time loop's thread (a sweep: one job per core already fills the machine).
    Inline,
    /// On a second thread fed in batches ([`crate::output::pipeline`]): physics and output overlap.
    Background,
}

/// Writes a whole run into `sink`: the metadata records (`bridgetwin`, `scenario`,
/// `bridge_model`), the attachments (the scenario as the user wrote it, the road profile),
/// the modal state, then every record of the simulation. The caller finishes the sink
/// (`finish`, or `finish_partial` when `summary.stopped_at_s` is set).
pub fn write_run<W: Write + Seek + Send>(
    sink: &mut McapSink<W>,
    resolved: &Resolved,
    prepared: &Prepared,
    original_toml: &str,
    control: &mut Control,
    thread: WriterThread,
) -> Result<Written> {
    let s = &resolved.scenario;
    let start = resolved.start_time_ns;
    sink.write_metadata(
        "bridgetwin",
        BTreeMap::from([
            ("version".to_string(), env!("CARGO_PKG_VERSION").to_string()),
            (
                "git_revision".to_string(),
                option_env!("BRIDGETWIN_GIT_REVISION")
                    .unwrap_or("unknown")
                    .to_string(),
            ),
            ("seed".to_string(), s.seed.to_string()),
            ("start_time".to_string(), s.start_time.clone()),
        ]),
    )?;
    sink.write_metadata(
        "scenario",
        BTreeMap::from([("toml".to_string(), s.to_toml())]),
    )?;
    let model = &prepared.model;
    let freqs: Vec<String> = (1..=model.omega_rad_s.len().min(10))
        .map(|n| format!("{:.6}", model.frequency_hz(n)))
        .collect();
    sink.write_metadata(
        "bridge_model",
        BTreeMap::from([
            ("model".to_string(), s.bridge.model.label()),
            ("natural_frequencies_hz".to_string(), freqs.join(",")),
            (
                "damping_ratio".to_string(),
                s.bridge.damping_ratio.to_string(),
            ),
            (
                "rayleigh_a0_per_s".to_string(),
                model.rayleigh.a0_per_s.to_string(),
            ),
            ("rayleigh_a1_s".to_string(), model.rayleigh.a1_s.to_string()),
            (
                "flexural_rigidity_n_m2".to_string(),
                s.bridge.flexural_rigidity_n_m2.to_string(),
            ),
            (
                "mass_per_length_kg_m".to_string(),
                s.bridge.mass_per_length_kg_m.to_string(),
            ),
            ("span_m".to_string(), s.bridge.span_m.to_string()),
            ("road".to_string(), prepared.road.describe().to_string()),
        ]),
    )?;
    sink.attach(
        "scenario.toml",
        "application/toml",
        original_toml.as_bytes(),
        start,
    )?;
    sink.attach(
        "road_profile.csv",
        "text/csv",
        prepared.road.to_csv().as_bytes(),
        start,
    )?;
    let mut recorder = McapRecorder::new(sink, resolved, model.shape_positions_m().to_vec())?;
    let (freqs, zetas) = model.modal_summary(10);
    let temperatures_c = prepared
        .condition
        .as_ref()
        .map(|c| (c.state.temperature_structure_c, c.state.temperature_air_c));
    recorder.write_modal_state(&freqs, &zetas, temperatures_c)?;
    recorder.flush_every(Duration::from_secs(2));
    let loop_start = Instant::now();
    let (summary, recorder) = match thread {
        WriterThread::Inline => {
            let summary = crate::sim::run_controlled(resolved, prepared, &mut recorder, control)?;
            (summary, recorder)
        }
        WriterThread::Background => crate::output::pipeline::record_in_background(recorder, |r| {
            crate::sim::run_controlled(resolved, prepared, r, control)
        })?,
    };
    Ok(Written {
        summary,
        messages: recorder.messages,
        loop_s: loop_start.elapsed().as_secs_f64(),
        write_s: recorder.write_time.as_secs_f64(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::output::SinkOptions;
    use crate::scenario::Scenario;

    /// The default scenario, shortened, written by `write_run` with the writer `thread`.
    fn bytes(thread: WriterThread) -> Vec<u8> {
        let mut s = Scenario::default_scenario();
        s.duration_s = Some(2.0);
        let resolved = s.resolve().unwrap();
        let prepared = crate::sim::prepare(&resolved).unwrap();
        let mut sink = McapSink::in_memory(&SinkOptions::default()).unwrap();
        let mut progress = |_: &crate::sim::RunProgress| {};
        let mut control = Control {
            progress: &mut progress,
            stop: None,
        };
        write_run(&mut sink, &resolved, &prepared, "", &mut control, thread).unwrap();
        sink.finish_to_bytes().unwrap()
    }

    #[test]
    fn the_writer_thread_writes_the_same_bytes_as_inline_writing() {
        let inline = bytes(WriterThread::Inline);
        assert!(inline.len() > 100_000, "{}", inline.len());
        assert!(inline == bytes(WriterThread::Background));
    }
}
