"""A detected vehicle (its axles' times at a reference point, its speed) and where its axles
are: the travel coordinate s runs from the entry support (s = 0) to the exit support."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

GROUP_SPACING_MAX_M = 2.1  # axles closer than this form a group (src/measurement/wim/groups.rs)


@dataclass
class Vehicle:
    direction: int  # +1: enters at x = 0; -1: enters at x = L
    t_axle: np.ndarray  # s, time each axle passes the entry step's reference point s_c
    speed: float
    index: int = 0
    loads_n: np.ndarray | None = None
    cluster: int = -1
    cluster_size: int = 1
    matched_exit: int = 0
    residual: float | None = None
    poor_fit: bool = False
    truth: dict | None = field(default=None, repr=False)

    @property
    def spacings(self) -> np.ndarray:
        return np.diff(self.t_axle) * self.speed


@dataclass
class Geometry:
    """Where the axle times refer to along the travel coordinate s (from the entry support):
    the FAD steps' reference points, or the entry support itself for road axle detectors."""

    span_m: float
    s_entry: dict  # direction -> s of the entry step's reference point
    distance: dict  # direction -> D, s from the entry step to the exit step


def axle_positions(v: Vehicle, t: np.ndarray, geo: Geometry) -> np.ndarray:
    """[n_t, n_axles] travel coordinate s of every axle at the times t."""
    return geo.s_entry[v.direction] + v.speed * (t[:, None] - v.t_axle[None, :])


def occupancy(v: Vehicle, geo: Geometry, s_lo: float, s_hi: float) -> tuple[float, float]:
    """Times between which some axle of v lies in [s_lo, s_hi]."""
    s0 = geo.s_entry[v.direction]
    return v.t_axle[0] + (s_lo - s0) / v.speed, v.t_axle[-1] + (s_hi - s0) / v.speed
