//! Dataset sweeps: a plan expanded into runs ([`plan`]), the runs of one shard executed in
//! parallel, one MCAP per run, and a manifest (`runs.csv`).
//!
//! Layout of the output directory:
//! - `runs/<id>.mcap`: the run, byte-identical to `bridgetwin simulate` on its scenario;
//! - `runs/<id>.json`: its headline results, written last: a run is finished when its
//!   JSON exists, so a rerun skips it (resume) and a killed run is redone;
//! - `runs.csv`: the manifest, rebuilt from every finished run's JSON at the end of each
//!   invocation (each shard rebuilds it; the last to finish lists every run).
//!
//! Runs are given to shards round robin (`index mod count`), the same on every node.

pub mod plan;

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Mutex;

use serde::{Deserialize, Serialize};

use crate::app::run::{write_run, WriterThread};
use crate::error::{Error, Result};
use crate::output::{McapSink, SinkOptions};

pub use plan::{Expanded, Plan, RunSpec};

/// Which part of the runs this invocation does.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    pub index: usize,
    pub count: usize,
}

impl Shard {
    /// The whole sweep.
    pub const ALL: Shard = Shard { index: 0, count: 1 };

    /// Checks `index < count`; `source` names where the values came from.
    pub fn new(index: usize, count: usize, source: &str) -> Result<Shard> {
        if count == 0 || index >= count {
            return Err(Error::invalid(
                source,
                format!("{index}/{count}"),
                "the shard index must be in 0..count and count >= 1",
            ));
        }
        Ok(Shard { index, count })
    }

    /// Whether run `index` belongs to this shard.
    pub fn owns(&self, run_index: usize) -> bool {
        run_index % self.count == self.index
    }
}

/// Headline results of one run (its JSON file and its manifest row).
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct RunResult {
    pub id: String,
    pub seed: u64,
    pub parameters: Vec<(String, String)>,
    pub output: String,
    pub duration_s: f64,
    pub f1_hz: f64,
    pub peak_midspan_deflection_m: f64,
    /// "vehicle:axle=max/static" per axle, `;`-separated.
    pub dlc: String,
    pub contact_loss_steps: u64,
    pub bytes: u64,
}

/// What one invocation did.
#[derive(Debug, Default)]
pub struct SweepReport {
    pub ran: usize,
    pub skipped: usize,
    pub failed: Vec<(String, String)>,
    pub manifest_rows: usize,
}

/// Runs this shard's runs of `expanded` into `out` with `jobs` threads.
/// `on_done(id)` is called as runs finish (progress); `stop` ends the sweep early
/// (runs already started finish as `.partial` files and are redone on resume).
pub fn run_sweep(
    expanded: &Expanded,
    out: &Path,
    shard: Shard,
    jobs: usize,
    stop: &AtomicBool,
    on_done: &(dyn Fn(&str) + Sync),
) -> Result<SweepReport> {
    let runs_dir = out.join("runs");
    std::fs::create_dir_all(&runs_dir).map_err(|e| Error::Output {
        path: runs_dir.display().to_string(),
        reason: format!("cannot create the directory: {e}"),
    })?;
    let mine: Vec<&RunSpec> = expanded
        .runs
        .iter()
        .filter(|r| shard.owns(r.index))
        .collect();
    let next = AtomicUsize::new(0);
    let report = Mutex::new(SweepReport::default());
    std::thread::scope(|scope| {
        for _ in 0..jobs.max(1) {
            scope.spawn(|| loop {
                if stop.load(Ordering::Relaxed) {
                    return;
                }
                let Some(run) = mine.get(next.fetch_add(1, Ordering::Relaxed)) else {
                    return;
                };
                let outcome = run_one(run, &runs_dir, stop);
                let mut r = report.lock().unwrap_or_else(|e| e.into_inner());
                match outcome {
                    Ok(true) => r.ran += 1,
                    Ok(false) => r.skipped += 1,
                    Err(e) => r.failed.push((run.id.clone(), e.to_string())),
                }
                drop(r);
                on_done(&run.id);
            });
        }
    });
    let mut report = report.into_inner().unwrap_or_else(|e| e.into_inner());
    report.manifest_rows = write_manifest(expanded, out)?;
    Ok(report)
}

fn json_path(runs_dir: &Path, id: &str) -> PathBuf {
    runs_dir.join(format!("{id}.json"))
}

/// Runs one scenario unless its JSON says it is done; `Ok(false)` when skipped.
fn run_one(run: &RunSpec, runs_dir: &Path, stop: &AtomicBool) -> Result<bool> {
    let json = json_path(runs_dir, &run.id);
    if json.exists() {
        return Ok(false);
    }
    let mcap = runs_dir.join(format!("{}.mcap", run.id));
    let mut resolved = run.scenario.resolve()?;
    resolved.source_toml = run.toml.clone();
    let prepared = crate::sim::prepare(&resolved)?;
    let options = SinkOptions {
        force: true,
        ..Default::default()
    };
    let mut sink = McapSink::create(&mcap, options)?;
    let mut progress = |_: &crate::sim::RunProgress| {};
    let mut control = crate::sim::Control {
        progress: &mut progress,
        stop: Some(stop),
    };
    let written = match write_run(
        &mut sink,
        &resolved,
        &prepared,
        &mut control,
        WriterThread::Inline,
    ) {
        Ok(w) if w.summary.stopped_at_s.is_none() => w,
        Ok(_) => {
            sink.finish_partial()?;
            return Err(Error::invalid(&run.id, "run", "stopped before the end"));
        }
        Err(e) => {
            sink.discard();
            return Err(e);
        }
    };
    let path = sink.finish()?;
    let summary = &written.summary;
    let result = RunResult {
        id: run.id.clone(),
        seed: run.scenario.seed,
        parameters: run.parameters.clone(),
        output: format!("runs/{}.mcap", run.id),
        duration_s: summary.duration_s,
        f1_hz: summary
            .natural_frequencies_hz
            .first()
            .copied()
            .unwrap_or(f64::NAN),
        peak_midspan_deflection_m: summary.peak_midspan_deflection_m,
        dlc: summary
            .dlc
            .iter()
            .map(|(v, a, dlc, _)| format!("{v}:{a}={dlc:.6}"))
            .collect::<Vec<_>>()
            .join(";"),
        contact_loss_steps: summary.contact_loss_steps,
        bytes: std::fs::metadata(&path).map_or(0, |m| m.len()),
    };
    write_atomically(
        &json,
        &serde_json::to_vec_pretty(&result).unwrap_or_default(),
    )?;
    Ok(true)
}

/// Writes `bytes` to `path` through a temporary file and a rename, so that readers (and
/// other shards) never see half a file.
fn write_atomically(path: &Path, bytes: &[u8]) -> Result<()> {
    let fail = |e: std::io::Error| Error::Output {
        path: path.display().to_string(),
        reason: e.to_string(),
    };
    let mut tmp = path.as_os_str().to_owned();
    tmp.push(format!(".tmp{}", std::process::id()));
    let tmp = PathBuf::from(tmp);
    std::fs::write(&tmp, bytes).map_err(fail)?;
    std::fs::rename(&tmp, path).map_err(fail)
}

/// Rebuilds `runs.csv` from every finished run's JSON, in run order. Returns its rows.
fn write_manifest(expanded: &Expanded, out: &Path) -> Result<usize> {
    let runs_dir = out.join("runs");
    let mut csv = String::from("run_id,seed");
    // A swept `seed` is already the second column.
    let swept: Vec<bool> = expanded.paths.iter().map(|p| p != "seed").collect();
    for p in expanded.paths.iter().filter(|p| *p != "seed") {
        csv.push(',');
        csv.push_str(&csv_field(p));
    }
    csv.push_str(
        ",output,duration_s,f1_hz,peak_midspan_deflection_m,dlc,contact_loss_steps,bytes\n",
    );
    let mut rows = 0;
    for run in &expanded.runs {
        let Ok(text) = std::fs::read(json_path(&runs_dir, &run.id)) else {
            continue;
        };
        let r: RunResult = serde_json::from_slice(&text).map_err(|e| Error::File {
            path: json_path(&runs_dir, &run.id).display().to_string(),
            reason: e.to_string(),
        })?;
        csv.push_str(&format!("{},{}", r.id, r.seed));
        for ((_, value), _) in r.parameters.iter().zip(&swept).filter(|(_, keep)| **keep) {
            csv.push(',');
            csv.push_str(&csv_field(value));
        }
        csv.push_str(&format!(
            ",{},{},{},{},{},{},{}\n",
            r.output,
            r.duration_s,
            r.f1_hz,
            r.peak_midspan_deflection_m,
            r.dlc,
            r.contact_loss_steps,
            r.bytes
        ));
        rows += 1;
    }
    write_atomically(&out.join("runs.csv"), csv.as_bytes())?;
    Ok(rows)
}

/// Quotes a CSV field when it holds a comma or a quote.
fn csv_field(text: &str) -> String {
    if text.contains([',', '"', '\n']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shards_partition_the_runs() {
        let shards: Vec<Shard> = (0..3)
            .map(|i| Shard::new(i, 3, "--shard").unwrap())
            .collect();
        for run in 0..20 {
            assert_eq!(shards.iter().filter(|s| s.owns(run)).count(), 1);
        }
        assert!(Shard::new(3, 3, "--shard").is_err());
        assert!(Shard::new(0, 0, "--shard").is_err());
    }

    #[test]
    fn csv_fields_are_quoted_when_needed() {
        assert_eq!(csv_field("20.0"), "20.0");
        assert_eq!(csv_field("[1, 2]"), "\"[1, 2]\"");
        assert_eq!(csv_field("\"A\""), "\"\"\"A\"\"\"");
    }
}
