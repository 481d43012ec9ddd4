//! The estimate before a run (docs/output.md, "The estimate before a run"): solver
//! steps, messages, bytes and files from the scenario alone (the loop's forecast, sized
//! by the output's encoders), deterministic; and the wall time on this machine, from a
//! short burst of the run's own time loop timed here.

use std::time::Instant;

use crate::error::Result;
use crate::output::{
    estimate_output, FileShape, McapRecorder, McapSink, OutputEstimate, SinkOptions,
};
use crate::scenario::Resolved;
use crate::sim::{Control, Prepared, RunProgress};

/// What a run will write and how long it will take.
#[derive(Debug, Clone)]
pub struct RunEstimate {
    /// Solver steps (exact): the resolved scenario's.
    pub steps: u64,
    /// Simulated time, s.
    pub duration_s: f64,
    /// Messages in all files.
    pub messages: u64,
    /// Bytes of all files.
    pub bytes: u64,
    /// Files: 1, or the parts of a split run.
    pub files: u64,
    /// Vehicles the run carries (scheduled and drawn from its traffic).
    pub vehicles: f64,
    /// Per channel.
    pub output: OutputEstimate,
    /// The wall time and how it was found.
    pub timing: Timing,
}

/// The wall-time estimate, from a burst of the run's own loop on this machine: the
/// burst's loop time less its writing is the per-step cost of physics, sensors and
/// records; its writing time per message the cost of encoding and compressing. The run
/// writes on a second thread, so the two overlap ([`OVERLAP`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Timing {
    /// Steps of the burst timed.
    pub burst_steps: u64,
    /// Time loop cost per solver step (physics, sensors, records), s.
    pub step_s: f64,
    /// Encoding, compressing and writing cost per message, s.
    pub message_s: f64,
    /// Building the loop (solver factorization, sensor taps, the output's metadata), s.
    pub setup_s: f64,
    /// The run's wall time from the end of the estimate: setup and loop, s.
    pub wall_s: f64,
    /// Wall time the calibration took, s.
    pub calibration_s: f64,
}

/// How much of the shorter of the two threads' work (physics or writing) adds to the
/// longer one when they overlap: handing batches over and sharing two cores with the
/// OS. Measured on the examples: see docs/output.md.
pub const OVERLAP: f64 = 0.15;

/// The loop time a burst aims at: long enough that the clock's resolution and the first
/// steps' warm-up do not matter, short enough to go unnoticed.
const BURST_TARGET_S: f64 = 0.03;
/// Bursts stop growing once the calibration has taken this long.
const CALIBRATION_BUDGET_S: f64 = 0.15;
/// ... or this share of the run it times (as projected from the bursts so far): a run
/// of a fraction of a second is not worth a tenth of a second of calibration.
const CALIBRATION_SHARE: f64 = 0.05;
/// The first burst's steps.
const FIRST_BURST_STEPS: u64 = 200;

/// Steps, messages, bytes and files of the run `resolved` (on the model and road of
/// `prepared`) written in files of `shape`. Deterministic.
pub fn estimate_output_of(
    resolved: &Resolved,
    prepared: &Prepared,
    shape: &FileShape,
) -> Result<(OutputEstimate, f64)> {
    let manifest = crate::sim::manifest(resolved, prepared)?;
    let forecast = crate::sim::forecast(resolved, prepared)?;
    Ok((
        estimate_output(&manifest, &forecast, shape)?,
        forecast.vehicles,
    ))
}

/// The full estimate: [`estimate_output_of`] and the wall time on this machine
/// ([`time_run`]).
pub fn estimate_run(
    resolved: &Resolved,
    prepared: &Prepared,
    shape: &FileShape,
) -> Result<RunEstimate> {
    let (output, vehicles) = estimate_output_of(resolved, prepared, shape)?;
    let timing = time_run(resolved, prepared, output.messages)?;
    Ok(RunEstimate {
        steps: resolved.steps,
        duration_s: resolved.duration_s(),
        messages: output.messages,
        bytes: output.bytes,
        files: output.files,
        vehicles,
        output,
        timing,
    })
}

/// One burst: the run cut to `steps` steps, written into memory on this thread.
struct Burst {
    setup_s: f64,
    loop_s: f64,
    write_s: f64,
    messages: u64,
}

fn burst(resolved: &Resolved, prepared: &Prepared, steps: u64) -> Result<Burst> {
    let mut cut = resolved.clone();
    cut.steps = steps;
    let mut sink = McapSink::in_memory(&SinkOptions::default())?;
    let mut recorder = McapRecorder::new(&mut sink);
    let started = Instant::now();
    // The loop reports step 0 once it has built everything: the setup ends there.
    let mut loop_started = None;
    let mut progress = |_: &RunProgress| {
        loop_started.get_or_insert_with(Instant::now);
    };
    let mut control = Control {
        progress: &mut progress,
        stop: None,
    };
    crate::sim::run_controlled(&cut, prepared, &mut recorder, &mut control)?;
    let ended = Instant::now();
    let loop_started = loop_started.unwrap_or(started);
    Ok(Burst {
        setup_s: (loop_started - started).as_secs_f64(),
        loop_s: (ended - loop_started).as_secs_f64(),
        write_s: recorder.write_time.as_secs_f64(),
        messages: recorder.messages,
    })
}

/// The calibration's budget after a burst `b` of `steps` of a `run_steps` run: the
/// smaller of [`CALIBRATION_BUDGET_S`] and [`CALIBRATION_SHARE`] of the run's projected
/// setup and loop.
fn budget_s(b: &Burst, steps: u64, run_steps: u64) -> f64 {
    let projected_s = b.setup_s + b.loop_s * run_steps as f64 / steps.max(1) as f64;
    CALIBRATION_BUDGET_S.min(CALIBRATION_SHARE * projected_s)
}

/// Times bursts of the run's own loop (growing until one lasts [`BURST_TARGET_S`], a
/// quarter of the run at most, then once more at that size, the faster kept; all within
/// [`budget_s`]) and extrapolates to the run's `steps` and `messages`.
pub fn time_run(resolved: &Resolved, prepared: &Prepared, messages: u64) -> Result<Timing> {
    let started = Instant::now();
    let longest = (resolved.steps / 4).max(1);
    let mut steps = FIRST_BURST_STEPS.min(longest);
    let measured = loop {
        let b = burst(resolved, prepared, steps)?;
        let spent_s = started.elapsed().as_secs_f64();
        let budget_s = budget_s(&b, steps, resolved.steps);
        let grow = (BURST_TARGET_S / b.loop_s.max(1e-6))
            .ceil()
            .clamp(2.0, 16.0) as u64;
        let next = (steps * grow).min(longest);
        // The next burst costs its setup and about `grow` times this loop.
        let next_s = b.setup_s + b.loop_s * (next as f64 / steps as f64);
        if b.loop_s >= BURST_TARGET_S || next == steps || spent_s + next_s > budget_s {
            break (steps, b);
        }
        steps = next;
    };
    let (burst_steps, mut b) = measured;
    // Once more at the same size when the budget allows, keeping the faster: a moment of
    // load from another process should not stand for the whole run.
    let budget_s = budget_s(&b, burst_steps, resolved.steps);
    if started.elapsed().as_secs_f64() + b.setup_s + b.loop_s <= budget_s {
        let again = burst(resolved, prepared, burst_steps)?;
        if again.loop_s < b.loop_s {
            b = again;
        }
    }
    let message_s = b.write_s / b.messages.max(1) as f64;
    let step_s = (b.loop_s - b.write_s).max(0.0) / burst_steps as f64;
    let physics_s = step_s * resolved.steps as f64;
    let writing_s = message_s * messages as f64;
    // On a single core the writer thread cannot overlap the loop at all.
    let single_core = std::thread::available_parallelism().is_ok_and(|n| n.get() < 2);
    let overlap = if single_core { 1.0 } else { OVERLAP };
    let wall_s = b.setup_s + physics_s.max(writing_s) + overlap * physics_s.min(writing_s);
    Ok(Timing {
        burst_steps,
        step_s,
        message_s,
        setup_s: b.setup_s,
        wall_s,
        calibration_s: started.elapsed().as_secs_f64(),
    })
}
