//! A moving mass crossing a simply supported beam: semi-analytical modal solution.
//!
//! The mass `m_v` is rigidly attached to the beam surface at `x_v = v t` (no spring, no
//! lift-off): it follows the deflection under it, so its inertia loads the beam. This is
//! the stiff-suspension limit of the sprung mass ([`super::sprung_mass`]), as the moving
//! force ([`super::moving_force`]) is its soft limit. Formulation: Fryba (1972/1999),
//! chapter 5 ("moving mass"), and Yang, Yau & Wu, Vehicle-Bridge Interaction Dynamics
//! (2004), chapter 2, projected on the exact modes `sin(n pi x / L)`.
//!
//! # Equations (displacements and forces positive DOWNWARD)
//!
//! `w(x, t) = sum q_n phi_n(x)`, `phi_n = sin(n pi x / L)`. The mass moves with the beam
//! point under it, `u(t) = w(v t, t)`, so its vertical acceleration is the TOTAL derivative
//!
//! `u'' = w_tt + 2 v w_xt + v^2 w_xx`
//!      `= sum (q_n'' phi_n + 2 v q_n' phi_n' + v^2 q_n phi_n'')` at `x = v t`,
//!
//! i.e. the local acceleration, the Coriolis term `2 v w_xt` and the centripetal term
//! `v^2 w_xx` (all three are included; the speed is constant). The contact force on the
//! beam is `F = m_v (g - u'')`, and each mode obeys
//! `(m L / 2)(q_n'' + 2 zeta_n w_n q_n' + w_n^2 q_n) = F phi_n(v t)`. In matrix form
//!
//! `(M_b I + m_v phi phi^T) q'' = m_v phi (g - 2 v phi'^T q' - v^2 phi''^T q)
//!                                - M_b (2 zeta w q' + w^2 q)`,   `M_b = m L / 2`,
//!
//! whose rank-one mass matrix is inverted in closed form (Sherman-Morrison):
//! `q'' = (b - m_v phi s) / M_b` with `s = phi^T q'' = phi^T b / (M_b + m_v phi^T phi)`.
//! The beam starts at rest; the mass enters at `x = 0`, `t = 0` (where `phi = 0`, so it
//! adds neither force nor inertia at the start). After it leaves (`v t > L`) the beam
//! vibrates freely. The road is level; the mass has no road irregularity to follow.
//!
//! Integration: every mode dynamically, with the adaptive Dormand-Prince 5(4) method of
//! [`super::dopri45`], the step capped at `step_stability_factor / w_N` for the same
//! reason as in [`super::sprung_mass`] (explicit stability of the undamped top modes on
//! the imaginary axis). The added mass only lowers the frequencies, so the cap still holds.

use super::beam::{harmonics, SimplySupportedBeam};
use super::crossing::{validate_sample_times, BeamModes, CrossingDefaults, CrossingOptions};
use super::dopri45::Dopri45Stats;
use crate::error::{require_positive, Error, Result};

pub use super::crossing::MAX_MODES;

/// Model and integration settings: 50 modes and steps of at most 2e-5 s by default (the
/// common defaults are at [`CrossingOptions`]). The peaks are taken at the accepted steps,
/// and a step h samples a peak of frequency w within (w h)^2 / 8 (3e-8 at 4 Hz); with few
/// modes the stability cap alone would allow steps of ~T_1 / 10.
pub type MovingMassOptions = CrossingOptions<MovingMassProblem>;

impl CrossingDefaults for MovingMassProblem {
    const N_MODES: usize = 50;
    const MAX_STEP_S: f64 = 2e-5;
}

/// The crossing to solve.
#[derive(Debug, Clone)]
pub struct MovingMassProblem {
    /// The beam.
    pub beam: SimplySupportedBeam,
    /// The moving mass, kg.
    pub mass_kg: f64,
    /// Constant forward speed, m/s.
    pub speed_m_s: f64,
    /// Settings.
    pub options: MovingMassOptions,
}

/// The response at one sample time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MovingMassSample {
    /// Time since the mass entered the beam, s.
    pub time_s: f64,
    /// Beam deflection at midspan (downward positive), m.
    pub midspan_deflection_m: f64,
    /// Beam deflection under the mass = mass displacement (0 off the beam), m.
    pub contact_deflection_m: f64,
    /// Downward contact force `m_v (g - u'')` on the beam (the weight off the beam), N.
    pub contact_force_n: f64,
}

/// Time series and peaks of a crossing.
#[derive(Debug, Clone, PartialEq)]
pub struct MovingMassSolution {
    /// One sample per requested time, in order.
    pub samples: Vec<MovingMassSample>,
    /// Largest midspan deflection over every integration step up to the last sample, m.
    pub peak_midspan_deflection_m: f64,
    /// When it occurred, s.
    pub peak_time_s: f64,
    /// Largest midspan deflection while the mass is on the beam (`t <= L / v`), m.
    pub peak_midspan_deflection_on_beam_m: f64,
    /// Integrator work counters.
    pub stats: Dopri45Stats,
}

/// The ODE `y = [q, q']` with its work buffers.
struct Model {
    n: usize,
    speed_m_s: f64,
    modes: BeamModes,
    mass_kg: f64,
    gravity_m_s2: f64,
}

/// Mode shapes and their x-derivatives at the mass.
struct Workspace {
    sin: Vec<f64>,
    cos: Vec<f64>,
    b: Vec<f64>,
}

impl Workspace {
    fn new(n: usize) -> Self {
        Self {
            sin: vec![0.0; n],
            cos: vec![0.0; n],
            b: vec![0.0; n],
        }
    }
}

impl Model {
    /// Writes `q''` into `qdd` and returns the contact force `m_v (g - u'')` (weight only
    /// off the beam, where the beam is free).
    fn accelerations(
        &self,
        ws: &mut Workspace,
        t: f64,
        y: &[f64],
        on_beam: bool,
        qdd: &mut [f64],
    ) -> f64 {
        let n = self.n;
        let (q, qd) = (&y[..n], &y[n..2 * n]);
        for j in 0..n {
            ws.b[j] = -self.modes.modal_mass_kg
                * (self.modes.two_zeta_omega[j] * qd[j] + self.modes.omega_sq[j] * q[j]);
        }
        if !on_beam {
            for (a, b) in qdd.iter_mut().zip(&ws.b) {
                *a = b / self.modes.modal_mass_kg;
            }
            return self.mass_kg * self.gravity_m_s2;
        }
        let k = self.modes.wavenumber_per_m;
        let v = self.speed_m_s;
        harmonics(k * v * t, &mut ws.sin, &mut ws.cos);
        // Convective part of u'': 2 v w_xt + v^2 w_xx at the mass.
        let (mut coriolis, mut centripetal, mut phi_sq) = (0.0, 0.0, 0.0);
        for j in 0..n {
            let kn = (j + 1) as f64 * k;
            coriolis += 2.0 * v * qd[j] * kn * ws.cos[j];
            centripetal -= v * v * q[j] * kn * kn * ws.sin[j];
            phi_sq += ws.sin[j] * ws.sin[j];
        }
        let load = self.mass_kg * (self.gravity_m_s2 - coriolis - centripetal);
        let mut phi_b = 0.0;
        for j in 0..n {
            ws.b[j] += load * ws.sin[j];
            phi_b += ws.sin[j] * ws.b[j];
        }
        // Sherman-Morrison: s = phi^T q''.
        let s = phi_b / (self.modes.modal_mass_kg + self.mass_kg * phi_sq);
        for ((a, b), phi) in qdd.iter_mut().zip(&ws.b).zip(&ws.sin) {
            *a = (b - self.mass_kg * phi * s) / self.modes.modal_mass_kg;
        }
        // u'' = phi^T q'' + convective terms.
        self.mass_kg * (self.gravity_m_s2 - s - coriolis - centripetal)
    }

    fn rhs(&self, ws: &mut Workspace, t: f64, y: &[f64], dydt: &mut [f64], on_beam: bool) {
        let n = self.n;
        dydt[..n].copy_from_slice(&y[n..2 * n]);
        let (_, qdd) = dydt.split_at_mut(n);
        self.accelerations(ws, t, y, on_beam, qdd);
    }

    fn sample(&self, ws: &mut Workspace, t: f64, y: &[f64], on_beam: bool) -> MovingMassSample {
        let mut qdd = vec![0.0; self.n];
        let force = self.accelerations(ws, t, y, on_beam, &mut qdd);
        let contact = if on_beam {
            // `accelerations` left the shapes at the mass in `ws.sin`.
            y[..self.n].iter().zip(&ws.sin).map(|(q, s)| q * s).sum()
        } else {
            0.0
        };
        MovingMassSample {
            time_s: t,
            midspan_deflection_m: self.modes.midspan(y),
            contact_deflection_m: contact,
            contact_force_n: force,
        }
    }
}

impl MovingMassProblem {
    /// Checks every input.
    pub fn validate(&self) -> Result<()> {
        self.beam.validate()?;
        require_positive("mass_kg", self.mass_kg)?;
        require_positive("speed_m_s", self.speed_m_s)?;
        self.options.validate()?;
        Ok(())
    }

    /// Time the mass leaves the beam, `L / v`, s.
    pub fn exit_time_s(&self) -> f64 {
        self.beam.span_m / self.speed_m_s
    }

    /// Integrates from t = 0 to the last sample time and returns the response at
    /// `sample_times_s` (finite, >= 0, non-decreasing).
    pub fn solve(&self, sample_times_s: &[f64]) -> Result<MovingMassSolution> {
        self.validate()?;
        validate_sample_times(sample_times_s)?;
        let t_end = sample_times_s.last().copied().unwrap_or(0.0);
        let beam = &self.beam;
        let o = &self.options;
        let n = o.n_modes;
        let model = Model {
            n,
            speed_m_s: self.speed_m_s,
            modes: BeamModes::new(beam, n, &o.damping),
            mass_kg: self.mass_kg,
            gravity_m_s2: o.gravity_m_s2,
        };
        let mut rhs_ws = Workspace::new(n);
        let mut observer_ws = Workspace::new(n);
        let exit_s = self.exit_time_s();
        let mut atol = vec![o.atol_displacement_m; 2 * n];
        atol[n..].fill(o.atol_velocity_m_s);
        let mut solver = o.integrator(&model.modes, atol)?;
        let mut state = vec![0.0; 2 * n];
        let mut samples = Vec::with_capacity(sample_times_s.len());
        let mut next_sample = 0;
        let mut peak = (0.0, 0.0);
        let mut peak_on_beam = 0.0_f64;
        let mut t = 0.0;
        // Two segments with a smooth right-hand side: on the beam, then free vibration.
        let segments = [(exit_s.min(t_end), true), (t_end, false)];
        for (seg_end, on_beam) in segments {
            loop {
                while next_sample < sample_times_s.len() && sample_times_s[next_sample] <= t {
                    samples.push(model.sample(&mut observer_ws, t, &state, on_beam));
                    next_sample += 1;
                }
                let target = match sample_times_s.get(next_sample) {
                    Some(&ts) if ts < seg_end => ts,
                    _ => seg_end,
                };
                if target <= t {
                    break;
                }
                let mut rhs =
                    |tt: f64, y: &[f64], d: &mut [f64]| model.rhs(&mut rhs_ws, tt, y, d, on_beam);
                solver.advance(&mut rhs, t, target, &mut state, &mut |tt, y| {
                    let w_mid = model.modes.midspan(y);
                    if w_mid > peak.1 {
                        peak = (tt, w_mid);
                    }
                    if on_beam {
                        peak_on_beam = peak_on_beam.max(w_mid);
                    }
                })?;
                t = target;
                if state.iter().any(|s| !s.is_finite()) {
                    return Err(Error::Divergence {
                        time_s: t,
                        step: solver.stats().accepted_steps,
                        quantity: "state".into(),
                        value: f64::NAN,
                        hint: "non-finite moving-mass state".into(),
                    });
                }
            }
        }
        // The final sample(s) at t_end.
        while next_sample < sample_times_s.len() {
            samples.push(model.sample(&mut observer_ws, t, &state, t <= exit_s));
            next_sample += 1;
        }
        Ok(MovingMassSolution {
            samples,
            peak_midspan_deflection_m: peak.1,
            peak_time_s: peak.0,
            peak_midspan_deflection_on_beam_m: peak_on_beam,
            stats: solver.stats(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::studies::analytic::{
        ModalDamping, MovingForceSolution, SprungMassOptions, SprungMassProblem, SprungMassVehicle,
    };

    fn beam() -> SimplySupportedBeam {
        SimplySupportedBeam::new(25.0, 3.5e10 * 1.3901, 18_358.0).unwrap()
    }

    fn problem(mass_kg: f64, n_modes: usize) -> MovingMassProblem {
        MovingMassProblem {
            beam: beam(),
            mass_kg,
            speed_m_s: 25.0,
            options: MovingMassOptions {
                n_modes,
                ..Default::default()
            },
        }
    }

    #[test]
    fn without_gravity_nothing_moves() {
        let mut p = problem(5750.0, 5);
        p.options.gravity_m_s2 = 0.0;
        let sol = p.solve(&[0.5, 1.2]).unwrap();
        assert_eq!(sol.peak_midspan_deflection_m, 0.0);
        assert!(sol.samples.iter().all(|s| s.midspan_deflection_m == 0.0));
    }

    #[test]
    fn light_mass_tends_to_the_moving_force_linearly() {
        // The inertia effect relative to the weight scales with m_v / (m L): halving the
        // mass halves the relative difference from Fryba's force m_v g.
        let diff = |m: f64| {
            let p = problem(m, 10);
            let sol = p.solve(&[p.exit_time_s()]).unwrap();
            let fryba =
                MovingForceSolution::new(beam(), m * 9.81, 25.0, ModalDamping::None, 10).unwrap();
            let (_, peak) = fryba.peak_deflection_m(12.5, p.exit_time_s());
            (sol.peak_midspan_deflection_on_beam_m - peak) / peak
        };
        let (d1, d2) = (diff(4000.0), diff(2000.0));
        assert!(d1 > 0.0, "the mass's inertia adds deflection: {d1}");
        assert!((d1 / d2 - 2.0).abs() < 0.05, "{d1} {d2}");
    }

    #[test]
    fn stiff_sprung_mass_tends_to_the_moving_mass() {
        // Independent formulation: the sprung-mass module with a very stiff spring, whose
        // mass follows w(v t, t) with every convective term implicitly. With the mass's
        // frequency w_v above every kept mode the difference falls as 1/k: 1e-5, 1e-6,
        // 1e-7 at k = 1.6e9, 1.6e10, 1.6e11 N/m with 3 modes (the one-mode equation is
        // checked against a fixed-step RK4 in the next test).
        let diff = |k: f64| {
            let p = problem(5750.0, 3);
            let mm = p.solve(&[p.exit_time_s()]).unwrap();
            let sm = SprungMassProblem {
                beam: beam(),
                vehicle: SprungMassVehicle {
                    mass_kg: 5750.0,
                    stiffness_n_m: k,
                    damping_n_s_m: 0.0,
                },
                speed_m_s: 25.0,
                road: None,
                options: SprungMassOptions {
                    n_modes: 3,
                    max_step_s: 1e-4,
                    ..Default::default()
                },
            }
            .solve(&[p.exit_time_s()])
            .unwrap();
            (mm.peak_midspan_deflection_on_beam_m - sm.peak_midspan_deflection_on_beam_m).abs()
                / mm.peak_midspan_deflection_on_beam_m
        };
        let (d10, d11) = (diff(1.595e10), diff(1.595e11));
        assert!(d11 < 1e-6, "{d11}");
        assert!(d11 < 0.2 * d10, "{d10} {d11}");
    }

    #[test]
    fn one_mode_agrees_with_a_fixed_step_rk4_of_the_one_mode_equation() {
        // The one-mode equation written out on its own, with scalars instead of the
        // module's Sherman-Morrison update: q = midspan deflection (sin(pi / 2) = 1),
        // phi = sin(k v t), k = pi / L, and the mass's acceleration
        // u'' = phi q'' + 2 v k cos(k v t) q' - v^2 k^2 phi q, so
        // (M_b + m phi^2) q'' = m phi (g - 2 v k cos q' + v^2 k^2 phi q) - M_b w^2 q.
        // Classical RK4 with h = 1e-5 s: global error ~ (w h)^4 / 120 per unit w t, below
        // 1e-16 at w = 24 rad/s. The module integrates adaptively (rtol 1e-9) and takes
        // its peak at steps of at most 2e-5 s, which sample the peak within
        // (w_p h)^2 / 8 ~ 3e-8 for the ~4 Hz shape of the peak: 1.5e-7 is 5x that.
        let p = problem(5750.0, 1);
        let module = p.solve(&[p.exit_time_s()]).unwrap();
        let b = beam();
        let (m, v, g) = (5750.0, 25.0, 9.81);
        let k = std::f64::consts::PI / b.span_m;
        let mb = 0.5 * b.mass_per_length_kg_m * b.span_m;
        let w2 = b.omega_rad_s(1).powi(2);
        let accel = |t: f64, q: f64, qd: f64| {
            let (sin, cos) = (k * v * t).sin_cos();
            (m * sin * (g - 2.0 * v * k * cos * qd + v * v * k * k * sin * q) - mb * w2 * q)
                / (mb + m * sin * sin)
        };
        let h = 1e-5;
        let steps = (p.exit_time_s() / h).round() as usize;
        let (mut q, mut qd, mut peak) = (0.0f64, 0.0f64, 0.0f64);
        for i in 0..steps {
            let t = i as f64 * h;
            let (k1q, k1v) = (qd, accel(t, q, qd));
            let (k2q, k2v) = (
                qd + 0.5 * h * k1v,
                accel(t + 0.5 * h, q + 0.5 * h * k1q, qd + 0.5 * h * k1v),
            );
            let (k3q, k3v) = (
                qd + 0.5 * h * k2v,
                accel(t + 0.5 * h, q + 0.5 * h * k2q, qd + 0.5 * h * k2v),
            );
            let (k4q, k4v) = (qd + h * k3v, accel(t + h, q + h * k3q, qd + h * k3v));
            q += h / 6.0 * (k1q + 2.0 * k2q + 2.0 * k3q + k4q);
            qd += h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
            peak = peak.max(q);
        }
        let error = (module.peak_midspan_deflection_on_beam_m - peak).abs() / peak;
        assert!(
            error < 1.5e-7,
            "module {} m, RK4 {peak} m: {error:e}",
            module.peak_midspan_deflection_on_beam_m
        );
    }
}
