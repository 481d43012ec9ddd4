//! What `simulate`, `inspect` and `simulate --from` print: a short summary by default,
//! every axle with `--verbose`, nothing with `--quiet`; a warning for an `--out` that is
//! not `.mcap`; split runs found by their base name.

use std::path::Path;
use std::process::{Command, Output};

fn bridgetwin(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_bridgetwin"))
        .args(args)
        .output()
        .expect("runs bridgetwin")
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

fn path(dir: &Path, name: &str) -> String {
    dir.join(name).display().to_string()
}

/// The hour example over its first 60 s: some 17 vehicles, 40 axles, one part.
fn hour(dir: &Path, extra: &[&str]) -> Output {
    let out = path(dir, "hour.mcap");
    let mut args = vec![
        "simulate",
        "examples/hour_of_traffic.toml",
        "--duration-s",
        "60",
        "--out",
        &out,
        "--force",
    ];
    args.extend_from_slice(extra);
    bridgetwin(&args)
}

#[test]
fn the_default_summary_is_short_verbose_lists_every_axle_and_quiet_prints_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let default = hour(dir.path(), &[]);
    assert!(default.status.success(), "{}", stderr(&default));
    let text = stderr(&default);
    let axle_lines = |t: &str| t.lines().filter(|l| l.contains(" axle ")).count();
    // The bound: under 30 lines for the hour example, whatever its length (the
    // summary does not grow with the traffic; the full hour printed 2 381 lines before).
    assert!(text.lines().count() < 30, "{text}");
    assert!(text.contains("--verbose lists every axle"), "{text}");
    assert!(text.lines().any(|l| l.starts_with("wrote ")), "{text}");

    let verbose = hour(dir.path(), &["--verbose"]);
    let vtext = stderr(&verbose);
    let axles = axle_lines(&vtext);
    // More axles than the summary's limit: the overview replaced the list.
    assert!(axles > 8, "{vtext}");
    let overview = text
        .lines()
        .find(|l| l.contains("axles) on the bridge"))
        .unwrap();
    assert!(overview.contains(&format!("({axles} axles)")), "{overview}");

    let quiet = hour(dir.path(), &["--quiet"]);
    assert!(quiet.status.success());
    assert_eq!(stderr(&quiet), "");
    assert_eq!(quiet.stdout.len(), 0);
}

#[test]
fn a_small_run_lists_its_axles_and_an_out_that_is_not_mcap_is_warned_about() {
    let dir = tempfile::tempdir().unwrap();
    let out = path(dir.path(), "run.csv");
    let run = bridgetwin(&["simulate", "--duration-s", "8", "--out", &out]);
    assert!(run.status.success());
    let text = stderr(&run);
    assert!(
        text.contains("warning: --out") && text.contains("does not end in .mcap"),
        "{text}"
    );
    // The default truck's two axles, each on its own line.
    assert_eq!(text.lines().filter(|l| l.contains(" axle ")).count(), 2);
    let ok = bridgetwin(&[
        "simulate",
        "--duration-s",
        "2",
        "--out",
        &path(dir.path(), "a.MCAP"),
    ]);
    assert!(!stderr(&ok).contains("does not end in .mcap"));
}

#[test]
fn a_split_run_is_found_by_its_base_name_and_a_missing_one_names_the_part_looked_for() {
    let dir = tempfile::tempdir().unwrap();
    let made = hour(dir.path(), &["--quiet"]);
    assert!(made.status.success(), "{}", stderr(&made));
    let base = path(dir.path(), "hour.mcap");
    let inspect = bridgetwin(&["inspect", &base]);
    assert!(inspect.status.success(), "{}", stderr(&inspect));
    let note = stderr(&inspect);
    assert!(note.contains("is a split run: 1 part"), "{note}");
    assert!(note.contains("hour-0000.mcap"), "{note}");
    assert!(String::from_utf8_lossy(&inspect.stdout).contains("hour-0000.mcap"));

    let again = path(dir.path(), "again.mcap");
    let rerun = bridgetwin(&[
        "simulate",
        "--from",
        &base,
        "--duration-s",
        "1",
        "--out",
        &again,
        "--quiet",
    ]);
    assert!(rerun.status.success(), "{}", stderr(&rerun));
    assert!(stderr(&rerun).contains("reading"));

    let missing = bridgetwin(&["inspect", &path(dir.path(), "nope.mcap")]);
    assert_eq!(missing.status.code(), Some(1));
    let text = stderr(&missing);
    assert!(
        text.contains("no such file") && text.contains("nope-0000.mcap"),
        "{text}"
    );
}
