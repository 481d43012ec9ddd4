//! Interrupted runs and re-runs: a stop request ends the run at the next step; SIGINT and
//! SIGTERM make that request, finish a readable `.partial` file and exit 130; `kill -9`
//! leaves a `.partial` readable up to its last periodic flush; a run's stored scenario
//! re-runs to the same bytes (`simulate --from`).
//!
//! Nothing here is timed: the checks are on steps and on what the files hold. The waits
//! have deadlines only so that a broken stop fails instead of hanging (the runs are 10
//! days of simulated time, hours of work).

#![cfg(unix)]

use std::cell::Cell;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use bridgetwin::scenario::Scenario;
use bridgetwin::sim::{prepare, run_controlled, Control, Record, RunProgress, VecRecorder};

use crate::common::BIN;

fn bin() -> Command {
    Command::new(BIN)
}

/// Simulated time of the long runs: 10 days, hours of work, so a run that ignored its
/// signal would still be running at any deadline below.
const LONG_RUN_S: &str = "864000";

/// How long a wait may last before the test fails instead of hanging.
const DEADLINE: Duration = Duration::from_secs(120);

/// Starts a run long enough to be interrupted (the default scenario, 10 days simulated;
/// its estimate, over 100 GiB, may exceed the disk: it is never meant to finish, so the
/// space check is skipped).
fn start_long_run(out: &Path) -> Child {
    bin()
        .arg("simulate")
        .arg("--out")
        .arg(out)
        .args(["--duration-s", LONG_RUN_S, "--skip-space-check"])
        .stderr(Stdio::piped())
        .spawn()
        .unwrap()
}

fn partial(out: &Path) -> PathBuf {
    let mut name = out.as_os_str().to_owned();
    name.push(".partial");
    PathBuf::from(name)
}

/// Waits until the run has written at least `bytes` to its `.partial` file.
fn wait_for_data(out: &Path, bytes: u64) {
    let deadline = Instant::now() + DEADLINE;
    while std::fs::metadata(partial(out)).map_or(0, |m| m.len()) < bytes {
        assert!(
            Instant::now() < deadline,
            "the run wrote nothing in {DEADLINE:?}"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
}

fn send(child: &Child, signal: &str) {
    let status = Command::new("kill")
        .args([signal, &child.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success());
}

/// Messages of a complete file (summary required), with the last `/events` text and the
/// run-relative time of the last `/sensors/` message (s).
fn read_complete(path: &Path) -> (u64, String, f64) {
    let bytes = std::fs::read(path).unwrap();
    let summary = mcap::Summary::read(&bytes)
        .unwrap()
        .expect("a summary section");
    let mut last_event = String::new();
    let mut count = 0;
    let (mut first_ns, mut last_sensor_ns) = (None, 0);
    for message in mcap::MessageStream::new(&bytes).unwrap() {
        let message = message.unwrap();
        count += 1;
        first_ns.get_or_insert(message.log_time);
        if message.channel.topic == "/events" {
            let log: bridgetwin::output::proto::foxglove::Log =
                prost::Message::decode(&*message.data).unwrap();
            last_event = log.message;
        } else if message.channel.topic.starts_with("/sensors/") {
            last_sensor_ns = last_sensor_ns.max(message.log_time);
        }
    }
    assert_eq!(summary.stats.unwrap().message_count, count);
    let start_ns = first_ns.expect("messages");
    (count, last_event, (last_sensor_ns - start_ns) as f64 * 1e-9)
}

#[test]
fn a_stop_request_ends_the_run_at_the_next_step() {
    // The flag is set from the progress report of step 5000 (reports come every 5000
    // steps): the run checks it before step 5001 and ends with step 5000, its records
    // complete up to there (every 200 Hz sample of 0..=5 s) and nothing after.
    let resolved = Scenario::default_scenario().resolve().expect("resolves");
    let prepared = prepare(&resolved).expect("prepares");
    let stop = AtomicBool::new(false);
    let requested_at = Cell::new(None);
    let mut progress = |p: &RunProgress| {
        if p.step == 5000 && requested_at.get().is_none() {
            requested_at.set(Some(p.step));
            stop.store(true, Ordering::Relaxed);
        }
    };
    let mut control = Control {
        progress: &mut progress,
        stop: Some(&stop),
    };
    let mut recorder = VecRecorder::default();
    let summary = run_controlled(&resolved, &prepared, &mut recorder, &mut control).expect("runs");
    assert_eq!(
        requested_at.get(),
        Some(5000),
        "the report of step 5000 came"
    );
    assert_eq!(summary.steps, 5000);
    assert_eq!(summary.stopped_at_s, Some(5.0));
    let last_ns = resolved.dt_ns * 5000;
    let records = &recorder.records;
    assert!(
        records.iter().all(|r| r.t_ns() <= last_ns),
        "a record after the stop"
    );
    let samples = records
        .iter()
        .filter(|r| matches!(r, Record::Sensor { sensor: 0, .. }))
        .count();
    assert_eq!(samples, 1001, "sensor 0: every sample of 0..=5 s");
    assert!(records.iter().any(|r| matches!(
        r,
        Record::Event { text, .. } if text.contains("stopped on request at t = 5.000 s (step 5000")
    )));
}

#[test]
fn sigint_and_sigterm_finish_a_readable_partial_file_and_exit_130() {
    let dir = tempfile::tempdir().unwrap();
    for signal in ["-INT", "-TERM"] {
        let out = dir.path().join(format!("run{signal}.mcap"));
        let mut child = start_long_run(&out);
        wait_for_data(&out, 1 << 20);
        send(&child, signal);
        let deadline = Instant::now() + DEADLINE;
        let status = loop {
            if let Some(status) = child.try_wait().unwrap() {
                break status;
            }
            if Instant::now() > deadline {
                let _ = child.kill();
                panic!("{signal}: the run did not stop ({DEADLINE:?} after the signal)");
            }
            std::thread::sleep(Duration::from_millis(10));
        };
        let mut stderr = String::new();
        std::io::Read::read_to_string(&mut child.stderr.take().unwrap(), &mut stderr).unwrap();
        assert_eq!(status.code(), Some(130), "{signal}: {stderr}");
        // Where the run says it stopped is where its data ends: the file holds every
        // record up to that step and its last event says so.
        let stopped_at_s: f64 = stderr
            .split("interrupted at t = ")
            .nth(1)
            .and_then(|rest| rest.split(' ').next())
            .and_then(|t| t.parse().ok())
            .unwrap_or_else(|| panic!("{signal}: no stop time in {stderr}"));
        assert!(
            stopped_at_s > 0.0 && stopped_at_s < LONG_RUN_S.parse::<f64>().unwrap(),
            "{signal}: stopped at {stopped_at_s} s"
        );
        assert!(!out.exists(), "the final name is only for complete runs");
        let (count, last_event, last_sensor_s) = read_complete(&partial(&out));
        assert!(count > 10_000, "{signal}: {count} messages");
        assert!(
            last_event.contains(&format!("stopped on request at t = {stopped_at_s:.3} s")),
            "{signal}: last event {last_event:?}, stopped at {stopped_at_s}"
        );
        // `inspect` tells a reader the file ends early because the run was stopped.
        let inspect = bin().arg("inspect").arg(partial(&out)).output().unwrap();
        let report = String::from_utf8_lossy(&inspect.stdout);
        assert!(
            report.contains(&format!(
                "the output of a stopped run, not of the whole scenario: run stopped on \
                 request at t = {stopped_at_s:.3} s"
            )),
            "{signal}: inspect does not say the run was stopped:\n{report}"
        );
        // The default sensors sample at 200 Hz: the last sample is within one period
        // (and the printed time's rounding) of the stop.
        assert!(
            (stopped_at_s - last_sensor_s).abs() <= 0.005 + 5e-4,
            "{signal}: last sensor sample at {last_sensor_s} s, stop at {stopped_at_s} s"
        );
    }
}

/// Messages readable from `bytes` up to the first damaged record.
fn intact_messages(bytes: &[u8]) -> Vec<u64> {
    let Ok(stream) = mcap::MessageStream::new(bytes) else {
        return Vec::new();
    };
    stream
        .map_while(Result::ok)
        .map(|message| message.log_time)
        .collect()
}

#[test]
fn a_killed_run_reads_back_up_to_its_last_flush() {
    // Wait (on the file, not the clock) until the `.partial` holds 10^4 readable messages,
    // kill -9, and read it again: everything that was readable before the kill still is.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("killed.mcap");
    let mut child = start_long_run(&out);
    let deadline = Instant::now() + DEADLINE;
    let before = loop {
        let bytes = std::fs::read(partial(&out)).unwrap_or_default();
        let times = intact_messages(&bytes);
        if times.len() > 10_000 {
            break times;
        }
        assert!(
            Instant::now() < deadline,
            "fewer than 10^4 readable messages in {DEADLINE:?}"
        );
        std::thread::sleep(Duration::from_millis(20));
    };
    send(&child, "-KILL");
    child.wait().unwrap();
    let bytes = std::fs::read(partial(&out)).unwrap();
    assert!(mcap::Summary::read(&bytes).is_err() || mcap::Summary::read(&bytes).unwrap().is_none());
    // Read records until the damaged tail: every intact message decodes and time runs on.
    let after = intact_messages(&bytes);
    assert!(after.windows(2).all(|w| w[0] <= w[1]), "log times decrease");
    assert!(
        after.len() >= before.len() && after[..before.len()] == before[..],
        "{} messages readable before the kill, {} after",
        before.len(),
        after.len()
    );
    // `inspect` says what the file is: no summary, and a last chunk the writer never
    // finished (a killed run), not a "corrupted" record.
    let inspect = bin().arg("inspect").arg(partial(&out)).output().unwrap();
    let said = format!(
        "{}{}",
        String::from_utf8_lossy(&inspect.stdout),
        String::from_utf8_lossy(&inspect.stderr)
    );
    assert!(
        said.contains("no summary section (interrupted run?)"),
        "{said}"
    );
    assert!(!said.contains("corrupted"), "{said}");
    if inspect.status.code() != Some(0) {
        assert!(
            said.contains("ends in a chunk its writer never finished"),
            "{said}"
        );
    }
}

#[test]
fn the_stored_scenario_reruns_to_the_same_bytes() {
    let dir = tempfile::tempdir().unwrap();
    let example = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/two_trucks.toml");
    let first = dir.path().join("first.mcap");
    let again = dir.path().join("again.mcap");
    let run = |args: &[&std::ffi::OsStr]| {
        let output = bin().arg("simulate").args(args).output().unwrap();
        assert!(
            output.status.success(),
            "{}",
            String::from_utf8_lossy(&output.stderr)
        );
    };
    run(&[
        example.as_ref(),
        "--seed".as_ref(),
        "99".as_ref(),
        "--duration-s".as_ref(),
        "4".as_ref(),
        "--out".as_ref(),
        first.as_ref(),
    ]);
    run(&[
        "--from".as_ref(),
        first.as_ref(),
        "--out".as_ref(),
        again.as_ref(),
    ]);
    assert!(
        std::fs::read(&first).unwrap() == std::fs::read(&again).unwrap(),
        "--from must reproduce the file byte for byte"
    );
}

/// An interrupted run's data lives under its `.partial` name: starting the same run
/// again must not truncate it without `--force` (it once did, silently, exit 0), and the
/// refusal names the `.partial`. With `--force` the new run replaces it.
#[test]
fn a_rerun_keeps_an_interrupted_runs_partial_file_unless_forced() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("kept.mcap");
    let mut child = start_long_run(&out);
    wait_for_data(&out, 1 << 20);
    send(&child, "-INT");
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(130));
    let kept = std::fs::read(partial(&out)).unwrap();
    let rerun = |force: bool| {
        let mut cmd = bin();
        cmd.args(["simulate", "--quiet", "--duration-s", "0.5", "--out"])
            .arg(&out);
        if force {
            cmd.arg("--force");
        }
        cmd.output().unwrap()
    };
    let refused = rerun(false);
    let stderr = String::from_utf8_lossy(&refused.stderr);
    assert!(
        !refused.status.success(),
        "a rerun over the .partial succeeded: {stderr}"
    );
    assert!(
        stderr.contains("kept.mcap.partial") && stderr.contains("--force"),
        "{stderr}"
    );
    assert_eq!(
        std::fs::read(partial(&out)).unwrap(),
        kept,
        "the .partial changed"
    );
    assert!(!out.exists());
    let forced = rerun(true);
    assert!(
        forced.status.success(),
        "{}",
        String::from_utf8_lossy(&forced.stderr)
    );
    assert!(out.exists() && !partial(&out).exists());
}
