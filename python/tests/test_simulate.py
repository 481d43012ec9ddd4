"""Scenarios and runs from Python against the command line: the same checks, messages and
bytes; the GIL released while a run goes; Ctrl-C stops it and keeps a .partial."""

from __future__ import annotations

import signal
import subprocess
import sys
import textwrap
import threading
import time

import pytest

import bridgetwin
from conftest import REPO, run_cli


def test_default_scenario_is_the_cli_one():
    scenario = bridgetwin.default_scenario()
    assert scenario["bridge"]["span_m"] > 0
    assert bridgetwin.check(scenario) == []
    assert bridgetwin.check() == []


@pytest.mark.parametrize(
    "field, value",
    [("bridge.span_m", -3.0), ("solver.dt_s", 0.0), ("vehicles.0.speed_m_s", float("inf"))],
)
def test_check_names_the_field_and_value_as_the_cli_does(scratch, field, value):
    scenario = bridgetwin.default_scenario()
    table, *rest = field.split(".")
    target = scenario[table]
    if rest[0].isdigit():
        target = target[int(rest[0])]
        rest = rest[1:]
    target[rest[0]] = value
    with pytest.raises(bridgetwin.ScenarioError) as raised:
        bridgetwin.check(scenario)
    message = str(raised.value)
    assert field.split(".")[-1] in message
    # The command line on the same TOML prints the same message after "error: ".
    toml_text = bridgetwin._native.dict_to_toml(scenario)
    path = scratch / "bad.toml"
    path.write_text(toml_text)
    cli = run_cli("scenario", "check", path, check=False)
    assert cli.returncode in (1, 2), cli
    with pytest.raises(bridgetwin.ScenarioError) as from_file:
        bridgetwin.check(path)
    assert str(from_file.value) in cli.stderr, (str(from_file.value), cli.stderr)
    assert str(raised.value) == str(from_file.value)


def test_an_out_of_range_parameter_has_field_value_and_reason():
    scenario = bridgetwin.default_scenario()
    scenario["bridge"]["span_m"] = -3.0
    with pytest.raises(bridgetwin.ScenarioError) as raised:
        bridgetwin.check(scenario)
    assert raised.value.field == "bridge.span_m"
    assert raised.value.value == "-3"
    assert str(raised.value) == f"bridge.span_m = -3 {raised.value.reason}"
    assert "> 0" in raised.value.reason


def test_toml_errors_name_the_key():
    with pytest.raises(bridgetwin.ScenarioError, match="spam_m"):
        bridgetwin.check("[bridge]\nspam_m = 3\n")


def test_a_run_larger_than_the_free_space_is_refused_unless_told(scratch, monkeypatch):
    # A file system stand-in with 1000 bytes free (the variable the library reads for
    # tests): the run's estimate does not fit, so nothing is written.
    monkeypatch.setenv("BRIDGETWIN_FREE_SPACE_BYTES", "1000")
    out = scratch / "big.mcap"
    with pytest.raises(OSError) as raised:
        bridgetwin.simulate(out=out, duration_s=1.0)
    message = str(raised.value)
    for part in ("estimated size", "1000 B free", str(scratch), "skip_space_check=True"):
        assert part in message, message
    assert list(scratch.iterdir()) == []
    files = bridgetwin.simulate(out=out, duration_s=1.0, skip_space_check=True)
    assert files == [out] and out.is_file()


def test_simulate_out_writes_the_cli_bytes(scratch):
    example = REPO / "examples" / "two_trucks.toml"
    run_cli("simulate", example, "--seed", 7, "--duration-s", 3, "--out", scratch / "cli.mcap", "--quiet")
    files = bridgetwin.simulate(example, out=scratch / "py.mcap", seed=7, duration_s=3)
    assert [str(f) for f in files] == [str(scratch / "py.mcap")]
    assert (scratch / "py.mcap").read_bytes() == (scratch / "cli.mcap").read_bytes()
    with pytest.raises(OSError, match="exists"):
        bridgetwin.simulate(example, out=scratch / "py.mcap", seed=7, duration_s=3)
    bridgetwin.simulate(example, out=scratch / "py.mcap", seed=7, duration_s=3, force=True)
    assert (scratch / "py.mcap").read_bytes() == (scratch / "cli.mcap").read_bytes()


def test_simulate_in_memory_equals_the_file(scratch):
    run = bridgetwin.simulate(duration_s=2.0, seed=3)
    bridgetwin.simulate(out=scratch / "f.mcap", duration_s=2.0, seed=3)
    again = bridgetwin.read(scratch / "f.mcap")
    assert list(run) == list(again)
    for topic in run:
        assert run[topic].equals(again[topic]), topic
    assert run.scenario["seed"] == 3


def test_numpy_values_in_a_dict_keep_their_types(scratch):
    import numpy as np

    scenario = bridgetwin.default_scenario()
    scenario["seed"] = np.int64(11)
    scenario["bridge"]["damping_ratio"] = np.float64(0.025)
    run = bridgetwin.simulate(scenario, duration_s=np.float32(1.0))
    assert run.scenario["seed"] == 11 and isinstance(run.scenario["seed"], int)
    assert run.scenario["bridge"]["damping_ratio"] == 0.025
    loop = {}
    loop["self"] = loop
    with pytest.raises(TypeError, match="levels deep"):
        bridgetwin.check(loop)
    with pytest.raises(TypeError, match="64-bit"):
        bridgetwin.check({"seed": 2**70})


def test_a_bad_scenario_writes_nothing(scratch):
    scenario = bridgetwin.default_scenario()
    scenario["bridge"]["span_m"] = -1.0
    with pytest.raises(bridgetwin.ScenarioError, match="span_m"):
        bridgetwin.simulate(scenario, out=scratch / "x.mcap")
    assert list(scratch.iterdir()) == []


def test_simulate_releases_the_gil(scratch):
    """While a run goes on another thread, this thread keeps running Python: with the GIL
    held it would get no turn from the run's first step to its last, and count nothing
    between the two events. How long the gaps between its turns are is measured by
    python/benches/gil_and_stop.py, not here: that is the machine's business."""
    entered, done = threading.Event(), threading.Event()
    written = []

    def work():
        entered.set()
        written.extend(
            bridgetwin.simulate(REPO / "examples" / "hour_of_traffic.toml", out=scratch / "gil.mcap", duration_s=600.0)
        )
        done.set()

    worker = threading.Thread(target=work)
    worker.start()
    entered.wait()
    ticks = 0
    while not done.is_set():
        ticks += 1
        time.sleep(0.001)
    worker.join()
    assert written and all(p.exists() for p in written), written
    # Turns taken while the run went on: a held GIL leaves at most the one or two before
    # the run's first step; a released one, one per millisecond of a run of seconds.
    assert ticks > 50, ticks


def test_ctrl_c_stops_the_run_and_keeps_a_partial(scratch):
    out = scratch / "long.mcap"
    script = textwrap.dedent(
        f"""
        import signal, sys, bridgetwin
        # A child started from a background job inherits SIGINT ignored, and Python then
        # installs no handler: put Ctrl-C's default back, as an interactive session has it.
        signal.signal(signal.SIGINT, signal.default_int_handler)
        print("started", flush=True)
        try:
            bridgetwin.simulate(out={str(out)!r}, duration_s=100000.0, skip_space_check=True)
        except KeyboardInterrupt as e:
            print("interrupted", e.partial, flush=True)
            sys.exit(130)
        print("finished", flush=True)
        """
    )
    child = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, text=True)
    assert child.stdout.readline().strip() == "started"
    time.sleep(2.0)
    child.send_signal(signal.SIGINT)
    # A deadline so that a run that ignores Ctrl-C fails instead of hanging; how soon it
    # stops is measured by python/benches/gil_and_stop.py.
    rest, _ = child.communicate(timeout=60)
    assert child.returncode == 130, rest
    partial = out.with_name(out.name + ".partial")
    assert rest.split() == ["interrupted", str(partial)]
    assert not out.exists() and partial.exists()
    # A stopped run closes its file (summary and all): whole, only shorter, and read with
    # a warning that it is an interrupted run's output.
    with pytest.warns(bridgetwin.InterruptedRunWarning, match="interrupted run"):
        run = bridgetwin.read(partial)
    assert run.damage == []
    accel = run[run.sensors("accel")[0]]
    assert 0 < accel["time_s"].iloc[-1] < 100000.0


def test_ctrl_c_in_memory_hands_back_the_run_so_far():
    script = textwrap.dedent(
        """
        import signal, sys, bridgetwin
        # A child started from a background job inherits SIGINT ignored, and Python then
        # installs no handler: put Ctrl-C's default back, as an interactive session has it.
        signal.signal(signal.SIGINT, signal.default_int_handler)
        print("started", flush=True)
        try:
            bridgetwin.simulate(duration_s=100000.0, skip_space_check=True)
        except KeyboardInterrupt as e:
            accel = e.run[e.run.sensors("accel")[0]]
            print("interrupted", len(accel) > 0, e.partial, flush=True)
            sys.exit(130)
        """
    )
    child = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, text=True)
    assert child.stdout.readline().strip() == "started"
    time.sleep(2.0)
    child.send_signal(signal.SIGINT)
    rest, _ = child.communicate(timeout=60)
    assert child.returncode == 130, rest
    assert rest.split() == ["interrupted", "True", "None"]
