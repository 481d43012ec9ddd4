"""The package's reader on 1000 corrupted variants of a run (byte flips anywhere and aimed
at the header, the chunks and the summary; truncations; zeroed and garbage ranges): each
is read up to the damage with a DamagedFileWarning or refused with ReadError, never read as
whole, never another exception (a Rust panic would surface as PanicException, an abort
would end this process)."""

from __future__ import annotations

import warnings
from collections import Counter

import numpy as np
import pytest

import bridgetwin
from conftest import run_cli


def variants(data: bytes, rng: np.random.Generator):
    n = len(data)
    summary = n - n * 15 // 100

    def flip(lo, hi):
        v = bytearray(data)
        v[int(rng.integers(lo, hi))] ^= 1 << int(rng.integers(0, 8))
        return "flip", bytes(v)

    for _ in range(250):
        yield flip(0, n)
    for lo, hi in ((0, 64), (64, summary), (summary, n)):
        for _ in range(125):
            yield flip(lo, hi)
    for _ in range(125):
        yield "truncate", data[: int(rng.integers(0, n))]
    for kind in ("zero", "garbage"):
        for _ in range(125):
            at, length = int(rng.integers(0, n)), int(rng.integers(1, 4096))
            v = bytearray(data)
            end = min(at + length, n)
            v[at:end] = bytes(end - at) if kind == "zero" else rng.bytes(end - at)
            yield kind, bytes(v)


def test_corrupted_runs_are_reported_never_crash(tmp_path):
    original = tmp_path / "run.mcap"
    run_cli("simulate", "--duration-s", 1.5, "--quiet", "--out", original)
    data = original.read_bytes()
    path = tmp_path / "variant.mcap"
    rng = np.random.default_rng(16)
    verdicts: Counter = Counter()
    wrong = []
    count = 0
    for kind, variant in variants(data, rng):
        count += 1
        path.write_bytes(variant)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            try:
                run = bridgetwin.read(path)
            except bridgetwin.ReadError:
                verdicts["refused"] += 1
                continue
            except Exception as e:  # noqa: BLE001 - anything else is the defect we look for
                wrong.append(f"{kind}: {type(e).__name__}: {e}")
                continue
        damaged = [w for w in caught if issubclass(w.category, bridgetwin.DamagedFileWarning)]
        if damaged:
            assert run.damage, "a warning without run.damage"
            verdicts["damaged"] += 1
        elif variant != data:
            wrong.append(f"{kind}: read as whole although changed")
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
