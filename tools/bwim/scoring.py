"""Only then the truth (tools/bwim_check.py docstring, step 4): detections matched to
/truth/vehicles by direction and entry time, relative errors of the gross weight, groups of
axles, single axles and axles of a group, and the COST 323 class of each criterion."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .cost323 import CRITERIA, DOMAIN_GROSS_N, assess
from .io import Record
from .vehicles import GROUP_SPACING_MAX_M, Geometry, Vehicle


def match_truth(rec: Record, vehicles: list[Vehicle], truth: list[dict], geo: Geometry, tol_s: float) -> None:
    """Each detection to the truth vehicle of its direction entering nearest in time."""
    pairs = []
    for v in vehicles:
        t_in = v.t_axle[0] - geo.s_entry[v.direction] / v.speed
        for k, tr in enumerate(truth):
            if tr["direction"] == v.direction:
                dt = abs((tr["entry_ns"] - rec.t0_ns) / 1e9 - t_in)
                if dt <= tol_s:
                    pairs.append((dt, v.index, k))
    used_v, used_t = set(), set()
    for _, vi, k in sorted(pairs):
        if vi not in used_v and k not in used_t:
            vehicles[vi].truth = truth[k]
            used_v.add(vi)
            used_t.add(k)


def groups_of(spacings: np.ndarray) -> list[list[int]]:
    out = [[0]]
    for i, s in enumerate(spacings):
        if s < GROUP_SPACING_MAX_M:
            out[-1].append(i + 1)
        else:
            out.append([i + 1])
    return out


def vehicle_errors(v: Vehicle) -> dict:
    tr = v.truth
    row = {
        "truth_id": tr["id"],
        "class": tr["class"],
        "direction": v.direction,
        "cluster_size": v.cluster_size,
        "axles_detected": len(v.t_axle),
        "axles_true": len(tr["loads_n"]),
        "speed_m_s": v.speed,
        "speed_error": v.speed / tr["speed_m_s"] - 1.0,
        "gross_true_n": tr["gross_n"],
        "residual": v.residual,
    }
    if v.loads_n is None:
        row["weighed"] = False
        row["not_weighed"] = "poor fit" if v.poor_fit else "multiple presence"
        return row
    row.update(weighed=True, gross_n=float(v.loads_n.sum()), gross_error=float(v.loads_n.sum() / tr["gross_n"] - 1.0))
    if len(v.t_axle) == len(tr["loads_n"]):
        row["axle_errors"] = (v.loads_n / tr["loads_n"] - 1.0).tolist()
        row["spacing_errors_m"] = (v.spacings - tr["spacings_m"]).tolist()
        g_err, s_err, a_err = [], [], []
        for g in groups_of(tr["spacings_m"]):
            est, true = v.loads_n[g].sum(), tr["loads_n"][g].sum()
            if len(g) >= 2:
                g_err.append(est / true - 1.0)
                a_err += [float(v.loads_n[i] / tr["loads_n"][i] - 1.0) for i in g]
            else:
                s_err.append(est / true - 1.0)
        row.update(group_errors=g_err, single_errors=s_err, axle_of_group_errors=a_err)
    return row


def criterion_errors(rows: list[dict]) -> list[np.ndarray]:
    gross = [r["gross_error"] for r in rows if r.get("weighed")]
    group = [e for r in rows for e in r.get("group_errors", [])]
    single = [e for r in rows for e in r.get("single_errors", [])]
    axle = [e for r in rows for e in r.get("axle_of_group_errors", [])]
    return [np.array(x) for x in (gross, group, single, axle)]


def score_table(rows: list[dict], conditions: str) -> dict:
    return {
        name: assess(errs, c, conditions)
        for c, (name, errs) in enumerate(zip(CRITERIA, criterion_errors(rows), strict=True))
    }


@dataclass
class Scores:
    """The traffic's errors and counts against the truth."""

    rows: list[dict]  # per scored detection (traffic, > 3.5 t)
    weighed: list[dict]  # the rows weighed
    table: dict  # criterion -> COST 323 assessment
    loo_table: dict | None  # the calibration runs, leave-one-out
    heavy_truth: list[dict]  # traffic vehicles > 3.5 t in the truth
    missed: list[dict]  # of those, not detected (entering well inside the record)
    light: list[Vehicle]  # detections of vehicles of 3.5 t or less
    false_det: list[Vehicle]  # detections matching no truth vehicle
    multi_clusters: list[list[Vehicle]]  # multiple-presence events
    axle_ok: int  # scored detections with the right axle count


def score_run(
    rec: Record,
    vehicles: list[Vehicle],
    groups: list[list[Vehicle]],
    truth: list[dict],
    loo: list[dict],
    geo: Geometry,
    args,
) -> Scores:
    """Every detection matched to the truth; the traffic vehicles over 3.5 t scored."""
    # The scenario's listed vehicles (the calibration truck's runs) are no traffic.
    listed = set(rec.listed_vehicle_ids) | set(args.calibration_ids or [])
    match_truth(rec, vehicles, truth, geo, args.match_truth_s)
    scored = [
        v
        for v in vehicles
        if v.truth is not None and v.truth["id"] not in listed and v.truth["gross_n"] > DOMAIN_GROSS_N
    ]
    rows = [vehicle_errors(v) for v in scored]
    table = score_table(rows, args.conditions)
    loo_table = score_table(loo, "r2-I") if loo else None
    heavy_truth = [tr for tr in truth if tr["gross_n"] > DOMAIN_GROSS_N and tr["id"] not in listed]
    duration = rec.values.shape[0] / rec.fs_hz
    matched_ids = {v.truth["id"] for v in vehicles if v.truth is not None}
    multi_clusters = [g for g in groups if len(g) > 1]
    light = [v for v in vehicles if v.truth is not None and v.truth["gross_n"] <= DOMAIN_GROSS_N]
    false_det = [v for v in vehicles if v.truth is None]
    missed = [
        tr
        for tr in heavy_truth
        if tr["id"] not in matched_ids
        and (tr["entry_ns"] - rec.t0_ns) / 1e9 < duration - 3.0
        and (tr["entry_ns"] - rec.t0_ns) / 1e9 > 1.0
    ]
    weighed = [r for r in rows if r.get("weighed")]
    axle_ok = sum(1 for r in rows if r["axles_detected"] == r["axles_true"])
    return Scores(rows, weighed, table, loo_table, heavy_truth, missed, light, false_det, multi_clusters, axle_ok)
