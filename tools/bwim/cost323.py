"""COST 323 classes (B. Jacob, E. J. OBrien & S. Jehaes (eds.), Weigh-in-Motion of Road
Vehicles: Final Report of the COST 323 Action, LCPC, 2002): tolerances per class and
criterion, the minimum level of confidence pi0(n) and the class a criterion's relative
errors reach (the acceptance rule as tools/bwim_check.py's docstring reads it)."""

from __future__ import annotations

import math

import numpy as np
from scipy import stats
from scipy.optimize import brentq

# COST 323 tolerances delta (%) per class: gross, group of axles, single axle, axle of a
# group (src/measurement/wim/cost323.rs, TOLERANCES_PCT; docs/sensors.md section 3).
CLASSES = ["A(5)", "B+(7)", "B(10)", "C(15)", "D+(20)"]
CRITERIA = ["gross", "group of axles", "single axle", "axle of a group"]
TOLERANCE_PCT = {
    "A(5)": (5.0, 7.0, 8.0, 10.0),
    "B+(7)": (7.0, 10.0, 11.0, 14.0),
    "B(10)": (10.0, 13.0, 15.0, 20.0),
    "C(15)": (15.0, 18.0, 20.0, 25.0),
    "D+(20)": (20.0, 23.0, 25.0, 30.0),
}
BELOW = "below D+(20)"
# Minimum level of confidence pi0 (%) for a large sample, by repeatability (r1 full
# repeatability: one vehicle, same speed and load; r2 extended repeatability: one vehicle,
# several speeds and loads; R1 limited reproducibility: a few vehicles; R2 full
# reproducibility: a sample of the traffic) and environment (I: within a day; II: within
# a week or a month; III: over a year). As recalled from the COST 323 specification's
# table: *not checked here* (tools/bwim_check.py docstring).
PI_INF = {
    ("r1", "I"): 99.2, ("r1", "II"): 98.9, ("r1", "III"): 98.4,
    ("r2", "I"): 98.9, ("r2", "II"): 98.4, ("r2", "III"): 97.7,
    ("R1", "I"): 98.4, ("R1", "II"): 97.7, ("R1", "III"): 96.9,
    ("R2", "I"): 97.7, ("R2", "II"): 96.9, ("R2", "III"): 95.0,
}  # fmt: skip
ALPHA = 0.05
DOMAIN_GROSS_N = 3.5 * 9.81e3  # COST 323 domain of use: gross weight > 3.5 t


def pi0(n: int, conditions: str, alpha: float = ALPHA) -> float:
    """Minimum level of confidence for n values under the test conditions (bwim_check.py docstring)."""
    rep, env = conditions.split("-")
    u_inf = stats.norm.ppf(0.5 * (1.0 + PI_INF[(rep, env)] / 100.0))
    nu = n - 1
    return float(2.0 * stats.norm.cdf(u_inf * math.sqrt(nu / stats.chi2.ppf(1.0 - alpha, nu))) - 1.0)


def pi_level(m: float, s: float, delta: float) -> float:
    """Level of confidence of [-delta, delta] for normal errors of mean m and sd s."""
    return float(stats.norm.cdf((delta - m) / s) - stats.norm.cdf((-delta - m) / s))


def assess(errors: np.ndarray, criterion: int, conditions: str) -> dict:
    """The COST 323 class reached by one criterion's relative errors (fractions)."""
    e = 100.0 * np.asarray(errors, float)
    n = len(e)
    out = {"n": n, "mean_pct": float(e.mean()) if n else None, "std_pct": float(e.std(ddof=1)) if n > 1 else None}
    if n < 5:
        out.update(pi0=None, delta_min_pct=None, class_reached=None, note="fewer than 5 values")
        return out
    m, s = float(e.mean()), max(float(e.std(ddof=1)), 1e-9)
    p0 = pi0(n, conditions)
    dmin = brentq(lambda d: pi_level(m, s, d) - p0, 1e-9, abs(m) + 50.0 * s)
    reached = next((c for c in CLASSES if TOLERANCE_PCT[c][criterion] >= dmin), BELOW)
    out.update(
        pi0=p0,
        delta_min_pct=dmin,
        class_reached=reached,
        tests={
            c: {
                "delta_pct": TOLERANCE_PCT[c][criterion],
                "pi": pi_level(m, s, TOLERANCE_PCT[c][criterion]),
                "accepted": pi_level(m, s, TOLERANCE_PCT[c][criterion]) >= p0,
            }
            for c in CLASSES
        },
    )
    return out


def class_rank(name: str | None) -> int:
    return CLASSES.index(name) if name in CLASSES else len(CLASSES)
