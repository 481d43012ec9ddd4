"""The package's reader on 1000 corrupted variants of a run (byte flips anywhere and aimed
at the header, the chunks and the summary; truncations; zeroed and garbage ranges): each
is read up to the damage with a DamagedFileWarning or refused with ReadError, never read as
whole, never another exception (a Rust panic would surface as PanicException, an abort
would end this process)."""

from __future__ import annotations

import warnings
from collections import Counter

import numpy as np
import pandas as pd
import pytest

import bridgetwin
from conftest import run_cli


def variants(data: bytes, rng: np.random.Generator):
    """(kind, first changed byte, bytes) of each variant."""
    n = len(data)
    summary = n - n * 15 // 100

    def flip(lo, hi):
        v = bytearray(data)
        at = int(rng.integers(lo, hi))
        v[at] ^= 1 << int(rng.integers(0, 8))
        return "flip", at, bytes(v)

    for _ in range(250):
        yield flip(0, n)
    for lo, hi in ((0, 64), (64, summary), (summary, n)):
        for _ in range(125):
            yield flip(lo, hi)
    for _ in range(125):
        at = int(rng.integers(0, n))
        yield "truncate", at, data[:at]
    for kind in ("zero", "garbage"):
        for _ in range(125):
            at, length = int(rng.integers(0, n)), int(rng.integers(1, 4096))
            v = bytearray(data)
            end = min(at + length, n)
            v[at:end] = bytes(end - at) if kind == "zero" else rng.bytes(end - at)
            yield kind, at, bytes(v)


def first_chunk_offset(path) -> int:
    from mcap.reader import make_reader

    with open(path, "rb") as f:
        summary = make_reader(f).get_summary()
    return min(c.chunk_start_offset for c in summary.chunk_indexes)


def values(column: pd.Series) -> np.ndarray:
    if isinstance(column.dtype, pd.CategoricalDtype):
        return np.asarray(column.astype(object))  # a prefix has fewer categories
    return column.to_numpy()


def same(a: np.ndarray, b: np.ndarray) -> bool:
    if a.dtype == object:
        # Strings (categories, by value) are compared; variable-length lists are not.
        return all(x == y for x, y in zip(a, b) if isinstance(x, str))
    return np.array_equal(a, b, equal_nan=a.dtype.kind == "f")


def assert_prefix(run: bridgetwin.Run, whole: bridgetwin.Run, kind: str, at: int) -> None:
    """What a damaged read gives is the start of each topic of the whole file, unchanged:
    every column both have (an empty prefix lacks the map keys and list columns that only
    messages show; time_s counts from the start time in the metadata, which may be what was
    damaged). Number, boolean and string columns are compared; variable-length lists (a
    few WIM and vehicle fields) are not, to keep the test quick."""
    for topic, frame in run.items():
        assert topic in whole, f"{kind} at {at}: topic {topic} is not in the original"
        original = whole[topic]
        n = len(frame)
        assert n <= len(original), (kind, at, topic)
        for c in frame.columns:
            if c.endswith("time_s") or c not in original or n == 0:
                continue
            assert same(values(frame[c]), values(original[c])[:n]), f"{kind} at {at}: {topic} {c} differs"


def test_corrupted_runs_are_reported_never_crash(tmp_path):
    original = tmp_path / "run.mcap"
    # 8 s of the default run: 3 chunks, so damage falls before, in and between them.
    run_cli("simulate", "--duration-s", 8, "--quiet", "--out", original)
    data = original.read_bytes()
    whole = bridgetwin.read(original)
    first_chunk = first_chunk_offset(original)
    path = tmp_path / "variant.mcap"
    rng = np.random.default_rng(16)
    verdicts: Counter = Counter()
    wrong = []
    count = 0
    for kind, at, variant in variants(data, rng):
        count += 1
        path.write_bytes(variant)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            try:
                run = bridgetwin.read(path)
            except bridgetwin.ReadError as e:
                verdicts["refused"] += 1
                # Refused whole only when no record could be read: the damage is in the
                # magic or the header, before any data.
                if at >= first_chunk:
                    wrong.append(f"{kind} at {at}: refused although the damage is past the first chunk ({e})")
                continue
            except Exception as e:  # noqa: BLE001 - anything else is the defect we look for
                wrong.append(f"{kind} at {at}: {type(e).__name__}: {e}")
                continue
        damaged = [w for w in caught if issubclass(w.category, bridgetwin.DamagedFileWarning)]
        if damaged:
            assert run.damage, "a warning without run.damage"
            verdicts["damaged"] += 1
            try:
                assert_prefix(run, whole, kind, at)
            except AssertionError as e:
                wrong.append(str(e)[:300])
        elif variant != data:
            wrong.append(f"{kind} at {at}: read as whole although changed")
        else:
            verdicts["unchanged"] += 1
    assert count == 1000
    assert not wrong, f"{len(wrong)} wrong: {wrong[:10]}"
    assert verdicts["damaged"] > 100 and verdicts["refused"] > 10, verdicts


def test_garbage_and_empty_files_are_refused(tmp_path):
    for name, data in (("empty.mcap", b""), ("text.mcap", b"not a run\n" * 100)):
        path = tmp_path / name
        path.write_bytes(data)
        with pytest.raises(bridgetwin.ReadError, match="not an MCAP file|empty"):
            bridgetwin.read(path)
