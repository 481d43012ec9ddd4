#!/usr/bin/env python3
"""How long Python waits on a running simulation: the longest gap between the turns of a
thread that keeps running Python while ``bridgetwin.simulate`` goes on another, and how
soon Ctrl-C stops a run.

    python python/benches/gil_and_stop.py [--repeat 3] [--out out/gil_and_stop.csv]

The package's tests (python/tests/test_simulate.py) check the behaviour: the other thread
gets turns during the run, Ctrl-C ends it with a ``.partial``. The times are the
machine's, so they are measured here and not asserted there. What to expect:

- the longest gap stays near Python's switch interval (5 ms) plus the sleep (1 ms) and
  the scheduler's latency on a loaded machine; a run holding the GIL would show one gap
  as long as the whole run (the ratio ``max_gap_s / run_s`` near 1);
- Ctrl-C stops the run at its next step and closes the file (summary and all): well
  under a second on an idle machine, the close's fsync included.
"""

from __future__ import annotations

import argparse
import csv
import signal
import subprocess
import sys
import tempfile
import textwrap
import threading
import time
from pathlib import Path

import bridgetwin

REPO = Path(__file__).resolve().parents[2]


def gil_gaps(folder: Path, duration_s: float) -> tuple[float, float, int]:
    """(run's wall seconds, longest gap between this thread's turns, turns) while the
    hour example's first `duration_s` run on another thread."""
    done = threading.Event()

    def work():
        bridgetwin.simulate(
            REPO / "examples" / "hour_of_traffic.toml", out=folder / "gil.mcap", duration_s=duration_s, force=True
        )
        done.set()

    worker = threading.Thread(target=work)
    started = time.perf_counter()
    worker.start()
    gaps, ticks, last = [], 0, time.perf_counter()
    while not done.is_set():
        now = time.perf_counter()
        gaps.append(now - last)
        last = now
        ticks += 1
        time.sleep(0.001)
    worker.join()
    return time.perf_counter() - started, max(gaps, default=0.0), ticks


def stop_latency(folder: Path) -> float:
    """Seconds from SIGINT to the exit of a process running a long simulation."""
    out = folder / "long.mcap"
    script = textwrap.dedent(
        f"""
        import signal, sys, bridgetwin
        signal.signal(signal.SIGINT, signal.default_int_handler)
        print("started", flush=True)
        try:
            bridgetwin.simulate(out={str(out)!r}, duration_s=100000.0, skip_space_check=True, force=True)
        except KeyboardInterrupt:
            sys.exit(130)
        """
    )
    (folder / "long.mcap.partial").unlink(missing_ok=True)
    child = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, text=True)
    assert child.stdout.readline().strip() == "started"
    time.sleep(2.0)
    sent = time.perf_counter()
    child.send_signal(signal.SIGINT)
    child.communicate(timeout=120)
    took = time.perf_counter() - sent
    if child.returncode != 130:
        raise SystemExit(f"the interrupted run exited {child.returncode}, not 130")
    return took


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--repeat", type=int, default=3, help="measurements of each (3)")
    p.add_argument("--duration-s", type=float, default=600.0, help="simulated seconds of the GIL run (600)")
    p.add_argument("--out", help="write the measurements here (CSV)")
    args = p.parse_args()
    rows = []
    with tempfile.TemporaryDirectory(prefix="gil-and-stop-") as tmp:
        folder = Path(tmp)
        for k in range(args.repeat):
            run_s, gap_s, ticks = gil_gaps(folder, args.duration_s)
            stop_s = stop_latency(folder)
            rows.append({"repeat": k, "run_s": run_s, "max_gap_s": gap_s, "gap_over_run": gap_s / run_s,
                         "turns": ticks, "stop_after_sigint_s": stop_s})
            print(
                f"run {run_s:.2f} s, longest gap {1e3 * gap_s:.1f} ms ({100 * gap_s / run_s:.2f} % of the run, "
                f"{ticks} turns); Ctrl-C stopped the run in {stop_s:.3f} s",
                flush=True,
            )
    if args.out:
        Path(args.out).parent.mkdir(parents=True, exist_ok=True)
        with open(args.out, "w", newline="") as f:
            writer = csv.DictWriter(f, fieldnames=list(rows[0]))
            writer.writeheader()
            writer.writerows(rows)
    return 0


if __name__ == "__main__":
    sys.exit(main())
