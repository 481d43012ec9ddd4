//! Command-line interface: argument parsing, dispatch, printing, exit codes. The only
//! module that prints.

mod bench_cmd;
mod estimate_line;
pub mod from_mcap;
pub mod inspect_cmd;
mod layout_cmd;
mod run_path;
mod simulate_cmd;
mod sweep_cmd;
mod terminal;
mod verify_cmd;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};

/// Digital twin of a road bridge under traffic: vehicle-bridge interaction to MCAP.
#[derive(Debug, Parser)]
#[command(name = "bridgetwin", version, about, long_about = None)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Simulate a scenario and write the run to MCAP.
    Simulate(simulate_cmd::SimulateArgs),
    /// Print or check scenarios.
    #[command(subcommand)]
    Scenario(ScenarioCommand),
    /// Summarise a run: channels, counts, rates, metadata, attachments and headline truth
    /// (exit code 3 when the file is damaged: the figures cover its intact part).
    Inspect(inspect_cmd::InspectArgs),
    /// Build a Foxglove layout from a run's channels (JSON on stdout, or --out).
    Layout(layout_cmd::LayoutArgs),
    /// Run a dataset sweep: a plan of scenario variations, one MCAP per run, runs.csv.
    Sweep(sweep_cmd::SweepArgs),
    /// Run the analytical verification ladder (exit code 1 if any check fails).
    Verify(VerifyArgs),
    /// Reproduce the paper's studies and go past them (CSV, SVG, summary.md).
    Study(StudyArgs),
    /// Time a coupled step on each solver path against the paper's direct method.
    Bench(bench_cmd::BenchArgs),
}

#[derive(Debug, Subcommand)]
pub enum ScenarioCommand {
    /// Print the embedded default scenario (a starting point for your own).
    Show,
    /// Validate a scenario file.
    Check {
        /// Scenario TOML.
        file: PathBuf,
    },
    /// Print the scenario format as a JSON Schema (draft-07) for TOML editors, generated
    /// from the code: every key with its type, unit, default and allowed values
    /// (docs/scenario.schema.json).
    Schema,
    /// Print the scenario reference in Markdown, generated from the same schema
    /// (docs/scenario.md).
    Docs,
}

#[derive(Debug, clap::Args)]
pub struct VerifyArgs {
    /// Print JSON rows instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Run only the groups whose name contains this text.
    #[arg(long)]
    pub only: Option<String>,
}

#[derive(Debug, clap::Args)]
pub struct StudyArgs {
    /// Which study.
    #[arg(value_enum)]
    pub which: StudyKind,
    /// Output directory (created if missing).
    #[arg(long)]
    pub out: PathBuf,
    /// A reduced grid that runs in seconds (CI).
    #[arg(long)]
    pub quick: bool,
}

#[derive(Debug, Clone, Copy, clap::ValueEnum)]
pub enum StudyKind {
    /// Lumped mass vs finite elements: error and cost vs n and dt (the paper's section 6).
    Discretization,
    /// Dynamic load coefficients vs speed and road class against design codes (section 11).
    Dlc,
    /// Lumped low-rank, banded FE and modal paths against a converged reference.
    SolverPaths,
    /// A three-span girder: DAF of the sagging and hogging moments and DLC vs speed and
    /// road, against the codes; lumped mass vs finite elements on it.
    Continuous,
    /// The EN 1991-2 6.4.6 dynamic check: the ten HSLM-A trains vs speed on a short span
    /// and the paper's bridge, moving forces against vehicle models, DER and LIR.
    Hslm,
}

/// Parses arguments, runs the command and maps the outcome to an exit code:
/// 0 ok, 1 error (or failed verification), 2 usage, 3 `inspect` read a damaged file (up to
/// the damage), 130 stopped by SIGINT/SIGTERM.
pub fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            let code = if e.use_stderr() { 2 } else { 0 };
            let _ = e.print();
            return ExitCode::from(code);
        }
    };
    let outcome = match cli.command {
        Command::Simulate(args) => simulate_cmd::run(&args).map(|()| true),
        Command::Scenario(ScenarioCommand::Show) => {
            simulate_cmd::show();
            Ok(true)
        }
        Command::Scenario(ScenarioCommand::Check { file }) => {
            simulate_cmd::check(&file).map(|()| true)
        }
        Command::Scenario(ScenarioCommand::Schema) => {
            simulate_cmd::schema();
            Ok(true)
        }
        Command::Scenario(ScenarioCommand::Docs) => {
            simulate_cmd::docs();
            Ok(true)
        }
        Command::Inspect(args) => inspect_cmd::run(&args).map(|()| true),
        Command::Layout(args) => layout_cmd::run(&args).map(|()| true),
        Command::Sweep(args) => sweep_cmd::run(&args).map(|()| true),
        Command::Verify(args) => verify_cmd::run(&args),
        Command::Bench(args) => bench_cmd::run(&args).map(|()| true),
        Command::Study(args) => {
            let mut progress = |line: &str| eprintln!("  {line}");
            crate::studies::run_named(args.which_name(), &args.out, args.quick, &mut progress)
                .map(|()| {
                    eprintln!("wrote {}", args.out.display());
                    true
                })
                .map_err(anyhow::Error::from)
        }
    };
    match outcome {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::from(1),
        Err(e) if e.is::<simulate_cmd::Interrupted>() => {
            eprintln!("{e:#}");
            // 128 + SIGINT, the shell convention for a run stopped by the user.
            ExitCode::from(130)
        }
        Err(e) if e.is::<inspect_cmd::Damaged>() => {
            eprintln!("error: {e:#}");
            // Read, but not whole: 3, as tools/read_run.py exits (1 is "nothing read").
            ExitCode::from(3)
        }
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(1)
        }
    }
}

impl StudyArgs {
    fn which_name(&self) -> &'static str {
        match self.which {
            StudyKind::Discretization => "discretization",
            StudyKind::Dlc => "dlc",
            StudyKind::SolverPaths => "solver-paths",
            StudyKind::Continuous => "continuous",
            StudyKind::Hslm => "hslm",
        }
    }
}
