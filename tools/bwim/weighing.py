"""Axle loads by Moses' least squares (Moses 1979; tools/bwim_check.py docstring, step 3):
every weighing section stacked, vehicles whose times on the bridge overlap solved jointly,
fragments lighter than --min-gross-kn dropped, poor fits flagged."""

from __future__ import annotations

import math

import numpy as np

from .calibration import Calibration, nuisance
from .io import Record, weighing_sections
from .vehicles import GROUP_SPACING_MAX_M, Vehicle, axle_positions, occupancy


def clusters_of(vehicles: list[Vehicle], cal: Calibration) -> list[list[Vehicle]]:
    """Vehicles whose influence spans overlap in time, in groups (multiple presence)."""
    s_lo, s_hi = cal.s_grid[0], cal.s_grid[-1]
    spans = sorted(((*occupancy(v, cal.geometry, s_lo, s_hi), v) for v in vehicles), key=lambda x: x[0])
    out, end = [], -np.inf
    for a, b, v in spans:
        if out and a < end:
            out[-1].append(v)
            end = max(end, b)
        else:
            out.append([v])
            end = b
    return out


def moses(
    rec: Record,
    sections,
    cal: Calibration,
    group: list[Vehicle],
    pad_s: float,
    group_penalty: float = 0.0,
    f1: float | None = None,
) -> float:
    """Axle loads of the vehicles of one cluster by least squares (Moses 1979): every
    weighing section stacked (weighted by the inverse of its noise), each with its own
    nuisance columns (baseline, and with f1 the first mode's vibration). Returns the fit's
    relative residual (rms residual over rms of the vehicles' modelled strain)."""
    s_lo, s_hi = cal.s_grid[0], cal.s_grid[-1]
    a = min(occupancy(v, cal.geometry, s_lo, s_hi)[0] for v in group) - pad_s
    b = max(occupancy(v, cal.geometry, s_lo, s_hi)[1] for v in group) + pad_s
    k0, k1 = max(int(math.floor(a * rec.fs_hz)), 0), min(int(math.ceil(b * rec.fs_hz)), rec.values.shape[0])
    t = np.arange(k0, k1) / rec.fs_hz
    n_axles = sum(len(v.t_axle) for v in group)
    positions = [axle_positions(v, t, cal.geometry) for v in group]
    Z_all = nuisance(t, f1)
    nz = Z_all.shape[1]
    nsec = len(sections)
    nu = n_axles + nz * nsec
    AtA = np.zeros((nu, nu))
    Atb = np.zeros(nu)
    kept = []
    for c, (_, y) in enumerate(sections):
        ok = np.isfinite(y[k0:k1])
        rows = np.zeros((int(ok.sum()), nu))
        col = 0
        for v, s in zip(group, positions, strict=True):
            il = cal.il[v.direction][c]
            for i in range(len(v.t_axle)):
                rows[:, col] = np.interp(s[ok, i], cal.s_grid, il, left=0.0, right=0.0)
                col += 1
        rows[:, n_axles + nz * c : n_axles + nz * (c + 1)] = Z_all[ok]
        w2 = 1.0 / cal.noise[c] ** 2
        AtA += w2 * rows.T @ rows
        Atb += w2 * rows.T @ y[k0:k1][ok]
        kept.append((rows, y[k0:k1][ok]))
    if group_penalty > 0:
        # Tikhonov penalty on the differences of neighbouring axles of a group (spacing
        # < 2.1 m): the least squares barely tell such axles apart (bwim_check.py docstring).
        scale = group_penalty * float(np.mean(np.diag(AtA)[:n_axles]))
        col = 0
        for v in group:
            for i, sp in enumerate(v.spacings):
                if sp < GROUP_SPACING_MAX_M:
                    d = np.zeros(nu)
                    d[col + i], d[col + i + 1] = 1.0, -1.0
                    AtA += scale * np.outer(d, d)
            col += len(v.t_axle)
    try:
        sol = np.linalg.solve(AtA, Atb)
    except np.linalg.LinAlgError:
        sol = np.linalg.lstsq(AtA, Atb, rcond=None)[0]
    col = 0
    for v in group:
        v.loads_n = sol[col : col + len(v.t_axle)] * 1e3
        col += len(v.t_axle)
    # Fit quality: the residual's energy relative to the vehicles' modelled response.
    res = sum(float(np.sum((yy - rows @ sol) ** 2)) for rows, yy in kept)
    sig = sum(float(np.sum((rows[:, :n_axles] @ sol[:n_axles]) ** 2)) for rows, _ in kept)
    return math.sqrt(res / max(sig, 1e-30))


def weigh(
    rec: Record, vehicles: list[Vehicle], cal: Calibration, args, f1: float | None
) -> tuple[list[list[Vehicle]], list[Vehicle]]:
    """Every cluster weighed (jointly); detections lighter than --min-gross-kn are no
    vehicles (a rebound taken for a vehicle, a fragment): dropped and the cluster weighed
    again. A cluster whose fit leaves a relative residual above --max-residual (a vehicle
    the FAD gauges missed, a wrong axle count) is flagged and not weighed. Returns the
    clusters and the dropped detections."""
    sections = weighing_sections(rec, args.fad_max_m)
    if [round(p, 2) for p, _ in sections] != [round(p, 2) for p in cal.sections_m]:
        raise ValueError(f"the calibration's sections {cal.sections_m} are not this run's {[p for p, _ in sections]}")
    groups = clusters_of(vehicles, cal)
    dropped = []
    out = []
    for group in groups:
        if len(group) > 1 and args.multiple_presence == "skip":
            out.append(group)
            continue
        residual = None
        while group:
            residual = moses(rec, sections, cal, group, args.pad_s, args.group_penalty, f1)
            light = [v for v in group if v.loads_n.sum() < args.min_gross_kn * 1e3]
            if not light:
                break
            worst = min(light, key=lambda v: v.loads_n.sum())
            worst.loads_n = None
            dropped.append(worst)
            group = [v for v in group if v is not worst]
        for v in group:
            v.residual = residual
            if residual is not None and residual > args.max_residual:
                v.loads_n = None
                v.poor_fit = True
        if group:
            out.append(group)
    for k, group in enumerate(out):
        for v in group:
            v.cluster, v.cluster_size = k, len(group)
    return out, dropped
