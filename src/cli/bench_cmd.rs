//! `bridgetwin bench [--quick] [--json]`: per-step cost and accuracy of each solver path
//! against the paper's direct method, and the default scenario's real-time factor.

use anyhow::Result;

/// Arguments of `bridgetwin bench`.
#[derive(Debug, clap::Args)]
pub struct BenchArgs {
    /// 50 and 100 nodes only, fewer and shorter repetitions (well under 20 s).
    #[arg(long)]
    pub quick: bool,
    /// Print the report as JSON instead of a table.
    #[arg(long)]
    pub json: bool,
}

/// Runs the bench, progress on stderr, the table (or JSON) on stdout.
pub fn run(args: &BenchArgs) -> Result<()> {
    let mut progress = |line: &str| eprintln!("  {line}");
    let report = crate::studies::bench::run(args.quick, &mut progress)?;
    if args.json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        print!("{}", report.to_table());
    }
    Ok(())
}
