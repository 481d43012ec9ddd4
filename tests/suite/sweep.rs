//! `bridgetwin sweep`: shards add up to the unsharded sweep byte for byte with no run
//! twice, the job count does not change a byte, an interrupted sweep resumes, a run's file
//! is what `simulate` writes for its scenario, and bad plans fail before any run.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::atomic::{AtomicBool, Ordering};

use bridgetwin::app::sweep::{run_sweep, Plan, Shard};

const PLAN: &str = r#"
seed = 11
[grid]
"vehicles.0.speed_m_s" = [15.0, 25.0]
"road.profile.class" = ["A", "B", "C"]
[random]
draws = 1
"seed" = { integer = [0, 100000] }
"bridge.damping_ratio" = { uniform = [0.01, 0.03] }
"#;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_bridgetwin"))
}

fn sweep(plan: &Path, out: &Path, extra: &[&str]) -> Output {
    bin()
        .arg("sweep")
        .arg(plan)
        .arg("--out")
        .arg(out)
        .args(extra)
        .output()
        .unwrap()
}

fn ok(output: Output) -> Output {
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    output
}

fn write_plan(dir: &Path, text: &str) -> PathBuf {
    let plan = dir.join("plan.toml");
    std::fs::write(&plan, text).unwrap();
    plan
}

/// Every file under `dir/runs` (name -> bytes).
fn run_files(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    let Ok(entries) = std::fs::read_dir(dir.join("runs")) else {
        return BTreeMap::new();
    };
    entries
        .map(|e| {
            let e = e.unwrap();
            let name = e.file_name().to_string_lossy().into_owned();
            (name, std::fs::read(e.path()).unwrap())
        })
        .collect()
}

#[test]
fn shards_together_equal_the_unsharded_sweep_and_jobs_do_not_matter() {
    let dir = tempfile::tempdir().unwrap();
    let plan = write_plan(dir.path(), PLAN);
    let whole = dir.path().join("whole");
    ok(sweep(&plan, &whole, &["--jobs", "1"]));
    let whole_files = run_files(&whole);
    assert_eq!(whole_files.len(), 12, "6 runs x (mcap + json)");

    let parallel = dir.path().join("parallel");
    ok(sweep(&plan, &parallel, &["--jobs", "2"]));
    assert!(
        run_files(&parallel) == whole_files,
        "--jobs 2 differs from --jobs 1"
    );
    assert_eq!(
        std::fs::read(parallel.join("runs.csv")).unwrap(),
        std::fs::read(whole.join("runs.csv")).unwrap()
    );

    // Three shards in separate directories: disjoint, and together the whole sweep.
    let mut union = BTreeMap::new();
    for i in 0..3 {
        let out = dir.path().join(format!("shard{i}"));
        ok(sweep(
            &plan,
            &out,
            &["--shard", &format!("{i}/3"), "--jobs", "2"],
        ));
        for (name, bytes) in run_files(&out) {
            assert!(
                union.insert(name.clone(), bytes).is_none(),
                "{name} ran twice"
            );
        }
    }
    assert!(
        union == whole_files,
        "the shards differ from the unsharded sweep"
    );

    // Slurm's variables select the same shard as --shard.
    let slurm = dir.path().join("slurm");
    ok(bin()
        .args(["sweep"])
        .arg(&plan)
        .arg("--out")
        .arg(&slurm)
        .env("SLURM_ARRAY_TASK_ID", "2")
        .env("SLURM_ARRAY_TASK_MIN", "1")
        .env("SLURM_ARRAY_TASK_COUNT", "3")
        .output()
        .unwrap());
    assert!(run_files(&slurm) == run_files(&dir.path().join("shard1")));
}

#[test]
fn a_run_of_the_sweep_is_what_simulate_writes_for_its_scenario() {
    let dir = tempfile::tempdir().unwrap();
    let plan = write_plan(dir.path(), PLAN);
    let out = dir.path().join("sweep");
    ok(sweep(&plan, &out, &[]));
    let run = out.join("runs/run-000004.mcap");
    let again = dir.path().join("again.mcap");
    ok(bin()
        .args(["simulate", "--from"])
        .arg(&run)
        .arg("--out")
        .arg(&again)
        .output()
        .unwrap());
    assert!(std::fs::read(&run).unwrap() == std::fs::read(&again).unwrap());
    let manifest = std::fs::read_to_string(out.join("runs.csv")).unwrap();
    let lines: Vec<&str> = manifest.lines().collect();
    assert_eq!(lines.len(), 7, "{manifest}");
    assert!(lines[0].starts_with(
        "run_id,seed,road.profile.class,vehicles.0.speed_m_s,bridge.damping_ratio,output"
    ));
    // Grid order: the first key (road.profile.class) varies slowest.
    assert!(lines[5].contains(",C,15.0,"), "{}", lines[5]);
}

#[test]
fn an_interrupted_sweep_resumes_and_ends_identical() {
    // The interruption is made exactly, not timed: the sweep's stop flag is set when it
    // reports its first run done (one job: no other run has started), and what a kill -9
    // in the middle of the second run leaves, its `.partial`, is put beside it. Resuming
    // must skip the finished run, redo the rest and end with the clean sweep's files.
    let dir = tempfile::tempdir().unwrap();
    let plan = write_plan(dir.path(), PLAN);
    let clean = dir.path().join("clean");
    ok(sweep(&plan, &clean, &["--jobs", "2"]));

    let (parsed, base) = Plan::from_file(&plan).expect("plan reads");
    let expanded = parsed.expand(&base).expect("plan expands");
    let resumed = dir.path().join("resumed");
    let stop = AtomicBool::new(false);
    let report = run_sweep(&expanded, &resumed, Shard::ALL, 1, &stop, &|_| {
        stop.store(true, Ordering::Relaxed)
    })
    .expect("sweep runs");
    assert_eq!((report.ran, report.skipped), (1, 0), "{report:?}");
    let second = &expanded.runs[1].id;
    std::fs::write(
        resumed.join("runs").join(format!("{second}.mcap.partial")),
        b"the first bytes of a run killed midway",
    )
    .unwrap();
    let done_before = run_files(&resumed)
        .keys()
        .filter(|n| n.ends_with(".json"))
        .count();
    assert_eq!(done_before, 1);

    let output = ok(sweep(&plan, &resumed, &["--jobs", "2"]));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("skipped 1"), "{stderr}");
    let mut files = run_files(&resumed);
    files.retain(|name, _| !name.ends_with(".partial"));
    assert!(files == run_files(&clean), "resumed sweep differs");
    assert_eq!(
        std::fs::read(resumed.join("runs.csv")).unwrap(),
        std::fs::read(clean.join("runs.csv")).unwrap()
    );
}

#[test]
fn bad_plans_fail_before_any_run_naming_the_field() {
    let dir = tempfile::tempdir().unwrap();
    let cases: [(&str, &[&str], &str); 7] = [
        (
            "[grid]\n\"vehicles.0.sped_m_s\" = [10.0]\n",
            &[],
            "sped_m_s",
        ),
        (
            "[grid]\n\"vehicles.4.speed_m_s\" = [10.0]\n",
            &[],
            "vehicles.4.speed_m_s",
        ),
        (
            "[grid]\n\"vehicles.0.speed_m_s\" = [\"fast\"]\n",
            &[],
            "speed_m_s",
        ),
        (
            "[grid]\n\"bridge.span_m\" = [30.0, -5.0]\n",
            &[],
            "bridge.span_m = -5",
        ),
        (
            "[random]\ndraws = 2\n\"seed\" = { uniform = [5.0, 1.0] }\n",
            &[],
            "random.\"seed\"",
        ),
        (PLAN, &["--shard", "3/3"], "--shard = 3/3"),
        (PLAN, &["--jobs", "0"], "--jobs"),
    ];
    for (i, (text, extra, needle)) in cases.iter().enumerate() {
        let plan = dir.path().join(format!("bad{i}.toml"));
        std::fs::write(&plan, text).unwrap();
        let out = dir.path().join(format!("out{i}"));
        let output = sweep(&plan, &out, extra);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(1), "case {i}: {stderr}");
        assert!(
            stderr.contains(needle),
            "case {i}: {needle:?} not in {stderr}"
        );
        assert!(!out.exists(), "case {i}: output created before failing");
    }
    // An output directory that cannot be created.
    let plan = write_plan(dir.path(), PLAN);
    let output = sweep(&plan, Path::new("/dev/null/sweep"), &[]);
    assert_eq!(output.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&output.stderr).contains("/dev/null/sweep"));
}
