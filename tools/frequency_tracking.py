#!/usr/bin/env python3
"""Long-term tracking of f1 under a temperature cycle, with damage detection, scored
against the run's own truth.

    python3 tools/frequency_tracking.py run.mcap --train-h 4 --max-delay-s 2400
    python3 tools/frequency_tracking.py run.mcap --csv f1.csv --json f1.json --plot f1.svg

What it does, as a monitoring system would with a real installation's files (steps 1-4
see only the measured streams; the truth is read after the decision, to score it):

1. reads the accelerometers (``/sensors/accel/*``) onto one grid by the DAQ's own stamps,
   lost samples interpolated (as ``oma_check.load_accelerations``), and the deck
   thermometers (``/sensors/temp/*``, ``temperature_c``), with the native ``bridgetwin``
   reader when it is installed, else ``tools/read_run.py``;
2. cuts the record into windows of ``--window-s`` (600 s: Z24 kept one 11 min record an
   hour [1]); per window removes the mean, decimates by ``--decimate`` (FIR, zero phase)
   so that the band 0 .. 0.4 fs/q holds f1 and not f2, and identifies f1 by
   covariance-driven SSI [2] (pyoma2) as the median of the fullest cluster of stable
   poles in the band above ``--f-min-hz`` [7]; the window's temperature is the mean of
   the thermometers over it;
3. fits on the first ``--train-h`` hours, assumed healthy, the static regression [1, 3]
       f1^2 = a + b T + c min(T - Tk, 0)
   f1^2 because f1 = (pi / 2L^2) sqrt(EI / m) makes f1^2 proportional to E, and E(T) is
   bilinear with a knee near freezing (Z24 [1]); the knee Tk minimises the sum of squares
   over the training temperatures with ``--min-side`` windows either side (segmented
   regression [4]); without enough windows either side, or with ``--knee-c none``, the
   fit is linear (c = 0);
4. novelty: the residual e = f1^2 - (a + b T + ...) of every later window is tested
   against the prediction interval of the fit, |e| > k s sqrt(1 + x0' (X'X)^-1 x0), s^2 =
   SSE / (n - p) for p parameters, the knee included (the k-sigma band of [1, 3]; with the leverage term that widens it
   where the temperature leaves the training range [5]); an alarm is raised when
   ``--persist`` m consecutive windows leave the band (a run rule of control charts [6]),
   at the end of the m-th; windows where no f1 was identified are skipped;
5. only then reads ``/truth/bridge`` (the modal state after every rebuild: f1,
   damage_fraction) and ``/events`` (the "damage.N begins" line) and scores: f1 error
   per window against the time-averaged true f1, the detection delay (first alarm after
   the onset) and the false alarms (alarms before it).

Delay bound: a step change is flagged at the end of the m-th window that lies wholly
after it, at most (m + 1) L after the onset (L the window length); a damage that grows
over g seconds adds g. That holds when each damaged window leaves the band, i.e. when the
drop exceeds the band by a few s: the run prints the smallest drop so detected (band + 3 s,
the miss rate per window 0.13 %). ``--max-delay-s`` defaults to (m + 1) L.

Exit status 0 when the onset is detected within ``--max-delay-s`` and no alarm came before
it (a run without damage: no alarm at all), 1 otherwise, 2 on bad input, one line on
stderr naming the file (no such file, empty, not an MCAP file, truncated; no accelerometer
or no deck thermometer: not the frequency_tracking example; too few training windows, no
truth: ``tools/bad_input.py``), 4 when the tool itself failed.

[1] B. Peeters, G. De Roeck, One-year monitoring of the Z24-Bridge: environmental effects
    versus damage events, Earthq. Eng. Struct. Dyn. 30 (2001) 149-171.
[2] B. Peeters, G. De Roeck, Reference-based stochastic subspace identification for
    output-only modal analysis, Mech. Syst. Signal Process. 13 (1999) 855-878.
[3] F. Magalhaes, A. Cunha, E. Caetano, Vibration based structural health monitoring of
    an arch bridge: from automated OMA to damage detection, MSSP 28 (2012) 212-228.
[4] D. J. Hudson, Fitting segmented curves whose join points have to be estimated,
    J. Am. Stat. Assoc. 61 (1966) 1097-1129.
[5] D. C. Montgomery, E. A. Peck, G. G. Vining, Introduction to Linear Regression
    Analysis, Wiley: the prediction interval of a new observation.
[6] D. C. Montgomery, Introduction to Statistical Quality Control, Wiley: run rules
    (Western Electric) for control charts.
[7] F. Magalhaes, A. Cunha, E. Caetano, Online automatic identification of the modal
    parameters of a long span arch bridge, MSSP 23 (2009) 316-329.
"""

from __future__ import annotations

import argparse
import csv
import json
import os
import sys
import time
from pathlib import Path

# One BLAS thread: the matrices are small (SSI's block Toeplitz matrix is channels x br
# square), threads only contend, with each other and with a second CI lane (3x slower on
# 2 loaded cores).
for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import numpy as np  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bad_input import check_mcap, fail, guard, reader_error, require_topics, summary_of  # noqa: E402

ACCEL, TEMP, TRUTH, EVENTS = "/sensors/accel/", "/sensors/temp/", "/truth/bridge", "/events"


def read_topics(path: str, prefixes: tuple[str, ...], exact: tuple[str, ...] = ()) -> dict:
    """{topic: {column: numpy array}} for the topics starting with `prefixes` or named in
    `exact`: the native reader when importable, else tools/read_run.py (pure Python)."""
    try:
        import bridgetwin

        run = bridgetwin.read(path, topics=[p + "*" for p in prefixes] + list(exact))
        return {t: {c: frame[c].to_numpy() for c in frame.columns} for t, frame in run.items()}
    except ImportError:
        from read_run import list_topics, load_topics

        topics = [t for t in list_topics(path) if t.startswith(prefixes) or t in exact]
        out = load_topics(path, topics)
        for arrays in out.values():  # read_run names a block's temperature "temperature"
            if "temperature" in arrays and "temperature_c" not in arrays:
                arrays["temperature_c"] = arrays.pop("temperature")
        return out


def load_measured(path: str):
    """Accelerations on one grid (as oma_check.load_accelerations), the thermometers."""
    topics = read_topics(path, (ACCEL, TEMP))
    accel = sorted(t for t in topics if t.startswith(ACCEL) and len(topics[t]["timestamp_ns"]) > 1)
    temps = [t for t in topics if t.startswith(TEMP) and len(topics[t]["timestamp_ns"]) > 0]
    if not accel:
        raise ValueError(f"{path}: no accelerometer ({ACCEL}*)")
    if not temps:
        raise ValueError(f"{path}: no thermometer ({TEMP}*): cannot compensate temperature")
    stamps = [np.asarray(topics[t]["timestamp_ns"], dtype=np.int64) for t in accel]
    period_ns = float(np.median([np.median(np.diff(s)) for s in stamps]))
    t0 = min(int(s[0]) for s in stamps)
    index = [np.rint((s - t0) / period_ns).astype(np.int64) for s in stamps]
    first, last = max(int(i[0]) for i in index), min(int(i[-1]) for i in index)
    grid = np.arange(first, last + 1)
    data = np.empty((len(grid), len(accel)))
    for c, (i, t) in enumerate(zip(index, accel)):
        i, keep = np.unique(i, return_index=True)
        data[:, c] = np.interp(grid, i, np.asarray(topics[t]["acceleration_m_s2"], float)[keep])
    temp_t = np.concatenate([np.asarray(topics[t]["timestamp_ns"], np.int64) for t in temps])
    temp_v = np.concatenate([np.asarray(topics[t]["temperature_c"], float) for t in temps])
    return data, 1e9 / period_ns, t0 + first * period_ns, temp_t, temp_v, accel, temps


def identify_f1(x: np.ndarray, fs: float, args) -> float:
    """f1 of one window: SSI-cov [2] (pyoma2) up to `--ordmax`; the stable poles (pyoma2's
    frequency, damping and MAC criteria between successive orders) with 0 < zeta < 0.2 in
    the band [f_min, 0.4 fs] are clustered, each pole counting the stable poles within
    +/- rtol of it; f1 is the median of the fullest cluster (the automated picking of
    [7]). NaN when no pole is stable."""
    from scipy import signal
    from pyoma2.algorithms import SSI
    from pyoma2.setup import SingleSetup

    x = x - x.mean(axis=0)
    if args.decimate > 1:
        x = signal.decimate(x, args.decimate, axis=0, ftype="fir", zero_phase=True)
        fs /= args.decimate
    setup = SingleSetup(x, fs=fs)
    setup.add_algorithms(SSI(name="ssi", method="cov", br=args.br, ordmax=args.ordmax))
    setup.run_all()
    res = setup["ssi"].result
    f, z = np.asarray(res.Fn_poles), np.asarray(res.Xi_poles)
    with np.errstate(invalid="ignore"):
        keep = (np.asarray(res.Lab) == 1) & (f >= args.f_min_hz) & (f <= 0.4 * fs) & (z > 0) & (z < 0.2)
    f = np.sort(f[keep])
    if len(f) == 0:
        return float("nan")
    lo = np.searchsorted(f, f * (1 - args.rtol))
    hi = np.searchsorted(f, f * (1 + args.rtol), side="right")
    best = int(np.argmax(hi - lo))  # the first (lowest) of the fullest clusters
    return float(np.median(f[lo[best] : hi[best]]))


def design(temp: np.ndarray, knee: float | None) -> np.ndarray:
    """Columns [1, T, min(T - Tk, 0)] (the last only with a knee)."""
    cols = [np.ones_like(temp), temp] + ([np.minimum(temp - knee, 0.0)] if knee is not None else [])
    return np.column_stack(cols)


def fit(temp: np.ndarray, f1: np.ndarray, knee_arg: str, min_side: int) -> dict:
    """Least squares of f1^2 on T, with the knee fixed, searched [4] or none."""
    y = f1**2
    if knee_arg == "none":
        candidates = [None]
    elif knee_arg == "auto":
        ts = np.sort(temp)
        mids = range(min_side, len(ts) - min_side + 1)  # min_side windows either side
        candidates = [None] + [0.5 * (ts[i - 1] + ts[i]) for i in mids]
    else:
        candidates = [float(knee_arg)]
    best = None
    for knee in candidates:
        X = design(temp, knee)
        coef, *_ = np.linalg.lstsq(X, y, rcond=None)
        sse = float(np.sum((y - X @ coef) ** 2))
        if best is None or sse < best["sse"]:
            best = {"knee": knee, "coef": coef, "sse": sse, "xtx_inv": np.linalg.pinv(X.T @ X)}
    p = len(best["coef"]) + (1 if knee_arg == "auto" and best["knee"] is not None else 0)
    best["dof"] = len(y) - p
    best["s"] = float(np.sqrt(best["sse"] / best["dof"]))
    return best


def predict(model: dict, temp: np.ndarray, k: float) -> tuple[np.ndarray, np.ndarray]:
    """Predicted f1^2 and the half-width of the k-sigma prediction interval [5]."""
    X = design(temp, model["knee"])
    leverage = np.einsum("ij,jk,ik->i", X, model["xtx_inv"], X)
    return X @ model["coef"], k * model["s"] * np.sqrt(1.0 + leverage)


def alarms(outside: np.ndarray, valid: np.ndarray, m: int) -> list[int]:
    """Indices of the windows that complete a run of m consecutive out-of-band windows
    (one alarm per excursion; windows without f1 neither extend nor break a run)."""
    out, run = [], 0
    for i in range(len(outside)):
        if not valid[i]:
            continue
        run = run + 1 if outside[i] else 0
        if run == m:
            out.append(i)
    return out


def read_truth(path: str):
    """(modal-state times ns, true f1 Hz, damage onset ns or None) from the truth."""
    topics = read_topics(path, (), (TRUTH, EVENTS))
    if TRUTH not in topics:
        raise ValueError(f"{path}: no {TRUTH}")
    b = topics[TRUTH]
    modal = []  # (ns, f1, damage fractions) of the messages that carry the modal state
    for t, f, d in zip(b["log_time_ns"], b["natural_frequency_hz"], b["damage_fraction"]):
        f, d = np.atleast_1d(np.asarray(f, float)), np.atleast_1d(np.asarray(d, float))
        if len(f):
            modal.append((int(t), f[0], d))
    if not modal:
        raise ValueError(f"{path}: {TRUTH} has no modal state")
    onset = None
    events = topics.get(EVENTS, {})
    for t, text in zip(events.get("log_time_ns", []), events.get("message", [])):
        if str(text).startswith("damage.") and " begins" in str(text):
            onset = int(t) if onset is None else min(onset, int(t))
    if onset is None:  # no event line: the first modal state with a damaged element
        onset = next((t for t, _, d in modal if len(d) and d.max() > 1e-9), None)
    return np.array([t for t, _, _ in modal]), np.array([f for _, f, _ in modal]), onset


def plot(out: str, rows: list[dict], model: dict, onset_h, detect_h, train_h: float) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    h = np.array([r["mid_h"] for r in rows])
    col = {k: np.array([r[k] for r in rows], float) for k in rows[0] if k != "alarm"}
    fig, ax = plt.subplots(3, 1, sharex=True, figsize=(9, 8))
    ax[0].plot(h, col["true_f1_hz"], "k-", lw=1, label="true f1 (/truth/bridge)")
    ax[0].plot(h, col["f1_hz"], "o", ms=3, label="identified f1 (SSI-cov, per window)")
    ax[0].plot(h, col["predicted_f1_hz"], "--", lw=1, label="f1 predicted from T (healthy fit)")
    ax[0].set_ylabel("f1 (Hz)")
    ax[1].plot(h, col["temperature_c"], "o-", ms=2, color="tab:red")
    if model["knee"] is not None:
        ax[1].axhline(model["knee"], color="grey", lw=0.8, ls=":")
        label = f"knee {model['knee']:.2f} degC (fitted)"
        ax[1].annotate(label, (h[-1], model["knee"]), ha="right", va="bottom", fontsize=8)
    ax[1].set_ylabel("deck T (degC), measured")
    band = 100 * col["band_rel"]
    ax[2].fill_between(h, -band, band, color="tab:green", alpha=0.2, label="band")
    ax[2].plot(h, 100 * col["residual_rel"], "o-", ms=3, label="residual (f1 - predicted) / predicted")
    ax[2].set_ylabel("residual (%)")
    ax[2].set_xlabel("time (h)")
    for a in ax:
        a.axvspan(0, train_h, color="grey", alpha=0.1)
        if onset_h is not None:
            label = "damage onset (truth)" if a is ax[0] else None
            a.axvline(onset_h, color="tab:red", ls="--", lw=1, label=label)
        if detect_h is not None:
            a.axvline(detect_h, color="tab:purple", lw=1.5, label="detection" if a is ax[0] else None)
    ax[0].legend(fontsize=8, loc="upper left")
    ax[2].legend(fontsize=8, loc="lower left")
    title = f"f1 tracking: training (shaded) the first {train_h:g} h"
    title += f"; damage onset at {onset_h:.2f} h" if onset_h is not None else "; no damage"
    title += f", detected at {detect_h:.2f} h" if detect_h is not None else ""
    ax[0].set_title(title)
    fig.tight_layout()
    plt.rcParams["svg.hashsalt"] = "frequency_tracking"  # the same bytes for the same run
    fig.savefig(out, metadata={"Date": None} if out.endswith(".svg") else None)


def track(data, fs, start_ns, temp_t, temp_v, args) -> tuple[list[dict], dict, list[int]]:
    """Steps 2-4, blind: the windows (f1, T, prediction, band), the fit, the alarms."""
    n = int(round(args.window_s * fs))
    rows = []
    for w in range(len(data) // n):
        t_to = start_ns + (w + 1) * args.window_s * 1e9
        inside = (temp_t >= t_to - args.window_s * 1e9) & (temp_t < t_to)
        rows.append({
            "window": w,
            "start_h": w * args.window_s / 3600,
            "mid_h": (w + 0.5) * args.window_s / 3600,
            "end_ns": int(t_to),
            "training": (w + 1) * args.window_s <= args.train_h * 3600,
            "temperature_c": float(temp_v[inside].mean()) if inside.any() else float("nan"),
            "f1_hz": identify_f1(data[w * n : (w + 1) * n], fs, args),
        })
    f1 = np.array([r["f1_hz"] for r in rows])
    temp = np.array([r["temperature_c"] for r in rows])
    valid = np.isfinite(f1) & np.isfinite(temp)
    train = np.array([r["training"] for r in rows], dtype=bool)
    if (train & valid).sum() < 8:
        raise ValueError(f"{int((train & valid).sum())} training windows with f1 and T (fewer than 8)")
    model = fit(temp[train & valid], f1[train & valid], args.knee_c, args.min_side)
    pred2, half = predict(model, temp, args.k)  # NaN where no temperature
    model["s_rel"] = model["s"] / (2 * float(np.median(pred2[train & valid])))  # d(f^2) = 2 f df
    for r, y, h in zip(rows, pred2, half):
        e = r["f1_hz"] ** 2 - y
        r.update({
            "predicted_f1_hz": float(np.sqrt(y)),
            "residual_rel": float(e / (2 * y)),
            "band_rel": float(h / (2 * y)),
            "outside": bool(abs(e) > h),
        })
    outside = np.array([r["outside"] for r in rows], dtype=bool)
    return rows, model, alarms(outside & ~train, valid & ~train, args.persist)


def score(rows, alarm_idx, truth_t, truth_f1, onset_ns, start_ns, args) -> dict:
    """Step 5: f1 error per window against the time-averaged truth, detection, false alarms."""
    for r in rows:
        grid = np.linspace(r["end_ns"] - args.window_s * 1e9, r["end_ns"], 61)
        state = np.clip(np.searchsorted(truth_t, grid, side="right") - 1, 0, None)
        r["true_f1_hz"] = float(truth_f1[state].mean())
        r["f1_error_rel"] = (r["f1_hz"] - r["true_f1_hz"]) / r["true_f1_hz"]
        r["alarm"] = r["window"] in alarm_idx
    alarm_ns = [rows[i]["end_ns"] for i in alarm_idx]
    false_ns = [t for t in alarm_ns if onset_ns is None or t <= onset_ns]
    detect_ns = next((t for t in alarm_ns if onset_ns is not None and t > onset_ns), None)
    delay_s = (detect_ns - onset_ns) * 1e-9 if detect_ns is not None else None
    hours = lambda t: (t - start_ns) * 1e-9 / 3600 if t is not None else None  # noqa: E731
    err = np.array([r["f1_error_rel"] for r in rows if np.isfinite(r["f1_hz"])])
    why = [f"{len(false_ns)} false alarm(s)"] if false_ns else []
    if onset_ns is not None and hours(onset_ns) < args.train_h:
        why.append("the onset lies in the training period (the fit learnt the damage)")
    if onset_ns is not None and (delay_s is None or delay_s > args.max_delay_s):
        why.append(f"onset not detected within {args.max_delay_s:.0f} s")
    return {
        "f1_error_rel": {
            "mean": float(err.mean()), "sd": float(err.std(ddof=1)), "max_abs": float(abs(err).max())
        },
        "identified": len(err),
        "onset_h": hours(onset_ns),
        "alarms_h": [hours(t) for t in alarm_ns],
        "detection_h": hours(detect_ns),
        "delay_s": delay_s,
        "false_alarms": len(false_ns),
        "fail_reasons": why,
        "pass": not why,
    }


def main(argv: list[str]) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("run", help="bridgetwin MCAP file")
    p.add_argument("--window-s", type=float, default=600.0, help="window length (600 s)")
    p.add_argument("--train-h", type=float, default=4.0, help="healthy training period from the start (4 h)")
    p.add_argument("--knee-c", default="auto", help="knee: auto (searched), none (linear) or degC")
    p.add_argument("--min-side", type=int, default=5, help="training windows either side of a knee (5)")
    p.add_argument("--k", type=float, default=3.0, help="band half-width in prediction sigmas (3)")
    p.add_argument("--persist", type=int, default=2, help="windows out of band in a row for an alarm (2)")
    p.add_argument("--max-delay-s", type=float, help="detection bound ((persist + 1) x window)")
    p.add_argument("--decimate", type=int, default=4, help="decimation before SSI, band 0.4 fs/q (4)")
    p.add_argument("--f-min-hz", type=float, default=1.0, help="lowest pole kept (1 Hz)")
    p.add_argument("--br", type=int, default=30, help="SSI block rows (30)")
    p.add_argument("--ordmax", type=int, default=30, help="SSI maximum order (30)")
    p.add_argument("--rtol", type=float, default=0.02, help="half-width of a pole cluster (0.02)")
    p.add_argument("--csv", help="write the per-window table here")
    p.add_argument("--json", help="write the result here")
    p.add_argument("--plot", help="write the figure here (.svg, .png)")
    args = p.parse_args(argv)
    if args.max_delay_s is None:
        args.max_delay_s = (args.persist + 1) * args.window_s
    os.environ.setdefault("TQDM_DISABLE", "1")  # pyoma2's progress bars
    import logging

    logging.disable(logging.INFO)  # pyoma2 logs every step at INFO
    clock = time.perf_counter()
    check_mcap(args.run)
    topics = [c.topic for c in summary_of(args.run).channels.values()]
    require_topics(args.run, (ACCEL,), "accelerometer", "frequency_tracking", topics)
    require_topics(args.run, (TEMP,), "deck thermometer", "frequency_tracking", topics)
    try:
        data, fs, start_ns, temp_t, temp_v, accel, temps = load_measured(args.run)
        rows, model, alarm_idx = track(data, fs, start_ns, temp_t, temp_v, args)
    except ValueError as e:  # what the steps find wrong in the data
        return fail("frequency_tracking", e if str(e).startswith(args.run) else f"{args.run}: {e}")
    except Exception as e:  # noqa: BLE001 - a file the readers cannot read is bad input
        return fail("frequency_tracking", reader_error(args.run, e))
    elapsed, hours = time.perf_counter() - clock, len(data) / fs / 3600
    try:  # the decision is made: only now the truth, to score it
        truth_t, truth_f1, onset_ns = read_truth(args.run)
    except ValueError as e:
        return fail("frequency_tracking", e)
    except Exception as e:  # noqa: BLE001
        return fail("frequency_tracking", reader_error(args.run, e))
    result = score(rows, alarm_idx, truth_t, truth_f1, onset_ns, start_ns, args)
    band = float(np.nanmedian([r["band_rel"] for r in rows]))
    err = result["f1_error_rel"]
    knee = f"knee at {model['knee']:.2f} degC" if model["knee"] is not None else "linear (no knee)"
    print(f"{args.run}: {len(accel)} accelerometers at {fs:.1f} Hz, {len(temps)} thermometer(s), "
          f"{hours:.2f} h in {len(rows)} windows of {args.window_s:g} s, "
          f"processed in {elapsed:.1f} s ({elapsed / hours:.1f} s per hour of data)")
    print(f"f1 identified in {result['identified']}/{len(rows)} windows; error vs truth: "
          f"mean {100 * err['mean']:+.3f} %, sd {100 * err['sd']:.3f} %, "
          f"max |.| {100 * err['max_abs']:.3f} %")
    print(f"fit of f1^2(T) on the first {args.train_h:g} h "
          f"({sum(r['training'] and np.isfinite(r['f1_hz']) for r in rows)} windows): {knee}, "
          f"residual sd {100 * model['s_rel']:.3f} % of f1")
    print(f"band +/-{args.k:g} prediction sigma = +/-{100 * band:.3f} % of f1 (median); a drop of "
          f"{100 * (band + 3 * model['s_rel']):.2f} % or more leaves it in 99.87 % of windows")
    print(f"alarms ({args.persist} consecutive windows out of band): "
          + (", ".join(f"{h:.2f} h" for h in result["alarms_h"]) or "none"))
    if onset_ns is None:
        print("truth: no damage onset in this run")
    else:
        detection = "none" if result["detection_h"] is None else (
            f"at {result['detection_h']:.2f} h, delay {result['delay_s']:.0f} s "
            f"(bound {args.max_delay_s:.0f} s)")
        print(f"truth: damage onset at {result['onset_h']:.2f} h; detection: {detection}")
    print(f"false alarms before the onset: {result['false_alarms']}")
    if result["pass"]:
        detected = f"onset detected within {args.max_delay_s:.0f} s, no false alarm before it"
        print("PASS: " + ("no damage and no alarm" if onset_ns is None else detected))
    else:
        print("FAIL: " + "; ".join(result["fail_reasons"]))
    keys = ["window", "start_h", "mid_h", "temperature_c", "f1_hz", "true_f1_hz", "f1_error_rel",
            "predicted_f1_hz", "residual_rel", "band_rel", "training", "outside", "alarm"]
    if args.csv:
        with open(args.csv, "w", newline="") as f:
            writer = csv.DictWriter(f, fieldnames=keys, extrasaction="ignore")
            writer.writeheader()
            for r in rows:
                writer.writerow({k: round(v, 6) if isinstance(v, float) else v for k, v in r.items()})
    if args.json:
        settings = {k: v for k, v in vars(args).items() if k not in ("run", "csv", "json", "plot")}
        fitted = {"knee_c": model["knee"], "coef_hz2": [float(c) for c in model["coef"]],
                  "s_hz2": model["s"], "s_rel": model["s_rel"], "band_rel_median": band}
        Path(args.json).write_text(json.dumps({
            "run": args.run, "accelerometers": accel, "thermometers": temps, "fs_hz": fs, "hours": hours,
            "seconds_per_hour": elapsed / hours, "settings": settings, "fit": fitted, **result,
            "windows": [{k: r[k] for k in keys} for r in rows],
        }, indent=1))
    if args.plot:
        plot(args.plot, rows, model, result["onset_h"], result["detection_h"], args.train_h)
    return 0 if result["pass"] else 1


if __name__ == "__main__":
    sys.exit(guard("frequency_tracking", main, sys.argv[1:]))
