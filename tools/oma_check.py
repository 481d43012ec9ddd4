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
3. picks the modes blind, without the truth: the peaks of the first singular value of the
   FDD spectrum that stand out by at least ``--min-prominence-db`` above the valleys
   beside them, between ``--f-min-hz`` and 0.4 x the sample rate (the anti-alias pass
   band), and for each peak the SSI pole nearest to it at the lowest order where it is
   stable (pyoma2's ``mpe`` with ``sel_freq`` = the FDD peaks; a pole farther than
   ``rtol`` is not found);
4. only then reads ``/truth/bridge`` (the modal state written at t = 0) and scores: each
   true mode is matched to the nearest identified one. Identified modes that match no
   bridge mode (a vehicle's bounce, a load band edge) are listed, not scored.

Exit status 0 when every scored mode's SSI frequency is within ``--tol`` (relative) of the
truth, 1 otherwise, 2 on bad input, with one line on stderr naming the file (no such file,
empty, not an MCAP file, truncated, no accelerometer topic, too few samples, no truth:
``tools/bad_input.py``), 4 when the tool itself failed. Damping is reported, not scored: its estimate from
short ambient records scatters by tens of percent.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bad_input import check_mcap, fail, guard, reader_error, require_topics  # noqa: E402
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


def fdd_peaks(freq_hz: np.ndarray, s1: np.ndarray, f_min_hz: float, f_max_hz: float, min_prominence_db: float) -> list[float]:
    """Frequencies of the peaks of the first singular value `s1` that rise at least
    `min_prominence_db` above the higher of the two valleys beside them (each valley
    runs to the next point above the peak, or to the end), inside [f_min_hz, f_max_hz]."""
    peaks = []
    for i in range(1, len(s1) - 1):
        if not (s1[i] > s1[i - 1] and s1[i] >= s1[i + 1] and f_min_hz <= freq_hz[i] <= f_max_hz):
            continue
        left = i
        while left > 0 and s1[left - 1] <= s1[i]:
            left -= 1
        right = i
        while right < len(s1) - 1 and s1[right + 1] <= s1[i]:
            right += 1
        valley = max(s1[left : i + 1].min(), s1[i : right + 1].min())
        if valley > 0 and 10.0 * np.log10(s1[i] / valley) >= min_prominence_db:
            peaks.append(float(freq_hz[i]))
    return peaks


def identify(data: np.ndarray, fs_hz: float, args) -> dict:
    """FDD peaks and the SSI-cov poles at them, picked without the truth."""
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
    fdd_result = setup["FDD"].result
    peaks = fdd_peaks(
        np.asarray(fdd_result.freq),
        np.asarray(fdd_result.S_val[0, 0, :]),
        args.f_min_hz,
        0.4 * fs_hz,
        args.min_prominence_db,
    )
    if not peaks:
        return {"fdd_f_hz": [], "ssi_f_hz": [], "ssi_zeta": []}
    # The lowest order at which each mode is stable; short records may have none, then
    # the poles at the highest order.
    setup.mpe("SSIcov", sel_freq=peaks, order_in="find_min", rtol=args.rtol)
    ssi_result = setup["SSIcov"].result
    found = np.atleast_1d(ssi_result.Fn) if ssi_result.Fn is not None else np.array([])
    if len(found) != len(peaks) or not np.all(np.isfinite(found)):
        setup.mpe("SSIcov", sel_freq=peaks, order_in=args.ordmax, rtol=args.rtol)
        ssi_result = setup["SSIcov"].result
    return {
        "fdd_f_hz": peaks,
        "ssi_f_hz": [float(v) for v in np.atleast_1d(ssi_result.Fn)],
        "ssi_zeta": [float(v) for v in np.atleast_1d(ssi_result.Xi)],
    }


def nearest(values: list[float], target: float) -> int | None:
    """Index of the finite value nearest to `target`, or None."""
    finite = [(abs(v - target), i) for i, v in enumerate(values) if np.isfinite(v)]
    return min(finite)[1] if finite else None


def score(truth_f, truth_z, found: dict, tol: float) -> tuple[list[dict], list[float]]:
    """One row per true mode (matched to the nearest identified SSI mode), and the
    identified frequencies no true mode matched."""
    rows, matched = [], set()
    nan = float("nan")
    for k, (f, z) in enumerate(zip(truth_f, truth_z)):
        i = nearest(found["ssi_f_hz"], f)
        j = nearest(found["fdd_f_hz"], f)
        ssi_f = found["ssi_f_hz"][i] if i is not None else nan
        ssi_z = found["ssi_zeta"][i] if i is not None else nan
        fdd_f = found["fdd_f_hz"][j] if j is not None else nan
        if i is not None:
            matched.add(i)
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
    unmatched = [v for i, v in enumerate(found["ssi_f_hz"]) if i not in matched]
    return rows, unmatched


def main(argv: list[str]) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("run", help="bridgetwin MCAP file")
    p.add_argument("--modes", type=int, default=2, help="modes scored, from the first (2)")
    p.add_argument("--tol", type=float, default=0.01, help="relative frequency tolerance (0.01)")
    p.add_argument("--br", type=int, default=40, help="SSI block rows (40)")
    p.add_argument("--ordmax", type=int, default=40, help="SSI maximum model order (40)")
    p.add_argument("--nxseg", type=int, default=2048, help="FDD segment length (2048)")
    p.add_argument("--rtol", type=float, default=0.05, help="SSI pole search tolerance (0.05)")
    p.add_argument(
        "--min-prominence-db",
        type=float,
        default=10.0,
        help="an FDD peak must rise this far above the valleys beside it (10 dB)",
    )
    p.add_argument("--f-min-hz", type=float, default=1.0, help="lowest frequency picked (1 Hz)")
    p.add_argument("--start-s", type=float, default=0.0, help="ignore the record before (s)")
    p.add_argument("--end-s", type=float, default=None, help="ignore the record after (s)")
    p.add_argument("--json", help="write the result table here")
    args = p.parse_args(argv)
    check_mcap(args.run)
    require_topics(args.run, (ACCEL_PREFIX,), "accelerometer", "ambient_monitoring")
    try:
        data, fs_hz, names, filled = load_accelerations(args.run, args.start_s, args.end_s)
    except ValueError as e:  # what load_accelerations finds wrong: its message names the file
        return fail("oma_check", e)
    except Exception as e:  # noqa: BLE001 - a file the readers cannot read is bad input
        return fail("oma_check", reader_error(args.run, e))
    # What pyoma2 needs, said before it fails with its own words: FDD decomposes the
    # cross-spectral matrix of two channels or more, over segments overlapping by half.
    if data.shape[1] < 2:
        return fail(
            "oma_check",
            f"{args.run}: {data.shape[1]} accelerometer topic ({', '.join(names)}): the analysis needs two or more: "
            "is it the ambient_monitoring example?",
        )
    if data.shape[0] <= args.nxseg // 2:
        return fail(
            "oma_check",
            f"{args.run}: {data.shape[0]} samples ({data.shape[0] / fs_hz:.1f} s): too short for FDD segments of "
            f"--nxseg {args.nxseg} (more than {args.nxseg // 2} samples needed)",
        )
    # Blind: the picking sees the data only; the truth is read afterwards to score.
    try:
        found = identify(data, fs_hz, args)
    except (ValueError, np.linalg.LinAlgError) as e:  # pyoma2 on a record it cannot decompose
        return fail("oma_check", f"{args.run}: the identification failed on this record: {type(e).__name__}: {e}")
    try:
        truth_f, truth_z = truth_modes(args.run)
    except (OSError, ValueError, KeyError) as e:
        return fail("oma_check", f"{args.run}: no truth to score against ({TRUTH_BRIDGE}): {e}")
    usable = [k for k, f in enumerate(truth_f) if f < 0.4 * fs_hz][: args.modes]
    if len(usable) < args.modes:
        print(
            f"oma_check: only {len(usable)} true modes lie below 0.4 fs = {0.4 * fs_hz:.1f} Hz",
            file=sys.stderr,
        )
        return 2
    rows, unmatched = score(truth_f[usable], truth_z[usable], found, args.tol)
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
    print(
        "identified blind: FDD peaks "
        + ", ".join(f"{f:.3f}" for f in found["fdd_f_hz"])
        + " Hz; SSI modes matching no scored bridge mode: "
        + (", ".join(f"{f:.3f}" for f in unmatched) or "none")
    )
    ok = all(r["pass"] for r in rows)
    print(f"{'PASS' if ok else 'FAIL'}: SSI frequencies within {100 * args.tol:g} % of the truth")
    if args.json:
        Path(args.json).write_text(
            json.dumps(
                {
                    "fs_hz": fs_hz,
                    "channels": names,
                    "filled": filled,
                    "identified": found,
                    "unmatched_ssi_f_hz": unmatched,
                    "modes": rows,
                },
                indent=2,
            )
        )
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(guard("oma_check", main, sys.argv[1:]))
