"""Scenarios and runs from Python: the same parsing, checks and bytes as the command line."""

from __future__ import annotations

import os
import tempfile
import warnings
from pathlib import Path
from typing import Any

from . import _native
from ._read import InterruptedRunWarning, Run, read

Scenario = dict[str, Any] | str | os.PathLike | None


def default_scenario() -> dict[str, Any]:
    """The embedded default scenario (``bridgetwin scenario show``) as a dict."""
    return _native.toml_to_dict(_native.default_scenario_toml(), "<default scenario>")


def _source(scenario: Scenario) -> dict[str, Any]:
    """Keyword arguments naming the scenario for the native functions."""
    if scenario is None:
        return {}
    if isinstance(scenario, os.PathLike):
        return {"path": os.fspath(scenario)}
    if isinstance(scenario, str):
        # A file name, or TOML text: text has a newline or a table header or a key.
        if "\n" not in scenario and "=" not in scenario and "[" not in scenario:
            return {"path": scenario}
        return {"text": scenario, "source": "<scenario text>"}
    if isinstance(scenario, dict):
        return {"text": _native.dict_to_toml(scenario), "source": "<scenario dict>"}
    raise TypeError(f"scenario: expected a dict, TOML text or a path, got {type(scenario).__name__}")


def check(scenario: Scenario = None) -> list[str]:
    """Parses and resolves a scenario as ``bridgetwin scenario check`` does.

    Args:
        scenario: a dict (as :func:`default_scenario` returns), TOML text, or the path of
            a ``.toml`` file; ``None`` is the default scenario.

    Returns the warnings (an empty list for a clean scenario). Raises
    ``bridgetwin.ScenarioError`` with the command line's message, which names the field
    and the value (``bridge.span_m = -3 must be positive``); ``field``, ``value`` and
    ``reason`` are attributes of the exception when one parameter is out of range.
    """
    return _native.check(**_source(scenario))


def simulate(
    scenario: Scenario = None,
    out: str | os.PathLike | None = None,
    seed: int | None = None,
    duration_s: float | None = None,
    force: bool = False,
    skip_space_check: bool = False,
) -> Run | list[Path]:
    """Runs a scenario, exactly as ``bridgetwin simulate`` does.

    Args:
        scenario: a dict, TOML text or a ``.toml`` path; ``None`` is the default scenario.
        out: the ``.mcap`` file to write (hourly parts ``name-0000.mcap`` ... when the
            scenario sets ``output.split_every_s``); ``None`` runs into a temporary folder
            and returns the run read back (for runs that fit in memory).
        seed: overrides the scenario's seed (same seed, same bytes).
        duration_s: overrides the scenario's duration (s).
        force: overwrite ``out`` if it exists.
        skip_space_check: run even when the estimated size exceeds the free space of
            ``out``'s file system (by default such a run raises OSError before anything
            is written, as the command line refuses it without ``--skip-space-check``).

    Returns the :class:`Run` when ``out`` is None, else the files written. The run does
    not hold the GIL, so threads (``concurrent.futures.ThreadPoolExecutor``) run several
    at once on several cores. Ctrl-C stops it at the next step and raises
    KeyboardInterrupt; the data written so far stay in ``<out>.partial`` (its ``partial``
    attribute), as with the command line; with ``out=None`` the run so far is its ``run``
    attribute instead.
    """
    kwargs = dict(
        _source(scenario),
        seed=seed,
        duration_s=duration_s,
        force=force,
        skip_space_check=skip_space_check,
    )
    if out is not None:
        return [Path(p) for p in _native.simulate(os.fspath(out), **kwargs)]
    with tempfile.TemporaryDirectory(prefix="bridgetwin-") as folder:
        target = Path(folder) / "run.mcap"
        try:
            files = _native.simulate(os.fspath(target), **kwargs)
        except KeyboardInterrupt as e:
            # The temporary folder goes with this call: what ran so far comes back on the
            # exception as `run` (its `partial` file is gone).
            partial = getattr(e, "partial", None)
            with warnings.catch_warnings():
                # The KeyboardInterrupt already says the run was interrupted.
                warnings.simplefilter("ignore", InterruptedRunWarning)
                e.run = read(partial) if partial and Path(partial).exists() else None
            e.partial = None
            raise
        return read(files)
