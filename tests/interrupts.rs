//! Interrupted runs and re-runs: SIGINT/SIGTERM finish a readable `.partial` file and exit
//! 130; `kill -9` leaves a `.partial` readable up to its last periodic flush; a run's
//! stored scenario re-runs to the same bytes (`simulate --from`).

#![cfg(unix)]

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_bridgetwin"))
}

/// Starts a run long enough to be interrupted (the default scenario, 3 h simulated).
fn start_long_run(out: &Path) -> Child {
    bin()
        .arg("simulate")
        .arg("--out")
        .arg(out)
        .args(["--duration-s", "10800"])
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
    let deadline = Instant::now() + Duration::from_secs(60);
    while std::fs::metadata(partial(out)).map_or(0, |m| m.len()) < bytes {
        assert!(Instant::now() < deadline, "the run wrote nothing for 60 s");
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

/// Messages of a complete file (summary required), with the last `/events` text.
fn read_complete(path: &Path) -> (u64, String) {
    let bytes = std::fs::read(path).unwrap();
    let summary = mcap::Summary::read(&bytes)
        .unwrap()
        .expect("a summary section");
    let mut last_event = String::new();
    let mut count = 0;
    for message in mcap::MessageStream::new(&bytes).unwrap() {
        let message = message.unwrap();
        count += 1;
        if message.channel.topic == "/events" {
            let log: bridgetwin::output::proto::foxglove::Log =
                prost::Message::decode(&*message.data).unwrap();
            last_event = log.message;
        }
    }
    assert_eq!(summary.stats.unwrap().message_count, count);
    (count, last_event)
}

#[test]
fn sigint_and_sigterm_finish_a_readable_partial_file_and_exit_130() {
    let dir = tempfile::tempdir().unwrap();
    for signal in ["-INT", "-TERM"] {
        let out = dir.path().join(format!("run{signal}.mcap"));
        let mut child = start_long_run(&out);
        wait_for_data(&out, 1 << 20);
        let sent = Instant::now();
        send(&child, signal);
        let output = {
            let status = child.wait().unwrap();
            let mut stderr = String::new();
            std::io::Read::read_to_string(&mut child.stderr.take().unwrap(), &mut stderr).unwrap();
            (status, stderr)
        };
        let stopped_in = sent.elapsed();
        assert_eq!(output.0.code(), Some(130), "{signal}: {}", output.1);
        assert!(
            stopped_in < Duration::from_secs(1),
            "{signal}: took {stopped_in:?} to stop"
        );
        assert!(output.1.contains("interrupted at t ="), "{}", output.1);
        assert!(!out.exists(), "the final name is only for complete runs");
        let (count, last_event) = read_complete(&partial(&out));
        assert!(count > 10_000, "{signal}: {count} messages");
        assert!(
            last_event.contains("stopped on request"),
            "{signal}: last event {last_event:?}"
        );
    }
}

#[test]
fn a_killed_run_reads_back_up_to_its_last_flush() {
    // The sink closes a chunk every 2 s of wall time; kill -9 after the first flushes.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("killed.mcap");
    let mut child = start_long_run(&out);
    wait_for_data(&out, 1 << 20);
    std::thread::sleep(Duration::from_millis(2500));
    send(&child, "-KILL");
    child.wait().unwrap();
    let bytes = std::fs::read(partial(&out)).unwrap();
    assert!(mcap::Summary::read(&bytes).is_err() || mcap::Summary::read(&bytes).unwrap().is_none());
    // Read records until the damaged tail: every intact message decodes and time runs on.
    let mut count = 0u64;
    let mut last_time = 0;
    for message in mcap::MessageStream::new(&bytes).unwrap() {
        let Ok(message) = message else { break };
        assert!(message.log_time >= last_time);
        last_time = message.log_time;
        count += 1;
    }
    assert!(count > 10_000, "only {count} messages survived");
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
