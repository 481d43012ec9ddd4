"""The overview figure: the chosen sensors, vehicles shaded, the PSD with the true f1,
per-vehicle peaks; decimated (at most 2 x buckets points per series)."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import numpy as np

import bridgetwin
from bridgetwin import plot


def test_envelope_keeps_extremes_and_bounds_points():
    t = np.linspace(0, 100, 1_000_001)
    y = np.sin(t)
    y[123_457] = 5.0
    te, ye = plot.envelope(t, y, buckets=500)
    assert len(te) <= 1000 and len(te) == len(ye)
    assert ye.max() == 5.0 and ye.min() == y.min()


def test_overview_of_a_run(runs, tmp_path):
    run = bridgetwin.read(runs / "block.mcap")
    out = tmp_path / "overview.png"
    fig = plot.overview(run, out=out, buckets=300)
    assert out.stat().st_size > 20_000
    axes = {ax.get_label(): ax for ax in fig.axes}
    accel = axes["accel"]
    drawn = [line for line in accel.get_lines() if len(line.get_xdata()) > 2]
    assert drawn, "no acceleration series"
    assert all(len(line.get_xdata()) <= 600 for line in drawn)
    # Each vehicle's time on the bridge is shaded: one bar per vehicle.
    windows = plot._vehicle_windows(run)
    assert len(windows) == len(run["/truth/vehicles"]) == 2
    shaded = [c for c in accel.collections if c.get_label() == "vehicle on the bridge"]
    assert len(shaded) == 1 and len(shaded[0].get_paths()) == len(windows)
    for path, (t0, t1, _) in zip(shaded[0].get_paths(), windows):
        xs = path.vertices[:, 0]
        assert np.isclose(xs.min(), t0) and np.isclose(xs.max(), t1)
    psd_text = " ".join(t.get_text() for t in axes["psd"].texts) + " ".join(
        str(line.get_label()) for line in axes["psd"].get_lines()
    )
    f1 = run.natural_frequencies_hz[0]
    assert f"{f1:.2f}" in psd_text or f"{f1:.3g}" in psd_text, psd_text
    assert axes["peaks"].has_data()


def test_quickstart_runs_and_finds_f1(tmp_path):
    """examples/python/quickstart.py: simulate, read, plot, identify f1 (exit 0 within 2 %)."""
    import subprocess
    import sys

    from conftest import REPO

    script = REPO / "examples" / "python" / "quickstart.py"
    assert len(script.read_text().splitlines()) < 30
    done = subprocess.run([sys.executable, str(script), str(tmp_path / "q.png")], capture_output=True, text=True, cwd=tmp_path)
    assert done.returncode == 0, done.stdout + done.stderr
    assert "f1: identified" in done.stdout and (tmp_path / "q.png").stat().st_size > 20_000


def test_the_command_line_draws_split_runs(runs, tmp_path):
    import subprocess
    import sys

    from conftest import REPO

    out = tmp_path / "day.png"
    done = subprocess.run(
        [sys.executable, str(REPO / "tools" / "plot_run.py"), str(runs / "day.mcap"), "--out", str(out)],
        capture_output=True, text=True,
    )
    assert done.returncode == 0, done.stderr
    assert "3 file(s)" in done.stdout and out.stat().st_size > 20_000
