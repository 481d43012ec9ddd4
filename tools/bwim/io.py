"""Reading a run as an operator's files: the strain records on one time grid (with the
gauges' positions and the span from the metadata), the road axle detectors' hits (with
their measured positions), and, for the calibration truck and the scoring only, the truth."""

from __future__ import annotations

import math
import sys
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

STRAIN_PREFIX = "/sensors/strain/"
AXLE_PREFIX = "/sensors/axle/"
TRUTH_VEHICLES = "/truth/vehicles"
TRUTH_AXLE_DETECTIONS = "/truth/axle_detections"
TOOLS = Path(__file__).resolve().parent.parent


def _tools_on_path() -> None:
    """tools/ importable (read_run.py, the fallback reader)."""
    sys.path.insert(0, str(TOOLS))


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
        _tools_on_path()
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
        _tools_on_path()
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


# --------------------------------------------------------------------------- axle detectors


@dataclass
class AxleDetector:
    """One road axle detector (tape switch): what its installer measured and its hits."""

    id: str
    position_m: float  # on the road axis, the bridge's x (negative on the approach)
    lane: int | None  # the lane it spans; None: every lane
    jitter_s: float
    miss_probability: float
    times_s: np.ndarray  # the detector's time of each hit, s after the strain grid's sample 0


def _lane(value) -> int | None:
    try:
        return int(value)
    except (TypeError, ValueError):
        return None


def _float(value, default: float) -> float:
    try:
        return float(value)
    except (TypeError, ValueError):
        return default


def read_axle_detectors(path: str, t0_ns: int) -> list[AxleDetector]:
    """Every road axle detector of the run (``/sensors/axle/<id>``): its hits' detected times
    on the strain grid's time axis and its channel metadata (position, lane, jitter)."""
    bt = _reader()
    if bt is not None:
        run = bt.read(path, topics=AXLE_PREFIX + "*")
        topics = sorted(t for t in run.keys() if t.startswith(AXLE_PREFIX))
        hits = {t: run[t]["detected_time_ns"].to_numpy(np.int64) for t in topics}
        meta = {t: dict(run.channels[t]) for t in topics}
    else:
        _tools_on_path()
        from mcap.reader import make_reader
        from read_run import list_topics, load_topics

        topics = sorted(t for t in list_topics(path) if t.startswith(AXLE_PREFIX))
        arrays = load_topics(path, topics) if topics else {}
        hits = {t: np.asarray(a["detected_time_ns"], np.int64) for t, a in arrays.items()}
        with open(path, "rb") as f:
            summary = make_reader(f).get_summary()
            meta = {c.topic: dict(c.metadata) for c in summary.channels.values() if c.topic in hits}
    out = []
    for t in topics:
        m = meta.get(t, {})
        out.append(
            AxleDetector(
                t[len(AXLE_PREFIX) :],
                _float(m.get("position_m"), math.nan),
                _lane(m.get("lane")),
                _float(m.get("jitter_s"), 0.0),
                _float(m.get("miss_probability"), 0.0),
                np.sort((hits[t] - t0_ns) / 1e9),
            )
        )
    return out


def read_axle_truth(path: str) -> list[dict]:
    """/truth/axle_detections: every crossing of every detector, as dicts (detector_id,
    vehicle_id, axle_index, detected)."""
    bt = _reader()
    if bt is not None:
        run = bt.read(path, topics=TRUTH_AXLE_DETECTIONS)
        if TRUTH_AXLE_DETECTIONS not in run.keys():
            return []
        df = run[TRUTH_AXLE_DETECTIONS]
        cols = {c: df[c].to_numpy() for c in ("detector_id", "vehicle_id", "axle_index", "detected")}
    else:
        _tools_on_path()
        from read_run import list_topics, load_topics

        if TRUTH_AXLE_DETECTIONS not in list_topics(path):
            return []
        a = load_topics(path, [TRUTH_AXLE_DETECTIONS])[TRUTH_AXLE_DETECTIONS]
        cols = {c: a[c] for c in ("detector_id", "vehicle_id", "axle_index", "detected")}
    return [
        {
            "detector_id": str(d),
            "vehicle_id": int(v),
            "axle_index": int(i),
            "detected": bool(k),
        }
        for d, v, i, k in zip(
            cols["detector_id"], cols["vehicle_id"], cols["axle_index"], cols["detected"], strict=True
        )
    ]
