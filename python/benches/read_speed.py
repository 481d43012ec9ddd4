#!/usr/bin/env python3
"""Read speed and memory of ``bridgetwin.read`` against ``tools/read_run.py``'s
``load_run`` on the same files, and the time of the overview plot.

    python python/benches/read_speed.py --make out/bench   # simulates the hour example in
                                                           # both layouts first (~minutes)
    python python/benches/read_speed.py RUN.mcap [RUN2.mcap ...] [--skip-script]

Each measurement runs in its own process (peak memory is the process's max RSS less its
RSS after the imports). For every file it prints, and writes to ``read_speed.csv`` beside
the first file (or in --make's folder): the sensor topics' messages, rows and seconds of
data; the seconds and peak memory of each reader; messages per second; seconds per hour
of data; the speed ratio; the package's peak memory over the bytes of the arrays it
returns; and the seconds of ``bridgetwin.plot.overview`` on the run read whole.
"""

from __future__ import annotations

import argparse
import csv
import json
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]

CHILD = r"""
import json, resource, sys, time
sys.path.insert(0, {tools!r})
def rss():
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) * 1024
import numpy as np
mode, path = sys.argv[1], sys.argv[2]
if mode == "script":
    import read_run
else:
    import bridgetwin, bridgetwin.plot, matplotlib
    matplotlib.use("Agg")
base = rss()
started = time.perf_counter()
if mode == "script":
    arrays = read_run.load_run(path)
    nbytes = sum(a.nbytes for cols in arrays.values() for a in cols.values())
    rows = sum(len(cols["log_time_ns"]) for cols in arrays.values())
    seconds = time.perf_counter() - started
elif mode == "package":
    run = bridgetwin.read(path, topics="/sensors/*")
    nbytes = int(sum(f.memory_usage(index=False, deep=True).sum() for f in run.values()))
    rows = sum(len(f) for f in run.values())
    seconds = time.perf_counter() - started
else:
    run = bridgetwin.read(path)
    read_s = time.perf_counter() - started
    fig = bridgetwin.plot.overview(run, out=sys.argv[3])
    nbytes, rows = 0, 0
    seconds = time.perf_counter() - started
peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
print(json.dumps(dict(seconds=seconds, peak_bytes=peak - base, array_bytes=nbytes, rows=rows)))
"""


def measure(mode: str, path: Path, extra: list[str] | None = None) -> dict:
    code = CHILD.format(tools=str(REPO / "tools"))
    out = subprocess.run(
        [sys.executable, "-c", code, mode, str(path), *(extra or [])],
        capture_output=True, text=True, check=True,
    )
    return json.loads(out.stdout.strip().splitlines()[-1])


def sensor_messages(path: Path) -> tuple[int, float]:
    """Messages on the /sensors/ topics and the seconds of data, from `bridgetwin inspect`."""
    report = json.loads(
        subprocess.run(
            [str(REPO / "target/release/bridgetwin"), "inspect", str(path), "--json"],
            capture_output=True, text=True, check=True,
        ).stdout
    )
    messages = sum(c["message_count"] for c in report["channels"] if c["topic"].startswith("/sensors/"))
    return messages, float(report["duration_s"])


def make(folder: Path) -> list[Path]:
    folder.mkdir(parents=True, exist_ok=True)
    example = REPO / "examples/hour_of_traffic.toml"
    sample = folder / "hour_sample.toml"
    text = example.read_text().replace('layout = "block"', 'layout = "sample"')
    sample.write_text(text.replace("#:schema ../docs/", f"#:schema {REPO}/docs/"))
    made = []
    for scenario, name in ((example, "hour_block"), (sample, "hour_sample")):
        out = folder / f"{name}.mcap"
        subprocess.run(
            [str(REPO / "target/release/bridgetwin"), "simulate", str(scenario), "--out", str(out), "--force", "--quiet"],
            check=True,
        )
        made.append(sorted(folder.glob(f"{name}*.mcap"))[0])
    return made


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("files", nargs="*", type=Path)
    p.add_argument("--make", type=Path, help="simulate the hour example in both layouts into this folder first")
    p.add_argument("--skip-script", action="store_true", help="time only the package")
    args = p.parse_args()
    files = list(args.files) + (make(args.make) if args.make else [])
    if not files:
        p.error("give run files or --make FOLDER")
    rows = []
    for path in files:
        messages, data_s = sensor_messages(path)
        package = min((measure("package", path) for _ in range(3)), key=lambda r: r["seconds"])
        script = None if args.skip_script else measure("script", path)
        overview = measure("overview", path, [str(path.with_suffix(".overview.png"))])
        row = dict(
            file=path.name, sensor_messages=messages, data_s=round(data_s, 1), rows=package["rows"],
            package_s=round(package["seconds"], 3), package_peak_mb=round(package["peak_bytes"] / 1e6, 1),
            array_mb=round(package["array_bytes"] / 1e6, 1),
            peak_over_arrays=round(package["peak_bytes"] / package["array_bytes"], 2),
            package_msgs_per_s=round(messages / package["seconds"]),
            package_s_per_hour=round(package["seconds"] * 3600 / data_s, 3),
            overview_s=round(overview["seconds"], 2),
        )
        if script is not None:
            row.update(
                script_s=round(script["seconds"], 2), script_peak_mb=round(script["peak_bytes"] / 1e6, 1),
                script_msgs_per_s=round(messages / script["seconds"]),
                speedup=round(script["seconds"] / package["seconds"], 1),
            )
        rows.append(row)
        print(json.dumps(row), flush=True)
    table = (args.make or files[0].parent) / "read_speed.csv"
    with open(table, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[-1]))
        writer.writeheader()
        writer.writerows(rows)
    print(f"wrote {table}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
