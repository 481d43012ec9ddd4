//! One run written as one MCAP file (or its hourly parts): the time loop driven into the
//! MCAP output. Shared by `simulate`, `sweep` and the benches.

use std::io::{Seek, Write};
use std::time::Instant;

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

/// Runs the scenario into `sink`: the time loop hands the manifest and every record to an
/// MCAP recorder (on this thread or a second one), which writes the metadata records
/// (`bridgetwin`, `scenario`, `bridge_model`), the attachments (the scenario as the user
/// wrote it, `resolved.source_toml`, and the road profile), the modal state, then every
/// record. Chunks close every `resolved.flush_every_ns` of simulated time. The caller
/// finishes the sink (`finish`, or `finish_partial` when `summary.stopped_at_s` is set).
pub fn write_run<W: Write + Seek + Send>(
    sink: &mut McapSink<W>,
    resolved: &Resolved,
    prepared: &Prepared,
    control: &mut Control,
    thread: WriterThread,
) -> Result<Written> {
    let mut recorder = McapRecorder::new(sink).flush_every_ns(Some(resolved.flush_every_ns));
    let loop_start = Instant::now();
    let (summary, recorder) = match thread {
        WriterThread::Inline => {
            let summary = crate::sim::run_controlled(resolved, prepared, &mut recorder, control)?;
            (summary, recorder)
        }
        WriterThread::Background => super::pipeline::record_in_background(recorder, |r| {
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
        write_run(&mut sink, &resolved, &prepared, &mut control, thread).unwrap();
        sink.finish_to_bytes().unwrap()
    }

    #[test]
    fn the_writer_thread_writes_the_same_bytes_as_inline_writing() {
        let inline = bytes(WriterThread::Inline);
        assert!(inline.len() > 100_000, "{}", inline.len());
        assert!(inline == bytes(WriterThread::Background));
    }
}
