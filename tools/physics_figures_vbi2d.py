"""The sprung-mass crossing of docs/physics.md section 5.3, computed two ways, for
tools/physics_figures.py.

1. ``vbi2d_newmark``: VBI-2D's own time stepping as that section describes it
   (``V01_Analytical_Verification_Examples.m``): the vehicle DOF and the modal
   coordinates (shapes ``sqrt(2 / L) sin(n pi x / L)``, modal mass ``m``) advanced
   together by average-acceleration Newmark, the coupled matrices evaluated at the
   vehicle's position at the start of the step, the road's elevation and rate at its
   end, the rate by a backward difference of the sampled road. Upward positive inside,
   the midspan deflection returned downward positive.

   ``vbi2d_assembly=True`` assembles the convective dashpot term of the bridge rows as
   the VBI-2D script does: it fills the upper triangle with ``c v phi_i phi_j'``
   (``i < j``) and mirrors it, so an entry below the diagonal (row ``j``, column ``i``)
   holds ``c v phi_i phi_j'`` where the equation of section 5.3 has ``c v phi_j phi_i'``.
   That is what VBI-2D's published files carry; ``False`` uses the term as written.
   Without a dashpot (``c = 0``) the two are the same.

2. ``continuous_reference``: the same modal equations (section 5.3, downward positive)
   integrated without a time-step error worth the name, by a fourth-order Lawson
   (integrating-factor) Runge-Kutta method: each mode's undamped oscillator is
   propagated exactly (its frequency is what makes the system stiff), the coupling
   (spring, dashpot, vehicle) by classical RK4 on the transformed variables. The ramp's
   kinks are step boundaries. Shares no code with 1.

The functions after those two compute the figures of section 5.3 from them (cached:
several figures share a run). numpy only; nothing of the crate is used.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

G_M_S2 = 9.81


@dataclass(frozen=True)
class SprungMassCase:
    """One of the VBI-2D verification cases (section 5.3): beam, vehicle, road."""

    name: str
    damping_n_s_m: float
    ramp: bool
    span_m: float = 25.0
    young_pa: float = 3.5e10
    inertia_m4: float = 1.3901
    mass_per_m_kg_m: float = 18358.0
    vehicle_mass_kg: float = 5750.0
    stiffness_n_m: float = 1595e3
    speed_m_s: float = 25.0
    ramp_height_m: float = 0.01

    def ramp_x_m(self) -> tuple[float, float]:
        """VBI-2D's ramp: linear from L/3 to L/2, level before and after."""
        return self.span_m / 3.0, self.span_m / 2.0

    def omega_rad_s(self, n_modes: int) -> np.ndarray:
        n = np.arange(1, n_modes + 1)
        ei_over_m = self.young_pa * self.inertia_m4 / self.mass_per_m_kg_m
        return (n * np.pi / self.span_m) ** 2 * np.sqrt(ei_over_m)

    def road_m(self, x_m: np.ndarray) -> np.ndarray:
        if not self.ramp:
            return np.zeros_like(x_m)
        a, b = self.ramp_x_m()
        span = self.span_m
        h = self.ramp_height_m
        return np.interp(x_m, [0.0, a, b, span], [0.0, 0.0, h, h])


VBI2D_CASES = (
    SprungMassCase("SprungVeh", 0.0, False),
    SprungMassCase("RampOn", 0.0, True),
    SprungMassCase("DampOn", 400e3, True),
)


def vbi2d_newmark(
    case: SprungMassCase, dt_s: float, n_modes: int, vbi2d_assembly: bool = True
) -> tuple[np.ndarray, np.ndarray]:
    """Times (s) and midspan deflection (m, downward positive) of VBI-2D's scheme, one
    sample per step from t = 0 to L / v."""
    span = case.span_m
    v = case.speed_m_s
    k = case.stiffness_n_m
    c = case.damping_n_s_m
    m_b = case.mass_per_m_kg_m
    n_steps = int(round(span / v / dt_s))
    t = np.arange(n_steps + 1) * dt_s
    x = v * t
    h = case.road_m(x)
    h_dot = np.concatenate([[0.0], np.diff(h)]) / dt_s  # backward difference, as VBI-2D
    n = np.arange(1, n_modes + 1)
    omega = case.omega_rad_s(n_modes)
    norm = np.sqrt(2.0 / span)

    def phi(xx: float) -> np.ndarray:
        on = 1.0 if 0.0 <= xx <= span else 0.0
        return norm * np.sin(n * np.pi * xx / span) * on

    def dphi(xx: float) -> np.ndarray:
        on = 1.0 if 0.0 <= xx <= span else 0.0
        return norm * (n * np.pi / span) * np.cos(n * np.pi * xx / span) * on

    dof = n_modes + 1
    mass = np.diag(np.r_[case.vehicle_mass_kg, np.full(n_modes, m_b)])
    beta, gamma = 0.25, 0.5
    c1 = 1.0 / (beta * dt_s**2)
    c2 = gamma / (beta * dt_s)
    c3 = 1.0 / (beta * dt_s)
    c4 = 1.0 / (2.0 * beta) - 1.0
    c5 = 1.0 - gamma / beta
    c6 = (1.0 - gamma / (2.0 * beta)) * dt_s
    q = np.zeros(dof)
    qd = np.zeros(dof)
    qdd = np.zeros(dof)
    midspan = np.zeros(n_steps + 1)
    phi_mid = phi(span / 2.0)
    stiff_modal = np.diag(m_b * omega**2)
    g_up = -G_M_S2
    for i in range(n_steps):
        p = phi(x[i])
        dp = dphi(x[i])
        kk = np.zeros((dof, dof))
        cc = np.zeros((dof, dof))
        kk[0, 0] = k
        kk[0, 1:] = -k * p - c * v * dp
        kk[1:, 0] = -k * p
        coupling = k * np.outer(p, p) + c * v * np.outer(p, dp)
        if vbi2d_assembly:
            upper = np.triu(coupling, 1)
            coupling = upper + upper.T + np.diag(np.diag(coupling))
        kk[1:, 1:] = stiff_modal + coupling
        cc[0, 0] = c
        cc[0, 1:] = -c * p
        cc[1:, 0] = -c * p
        cc[1:, 1:] = c * np.outer(p, p)
        force = np.empty(dof)
        force[0] = k * h[i + 1] + c * h_dot[i + 1]
        force[1:] = (case.vehicle_mass_kg * g_up - k * h[i + 1] - c * h_dot[i + 1]) * phi(x[i + 1])
        a_vec = q * c1 + qd * c3 + qdd * c4
        b_vec = c2 * q - c5 * qd - c6 * qdd
        q = np.linalg.solve(kk + c1 * mass + c2 * cc, force + mass @ a_vec + cc @ b_vec)
        qd = c2 * q - b_vec
        qdd = q * c1 - a_vec
        midspan[i + 1] = -(phi_mid @ q[1:])
    return t, midspan


def continuous_reference(
    case: SprungMassCase, n_modes: int, steps_per_ms: int
) -> tuple[np.ndarray, np.ndarray]:
    """Times (s) and midspan deflection (m, downward positive) of the modal equations of
    section 5.3 by Lawson RK4, ``steps_per_ms`` steps per millisecond (rounded so that
    the ramp's kinks fall on step boundaries)."""
    span = case.span_m
    v = case.speed_m_s
    k = case.stiffness_n_m
    c = case.damping_n_s_m
    m_v = case.vehicle_mass_kg
    wave = np.arange(1, n_modes + 1) * np.pi / span
    omega = case.omega_rad_s(n_modes)
    gain = 2.0 / (case.mass_per_m_kg_m * span)
    if case.ramp:
        a, b = case.ramp_x_m()
        knots_s = [0.0, a / v, b / v, span / v]
        slope = case.ramp_height_m / (b - a)
        pieces = [(0.0, 0.0, 0.0), (slope, 0.0, a), (0.0, case.ramp_height_m, 0.0)]
    else:
        knots_s = [0.0, span / v]
        pieces = [(0.0, 0.0, 0.0)]

    # State: y, y' of the vehicle, then q, q' of the modes; the modes' oscillator part
    # is integrated exactly, so the propagator acts on (q, q') only.
    def propagate(state: np.ndarray, tau: float) -> np.ndarray:
        out = state.copy()
        qq = state[2 : 2 + n_modes]
        qv = state[2 + n_modes :]
        cw = np.cos(omega * tau)
        sw = np.sin(omega * tau)
        out[2 : 2 + n_modes] = cw * qq + sw / omega * qv
        out[2 + n_modes :] = -omega * sw * qq + cw * qv
        return out

    def coupling(t: float, state: np.ndarray, piece: tuple[float, float, float]) -> np.ndarray:
        slope_r, level_r, x0 = piece
        x = v * t
        s_n = np.sin(wave * x)
        c_n = np.cos(wave * x) * wave
        qq = state[2 : 2 + n_modes]
        qv = state[2 + n_modes :]
        road = level_r + slope_r * (x - x0)
        stretch = state[0] - s_n @ qq + road
        rate = state[1] - s_n @ qv - v * (c_n @ qq) + v * slope_r
        f_susp = k * stretch + c * rate
        out = np.zeros_like(state)
        out[0] = state[1]
        out[1] = -f_susp / m_v
        out[2 + n_modes :] = gain * (m_v * G_M_S2 + f_susp) * s_n
        return out

    state = np.zeros(2 + 2 * n_modes)
    times = [0.0]
    mid = [0.0]
    odd = np.sin(np.arange(1, n_modes + 1) * np.pi / 2.0)
    for (t_a, t_b), piece in zip(zip(knots_s[:-1], knots_s[1:]), pieces):
        n_steps = max(1, int(round((t_b - t_a) * 1000.0 * steps_per_ms)))
        h = (t_b - t_a) / n_steps
        for j in range(n_steps):
            t = t_a + j * h
            k1 = coupling(t, state, piece)
            half = propagate(state, h / 2)
            k2 = coupling(t + h / 2, half + propagate(h / 2 * k1, h / 2), piece)
            k3 = coupling(t + h / 2, half + h / 2 * k2, piece)
            k4 = coupling(t + h, propagate(state, h) + propagate(h * k3, h / 2), piece)
            state = propagate(state, h) + h / 6 * (
                propagate(k1, h) + 2 * propagate(k2 + k3, h / 2) + k4
            )
            times.append(t + h)
            mid.append(odd @ state[2 : 2 + n_modes])
    return np.array(times), np.array(mid)


# ---------------------------------------------------------------- the figures of section 5.3

VBI_CASE = {c.name: c for c in VBI2D_CASES}


def vbi2d_beam_f1_hz() -> float:
    """f1 of the VBI-2D verification beam, L = 25 m, E = 3.5e10 Pa, I = 1.3901 m^4,
    m = 18 358 kg/m (section 5.3)."""
    return float(VBI2D_CASES[0].omega_rad_s(1)[0] / (2 * np.pi))


def vbi2d_vehicle_alone_hz() -> float:
    """sqrt(k / m) / (2 pi) of 5 750 kg on 1 595 kN/m (section 5.3)."""
    case = VBI2D_CASES[0]
    return float(np.sqrt(case.stiffness_n_m / case.vehicle_mass_kg) / (2 * np.pi))


@lru_cache(maxsize=None)
def vbi2d_run(name: str, dt_s: float, n_modes: int, vbi2d_assembly: bool = True):
    """VBI-2D's scheme for one case (section 5.3; cached: several figures share a run)."""
    return vbi2d_newmark(VBI_CASE[name], dt_s, n_modes, vbi2d_assembly)


def vbi2d_published_sample(name: str, what: str) -> float:
    """The 1 ms, 100-mode re-run's peak or sample, as the published table of section 5.3
    lists it (reproduces VBI-2D's files)."""
    t, w = vbi2d_run(name, 1e-3, 100)
    if what == "peak":
        return float(w.max())
    if what == "peak_t":
        return float(t[int(np.argmax(w))])
    return float(w[int(round(float(what) / 1e-3))])


def vbi2d_mode_truncation_peak_rel() -> float:
    """Largest relative peak change from VBI-2D's 100 modes to the re-run's 25 at 1 ms
    (section 5.3)."""
    worst = 0.0
    for case in VBI2D_CASES:
        p100 = vbi2d_run(case.name, 1e-3, 100)[1].max()
        p25 = vbi2d_run(case.name, 1e-3, 25)[1].max()
        worst = max(worst, abs(p25 / p100 - 1))
    return worst


def vbi2d_step_error_peak_rel(name: str) -> float:
    """|2 (p(dt) - p(dt/2))| / p(dt), dt = 1 ms, 25 modes, p the largest sample of each
    run (section 5.3)."""
    p1 = vbi2d_run(name, 1e-3, 25)[1].max()
    p2 = vbi2d_run(name, 5e-4, 25)[1].max()
    return abs(2 * (p1 - p2) / p1)


def vbi2d_step_error_history_rel(name: str) -> float:
    """max_t |2 (w_dt(t) - w_dt/2(t))| over the 1 ms peak, 25 modes (section 5.3)."""
    w1 = vbi2d_run(name, 1e-3, 25)[1]
    w2 = vbi2d_run(name, 5e-4, 25)[1][::2]
    return float(np.max(np.abs(2 * (w1 - w2))) / w1.max())


def vbi2d_assembly_history_rel() -> float:
    """DampOn at 1 ms, 25 modes: largest change of the history, over the peak, from
    VBI-2D's mirrored dashpot term to the term as the equations have it (section 5.3)."""
    w_vbi = vbi2d_run("DampOn", 1e-3, 25, True)[1]
    w_eq = vbi2d_run("DampOn", 1e-3, 25, False)[1]
    return float(np.max(np.abs(w_eq - w_vbi)) / w_vbi.max())


def vbi2d_assembly_peak_rel() -> float:
    """DampOn at 1 ms, 25 modes: the peak's relative change from VBI-2D's term to the
    equations' (section 5.3)."""
    p_vbi = vbi2d_run("DampOn", 1e-3, 25, True)[1].max()
    p_eq = vbi2d_run("DampOn", 1e-3, 25, False)[1].max()
    return float(p_eq / p_vbi - 1)


@lru_cache(maxsize=None)
def sprung_mass_reference_peak_m(name: str) -> float:
    """Peak of the continuous modal equations, 25 modes (Lawson RK4, 8 steps per ms; 16
    steps move the peaks by at most 1.3e-7), refined by a parabola through the largest
    sample and its neighbours (section 5.3)."""
    _, w = continuous_reference(VBI_CASE[name], 25, 8)
    i = int(np.argmax(w))
    y0, y1, y2 = w[i - 1 : i + 2]
    return float(y1 - (y2 - y0) ** 2 / (8 * (y0 - 2 * y1 + y2)))


def vbi2d_fine_step_vs_reference_rel() -> float:
    """Largest |p_scheme / p_reference - 1| with VBI-2D's scheme at 0.125 ms, 25 modes,
    against the continuous equations (section 5.3)."""
    worst = 0.0
    for case in VBI2D_CASES:
        p = vbi2d_run(case.name, 1.25e-4, 25)[1].max()
        worst = max(worst, abs(p / sprung_mass_reference_peak_m(case.name) - 1))
    return worst


def vbi2d_fine_step_equations_term_rel() -> float:
    """DampOn with the dashpot term as the equations have it, the scheme at 0.125 ms, 25
    modes: p_scheme / p_reference - 1 (section 5.3)."""
    p = vbi2d_run("DampOn", 1.25e-4, 25, False)[1].max()
    return float(p / sprung_mass_reference_peak_m("DampOn") - 1)
