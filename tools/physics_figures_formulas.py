"""The closed-form figures of docs/physics.md marked *derived* (sections 1-4, 5.1, 6.2,
7, 8, 10 and 12), one small function each, coded from the formulas and inputs that
document states, for tools/physics_figures.py. numpy and scipy only; nothing of the
crate is used.
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np
from scipy.linalg import eigh
from scipy.optimize import brentq, minimize_scalar

# The paper's bridge (section 1) and the crate's rounding of it.
PAPER_SPAN_M = 30.0
PAPER_F1_HZ = 3.78
BEAM_MASS_KG_M = 12_000.0
BEAM_EI_N_M2 = 5.629e10
G_M_S2 = 9.81

# ---------------------------------------------------------------- section 1


def ei_over_m_from_f1() -> float:
    """EI / m = (2 L^2 f1 / pi)^2 for L = 30 m, f1 = 3.78 Hz (docs/physics.md section 1)."""
    return (2.0 * PAPER_SPAN_M**2 * PAPER_F1_HZ / math.pi) ** 2


def simple_beam_frequency_hz(mode: int) -> float:
    """f_n = (n^2 pi / (2 L^2)) sqrt(EI / m) of the crate's rounded beam, m = 12 000 kg/m,
    EI = 5.629e10 N m^2, L = 30 m (section 1)."""
    return mode**2 * math.pi / (2.0 * PAPER_SPAN_M**2) * math.sqrt(BEAM_EI_N_M2 / BEAM_MASS_KG_M)


# ---------------------------------------------------------------- section 2


def flexibility_matrix(n_masses: int, span_m: float, ei: float) -> np.ndarray:
    """F_ij: deflection at x_i under a unit load at x_j, x_i = i L / (N + 1) (section 2)."""
    x = np.arange(1, n_masses + 1) * span_m / (n_masses + 1)
    f = np.empty((n_masses, n_masses))
    for j, a in enumerate(x):
        b = span_m - a
        left = x <= a
        xl = x[left]
        xr = x[~left]
        f[left, j] = b * xl * (span_m**2 - b**2 - xl**2) / (6 * ei * span_m)
        f[~left, j] = a * (span_m - xr) * (2 * span_m * xr - xr**2 - a**2) / (6 * ei * span_m)
    return f


def lumped_frequency_error(n_masses: int, mode: int) -> float:
    """Relative error of f_mode of the lumped-mass model (K = F^-1, masses m L / (N + 1) at
    the interior points) against the continuous beam (section 2, "Convergence")."""
    k = np.linalg.inv(flexibility_matrix(n_masses, PAPER_SPAN_M, BEAM_EI_N_M2))
    k = 0.5 * (k + k.T)
    mass = np.full(n_masses, BEAM_MASS_KG_M * PAPER_SPAN_M / (n_masses + 1))
    lam = eigh(k, np.diag(mass), eigvals_only=True)
    f = math.sqrt(lam[mode - 1]) / (2 * math.pi)
    return f / simple_beam_frequency_hz(mode) - 1.0


# ---------------------------------------------------------------- section 3


def hermite_worst_error_f1_to_f3(n_elements: int) -> float:
    """Worst relative error of f1..f3 of a simply supported beam of cubic Hermite elements
    with consistent mass (section 3, "Convergence"), assembled here."""
    el = PAPER_SPAN_M / n_elements
    ke = (BEAM_EI_N_M2 / el**3) * np.array(
        [
            [12, 6 * el, -12, 6 * el],
            [6 * el, 4 * el**2, -6 * el, 2 * el**2],
            [-12, -6 * el, 12, -6 * el],
            [6 * el, 2 * el**2, -6 * el, 4 * el**2],
        ]
    )
    me = (BEAM_MASS_KG_M * el / 420.0) * np.array(
        [
            [156, 22 * el, 54, -13 * el],
            [22 * el, 4 * el**2, 13 * el, -3 * el**2],
            [54, 13 * el, 156, -22 * el],
            [-13 * el, -3 * el**2, -22 * el, 4 * el**2],
        ]
    )
    ndof = 2 * (n_elements + 1)
    kk = np.zeros((ndof, ndof))
    mm = np.zeros((ndof, ndof))
    for e in range(n_elements):
        s = slice(2 * e, 2 * e + 4)
        kk[s, s] += ke
        mm[s, s] += me
    free = [d for d in range(ndof) if d not in (0, ndof - 2)]  # w = 0 at both supports
    lam = eigh(kk[np.ix_(free, free)], mm[np.ix_(free, free)], eigvals_only=True)
    f = np.sqrt(lam[:3]) / (2 * math.pi)
    exact = np.array([simple_beam_frequency_hz(n) for n in (1, 2, 3)])
    return float(np.max(np.abs(f / exact - 1.0)))


# ---------------------------------------------------------------- section 4


def rayleigh_coefficients() -> tuple[float, float]:
    """a0 = 2 zeta w1 w2 / (w1 + w2), a1 = 2 zeta / (w1 + w2), zeta = 0.02 on modes 1 and 2
    of the paper's beam (section 4.1)."""
    w1 = 2 * math.pi * simple_beam_frequency_hz(1)
    w2 = 2 * math.pi * simple_beam_frequency_hz(2)
    return 2 * 0.02 * w1 * w2 / (w1 + w2), 2 * 0.02 / (w1 + w2)


def rayleigh_ratio_mode3_percent() -> float:
    """zeta(w3) = a0 / (2 w3) + a1 w3 / 2 in percent (section 4.1)."""
    a0, a1 = rayleigh_coefficients()
    w3 = 2 * math.pi * simple_beam_frequency_hz(3)
    return 100 * (a0 / (2 * w3) + a1 * w3 / 2)


def newmark_period_elongation_percent(dt_over_period: float) -> float:
    """Exact T_num / T - 1 = (w dt / 2) / atan(w dt / 2) - 1 in percent (section 4.2)."""
    half = math.pi * dt_over_period
    return 100 * (half / math.atan(half) - 1.0)


def newmark_period_series_percent(dt_over_period: float) -> float:
    """The series' first term (w dt)^2 / 12 in percent (section 4.2)."""
    return 100 * (2 * math.pi * dt_over_period) ** 2 / 12


def step_for_axle_hop_ms() -> float:
    """Largest dt with dt / T <= 0.02 at 15 Hz, the top of the axle-hop range (section 4.2)."""
    return 1000 * 0.02 / 15.0


def tyre_excitation_top_hz() -> float:
    """v n2 at 20 m/s and n2 = 4 cycle/m (section 4.2)."""
    return 20.0 * 4.0


def step_ratio_at_1ms_80hz() -> float:
    """dt / T for 1 ms at 80 Hz (section 4.2)."""
    return 1e-3 * tyre_excitation_top_hz()


# ---------------------------------------------------------------- section 5.1


def _moving_force_modes(alpha: float, zeta: float, n_modes: int, t: np.ndarray) -> np.ndarray:
    """Midspan deflection over P L^3 / (48 EI) of a force crossing a pinned beam at
    alpha = v / (2 f1 L), modes solved in closed form, forced then free (section 5.1).
    Units: L = 1, EI = m = 1, P = 48, so the static midspan deflection is 1."""
    n = np.arange(1, n_modes + 1)[:, None]
    w = (n * math.pi) ** 2
    v = alpha * 2 * (math.pi / 2)  # 2 f1 L with f1 = pi / 2
    big_omega = n * math.pi * v
    f0 = 2 * 48.0
    den = (w**2 - big_omega**2) ** 2 + (2 * zeta * w * big_omega) ** 2
    amp_s = f0 * (w**2 - big_omega**2) / den
    amp_c = -f0 * 2 * zeta * w * big_omega / den
    wd = w * math.sqrt(1 - zeta**2)
    c1 = -amp_c
    c2 = (zeta * w * c1 - amp_s * big_omega) / wd

    def forced(tt):
        decay = np.exp(-zeta * w * tt)
        q = amp_s * np.sin(big_omega * tt) + amp_c * np.cos(big_omega * tt)
        q = q + decay * (c1 * np.cos(wd * tt) + c2 * np.sin(wd * tt))
        qd = amp_s * big_omega * np.cos(big_omega * tt) - amp_c * big_omega * np.sin(big_omega * tt)
        qd = qd + decay * (
            (-zeta * w * c1 + wd * c2) * np.cos(wd * tt)
            + (-zeta * w * c2 - wd * c1) * np.sin(wd * tt)
        )
        return q, qd

    t_exit = 1.0 / v
    q_e, qd_e = forced(np.array([[t_exit]]))
    tt = t[None, :]
    q_f, _ = forced(np.minimum(tt, t_exit))
    tau = np.maximum(tt - t_exit, 0.0)
    q_free = np.exp(-zeta * w * tau) * (
        q_e * np.cos(wd * tau) + (qd_e + zeta * w * q_e) / wd * np.sin(wd * tau)
    )
    q = np.where(tt <= t_exit, q_f, q_free)
    return np.sin(n[:, 0] * math.pi / 2) @ q


def moving_force_daf(alpha: float, zeta: float = 0.0, n_modes: int = 100) -> float:
    """Peak midspan deflection over P L^3 / (48 EI), 100 modes, the forced phase and two
    periods of mode 1 after the force leaves (section 5.1, "Dynamic amplification")."""
    v = alpha * math.pi
    t_end = 1.0 / v + 2 * (2 * math.pi / math.pi**2)
    t = np.linspace(0.0, t_end, 6001)
    w = _moving_force_modes(alpha, zeta, n_modes, t)
    i = int(np.argmax(w))
    lo, hi = t[max(i - 1, 0)], t[min(i + 1, len(t) - 1)]
    res = minimize_scalar(
        lambda s: -_moving_force_modes(alpha, zeta, n_modes, np.array([s]))[0],
        bounds=(lo, hi),
        method="bounded",
        options={"xatol": 1e-12},
    )
    return max(float(-res.fun), float(w[i]))


@lru_cache(maxsize=None)
def moving_force_daf_maximum() -> tuple[float, float]:
    """The largest undamped DAF over alpha and where it is (section 5.1)."""
    res = minimize_scalar(
        lambda a: -moving_force_daf(a),
        bounds=(0.55, 0.7),
        method="bounded",
        options={"xatol": 1e-6},
    )
    return float(-res.fun), float(res.x)


def critical_speed_paper_m_s() -> float:
    """2 f1 L of the paper's bridge, f1 = 3.78 Hz, L = 30 m (section 5.1)."""
    return 2 * PAPER_F1_HZ * PAPER_SPAN_M


def paper_beam_daf(speed_m_s: float, zeta: float) -> float:
    """The DAF at a speed on the paper's bridge, zeta on every mode (section 5.1)."""
    return moving_force_daf(speed_m_s / critical_speed_paper_m_s(), zeta)


# ---------------------------------------------------------------- section 6.2

HALF_CAR_PRESETS = {
    # body mass, pitch inertia, axle spacing, axle masses, suspensions, tyres (section 6.2)
    "two_axle_truck": (
        17_735.0,
        1.47e5,
        4.27,
        (1500.0, 1000.0),
        (2.47e6, 4.23e6),
        (3.74e6, 4.60e6),
    ),
    "vbi2d_e01": (10_500.0, 5.0e4, 5.0, (900.0, 900.0), (6e6, 6e6), (1.75e6, 1.75e6)),
}


def half_car_rigid_road_modes_hz(preset: str) -> np.ndarray:
    """Undamped frequencies of the 4-DOF half car on a rigid road, K and M of section 6.1,
    centre of gravity at mid-wheelbase (d = -s/2, +s/2), the presets of section 6.2."""
    m_b, i_b, s, (m1, m2), (k1, k2), (kt1, kt2) = HALF_CAR_PRESETS[preset]
    d1, d2 = -s / 2, s / 2
    kk = np.array(
        [
            [k1 + k2, k1 * d1 + k2 * d2, -k1, -k2],
            [k1 * d1 + k2 * d2, k1 * d1**2 + k2 * d2**2, -k1 * d1, -k2 * d2],
            [-k1, -k1 * d1, k1 + kt1, 0.0],
            [-k2, -k2 * d2, 0.0, k2 + kt2],
        ]
    )
    lam = eigh(kk, np.diag([m_b, i_b, m1, m2]), eigvals_only=True)
    return np.sqrt(lam) / (2 * math.pi)


def half_car_static_axle_load_kn(preset: str, axle: int) -> float:
    """Lever rule, centre of gravity at mid-wheelbase: half the body plus the axle, g = 9.81
    (section 6.2)."""
    m_b, _, _, axles, _, _ = HALF_CAR_PRESETS[preset]
    return (m_b / 2 + axles[axle]) * G_M_S2 / 1000


# ---------------------------------------------------------------- section 7

ISO_CLASS_GD0 = dict(zip("ABCDEFGH", (16e-6 * 4**i for i in range(8))))


def iso8608_band_rms_mm(road_class: str, n1: float = 0.01, n2: float = 4.0) -> float:
    """sqrt(G_d(n0) n0^2 (1/n1 - 1/n2)) with n0 = 0.1 cycle/m, in mm (section 7)."""
    return 1000 * math.sqrt(ISO_CLASS_GD0[road_class] * 0.1**2 * (1 / n1 - 1 / n2))


# ---------------------------------------------------------------- section 8


def jtg_d60_mu(f_hz: float) -> float:
    """JTG D60 impact coefficient mu: 0.1767 ln f - 0.0157 (section 8)."""
    return 0.1767 * math.log(f_hz) - 0.0157


# ---------------------------------------------------------------- section 10


def continuous_girder_lambdas(n_spans: int, n_roots: int) -> list[float]:
    """The lowest roots lambda = beta L of n equal pinned spans on rigid point supports:
    w = A sin + B cos + C sinh + D cosh of beta x per span, w = w'' = 0 at the ends,
    w = 0 either side of a support, w' and w'' continuous (section 10)."""

    def det(lam: float) -> float:
        size = 4 * n_spans
        a = np.zeros((size, size))

        def basis(xi, deriv):
            s, c, sh, ch = (
                math.sin(lam * xi),
                math.cos(lam * xi),
                math.sinh(lam * xi),
                math.cosh(lam * xi),
            )
            rows = [
                [s, c, sh, ch],
                [c, -s, ch, sh],
                [-s, -c, sh, ch],
            ]
            return np.array(rows[deriv]) * lam**deriv

        r = 0
        a[r, 0:4] = basis(0, 0)
        a[r + 1, 0:4] = basis(0, 2)
        r += 2
        for j in range(n_spans - 1):
            lcol, rcol = slice(4 * j, 4 * j + 4), slice(4 * j + 4, 4 * j + 8)
            a[r, lcol] = basis(1, 0)
            a[r + 1, rcol] = basis(0, 0)
            a[r + 2, lcol] = basis(1, 1)
            a[r + 2, rcol] = -basis(0, 1)
            a[r + 3, lcol] = basis(1, 2)
            a[r + 3, rcol] = -basis(0, 2)
            r += 4
        last = slice(4 * n_spans - 4, 4 * n_spans)
        a[r, last] = basis(1, 0)
        a[r + 1, last] = basis(1, 2)
        return float(np.linalg.det(a))

    grid = np.linspace(2.0, 8.0, 601)  # roots are more than 0.3 apart
    values = [det(x) for x in grid]
    roots = []
    for x0, x1, v0, v1 in zip(grid[:-1], grid[1:], values[:-1], values[1:]):
        if v0 == 0.0:
            roots.append(float(x0))
        elif v0 * v1 < 0:
            roots.append(brentq(det, x0, x1, xtol=1e-14))
        if len(roots) == n_roots:
            break
    return roots


def three_span_frequency_hz(mode: int) -> float:
    """f = (lambda / pi)^2 f1 for three equal spans of the paper's section (section 10)."""
    lam = continuous_girder_lambdas(3, 3)[mode - 1]
    return (lam / math.pi) ** 2 * simple_beam_frequency_hz(1)


# ---------------------------------------------------------------- section 12


def stiffness_ratio_default_law(temp_c: float) -> float:
    """E / E_ref of the default law: 1 at 20 degC, -0.0015 per degC down to the knee at
    0 degC, -0.03 per degC below it (section 12)."""
    above = 1.0 - 0.0015 * (max(temp_c, 0.0) - 20.0)
    return above - 0.03 * min(temp_c, 0.0)


def f1_at_temperature_hz(temp_c: float, damped: bool) -> float:
    """f1 sqrt(E / E_ref); damped: times sqrt(1 - zeta^2), zeta = 0.02 on mode 1 (Rayleigh
    fitted on modes 1 and 2) (section 12)."""
    f = simple_beam_frequency_hz(1) * math.sqrt(stiffness_ratio_default_law(temp_c))
    return f * math.sqrt(1 - 0.02**2) if damped else f
