"""Axles and speed from road axle detectors (tape switches; ``--axles detectors``), the
alternative to the FAD gauges in SiWIM practice.

Per lane a pair of detectors a known distance ``D`` apart: their positions come from the
channel metadata, as the installer measured them (neighbours on one side of the bridge,
closest first, when a lane has more). Each detector's hits are grouped into vehicles by time gaps
(``--max-axle-gap-s``); a group on the upstream detector is paired with the group on the
downstream one under the delay ``d`` (between ``D / --v-max`` and ``D / --v-min``) that makes
most of its hits reappear there within ``--tape-tolerance-s`` (ties: the delay nearest the
lane's median delay, a missing hit leaving one axle against one). Then ``v = D / d``, ``d``
the mean delay of the axles seen by both detectors; an axle one detector missed takes its
time from the other, shifted by ``d`` (counted); an axle both missed is lost (the vehicle
then has an axle too few, as with a weak FAD step); a vehicle one detector missed whole
(a car's two axles) keeps the other's hits at the lane's median speed (counted). Each axle's time at the downstream
detector (the mean of both detectors' when both saw it) is carried at constant speed to the
entry support (``s = 0``): the vehicles' axle times there, spacings ``v`` times their
differences, split where two axles are farther apart than ``--max-spacing-m``. Which way a
pair's traffic goes is read from its hits (the orientation that pairs more axles); a pair
across every lane serves the direction whose approach it is on, and the hits that pair the
other way round, the other direction's vehicles leaving the bridge, are left out."""

from __future__ import annotations

import numpy as np

from .axles import first_frequency, group_axles
from .io import AxleDetector, Record, read_axle_detectors
from .vehicles import Geometry, Vehicle


def travel_s(x: float, direction: int, span_m: float) -> float:
    """Travel coordinate s (from the entry support) of the road position x."""
    return x if direction > 0 else span_m - x


def off_bridge_m(x: float, span_m: float) -> float:
    return max(-x, x - span_m, 0.0)


def best_delay(a: np.ndarray, b: np.ndarray, lo: float, hi: float, tol: float, prior: float | None):
    """(matches, d): the delay d in [lo, hi] under which most hits a reappear in b within
    tol; ties to the delay nearest prior, else to the smallest misfit. None without any."""
    diff = b[None, :] - a[:, None]
    cand = diff[(diff >= lo) & (diff <= hi)]
    best = None
    for d in cand:
        near = np.abs(diff - d).min(axis=1)
        hit = near <= tol
        m = int(hit.sum())
        key = (-m, abs(d - prior) if prior is not None else float(np.sum(near[hit] ** 2)))
        if best is None or key < best[0]:
            best = (key, m, float(d))
    return None if best is None else (best[1], best[2])


def merge_axles(a: np.ndarray, b: np.ndarray, d: float, tol: float):
    """The axles of one vehicle from its hits a (upstream) and b (downstream) under the delay
    d: (times at the downstream detector, mean delay, seen by both, by a only, by b only)."""
    pairs, used = [], set()
    for i, t in enumerate(a):
        j = int(np.argmin(np.abs(b - t - d)))
        if abs(b[j] - t - d) <= tol and j not in used:
            pairs.append((i, j))
            used.add(j)
    if pairs:
        d = float(np.mean([b[j] - a[i] for i, j in pairs]))
    paired_a = {i for i, _ in pairs}
    times = [0.5 * (a[i] + d + b[j]) for i, j in pairs]
    times += [a[i] + d for i in range(len(a)) if i not in paired_a]
    times += [b[j] for j in range(len(b)) if j not in used]
    return np.sort(np.array(times)), d, len(pairs), len(a) - len(pairs), len(b) - len(used)


def pair_hits(up: np.ndarray, down: np.ndarray, distance: float, args, prior: float | None = None):
    """Vehicles from one pair's hits (module doc): [(times at the downstream detector, delay,
    both, only up, only down)], and the hit groups left unpaired on each detector."""
    gap, tol = args.max_axle_gap_s, args.tape_tolerance_s
    lo, hi = distance / args.v_max, distance / args.v_min
    ga, gb = group_axles(up, gap), group_axles(down, gap)
    ends = np.array([h[-1] for h in gb])
    out, used, alone_up = [], set(), []
    for g in ga:
        best = None
        for j in range(int(np.searchsorted(ends, g[0] + lo - tol)), len(gb)):
            if gb[j][0] > g[-1] + hi + tol:
                break
            if j in used:
                continue
            r = best_delay(g, gb[j], lo, hi, tol, prior)
            if r is not None and (best is None or r[0] > best[0][0]):
                best = (r, j)
        if best is None:
            alone_up.append(g)
            continue
        used.add(best[1])
        out.append(merge_axles(g, gb[best[1]], best[0][1], tol))
    return out, alone_up, [h for j, h in enumerate(gb) if j not in used]


def pair_detectors(detectors: list[AxleDetector], span_m: float) -> tuple[list[tuple], list[str]]:
    """[(lane, detector, detector)]: in each lane (None: detectors across every lane) the
    neighbours along the road on one side of the bridge, closest pairs first (then nearest
    the bridge), each detector in one pair; and the ids of the detectors left out."""
    lanes: dict = {}
    for d in detectors:
        if np.isfinite(d.position_m):
            lanes.setdefault(d.lane, []).append(d)
    pairs, unused = [], [d.id for d in detectors if not np.isfinite(d.position_m)]
    for lane, ds in sorted(lanes.items(), key=lambda kv: (kv[0] is None, kv[0] or 0)):
        ds = sorted(ds, key=lambda d: (d.position_m, d.id))
        side = [d.position_m < 0.5 * span_m for d in ds]
        cand = [
            (
                ds[k + 1].position_m - ds[k].position_m,
                off_bridge_m(ds[k].position_m, span_m) + off_bridge_m(ds[k + 1].position_m, span_m),
                k,
            )
            for k in range(len(ds) - 1)
            if side[k] == side[k + 1] and ds[k + 1].position_m - ds[k].position_m > 0.1
        ]
        taken = set()
        for _, _, k in sorted(cand):
            if k not in taken and k + 1 not in taken:
                pairs.append((lane, ds[k], ds[k + 1]))
                taken |= {k, k + 1}
        unused += [d.id for k, d in enumerate(ds) if k not in taken]
    return pairs, unused


def detect_vehicles_tapes(rec: Record, args) -> tuple[list[Vehicle], dict, Geometry]:
    """Vehicles from the road axle detectors (module doc); the geometry's reference point is
    the entry support itself (s = 0)."""
    L = rec.span_m
    detectors = read_axle_detectors(rec.path, rec.t0_ns)
    if not detectors:
        raise ValueError("no road axle detectors (/sensors/axle/*) in the run: --axles detectors needs them")
    pairs, unused = pair_detectors(detectors, L)
    if not pairs:
        raise ValueError(
            f"no pair of axle detectors in one lane with their positions ({[d.id for d in detectors]}): "
            "need two per lane"
        )
    geo = Geometry(L, {1: 0.0, -1: 0.0}, {1: L, -1: L})
    info = {
        "axles": "detectors",
        "f1_hz": first_frequency(rec, args.fad_max_m),
        "pairs": [],
        "unused_detectors": unused,
    }
    vehicles = []
    for lane, p, q in pairs:
        distance = abs(q.position_m - p.position_m)
        # Which way the pair's traffic goes: in one lane the orientation that pairs more
        # axles; across every lane (or without hits) the direction whose approach it is on.
        tries = []
        for direction, up, down in ((1, p, q), (-1, q, p)):
            found, _, _ = pair_hits(up.times_s, down.times_s, distance, args)
            tries.append((sum(f[2] for f in found), direction, up, down, found))
        approach = 1 if p.position_m < 0.5 * L else -1
        if lane is None or tries[0][0] == tries[1][0]:
            tries.sort(key=lambda x: x[1] == approach, reverse=True)
        else:
            tries.sort(key=lambda x: x[0], reverse=True)
        _, direction, up, down, found = tries[0]
        # Again with the lane's median delay to settle ties (a vehicle with missed axles).
        clear = [f[1] for f in found if f[2] >= 2]
        prior = float(np.median(clear)) if clear else None
        found, alone_up, alone_down = pair_hits(up.times_s, down.times_s, distance, args, prior)
        # Groups that pair the other way round: the other direction's vehicles (a detector
        # across every lane), not used here. What remains is a vehicle one detector missed
        # whole (each of its axles): kept at the lane's median speed.
        other = 0
        if alone_up and alone_down:
            cat = np.concatenate
            back, alone_down, alone_up = pair_hits(cat(alone_down), cat(alone_up), distance, args)
            other = len(back)
        alone = []
        if prior is not None:
            alone = [(g + prior, prior, 0, 0, 0) for g in alone_up] + [(h, prior, 0, 0, 0) for h in alone_down]
        s_down = travel_s(down.position_m, direction, L)
        lone = 0
        n_vehicles = 0
        for t_down, delay, both, _, _ in found + alone:
            speed = distance / delay
            t_axle = t_down - s_down / speed  # at the entry support, s = 0
            for part in np.split(t_axle, np.where(np.diff(t_axle) * speed > args.max_spacing_m)[0] + 1):
                if len(part) >= 2:
                    vehicles.append(Vehicle(direction, part, speed, matched_exit=both))
                    n_vehicles += 1
                else:
                    lone += 1
        info["pairs"].append(
            {
                "lane": lane,
                "direction": direction,
                "up": up.id,
                "down": down.id,
                "up_position_m": up.position_m,
                "down_position_m": down.position_m,
                "distance_m": distance,
                "jitter_s": [up.jitter_s, down.jitter_s],
                "hits_up": len(up.times_s),
                "hits_down": len(down.times_s),
                "groups_paired": len(found),
                "vehicles": n_vehicles,
                "axles_both": sum(f[2] for f in found),
                "axles_up_only": sum(f[3] for f in found),
                "axles_down_only": sum(f[4] for f in found),
                "groups_up_only": len(alone_up),
                "groups_down_only": len(alone_down),
                "groups_at_median_speed": len(alone),
                "groups_other_direction": other,
                "lone_axles": lone,
                "median_delay_s": prior,
            }
        )
    vehicles.sort(key=lambda v: v.t_axle[0])
    for k, v in enumerate(vehicles):
        v.index = k
    return vehicles, info, geo
