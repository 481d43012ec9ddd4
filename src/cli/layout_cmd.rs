//! `bridgetwin layout RUN.mcap [--out layout.json]`: a Foxglove layout built from the
//! run's own channels (`output::layout`).

use std::path::PathBuf;

use anyhow::{Context, Result};

use crate::output::layout::{layout_for_file, LayoutOptions};

/// Arguments of `layout`.
#[derive(Debug, clap::Args)]
pub struct LayoutArgs {
    /// MCAP file written by `bridgetwin simulate` (a `.partial` file works too); for a
    /// split run, one part, or its base name (`day.mcap` for `day-0000.mcap`, ...) for
    /// the first part.
    pub file: PathBuf,
    /// Write the layout to this file instead of stdout.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Plot the axle forces of this vehicle (repeatable; default: the first vehicles to
    /// reach the bridge).
    #[arg(long = "vehicle", value_name = "ID")]
    pub vehicles: Vec<u32>,
    /// How many vehicles get an axle-force panel when none is chosen.
    #[arg(long, default_value_t = LayoutOptions::default().max_vehicles)]
    pub max_vehicles: usize,
    /// Sensors plotted per kind (spread along the bridge).
    #[arg(long, default_value_t = LayoutOptions::default().max_sensors_per_kind)]
    pub sensors_per_kind: usize,
}

/// Runs `layout`: the layout on stdout (or in `--out`), notes on stderr.
pub fn run(args: &LayoutArgs) -> Result<()> {
    let options = LayoutOptions {
        vehicles: args.vehicles.clone(),
        max_vehicles: args.max_vehicles,
        max_sensors_per_kind: args.sensors_per_kind,
    };
    let path = super::run_path::RunPath::find(&args.file)?;
    if let Some(note) = path.note() {
        eprintln!("{note}");
    }
    let layout = layout_for_file(path.first(), &options)?;
    for note in &layout.notes {
        eprintln!("note: {note}");
    }
    let text = serde_json::to_string_pretty(&layout.json)? + "\n";
    match &args.out {
        Some(path) => {
            std::fs::write(path, text).with_context(|| format!("writing {}", path.display()))?;
            eprintln!(
                "wrote {} (Foxglove: Layouts, Import from file)",
                path.display()
            );
            Ok(())
        }
        None => super::inspect_cmd::write_stdout(&text),
    }
}
