//! Output paths and command-line arguments.

use super::harness::{edited, Case, Edit::Set};

pub(super) fn output_cases() -> Vec<Case> {
    let ok = || edited(&[]).into_bytes();
    vec![
        Case::raw(
            "output folder does not exist",
            ok(),
            &["nodir/run.mcap", "No such file or directory"],
        )
        .writing_to("nodir/run.mcap"),
        Case::raw(
            "output folder not writable",
            ok(),
            &["ro/run.mcap", "Permission denied"],
        )
        .writing_to("ro/run.mcap")
        .folder("ro", 0o555)
        .needs_unwritable("ro"),
        // The same refusal where even root meets it (the case above is skipped as root,
        // and says so): sysfs lets nobody create a file.
        Case::raw(
            "output folder refuses new files (sysfs)",
            ok(),
            &["/sys/bridgetwin-bad-input.mcap", "Permission denied"],
        )
        .writing_to("/sys/bridgetwin-bad-input.mcap"),
        Case::raw(
            "output exists, no --force (kept unchanged)",
            ok(),
            &["run.mcap", "already exists"],
        )
        .file("run.mcap", b"an earlier run: must be kept byte for byte"),
        // /dev/full exists, so without --force the run stops before writing.
        Case::args(
            "output /dev/full",
            &["simulate", "--out", "/dev/full", "--duration-s", "0.5"],
            1,
            &["/dev/full"],
        ),
        // With --force: a device is never replaced by a run.
        Case::args(
            "output /dev/full with --force",
            &[
                "simulate",
                "--out",
                "/dev/full",
                "--force",
                "--duration-s",
                "0.5",
            ],
            1,
            &["/dev/full", "exists and is not a regular file"],
        ),
        Case::raw(
            "output path is a directory",
            ok(),
            &["writing outdir: is a directory"],
        )
        .writing_to("outdir")
        .folder("outdir", 0o755),
        Case::raw(
            "output path is the current directory",
            ok(),
            &["writing .:"],
        )
        .writing_to("."),
        Case::raw(
            "output folder is a file",
            ok(),
            &["afile/run.mcap", "Not a directory"],
        )
        .writing_to("afile/run.mcap")
        .file("afile", b"not a folder"),
        // A file system stand-in with 1000 bytes free (a test cannot fill a disk): the
        // half-second run's estimate, about 100 KiB, does not fit. The message names the
        // estimate, the free space, the folder and the flag that overrides it.
        Case::raw(
            "an estimate beyond the free space",
            ok(),
            &[
                "refusing to write run.mcap",
                "estimated size",
                "KiB",
                "exceeds the 1000 B free",
                "output folder .",
                "--skip-space-check",
            ],
        )
        .env("BRIDGETWIN_FREE_SPACE_BYTES", "1000"),
        Case::raw(
            "an estimate beyond the free space of the output's folder",
            ok(),
            &[
                "refusing to write sub/run.mcap",
                "output folder sub",
                "1000 B free",
            ],
        )
        .writing_to("sub/run.mcap")
        .folder("sub", 0o755)
        .env("BRIDGETWIN_FREE_SPACE_BYTES", "1000"),
        Case::raw(
            "free-space stand-in not a number",
            ok(),
            &[
                "BRIDGETWIN_FREE_SPACE_BYTES",
                "\"lots\"",
                "whole number of bytes",
            ],
        )
        .env("BRIDGETWIN_FREE_SPACE_BYTES", "lots"),
    ]
}

pub(super) fn cli_cases() -> Vec<Case> {
    let sim = |extra: &[&'static str]| -> Vec<&'static str> {
        let mut a = vec!["simulate", "--out", "run.mcap"];
        a.extend_from_slice(extra);
        a
    };
    vec![
        Case::args(
            "unknown flag",
            &sim(&["--bogus", "--duration-s", "0.5"]),
            2,
            &["--bogus"],
        ),
        Case::args(
            "--seed not a number",
            &sim(&["--seed", "abc", "--duration-s", "0.5"]),
            2,
            &["--seed", "'abc'"],
        ),
        Case::args(
            "--seed negative",
            &sim(&["--seed=-1", "--duration-s", "0.5"]),
            2,
            &["--seed", "'-1'"],
        ),
        Case::args(
            "--seed beyond u64",
            &sim(&["--seed", "18446744073709551616", "--duration-s", "0.5"]),
            2,
            &["--seed", "18446744073709551616"],
        ),
        // clap takes `-1` after a flag for another flag: a usage error naming `-1` but not
        // `--duration-s`. With `allow_negative_numbers` on the argument it becomes the
        // validation error `duration_s = -1` (exit 1), the alternative accepted here.
        Case::args(
            "--duration-s -1",
            &sim(&["--duration-s", "-1"]),
            2,
            &["'-1'"],
        )
        .or_else(1, &["duration_s = -1 "]),
        Case::args(
            "--duration-s=-1",
            &sim(&["--duration-s=-1"]),
            1,
            &["duration_s = -1 must be a finite number > 0"],
        ),
        Case::args(
            "--duration-s nan",
            &sim(&["--duration-s", "nan"]),
            1,
            &["duration_s = NaN must be a finite number > 0"],
        ),
        Case::args(
            "--duration-s inf",
            &sim(&["--duration-s", "inf"]),
            1,
            &["duration_s = inf must be a finite number > 0"],
        ),
        Case::args(
            "--duration-s 0",
            &sim(&["--duration-s", "0"]),
            1,
            &["duration_s = 0 must be a finite number > 0"],
        ),
        Case::args(
            "--duration-s not a number",
            &sim(&["--duration-s", "ten"]),
            2,
            &["--duration-s", "'ten'"],
        ),
        Case::args(
            "--duration-s beyond 30 days",
            &sim(&["--duration-s", "1e7"]),
            1,
            &["duration_s = 10000000 must be at most 30 days"],
        ),
        Case::args(
            "--out missing",
            &["simulate", "--duration-s", "0.5"],
            2,
            &["--out"],
        ),
        Case::args("unknown command", &["frobnicate"], 2, &["'frobnicate'"]),
        Case::raw(
            "scenario check on a bad scenario",
            edited(&[Set("bridge.span_m", "0.0")]).into_bytes(),
            &["bridge.span_m = 0 must be a finite number > 0"],
        )
        .with_args(&["scenario", "check", "scenario.toml"]),
    ]
}
