//! The default scenario end to end, split into its parts (shared with the criterion bench
//! `benches/end_to_end.rs`): the coupled solver and the DAQ chains with a recorder that
//! drops every record (physics only), the records of a run (collected beforehand)
//! encoded and written to an in-memory MCAP (writing only), and both, as `bridgetwin
//! simulate` does, into memory (end to end: the writer on a second thread, see
//! [`crate::output::pipeline`]; and on one thread, as a sweep job does). Real-time factor =
//! simulated / wall time.

use std::hint::black_box;

use serde::Serialize;

use super::timing::median_wall_s;
use crate::app::pipeline;
use crate::app::run::WriterThread;
use crate::error::Result;
use crate::output::{McapRecorder, McapSink, SinkOptions};
use crate::scenario::{Layout, Resolved, Scenario};
use crate::sim::{prepare, run, Prepared, Record, Recorder, VecRecorder};

/// Counts records and drops them.
#[derive(Debug, Default)]
pub struct Discard(pub u64);

impl Recorder for Discard {
    fn record(&mut self, record: Record) -> Result<()> {
        self.0 += black_box(&record).t_ns() & 1;
        Ok(())
    }
}

/// The default scenario in `layout`, resolved and prepared (model and road built).
pub fn default_scenario(layout: Layout) -> Result<(Resolved, Prepared)> {
    let mut s = Scenario::default_scenario();
    s.output.layout = layout;
    let resolved = s.resolve()?;
    let prepared = prepare(&resolved)?;
    Ok((resolved, prepared))
}

/// Runs the physics and the sensor chains, dropping the records.
pub fn physics_only(resolved: &Resolved, prepared: &Prepared) -> Result<u64> {
    let mut discard = Discard(0);
    run(resolved, prepared, &mut discard, &mut |_, _| {})?;
    Ok(discard.0)
}

/// Writes `records` (or runs the simulation when `None`, with the writer on `thread`) into
/// an in-memory MCAP; returns its size in bytes.
pub fn write_mcap(
    resolved: &Resolved,
    prepared: &Prepared,
    records: Option<&[Record]>,
    thread: WriterThread,
) -> Result<usize> {
    let mut sink = McapSink::in_memory(&SinkOptions::default())?;
    let mut recorder = McapRecorder::new(&mut sink);
    match records {
        Some(records) => {
            recorder.begin(&crate::sim::manifest(resolved, prepared)?)?;
            for r in records {
                recorder.record(r.clone())?;
            }
            recorder.finish()?;
        }
        None if thread == WriterThread::Inline => {
            run(resolved, prepared, &mut recorder, &mut |_, _| {})?;
        }
        None => {
            pipeline::record_in_background(recorder, |r| {
                run(resolved, prepared, r, &mut |_, _| {})
            })?;
        }
    }
    Ok(sink.finish_to_bytes()?.len())
}

/// The records of one run of the scenario.
pub fn collect_records(resolved: &Resolved, prepared: &Prepared) -> Result<Vec<Record>> {
    let mut collected = VecRecorder::default();
    run(resolved, prepared, &mut collected, &mut |_, _| {})?;
    Ok(collected.records)
}

/// Median wall times of the three parts of the default scenario.
#[derive(Debug, Clone, Serialize)]
pub struct EndToEnd {
    pub layout: String,
    pub simulated_s: f64,
    pub solver_steps: u64,
    pub records: usize,
    pub mcap_bytes: usize,
    /// As `simulate` does it: the writer on a second thread.
    pub end_to_end_s: f64,
    /// Everything on one thread (a sweep job).
    pub end_to_end_one_thread_s: f64,
    pub physics_only_s: f64,
    pub writing_only_s: f64,
    /// simulated_s / end_to_end_s.
    pub real_time_factor: f64,
    pub real_time_factor_physics_only: f64,
    pub real_time_factor_writing_only: f64,
    /// end_to_end_s / writing_only_s (1 would mean physics costs nothing next to output).
    pub end_to_end_over_writing_only: f64,
    /// end_to_end_one_thread_s / writing_only_s.
    pub one_thread_over_writing_only: f64,
    pub repetitions: usize,
}

/// Measures the default scenario (its own layout) with `repetitions` after a warm-up.
pub fn measure(repetitions: usize) -> Result<EndToEnd> {
    let layout = Scenario::default_scenario().output.layout;
    let (resolved, prepared) = default_scenario(layout)?;
    let records = collect_records(&resolved, &prepared)?;
    let mcap_bytes = write_mcap(&resolved, &prepared, Some(&records), WriterThread::Inline)?;
    // Errors cannot appear in the timed calls: each call did the same work just above.
    let end_to_end_s = median_wall_s(repetitions, || {
        black_box(write_mcap(&resolved, &prepared, None, WriterThread::Background).ok());
    });
    let end_to_end_one_thread_s = median_wall_s(repetitions, || {
        black_box(write_mcap(&resolved, &prepared, None, WriterThread::Inline).ok());
    });
    let physics_only_s = median_wall_s(repetitions, || {
        black_box(physics_only(&resolved, &prepared).ok());
    });
    let writing_only_s = median_wall_s(repetitions, || {
        black_box(write_mcap(&resolved, &prepared, Some(&records), WriterThread::Inline).ok());
    });
    let simulated_s = resolved.duration_s();
    Ok(EndToEnd {
        layout: format!("{layout:?}").to_lowercase(),
        simulated_s,
        solver_steps: resolved.steps,
        records: records.len(),
        mcap_bytes,
        end_to_end_s,
        end_to_end_one_thread_s,
        physics_only_s,
        writing_only_s,
        real_time_factor: simulated_s / end_to_end_s,
        real_time_factor_physics_only: simulated_s / physics_only_s,
        real_time_factor_writing_only: simulated_s / writing_only_s,
        end_to_end_over_writing_only: end_to_end_s / writing_only_s,
        one_thread_over_writing_only: end_to_end_one_thread_s / writing_only_s,
        repetitions: repetitions.max(1),
    })
}
