#!/usr/bin/env python3
"""Threads running bridgetwin.simulate at once: the run holds no GIL, so a
concurrent.futures pool of N threads runs N simulations on N cores.

    python python/benches/pool_scaling.py [--runs 8] [--duration-s 300] [--out out/pool]

Runs the same batch (``--runs`` simulations of ``--scenario``, by default
examples/hour_of_traffic.toml, each
``--duration-s`` long, different seeds, written to files) with 1, 2, 3 and 4 worker
threads, and writes ``pool_scaling.csv`` and ``pool_scaling.svg`` (wall time and speed-up
against the number of threads, the cores kept busy, and the bound a pool can reach: a
run already keeps more than one core busy, its output being encoded and compressed on a
thread of its own).
"""

from __future__ import annotations

import argparse
import csv
import os
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import bridgetwin

REPO = Path(__file__).resolve().parents[2]


def batch(workers: int, runs: int, duration_s: float, folder: Path, scenario: Path) -> float:
    def one(seed: int):
        return bridgetwin.simulate(scenario, out=folder / f"w{workers}-s{seed}.mcap", seed=seed, duration_s=duration_s, force=True)

    started, cpu = time.perf_counter(), time.process_time()
    with ThreadPoolExecutor(max_workers=workers) as pool:
        list(pool.map(one, range(runs)))
    return time.perf_counter() - started, time.process_time() - cpu


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--runs", type=int, default=8)
    p.add_argument("--duration-s", type=float, default=300.0)
    p.add_argument("--out", type=Path, default=Path("out/pool_scaling"))
    p.add_argument("--scenario", type=Path, default=REPO / "examples" / "hour_of_traffic.toml")
    args = p.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    cores = os.cpu_count() or 1
    rows = []
    with tempfile.TemporaryDirectory(prefix="bridgetwin-pool-") as tmp:
        batch(1, 1, args.duration_s, Path(tmp), args.scenario)  # warm the page cache and the allocator
        for workers in (1, 2, 3, 4):
            wall, cpu = batch(workers, args.runs, args.duration_s, Path(tmp), args.scenario)
            rows.append(
                dict(
                    threads=workers, wall_s=round(wall, 2), cpu_s=round(cpu, 2),
                    cores_busy=round(cpu / wall, 2), runs=args.runs, duration_s=args.duration_s,
                )
            )
            print(rows[-1], flush=True)
    # One run already keeps `cores_busy` of the first row busy (its output is encoded and
    # compressed on a thread of its own): the pool can at best fill the machine.
    per_run = rows[0]["cores_busy"]
    for row in rows:
        row["speedup"] = round(rows[0]["wall_s"] / row["wall_s"], 2)
        row["bound"] = round(min(row["threads"], cores / per_run), 2)
    with open(args.out / "pool_scaling.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    threads = [r["threads"] for r in rows]
    fig, (a, b) = plt.subplots(1, 2, figsize=(10, 4), constrained_layout=True)
    a.bar(threads, [r["wall_s"] for r in rows], color="tab:blue")
    a.set_xlabel("threads in the pool")
    a.set_ylabel(f"wall time of {args.runs} runs (s)")
    b.plot(threads, [r["speedup"] for r in rows], "o-", label="measured")
    b.plot(threads, [r["bound"] for r in rows], "k--", linewidth=1,
           label=f"bound: {cores} cores / {per_run:g} cores per run")
    b.plot(threads, [r["cores_busy"] for r in rows], "s:", color="tab:green", label="cores busy (CPU time / wall)")
    b.set_xlabel("threads in the pool")
    b.set_ylabel("speed-up over 1 thread; cores busy")
    b.legend()
    fig.suptitle(
        f"bridgetwin.simulate in a ThreadPoolExecutor: {args.runs} x {args.duration_s:g} s of "
        f"{args.scenario.name}, {cores} cores",
        fontsize=10,
    )
    fig.savefig(args.out / "pool_scaling.svg")
    print(f"wrote {args.out / 'pool_scaling.csv'} and {args.out / 'pool_scaling.svg'}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
