#!/usr/bin/env python3
"""Check that two runs carry the same sensor data, e.g. the block and the per-sample
layout of one scenario and seed:

    python3 tools/compare_runs.py block.mcap sample.mcap

Loads every /sensors/ and /truth/sensors/ topic of both files with read_run.py and
compares the values exactly and the time stamps to 1 us: a block carries its first
sample's time and the period rounded to whole ns, so at rates whose period is not a
whole number of ns (300 Hz) the times it implies drift from the per-sample stamps by up
to block_samples / 2 ns (16 ns for 50 samples at 300 Hz).

Exit code 0 when the sensor data are identical; 1 on any difference, on a file damaged
inside (flipped bytes), or when the files have no sensor topic at all (there is nothing to
compare, so nothing is shown to be equal); 2, one line on stderr naming the file, when a
file cannot be compared: no such file, empty, not an MCAP file, truncated (it ends
without the MCAP footer: a killed run's .partial, a copy cut short; tools/bad_input.py);
4 when the tool itself failed."""

from __future__ import annotations

import sys

from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bad_input import check_mcap, guard  # noqa: E402
from read_run import Damage, load_run  # noqa: E402

PREFIXES = ("/sensors/", "/truth/sensors/")
# Allowed difference of the time columns (see the module note), in their units.
TIME_TOLERANCE = {"log_time_ns": 1000, "timestamp_ns": 1000, "time_s": 1e-6}


def compare(path_a: str, path_b: str) -> list[str]:
    """Differences between the sensor arrays of two runs (empty when identical)."""
    damage_a, damage_b = Damage(), Damage()
    a, b = load_run(path_a, PREFIXES, damage_a), load_run(path_b, PREFIXES, damage_b)
    problems = [f"{path} is damaged: {'; '.join(d.problems)}" for path, d in ((path_a, damage_a), (path_b, damage_b)) if d]
    if not a and not b:
        problems.append(f"neither file has a topic under {', '.join(PREFIXES)}: nothing to compare")
    if sorted(a) != sorted(b):
        problems.append(f"topics differ: {sorted(set(a) ^ set(b))}")
    for topic in sorted(set(a) & set(b)):
        # Block messages have extra per-message fields (quantity, unit, period): compare
        # the columns both layouts share.
        for column in sorted(set(a[topic]) & set(b[topic])):
            if column in ("sensor_id",):
                continue
            x, y = a[topic][column], b[topic][column]
            tolerance = TIME_TOLERANCE[column] if column in TIME_TOLERANCE else 0
            if x.shape != y.shape or not np.allclose(x, y, rtol=0, atol=tolerance):
                problems.append(f"{topic} {column}: {x.shape} vs {y.shape}")
        if "log_time_ns" not in a[topic] or len(a[topic]["log_time_ns"]) == 0:
            problems.append(f"{topic}: no samples")
    return problems


def main(argv: list[str]) -> int:
    if len(argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    for path in argv[1:]:
        check_mcap(path)  # BadInput: one line, exit 2 (guard below)
    try:
        problems = compare(argv[1], argv[2])
    except Exception as e:  # noqa: BLE001 - a file the readers cannot read is a difference
        problems = [f"cannot be read: {type(e).__name__}: {e}"]
    for p in problems:
        print(f"DIFF {p}")
    if not problems:
        print(f"OK {argv[1]} and {argv[2]} carry identical sensor data")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(guard("compare_runs", main, sys.argv))
