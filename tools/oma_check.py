#!/usr/bin/env python3
"""Operational modal analysis of a bridgetwin run, scored against the run's own truth.

    python3 tools/oma_check.py run.mcap                   # SSI-cov and FDD, modes 1-2
    python3 tools/oma_check.py run.mcap --modes 3 --tol 0.01 --json oma.json

What it does, as a monitoring engineer would with a real installation's files:

1. reads every accelerometer topic (``/sensors/accel/*``, per-sample or block layout) into
   one array ``data[n_samples, n_channels]``, placing each sample by the DAQ's own stamp
   (the ``timestamp`` field: the node clock, not the true time) on the nominal grid;
   samples a fault lost are filled by linear interpolation and counted;
2. runs pyoma2 (``pip install pyoma-2``): covariance-driven stochastic subspace
   identification (``SSI`` with ``method="cov"``) and frequency-domain decomposition
   (``FDD``) on the whole record;
3. picks, for each true mode below 0.4 x the sample rate (the anti-alias pass band), the
   identified pole nearest to it (pyoma2's ``mpe`` with ``sel_freq`` = the true
   frequencies; a pole farther than ``rtol`` is not found), and compares frequency and
   damping with ``/truth/bridge`` (the modal state written at t = 0).

Exit status 0 when every scored mode's SSI frequency is within ``--tol`` (relative) of the
truth, 1 otherwise, 2 on bad input. Damping is reported, not scored: its estimate from
short ambient records scatters by tens of percent.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from read_run import list_topics, load_topics  # noqa: E402

ACCEL_PREFIX = "/sensors/accel/"
TRUTH_BRIDGE = "/truth/bridge"


def load_accelerations(path: str, start_s: float = 0.0, end_s: float | None = None):
    """(data[n, c], fs_hz, channel names, samples filled) from the accelerometer topics."""
    topics = sorted(t for t in list_topics(path) if t.startswith(ACCEL_PREFIX))
    if not topics:
        raise ValueError(f"{path}: no accelerometer topics ({ACCEL_PREFIX}*)")
    arrays = load_topics(path, topics)
    stamps, values = [], []
    for topic in topics:
        a = arrays[topic]
        stamps.append(np.asarray(a["timestamp_ns"], dtype=np.int64))
        values.append(np.asarray(a["acceleration_m_s2"], dtype=float))
    periods = [np.median(np.diff(s)) for s in stamps if len(s) > 1]
    if not periods:
        raise ValueError(f"{path}: too few samples to find the sample rate")
    period_ns = float(np.median(periods))
    fs_hz = 1e9 / period_ns
    t0 = min(int(s[0]) for s in stamps)
    index = [np.rint((s - t0) / period_ns).astype(np.int64) for s in stamps]
    first = max(int(i[0]) for i in index)
    last = min(int(i[-1]) for i in index)
    first = max(first, int(np.ceil(start_s * fs_hz)))
    if end_s is not None:
        last = min(last, int(np.floor(end_s * fs_hz)))
    if last - first < 100:
        raise ValueError(f"{path}: fewer than 100 common samples in the chosen window")
    grid = np.arange(first, last + 1)
    data = np.empty((len(grid), len(topics)))
    filled = 0
    for c, (i, v) in enumerate(zip(index, values)):
        i, keep = np.unique(i, return_index=True)
        v = v[keep]
        inside = (i >= first) & (i <= last)
        filled += len(grid) - int(inside.sum())
        data[:, c] = np.interp(grid, i, v)
    names = [t[len(ACCEL_PREFIX):] for t in topics]
    return data, fs_hz, names, filled


def truth_modes(path: str) -> tuple[np.ndarray, np.ndarray]:
    """True natural frequencies (Hz) and damping ratios from the run's modal state."""
    bridge = load_topics(path, [TRUTH_BRIDGE])[TRUTH_BRIDGE]
    freqs = bridge.get("natural_frequency_hz")
    zetas = bridge.get("damping_ratio")
    if freqs is None or len(freqs) == 0:
        raise ValueError(f"{path}: {TRUTH_BRIDGE} has no modal state")
    row = 0  # the modal state is the first message (t = 0)
    f = np.asarray(freqs[row] if freqs.dtype == object else freqs[row], dtype=float)
    z = np.asarray(zetas[row] if zetas.dtype == object else zetas[row], dtype=float)
    return f, z


def identify(data: np.ndarray, fs_hz: float, sel_freq: list[float], args) -> dict:
    """SSI-cov and FDD with pyoma2; identified f and zeta per selected true frequency."""
    import logging

    logging.disable(logging.INFO)  # pyoma2 logs every step at INFO
    from pyoma2.algorithms import FDD, SSI
    from pyoma2.setup import SingleSetup

    # The DC part (sensor bias, gravity-free static deflection) carries no modal
    # information and would dominate the covariances.
    data = data - data.mean(axis=0)
    setup = SingleSetup(data, fs=fs_hz)
    ssi = SSI(name="SSIcov", method="cov", br=args.br, ordmax=args.ordmax)
    fdd = FDD(name="FDD", nxseg=args.nxseg, method_SD="per")
    setup.add_algorithms(ssi, fdd)
    setup.run_all()
    # The lowest order at which each mode is stable; short records may have none, then
    # the poles at the highest order.
    setup.mpe("SSIcov", sel_freq=sel_freq, order_in="find_min", rtol=args.rtol)
    ssi_result = setup["SSIcov"].result
    found = np.atleast_1d(ssi_result.Fn) if ssi_result.Fn is not None else np.array([])
    if len(found) != len(sel_freq) or not np.all(np.isfinite(found)):
        setup.mpe("SSIcov", sel_freq=sel_freq, order_in=args.ordmax, rtol=args.rtol)
        ssi_result = setup["SSIcov"].result
    setup.mpe("FDD", sel_freq=sel_freq, DF=args.df_hz)
    fdd_result = setup["FDD"].result
    return {
        "ssi_f_hz": [float(v) for v in np.atleast_1d(ssi_result.Fn)],
        "ssi_zeta": [float(v) for v in np.atleast_1d(ssi_result.Xi)],
        "fdd_f_hz": [float(v) for v in np.atleast_1d(fdd_result.Fn)],
    }


def score(truth_f, truth_z, found: dict, tol: float) -> list[dict]:
    rows = []
    for k, (f, z) in enumerate(zip(truth_f, truth_z)):
        ssi_f = found["ssi_f_hz"][k] if k < len(found["ssi_f_hz"]) else float("nan")
        ssi_z = found["ssi_zeta"][k] if k < len(found["ssi_zeta"]) else float("nan")
        fdd_f = found["fdd_f_hz"][k] if k < len(found["fdd_f_hz"]) else float("nan")
        err = (ssi_f - f) / f
        rows.append(
            {
                "mode": k + 1,
                "true_f_hz": float(f),
                "ssi_f_hz": ssi_f,
                "ssi_f_error": err,
                "fdd_f_hz": fdd_f,
                "fdd_f_error": (fdd_f - f) / f,
                "true_zeta": float(z),
                "ssi_zeta": ssi_z,
                "pass": bool(np.isfinite(err) and abs(err) <= tol),
            }
        )
    return rows


def main(argv: list[str]) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("run", help="bridgetwin MCAP file")
    p.add_argument("--modes", type=int, default=2, help="modes scored, from the first (2)")
    p.add_argument("--tol", type=float, default=0.01, help="relative frequency tolerance (0.01)")
    p.add_argument("--br", type=int, default=40, help="SSI block rows (40)")
    p.add_argument("--ordmax", type=int, default=40, help="SSI maximum model order (40)")
    p.add_argument("--nxseg", type=int, default=2048, help="FDD segment length (2048)")
    p.add_argument("--rtol", type=float, default=0.05, help="SSI pole search tolerance (0.05)")
    p.add_argument("--df-hz", type=float, default=0.2, help="FDD peak search half-width (0.2 Hz)")
    p.add_argument("--start-s", type=float, default=0.0, help="ignore the record before (s)")
    p.add_argument("--end-s", type=float, default=None, help="ignore the record after (s)")
    p.add_argument("--json", help="write the result table here")
    args = p.parse_args(argv)
    try:
        data, fs_hz, names, filled = load_accelerations(args.run, args.start_s, args.end_s)
        truth_f, truth_z = truth_modes(args.run)
    except (OSError, ValueError, KeyError) as e:
        print(f"oma_check: {e}", file=sys.stderr)
        return 2
    usable = [k for k, f in enumerate(truth_f) if f < 0.4 * fs_hz][: args.modes]
    if len(usable) < args.modes:
        print(
            f"oma_check: only {len(usable)} true modes lie below 0.4 fs = {0.4 * fs_hz:.1f} Hz",
            file=sys.stderr,
        )
        return 2
    sel = [float(truth_f[k]) for k in usable]
    found = identify(data, fs_hz, sel, args)
    rows = score(truth_f[usable], truth_z[usable], found, args.tol)
    print(
        f"{args.run}: {data.shape[1]} accelerometers ({', '.join(names)}), "
        f"{data.shape[0]} samples at {fs_hz:.3f} Hz ({data.shape[0] / fs_hz:.1f} s), "
        f"{filled} lost samples filled"
    )
    print("mode  true f (Hz)  SSI f (Hz)  error    FDD f (Hz)  error    true zeta  SSI zeta")
    for r in rows:
        print(
            f"{r['mode']:>4}  {r['true_f_hz']:>11.4f}  {r['ssi_f_hz']:>10.4f}  "
            f"{100 * r['ssi_f_error']:>+6.2f}%  {r['fdd_f_hz']:>10.4f}  "
            f"{100 * r['fdd_f_error']:>+6.2f}%  {r['true_zeta']:>9.4f}  {r['ssi_zeta']:>8.4f}"
        )
    ok = all(r["pass"] for r in rows)
    print(f"{'PASS' if ok else 'FAIL'}: SSI frequencies within {100 * args.tol:g} % of the truth")
    if args.json:
        Path(args.json).write_text(
            json.dumps(
                {"fs_hz": fs_hz, "channels": names, "filled": filled, "modes": rows},
                indent=2,
            )
        )
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
