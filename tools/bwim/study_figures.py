"""The figures of the B-WIM study (tools/bwim_study.py): error and class against road,
speed, noise and traffic flow, the calibrated influence lines, the hour."""

from __future__ import annotations

from pathlib import Path

import numpy as np


def plot_all(rows: list[dict], out: Path, il_static: dict | None, cal: dict | None) -> list[str]:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    made = []
    bands = (("A(5)", 5, "C2"), ("B+(7)", 7, "C1"), ("B(10)", 10, "C3"))

    def deltas(ax):
        for name, d, col in bands:
            ax.axhline(d / 2, color=col, lw=0.8, ls=":", label=f"{name}: delta/2 = {d / 2:g} %")

    def by(group):
        return [r for r in rows if r["group"] == group and not r.get("failed")]

    # Road class.
    rr = by("road")
    if rr:
        fig, ax = plt.subplots(1, 2, figsize=(11, 4.2))
        order = ["smooth", "A", "B", "C"]
        for crit, lab in (("gross", "gross"), ("group", "group of axles"), ("single", "single axle")):
            xs, ys = [], []
            for r in rr:
                xs.append(order.index(r["x"]) + {"gross": -0.15, "group": 0.0, "single": 0.15}[crit])
                ys.append(r[f"{crit}_sd_pct"])
            ax[0].plot(xs, ys, "o", label=lab)
        ax[0].set_xticks(range(len(order)), ["smooth", "class A", "class B", "class C"])
        deltas(ax[0])
        ax[0].set(
            ylabel="standard deviation of the error (%)", title="B-WIM error against road roughness (two seeds each)"
        )
        ax[0].legend(fontsize=7)
        for r in rr:
            ax[1].plot(order.index(r["x"]), r["gross_delta_min_pct"], "o", color="C0")
        for name, d, col in bands:
            ax[1].axhline(d, color=col, lw=0.8, ls=":", label=f"{name}")
        ax[1].axhline(15, color="C4", lw=0.8, ls=":", label="C(15)")
        ax[1].set_xticks(range(len(order)), ["smooth", "class A", "class B", "class C"])
        ax[1].set(ylabel="delta_min, gross weight (%)", title="narrowest COST 323 interval passed (R2-I)")
        ax[1].legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(out / "error_vs_road.svg")
        plt.close(fig)
        made.append("error_vs_road.svg")
    # Speed, noise: gross sd and delta_min.
    for group, fname, xlabel, title in (
        ("speed", "error_vs_speed.svg", "mean traffic speed (m/s)", "B-WIM error against traffic speed (class A)"),
        (
            "noise",
            "error_vs_noise.svg",
            "strain noise density / foil gauge's (0.0224 microstrain/sqrt(Hz))",
            "B-WIM error against strain noise (class A)",
        ),
    ):
        rr = sorted(by(group), key=lambda r: r["x"])
        if not rr:
            continue
        fig, ax = plt.subplots(1, 2, figsize=(11, 4.2))
        x = [r["x"] for r in rr]
        for crit, lab in (("gross", "gross"), ("group", "group of axles"), ("single", "single axle")):
            ax[0].plot(x, [r[f"{crit}_sd_pct"] for r in rr], "o-", label=lab)
        deltas(ax[0])
        ax[0].set(xlabel=xlabel, ylabel="standard deviation of the error (%)", title=title)
        if group == "noise":
            ax[0].set_xscale("log")
        ax[0].legend(fontsize=7)
        ax[1].plot(x, [100.0 * r["detected"] / max(r["trucks"], 1) for r in rr], "o-", label="trucks detected (%)")
        ax[1].plot(
            x, [100.0 * r["axle_count_right"] / max(r["detected"], 1) for r in rr], "s-", label="axle count right (%)"
        )
        ax[1].set(xlabel=xlabel, ylabel="%", title="FAD axle detection", ylim=(0, 105))
        if group == "noise":
            ax[1].set_xscale("log")
        ax[1].legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(out / fname)
        plt.close(fig)
        made.append(fname)
    # Multiple presence.
    rr = by("flow")
    if rr:
        fig, ax = plt.subplots(1, 2, figsize=(11, 4.2))
        for mode, mk in (("joint", "o-"), ("skip", "s--")):
            sel = sorted([r for r in rr if r["mode"] == mode], key=lambda r: r["x"])
            ax[0].plot(
                [r["x"] for r in sel],
                [r["gross_sd_pct"] for r in sel],
                mk,
                label=f"gross, multiple presence {'solved jointly' if mode == 'joint' else 'skipped'}",
            )
            if mode == "joint":
                for r in sel:
                    ax[0].annotate(
                        f"n = {r['scored']}",
                        (r["x"], r["gross_sd_pct"]),
                        fontsize=7,
                        xytext=(4, 4),
                        textcoords="offset points",
                    )
            ax[1].plot(
                [r["x"] for r in sel],
                [100.0 * r["scored"] / max(r["trucks"], 1) for r in sel],
                mk,
                label=f"trucks weighed ({mode})",
            )
        sel = sorted([r for r in rr if r["mode"] == "joint"], key=lambda r: r["x"])
        ax[1].plot(
            [r["x"] for r in sel],
            [100.0 * r["scored_in_mp"] / max(r["scored"], 1) for r in sel],
            "^:",
            label="weighed trucks in multiple presence",
        )
        deltas(ax[0])
        ax[0].set(
            xlabel="flow per lane (veh/h, two lanes, 20 % trucks)",
            ylabel="gross weight error sd (%)",
            title="B-WIM gross error against traffic flow",
        )
        ax[0].legend(fontsize=7)
        ax[1].set(
            xlabel="flow per lane (veh/h)", ylabel="% of the trucks over 3.5 t", title="what is weighed", ylim=(0, 105)
        )
        ax[1].legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(out / "error_vs_flow.svg")
        plt.close(fig)
        made.append("error_vs_flow.svg")
    # Calibration.
    rr = by("calibration")
    if rr:
        fig, ax = plt.subplots(figsize=(8, 4.2))
        labels = [r["variant"] for r in rr]
        xx = np.arange(len(rr))
        for k, (crit, lab) in enumerate(
            (
                ("gross", "gross"),
                ("group", "group of axles"),
                ("single", "single axle"),
                ("axle_of_group", "axle of a group"),
            )
        ):
            ax.bar(xx + (k - 1.5) * 0.2, [r[f"{crit}_sd_pct"] for r in rr], 0.2, label=lab)
        ax.set_xticks(xx, labels, rotation=15, fontsize=7)
        ax.set(
            ylabel="standard deviation of the error (%)",
            title="calibration runs used, and regularised Moses (same run)",
        )
        ax.set_yscale("log")
        ax.legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(out / "calibration.svg")
        plt.close(fig)
        made.append("calibration.svg")
    # Influence lines.
    if il_static and cal:
        fig, ax = plt.subplots(figsize=(8, 4.5))
        s = np.array(cal["s_grid_m"])
        for c, pos in enumerate(cal["sections_m"]):
            ref = il_static.get(float(pos))
            if ref is not None:
                ax.plot(ref[0], ref[1], color=f"C{c}", lw=2.5, alpha=0.35, label=f"x = {pos:g} m, static (twin)")
            ax.plot(
                s,
                np.array(cal["il_microstrain_per_kn"]["1"])[c],
                color=f"C{c}",
                lw=1,
                label=f"x = {pos:g} m, calibrated (direction +1)",
            )
        ax.set(
            xlim=(-1, max(s) + 0.5),
            xlabel="axle position s from the entry support (m)",
            ylabel="microstrain per kN",
            title="influence lines: matrix method on the calibration runs vs the twin's static lines",
        )
        ax.legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(out / "influence_lines.svg")
        plt.close(fig)
        made.append("influence_lines.svg")
    return made
