"""Influence lines by the matrix method (OBrien, Quilligan & Karoumi 2006; tools/bwim_check.py
docstring, step 2) from the calibration truck's runs: its known axle loads and spacings, its
measured axle times, every run stacked in one least-squares system per direction."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import sparse

from .axles import first_frequency
from .io import Record, weighing_signals
from .vehicles import Geometry, Vehicle, axle_positions, occupancy


@dataclass
class Calibration:
    geometry: Geometry
    s_grid: np.ndarray
    sections_m: list[float]
    il: dict  # direction -> [n_sections, n_grid], microstrain per kN
    noise: np.ndarray  # per section, microstrain
    gauge_ids: list[str]
    runs_used: list[int]
    source: str = ""
    axles: str = "fad"  # how the axles were found: "fad" or "detectors" (road axle detectors)
    detectors: list | None = None  # with "detectors": the pairs used (ids, positions, distance)

    def to_json(self) -> dict:
        d = {
            "source": self.source,
            "span_m": self.geometry.span_m,
            "s_entry_m": {str(k): v for k, v in self.geometry.s_entry.items()},
            "fad_distance_m": {str(k): v for k, v in self.geometry.distance.items()},
            "s_grid_m": self.s_grid.tolist(),
            "sections_m": self.sections_m,
            "il_microstrain_per_kn": {str(k): v.tolist() for k, v in self.il.items()},
            "noise_microstrain": self.noise.tolist(),
            "gauge_ids": self.gauge_ids,
            "runs_used": self.runs_used,
        }
        if self.axles != "fad":  # a FAD calibration's file stays as it was
            d["axles"] = self.axles
            d["axle_detectors"] = self.detectors
        return d

    @staticmethod
    def from_json(d: dict) -> Calibration:
        geo = Geometry(
            float(d["span_m"]),
            {int(k): float(v) for k, v in d["s_entry_m"].items()},
            {int(k): float(v) for k, v in d["fad_distance_m"].items()},
        )
        return Calibration(
            geo,
            np.array(d["s_grid_m"]),
            list(d["sections_m"]),
            {int(k): np.array(v) for k, v in d["il_microstrain_per_kn"].items()},
            np.array(d["noise_microstrain"]),
            list(d["gauge_ids"]),
            list(d["runs_used"]),
            d.get("source", ""),
            d.get("axles", "fad"),
            d.get("axle_detectors"),
        )


def hat_matrix(s: np.ndarray, s_grid: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Piecewise-linear basis on s_grid at the points s: (left node, weight left, weight
    right); points outside the grid get zero weights."""
    h = s_grid[1] - s_grid[0]
    u = (s - s_grid[0]) / h
    j = np.floor(u).astype(np.int64)
    f = u - j
    inside = (j >= 0) & (j < len(s_grid) - 1)
    j = np.where(inside, j, 0)
    return j, np.where(inside, 1.0 - f, 0.0), np.where(inside, f, 0.0)


def section_noise(y: np.ndarray) -> float:
    """Robust noise level of a strain record: 1.4826 MAD of the first difference / sqrt 2."""
    d = np.diff(y[np.isfinite(y)])
    return max(1.4826 * float(np.median(np.abs(d - np.median(d)))) / math.sqrt(2), 1e-9)


def calibration_runs(
    rec: Record,
    vehicles: list[Vehicle],
    cal_truth: list[dict],
    geo: Geometry,
    args,
    others: list[Vehicle] | None = None,
    calibrate_distance: bool = True,
):
    """The detections that are the calibration truck's runs, alone on the bridge, and the
    geometry with the FAD distance calibrated on them: each run's speed from its known
    axle spacings (least squares of its axle times against them) times its measured delay
    between the supports' steps, median over the runs of a direction. Without
    calibrate_distance (road axle detectors: the installer measured their distance) the
    geometry is returned as it is."""
    L = rec.span_m
    runs = []
    for tr in cal_truth:
        t_entry = (tr["entry_ns"] - rec.t0_ns) / 1e9
        best = None
        for v in vehicles:
            if v.direction != tr["direction"] or len(v.t_axle) != len(tr["loads_n"]):
                continue
            dt = abs(v.t_axle[0] - geo.s_entry[v.direction] / v.speed - t_entry)
            if dt < args.cal_match_s and (best is None or dt < best[0]):
                best = (dt, v)
        if best is not None:
            runs.append((tr, best[1]))
    clean = []
    others = vehicles if others is None else others
    for tr, v in runs:
        a, b = occupancy(v, geo, -2.0, L + 2.0)
        if not any(
            o is not v and occupancy(o, geo, -2.0, L + 2.0)[0] < b and occupancy(o, geo, -2.0, L + 2.0)[1] > a
            for o in others
        ):
            clean.append((tr, v))
    directions = {v.direction for v in vehicles}
    if not clean or not {tr["direction"] for tr, _ in clean} >= directions:
        raise ValueError(
            f"calibration: {len(clean)} usable calibration runs (found {len(runs)} of {len(cal_truth)} known vehicles); need runs alone on the bridge in each direction of the traffic"
        )
    if not calibrate_distance:
        return clean, geo
    distance = dict(geo.distance)
    for direction in (1, -1):
        ds = []
        for tr, v in clean:
            if v.direction == direction and len(tr["spacings_m"]):
                cum = np.concatenate([[0.0], np.cumsum(tr["spacings_m"])])
                v_true = 1.0 / np.polyfit(cum, v.t_axle, 1)[0]
                ds.append(distance[direction] * v_true / v.speed)  # D = v_true * delay
        if ds:
            distance[direction] = float(np.median(ds))
    return clean, Geometry(L, dict(geo.s_entry), distance)


def nuisance(t: np.ndarray, f1: float | None) -> np.ndarray:
    """Columns a record may carry besides the vehicles' static response: the baseline and,
    with f1, the bridge's first-mode vibration, cos and sin at f1 with linearly varying
    amplitudes (free and forced vibration over one crossing)."""
    cols = [np.ones_like(t)]
    if f1:
        tc = (t - t.mean()) / max(t.max() - t.min(), 1e-9)
        c, s = np.cos(2 * np.pi * f1 * t), np.sin(2 * np.pi * f1 * t)
        cols += [c, s, tc * c, tc * s]
    return np.column_stack(cols)


def run_normals(rec: Record, tr: dict, v: Vehicle, geo: Geometry, s_grid: np.ndarray, args, f1: float | None = None):
    """One calibration run's share of the influence-line normal equations, with its baseline
    offset eliminated (Schur complement): (M [ng, ng], g [ng, n_sections]). The run's speed
    comes from its known spacings, its axle positions from the measured axle times."""
    ng = len(s_grid)
    Y = weighing_signals(rec, args.fad_max_m)[1]
    cum = np.concatenate([[0.0], np.cumsum(tr["spacings_m"])])
    slope, icpt = np.polyfit(cum, v.t_axle, 1)
    vv = Vehicle(v.direction, icpt + slope * cum, 1.0 / slope)
    a, b = occupancy(vv, geo, s_grid[0], s_grid[-1])
    k0 = max(int(math.floor((a - args.pad_s) * rec.fs_hz)), 0)
    k1 = min(int(math.ceil((b + args.pad_s) * rec.fs_hz)), len(Y))
    t = np.arange(k0, k1) / rec.fs_hz
    ok = np.isfinite(Y[k0:k1]).all(axis=1)
    s = axle_positions(vv, t[ok], geo)
    n = int(ok.sum())
    rows, cols, vals = [], [], []
    rr = np.arange(n)
    for i, load in enumerate(tr["loads_n"] / 1e3):
        j, wl, wr = hat_matrix(s[:, i], s_grid)
        rows += [rr, rr]
        cols += [j, j + 1]
        vals += [load * wl, load * wr]
    A = sparse.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(n, ng)).toarray()
    Z = nuisance(t[ok], f1)
    Yk = Y[k0:k1][ok]
    # Eliminate the run's nuisance columns (Schur complement).
    NZZ = Z.T @ Z
    P = np.linalg.solve(NZZ, Z.T)  # (Z^T Z)^-1 Z^T
    AZ = A.T @ Z
    M = A.T @ A - AZ @ (P @ A)
    g = A.T @ Yk - AZ @ (P @ Yk)
    return M, g


def solve_il(parts: list, ng: int, smoothing: float) -> np.ndarray:
    """Influence-line ordinates [n_sections, ng] from the runs' normal equations, with a
    second-difference penalty scaled to the data."""
    M = sum(m for m, _ in parts)
    g = sum(gg for _, gg in parts)
    D2 = np.zeros((ng - 2, ng))
    idx = np.arange(ng - 2)
    D2[idx, idx], D2[idx, idx + 1], D2[idx, idx + 2] = 1.0, -2.0, 1.0
    lam = smoothing * float(np.mean(np.diag(M)))
    return np.linalg.solve(M + lam * (D2.T @ D2) + 1e-12 * float(np.trace(M)) / ng * np.eye(ng), g).T


def calibrate(rec: Record, clean: list, geo: Geometry, args) -> tuple[Calibration, dict]:
    """Influence lines by the matrix method from the calibration runs; also the runs'
    normal equations, for leave-one-out."""
    L = rec.span_m
    positions, Y = weighing_signals(rec, args.fad_max_m)
    s_grid = np.arange(-args.il_margin_m, L + args.il_margin_m + 1e-9, args.il_step_m)
    ng = len(s_grid)
    f1 = first_frequency(rec, args.fad_max_m) if args.vibration_terms else None
    parts = {tr["id"]: (v.direction, run_normals(rec, tr, v, geo, s_grid, args, f1)) for tr, v in clean}
    il = {}
    for direction in (1, -1):
        mine = [p for d, p in parts.values() if d == direction]
        if mine:
            il[direction] = solve_il(mine, ng, args.il_smoothing)
    # A direction without calibration run borrows the mirror of the other (a symmetric
    # girder and gauges).
    for direction in (1, -1):
        if direction not in il:
            other = il[-direction]
            il[direction] = np.array([np.interp(L - s_grid, s_grid, other[c]) for c in range(len(positions))])
    noise = np.array([section_noise(Y[:, c]) for c in range(Y.shape[1])])
    cal = Calibration(
        geo, s_grid, positions, il, noise, rec.ids, sorted(parts), rec.path, getattr(args, "axles", "fad")
    )
    return cal, parts


def leave_one_out(cal: Calibration, parts: dict, run_id: int, smoothing: float) -> Calibration:
    """The calibration without one run (its direction's influence lines re-solved)."""
    direction = parts[run_id][0]
    others = [p for k, (d, p) in parts.items() if d == direction and k != run_id]
    if not others:
        raise ValueError("no other run in that direction")
    il = dict(cal.il)
    il[direction] = solve_il(others, len(cal.s_grid), smoothing)
    return Calibration(
        cal.geometry,
        cal.s_grid,
        cal.sections_m,
        il,
        cal.noise,
        cal.gauge_ids,
        [k for k in cal.runs_used if k != run_id],
        cal.source,
        cal.axles,
        cal.detectors,
    )
