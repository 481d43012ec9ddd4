"""The report: the printed summary and tables, the JSON of the results and the figure."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from .calibration import Calibration
from .cost323 import TOLERANCE_PCT
from .io import Record
from .scoring import Scores

G = 9.81


def print_table(title: str, table: dict) -> None:
    print(title)
    print("  criterion         n   mean %   std %    pi0 %  delta_min %  class reached")
    for name, r in table.items():
        if r["n"] < 5:
            print(f"  {name:<16} {r['n']:>3}   (fewer than 5 values)")
            continue
        print(
            f"  {name:<16} {r['n']:>3}  {r['mean_pct']:>+6.2f}  {r['std_pct']:>6.2f}  {100 * r['pi0']:>6.1f}  {r['delta_min_pct']:>10.2f}   {r['class_reached']}"
        )


def _detection_lines(args, cal: Calibration, det: dict, n_vehicles: int, n_dropped: int) -> list[str]:
    """The calibration's and the detection's lines: FAD gauges or road axle detectors."""
    src = (
        f"from {args.calibration_from} ({cal.source})"
        if args.calibration_from
        else f"on runs {cal.runs_used} (vehicles of known weight)"
    )
    dropped = f"{n_dropped} detections lighter than {args.min_gross_kn:g} kN dropped"
    if det.get("axles") != "detectors":
        return [
            f"calibration {src}: FAD distance {cal.geometry.distance[1]:.3f} m (+1), {cal.geometry.distance[-1]:.3f} m (-1); weighing sections at {cal.sections_m} m",
            f"detected {n_vehicles} vehicles ({det['unconfirmed_groups']} entry groups unconfirmed at the exit, {dropped}); FAD noise {det['fad_noise_microstrain']['W']:.3f} / {det['fad_noise_microstrain']['E']:.3f} microstrain (step filter)",
        ]
    lines = [
        f"calibration {src}: axles and speed from the road axle detectors; weighing sections at {cal.sections_m} m",
        f"detected {n_vehicles} vehicles by the road axle detectors ({dropped})"
        + (f"; detectors not used: {det['unused_detectors']}" if det["unused_detectors"] else ""),
    ]
    for p in det["pairs"]:
        lane = "every lane" if p["lane"] is None else f"lane {p['lane']}"
        lines.append(
            f"  {lane}, direction {p['direction']:+d}: {p['up']} ({p['up_position_m']:g} m) -> {p['down']} ({p['down_position_m']:g} m), {p['distance_m']:.3f} m apart: "
            f"{p['hits_up']} / {p['hits_down']} hits, {p['vehicles']} vehicles; axles seen by both {p['axles_both']}, "
            f"by one only (time from the other) {p['axles_up_only']} / {p['axles_down_only']}; "
            f"vehicles on one detector only {p['groups_up_only']} / {p['groups_down_only']} ({p['groups_at_median_speed']} kept at the lane's median speed), lone axles {p['lone_axles']}"
            + (
                f", {p['groups_other_direction']} vehicles going the other way not used"
                if p["groups_other_direction"]
                else ""
            )
        )
    return lines


def axle_truth_lines(det: dict, crossings: list[dict]) -> tuple[list[str], list[dict]]:
    """/truth/axle_detections per pair: crossings, hits missed by each detector, axles both
    missed (lost to the pipeline)."""
    lines, out = [], []
    for p in det.get("pairs", []):
        mine = {p["up"]: {}, p["down"]: {}}
        for c in crossings:
            if c["detector_id"] in mine:
                mine[c["detector_id"]][(c["vehicle_id"], c["axle_index"])] = c["detected"]
        up, down = mine[p["up"]], mine[p["down"]]
        row = {
            "up": p["up"],
            "down": p["down"],
            "crossings_up": len(up),
            "crossings_down": len(down),
            "missed_up": sum(1 for k in up.values() if not k),
            "missed_down": sum(1 for k in down.values() if not k),
            "missed_by_both": sum(1 for a, k in up.items() if not k and a in down and not down[a]),
        }
        out.append(row)
        lines.append(
            f"axle detectors {p['up']} / {p['down']}, truth: "
            f"{row['crossings_up']} / {row['crossings_down']} axle crossings, "
            f"{row['missed_up']} / {row['missed_down']} missed, {row['missed_by_both']} missed by both"
        )
    return lines, out


def print_report(
    args,
    rec: Record,
    cal: Calibration,
    det: dict,
    n_vehicles: int,
    n_dropped: int,
    loo: list[dict],
    s: Scores,
    times: tuple[float, float],
    ok: bool,
    axle_truth: list[str],
) -> None:
    t_read, t_process = times
    duration = rec.values.shape[0] / rec.fs_hz
    rows, weighed = s.rows, s.weighed
    print(
        f"{args.run}: {len(rec.ids)} strain gauges at {rec.fs_hz:g} Hz, {duration:.1f} s, span {rec.span_m:g} m, {rec.lost} lost samples; read in {t_read:.2f} s, processed in {t_process:.2f} s ({t_process / max(duration, 1e-9) * 3600:.1f} s per hour of data)"
    )
    for line in _detection_lines(args, cal, det, n_vehicles, n_dropped):
        print(line)
    print(
        f"multiple presence: {len(s.multi_clusters)} events with {sum(len(g) for g in s.multi_clusters)} vehicles ({'solved jointly' if args.multiple_presence == 'joint' else 'not weighed'}); scored vehicles in them: {sum(1 for r in weighed if r['cluster_size'] > 1)}"
    )
    print(
        f"truth: {len(s.heavy_truth)} vehicles > 3.5 t in the traffic: {len(rows)} detected, {len(weighed)} weighed and scored ({sum(1 for r in rows if r.get('not_weighed') == 'multiple presence')} in multiple presence not weighed, {sum(1 for r in rows if r.get('not_weighed') == 'poor fit')} flagged for a poor fit), {len(s.missed)} missed; {len(s.light)} detections of lighter vehicles and {len(s.false_det)} unmatched detections not scored"
    )
    for line in axle_truth:
        print(line)
    print(
        f"axle count right for {s.axle_ok} of {len(rows)} detected; speed error {100 * np.mean([r['speed_error'] for r in rows]) if rows else float('nan'):+.2f} % mean, {100 * np.std([r['speed_error'] for r in rows]) if rows else float('nan'):.2f} % sd"
    )
    if s.loo_table:
        print_table(f"calibration runs, leave-one-out (r2-I, {len(loo)} runs):", s.loo_table)
    print_table(f"traffic, COST 323 conditions {args.conditions}:", s.table)
    verdict = "PASS" if ok else "FAIL"
    print(
        f"{verdict}: gross weight class {s.table['gross'].get('class_reached')} "
        f"(expected {args.expect_class} or better)"
    )


def write_json(
    path: str,
    args,
    rec: Record,
    cal: Calibration,
    det: dict,
    n_vehicles: int,
    n_dropped: int,
    loo: list[dict],
    s: Scores,
    times: tuple[float, float],
    ok: bool,
    axle_truth: list[dict] | None,
) -> None:
    rows, weighed = s.rows, s.weighed
    out = {
        "run": args.run,
        "duration_s": rec.values.shape[0] / rec.fs_hz,
        "fs_hz": rec.fs_hz,
        "read_s": times[0],
        "process_s": times[1],
        "calibration": cal.to_json(),
        "detection": det,
        "conditions": args.conditions,
        "vehicles_detected": n_vehicles,
        "detections_dropped": n_dropped,
        "truth_over_3_5t": len(s.heavy_truth),
        "detected_over_3_5t": len(rows),
        "scored": len(weighed),
        "poor_fit": sum(1 for r in rows if r.get("not_weighed") == "poor fit"),
        "missed": len(s.missed),
        "light_detections": len(s.light),
        "unmatched_detections": len(s.false_det),
        "multiple_presence_events": len(s.multi_clusters),
        "multiple_presence_vehicles": sum(len(g) for g in s.multi_clusters),
        "scored_in_multiple_presence": sum(1 for r in weighed if r["cluster_size"] > 1),
        "axle_count_right": s.axle_ok,
        "criteria": s.table,
        "calibration_leave_one_out": s.loo_table,
        "expect_class": args.expect_class,
        "pass": ok,
        "vehicles": rows,
        "calibration_runs": loo,
    }
    if axle_truth is not None:  # --axles detectors only: a FAD run's JSON stays as it was
        out["axle_detector_truth"] = axle_truth
    Path(path).write_text(json.dumps(out, indent=1, default=float))


def plot(path: str, cal: Calibration, rows: list[dict], table: dict, title: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(2, 2, figsize=(11, 8))
    for direction, style in ((1, "-"), (-1, "--")):
        for c, p in enumerate(cal.sections_m):
            ax[0, 0].plot(
                cal.s_grid, cal.il[direction][c], style, color=f"C{c}", label=f"x = {p:g} m, dir {direction:+d}"
            )
    ax[0, 0].set(
        xlabel="axle position from the entry support s (m)",
        ylabel="influence line (microstrain / kN)",
        title="calibrated influence lines (matrix method)",
    )
    ax[0, 0].legend(fontsize=7)
    w = [r for r in rows if r.get("weighed")]
    single = [r for r in w if r["cluster_size"] == 1]
    multi = [r for r in w if r["cluster_size"] > 1]
    for sel, lab, mk in ((single, "alone on the bridge", "o"), (multi, "multiple presence (joint)", "x")):
        if sel:
            ax[0, 1].plot(
                [r["gross_true_n"] / 1e3 / G for r in sel],
                [r["gross_n"] / 1e3 / G for r in sel],
                mk,
                label=f"{lab} ({len(sel)})",
            )
    if w:
        hi = max(r["gross_true_n"] for r in w) / 1e3 / G * 1.1
        ax[0, 1].plot([0, hi], [0, hi], "k-", lw=0.8)
    ax[0, 1].set(xlabel="static gross weight (t)", ylabel="B-WIM gross weight (t)", title="gross weight")
    ax[0, 1].legend(fontsize=8)
    e = 100 * np.array([r["gross_error"] for r in w]) if w else np.array([])
    if len(e):
        ax[1, 0].hist(e, bins=max(8, len(e) // 5), color="C0", alpha=0.8)
    g = table["gross"]
    for c, col in (("A(5)", "C2"), ("B+(7)", "C1"), ("B(10)", "C3")):
        d = TOLERANCE_PCT[c][0]
        ax[1, 0].axvspan(-d, d, color=col, alpha=0.08)
        ax[1, 0].axvline(d, color=col, lw=0.8, label=f"{c}: +/-{d:g} %")
        ax[1, 0].axvline(-d, color=col, lw=0.8)
    t = (
        f"gross error: mean {g['mean_pct']:+.2f} %, sd {g['std_pct']:.2f} %, class {g.get('class_reached')}"
        if g["n"] >= 5
        else "gross error"
    )
    ax[1, 0].set(xlabel="gross weight error (%)", ylabel="vehicles", title=t)
    ax[1, 0].legend(fontsize=8)
    if w:
        ax[1, 1].plot([r["speed_m_s"] for r in single], [100 * r["gross_error"] for r in single], "o", label="alone")
        ax[1, 1].plot(
            [r["speed_m_s"] for r in multi], [100 * r["gross_error"] for r in multi], "x", label="multiple presence"
        )
    ax[1, 1].axhline(0, color="k", lw=0.8)
    ax[1, 1].set(xlabel="measured speed (m/s)", ylabel="gross weight error (%)", title="error against speed")
    ax[1, 1].legend(fontsize=8)
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
