"""Reading runs: the columns decoded in Rust become pandas DataFrames, one per topic."""

from __future__ import annotations

import glob as _glob
import os
import re
import warnings
from collections.abc import Iterator, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from . import _native

PathLike = str | os.PathLike


class DamagedFileWarning(UserWarning):
    """A file of the run is damaged or cut short: it was read up to the damage."""


class InterruptedRunWarning(UserWarning):
    """A file of the run is a ``.partial``: the output of a run that was stopped (Ctrl-C,
    SIGTERM) or killed before it finished. Its data may end before the scenario's
    duration, even when the file itself is whole (a stopped run closes its file)."""


PARTIAL_SUFFIX = ".partial"


class Run(Mapping[str, pd.DataFrame]):
    """A bridgetwin run: topic name -> DataFrame, plus what the files say about it.

    Columns follow ``tools/read_run.py``: ``log_time_ns`` (int64, Unix-epoch ns, the true
    time), ``time_s`` (seconds since the run's start), ``timestamp_ns`` (the message's
    stamp: the DAQ node's clock on the measured topics of clocked sensors), then every
    field by its name, the unit in the name (``acceleration_m_s2``, ``strain_microstrain``,
    ``force_n``). Block and per-sample layouts give the same rows. Repeated messages (the
    axles of ``/truth/axle_loads``) give one row per element; equal-length number lists
    (the deflected shape) give columns ``name.0``, ``name.1``, ...

    Attributes:
        metadata: the file's metadata records (``bridgetwin``, ``scenario``,
            ``bridge_model``, ``split``), each a dict of strings.
        scenario: the resolved scenario the run was made from, as a dict.
        channels: per topic, its schema name and channel metadata (``unit``,
            ``sample_rate_hz``, ``position_m``, ...); also in ``run[topic].attrs``.
        attachments: name -> bytes (``scenario.toml`` as written, ``road_profile.csv``).
        parts: the files read, in time order, with their message counts and damage.
        damage: one line per damaged file: where its intact part ends.
        start_time_ns: Unix-epoch ns of the run's t = 0.
        undecoded: topics not read because their schema is not a bridgetwin one
            (``/scene``: Foxglove 3D scene updates), with their schema names.
    """

    def __init__(self, raw: dict[str, Any]):
        self._frames: dict[str, pd.DataFrame] = {}
        self.channels: dict[str, dict[str, Any]] = {}
        for name, topic in raw["topics"].items():
            frame = _frame(topic["columns"], topic["rows"])
            frame.attrs["topic"] = name
            frame.attrs["schema"] = topic["schema"]
            frame.attrs.update(topic["metadata"])
            self._frames[name] = frame
            self.channels[name] = {"schema": topic["schema"], **topic["metadata"]}
        self.metadata: dict[str, dict[str, str]] = raw["metadata"]
        self.attachments: dict[str, bytes] = raw["attachments"]
        self.parts: list[dict[str, Any]] = raw["parts"]
        self.start_time_ns: int = raw["start_time_ns"]
        self.undecoded: dict[str, str] = raw["undecoded"]
        self.damage: list[str] = [
            f"{p['path']}: {p['damage']}" for p in self.parts if p["damage"] is not None
        ]
        self.scenario: dict[str, Any] = self._scenario()

    def _scenario(self) -> dict[str, Any]:
        toml_text = self.metadata.get("scenario", {}).get("toml")
        if not toml_text:
            return {}
        try:
            return _native.toml_to_dict(toml_text, "scenario metadata")
        except _native.ScenarioError as e:
            # Records are handed on before the data section's CRC is checked at its end:
            # in a damaged file the metadata itself may be what is damaged.
            if self.damage:
                self.damage.append(f"the scenario metadata does not parse ({e}); run.scenario is empty")
                return {}
            raise _native.ReadError(f"the scenario metadata does not parse: {e}") from None

    def __getitem__(self, topic: str) -> pd.DataFrame:
        try:
            return self._frames[topic]
        except KeyError:
            raise KeyError(f"{topic!r}: not in this run; topics: {', '.join(self._frames)}") from None

    def __iter__(self) -> Iterator[str]:
        return iter(self._frames)

    def __len__(self) -> int:
        return len(self._frames)

    def sensors(self, kind: str | None = None) -> list[str]:
        """The measured sensor topics (``/sensors/<kind>/<id>``), optionally of one kind
        (``accel``, ``strain``, ``disp``, ...), in the order of the file."""
        prefix = "/sensors/" if kind is None else f"/sensors/{kind}/"
        return [t for t in self._frames if t.startswith(prefix)]

    @property
    def natural_frequencies_hz(self) -> list[float]:
        """The bridge model's natural frequencies at t = 0 (``bridge_model`` metadata)."""
        text = self.metadata.get("bridge_model", {}).get("natural_frequencies_hz", "")
        return [float(x) for x in text.split(",") if x]

    def __repr__(self) -> str:
        rows = sum(len(f) for f in self._frames.values())
        files = len(self.parts)
        damaged = f", {len(self.damage)} damaged" if self.damage else ""
        return f"<bridgetwin.Run: {len(self)} topics, {rows} rows, {files} file(s){damaged}>"


def _frame(columns: list[tuple], rows: int) -> pd.DataFrame:
    data: dict[str, Any] = {}
    for name, kind, values, extra, missing in columns:
        data[name] = _column(kind, values, extra, missing)
    # Each column keeps its own array (no copy into a 2-D block): memory stays that of the
    # arrays Rust handed over.
    frame = pd.DataFrame(data, copy=False)
    if not data:
        frame = pd.DataFrame(index=pd.RangeIndex(rows))
    return frame


def _column(kind: str, values: np.ndarray, extra: Any, missing: np.ndarray | None) -> Any:
    if kind == "category":
        return pd.Categorical.from_codes(values.astype(np.int32), categories=extra)
    if kind in ("f64_list", "u32_list"):
        return _split(values, extra, missing)
    if kind == "str_list":
        lists = [extra[a:b] for a, b in zip(values[:-1], values[1:])]
        return _masked_objects(lists, missing)
    if missing is None or not missing.any():
        return values
    if kind == "f64":
        out = values.copy()
        out[missing] = np.nan
        return out
    if kind == "bool":
        return pd.arrays.BooleanArray(values, missing)
    return pd.arrays.IntegerArray(values, missing)


def _split(offsets: np.ndarray, values: np.ndarray, missing: np.ndarray | None) -> np.ndarray:
    starts, ends = offsets[:-1], offsets[1:]
    lists = [values[a:b] for a, b in zip(starts, ends)]
    return _masked_objects(lists, missing)


def _masked_objects(lists: list[Any], missing: np.ndarray | None) -> np.ndarray:
    out = np.empty(len(lists), dtype=object)
    for i, item in enumerate(lists):
        out[i] = None if missing is not None and missing[i] else item
    return out


_PART = re.compile(r"-\d{4}\.mcap$")


def run_files(path_or_glob: PathLike | Sequence[PathLike]) -> list[Path]:
    """The files of a run: a file, a glob (``day-*.mcap``), a list of files, or the name
    of a split run (``day.mcap`` when the files are ``day-0000.mcap``, ...)."""
    if isinstance(path_or_glob, (str, os.PathLike)):
        text = os.fspath(path_or_glob)
        if any(c in text for c in "*?["):
            found = sorted(Path(p) for p in _glob.glob(text))
            if not found:
                raise _native.ReadError(f"{text}: no file matches")
            return found
        path = Path(text)
        if path.exists():
            return [path]
        stem = str(path.with_suffix("")) if path.suffix == ".mcap" else str(path)
        parts = sorted(Path(p) for p in _glob.glob(_glob.escape(stem) + "-[0-9][0-9][0-9][0-9].mcap"))
        if parts:
            return parts
        partial = Path(text + ".partial")
        if partial.exists():
            return [partial]
        raise FileNotFoundError(f"{text}: no such file (nor {Path(stem).name}-NNNN.mcap parts)")
    return [Path(p) for p in path_or_glob]


def read(
    path_or_glob: PathLike | Sequence[PathLike],
    topics: str | Sequence[str] | None = None,
) -> Run:
    """Reads a run into a :class:`Run` (topic -> pandas DataFrame), decoding in Rust.

    Args:
        path_or_glob: an ``.mcap`` file, a glob of hourly parts (``"day-*.mcap"``), a list
            of files, or a split run's name (``"day.mcap"`` for ``day-0000.mcap`` ...).
            Parts are joined in time order into one run; parts of different runs are
            refused.
        topics: topic names or patterns with ``*`` (``"/sensors/*"``); ``None`` reads all.

    A ``.partial`` file (the output of a stopped or killed run) gives an
    :class:`InterruptedRunWarning`: its data may end early. A damaged file (a killed run's
    ``.partial``, a copy cut short) is read up to the damage, with a
    :class:`DamagedFileWarning` saying where the intact part ends (also in
    ``run.damage``). Raises ``bridgetwin.ReadError`` when nothing can be read.
    """
    files = run_files(path_or_glob)
    if isinstance(topics, str):
        topics = [topics]
    raw = _native.read_run([os.fspath(f) for f in files], None if topics is None else list(topics))
    run = Run(raw)
    for f in files:
        if os.fspath(f).endswith(PARTIAL_SUFFIX):
            warnings.warn(
                f"{os.fspath(f)}: the output of an interrupted run (stopped or killed before it "
                "finished): its data may end before the scenario's duration",
                InterruptedRunWarning,
                stacklevel=2,
            )
    for line in run.damage:
        warnings.warn(line, DamagedFileWarning, stacklevel=2)
    return run
