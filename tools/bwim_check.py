#!/usr/bin/env python3
"""Bridge weigh-in-motion (B-WIM) of a bridgetwin run, scored against the run's own truth.

    python3 tools/bwim_check.py run.mcap                        # calibrate, weigh, score
    python3 tools/bwim_check.py run.mcap --expect-class "B+(7)" --json bwim.json --plot bwim.svg
    python3 tools/bwim_check.py run.mcap --save-calibration cal.json
    python3 tools/bwim_check.py other.mcap --calibration-from cal.json   # another run's calibration

What it does, as a B-WIM operator would with a real installation's files. It reads only the
measured strain streams (``/sensors/strain/*``: the DAQ's stamps and values, the gauges'
positions from the channel metadata, the span from the run's metadata) and, for the
calibration, the calibration truck's static axle loads and axle spacings: the weighbridge
ticket and tape measure of a real calibration. Those come from ``/truth/vehicles`` for the
vehicles given by ``--calibration-ids`` (default: the vehicles the scenario lists one by one,
``[[vehicles]]``; the generated traffic is never used), together with their direction and
roughly when they crossed (the crew's log), only to say which detected vehicle is the truck.

1. **Axle detection and speed (FAD).** Gauges within ``--fad-max-m`` of a support are
   free-of-axle-detector gauges; those at one support are averaged. Near a support the
   strain influence line of a simply supported span rises steeply over the gauge's distance
   ``a`` from the support and falls slowly beyond, so each axle entering at that end is a
   step of about ``a (1 - a / L) P y / EI`` in the record (about 1 microstrain for a 6 t
   axle here), each axle leaving there a step down. The bridge's second mode, which would
   pass for a train of axles, is first subtracted from the FAD records with a reference:
   the difference of two weighing sections placed symmetrically (x and L - x), band-passed
   around ``4 f1`` (``f1`` picked blind from the spectrum), scaled by least squares. A step
   filter (mean of the next ``w`` samples minus mean of the previous ``w``, less its running
   median) turns the steps into peaks (``scipy.signal.find_peaks``) above
   ``--fad-threshold`` times its robust noise level (1.4826 MAD); a peak next to a deeper
   one of the other sign (``--lobe-s``) is that step's rebound, not a step. Clear entry
   steps grouped by time gaps (``--max-axle-gap-s``) make a candidate vehicle; the delay to
   the far support is the lag that best correlates the entry steps with the exit steps
   (``--min-correlation``), so speed ``v = D / delay``; the axles are the peaks of the sum
   of the entry steps and the exit steps one delay later (both ends' evidence,
   ``--axle-threshold``, each end at least ``--end-threshold``), at least ``--min-spacing-m``
   apart and split where two are farther apart than ``--max-spacing-m``. Spacings are ``v``
   times the differences of the axle times. ``D``, the effective distance between the two
   supports' steps (nominally ``L - a``), is calibrated on the truck: its known spacings
   give its speed.
2. **Influence lines by the matrix method** (E. J. OBrien, M. J. Quilligan & R. Karoumi,
   "Calculating an influence line from direct measurements", Proc. ICE Bridge Eng. 159
   (BE1), 2006, 31-34; as cited, *not checked here*): with known axle loads ``A_i`` and axle
   positions ``s_i(t)`` the measured strain is ``e(t) = sum_i A_i I(s_i(t))``, linear in the
   ordinates of ``I``; least squares over every calibration run. The paper's ordinates sit
   at the sample spacing of one run; here they are the nodal values of a piecewise-linear
   ``I(s)`` (``--il-step-m``) so that runs at different speeds stack in one system, with a
   small second-difference (Tikhonov) penalty (``--il-smoothing``). Each run has its own
   nuisance columns, eliminated exactly: a baseline and the first mode's vibration (cos
   and sin at ``f1`` with linearly varying amplitudes; ``--no-vibration-terms``). One
   influence line per weighing section (gauges at one position, averaged) and travel
   direction (lane), in the travel coordinate ``s`` from the entry support. The calibrated
   line keeps what the truck's own dynamics add on average over the runs (the method's
   known limit): the study compares it with the twin's static influence line.
3. **Axle loads by Moses' least squares** (F. Moses, "Weigh-in-motion system using
   instrumented bridges", Transportation Engineering Journal, Proc. ASCE 105 (TE3), 1979,
   233-249, as docs/sensors.md section 3 cites it): ``min ||e - sum_i A_i I(s_i(t))||^2``
   over the vehicle's time on the bridge, every weighing section stacked (each weighted by
   the inverse of its noise), each section with the nuisance columns above. Vehicles whose
   times on the bridge overlap (multiple presence: two lanes, a close follower) are solved
   jointly, the unknowns being the axles of all of them (``--multiple-presence skip``
   leaves them unweighed instead). A detection lighter than ``--min-gross-kn`` is no vehicle:
   dropped, and its cluster solved again. A cluster whose fit leaves a relative residual
   (rms residual over rms of the modelled vehicle strain) above ``--max-residual`` is flagged
   and not weighed: a vehicle the FAD gauges missed or a wrong axle count shows there.
   ``--group-penalty`` adds a Tikhonov penalty on the load differences of neighbouring axles
   in a group (default 0: plain Moses). Gross weight = sum of the axle loads. Vehicles the FAD gauges do not see (cars, below about 3 t per
   axle) are not weighed; their strain, when they share the bridge with a truck, goes into
   the truck's estimate.
4. **Only then the truth.** ``/truth/vehicles`` (static axle loads, spacings, speed, entry
   time at the entry support) is matched to the detections by direction and entry time;
   relative errors of the gross weight, of each group of axles (spacing < 2.1 m, as
   ``src/measurement/wim/groups.rs``), of single axles and of the axles of a group, for the
   traffic vehicles of the COST 323 domain (gross weight > 3.5 t). The calibration runs are
   scored apart, leave-one-out (each run weighed with the influence lines of the others;
   conditions r2-I: one vehicle, several speeds).

**COST 323 classes.** Tolerances ``delta`` per class and criterion as the crate's table
(``src/measurement/wim/cost323.rs``, docs/sensors.md section 3; B. Jacob, E. J. OBrien &
S. Jehaes (eds.), Weigh-in-Motion of Road Vehicles: Final Report of the COST 323 Action,
LCPC, 2002). Acceptance: from the ``n`` relative errors of a criterion, mean ``m`` and
standard deviation ``s``, the level of confidence of the centred interval ``[-delta, delta]``
under a normal law is ``pi = Phi((delta - m) / s) - Phi((-delta - m) / s)``; a criterion is in
a class when ``pi >= pi0``. The minimum ``pi0`` depends on the test conditions (repeatability
r1, r2, R1, R2 x environment I, II, III; ``--conditions``, default ``R2-I``: a sample of the
traffic within one day) and on ``n``:
``pi0(n) = 2 Phi(u_inf sqrt((n - 1) / chi2_{n-1, 1-alpha})) - 1``, ``u_inf = Phi^-1((1 + pi_inf)/2)``:
the level that a system whose errors are unbiased and normal with exactly the coverage
``pi_inf`` of the conditions still reaches with probability ``1 - alpha`` (``alpha`` = 5 %) in a
sample of ``n`` (the sample standard deviation at its upper ``1 - alpha`` quantile), so that small
samples are judged with the margin their scatter needs and ``pi0 -> pi_inf`` as ``n`` grows. This
is this tool's reading of the specification's acceptance rule, and the ``pi_inf`` values in
``PI_INF`` are as recalled from the specification's table: *not checked here* against its
text (docs/sensors.md section 3 says the same of the tolerance table). ``delta_min``, the
narrowest interval that passes, is reported with ``pi`` and ``pi0`` so that the margin is
visible. The class reached is the best class whose ``delta`` is at least ``delta_min``.

Exit status 0 when the gross-weight class reached is ``--expect-class`` or better (default
D+(20)), 1 otherwise, 2 on bad input (no strain topics, no FAD gauges, no usable
calibration run, nothing to score).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
import time
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

# Small matrices only: one BLAS thread is faster than two fighting over a shared machine.
for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import numpy as np  # noqa: E402
from scipy import sparse, stats  # noqa: E402
from scipy.ndimage import median_filter  # noqa: E402
from scipy.optimize import brentq  # noqa: E402
from scipy.signal import butter, find_peaks, sosfiltfilt, welch  # noqa: E402

STRAIN_PREFIX = "/sensors/strain/"
TRUTH_VEHICLES = "/truth/vehicles"

# COST 323 tolerances delta (%) per class: gross, group of axles, single axle, axle of a
# group (src/measurement/wim/cost323.rs, TOLERANCES_PCT; docs/sensors.md section 3).
CLASSES = ["A(5)", "B+(7)", "B(10)", "C(15)", "D+(20)"]
CRITERIA = ["gross", "group of axles", "single axle", "axle of a group"]
TOLERANCE_PCT = {
    "A(5)": (5.0, 7.0, 8.0, 10.0),
    "B+(7)": (7.0, 10.0, 11.0, 14.0),
    "B(10)": (10.0, 13.0, 15.0, 20.0),
    "C(15)": (15.0, 18.0, 20.0, 25.0),
    "D+(20)": (20.0, 23.0, 25.0, 30.0),
}
BELOW = "below D+(20)"
# Minimum level of confidence pi0 (%) for a large sample, by repeatability (r1 full
# repeatability: one vehicle, same speed and load; r2 extended repeatability: one vehicle,
# several speeds and loads; R1 limited reproducibility: a few vehicles; R2 full
# reproducibility: a sample of the traffic) and environment (I: within a day; II: within
# a week or a month; III: over a year). As recalled from the COST 323 specification's
# table: *not checked here* (module doc).
PI_INF = {
    ("r1", "I"): 99.2, ("r1", "II"): 98.9, ("r1", "III"): 98.4,
    ("r2", "I"): 98.9, ("r2", "II"): 98.4, ("r2", "III"): 97.7,
    ("R1", "I"): 98.4, ("R1", "II"): 97.7, ("R1", "III"): 96.9,
    ("R2", "I"): 97.7, ("R2", "II"): 96.9, ("R2", "III"): 95.0,
}  # fmt: skip
ALPHA = 0.05
GROUP_SPACING_MAX_M = 2.1  # src/measurement/wim/groups.rs
DOMAIN_GROSS_N = 3.5 * 9.81e3  # COST 323 domain of use: gross weight > 3.5 t
G = 9.81


# --------------------------------------------------------------------------- reading


@dataclass
class Record:
    """The measured strain on one time grid, and what the installation knows."""

    path: str
    fs_hz: float
    t0_ns: int  # DAQ stamp of grid sample 0 (Unix-epoch ns)
    ids: list[str]
    positions_m: np.ndarray
    values: np.ndarray  # [n_samples, n_gauges], microstrain, NaN where lost
    span_m: float
    listed_vehicle_ids: list[int]
    lost: int = 0
    cache: dict = field(default_factory=dict, repr=False)


def _reader():
    """The bridgetwin package's reader when importable, else None (tools/read_run.py)."""
    try:
        import bridgetwin  # noqa: F401

        return bridgetwin
    except ImportError:
        return None


def read_strains(path: str) -> Record:
    """Every strain gauge of the run on the common grid of the DAQ stamps."""
    bt = _reader()
    if bt is not None:
        run = bt.read(path, topics=STRAIN_PREFIX + "*")
        topics = sorted(t for t in run.keys() if t.startswith(STRAIN_PREFIX))
        series = {}
        for t in topics:
            df = run[t]
            series[t] = (df["timestamp_ns"].to_numpy(np.int64), df["strain_microstrain"].to_numpy(float))
        positions = {t: float(run.channels[t]["position_m"]) for t in topics}
        meta = run.metadata
    else:
        sys.path.insert(0, str(Path(__file__).resolve().parent))
        from mcap.reader import make_reader
        from read_run import list_topics, load_topics

        topics = sorted(t for t in list_topics(path) if t.startswith(STRAIN_PREFIX))
        arrays = load_topics(path, topics) if topics else {}
        series = {
            t: (np.asarray(a["timestamp_ns"], np.int64), np.asarray(a["strain_microstrain"], float))
            for t, a in arrays.items()
        }
        with open(path, "rb") as f:
            reader = make_reader(f)
            summary = reader.get_summary()
            positions = {
                c.topic: float(c.metadata.get("position_m", "nan"))
                for c in summary.channels.values()
                if c.topic in series
            }
            meta = {m.name: dict(m.metadata) for m in reader.iter_metadata()}
    if not series:
        raise ValueError(f"{path}: no strain topics ({STRAIN_PREFIX}*)")
    periods = [np.median(np.diff(s)) for s, _ in series.values() if len(s) > 1]
    if not periods:
        raise ValueError(f"{path}: too few strain samples")
    period = float(min(periods))
    t0 = min(int(s[0]) for s, _ in series.values())
    n = max(int(round((s[-1] - t0) / period)) for s, _ in series.values()) + 1
    values = np.full((n, len(series)), np.nan)
    lost = 0
    for c, (s, v) in enumerate(series.values()):
        idx = np.rint((s - t0) / period).astype(np.int64)
        if abs(np.median(np.diff(s)) - period) > 1e-3 * period:  # another rate: interpolate
            values[:, c] = np.interp(np.arange(n) * period, (s - t0).astype(float), v)
        else:
            values[idx, c] = v
        lost += int(np.isnan(values[:, c]).sum())
    span = float(meta.get("bridge_model", {}).get("span_m", "nan"))
    if not math.isfinite(span):
        raise ValueError(f"{path}: no span in the run's metadata (bridge_model.span_m)")
    listed = []
    toml_text = meta.get("scenario", {}).get("toml")
    if toml_text:
        scenario = tomllib.loads(toml_text)
        listed = [int(v.get("id", i + 1)) for i, v in enumerate(scenario.get("vehicles", []))]
    ids = [t[len(STRAIN_PREFIX) :] for t in series]
    return Record(path, 1e9 / period, t0, ids, np.array([positions[t] for t in series]), values, span, listed, lost)


def read_truth(path: str) -> list[dict]:
    """/truth/vehicles as one dict per vehicle (direction +1 / -1, times in epoch ns)."""
    bt = _reader()
    rows = []
    if bt is not None:
        df = bt.read(path, topics=TRUTH_VEHICLES)[TRUTH_VEHICLES]
        cols = df.columns

        def arr(row, name):
            if name in cols:
                return np.atleast_1d(np.asarray(row[name], float))
            return np.array([row[c] for c in cols if c.startswith(name + ".") and np.isfinite(row[c])], float)

        for _, row in df.iterrows():
            if not _known(row["entry_time_ns"]):
                continue  # still on the approach when the run ended
            rows.append(
                _truth_row(
                    row["vehicle_id"],
                    row["vehicle_class"],
                    row["direction"],
                    row["speed_m_s"],
                    row["entry_time_ns"],
                    arr(row, "static_axle_load_n"),
                    arr(row, "axle_spacing_m"),
                )
            )
    else:
        sys.path.insert(0, str(Path(__file__).resolve().parent))
        from read_run import load_topics

        a = load_topics(path, [TRUTH_VEHICLES])[TRUTH_VEHICLES]
        for k in range(len(a["vehicle_id"])):
            if not _known(a["entry_time_ns"][k]):
                continue
            rows.append(
                _truth_row(
                    a["vehicle_id"][k],
                    a["vehicle_class"][k],
                    a["direction"][k],
                    a["speed_m_s"][k],
                    a["entry_time_ns"][k],
                    a["static_axle_load_n"][k],
                    a["axle_spacing_m"][k],
                )
            )
    return rows


def _known(value) -> bool:
    try:
        return value is not None and math.isfinite(float(value))
    except (TypeError, ValueError):
        return False


def _truth_row(vid, cls, direction, speed, entry_ns, loads, spacings) -> dict:
    d = str(direction)
    sign = -1 if d in ("2", "-1") or "DECREASING" in d else 1
    loads = np.atleast_1d(np.asarray(loads, float))
    spacings = np.atleast_1d(np.asarray(spacings, float))[: max(len(loads) - 1, 0)]
    return {
        "id": int(vid),
        "class": str(cls),
        "direction": sign,
        "speed_m_s": float(speed),
        "entry_ns": int(entry_ns),
        "loads_n": loads,
        "spacings_m": spacings,
        "gross_n": float(loads.sum()),
    }


# --------------------------------------------------------------------------- detection


@dataclass
class Vehicle:
    direction: int  # +1: enters at x = 0; -1: enters at x = L
    t_axle: np.ndarray  # s, time each axle passes the entry step's reference point s_c
    speed: float
    index: int = 0
    loads_n: np.ndarray | None = None
    cluster: int = -1
    cluster_size: int = 1
    matched_exit: int = 0
    residual: float | None = None
    poor_fit: bool = False
    truth: dict | None = field(default=None, repr=False)

    @property
    def spacings(self) -> np.ndarray:
        return np.diff(self.t_axle) * self.speed


@dataclass
class Geometry:
    """Where the FAD steps sit along the travel coordinate s (from the entry support)."""

    span_m: float
    s_entry: dict  # direction -> s of the entry step's reference point
    distance: dict  # direction -> D, s from the entry step to the exit step


def step_filter(x: np.ndarray, w: int) -> np.ndarray:
    """mean(x[i : i + w]) - mean(x[i - w : i]) at every i (cumulative sums, O(n))."""
    c = np.concatenate([[0.0], np.cumsum(x)])
    n = len(x)
    i = np.arange(n)
    lo, hi = np.clip(i - w, 0, n), np.clip(i + w, 0, n)
    return (c[hi] - c[i]) / np.maximum(hi - i, 1) - (c[i] - c[lo]) / np.maximum(i - lo, 1)


def fill_nan(x: np.ndarray) -> np.ndarray:
    bad = np.isnan(x)
    if not bad.any():
        return x
    i = np.arange(len(x))
    return np.interp(i, i[~bad], x[~bad])


def first_frequency(rec: Record, fad_max_m: float) -> float | None:
    """The bridge's first natural frequency, picked blind: the lowest peak above 1 Hz of
    the weighing gauges' summed Welch spectrum that stands 6 dB above its surroundings."""
    inner = np.where((rec.positions_m > fad_max_m) & (rec.positions_m < rec.span_m - fad_max_m))[0]
    if len(inner) == 0:
        return None
    n = min(8192, rec.values.shape[0])
    psd = None
    for c in inner:
        f, p = welch(fill_nan(rec.values[:, c]), fs=rec.fs_hz, nperseg=n)
        psd = p if psd is None else psd + p
    m = (f >= 1.0) & (f <= 0.4 * rec.fs_hz)
    k, _ = find_peaks(10 * np.log10(psd[m] + 1e-30), prominence=6.0)
    return float(f[m][k[0]]) if len(k) else None


def antisymmetric_reference(rec: Record, fad_max_m: float, f1: float | None):
    """The second mode's vibration, from two weighing sections placed symmetrically (x and
    L - x): their difference cancels the symmetric modes, band-passed around 4 f1 (a
    simply supported girder's f2) from 2.8 f1 to 5.6 f1. None without such a pair."""
    if f1 is None:
        return None
    sections = weighing_sections(rec, fad_max_m)
    L = rec.span_m
    for x, y in sections:
        for x2, y2 in sections:
            if x < L / 2 - 0.5 and abs(x + x2 - L) < 0.05:
                hi = min(5.6 * f1, 0.4 * rec.fs_hz)
                if 2.8 * f1 >= hi:
                    return None
                sos = butter(4, [2.8 * f1, hi], "bandpass", fs=rec.fs_hz, output="sos")
                return sosfiltfilt(sos, fill_nan(y) - fill_nan(y2))
    return None


def cancel_reference(x: np.ndarray, ref: np.ndarray | None, fs: float, f1: float | None) -> np.ndarray:
    """x less its least-squares share of the reference vibration (in the reference's band)."""
    if ref is None:
        return x
    sos = butter(4, [2.8 * f1, min(5.6 * f1, 0.4 * fs)], "bandpass", fs=fs, output="sos")
    xb = sosfiltfilt(sos, x)
    return x - float(np.dot(xb, ref) / max(np.dot(ref, ref), 1e-30)) * ref


def fad_channels(rec: Record, fad_max_m: float) -> dict:
    """{'W': averaged signal of the gauges near x = 0, 'E': near x = L} and their positions."""
    west = np.where(rec.positions_m <= fad_max_m)[0]
    east = np.where(rec.positions_m >= rec.span_m - fad_max_m)[0]
    if len(west) == 0 or len(east) == 0:
        raise ValueError(f"no FAD gauges within {fad_max_m} m of both supports (positions {rec.positions_m.tolist()})")
    return {
        "W": (fill_nan(np.nanmean(rec.values[:, west], axis=1)), float(rec.positions_m[west].mean()), west),
        "E": (fill_nan(np.nanmean(rec.values[:, east], axis=1)), float(rec.positions_m[east].mean()), east),
    }


def robust_sd(x: np.ndarray) -> float:
    return max(1.4826 * float(np.median(np.abs(x - np.median(x)))), 1e-12)


def peak_times(d: np.ndarray, fs: float, height: float, dist: int, lobe: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """Times (s, refined by a parabola through the top three samples) and heights of the
    peaks of d above height. With lobe > 0, a peak with a deeper trough of the other sign
    within lobe samples is dropped: it is the rebound of that other step, not a step."""
    k, p = find_peaks(d, height=height, distance=dist, prominence=0.5 * height)
    k = k[(k > 0) & (k < len(d) - 1)]
    if lobe > 0 and len(k):
        lo = np.clip(k - lobe, 0, len(d))
        hi = np.clip(k + lobe + 1, 0, len(d))
        trough = np.array([-d[a:b].min() for a, b in zip(lo, hi, strict=True)])
        k = k[trough < d[k]]
    a, b, c = d[k - 1], d[k], d[k + 1]
    den = a - 2 * b + c
    frac = np.where(np.abs(den) > 1e-15, 0.5 * (a - c) / np.where(den == 0, 1, den), 0.0)
    return (k + np.clip(frac, -0.5, 0.5)) / fs, b


def group_axles(times: np.ndarray, max_gap_s: float) -> list[np.ndarray]:
    if len(times) == 0:
        return []
    cuts = np.where(np.diff(times) > max_gap_s)[0] + 1
    return np.split(times, cuts)


def xcorr_delay(a: np.ndarray, b: np.ndarray, k0: int, k1: int, lag_min: int, lag_max: int):
    """The lag (samples, parabola-refined) in [lag_min, lag_max] maximising the normalised
    correlation of a[k0:k1] with b[k0 + lag : k1 + lag], and that correlation."""
    lag_max = min(lag_max, len(b) - k1)
    if lag_max <= lag_min or k1 - k0 < 3:
        return None
    seg = a[k0:k1]
    c = np.correlate(b[k0 + lag_min : k1 + lag_max], seg, mode="valid")
    sq = np.concatenate([[0.0], np.cumsum(b[k0 + lag_min : k1 + lag_max] ** 2)])
    n = k1 - k0
    norm = np.sqrt(np.maximum((sq[n:] - sq[:-n]) * np.dot(seg, seg), 1e-30))
    r = c / norm
    i = int(np.argmax(r))
    frac = 0.0
    if 0 < i < len(r) - 1:
        den = r[i - 1] - 2 * r[i] + r[i + 1]
        frac = float(np.clip(0.5 * (r[i - 1] - r[i + 1]) / den, -0.5, 0.5)) if den != 0 else 0.0
    return lag_min + i + frac, float(r[i])


def detect_vehicles(rec: Record, geo: Geometry | None, args) -> tuple[list[Vehicle], dict, Geometry]:
    """Vehicles from the FAD steps (module doc, step 1), in two passes: a vehicle is a group
    of clear steps (above --fad-threshold) at the entry support whose step pattern reappears
    at the exit support one delay later (the delay by cross-correlation of the two step
    records); its axles are the peaks of the sum of the entry steps and the exit steps
    shifted by the delay (both ends' evidence, --axle-threshold), at least --min-spacing-m
    apart. The bridge's second mode, which the step filter would take for axles, is first
    removed from the FAD records with a reference: the difference of two symmetric
    weighing sections, band-passed around 4 f1 (f1 found blind)."""
    fad = fad_channels(rec, args.fad_max_m)
    fs = rec.fs_hz
    w = max(2, int(round(args.fad_window_s * fs)))
    f1 = first_frequency(rec, args.fad_max_m)
    ref = antisymmetric_reference(rec, args.fad_max_m, f1) if args.cancel_mode2 else None
    filt = {}
    for end, (x, _, _) in fad.items():
        d = step_filter(cancel_reference(x, ref, fs, f1), w)
        # Less its running median: the slow part of the influence line (every axle on the
        # span tilts the record a little) is not a step.
        filt[end] = d - median_filter(d, size=max(3, int(args.trend_window_s * fs)) | 1, mode="nearest")
    sd = {end: robust_sd(d) for end, d in filt.items()}
    info = {"fad_noise_microstrain": sd, "step_filter_samples": w, "f1_hz": f1, "mode2_cancelled": ref is not None}
    L = rec.span_m
    a_w, a_e = fad["W"][1], L - fad["E"][1]
    if geo is None:  # nominal: the middle of each steep part of the influence line
        geo = Geometry(L, {1: a_w / 2, -1: a_e / 2}, {1: L - a_e / 2 - a_w / 2, -1: L - a_w / 2 - a_e / 2})
    vehicles = []
    unconfirmed = 0
    n = len(filt["W"])
    dist0 = max(1, int(round(args.min_axle_sep_s * fs)))
    for direction, ent, ext in ((1, "W", "E"), (-1, "E", "W")):
        d_in, d_out = filt[ent], -filt[ext]
        lobe = int(round(args.lobe_s * fs))
        up, _ = peak_times(d_in, fs, args.fad_threshold * sd[ent], dist0, lobe)
        D = geo.distance[direction]
        groups = group_axles(up, args.max_axle_gap_s)
        for g, seeds in enumerate(groups):
            lo = seeds[0] - args.max_axle_gap_s
            hi = seeds[-1] + args.max_axle_gap_s
            if g > 0:
                lo = max(lo, 0.5 * (groups[g - 1][-1] + seeds[0]))
            if g + 1 < len(groups):
                hi = min(hi, 0.5 * (seeds[-1] + groups[g + 1][0]))
            k0, k1 = max(int(lo * fs), 0), min(int(hi * fs), n)
            # The delay: the exit record's steps correlated with the entry record's.
            xc = xcorr_delay(
                np.maximum(d_in, 0.0),
                np.maximum(d_out, 0.0),
                k0,
                k1,
                int(D / args.v_max * fs),
                int(D / args.v_min * fs) + 1,
            )
            if xc is None or xc[1] < args.min_correlation:
                unconfirmed += 1
                continue
            lag = xc[0]
            delay = lag / fs
            speed = D / delay
            li = int(round(lag))
            k1 = min(k1, n - li)
            both = d_in[k0:k1] + d_out[k0 + li : k1 + li]
            sep = max(1, int(args.min_spacing_m / speed * fs))
            t_ax, _ = peak_times(both, fs, args.axle_threshold * math.hypot(sd[ent], sd[ext]), sep, lobe)
            kk = np.rint(t_ax * fs).astype(int)
            # Each end must see the step on its own too.
            ok = (d_in[k0 + kk] > args.end_threshold * sd[ent]) & (d_out[k0 + li + kk] > args.end_threshold * sd[ext])
            t_ax = t_ax[ok] + k0 / fs
            keep = np.array(sorted(t for t in t_ax if np.min(np.abs(seeds - t)) <= args.max_axle_gap_s))
            if len(keep) == 0:
                unconfirmed += 1
                continue
            # Axles farther apart than any vehicle's belong to different vehicles (a car
            # close ahead of a truck); lone axles are dropped.
            for part in np.split(keep, np.where(np.diff(keep) * speed > args.max_spacing_m)[0] + 1):
                if len(part) >= 2:
                    vehicles.append(Vehicle(direction, part, speed, matched_exit=len(part)))
                else:
                    info["lone_axles"] = info.get("lone_axles", 0) + 1
    vehicles.sort(key=lambda v: v.t_axle[0] - geo.s_entry[v.direction] / v.speed)
    for k, v in enumerate(vehicles):
        v.index = k
    info["unconfirmed_groups"] = unconfirmed
    return vehicles, info, geo


# --------------------------------------------------------------------------- influence lines


@dataclass
class Calibration:
    geometry: Geometry
    s_grid: np.ndarray
    sections_m: list[float]
    il: dict  # direction -> [n_sections, n_grid], microstrain per kN
    noise: np.ndarray  # per section, microstrain
    gauge_ids: list[str]
    runs_used: list[int]
    source: str = ""

    def to_json(self) -> dict:
        return {
            "source": self.source,
            "span_m": self.geometry.span_m,
            "s_entry_m": {str(k): v for k, v in self.geometry.s_entry.items()},
            "fad_distance_m": {str(k): v for k, v in self.geometry.distance.items()},
            "s_grid_m": self.s_grid.tolist(),
            "sections_m": self.sections_m,
            "il_microstrain_per_kn": {str(k): v.tolist() for k, v in self.il.items()},
            "noise_microstrain": self.noise.tolist(),
            "gauge_ids": self.gauge_ids,
            "runs_used": self.runs_used,
        }

    @staticmethod
    def from_json(d: dict) -> Calibration:
        geo = Geometry(
            float(d["span_m"]),
            {int(k): float(v) for k, v in d["s_entry_m"].items()},
            {int(k): float(v) for k, v in d["fad_distance_m"].items()},
        )
        return Calibration(
            geo,
            np.array(d["s_grid_m"]),
            list(d["sections_m"]),
            {int(k): np.array(v) for k, v in d["il_microstrain_per_kn"].items()},
            np.array(d["noise_microstrain"]),
            list(d["gauge_ids"]),
            list(d["runs_used"]),
            d.get("source", ""),
        )


def weighing_signals(rec: Record, fad_max_m: float) -> tuple[list[float], np.ndarray]:
    """Positions and signals [n_samples, n_sections] of the weighing sections: the gauges
    away from the supports, averaged by position (computed once per record)."""
    key = ("sections", fad_max_m)
    if key not in rec.cache:
        inner = np.where((rec.positions_m > fad_max_m) & (rec.positions_m < rec.span_m - fad_max_m))[0]
        if len(inner) == 0:
            raise ValueError("no weighing gauges away from the supports")
        positions = sorted({round(float(p), 2) for p in rec.positions_m[inner]})
        cols = [inner[np.abs(rec.positions_m[inner] - p) < 0.01] for p in positions]
        Y = np.column_stack(
            [
                rec.values[:, c].mean(axis=1)
                if np.isfinite(rec.values[:, c]).all()
                else np.nanmean(rec.values[:, c], axis=1)
                for c in cols
            ]
        )
        rec.cache[key] = (positions, Y)
    return rec.cache[key]


def weighing_sections(rec: Record, fad_max_m: float):
    """[(position, signal)] of the weighing sections."""
    positions, Y = weighing_signals(rec, fad_max_m)
    return [(p, Y[:, c]) for c, p in enumerate(positions)]


def hat_matrix(s: np.ndarray, s_grid: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Piecewise-linear basis on s_grid at the points s: (left node, weight left, weight
    right); points outside the grid get zero weights."""
    h = s_grid[1] - s_grid[0]
    u = (s - s_grid[0]) / h
    j = np.floor(u).astype(np.int64)
    f = u - j
    inside = (j >= 0) & (j < len(s_grid) - 1)
    j = np.where(inside, j, 0)
    return j, np.where(inside, 1.0 - f, 0.0), np.where(inside, f, 0.0)


def axle_positions(v: Vehicle, t: np.ndarray, geo: Geometry) -> np.ndarray:
    """[n_t, n_axles] travel coordinate s of every axle at the times t."""
    return geo.s_entry[v.direction] + v.speed * (t[:, None] - v.t_axle[None, :])


def section_noise(y: np.ndarray) -> float:
    """Robust noise level of a strain record: 1.4826 MAD of the first difference / sqrt 2."""
    d = np.diff(y[np.isfinite(y)])
    return max(1.4826 * float(np.median(np.abs(d - np.median(d)))) / math.sqrt(2), 1e-9)


def occupancy(v: Vehicle, geo: Geometry, s_lo: float, s_hi: float) -> tuple[float, float]:
    """Times between which some axle of v lies in [s_lo, s_hi]."""
    s0 = geo.s_entry[v.direction]
    return v.t_axle[0] + (s_lo - s0) / v.speed, v.t_axle[-1] + (s_hi - s0) / v.speed


def calibration_runs(
    rec: Record,
    vehicles: list[Vehicle],
    cal_truth: list[dict],
    geo: Geometry,
    args,
    others: list[Vehicle] | None = None,
):
    """The detections that are the calibration truck's runs, alone on the bridge, and the
    geometry with the FAD distance calibrated on them: each run's speed from its known
    axle spacings (least squares of its axle times against them) times its measured delay
    between the supports' steps, median over the runs of a direction."""
    L = rec.span_m
    runs = []
    for tr in cal_truth:
        t_entry = (tr["entry_ns"] - rec.t0_ns) / 1e9
        best = None
        for v in vehicles:
            if v.direction != tr["direction"] or len(v.t_axle) != len(tr["loads_n"]):
                continue
            dt = abs(v.t_axle[0] - geo.s_entry[v.direction] / v.speed - t_entry)
            if dt < args.cal_match_s and (best is None or dt < best[0]):
                best = (dt, v)
        if best is not None:
            runs.append((tr, best[1]))
    clean = []
    others = vehicles if others is None else others
    for tr, v in runs:
        a, b = occupancy(v, geo, -2.0, L + 2.0)
        if not any(
            o is not v and occupancy(o, geo, -2.0, L + 2.0)[0] < b and occupancy(o, geo, -2.0, L + 2.0)[1] > a
            for o in others
        ):
            clean.append((tr, v))
    directions = {v.direction for v in vehicles}
    if not clean or not {tr["direction"] for tr, _ in clean} >= directions:
        raise ValueError(
            f"calibration: {len(clean)} usable calibration runs (found {len(runs)} of {len(cal_truth)} known vehicles); need runs alone on the bridge in each direction of the traffic"
        )
    distance = dict(geo.distance)
    for direction in (1, -1):
        ds = []
        for tr, v in clean:
            if v.direction == direction and len(tr["spacings_m"]):
                cum = np.concatenate([[0.0], np.cumsum(tr["spacings_m"])])
                v_true = 1.0 / np.polyfit(cum, v.t_axle, 1)[0]
                ds.append(distance[direction] * v_true / v.speed)  # D = v_true * delay
        if ds:
            distance[direction] = float(np.median(ds))
    return clean, Geometry(L, dict(geo.s_entry), distance)


def nuisance(t: np.ndarray, f1: float | None) -> np.ndarray:
    """Columns a record may carry besides the vehicles' static response: the baseline and,
    with f1, the bridge's first-mode vibration, cos and sin at f1 with linearly varying
    amplitudes (free and forced vibration over one crossing)."""
    cols = [np.ones_like(t)]
    if f1:
        tc = (t - t.mean()) / max(t.max() - t.min(), 1e-9)
        c, s = np.cos(2 * np.pi * f1 * t), np.sin(2 * np.pi * f1 * t)
        cols += [c, s, tc * c, tc * s]
    return np.column_stack(cols)


def run_normals(rec: Record, tr: dict, v: Vehicle, geo: Geometry, s_grid: np.ndarray, args, f1: float | None = None):
    """One calibration run's share of the influence-line normal equations, with its baseline
    offset eliminated (Schur complement): (M [ng, ng], g [ng, n_sections]). The run's speed
    comes from its known spacings, its axle positions from the measured axle times."""
    ng = len(s_grid)
    Y = weighing_signals(rec, args.fad_max_m)[1]
    cum = np.concatenate([[0.0], np.cumsum(tr["spacings_m"])])
    slope, icpt = np.polyfit(cum, v.t_axle, 1)
    vv = Vehicle(v.direction, icpt + slope * cum, 1.0 / slope)
    a, b = occupancy(vv, geo, s_grid[0], s_grid[-1])
    k0 = max(int(math.floor((a - args.pad_s) * rec.fs_hz)), 0)
    k1 = min(int(math.ceil((b + args.pad_s) * rec.fs_hz)), len(Y))
    t = np.arange(k0, k1) / rec.fs_hz
    ok = np.isfinite(Y[k0:k1]).all(axis=1)
    s = axle_positions(vv, t[ok], geo)
    n = int(ok.sum())
    rows, cols, vals = [], [], []
    rr = np.arange(n)
    for i, load in enumerate(tr["loads_n"] / 1e3):
        j, wl, wr = hat_matrix(s[:, i], s_grid)
        rows += [rr, rr]
        cols += [j, j + 1]
        vals += [load * wl, load * wr]
    A = sparse.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(n, ng)).toarray()
    Z = nuisance(t[ok], f1)
    Yk = Y[k0:k1][ok]
    # Eliminate the run's nuisance columns (Schur complement).
    NZZ = Z.T @ Z
    P = np.linalg.solve(NZZ, Z.T)  # (Z^T Z)^-1 Z^T
    AZ = A.T @ Z
    M = A.T @ A - AZ @ (P @ A)
    g = A.T @ Yk - AZ @ (P @ Yk)
    return M, g


def solve_il(parts: list, ng: int, smoothing: float) -> np.ndarray:
    """Influence-line ordinates [n_sections, ng] from the runs' normal equations, with a
    second-difference penalty scaled to the data."""
    M = sum(m for m, _ in parts)
    g = sum(gg for _, gg in parts)
    D2 = np.zeros((ng - 2, ng))
    idx = np.arange(ng - 2)
    D2[idx, idx], D2[idx, idx + 1], D2[idx, idx + 2] = 1.0, -2.0, 1.0
    lam = smoothing * float(np.mean(np.diag(M)))
    return np.linalg.solve(M + lam * (D2.T @ D2) + 1e-12 * float(np.trace(M)) / ng * np.eye(ng), g).T


def calibrate(rec: Record, clean: list, geo: Geometry, args) -> tuple[Calibration, dict]:
    """Influence lines by the matrix method from the calibration runs; also the runs'
    normal equations, for leave-one-out."""
    L = rec.span_m
    positions, Y = weighing_signals(rec, args.fad_max_m)
    s_grid = np.arange(-args.il_margin_m, L + args.il_margin_m + 1e-9, args.il_step_m)
    ng = len(s_grid)
    f1 = first_frequency(rec, args.fad_max_m) if args.vibration_terms else None
    parts = {tr["id"]: (v.direction, run_normals(rec, tr, v, geo, s_grid, args, f1)) for tr, v in clean}
    il = {}
    for direction in (1, -1):
        mine = [p for d, p in parts.values() if d == direction]
        if mine:
            il[direction] = solve_il(mine, ng, args.il_smoothing)
    # A direction without calibration run borrows the mirror of the other (a symmetric
    # girder and gauges).
    for direction in (1, -1):
        if direction not in il:
            other = il[-direction]
            il[direction] = np.array([np.interp(L - s_grid, s_grid, other[c]) for c in range(len(positions))])
    noise = np.array([section_noise(Y[:, c]) for c in range(Y.shape[1])])
    cal = Calibration(geo, s_grid, positions, il, noise, rec.ids, sorted(parts), rec.path)
    return cal, parts


def leave_one_out(cal: Calibration, parts: dict, run_id: int, smoothing: float) -> Calibration:
    """The calibration without one run (its direction's influence lines re-solved)."""
    direction = parts[run_id][0]
    others = [p for k, (d, p) in parts.items() if d == direction and k != run_id]
    if not others:
        raise ValueError("no other run in that direction")
    il = dict(cal.il)
    il[direction] = solve_il(others, len(cal.s_grid), smoothing)
    return Calibration(
        cal.geometry,
        cal.s_grid,
        cal.sections_m,
        il,
        cal.noise,
        cal.gauge_ids,
        [k for k in cal.runs_used if k != run_id],
        cal.source,
    )


# --------------------------------------------------------------------------- weighing


def clusters_of(vehicles: list[Vehicle], cal: Calibration) -> list[list[Vehicle]]:
    """Vehicles whose influence spans overlap in time, in groups (multiple presence)."""
    s_lo, s_hi = cal.s_grid[0], cal.s_grid[-1]
    spans = sorted(((*occupancy(v, cal.geometry, s_lo, s_hi), v) for v in vehicles), key=lambda x: x[0])
    out, end = [], -np.inf
    for a, b, v in spans:
        if out and a < end:
            out[-1].append(v)
            end = max(end, b)
        else:
            out.append([v])
            end = b
    return out


def moses(
    rec: Record,
    sections,
    cal: Calibration,
    group: list[Vehicle],
    pad_s: float,
    group_penalty: float = 0.0,
    f1: float | None = None,
) -> float:
    """Axle loads of the vehicles of one cluster by least squares (Moses 1979): every
    weighing section stacked (weighted by the inverse of its noise), each with its own
    nuisance columns (baseline, and with f1 the first mode's vibration). Returns the fit's
    relative residual (rms residual over rms of the vehicles' modelled strain)."""
    s_lo, s_hi = cal.s_grid[0], cal.s_grid[-1]
    a = min(occupancy(v, cal.geometry, s_lo, s_hi)[0] for v in group) - pad_s
    b = max(occupancy(v, cal.geometry, s_lo, s_hi)[1] for v in group) + pad_s
    k0, k1 = max(int(math.floor(a * rec.fs_hz)), 0), min(int(math.ceil(b * rec.fs_hz)), rec.values.shape[0])
    t = np.arange(k0, k1) / rec.fs_hz
    n_axles = sum(len(v.t_axle) for v in group)
    positions = [axle_positions(v, t, cal.geometry) for v in group]
    Z_all = nuisance(t, f1)
    nz = Z_all.shape[1]
    nsec = len(sections)
    nu = n_axles + nz * nsec
    AtA = np.zeros((nu, nu))
    Atb = np.zeros(nu)
    kept = []
    for c, (_, y) in enumerate(sections):
        ok = np.isfinite(y[k0:k1])
        rows = np.zeros((int(ok.sum()), nu))
        col = 0
        for v, s in zip(group, positions, strict=True):
            il = cal.il[v.direction][c]
            for i in range(len(v.t_axle)):
                rows[:, col] = np.interp(s[ok, i], cal.s_grid, il, left=0.0, right=0.0)
                col += 1
        rows[:, n_axles + nz * c : n_axles + nz * (c + 1)] = Z_all[ok]
        w2 = 1.0 / cal.noise[c] ** 2
        AtA += w2 * rows.T @ rows
        Atb += w2 * rows.T @ y[k0:k1][ok]
        kept.append((rows, y[k0:k1][ok]))
    if group_penalty > 0:
        # Tikhonov penalty on the differences of neighbouring axles of a group (spacing
        # < 2.1 m): the least squares barely tell such axles apart (module doc).
        scale = group_penalty * float(np.mean(np.diag(AtA)[:n_axles]))
        col = 0
        for v in group:
            for i, sp in enumerate(v.spacings):
                if sp < GROUP_SPACING_MAX_M:
                    d = np.zeros(nu)
                    d[col + i], d[col + i + 1] = 1.0, -1.0
                    AtA += scale * np.outer(d, d)
            col += len(v.t_axle)
    try:
        sol = np.linalg.solve(AtA, Atb)
    except np.linalg.LinAlgError:
        sol = np.linalg.lstsq(AtA, Atb, rcond=None)[0]
    col = 0
    for v in group:
        v.loads_n = sol[col : col + len(v.t_axle)] * 1e3
        col += len(v.t_axle)
    # Fit quality: the residual's energy relative to the vehicles' modelled response.
    res = sum(float(np.sum((yy - rows @ sol) ** 2)) for rows, yy in kept)
    sig = sum(float(np.sum((rows[:, :n_axles] @ sol[:n_axles]) ** 2)) for rows, _ in kept)
    return math.sqrt(res / max(sig, 1e-30))


def weigh(
    rec: Record, vehicles: list[Vehicle], cal: Calibration, args, f1: float | None
) -> tuple[list[list[Vehicle]], list[Vehicle]]:
    """Every cluster weighed (jointly); detections lighter than --min-gross-kn are no
    vehicles (a rebound taken for a vehicle, a fragment): dropped and the cluster weighed
    again. A cluster whose fit leaves a relative residual above --max-residual (a vehicle
    the FAD gauges missed, a wrong axle count) is flagged and not weighed. Returns the
    clusters and the dropped detections."""
    sections = weighing_sections(rec, args.fad_max_m)
    if [round(p, 2) for p, _ in sections] != [round(p, 2) for p in cal.sections_m]:
        raise ValueError(f"the calibration's sections {cal.sections_m} are not this run's {[p for p, _ in sections]}")
    groups = clusters_of(vehicles, cal)
    dropped = []
    out = []
    for group in groups:
        if len(group) > 1 and args.multiple_presence == "skip":
            out.append(group)
            continue
        residual = None
        while group:
            residual = moses(rec, sections, cal, group, args.pad_s, args.group_penalty, f1)
            light = [v for v in group if v.loads_n.sum() < args.min_gross_kn * 1e3]
            if not light:
                break
            worst = min(light, key=lambda v: v.loads_n.sum())
            worst.loads_n = None
            dropped.append(worst)
            group = [v for v in group if v is not worst]
        for v in group:
            v.residual = residual
            if residual is not None and residual > args.max_residual:
                v.loads_n = None
                v.poor_fit = True
        if group:
            out.append(group)
    for k, group in enumerate(out):
        for v in group:
            v.cluster, v.cluster_size = k, len(group)
    return out, dropped


# --------------------------------------------------------------------------- COST 323


def pi0(n: int, conditions: str, alpha: float = ALPHA) -> float:
    """Minimum level of confidence for n values under the test conditions (module doc)."""
    rep, env = conditions.split("-")
    u_inf = stats.norm.ppf(0.5 * (1.0 + PI_INF[(rep, env)] / 100.0))
    nu = n - 1
    return float(2.0 * stats.norm.cdf(u_inf * math.sqrt(nu / stats.chi2.ppf(1.0 - alpha, nu))) - 1.0)


def pi_level(m: float, s: float, delta: float) -> float:
    """Level of confidence of [-delta, delta] for normal errors of mean m and sd s."""
    return float(stats.norm.cdf((delta - m) / s) - stats.norm.cdf((-delta - m) / s))


def assess(errors: np.ndarray, criterion: int, conditions: str) -> dict:
    """The COST 323 class reached by one criterion's relative errors (fractions)."""
    e = 100.0 * np.asarray(errors, float)
    n = len(e)
    out = {"n": n, "mean_pct": float(e.mean()) if n else None, "std_pct": float(e.std(ddof=1)) if n > 1 else None}
    if n < 5:
        out.update(pi0=None, delta_min_pct=None, class_reached=None, note="fewer than 5 values")
        return out
    m, s = float(e.mean()), max(float(e.std(ddof=1)), 1e-9)
    p0 = pi0(n, conditions)
    dmin = brentq(lambda d: pi_level(m, s, d) - p0, 1e-9, abs(m) + 50.0 * s)
    reached = next((c for c in CLASSES if TOLERANCE_PCT[c][criterion] >= dmin), BELOW)
    out.update(
        pi0=p0,
        delta_min_pct=dmin,
        class_reached=reached,
        tests={
            c: {
                "delta_pct": TOLERANCE_PCT[c][criterion],
                "pi": pi_level(m, s, TOLERANCE_PCT[c][criterion]),
                "accepted": pi_level(m, s, TOLERANCE_PCT[c][criterion]) >= p0,
            }
            for c in CLASSES
        },
    )
    return out


def class_rank(name: str | None) -> int:
    return CLASSES.index(name) if name in CLASSES else len(CLASSES)


# --------------------------------------------------------------------------- scoring


def match_truth(rec: Record, vehicles: list[Vehicle], truth: list[dict], geo: Geometry, tol_s: float) -> None:
    """Each detection to the truth vehicle of its direction entering nearest in time."""
    pairs = []
    for v in vehicles:
        t_in = v.t_axle[0] - geo.s_entry[v.direction] / v.speed
        for k, tr in enumerate(truth):
            if tr["direction"] == v.direction:
                dt = abs((tr["entry_ns"] - rec.t0_ns) / 1e9 - t_in)
                if dt <= tol_s:
                    pairs.append((dt, v.index, k))
    used_v, used_t = set(), set()
    for _, vi, k in sorted(pairs):
        if vi not in used_v and k not in used_t:
            vehicles[vi].truth = truth[k]
            used_v.add(vi)
            used_t.add(k)


def groups_of(spacings: np.ndarray) -> list[list[int]]:
    out = [[0]]
    for i, s in enumerate(spacings):
        if s < GROUP_SPACING_MAX_M:
            out[-1].append(i + 1)
        else:
            out.append([i + 1])
    return out


def vehicle_errors(v: Vehicle) -> dict:
    tr = v.truth
    row = {
        "truth_id": tr["id"],
        "class": tr["class"],
        "direction": v.direction,
        "cluster_size": v.cluster_size,
        "axles_detected": len(v.t_axle),
        "axles_true": len(tr["loads_n"]),
        "speed_m_s": v.speed,
        "speed_error": v.speed / tr["speed_m_s"] - 1.0,
        "gross_true_n": tr["gross_n"],
        "residual": v.residual,
    }
    if v.loads_n is None:
        row["weighed"] = False
        row["not_weighed"] = "poor fit" if v.poor_fit else "multiple presence"
        return row
    row.update(weighed=True, gross_n=float(v.loads_n.sum()), gross_error=float(v.loads_n.sum() / tr["gross_n"] - 1.0))
    if len(v.t_axle) == len(tr["loads_n"]):
        row["axle_errors"] = (v.loads_n / tr["loads_n"] - 1.0).tolist()
        row["spacing_errors_m"] = (v.spacings - tr["spacings_m"]).tolist()
        g_err, s_err, a_err = [], [], []
        for g in groups_of(tr["spacings_m"]):
            est, true = v.loads_n[g].sum(), tr["loads_n"][g].sum()
            if len(g) >= 2:
                g_err.append(est / true - 1.0)
                a_err += [float(v.loads_n[i] / tr["loads_n"][i] - 1.0) for i in g]
            else:
                s_err.append(est / true - 1.0)
        row.update(group_errors=g_err, single_errors=s_err, axle_of_group_errors=a_err)
    return row


def criterion_errors(rows: list[dict]) -> list[np.ndarray]:
    gross = [r["gross_error"] for r in rows if r.get("weighed")]
    group = [e for r in rows for e in r.get("group_errors", [])]
    single = [e for r in rows for e in r.get("single_errors", [])]
    axle = [e for r in rows for e in r.get("axle_of_group_errors", [])]
    return [np.array(x) for x in (gross, group, single, axle)]


def score_table(rows: list[dict], conditions: str) -> dict:
    return {
        name: assess(errs, c, conditions)
        for c, (name, errs) in enumerate(zip(CRITERIA, criterion_errors(rows), strict=True))
    }


def print_table(title: str, table: dict) -> None:
    print(title)
    print("  criterion         n   mean %   std %    pi0 %  delta_min %  class reached")
    for name, r in table.items():
        if r["n"] < 5:
            print(f"  {name:<16} {r['n']:>3}   (fewer than 5 values)")
            continue
        print(
            f"  {name:<16} {r['n']:>3}  {r['mean_pct']:>+6.2f}  {r['std_pct']:>6.2f}  {100 * r['pi0']:>6.1f}  {r['delta_min_pct']:>10.2f}   {r['class_reached']}"
        )


# --------------------------------------------------------------------------- plot


def plot(path: str, cal: Calibration, rows: list[dict], table: dict, title: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(2, 2, figsize=(11, 8))
    for direction, style in ((1, "-"), (-1, "--")):
        for c, p in enumerate(cal.sections_m):
            ax[0, 0].plot(
                cal.s_grid, cal.il[direction][c], style, color=f"C{c}", label=f"x = {p:g} m, dir {direction:+d}"
            )
    ax[0, 0].set(
        xlabel="axle position from the entry support s (m)",
        ylabel="influence line (microstrain / kN)",
        title="calibrated influence lines (matrix method)",
    )
    ax[0, 0].legend(fontsize=7)
    w = [r for r in rows if r.get("weighed")]
    single = [r for r in w if r["cluster_size"] == 1]
    multi = [r for r in w if r["cluster_size"] > 1]
    for sel, lab, mk in ((single, "alone on the bridge", "o"), (multi, "multiple presence (joint)", "x")):
        if sel:
            ax[0, 1].plot(
                [r["gross_true_n"] / 1e3 / G for r in sel],
                [r["gross_n"] / 1e3 / G for r in sel],
                mk,
                label=f"{lab} ({len(sel)})",
            )
    if w:
        hi = max(r["gross_true_n"] for r in w) / 1e3 / G * 1.1
        ax[0, 1].plot([0, hi], [0, hi], "k-", lw=0.8)
    ax[0, 1].set(xlabel="static gross weight (t)", ylabel="B-WIM gross weight (t)", title="gross weight")
    ax[0, 1].legend(fontsize=8)
    e = 100 * np.array([r["gross_error"] for r in w]) if w else np.array([])
    if len(e):
        ax[1, 0].hist(e, bins=max(8, len(e) // 5), color="C0", alpha=0.8)
    g = table["gross"]
    for c, col in (("A(5)", "C2"), ("B+(7)", "C1"), ("B(10)", "C3")):
        d = TOLERANCE_PCT[c][0]
        ax[1, 0].axvspan(-d, d, color=col, alpha=0.08)
        ax[1, 0].axvline(d, color=col, lw=0.8, label=f"{c}: +/-{d:g} %")
        ax[1, 0].axvline(-d, color=col, lw=0.8)
    t = (
        f"gross error: mean {g['mean_pct']:+.2f} %, sd {g['std_pct']:.2f} %, class {g.get('class_reached')}"
        if g["n"] >= 5
        else "gross error"
    )
    ax[1, 0].set(xlabel="gross weight error (%)", ylabel="vehicles", title=t)
    ax[1, 0].legend(fontsize=8)
    if w:
        ax[1, 1].plot([r["speed_m_s"] for r in single], [100 * r["gross_error"] for r in single], "o", label="alone")
        ax[1, 1].plot(
            [r["speed_m_s"] for r in multi], [100 * r["gross_error"] for r in multi], "x", label="multiple presence"
        )
    ax[1, 1].axhline(0, color="k", lw=0.8)
    ax[1, 1].set(xlabel="measured speed (m/s)", ylabel="gross weight error (%)", title="error against speed")
    ax[1, 1].legend(fontsize=8)
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


# --------------------------------------------------------------------------- main


def run(args) -> int:
    t_start = time.perf_counter()
    try:
        rec = read_strains(args.run)
    except Exception as e:  # noqa: BLE001 - a file the readers cannot read is bad input
        print(f"bwim_check: {type(e).__name__}: {e}", file=sys.stderr)
        return 2
    t_read = time.perf_counter() - t_start
    try:
        cal = None
        geo = None
        if args.calibration_from:
            cal = Calibration.from_json(json.loads(Path(args.calibration_from).read_text()))
            geo = cal.geometry
        vehicles, det, geo = detect_vehicles(rec, geo, args)
        if not vehicles:
            raise ValueError("no vehicle detected by the FAD gauges")
        truth = None
        loo = []
        if cal is None:
            # The calibration truck's weighbridge ticket: its static loads and spacings.
            truth = read_truth(args.run)
            ids = args.calibration_ids if args.calibration_ids is not None else rec.listed_vehicle_ids
            cal_truth = [tr for tr in truth if tr["id"] in set(ids)]
            if not cal_truth:
                raise ValueError(f"no calibration vehicle (ids {ids}) in {TRUTH_VEHICLES}")
            _, geo = calibration_runs(rec, vehicles, cal_truth, geo, args, others=[])
            vehicles, det, geo = detect_vehicles(rec, geo, args)  # with the calibrated distance
            # The runs alone on the bridge: a first calibration on every run weighs the
            # detections, so that rebounds taken for vehicles (lighter than --min-gross-kn)
            # do not disqualify a run.
            f1 = det["f1_hz"] if args.vibration_terms else None
            every, geo = calibration_runs(rec, vehicles, cal_truth, geo, args, others=[])
            _, dropped = weigh(rec, vehicles, calibrate(rec, every, geo, args)[0], args, f1)
            real = [v for v in vehicles if all(v is not d for d in dropped)]
            for v in vehicles:
                v.loads_n = None
            clean, geo = calibration_runs(rec, vehicles, cal_truth, geo, args, others=real)
            cal, parts = calibrate(rec, clean, geo, args)
            # Leave-one-out: each calibration run weighed with the others' influence lines.
            sections = weighing_sections(rec, args.fad_max_m)
            for tr, v in clean:
                try:
                    cal_k = leave_one_out(cal, parts, tr["id"], args.il_smoothing)
                except ValueError:
                    continue
                moses(
                    rec,
                    sections,
                    cal_k,
                    [v],
                    args.pad_s,
                    args.group_penalty,
                    det["f1_hz"] if args.vibration_terms else None,
                )
                v.truth = tr
                loo.append(vehicle_errors(v))
                v.truth, v.loads_n = None, None
        groups, dropped = weigh(rec, vehicles, cal, args, det["f1_hz"] if args.vibration_terms else None)
        vehicles = [v for v in vehicles if all(v is not d for d in dropped)]
        for k, v in enumerate(vehicles):
            v.index = k
    except ValueError as e:
        print(f"bwim_check: {e}", file=sys.stderr)
        return 2
    t_process = time.perf_counter() - t_start
    if args.save_calibration:
        Path(args.save_calibration).write_text(json.dumps(cal.to_json(), indent=1))
    # ---- only now the truth of the traffic
    if truth is None:
        truth = read_truth(args.run)
    # The scenario's listed vehicles (the calibration truck's runs) are no traffic.
    listed = set(rec.listed_vehicle_ids) | set(args.calibration_ids or [])
    match_truth(rec, vehicles, truth, geo, args.match_truth_s)
    scored = [
        v
        for v in vehicles
        if v.truth is not None and v.truth["id"] not in listed and v.truth["gross_n"] > DOMAIN_GROSS_N
    ]
    rows = [vehicle_errors(v) for v in scored]
    table = score_table(rows, args.conditions)
    loo_table = score_table(loo, "r2-I") if loo else None
    heavy_truth = [tr for tr in truth if tr["gross_n"] > DOMAIN_GROSS_N and tr["id"] not in listed]
    duration = rec.values.shape[0] / rec.fs_hz
    matched_ids = {v.truth["id"] for v in vehicles if v.truth is not None}
    multi_clusters = [g for g in groups if len(g) > 1]
    light = [v for v in vehicles if v.truth is not None and v.truth["gross_n"] <= DOMAIN_GROSS_N]
    false_det = [v for v in vehicles if v.truth is None]
    missed = [
        tr
        for tr in heavy_truth
        if tr["id"] not in matched_ids
        and (tr["entry_ns"] - rec.t0_ns) / 1e9 < duration - 3.0
        and (tr["entry_ns"] - rec.t0_ns) / 1e9 > 1.0
    ]
    weighed = [r for r in rows if r.get("weighed")]
    if not weighed:
        print(
            f"bwim_check: no traffic vehicle over 3.5 t was detected and weighed ({len(heavy_truth)} in the truth)",
            file=sys.stderr,
        )
        return 2
    gross = table["gross"]
    ok = gross.get("class_reached") is not None and class_rank(gross["class_reached"]) <= class_rank(args.expect_class)
    # ---- report
    print(
        f"{args.run}: {len(rec.ids)} strain gauges at {rec.fs_hz:g} Hz, {duration:.1f} s, span {rec.span_m:g} m, {rec.lost} lost samples; read in {t_read:.2f} s, processed in {t_process:.2f} s ({t_process / max(duration, 1e-9) * 3600:.1f} s per hour of data)"
    )
    src = (
        f"from {args.calibration_from} ({cal.source})"
        if args.calibration_from
        else f"on runs {cal.runs_used} (vehicles of known weight)"
    )
    print(
        f"calibration {src}: FAD distance {cal.geometry.distance[1]:.3f} m (+1), {cal.geometry.distance[-1]:.3f} m (-1); weighing sections at {cal.sections_m} m"
    )
    print(
        f"detected {len(vehicles)} vehicles ({det['unconfirmed_groups']} entry groups unconfirmed at the exit, {len(dropped)} detections lighter than {args.min_gross_kn:g} kN dropped); FAD noise {det['fad_noise_microstrain']['W']:.3f} / {det['fad_noise_microstrain']['E']:.3f} microstrain (step filter)"
    )
    print(
        f"multiple presence: {len(multi_clusters)} events with {sum(len(g) for g in multi_clusters)} vehicles ({'solved jointly' if args.multiple_presence == 'joint' else 'not weighed'}); scored vehicles in them: {sum(1 for r in weighed if r['cluster_size'] > 1)}"
    )
    print(
        f"truth: {len(heavy_truth)} vehicles > 3.5 t in the traffic: {len(rows)} detected, {len(weighed)} weighed and scored ({sum(1 for r in rows if r.get('not_weighed') == 'multiple presence')} in multiple presence not weighed, {sum(1 for r in rows if r.get('not_weighed') == 'poor fit')} flagged for a poor fit), {len(missed)} missed; {len(light)} detections of lighter vehicles and {len(false_det)} unmatched detections not scored"
    )
    axle_ok = sum(1 for r in rows if r["axles_detected"] == r["axles_true"])
    print(
        f"axle count right for {axle_ok} of {len(rows)} detected; speed error {100 * np.mean([r['speed_error'] for r in rows]) if rows else float('nan'):+.2f} % mean, {100 * np.std([r['speed_error'] for r in rows]) if rows else float('nan'):.2f} % sd"
    )
    if loo_table:
        print_table(f"calibration runs, leave-one-out (r2-I, {len(loo)} runs):", loo_table)
    print_table(f"traffic, COST 323 conditions {args.conditions}:", table)
    verdict = "PASS" if ok else "FAIL"
    print(f"{verdict}: gross weight class {gross.get('class_reached')} (expected {args.expect_class} or better)")
    if args.json:
        Path(args.json).write_text(
            json.dumps(
                {
                    "run": args.run,
                    "duration_s": duration,
                    "fs_hz": rec.fs_hz,
                    "read_s": t_read,
                    "process_s": t_process,
                    "calibration": cal.to_json(),
                    "detection": det,
                    "conditions": args.conditions,
                    "vehicles_detected": len(vehicles),
                    "detections_dropped": len(dropped),
                    "truth_over_3_5t": len(heavy_truth),
                    "detected_over_3_5t": len(rows),
                    "scored": len(weighed),
                    "poor_fit": sum(1 for r in rows if r.get("not_weighed") == "poor fit"),
                    "missed": len(missed),
                    "light_detections": len(light),
                    "unmatched_detections": len(false_det),
                    "multiple_presence_events": len(multi_clusters),
                    "multiple_presence_vehicles": sum(len(g) for g in multi_clusters),
                    "scored_in_multiple_presence": sum(1 for r in weighed if r["cluster_size"] > 1),
                    "axle_count_right": axle_ok,
                    "criteria": table,
                    "calibration_leave_one_out": loo_table,
                    "expect_class": args.expect_class,
                    "pass": ok,
                    "vehicles": rows,
                    "calibration_runs": loo,
                },
                indent=1,
                default=float,
            )
        )
    if args.plot:
        plot(
            args.plot,
            cal,
            weighed,
            table,
            f"B-WIM of {Path(args.run).name}: {len(weighed)} vehicles > 3.5 t weighed, conditions {args.conditions}",
        )
    return 0 if ok else 1


def parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("run", help="bridgetwin MCAP file (or, with the bridgetwin package, a glob of hourly parts)")
    p.add_argument(
        "--expect-class",
        default="D+(20)",
        choices=CLASSES,
        help="exit 1 unless the gross weight reaches this class (D+(20))",
    )
    p.add_argument(
        "--conditions",
        default="R2-I",
        choices=[f"{r}-{e}" for r, e in PI_INF],
        help="COST 323 test conditions of the traffic sample (R2-I)",
    )
    p.add_argument(
        "--calibration-ids",
        type=lambda s: [int(x) for x in s.split(",") if x],
        help="vehicle ids of the calibration runs (default: the scenario's [[vehicles]])",
    )
    p.add_argument(
        "--calibration-from", help="use this calibration file (from --save-calibration) instead of calibrating"
    )
    p.add_argument("--save-calibration", help="write the calibration (influence lines, FAD distance) here")
    p.add_argument(
        "--multiple-presence",
        choices=["joint", "skip"],
        default="joint",
        help="vehicles on the bridge together: solved jointly (default) or not weighed",
    )
    p.add_argument("--fad-max-m", type=float, default=1.0, help="gauges this close to a support are FAD gauges (1.0 m)")
    p.add_argument("--fad-window-s", type=float, default=0.02, help="half length of the step filter (0.02 s)")
    p.add_argument("--fad-threshold", type=float, default=5.0, help="step detection threshold in noise sd (5)")
    p.add_argument(
        "--no-mode2-cancel",
        dest="cancel_mode2",
        action="store_false",
        help="keep the bridge's second mode in the FAD records",
    )
    p.add_argument(
        "--trend-window-s", type=float, default=0.5, help="running median removed from the step records (0.5 s)"
    )
    p.add_argument(
        "--lobe-s", type=float, default=0.1, help="a step's rebound of the other sign within this is no step (0.1 s)"
    )
    p.add_argument(
        "--axle-threshold",
        type=float,
        default=4.0,
        help="axle threshold on the sum of both ends' steps, in its noise sd (4)",
    )
    p.add_argument("--end-threshold", type=float, default=2.5, help="each end's step at an axle, in its noise sd (2.5)")
    p.add_argument(
        "--min-correlation", type=float, default=0.5, help="entry and exit step records must correlate this well (0.5)"
    )
    p.add_argument("--min-spacing-m", type=float, default=0.9, help="closest two axles of a vehicle (0.9 m)")
    p.add_argument("--max-spacing-m", type=float, default=8.0, help="farthest two consecutive axles of a vehicle (8 m)")
    p.add_argument(
        "--max-residual",
        type=float,
        default=0.3,
        help="a fit leaving more relative residual is flagged and not weighed (0.3)",
    )
    p.add_argument(
        "--min-gross-kn",
        type=float,
        default=10.0,
        help="a detection weighing less is no vehicle: dropped and its cluster weighed again (10 kN)",
    )
    p.add_argument("--min-axle-sep-s", type=float, default=0.025, help="closest two axles' steps (0.025 s)")
    p.add_argument(
        "--max-axle-gap-s", type=float, default=0.6, help="a longer gap between axle steps starts a new vehicle (0.6 s)"
    )
    p.add_argument("--v-min", type=float, default=5.0, help="slowest speed searched (5 m/s)")
    p.add_argument("--v-max", type=float, default=45.0, help="fastest speed searched (45 m/s)")
    p.add_argument("--il-step-m", type=float, default=0.1, help="node spacing of the influence lines (0.1 m)")
    p.add_argument(
        "--il-margin-m", type=float, default=1.0, help="influence lines extend this far beyond the supports (1.0 m)"
    )
    p.add_argument(
        "--il-smoothing", type=float, default=1e-3, help="second-difference penalty, relative to the data (1e-3)"
    )
    p.add_argument(
        "--group-penalty",
        type=float,
        default=0.0,
        help="Tikhonov penalty on load differences inside axle groups, relative (0: plain Moses)",
    )
    p.add_argument(
        "--no-vibration-terms",
        dest="vibration_terms",
        action="store_false",
        help="no first-mode vibration columns in the least squares",
    )
    p.add_argument("--pad-s", type=float, default=0.3, help="record kept before and after a vehicle's crossing (0.3 s)")
    p.add_argument(
        "--cal-match-s",
        type=float,
        default=1.0,
        help="a calibration run is the detection within this of its logged entry (1.0 s)",
    )
    p.add_argument(
        "--match-truth-s", type=float, default=0.25, help="detection and truth entry times agree to (0.25 s)"
    )
    p.add_argument("--json", help="write the results here")
    p.add_argument("--plot", help="write an SVG figure here")
    return p


def main(argv: list[str]) -> int:
    return run(parser().parse_args(argv))


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
