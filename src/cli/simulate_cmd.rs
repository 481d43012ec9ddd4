//! `bridgetwin simulate` and `bridgetwin scenario`.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::Result;

use std::cell::Cell;

use super::estimate_line::{duration_text, estimate_line, time_left_s};
use crate::app::estimate::RunEstimate;
use crate::app::run::{run_to_files, FilesOptions, FilesOutcome, Written};
use crate::app::space::SpaceCheck;
use crate::scenario::{Scenario, DEFAULT_SCENARIO_TOML};

/// Arguments of `simulate`.
#[derive(Debug, clap::Args)]
pub struct SimulateArgs {
    /// Scenario TOML (default: the embedded default scenario).
    #[arg(conflicts_with = "from")]
    pub scenario: Option<PathBuf>,
    /// Re-run the scenario stored in a bridgetwin MCAP file (same seed: same bytes).
    #[arg(long, value_name = "FILE.mcap")]
    pub from: Option<PathBuf>,
    /// Output MCAP file (written as FILE.partial, renamed on success). With the scenario's
    /// `output.split_every_s`, the pattern of the parts' names: `day.mcap` gives
    /// `day-0000.mcap`, `day-0001.mcap`, ...
    #[arg(long)]
    pub out: PathBuf,
    /// Override the scenario's seed.
    #[arg(long, allow_negative_numbers = true)]
    pub seed: Option<u64>,
    /// Override the duration (s).
    #[arg(long, allow_negative_numbers = true)]
    pub duration_s: Option<f64>,
    /// Replace an existing output file (or part).
    #[arg(long)]
    pub force: bool,
    /// Run even when the estimated size exceeds the free space of the output's file
    /// system (by default such a run is refused before anything is written).
    #[arg(long)]
    pub skip_space_check: bool,
    /// Print the time split: setup, physics + sensors, writing.
    #[arg(long)]
    pub timings: bool,
    /// Print nothing but warnings and errors (no progress bar, no summary).
    #[arg(long, short, conflicts_with = "verbose")]
    pub quiet: bool,
    /// Print every axle's dynamic load coefficient and every warning (the default summary
    /// lists them for small runs only).
    #[arg(long, short)]
    pub verbose: bool,
}

/// Per-axle lines and warnings printed in full up to this many; past it, a summary line.
const FULL_LIST_MAX: usize = 8;

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

/// The run was stopped by SIGINT or SIGTERM; the file (of a split run: the current part)
/// was kept as `.partial`, the parts completed before it keep their final names.
#[derive(Debug, thiserror::Error)]
#[error(
    "interrupted at t = {stopped_at_s:.3} s: kept the data written so far in {partial}{}",
    completed_note(completed_parts)
)]
pub struct Interrupted {
    pub stopped_at_s: f64,
    pub partial: String,
    /// Parts of a split run completed before the interruption.
    pub completed_parts: Vec<PathBuf>,
}

/// ", after 2 complete parts (day-0000.mcap .. day-0001.mcap)", or nothing.
fn completed_note(parts: &[PathBuf]) -> String {
    match parts.len() {
        0 => String::new(),
        n => format!(", after {} ({})", count(n, "complete part"), span(parts)),
    }
}

/// "1 file", "24 files".
fn count(n: usize, noun: &str) -> String {
    match n {
        1 => format!("1 {noun}"),
        _ => format!("{n} {noun}s"),
    }
}

/// `a.mcap`, or `first .. last` of several files.
fn span(paths: &[PathBuf]) -> String {
    match paths {
        [] => String::new(),
        [one] => one.display().to_string(),
        [first, .., last] => format!("{} .. {}", first.display(), last.display()),
    }
}

/// Runs `simulate`.
pub fn run(args: &SimulateArgs) -> Result<()> {
    let started = Instant::now();
    let (mut scenario, original_toml) = match &args.from {
        Some(run) => {
            let path = super::run_path::RunPath::find(run)?;
            if let Some(note) = path.note() {
                eprintln!("{note}");
            }
            super::from_mcap::scenario_from_mcap(path.first())?
        }
        None => load_scenario(args.scenario.as_deref())?,
    };
    if let Some(seed) = args.seed {
        scenario.seed = seed;
    }
    if let Some(d) = args.duration_s {
        scenario.duration_s = Some(d);
    }
    let mut resolved = scenario.resolve()?;
    resolved.source_toml = original_toml;
    print_warnings(&resolved, args.verbose);
    warn_on_extension(&args.out);
    let stop = super::terminal::stop_on_signals()?;
    let bar = match args.quiet {
        true => None,
        false => super::terminal::progress_bar(resolved.steps, "{bar:30} {msg}"),
    };
    // The estimate's wall time and when it was made: the progress bar's time left starts
    // from it, and --timings compares it with the run.
    let estimated: Cell<Option<(f64, Instant)>> = Cell::new(None);
    let mut on_estimate = |e: &RunEstimate| {
        estimated.set(Some((e.timing.wall_s, Instant::now())));
        if !args.quiet {
            let line = estimate_line(e);
            match &bar {
                Some(b) => b.suspend(|| eprintln!("{line}")),
                None => eprintln!("{line}"),
            }
        }
    };
    let mut progress = |p: &crate::sim::RunProgress| {
        if let (Some(b), Some((wall_s, at))) = (&bar, estimated.get()) {
            b.set_position(p.step);
            b.set_message(progress_line(
                p,
                resolved.duration_s(),
                at.elapsed(),
                wall_s,
            ));
        }
    };
    let mut control = crate::sim::Control {
        progress: &mut progress,
        stop: Some(&stop),
    };
    let options = FilesOptions {
        force: args.force,
        space_check: match args.skip_space_check {
            true => SpaceCheck::Skip,
            false => SpaceCheck::default(),
        },
    };
    let outcome = run_to_files(
        &resolved,
        &args.out,
        options,
        &mut control,
        &mut on_estimate,
    );
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    match outcome {
        Ok(FilesOutcome::Stopped {
            written,
            partial,
            completed_parts,
        }) => Err(Interrupted {
            stopped_at_s: written.summary.stopped_at_s.unwrap_or(0.0),
            partial: partial.display().to_string(),
            completed_parts,
        }
        .into()),
        Ok(FilesOutcome::Finished {
            written:
                Written {
                    summary,
                    messages,
                    loop_s,
                    write_s,
                },
            paths,
        }) => {
            let split = resolved.scenario.output.split_every_s.is_some();
            let bytes: u64 = paths
                .iter()
                .map(|path| std::fs::metadata(path).map_or(0, |m| m.len()))
                .sum();
            let wall_s = started.elapsed().as_secs_f64();
            if !args.quiet {
                let files = match split {
                    false => format!("{:.1} MiB", bytes as f64 / 1048576.0),
                    true => format!("{}, {}", count(paths.len(), "file"), size_text(bytes)),
                };
                eprintln!(
                    "wrote {} ({files}, {} messages, {:.1} B/message): {:.2} s simulated in {:.2} s ({:.0}x real time)",
                    span(&paths),
                    messages,
                    bytes as f64 / messages.max(1) as f64,
                    summary.duration_s,
                    wall_s,
                    summary.duration_s / wall_s
                );
                print_summary(&summary, args.verbose);
            }
            if args.timings {
                print_timings(wall_s, loop_s, write_s, summary.duration_s);
                if let Some((estimate_s, at)) = estimated.get() {
                    eprintln!(
                        "the estimate said {} from its line to the end; the run took {}",
                        duration_text(estimate_s),
                        duration_text(at.elapsed().as_secs_f64())
                    );
                }
            }
            Ok(())
        }
        Err((e, completed_parts)) => {
            if !completed_parts.is_empty() {
                // They are whole, valid files: say so rather than leave them unexplained.
                eprintln!(
                    "note: the run failed; its {} stay ({})",
                    count(completed_parts.len(), "complete part"),
                    span(&completed_parts)
                );
            }
            Err(e.into())
        }
    }
}

/// The headline results of a run: f1, model rebuilds, dynamic load coefficients (every
/// axle for small runs or with `verbose`, else the extremes), peak deflection, contact loss.
fn print_summary(summary: &crate::sim::RunSummary, verbose: bool) {
    eprintln!(
        "f1 = {:.3} Hz; {}",
        summary
            .natural_frequencies_hz
            .first()
            .copied()
            .unwrap_or(f64::NAN),
        summary.road_description
    );
    if summary.model_rebuilds > 0 {
        eprintln!(
            "bridge model rebuilt {} times for temperature and damage; f1 at the end = {:.3} Hz",
            summary.model_rebuilds,
            summary
                .final_frequencies_hz
                .first()
                .copied()
                .unwrap_or(f64::NAN)
        );
    }
    if verbose || summary.dlc.len() <= FULL_LIST_MAX {
        for (id, axle, dlc, sigma) in &summary.dlc {
            eprintln!("vehicle {id} axle {axle}: on the bridge, at every solver step, max/static = {dlc:.3}, sigma/static = {sigma:.3}");
        }
    } else {
        eprintln!("{}", dlc_overview(&summary.dlc));
    }
    eprintln!(
        "peak midspan deflection {:.3} mm; steps with a tyre in tension or lifted off: {}",
        summary.peak_midspan_deflection_m * 1e3,
        summary.contact_loss_steps
    );
}

/// One line over many axles: how many vehicles and axles crossed, the largest max/static
/// (which axle) and the median, for the per-axle list ask `--verbose`.
fn dlc_overview(dlc: &[(u32, u32, f64, f64)]) -> String {
    let mut vehicles: Vec<u32> = dlc.iter().map(|(id, ..)| *id).collect();
    vehicles.dedup();
    let mut ratios: Vec<f64> = dlc.iter().map(|d| d.2).filter(|r| r.is_finite()).collect();
    ratios.sort_by(f64::total_cmp);
    let Some(worst) = dlc
        .iter()
        .filter(|d| d.2.is_finite())
        .max_by(|a, b| a.2.total_cmp(&b.2))
    else {
        return format!("{} axles crossed; no dynamic load coefficient", dlc.len());
    };
    format!(
        "{} vehicles ({} axles) on the bridge: max/static highest {:.3} (vehicle {} axle {}), median {:.3}; --verbose lists every axle",
        vehicles.len(),
        dlc.len(),
        worst.2,
        worst.0,
        worst.1,
        ratios[ratios.len() / 2]
    )
}

/// `--out x.csv` still writes MCAP: say so, since the name will mislead every reader.
fn warn_on_extension(out: &Path) {
    let is_mcap = out
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("mcap"));
    if !is_mcap {
        eprintln!(
            "warning: --out {} does not end in .mcap; the file is MCAP whatever its name",
            out.display()
        );
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

/// `812.4 MiB`, or `8.9 GiB` from 1 GiB on.
fn size_text(bytes: u64) -> String {
    const GIB: f64 = 1024.0 * 1024.0 * 1024.0;
    match bytes as f64 {
        b if b >= GIB => format!("{:.1} GiB", b / GIB),
        b => format!("{:.1} MiB", b / 1048576.0),
    }
}

/// Peak resident memory of this process (Linux `/proc`; `None` elsewhere).
fn peak_rss_kib() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

/// Questionable but legal inputs (coarse time step, vehicles that never arrive...):
/// all with `verbose`, else the first few and a count.
fn print_warnings(resolved: &crate::scenario::Resolved, verbose: bool) {
    let warnings = resolved.warnings();
    let shown = match verbose {
        true => warnings.len(),
        false => warnings.len().min(FULL_LIST_MAX),
    };
    for warning in &warnings[..shown] {
        eprintln!("warning: {warning}");
    }
    if shown < warnings.len() {
        eprintln!(
            "warning: ... and {} more like these (--verbose prints all)",
            warnings.len() - shown
        );
    }
}

/// `scenario show`: prints the default scenario.
pub fn show() {
    print!("{DEFAULT_SCENARIO_TOML}");
}

/// `scenario schema`: prints the scenario's JSON Schema.
pub fn schema() {
    print!("{}", crate::scenario::schema::json_text());
}

/// `scenario docs`: prints the scenario reference (Markdown).
pub fn docs() {
    print!("{}", crate::scenario::schema::reference_text());
}

/// `scenario check FILE`: validates a scenario and prints what a run of it would write
/// and take (the line `simulate` prints before it starts).
pub fn check(path: &Path) -> Result<()> {
    let (scenario, original_toml) = load_scenario(Some(path))?;
    let mut resolved = scenario.resolve()?;
    // The run stores the scenario as written: its bytes count in the estimate.
    resolved.source_toml = original_toml;
    print_warnings(&resolved, true);
    eprintln!(
        "{}: ok ({} vehicles, {} sensors, {:.2} s, {} steps)",
        path.display(),
        resolved.vehicles.len(),
        resolved.sensors.len(),
        resolved.duration_s(),
        resolved.steps
    );
    let prepared = crate::sim::prepare(&resolved)?;
    let options = crate::app::run::sink_options(&resolved, false);
    let shape = crate::output::FileShape::new(&options, Some(resolved.flush_every_ns));
    let estimate = crate::app::estimate::estimate_run(&resolved, &prepared, &shape)?;
    eprintln!("{}", estimate_line(&estimate));
    Ok(())
}

/// The progress bar's message: simulated time, the rate, the time left (from the
/// estimate at first, then from the pace so far), vehicles and model rebuilds.
fn progress_line(
    p: &crate::sim::RunProgress,
    duration_s: f64,
    wall: std::time::Duration,
    estimate_s: f64,
) -> String {
    let elapsed_s = wall.as_secs_f64();
    let rate = p.time_s / elapsed_s.max(1e-9);
    let left_s = time_left_s(p.step, p.steps, elapsed_s, estimate_s);
    let mut line = format!(
        "{:.0} of {duration_s:.0} s simulated, {rate:.0}x real time, about {} left",
        p.time_s,
        duration_text(left_s)
    );
    if p.vehicles_on_road > 0 || p.vehicles_passed > 0 {
        line.push_str(&format!(
            " | vehicles: {} on the road, {} passed",
            p.vehicles_on_road, p.vehicles_passed
        ));
    }
    if p.model_rebuilds > 0 {
        line.push_str(&format!(" | {} model rebuilds", p.model_rebuilds));
    }
    line
}
