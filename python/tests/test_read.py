"""bridgetwin.read against the repository's independent reader (tools/read_run.py, which
decodes every message with the official mcap and protobuf packages from the schemas in
the file): every topic, every column, bit for bit; both layouts; hourly parts joined."""

from __future__ import annotations

import warnings

import numpy as np
import pandas as pd
import pytest
import read_run  # tools/read_run.py

import bridgetwin
from conftest import copy, run_cli


def reference(path) -> dict[str, dict[str, np.ndarray]]:
    path = str(path)
    return read_run.load_topics(path, read_run.list_topics(path))


def as_array(column: pd.Series | np.ndarray) -> np.ndarray:
    if isinstance(column, pd.Series):
        column = column.array
    if isinstance(column, pd.Categorical):
        return np.asarray(column.astype(object))
    if isinstance(column, pd.arrays.BooleanArray) or isinstance(column, pd.arrays.IntegerArray):
        return column.to_numpy(dtype=object, na_value=np.nan)
    return np.asarray(column)


def assert_same_column(topic: str, name: str, ours, theirs: np.ndarray) -> None:
    ours = as_array(ours)
    assert len(ours) == len(theirs), f"{topic} {name}: {len(ours)} rows vs {len(theirs)}"
    if theirs.dtype == object or ours.dtype == object:
        for i, (a, b) in enumerate(zip(ours, theirs)):
            if isinstance(b, float) and np.isnan(b):
                assert a is None or (isinstance(a, float) and np.isnan(a)), f"{topic} {name}[{i}]"
            else:
                np.testing.assert_array_equal(np.asarray(a), np.asarray(b), err_msg=f"{topic} {name}[{i}]")
        return
    if theirs.dtype.kind == "f":
        # Bit for bit, NaN where the reference has NaN (a key missing from some rows).
        assert np.array_equal(ours.astype(np.float64), theirs, equal_nan=True), f"{topic} {name} differs"
    else:
        assert np.array_equal(ours, theirs), f"{topic} {name} differs"


def nested_fields(columns: dict[str, np.ndarray]) -> set[str]:
    """Repeated message fields of a reference topic: they have their own `F.log_time_ns`."""
    return {k[: -len(".log_time_ns")] for k in columns if k.endswith(".log_time_ns")}


def compare_topic(topic: str, frame: pd.DataFrame, columns: dict[str, np.ndarray]) -> int:
    """Asserts every reference column of one topic equals ours; returns values compared.

    The reference gives a repeated message field F rows of its own (``F.x`` with
    ``F.log_time_ns``). We give either one row per element (``/truth/axle_loads``: the
    frame's rows are the elements, its ``log_time_ns`` theirs) or, per message, the list
    of the elements' values (``/wim/*`` groups): concatenated, the same values."""
    compared = 0
    nested = nested_fields(columns)
    element_rows = {f for f in nested if len(frame) == len(columns[f"{f}.log_time_ns"]) and f"{f}.log_time_ns" not in frame}
    for name, theirs in columns.items():
        field = name.split(".")[0] if "." in name else None
        if name.endswith("time_s"):
            continue  # compared as times below
        if name == "node_timestamp_ns":
            # truth.proto: node_timestamp is "unset when it equals timestamp": the raw
            # protobuf default the reference reads is unset (NaN); we fill the stamp back in.
            theirs = np.where(np.isnan(theirs) | (theirs == 0), columns["timestamp_ns"], theirs)
        if field in nested and name == f"{field}.log_time_ns":
            if field in element_rows:
                assert_same_column(topic, name, frame["log_time_ns"], theirs)
            continue
        if field in nested and field not in element_rows:
            ours = frame[name] if name in frame else None
            if ours is None:
                parts = sorted((c for c in frame.columns if c.startswith(name + ".")), key=lambda c: int(c.rsplit(".", 1)[1]))
                assert parts, f"{topic}: no column {name} nor {name}.0 ...; ours: {list(frame.columns)}"
                flat = np.column_stack([frame[c].to_numpy() for c in parts]).ravel()
            else:
                flat = np.concatenate([np.asarray(v) for v in ours]) if len(ours) else np.zeros(0)
            assert_same_column(topic, name, flat, theirs)
        elif theirs.ndim == 2:
            for j in range(theirs.shape[1]):
                assert_same_column(topic, f"{name}.{j}", frame[f"{name}.{j}"], theirs[:, j])
        elif topic in ELEMENT_ROW_TOPICS and field is None and name not in frame:
            continue
        else:
            assert name in frame.columns, f"{topic}: no column {name}; ours: {list(frame.columns)}"
            if field is None and element_rows:
                # A message-level column of a topic whose rows are elements: every row
                # of ours carries its message's value.
                messages = pd.Series(theirs, index=columns["log_time_ns"])
                theirs = messages.loc[frame["log_time_ns"].to_numpy()].to_numpy()
            assert_same_column(topic, name, frame[name], theirs)
        compared += theirs.size
    return compared


# Topics whose rows are the elements of a repeated field (one row per axle).
ELEMENT_ROW_TOPICS = {"/truth/axle_loads"}


def assert_times_shifted(topic: str, frame: pd.DataFrame, columns: dict[str, np.ndarray], shift: list) -> None:
    """The reference counts time_s from the file's first message, we from the run's start:
    the same times, shifted by one constant for the whole run."""
    for name, theirs in columns.items():
        if not name.endswith("time_s") or not len(theirs):
            continue
        log = columns[name[: -len("time_s")] + "log_time_ns"]
        ours_name = name if name in frame else "time_s"
        if len(frame) != len(theirs):
            continue  # message rows of an element-row topic
        ours = frame[ours_name].to_numpy()
        if not shift:
            shift.append(ours[0] - theirs[0])
        np.testing.assert_allclose(ours - shift[0], theirs, rtol=0, atol=1e-9, err_msg=f"{topic} {name}")
        assert len(log) == len(theirs)


def compare_run(run: bridgetwin.Run, ref: dict[str, dict[str, np.ndarray]]) -> int:
    """Asserts every reference column of every topic equals ours; returns values compared."""
    # Only the Foxglove scene is not decoded (it is for the 3D panel, not for pipelines).
    assert run.undecoded == {"/scene": "foxglove.SceneUpdate"}, run.undecoded
    decoded = set(ref) - set(run.undecoded)
    assert set(run) == decoded, f"topics differ: {sorted(set(run) ^ decoded)}"
    compared, shift = 0, []
    for topic in sorted(decoded):
        compared += compare_topic(topic, run[topic], ref[topic])
        assert_times_shifted(topic, run[topic], ref[topic], shift)
    return compared


@pytest.mark.parametrize("layout", ["block", "sample"])
def test_every_topic_and_column_equals_the_independent_reader(runs, layout):
    path = runs / f"{layout}.mcap"
    run = bridgetwin.read(path)
    compared = compare_run(run, reference(path))
    assert compared > 100_000, compared
    assert run.damage == []
    assert run.scenario["output"]["layout"] == layout


def test_block_and_sample_layouts_give_the_same_frames(runs):
    """The same rows and values; the times of a block's samples are its first sample's
    plus i x sample_period_ns, rounded to whole ns: at 300 Hz they drift from the
    per-sample stamps (round(k x 1e9 / rate)) by up to block_samples / 2 ns
    (sensors.proto, SampleBlock.sample_period_ns)."""
    block = bridgetwin.read(runs / "block.mcap", topics="/sensors/*")
    sample = bridgetwin.read(runs / "sample.mcap", topics="/sensors/*")
    assert list(block) == list(sample) and len(block) > 0
    drift_ns = block.scenario["output"]["block_samples"] / 2
    worst = 0
    for topic in block:
        a, b = block[topic], sample[topic]
        assert list(a.columns) == list(b.columns), topic
        times = [c for c in a.columns if c.endswith(("_ns", "time_s"))]
        pd.testing.assert_frame_equal(a.drop(columns=times), b.drop(columns=times), check_exact=True, obj=topic)
        for name in times:
            scale = 1e9 if name.endswith("time_s") else 1
            gap = np.abs(a[name].to_numpy() - b[name].to_numpy()) * scale
            assert gap.max() <= drift_ns + 0.5, (topic, name, gap.max())
            worst = max(worst, gap.max())
    assert worst > 0, "no drift at all: the 300 Hz strain gauge is gone from two_trucks.toml?"


def test_hourly_parts_read_as_the_whole_run(runs):
    parts = sorted(runs.glob("day-*.mcap"))
    assert len(parts) == 3, parts
    whole = bridgetwin.read(runs / "whole.mcap")
    for given in (str(runs / "day-*.mcap"), runs / "day.mcap", list(reversed(parts))):
        joined = bridgetwin.read(given)
        assert [p["path"] for p in joined.parts] == [str(p) for p in parts]
        assert [p["part"] for p in joined.parts] == [0, 1, 2]
        assert list(joined) == list(whole)
        for topic in whole:
            pd.testing.assert_frame_equal(joined[topic], whole[topic], check_exact=True, obj=topic)
    # Each part also equals the independent reader on its own file.
    for part in parts:
        one = bridgetwin.read(part)
        compare_run(one, reference(part))


def test_topics_filter_and_errors(runs):
    run = bridgetwin.read(runs / "block.mcap", topics=["/sensors/accel/*", "/events"])
    assert set(run) == set(run.sensors("accel")) | {"/events"}
    with pytest.raises(bridgetwin.ReadError, match="/nope"):
        bridgetwin.read(runs / "block.mcap", topics="/nope")
    with pytest.raises(FileNotFoundError):
        bridgetwin.read(runs / "absent.mcap")
    with pytest.raises(bridgetwin.ReadError, match="no file matches"):
        bridgetwin.read(str(runs / "absent-*.mcap"))


def test_parts_of_different_runs_are_refused(runs, scratch):
    copy(runs / "day-0000.mcap", scratch / "x-0000.mcap")
    run_cli("simulate", runs / "split.toml", "--seed", 99, "--duration-s", 5, "--out", scratch / "y.mcap", "--quiet")
    copy(scratch / "y-0001.mcap", scratch / "x-0001.mcap")
    with pytest.raises(bridgetwin.ReadError, match="seed|run"):
        bridgetwin.read(str(scratch / "x-*.mcap"))


def test_metadata_scenario_and_channels(runs):
    run = bridgetwin.read(runs / "block.mcap")
    assert {"bridgetwin", "scenario", "bridge_model"} <= set(run.metadata)
    assert run.scenario == bridgetwin.read(runs / "sample.mcap").scenario | {"output": run.scenario["output"]}
    assert run.natural_frequencies_hz[0] > 0
    accel = run.sensors("accel")[0]
    assert run[accel].attrs["unit"] == run.channels[accel]["unit"]
    assert float(run[accel].attrs["sample_rate_hz"]) > 0
    assert b"[bridge]" in run.attachments["scenario.toml"]
    assert "/scene" in run.undecoded


def test_a_cut_file_reads_up_to_the_damage_with_a_warning(runs, scratch):
    data = (runs / "whole.mcap").read_bytes()  # 4 chunks: the cut leaves two whole
    cut = scratch / "cut.mcap"
    cut.write_bytes(data[: len(data) * 6 // 10])
    with pytest.warns(bridgetwin.DamagedFileWarning, match="intact part ends at or before byte"):
        run = bridgetwin.read(cut)
    assert len(run.damage) == 1 and "cut.mcap" in run.damage[0]
    whole = bridgetwin.read(runs / "whole.mcap")
    accel = run.sensors("accel")[0]
    got = run[accel]
    assert 0 < len(got) < len(whole[accel])
    # What was read is the start of the whole run, unchanged.
    pd.testing.assert_frame_equal(got, whole[accel].iloc[: len(got)], check_exact=True)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        bridgetwin.read(runs / "block.mcap")  # a whole file warns nothing


def test_a_partial_file_warns_that_it_is_an_interrupted_runs_output(runs, scratch):
    """A `.partial` is what a stopped or killed run leaves: even whole (a stopped run closes
    its file) its data may end before the scenario's duration, and the reader says so. The
    same bytes under the final name warn nothing: the warning follows the name, which is
    all that tells an interrupted run's whole file from a finished one."""
    whole = runs / "whole.mcap"
    partial = scratch / "whole.mcap.partial"
    partial.write_bytes(whole.read_bytes())
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        run = bridgetwin.read(partial)
    assert [w.category for w in caught] == [bridgetwin.InterruptedRunWarning], [str(w.message) for w in caught]
    message = str(caught[0].message)
    assert str(partial) in message and "interrupted run" in message and "may end" in message, message
    assert run.damage == []
    # The name without .partial finds it (as the command line does) and warns the same.
    with pytest.warns(bridgetwin.InterruptedRunWarning, match="interrupted run"):
        bridgetwin.read(scratch / "whole.mcap")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        bridgetwin.read(whole)
