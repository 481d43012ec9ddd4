//! The README's tour, run as written, so that it cannot rot: every `sh` block between a
//! `<!-- tour` mark and the next `<!-- /tour -->` runs line by line in one temporary
//! folder (holding a link to `examples/`, as a checkout would), with
//! `cargo run --release --` taken as the binary cargo built for the suite. A command that
//! exits non-zero fails the test, named with its README line and its stderr. The tour's
//! Python blocks are run by `python/tests/test_readme_tour.py`.

use std::path::Path;
use std::process::Command;

use super::common::BIN;
use super::markdown::{blocks, repo};

/// How the README spells the command line: replaced by the built binary.
const CARGO_RUN: &str = "cargo run --release --";

/// One command of the tour: its README line and its text.
#[derive(Debug, PartialEq)]
struct TourCommand {
    line: usize,
    text: String,
}

/// The 1-based line ranges of the tour regions of `text`: from a line starting with
/// `<!-- tour` to the next `<!-- /tour -->`.
fn tour_regions(text: &str) -> Vec<(usize, usize)> {
    let mut regions = Vec::new();
    let mut start = None;
    for (index, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.starts_with("<!-- tour") {
            assert!(
                start.is_none(),
                "README line {}: a tour mark inside a tour region",
                index + 1
            );
            start = Some(index + 1);
        } else if line == "<!-- /tour -->" {
            let from = start.take().unwrap_or_else(|| {
                panic!(
                    "README line {}: <!-- /tour --> with no tour mark",
                    index + 1
                )
            });
            regions.push((from, index + 1));
        }
    }
    assert!(
        start.is_none(),
        "a tour region of the README is never closed"
    );
    regions
}

/// The shell commands of the tour regions: every `sh` block's lines, a trailing `\` joining
/// a line to the next, blank and comment lines left out.
fn tour_commands(text: &str) -> Vec<TourCommand> {
    let regions = tour_regions(text);
    let mut commands = Vec::new();
    for block in blocks(text) {
        let in_tour = regions
            .iter()
            .any(|&(from, to)| from < block.fence_line && block.fence_line < to);
        if !in_tour || block.info != "sh" {
            continue;
        }
        let mut pending: Option<TourCommand> = None;
        for (line, content) in &block.lines {
            let content = content.trim();
            let (piece, continues) = match content.strip_suffix('\\') {
                Some(piece) => (piece.trim_end(), true),
                None => (content, false),
            };
            let command = match pending.take() {
                Some(mut open) => {
                    open.text.push(' ');
                    open.text.push_str(piece);
                    open
                }
                None => {
                    if piece.is_empty() || piece.starts_with('#') {
                        continue;
                    }
                    TourCommand {
                        line: *line,
                        text: piece.to_string(),
                    }
                }
            };
            if continues {
                pending = Some(command);
            } else {
                commands.push(command);
            }
        }
        if let Some(open) = pending {
            commands.push(open);
        }
    }
    commands
}

/// Runs `commands` in `dir`, `cargo run --release --` as `bin`; the first failure as a
/// message naming the command, its README line, its exit status and its stderr.
fn run_tour(commands: &[TourCommand], dir: &Path, bin: &str) -> Result<(), String> {
    for command in commands {
        let text = command.text.replace(CARGO_RUN, &format!("'{bin}'"));
        if text.split_whitespace().any(|word| word == "cargo") {
            return Err(format!(
                "README line {}: `{}` runs cargo in a way the tour test does not map (only `{CARGO_RUN}` is the binary)",
                command.line, command.text
            ));
        }
        let output = Command::new("sh")
            .arg("-c")
            .arg(&text)
            .current_dir(dir)
            .stdin(std::process::Stdio::null())
            .output()
            .map_err(|e| format!("README line {}: cannot start sh: {e}", command.line))?;
        if !output.status.success() {
            return Err(format!(
                "README line {}: `{}` failed ({}); stderr:\n{}",
                command.line,
                command.text,
                output.status,
                String::from_utf8_lossy(&output.stderr)
            ));
        }
    }
    Ok(())
}

/// A temporary folder laid out as the tour expects: `examples/` reachable as in a checkout.
fn tour_folder() -> tempfile::TempDir {
    let dir = tempfile::tempdir().expect("a temporary folder");
    std::os::unix::fs::symlink(repo().join("examples"), dir.path().join("examples"))
        .expect("examples/ linked into the tour's folder");
    dir
}

#[test]
fn every_shell_command_of_the_readme_tour_runs() {
    let readme = std::fs::read_to_string(repo().join("README.md")).expect("README.md");
    let commands = tour_commands(&readme);
    // The tour simulates, inspects, builds a layout and sweeps: fewer commands than that
    // means the marks or the blocks were lost, and nothing would be tested.
    assert!(
        commands.len() >= 5,
        "the README's tour has {} shell commands between its <!-- tour --> marks: {commands:?}",
        commands.len()
    );
    for needed in ["simulate", "inspect", "layout"] {
        assert!(
            commands
                .iter()
                .any(|c| c.text.starts_with(&format!("{CARGO_RUN} {needed}"))),
            "the README's tour no longer runs `{needed}`"
        );
    }
    let dir = tour_folder();
    if let Err(failure) = run_tour(&commands, dir.path(), BIN) {
        panic!("{failure}");
    }
    // What the tour promises to leave behind for the next steps (Foxglove, Python).
    for file in [
        "my.toml",
        "my.mcap",
        "trucks.mcap",
        "trucks.json",
        "layout.json",
    ] {
        let path = dir.path().join(file);
        let size = std::fs::metadata(&path).map(|m| m.len()).unwrap_or(0);
        assert!(size > 0, "the tour left no {file} (or an empty one)");
    }
}

/// The extraction and the runner on a made-up README: only `sh` blocks inside the marks,
/// continuations joined, and a failing command named with its line.
#[test]
fn the_tour_runner_names_the_command_that_fails() {
    let text = "```sh\nnot-in-the-tour\n```\n\
                <!-- tour: a made-up one -->\n\
                ```sh\n# a comment\ncargo run --release -- scenario show \\\n  > my.toml\n\n\
                cargo run --release -- simulate --no-such-flag\n```\n\
                ```python\nprint(1)\n```\n\
                <!-- /tour -->\n";
    let commands = tour_commands(text);
    assert_eq!(
        commands,
        [
            TourCommand {
                line: 7,
                text: "cargo run --release -- scenario show > my.toml".to_string()
            },
            TourCommand {
                line: 10,
                text: "cargo run --release -- simulate --no-such-flag".to_string()
            },
        ]
    );
    let dir = tour_folder();
    let failure = run_tour(&commands, dir.path(), BIN).expect_err("an unknown flag fails");
    assert!(
        failure
            .starts_with("README line 10: `cargo run --release -- simulate --no-such-flag` failed"),
        "{failure}"
    );
    assert!(
        failure.contains("--no-such-flag"),
        "stderr is shown: {failure}"
    );
    assert!(dir.path().join("my.toml").exists(), "the first command ran");
    let recursive = [TourCommand {
        line: 1,
        text: "cargo test --release".to_string(),
    }];
    let refused = run_tour(&recursive, dir.path(), BIN).expect_err("cargo test is not run");
    assert!(refused.contains("does not map"), "{refused}");
}
