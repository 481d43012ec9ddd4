#!/usr/bin/env python3
"""Plot a bridgetwin run to a PNG: accelerations, axle loads, displacements and deflected
shape snapshots.

    python3 tools/plot_run.py run.mcap --out run.png

Deflections are positive downward (the output contract), so those axes point down.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # files only, no display needed
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
from read_run import list_topics, load_topics  # noqa: E402

BLOCKS_SUFFIX = "/blocks"
SNAPSHOTS = 6


def sensor_topics(topics: list[str], prefix: str) -> list[str]:
    """Topics under `prefix`; a block topic only when its per-sample twin is absent."""
    chosen = [t for t in topics if t.startswith(prefix) and not t.endswith(BLOCKS_SUFFIX)]
    twins = {t + BLOCKS_SUFFIX for t in chosen}
    return chosen + [t for t in topics if t.startswith(prefix) and t.endswith(BLOCKS_SUFFIX) and t not in twins]


def no_data(ax, what: str) -> None:
    ax.text(0.5, 0.5, f"no {what} in this file", ha="center", va="center", transform=ax.transAxes)


def plot_accelerations(ax, data: dict, topics: list[str]) -> None:
    for topic in topics:
        ax.plot(data[topic]["time_s"], data[topic]["acceleration_m_s2"], lw=0.8, label=topic)
    ax.set(title="Accelerations (DAQ)", xlabel="time (s)", ylabel="acceleration (m/s²)")
    if topics:
        ax.legend(fontsize="small")
    else:
        no_data(ax, "/sensors/accel/* topics")


def plot_axle_loads(ax, axles: dict | None) -> None:
    ax.set(title="Axle contact forces (truth)", xlabel="time (s)", ylabel="force (kN)")
    if axles is None or "axles.force_n" not in axles:
        no_data(ax, "/truth/axle_loads")
        return
    pairs = np.unique(np.column_stack([axles["axles.vehicle_id"], axles["axles.axle_index"]]), axis=0)
    for vehicle_id, axle_index in pairs:
        rows = (axles["axles.vehicle_id"] == vehicle_id) & (axles["axles.axle_index"] == axle_index)
        time_s = axles["axles.time_s"][rows]
        line = ax.plot(time_s, axles["axles.force_n"][rows] / 1e3, lw=0.8, label=f"vehicle {vehicle_id} axle {axle_index}")
        ax.plot(time_s, axles["axles.static_load_n"][rows] / 1e3, lw=0.6, ls="--", color=line[0].get_color())
    ax.legend(fontsize="small", title="dashed: static load", title_fontsize="small")


def plot_displacements(ax, data: dict, topics: list[str], bridge: dict | None) -> None:
    for topic in topics:
        ax.plot(data[topic]["time_s"], data[topic]["displacement_m"] * 1e3, lw=0.8, label=topic)
    if bridge is not None and "midspan_deflection_m" in bridge:
        ax.plot(bridge["time_s"], bridge["midspan_deflection_m"] * 1e3, "k.", ms=3, label="/truth/bridge midspan")
    ax.set(title="Displacements", xlabel="time (s)", ylabel="deflection (mm, down)")
    if ax.lines:
        ax.invert_yaxis()
        ax.legend(fontsize="small")
    else:
        no_data(ax, "displacement topics")


def plot_shapes(ax, bridge: dict | None) -> None:
    ax.set(title="Deflected shape (truth)", xlabel="position along bridge (m)", ylabel="deflection (mm, down)")
    if bridge is None or np.size(bridge.get("deflection_m", [])) == 0 or bridge["deflection_m"].dtype == object:
        no_data(ax, "/truth/bridge deflection shapes")
        return
    deflection_m, time_s = bridge["deflection_m"], bridge["time_s"]
    # Evenly spaced snapshots plus the one with the largest deflection.
    picks = set(np.linspace(0, len(time_s) - 1, SNAPSHOTS).round().astype(int))
    picks.add(int(np.abs(deflection_m).max(axis=1).argmax()))
    colors = plt.cm.viridis(np.linspace(0, 1, len(picks)))
    for color, k in zip(colors, sorted(picks)):
        ax.plot(bridge["node_position_m"][k], deflection_m[k] * 1e3, color=color, label=f"t = {time_s[k]:.2f} s")
    ax.invert_yaxis()
    ax.legend(fontsize="small")


def plot_run(path: str, out: str, dpi: int = 120) -> None:
    topics = list_topics(path)
    accel = sensor_topics(topics, "/sensors/accel/")
    disp = sensor_topics(topics, "/sensors/disp/")
    wanted = accel + disp + [t for t in ("/truth/axle_loads", "/truth/bridge") if t in topics]
    data = load_topics(path, wanted)

    fig, axes = plt.subplots(2, 2, figsize=(13, 8), constrained_layout=True)
    plot_accelerations(axes[0, 0], data, accel)
    plot_axle_loads(axes[0, 1], data.get("/truth/axle_loads"))
    plot_displacements(axes[1, 0], data, disp, data.get("/truth/bridge"))
    plot_shapes(axes[1, 1], data.get("/truth/bridge"))
    for ax in axes.flat:
        ax.grid(True, alpha=0.3)
    fig.suptitle(Path(path).name)
    fig.savefig(out, dpi=dpi)
    plt.close(fig)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("file", metavar="FILE")
    parser.add_argument("--out", metavar="PNG", help="output image (default: FILE with .png)")
    parser.add_argument("--dpi", type=int, default=120)
    args = parser.parse_args()
    out = args.out or str(Path(args.file).with_suffix(".png"))
    plot_run(args.file, out, args.dpi)
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
