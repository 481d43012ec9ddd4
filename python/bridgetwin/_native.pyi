"""Type stub of ``bridgetwin._native``, the Rust extension (python/src/lib.rs).

The public API is the ``bridgetwin`` package (``read``, ``simulate``, ``check``, ...);
these are the functions it calls. ``python/tests/test_stub.py`` checks that every
function here exists in the extension with these parameter names, and the reverse.
"""

from collections.abc import Sequence
from os import PathLike
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt

__version__: str

class ScenarioError(ValueError):
    """A scenario is not valid; the message is the command line's."""

    #: The dotted field (``bridge.span_m``) when one parameter is out of range.
    field: str
    #: The value as written.
    value: str
    #: Why it is refused (``must be positive``).
    reason: str

class ReadError(OSError):
    """A run could not be read at all (missing file, not MCAP, parts of different runs)."""

class SimulationError(RuntimeError):
    """A run failed (divergence, output not writable); nothing half-written is left."""

def default_scenario_toml() -> str:
    """The embedded default scenario's TOML text (``bridgetwin scenario show``)."""

def toml_to_dict(text: str, source: str) -> dict[str, Any]:
    """TOML text as a dict (date-times as strings); errors (ScenarioError) name ``source``."""

def dict_to_toml(scenario: dict[str, Any]) -> str:
    """A scenario dict as TOML text; keys set to None are left out (their defaults apply),
    infinities and NaN are kept (the checks name them). TypeError names the path of a
    value of another type."""

def check(
    text: str | None = None,
    path: str | PathLike[str] | None = None,
    source: str = "scenario",
) -> list[str]:
    """Parses and resolves a scenario (text, else path, else the default); returns its
    warnings, raises ScenarioError naming the field and the value."""

def simulate(
    out: str | PathLike[str],
    text: str | None = None,
    path: str | PathLike[str] | None = None,
    source: str = "scenario",
    seed: int | None = None,
    duration_s: float | None = None,
    force: bool = False,
    skip_space_check: bool = False,
) -> list[Path]:
    """Runs a scenario into ``out`` off the GIL; returns the files written. Ctrl-C raises
    KeyboardInterrupt with ``partial`` (the ``.partial`` file kept). A run whose estimated
    size exceeds the free space of ``out``'s file system raises OSError before anything
    is written, unless ``skip_space_check``."""

#: One column: (name, kind, data, extra, missing). ``kind`` is one of ``f64``, ``i64``,
#: ``u32``, ``i32``, ``bool`` (data: the values), ``category`` (data: int32 codes, extra:
#: the categories), ``f64_list``, ``u32_list`` (data: uint64 offsets, extra: the values),
#: ``str_list`` (data: offsets, extra: list of str); ``missing`` is a bool mask or None.
Column = tuple[str, str, npt.NDArray[Any], Any, npt.NDArray[np.bool_] | None]

def read_run(paths: Sequence[str], topics: Sequence[str] | None = None) -> dict[str, Any]:
    """Reads the files of one run (parts in time order) off the GIL. Returns a dict with
    ``topics`` (name -> {schema, metadata, rows, columns: list[Column]}), ``metadata``,
    ``attachments``, ``parts`` (path, part, messages, damage), ``start_time_ns`` and
    ``undecoded``. Raises ReadError when nothing can be read."""

def welch_psd(
    samples: npt.NDArray[np.float64], spacing: float, segment_len: int
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """One-sided Welch PSD (Hann, 50 % overlap, segment means removed) of samples
    ``spacing`` seconds apart: (frequencies_hz, density per Hz), bins 1 .. n/2 - 1."""
