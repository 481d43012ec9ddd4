//! `bridgetwin sweep PLAN.toml --out DIR [--jobs N] [--shard I/N]`.

use std::path::PathBuf;

use anyhow::{bail, Context, Result};

use crate::app::sweep::{run_sweep, Plan, Shard};

/// Arguments of `sweep`.
#[derive(Debug, clap::Args)]
pub struct SweepArgs {
    /// The plan: base scenario, grid and random draws over dotted scenario paths.
    pub plan: PathBuf,
    /// Output directory (created): runs/<id>.mcap, runs/<id>.json, runs.csv.
    #[arg(long)]
    pub out: PathBuf,
    /// Runs at once (default: the number of cores).
    #[arg(long)]
    pub jobs: Option<usize>,
    /// This node's share, `I/N` with I in 0..N. Default: from SLURM_ARRAY_TASK_ID and
    /// SLURM_ARRAY_TASK_COUNT, or JOB_COMPLETION_INDEX with --shards, else everything.
    #[arg(long, value_name = "I/N")]
    pub shard: Option<String>,
    /// Shard count for Kubernetes Indexed Jobs (JOB_COMPLETION_INDEX gives the index).
    #[arg(long, value_name = "N")]
    pub shards: Option<usize>,
    /// Expand and check the plan, print the runs, run nothing.
    #[arg(long)]
    pub dry_run: bool,
}

/// Runs `sweep`; every input is checked before the first run starts.
pub fn run(args: &SweepArgs) -> Result<()> {
    let shard = resolve_shard(args, |name| std::env::var(name).ok())?;
    let (plan, base) = Plan::from_file(&args.plan)?;
    let expanded = plan.expand(&base)?;
    let mine = expanded.runs.iter().filter(|r| shard.owns(r.index)).count();
    eprintln!(
        "{}: {} runs, {mine} in shard {}/{}",
        args.plan.display(),
        expanded.runs.len(),
        shard.index,
        shard.count
    );
    if args.dry_run {
        for run in expanded.runs.iter().filter(|r| shard.owns(r.index)) {
            let values: Vec<String> = run
                .parameters
                .iter()
                .map(|(p, v)| format!("{p}={v}"))
                .collect();
            println!("{} {}", run.id, values.join(" "));
        }
        return Ok(());
    }
    let jobs = args.jobs.unwrap_or_else(|| {
        std::thread::available_parallelism().map_or(1, std::num::NonZeroUsize::get)
    });
    if jobs == 0 {
        bail!("--jobs = 0: give at least 1");
    }
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("cannot create the output directory {}", args.out.display()))?;
    let stop = super::terminal::stop_on_signals()?;
    let bar = super::terminal::progress_bar(
        mine as u64,
        "{bar:40} {pos}/{len} runs ({per_sec}, {eta} left)",
    );
    let on_done = |_: &str| {
        if let Some(b) = &bar {
            b.inc(1);
        }
    };
    let report = run_sweep(&expanded, &args.out, shard, jobs, &stop, &on_done)?;
    if let Some(b) = &bar {
        b.finish_and_clear();
    }
    eprintln!(
        "ran {}, skipped {} (already finished), failed {}; {} has {} of {} runs",
        report.ran,
        report.skipped,
        report.failed.len(),
        args.out.join("runs.csv").display(),
        report.manifest_rows,
        expanded.runs.len()
    );
    for (id, error) in &report.failed {
        eprintln!("  {id}: {error}");
    }
    if !report.failed.is_empty() {
        bail!("{} runs failed", report.failed.len());
    }
    Ok(())
}

/// The shard from `--shard`, else Slurm's array variables, else Kubernetes' index.
fn resolve_shard(args: &SweepArgs, env: impl Fn(&str) -> Option<String>) -> Result<Shard> {
    let number = |name: &str, text: &str| -> Result<usize> {
        text.trim()
            .parse()
            .with_context(|| format!("{name} = {text:?}: not a whole number"))
    };
    if let Some(text) = &args.shard {
        let Some((i, n)) = text.split_once('/') else {
            bail!("--shard = {text:?}: expected I/N, e.g. 0/4");
        };
        return Ok(Shard::new(
            number("--shard", i)?,
            number("--shard", n)?,
            "--shard",
        )?);
    }
    if let Some(id) = env("SLURM_ARRAY_TASK_ID") {
        let id = number("SLURM_ARRAY_TASK_ID", &id)?;
        let min =
            env("SLURM_ARRAY_TASK_MIN").map_or(Ok(0), |m| number("SLURM_ARRAY_TASK_MIN", &m))?;
        let Some(count) = env("SLURM_ARRAY_TASK_COUNT") else {
            bail!("SLURM_ARRAY_TASK_ID is set but SLURM_ARRAY_TASK_COUNT is not");
        };
        let count = number("SLURM_ARRAY_TASK_COUNT", &count)?;
        let index = id.checked_sub(min).with_context(|| {
            format!("SLURM_ARRAY_TASK_ID = {id} is below SLURM_ARRAY_TASK_MIN = {min}")
        })?;
        return Ok(Shard::new(
            index,
            count,
            "SLURM_ARRAY_TASK_ID/SLURM_ARRAY_TASK_COUNT",
        )?);
    }
    if let Some(index) = env("JOB_COMPLETION_INDEX") {
        let index = number("JOB_COMPLETION_INDEX", &index)?;
        let Some(count) = args.shards else {
            bail!("JOB_COMPLETION_INDEX = {index} is set: give the shard count with --shards N (the Job's completions)");
        };
        return Ok(Shard::new(index, count, "JOB_COMPLETION_INDEX/--shards")?);
    }
    Ok(Shard::ALL)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args(shard: Option<&str>, shards: Option<usize>) -> SweepArgs {
        SweepArgs {
            plan: "p.toml".into(),
            out: "o".into(),
            jobs: None,
            shard: shard.map(str::to_string),
            shards,
            dry_run: false,
        }
    }

    #[test]
    fn shard_sources_in_order_of_precedence() {
        let env = |vars: &'static [(&'static str, &'static str)]| {
            move |name: &str| vars.iter().find(|v| v.0 == name).map(|v| v.1.to_string())
        };
        let none = env(&[]);
        assert_eq!(
            resolve_shard(&args(Some("1/3"), None), none).unwrap(),
            Shard { index: 1, count: 3 }
        );
        assert_eq!(resolve_shard(&args(None, None), none).unwrap(), Shard::ALL);
        let slurm = env(&[
            ("SLURM_ARRAY_TASK_ID", "5"),
            ("SLURM_ARRAY_TASK_MIN", "1"),
            ("SLURM_ARRAY_TASK_COUNT", "8"),
        ]);
        assert_eq!(
            resolve_shard(&args(None, None), slurm).unwrap(),
            Shard { index: 4, count: 8 }
        );
        let k8s = env(&[("JOB_COMPLETION_INDEX", "2")]);
        assert_eq!(
            resolve_shard(&args(None, Some(4)), k8s).unwrap(),
            Shard { index: 2, count: 4 }
        );
        assert!(resolve_shard(&args(None, None), k8s)
            .unwrap_err()
            .to_string()
            .contains("--shards"));
        for bad in ["4/4", "x/2", "3", "1/0"] {
            assert!(
                resolve_shard(&args(Some(bad), None), none).is_err(),
                "{bad}"
            );
        }
    }
}
