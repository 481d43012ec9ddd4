"""The overview an engineer wants first, for runs of any length.

``overview(run)`` draws, on one figure: a few representative accelerometers; strain and
deflection with each vehicle's time on the bridge shaded; the PSD of an accelerometer with
the true f1 marked; and each vehicle's peak strain against its gross weight. Long series
are drawn as their min/max envelope over a few thousand buckets, so an hour draws in
seconds and no peak is lost to the decimation.
"""

from __future__ import annotations

import os
import warnings
from typing import TYPE_CHECKING, Any, Sequence

import numpy as np

from . import _native

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from ._read import Run

VALUE_COLUMNS = {
    "accel": ("acceleration_m_s2", "m/s²"),
    "strain": ("strain_microstrain", "µε"),
    "disp": ("displacement_m", "m"),
    # /truth/sensors/<id>: the noise-free response at a sensor; its deflection is drawn.
    "sensors": ("displacement_m", "m"),
}


def envelope(t: np.ndarray, y: np.ndarray, buckets: int = 2000) -> tuple[np.ndarray, np.ndarray]:
    """``(t, y)`` reduced to at most ``2 * buckets`` points: each bucket's minimum and
    maximum in time order, so the drawn band covers every sample (NaN gaps skipped)."""
    n = len(y)
    if n <= 2 * buckets:
        return t, y
    k = n // buckets
    m = k * buckets
    yb = y[:m].reshape(buckets, k)
    with warnings.catch_warnings():
        # A bucket inside a data gap is all NaN: it stays NaN (a gap in the line).
        warnings.simplefilter("ignore", RuntimeWarning)
        lo = np.nanmin(yb, axis=1)
        hi = np.nanmax(yb, axis=1)
    t_mid = t[:m].reshape(buckets, k)[:, k // 2]
    return np.repeat(t_mid, 2), np.column_stack([lo, hi]).ravel()


def welch_psd(y: np.ndarray, rate_hz: float, segment: int | None = None) -> tuple[np.ndarray, np.ndarray]:
    """One-sided PSD in units^2/Hz by the project's Welch estimate (Rust: Hann windows,
    50 % overlap, DC and Nyquist bins left out).

    Lost samples (NaN) are set to the mean: they lower the level slightly but do not
    move peaks. ``segment`` defaults to about 20 s of data (at least 256 samples, even,
    at most the record)."""
    y = np.asarray(y, dtype=float)
    finite = np.isfinite(y)
    if finite.sum() < 8:
        return np.array([]), np.array([])
    y = np.where(finite, y, np.mean(y[finite]))
    if segment is None:
        segment = int(2 ** np.ceil(np.log2(max(256, 20 * rate_hz))))
    segment = min(segment, len(y)) // 2 * 2
    return _native.welch_psd(np.ascontiguousarray(y), 1.0 / rate_hz, segment)


def representative_sensors(run: "Run", per_kind: int = 2) -> list[str]:
    """A few sensors of each kind: those nearest midspan and quarter span first."""
    span = _span_m(run)
    chosen: list[str] = []
    for kind in ("accel", "strain", "disp"):
        topics = run.sensors(kind)
        if not topics:
            continue

        def distance(topic: str) -> float:
            x = _float(run.channels[topic].get("position_m"))
            if x is None or span is None:
                return 0.0
            return min(abs(x - span / 2), abs(x - span / 4) + 0.01 * span)

        chosen += sorted(topics, key=distance)[:per_kind]
    return chosen


def overview(
    run: "Run",
    sensors: Sequence[str] | None = None,
    out: str | os.PathLike | None = None,
    buckets: int = 2000,
) -> "Figure":
    """The overview figure of a run (see the module doc); saved to ``out`` if given.

    Args:
        run: a :class:`bridgetwin.Run` (``bridgetwin.read`` or ``bridgetwin.simulate``).
        sensors: the sensor topics to draw; default :func:`representative_sensors`.
        out: a file to save (``.png``, ``.svg``, ``.pdf``).
        buckets: min/max buckets per series (twice as many points drawn at most).
    """
    import matplotlib

    if out is not None and matplotlib.get_backend().lower() not in ("agg", "svg", "pdf"):
        matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    sensors = list(sensors) if sensors is not None else representative_sensors(run)
    accel = [s for s in sensors if s.startswith("/sensors/accel/")]
    response = [s for s in sensors if s.startswith(("/sensors/strain/", "/sensors/disp/"))]
    if not response:
        # No strain gauge or displacement sensor: the true deflection at the chosen
        # accelerometers (their truth streams) still shows each vehicle's passage.
        truth = (f"/truth/sensors/{t.rsplit('/', 1)[1]}" for t in accel)
        response = [t for t in truth if t in run]
    vehicles = _vehicle_windows(run)
    fig, axes = plt.subplot_mosaic(
        [["accel", "accel"], ["response", "response"], ["psd", "peaks"]],
        figsize=(13, 10),
        constrained_layout=True,
    )
    _draw_series(axes["accel"], run, accel, vehicles, buckets, "acceleration (m/s²)")
    _draw_response(axes["response"], run, response, vehicles, buckets)
    if accel:
        axes["response"].sharex(axes["accel"])
    _draw_psd(axes["psd"], run, accel[0] if accel else None)
    _draw_peaks(axes["peaks"], run, response, vehicles)
    title = run.metadata.get("bridge_model", {}).get("model", "")
    fig.suptitle(f"bridgetwin run: {len(run.parts)} file(s), {title}", fontsize=11)
    if out is not None:
        fig.savefig(out, dpi=110)
    return fig


def _series(run: "Run", topic: str) -> tuple[np.ndarray, np.ndarray, str]:
    frame = run[topic]
    kind = topic.split("/")[2]
    column, unit = VALUE_COLUMNS.get(kind, (None, ""))
    if column is None or column not in frame:
        column = next(c for c in frame.columns if c not in ("log_time_ns", "time_s", "timestamp_ns"))
    return frame["time_s"].to_numpy(), frame[column].to_numpy(dtype=float), unit


def _shade(ax: Any, vehicles: list[tuple[float, float, float]]) -> None:
    if vehicles:
        ax.broken_barh(
            [(t0, t1 - t0) for t0, t1, _ in vehicles],
            (0, 1),
            transform=ax.get_xaxis_transform(),
            color="tab:orange",
            alpha=0.12,
            linewidth=0,
            label="vehicle on the bridge",
        )


def _draw_series(ax, run, topics, vehicles, buckets, ylabel):
    for topic in topics:
        t, y, _ = _series(run, topic)
        t, y = envelope(t, y, buckets)
        ax.plot(t, y, linewidth=0.6, label=_label(run, topic))
    _shade(ax, vehicles)
    ax.set_ylabel(ylabel)
    ax.set_xlabel("time (s)")
    if topics:
        ax.legend(loc="upper right", fontsize=8, ncol=min(4, len(topics) + 1))
    else:
        ax.text(0.5, 0.5, "no accelerometer", ha="center", transform=ax.transAxes)


def _draw_response(ax, run, topics, vehicles, buckets):
    strain = [t for t in topics if "/strain/" in t]
    disp = [t for t in topics if "/disp/" in t or t.startswith("/truth/sensors/")]
    for topic in strain:
        t, y, _ = _series(run, topic)
        ax.plot(*envelope(t, y, buckets), linewidth=0.6, label=_label(run, topic))
    ax.set_ylabel("strain (µε)" if strain else "")
    ax.set_xlabel("time (s)")
    handles, labels = ax.get_legend_handles_labels()
    if disp:
        twin = ax.twinx() if strain else ax
        for topic in disp:
            t, y, _ = _series(run, topic)
            twin.plot(*envelope(t, y * 1e3, buckets), linewidth=0.6, linestyle="--", label=_label(run, topic))
        twin.set_ylabel("deflection (mm, down positive)")
        h2, l2 = twin.get_legend_handles_labels()
        if twin is not ax:
            handles, labels = handles + h2, labels + l2
        else:
            handles, labels = h2, l2
    _shade(ax, vehicles)
    if handles:
        ax.legend(handles, labels, loc="upper right", fontsize=8)
    else:
        ax.text(0.5, 0.5, "no strain gauge or displacement sensor", ha="center", transform=ax.transAxes)


def _draw_psd(ax, run, topic):
    if topic is None:
        ax.text(0.5, 0.5, "no accelerometer", ha="center", transform=ax.transAxes)
        return
    t, y, _ = _series(run, topic)
    rate = _float(run.channels[topic].get("sample_rate_hz")) or 1.0 / np.median(np.diff(t))
    f, p = welch_psd(y, rate)
    ax.semilogy(f, p, linewidth=0.8, label=_label(run, topic))
    f1 = _true_f1(run)
    if f1 is not None:
        lo, hi = f1
        if hi - lo > 1e-3 * hi:
            ax.axvspan(lo, hi, color="tab:red", alpha=0.2, label=f"true f1 {lo:.3f}-{hi:.3f} Hz")
        else:
            ax.axvline(lo, color="tab:red", linestyle="--", linewidth=1, label=f"true f1 = {lo:.3f} Hz")
        ax.set_xlim(0, min(f[-1], max(4 * hi, 10)))
    ax.set_xlabel("frequency (Hz)")
    ax.set_ylabel("PSD ((m/s²)²/Hz)")
    ax.legend(fontsize=8)


def _draw_peaks(ax, run, topics, vehicles):
    topic = next((t for t in topics if "/strain/" in t), topics[0] if topics else None)
    if topic is None or not vehicles:
        ax.text(0.5, 0.5, "no vehicles or no response sensor", ha="center", transform=ax.transAxes)
        return
    t, y, unit = _series(run, topic)
    peaks, weights = [], []
    for t0, t1, weight_n in vehicles:
        a, b = np.searchsorted(t, [t0, t1])
        window = y[a:b]
        if window.size and np.isfinite(window).any():
            peaks.append(np.nanmax(np.abs(window)))
            weights.append(weight_n / 9.81e3)
    ax.scatter(weights, peaks, s=10, alpha=0.7)
    ax.set_xlabel("gross weight (t)")
    truth = " true deflection" if topic.startswith("/truth/") else ""
    ax.set_ylabel(f"peak |{topic.split('/')[-1]}{truth}| ({unit})")
    ax.set_title(f"per-vehicle peaks ({len(peaks)} vehicles, overlaps included)", fontsize=9)


def _vehicle_windows(run: "Run") -> list[tuple[float, float, float]]:
    if "/truth/vehicles" not in run:
        return []
    v = run["/truth/vehicles"]
    if not {"entry_time_ns", "exit_time_ns"} <= set(v.columns):
        return []
    entry = v["entry_time_ns"].to_numpy(dtype=float, na_value=np.nan)
    exit_ = v["exit_time_ns"].to_numpy(dtype=float, na_value=np.nan)
    weight = v["gross_weight_n"].to_numpy(dtype=float)
    keep = np.isfinite(entry) & np.isfinite(exit_)
    start = run.start_time_ns
    return [((a - start) * 1e-9, (b - start) * 1e-9, w) for a, b, w in zip(entry[keep], exit_[keep], weight[keep])]


def _true_f1(run: "Run") -> tuple[float, float] | None:
    values = []
    if "/truth/bridge" in run and "natural_frequency_hz" in run["/truth/bridge"]:
        for item in run["/truth/bridge"]["natural_frequency_hz"]:
            if item is not None and len(item):
                values.append(float(item[0]))
    if "/truth/bridge" in run and "natural_frequency_hz.0" in run["/truth/bridge"]:
        values += list(run["/truth/bridge"]["natural_frequency_hz.0"].dropna())
    if not values and run.natural_frequencies_hz:
        values = [run.natural_frequencies_hz[0]]
    return (min(values), max(values)) if values else None


def _label(run: "Run", topic: str) -> str:
    x = run.channels[topic].get("position_m")
    truth = " (true)" if topic.startswith("/truth/") else ""
    return f"{topic.split('/')[-1]}{truth} at {x} m" if x is not None else topic


def _span_m(run: "Run") -> float | None:
    return _float(run.metadata.get("bridge_model", {}).get("span_m"))


def _float(text: Any) -> float | None:
    try:
        return float(text)
    except (TypeError, ValueError):
        return None


_MCAP_MAGIC = b"\x89MCAP0\r\n"


def _is_cut(path: str | os.PathLike) -> bool:
    """Whether a file ends without the MCAP magic: cut short, not damaged inside."""
    with open(path, "rb") as f:
        size = f.seek(0, os.SEEK_END)
        f.seek(max(size - len(_MCAP_MAGIC), 0))
        return f.read() != _MCAP_MAGIC


def main(argv: Sequence[str] | None = None) -> int:
    """``python -m bridgetwin RUN [--out overview.png] [--sensors T ...]``: the overview of
    a run (a file, a glob of hourly parts or a split run's name).

    Exit status 0 when drawn; 3 when a file of the run is damaged or cut short and its
    intact part was drawn (one line on stderr says where it ends); 2, one line on stderr
    naming the file, when there is nothing to draw: no such file, empty, not an MCAP
    file, nothing intact before the damage, no sensor topic."""
    import argparse
    import sys
    import time

    from ._read import DamagedFileWarning, InterruptedRunWarning, read

    p = argparse.ArgumentParser(prog="python -m bridgetwin", description=main.__doc__)
    p.add_argument("run", help="run.mcap, 'day-*.mcap' or day.mcap (its hourly parts)")
    p.add_argument("--out", default="overview.png", help="the figure (.png, .svg, .pdf); default overview.png")
    p.add_argument("--sensors", nargs="*", help="sensor topics to draw (default: a few representative ones)")
    p.add_argument("--buckets", type=int, default=2000, help="min/max buckets per series (2000)")
    args = p.parse_args(argv)
    import matplotlib

    matplotlib.use("Agg")
    started = time.perf_counter()
    name = "python -m bridgetwin"
    if os.path.isfile(args.run) and os.path.getsize(args.run) == 0:
        print(f"{name}: {args.run}: empty (0 bytes)", file=sys.stderr)
        return 2
    try:
        with warnings.catch_warnings():
            # Said once below, on one line each, instead of Python's two-line warnings.
            warnings.simplefilter("ignore", DamagedFileWarning)
            warnings.simplefilter("ignore", InterruptedRunWarning)
            run = read(args.run)
    except (_native.ReadError, OSError) as e:  # FileNotFoundError names the path already
        text = str(e) if os.fspath(args.run) in str(e) else f"{args.run}: {e}"
        print(f"{name}: {text.splitlines()[0]}", file=sys.stderr)
        return 2
    rows = sum(len(run[t]) for t in run.sensors())
    if rows == 0:
        if run.damage:
            cut = [p["path"] for p in run.parts if p["damage"] is not None and _is_cut(p["path"])]
            what = "truncated" if cut else "damaged"
            why = f"{what} before its first intact message, nothing to draw: {'; '.join(run.damage)}"
        else:
            why = f"{args.run}: no sensor topic (/sensors/*) has a message: nothing to draw"
        print(f"{name}: {why}", file=sys.stderr)
        return 2
    overview(run, sensors=args.sensors, out=args.out, buckets=args.buckets)
    print(f"{args.out}: {run!r}, drawn in {time.perf_counter() - started:.1f} s")
    if run.damage:
        print(f"{name}: drew the intact part: {'; '.join(run.damage)}", file=sys.stderr)
        return 3
    return 0

