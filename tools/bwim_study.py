#!/usr/bin/env python3
"""B-WIM study: where bridge weigh-in-motion works on the twin and where it breaks.

    python3 tools/bwim_study.py --out docs/figures/bwim            # about 6 minutes on 2 cores
    python3 tools/bwim_study.py --out /tmp/bwim-study --quick      # fewer variants, no hour

Runs ``bridgetwin simulate`` on variants of ``examples/bwim_calibration.toml`` (the
calibration truck's 16 runs, then ten minutes of two-way traffic), one at a time, and
``tools/bwim_check.py`` on each, and writes ``bwim_study.csv``, SVG figures and ``summary.md``:

- road: smooth, ISO 8608 classes A (the example), B and C, two seeds each;
- traffic speed: lane mean speed 15, 20, 24.7 (the example) and 30 m/s;
- strain noise: the foil gauge's white-noise density times 0.5, 1, 2, 4 and 8;
- multiple presence: 100, 400 (the example), 800 and 1500 vehicles per hour and lane, each
  weighed with multiple presence solved jointly and with it skipped;
- calibration: the same run calibrated on subsets of the truck's runs (one speed, two
  speeds, all eight), and weighed with a group penalty (regularised Moses);
- the calibrated influence lines against the twin's static ones (a 100 kN constant force
  crossing at 2.5 m/s, noise-free truth streams), and the hour of
  ``examples/bwim_hour_of_traffic.toml`` (simulation and processing times, its figure).

Every variant keeps the example's seed unless said, so the variants differ in the one
thing varied. The scores are one realisation of ten minutes of traffic (about 30 trucks):
differences of a few tenths of a percent in a standard deviation are within the sampling
scatter (the relative standard error of a standard deviation from n values is about
1 / sqrt(2 (n - 1)), 13 % for n = 30).

Exit status 0 when the study is written; 2, one line on stderr naming the file, when the
bridgetwin binary (``--bin``) is missing, empty, cut short, not a program or not bridgetwin,
or one of its runs fails (``tools/bad_input.py``); 4 when the tool itself failed.
"""

from __future__ import annotations

import argparse
import contextlib
import csv
import io
import json
import re
import shutil
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(HERE))
import bwim_check  # noqa: E402
from bad_input import check_binary, guard, run_binary  # noqa: E402
from bwim.study_figures import plot_all  # noqa: E402
from bwim.study_summary import write_summary  # noqa: E402

BASE = ROOT / "examples" / "bwim_calibration.toml"
HOUR = ROOT / "examples" / "bwim_hour_of_traffic.toml"
FOIL_NOISE = 0.5 / 500**0.5  # strain_foil white-noise density, microstrain / sqrt(Hz)
HOURLY = 24.0 / 23.0  # the example's profile: no traffic in one hour of 24


def edit(text: str, pattern: str, repl: str, count: int = 1) -> str:
    """text with pattern (a regex, MULTILINE) replaced exactly `count` times."""
    new, n = re.subn(pattern, repl, text, flags=re.MULTILINE)
    if n != count:
        raise ValueError(f"pattern {pattern!r} found {n} times, expected {count}")
    return new


def variant(
    road: str | None = None,
    speed: float | None = None,
    noise: float | None = None,
    flow: float | None = None,
    seed: int | None = None,
) -> str:
    """The example's scenario with one thing changed."""
    t = BASE.read_text()
    if road is not None:
        prof = (
            '{ kind = "smooth" }'
            if road == "smooth"
            else f'{{ kind = "iso8608", class = "{road}", tyre_patch_filter_m = 0.24 }}'
        )
        t = edit(t, r"^profile = .*$", f"profile = {prof}")
    if speed is not None or flow is not None:
        f = (flow if flow is not None else 400.0) / HOURLY
        extra = f", speed_mean_m_s = {speed}" if speed is not None else ""
        t = edit(
            t,
            r"^lanes = .*$",
            f"lanes = [{{ direction = 1, flow_per_hour = {f:.4f}{extra} }}, {{ direction = -1, flow_per_hour = {f:.4f}{extra} }}]",
        )
    if noise is not None:
        t = edit(
            t, r'^preset = "strain_foil"$', f'preset = "strain_foil"\nnoise_density = {noise * FOIL_NOISE:.6g}', count=8
        )
    if seed is not None:
        t = edit(t, r"^seed = .*$", f"seed = {seed}")
    return t


def simulate(bt: str, toml_text: str, work: Path, name: str, log: list) -> tuple[Path, float]:
    scen = work / f"{name}.toml"
    scen.write_text(toml_text)
    out = work / f"{name}.mcap"
    t0 = time.perf_counter()
    run_binary([bt, "simulate", str(scen), "--out", str(out), "--force", "--quiet"])
    dt = time.perf_counter() - t0
    log.append(f"simulated {name} in {dt:.1f} s")
    return out, dt


def check(run: Path, extra: list[str], work: Path, name: str) -> tuple[dict, float, int]:
    """bwim_check on one run (in this process, its report swallowed): its JSON, time, exit."""
    js = work / f"{name}.json"
    t0 = time.perf_counter()
    err = io.StringIO()
    if js.exists():
        js.unlink()
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(err):
        code = guard("bwim_check", bwim_check.main, [str(run), "--json", str(js), *extra])
    dt = time.perf_counter() - t0
    if code not in (0, 1) or not js.exists():
        return {"error": err.getvalue().strip().replace("bwim_check: ", "")}, dt, code
    return json.loads(js.read_text()), dt, code


def row_of(group: str, label: str, x, res: dict, sim_s: float, check_s: float, extra: dict | None = None) -> dict:
    r = {"group": group, "variant": label, "x": x, "sim_s": round(sim_s, 2), "check_s": round(check_s, 2)}
    r.update(extra or {})
    if "error" in res:
        r["failed"] = 1
        r["note"] = res["error"]
        return r
    r.update(
        trucks=res["truth_over_3_5t"],
        detected=res["detected_over_3_5t"],
        scored=res["scored"],
        missed=res["missed"],
        poor_fit=res.get("poor_fit", 0),
        axle_count_right=res["axle_count_right"],
        mp_events=res["multiple_presence_events"],
        scored_in_mp=res["scored_in_multiple_presence"],
        speed_error_mean_pct=100 * float(np.mean([v["speed_error"] for v in res["vehicles"]])),
        speed_error_sd_pct=100 * float(np.std([v["speed_error"] for v in res["vehicles"]])),
    )
    for key, name in (
        ("gross", "gross"),
        ("group of axles", "group"),
        ("single axle", "single"),
        ("axle of a group", "axle_of_group"),
    ):
        c = res["criteria"][key]
        r[f"{name}_n"] = c["n"]
        r[f"{name}_mean_pct"] = None if c["mean_pct"] is None else round(c["mean_pct"], 3)
        r[f"{name}_sd_pct"] = None if c["std_pct"] is None else round(c["std_pct"], 3)
        r[f"{name}_delta_min_pct"] = None if c.get("delta_min_pct") is None else round(c["delta_min_pct"], 3)
        r[f"{name}_class"] = c.get("class_reached")
    loo = res.get("calibration_leave_one_out")
    if loo:
        r["cal_loo_gross_sd_pct"] = round(loo["gross"]["std_pct"], 3)
    return r


def static_influence_lines(bt: str, work: Path, log: list) -> tuple[dict, float]:
    """The twin's static strain influence lines of the weighing sections: a 100 kN constant
    force crossing at 2.5 m/s, read from the noise-free truth streams."""
    import tomllib

    t = BASE.read_text()
    head = t[: t.index("# No traffic")]
    sensors = t[t.index("# Strain gauges") :]
    head = edit(head, r"^duration_s = .*$", "duration_s = 60.0")
    scen = (
        head
        + '\n[[vehicles]]\nid = 1\nmodel = { kind = "moving_force", axle_loads_n = [100000.0] }\nspeed_m_s = 2.5\n\n'
        + sensors
    )
    run, dt = simulate(bt, scen, work, "static_il", log)
    spec = tomllib.loads(scen)
    approach = spec["road"]["approach_m"]
    span = spec["bridge"]["span_m"]
    gauges = {
        s["id"]: s["position_m"]
        for s in spec["sensors"]
        if s["kind"] == "strain" and 1.0 < s["position_m"] < span - 1.0
    }
    bt_mod = bwim_check._reader()
    topics = [f"/truth/sensors/{g}" for g in gauges]
    if bt_mod is not None:
        data = bt_mod.read(str(run), topics=topics)
        series = {
            g: (
                data[f"/truth/sensors/{g}"]["time_s"].to_numpy(),
                data[f"/truth/sensors/{g}"]["strain_microstrain"].to_numpy(),
            )
            for g in gauges
        }
    else:
        from read_run import load_topics

        data = load_topics(str(run), topics)
        series = {
            g: (
                np.asarray(data[f"/truth/sensors/{g}"]["time_s"]),
                np.asarray(data[f"/truth/sensors/{g}"]["strain_microstrain"]),
            )
            for g in gauges
        }
    out = {}
    for pos in sorted(set(gauges.values())):
        ids = [g for g, p in gauges.items() if p == pos]
        tt = series[ids[0]][0]
        e = np.mean([series[g][1] for g in ids], axis=0)
        out[float(pos)] = (tt * 2.5 - approach, e / 100.0)  # s (m), microstrain per kN
    return out, dt


def main(argv: list[str]) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--out", required=True, help="folder for the CSV, the figures and summary.md")
    p.add_argument("--bin", default=None, help="bridgetwin binary (default: target/release/bridgetwin, else on PATH)")
    p.add_argument("--work", default=None, help="folder for the runs (default: a temporary one, removed)")
    p.add_argument("--quick", action="store_true", help="fewer variants and no hour (a smoke test)")
    args = p.parse_args(argv)
    bt = args.bin or (
        str(ROOT / "target/release/bridgetwin")
        if (ROOT / "target/release/bridgetwin").exists()
        else shutil.which("bridgetwin")
    )
    if not bt:
        print("bwim_study: no bridgetwin binary (--bin)", file=sys.stderr)
        return 2
    bt = check_binary(bt)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    tmp = None
    if args.work:
        work = Path(args.work)
        work.mkdir(parents=True, exist_ok=True)
    else:
        tmp = tempfile.TemporaryDirectory(prefix="bwim-study-")
        work = Path(tmp.name)
    t_start = time.perf_counter()
    log: list[str] = []
    rows: list[dict] = []
    try:
        # Baseline: the example as it is; its calibration is kept for the figures.
        base_run, base_sim = simulate(bt, BASE.read_text(), work, "base", log)
        res, dt, _ = check(base_run, ["--save-calibration", str(work / "base_cal.json")], work, "base")
        base_row = row_of("road", "A (example)", "A", res, base_sim, dt, {"seed": "example"})
        rows.append(base_row)
        cal = json.loads((work / "base_cal.json").read_text())
        # Calibration subsets and regularised Moses, on the baseline run.
        subsets = [
            ("one speed, 15 m/s", "1,2"),
            ("one speed, 25 m/s", "11,12"),
            ("one speed, 29 m/s", "15,16"),
            ("two speeds, 15 and 29 m/s", "1,2,15,16"),
            ("eight speeds (example)", None),
        ]
        if args.quick:
            subsets = subsets[1:2] + subsets[-1:]
        for label, ids in subsets:
            extra = ["--calibration-ids", ids] if ids else []
            res, dt, _ = check(base_run, extra, work, "cal_" + re.sub(r"[^A-Za-z0-9]+", "_", label))
            rows.append(row_of("calibration", label, label, res, 0.0, dt))
        res, dt, _ = check(base_run, ["--group-penalty", "0.1"], work, "penalty")
        rows.append(row_of("calibration", "eight speeds, group penalty 0.1", "penalty", res, 0.0, dt))
        # Road roughness (two seeds).
        roads = ["smooth", "B", "C"] if not args.quick else ["C"]
        for road in roads:
            r_run, s = simulate(bt, variant(road=road), work, f"road_{road}", log)
            res, dt, _ = check(r_run, [], work, f"road_{road}")
            rows.append(row_of("road", road, road, res, s, dt, {"seed": "example"}))
        if not args.quick:
            for road in ["smooth", "A", "B", "C"]:
                r_run, s = simulate(bt, variant(road=road, seed=7), work, f"road_{road}_s7", log)
                res, dt, _ = check(r_run, [], work, f"road_{road}_s7")
                rows.append(row_of("road", f"{road} (seed 7)", road, res, s, dt, {"seed": 7}))
        # Traffic speed.
        speeds = [15.0, 20.0, 30.0] if not args.quick else [30.0]
        rows.append({**base_row, "group": "speed", "variant": "24.7 m/s (example)", "x": 24.72})
        for v in speeds:
            r_run, s = simulate(bt, variant(speed=v), work, f"speed_{v:g}", log)
            res, dt, _ = check(r_run, [], work, f"speed_{v:g}")
            rows.append(row_of("speed", f"{v:g} m/s", v, res, s, dt))
        # Strain noise.
        noises = [0.5, 2.0, 4.0, 8.0] if not args.quick else [4.0]
        rows.append({**base_row, "group": "noise", "variant": "x1 (foil gauge)", "x": 1.0})
        for k in noises:
            r_run, s = simulate(bt, variant(noise=k), work, f"noise_{k:g}", log)
            res, dt, _ = check(r_run, [], work, f"noise_{k:g}")
            rows.append(row_of("noise", f"x{k:g}", k, res, s, dt))
        # Multiple presence: flows, joint and skipped.
        flows = [100.0, 400.0, 800.0, 1500.0] if not args.quick else [400.0, 1500.0]
        for f in flows:
            if f == 400.0:
                f_run, s = base_run, base_sim
            else:
                f_run, s = simulate(bt, variant(flow=f), work, f"flow_{f:g}", log)
            for mode in ("joint", "skip"):
                res, dt, _ = check(f_run, ["--multiple-presence", mode], work, f"flow_{f:g}_{mode}")
                rows.append(
                    row_of(
                        "flow", f"{f:g} veh/h/lane, {mode}", f, res, s if mode == "joint" else 0.0, dt, {"mode": mode}
                    )
                )
        # The twin's static influence lines.
        il_static, _ = static_influence_lines(bt, work, log)
        # The hour.
        hour = {}
        if not args.quick:
            h_run, h_sim = simulate(bt, HOUR.read_text(), work, "hour", log)
            res, dt, code = check(h_run, ["--plot", str(out / "hour.svg"), "--expect-class", "B+(7)"], work, "hour")
            hour = {"sim_s": h_sim, "check_s": dt, "exit": code, "res": res}
            rows.append(row_of("hour", "hour of traffic (example)", "hour", res, h_sim, dt))
    except BaseException:
        if tmp is not None:
            tmp.cleanup()
        raise
    total = time.perf_counter() - t_start
    # CSV.
    keys = []
    for r in rows:
        for k in r:
            if k not in keys:
                keys.append(k)
    with open(out / "bwim_study.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys)
        w.writeheader()
        for r in rows:
            w.writerow(r)
    figures = plot_all(rows, out, il_static, cal)
    # IL agreement: rms difference from the static line, relative to its peak.
    il_err = {}
    s = np.array(cal["s_grid_m"])
    for c, pos in enumerate(cal["sections_m"]):
        ref = il_static.get(float(pos))
        if ref is not None:
            for d in ("1", "-1"):
                il = np.array(cal["il_microstrain_per_kn"][d])[c]
                xs = s if d == "1" else cal["span_m"] - s
                refi = np.interp(xs, ref[0], ref[1], left=0.0, right=0.0)
                il_err[(pos, d)] = (
                    float(np.sqrt(np.mean((il - refi) ** 2)) / refi.max()),
                    float(il.sum() / refi.sum() - 1.0),
                )
    write_summary(out, rows, figures, il_err, hour, total, log, bt, args.quick)
    if tmp is not None:
        tmp.cleanup()
    print(f"bwim_study: {len(rows)} rows, {len(figures)} figures, summary.md in {out} ({total:.0f} s)")
    return 0


if __name__ == "__main__":
    sys.exit(guard("bwim_study", main, sys.argv[1:]))
