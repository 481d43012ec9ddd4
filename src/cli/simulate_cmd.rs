//! `bridgetwin simulate` and `bridgetwin scenario`.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::Result;

use crate::scenario::{Scenario, DEFAULT_SCENARIO_TOML};
use crate::sink::{write_run, McapSink, SinkOptions, WriterThread, Written};

/// Arguments of `simulate`.
#[derive(Debug, clap::Args)]
pub struct SimulateArgs {
    /// Scenario TOML (default: the embedded default scenario).
    #[arg(conflicts_with = "from")]
    pub scenario: Option<PathBuf>,
    /// Re-run the scenario stored in a bridgetwin MCAP file (same seed: same bytes).
    #[arg(long, value_name = "FILE.mcap")]
    pub from: Option<PathBuf>,
    /// Output MCAP file (written as FILE.partial, renamed on success).
    #[arg(long)]
    pub out: PathBuf,
    /// Override the scenario's seed.
    #[arg(long, allow_negative_numbers = true)]
    pub seed: Option<u64>,
    /// Override the duration (s).
    #[arg(long, allow_negative_numbers = true)]
    pub duration_s: Option<f64>,
    /// Replace an existing output file.
    #[arg(long)]
    pub force: bool,
    /// Print the time split: setup, physics + sensors, writing.
    #[arg(long)]
    pub timings: bool,
}

/// Reads a scenario file (or the default) and applies the command-line overrides.
pub fn load_scenario(path: Option<&Path>) -> Result<(Scenario, String)> {
    match path {
        None => Ok((
            Scenario::default_scenario(),
            DEFAULT_SCENARIO_TOML.to_string(),
        )),
        // Relative paths inside (road CSV) are taken from the scenario's folder.
        Some(p) => Ok(Scenario::from_file(p)?),
    }
}

/// The run was stopped by SIGINT or SIGTERM; the file was kept as `.partial`.
#[derive(Debug, thiserror::Error)]
#[error("interrupted at t = {stopped_at_s:.3} s: kept the data written so far in {partial}")]
pub struct Interrupted {
    pub stopped_at_s: f64,
    pub partial: String,
}

/// Runs `simulate`.
pub fn run(args: &SimulateArgs) -> Result<()> {
    let started = Instant::now();
    let (mut scenario, original_toml) = match &args.from {
        Some(run) => super::from_mcap::scenario_from_mcap(run)?,
        None => load_scenario(args.scenario.as_deref())?,
    };
    if let Some(seed) = args.seed {
        scenario.seed = seed;
    }
    if let Some(d) = args.duration_s {
        scenario.duration_s = Some(d);
    }
    let resolved = scenario.resolve()?;
    print_warnings(&resolved);
    let prepared = crate::sim::prepare(&resolved)?;
    let mut sink = McapSink::create(
        &args.out,
        SinkOptions {
            force: args.force,
            ..Default::default()
        },
    )?;
    let stop = super::terminal::stop_on_signals()?;
    let bar =
        super::terminal::progress_bar(resolved.steps, "{bar:40} {pos}/{len} steps ({eta} left)");
    let mut progress = |step, _| {
        if let Some(b) = &bar {
            b.set_position(step);
        }
    };
    let mut control = crate::sim::Control {
        progress: &mut progress,
        stop: Some(&stop),
    };
    let outcome = write_run(
        &mut sink,
        &resolved,
        &prepared,
        &original_toml,
        &mut control,
        WriterThread::Background,
    );
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    match outcome.map_err(anyhow::Error::from) {
        Ok(Written { summary, .. }) if summary.stopped_at_s.is_some() => {
            let partial = sink.finish_partial()?;
            Err(Interrupted {
                stopped_at_s: summary.stopped_at_s.unwrap_or(0.0),
                partial: partial.display().to_string(),
            }
            .into())
        }
        Ok(Written {
            summary,
            messages,
            loop_s,
            write_s,
        }) => {
            let path = sink.finish()?;
            let bytes = std::fs::metadata(&path).map(|m| m.len()).unwrap_or(0);
            let wall_s = started.elapsed().as_secs_f64();
            eprintln!(
                "wrote {} ({:.1} MiB, {} messages, {:.1} B/message): {:.2} s simulated in {:.2} s ({:.0}x real time)",
                path.display(),
                bytes as f64 / 1048576.0,
                messages,
                bytes as f64 / messages.max(1) as f64,
                summary.duration_s,
                wall_s,
                summary.duration_s / wall_s
            );
            eprintln!(
                "f1 = {:.3} Hz; {}",
                summary
                    .natural_frequencies_hz
                    .first()
                    .copied()
                    .unwrap_or(f64::NAN),
                summary.road_description
            );
            for (id, axle, dlc, sigma) in &summary.dlc {
                eprintln!("vehicle {id} axle {axle}: on the bridge, at every solver step, max/static = {dlc:.3}, sigma/static = {sigma:.3}");
            }
            eprintln!(
                "peak midspan deflection {:.3} mm; steps with a tyre in tension or lifted off: {}",
                summary.peak_midspan_deflection_m * 1e3,
                summary.contact_loss_steps
            );
            if args.timings {
                print_timings(wall_s, loop_s, write_s, summary.duration_s);
            }
            Ok(())
        }
        Err(e) => {
            sink.discard();
            Err(e)
        }
    }
}

/// `--timings`: where the wall time went, and the peak memory. The writer runs on a second
/// thread, so its busy time overlaps the time loop's.
fn print_timings(wall_s: f64, loop_s: f64, write_s: f64, simulated_s: f64) {
    eprintln!(
        "timings: total {wall_s:.3} s = setup and finish {:.3} s + time loop {loop_s:.3} s \
         (physics and sensors on this thread; encoding and writing on a second \
         thread, busy {write_s:.3} s of it); real-time factor {:.0}",
        wall_s - loop_s,
        simulated_s / wall_s
    );
    if let Some(kib) = peak_rss_kib() {
        eprintln!("peak memory (VmHWM): {:.1} MiB", kib as f64 / 1024.0);
    }
}

/// Peak resident memory of this process (Linux `/proc`; `None` elsewhere).
fn peak_rss_kib() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

/// Questionable but legal inputs (coarse time step, vehicles that never arrive...).
fn print_warnings(resolved: &crate::scenario::Resolved) {
    for warning in resolved.warnings() {
        eprintln!("warning: {warning}");
    }
}

/// `scenario show`: prints the default scenario.
pub fn show() {
    print!("{DEFAULT_SCENARIO_TOML}");
}

/// `scenario check FILE`: validates a scenario.
pub fn check(path: &Path) -> Result<()> {
    let (scenario, _) = load_scenario(Some(path))?;
    let resolved = scenario.resolve()?;
    print_warnings(&resolved);
    eprintln!(
        "{}: ok ({} vehicles, {} sensors, {:.2} s, {} steps)",
        path.display(),
        resolved.vehicles.len(),
        resolved.sensors.len(),
        resolved.duration_s(),
        resolved.steps
    );
    Ok(())
}
