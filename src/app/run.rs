//! One run written as one MCAP file (or its hourly parts): the time loop driven into the
//! MCAP output. Shared by `simulate`, `sweep` and the benches.

use std::io::{Seek, Write};
use std::path::{Path, PathBuf};
use std::time::Instant;

use super::estimate::{estimate_run, RunEstimate};
use super::space::{check_space, SpaceCheck};
use crate::error::Result;
use crate::output::{check_output, FileShape, McapRecorder, McapSink, SinkOptions};
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

/// How a run into files ended.
#[derive(Debug)]
pub enum FilesOutcome {
    /// The run ended: its file, or the parts of a split run in time order.
    Finished {
        written: Written,
        paths: Vec<PathBuf>,
    },
    /// A stop request ended it: the current file was kept as `.partial`; the parts of a
    /// split run completed before it keep their final names.
    Stopped {
        written: Written,
        partial: PathBuf,
        completed_parts: Vec<PathBuf>,
    },
}

/// The sink options of a run: `force`, and one file per `output.split_every_s` of
/// simulated time from the scenario start to its end (the closing instant goes into the
/// last part).
pub fn sink_options(resolved: &Resolved, force: bool) -> SinkOptions {
    let start_ns = resolved.start_time_ns;
    let duration_ns = resolved.steps.saturating_mul(resolved.dt_ns);
    SinkOptions {
        force,
        // Validated >= 1 s: the rounding to whole ns cannot reach 0.
        split_every_ns: resolved
            .scenario
            .output
            .split_every_s
            .map(|every_s| (every_s * 1e9).round() as u64),
        split_start_ns: start_ns,
        split_end_ns: Some(start_ns.saturating_add(duration_ns)),
        ..Default::default()
    }
}

/// Options of [`run_to_files`]. `Default`: no `force`, the space check on.
#[derive(Debug, Clone, Copy, Default)]
pub struct FilesOptions {
    /// Replace existing output files.
    pub force: bool,
    /// Whether a run whose estimated size exceeds the output's free space is refused.
    pub space_check: SpaceCheck,
}

/// Runs a resolved scenario into the file `out` (or its hourly parts) as `simulate` does,
/// with the writer on a second thread: the same bytes whoever calls it (the command line,
/// the Python package). Before anything is written, the run is estimated
/// ([`estimate_run`]), `on_estimate` gets the estimate, and a run larger than the free
/// space of `out`'s file system is refused (unless `options.space_check` says not to),
/// after the checks of the output path itself. On an error nothing half-written stays
/// (whole parts completed before it do, and `completed_parts` of the error's note lists
/// them).
pub fn run_to_files(
    resolved: &Resolved,
    out: &Path,
    options: FilesOptions,
    control: &mut Control,
    on_estimate: &mut dyn FnMut(&RunEstimate),
) -> std::result::Result<FilesOutcome, (crate::Error, Vec<PathBuf>)> {
    // Errors before the loop, and in closing the files, leave no completed part behind.
    let alone = |e: crate::Error| (e, Vec::new());
    let prepared = crate::sim::prepare(resolved).map_err(alone)?;
    let sink_options = sink_options(resolved, options.force);
    let shape = FileShape::new(&sink_options, Some(resolved.flush_every_ns));
    let estimate = estimate_run(resolved, &prepared, &shape).map_err(alone)?;
    on_estimate(&estimate);
    check_output(out, &sink_options).map_err(alone)?;
    check_space(out, estimate.bytes, options.space_check).map_err(alone)?;
    let mut sink = McapSink::create(out, sink_options).map_err(alone)?;
    match write_run(
        &mut sink,
        resolved,
        &prepared,
        control,
        WriterThread::Background,
    ) {
        Ok(written) if written.summary.stopped_at_s.is_some() => {
            let completed_parts = sink.parts().map_err(alone)?.to_vec();
            let partial = sink.finish_partial().map_err(alone)?;
            Ok(FilesOutcome::Stopped {
                written,
                partial,
                completed_parts,
            })
        }
        Ok(written) => {
            let paths = sink.finish_parts().map_err(alone)?;
            Ok(FilesOutcome::Finished { written, paths })
        }
        Err(e) => {
            let completed_parts = sink.parts().map(<[_]>::to_vec).unwrap_or_default();
            sink.discard();
            Err((e, completed_parts))
        }
    }
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
