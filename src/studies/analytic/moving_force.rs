//! Constant forces crossing a simply supported beam at constant speed: Fryba's closed-form
//! modal solution, one force or an axle train by superposition.
//!
//! Source: L. Fryba, Vibration of Solids and Structures under Moving Loads (1972/1999),
//! chapter 1, eq. 1.30 and the free vibration after the load leaves. Each mode obeys
//!
//! `q_n'' + 2 zeta_n w_n q_n' + w_n^2 q_n = (2 P / (m L)) sin(n pi v t / L)`, `0 <= t <= L/v`,
//!
//! and vibrates freely afterwards, with `q_n, q_n'` continuous at exit; the deflection is
//! `w(x, t) = sum_n q_n(t) sin(n pi x / L)`. Every mode is solved in closed form (particular
//! `A sin + B cos` plus the damped homogeneous part fitted to a beam at rest); nothing is
//! stepped in time.
//!
//! Sign convention: forces and deflections positive DOWNWARD. Deflections are measured
//! from the dead-load equilibrium (the beam's own weight is not a load here).

use std::f64::consts::PI;

use super::beam::{harmonics, require_mode_count, ModalDamping, SimplySupportedBeam};
use super::oscillator::DampedOscillator;
use crate::error::{require_finite, require_non_negative, require_positive, Error, Result};

/// Largest mode count accepted (the series is evaluated term by term).
pub const MAX_MODES: usize = 10_000;

/// Several constant forces travelling together (the axles of a vehicle).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct MovingLoadTrain {
    /// `(offset_behind_front_m, force_n)` per axle: the axle enters the beam
    /// `offset / speed` seconds after the front one (offset 0). Forces positive downward.
    pub loads: Vec<(f64, f64)>,
}

/// One mode's response to a UNIT force entering at t = 0.
#[derive(Debug, Clone, Copy)]
struct ModeResponse {
    omega_rad_s: f64,
    zeta: f64,
    /// Forcing circular frequency `n pi v / L`.
    forcing_rad_s: f64,
    /// Modal force amplitude per newton, `2 / (m L)`.
    force_per_n: f64,
    /// Particular solution `A sin(W t) + B cos(W t)` (damped modes only).
    a: f64,
    b: f64,
    oscillator: DampedOscillator,
    /// Modal displacement and velocity when the force leaves the beam.
    exit_q: f64,
    exit_v: f64,
    passage_s: f64,
}

/// `sin(u) / u`, accurate near 0.
fn sinc(u: f64) -> f64 {
    if u.abs() < 1e-4 {
        1.0 - u * u / 6.0
    } else {
        u.sin() / u
    }
}

impl ModeResponse {
    fn new(
        omega_rad_s: f64,
        zeta: f64,
        forcing_rad_s: f64,
        force_per_n: f64,
        passage_s: f64,
    ) -> Self {
        let w2 = omega_rad_s * omega_rad_s;
        let detune = w2 - forcing_rad_s * forcing_rad_s;
        let cross = 2.0 * zeta * omega_rad_s * forcing_rad_s;
        let denom = detune * detune + cross * cross;
        // Particular solution of q'' + 2 zeta w q' + w^2 q = f sin(W t) (Clough & Penzien,
        // eq. 3-10): A = f (w^2 - W^2) / D, B = -f 2 zeta w W / D. Unused when zeta = 0.
        let (a, b) = if zeta > 0.0 {
            (force_per_n * detune / denom, -force_per_n * cross / denom)
        } else {
            (0.0, 0.0)
        };
        let mut mode = Self {
            omega_rad_s,
            zeta,
            forcing_rad_s,
            force_per_n,
            a,
            b,
            oscillator: DampedOscillator { omega_rad_s, zeta },
            exit_q: 0.0,
            exit_v: 0.0,
            passage_s,
        };
        let (q, v) = mode.forced(passage_s);
        mode.exit_q = q;
        mode.exit_v = v;
        mode
    }

    /// Displacement and velocity while the force is on the beam, `0 <= t <= L/v`.
    fn forced(&self, t: f64) -> (f64, f64) {
        let w = self.omega_rad_s;
        let big_w = self.forcing_rad_s;
        if self.zeta == 0.0 {
            // Undamped: q = f / (w^2 - W^2) (sin W t - (W / w) sin w t), rewritten with
            // sum-to-product identities so that it stays exact at and near resonance W = w
            // (where it tends to f / (2 w^2) (sin w t - w t cos w t)):
            // q  = f / (w + W) [sin(w t) / w - t cos((w + W) t / 2) sinc((w - W) t / 2)],
            // q' = f W / (w + W) t sin((w + W) t / 2) sinc((w - W) t / 2).
            let sum = w + big_w;
            let sc = sinc(0.5 * (w - big_w) * t);
            let (s_half, c_half) = (0.5 * sum * t).sin_cos();
            let q = self.force_per_n / sum * ((w * t).sin() / w - t * c_half * sc);
            let v = self.force_per_n * big_w / sum * t * s_half * sc;
            (q, v)
        } else {
            // Particular part plus the homogeneous part that starts from minus the
            // particular part's initial state, so that q(0) = q'(0) = 0.
            let (s, c) = (big_w * t).sin_cos();
            let h = self.oscillator.free_response(-self.b, -self.a * big_w, t);
            let q = self.a * s + self.b * c + h.displacement;
            let v = big_w * (self.a * c - self.b * s) + h.velocity;
            (q, v)
        }
    }

    /// Modal displacement, velocity and acceleration per newton, `tau` seconds after entry.
    fn state(&self, tau: f64) -> (f64, f64, f64) {
        let w = self.omega_rad_s;
        let damping = 2.0 * self.zeta * w;
        if tau <= 0.0 {
            (0.0, 0.0, 0.0)
        } else if tau <= self.passage_s {
            let (q, v) = self.forced(tau);
            let force = self.force_per_n * (self.forcing_rad_s * tau).sin();
            (q, v, force - damping * v - w * w * q)
        } else {
            let s = self
                .oscillator
                .free_response(self.exit_q, self.exit_v, tau - self.passage_s);
            (s.displacement, s.velocity, s.acceleration)
        }
    }
}

/// Which time derivative of the deflection to evaluate.
#[derive(Debug, Clone, Copy)]
enum Derivative {
    Displacement,
    Velocity,
    Acceleration,
}

/// Closed-form response of a simply supported beam to constant forces crossing it.
#[derive(Debug, Clone)]
pub struct MovingForceSolution {
    beam: SimplySupportedBeam,
    speed_m_s: f64,
    /// `(entry_time_s, force_n)` per load.
    loads: Vec<(f64, f64)>,
    modes: Vec<ModeResponse>,
}

impl MovingForceSolution {
    /// One constant force `force_n` (positive downward) entering at x = 0 at t = 0 with
    /// speed `speed_m_s`, `n_modes` modes (100 is plenty for displacement; velocity and
    /// acceleration converge more slowly).
    pub fn new(
        beam: SimplySupportedBeam,
        force_n: f64,
        speed_m_s: f64,
        damping: ModalDamping,
        n_modes: usize,
    ) -> Result<Self> {
        let train = MovingLoadTrain {
            loads: vec![(0.0, force_n)],
        };
        Self::for_train(beam, &train, speed_m_s, damping, n_modes)
    }

    /// Several forces at fixed spacings (superposition of single-force solutions, each
    /// delayed by `offset / speed`).
    pub fn for_train(
        beam: SimplySupportedBeam,
        train: &MovingLoadTrain,
        speed_m_s: f64,
        damping: ModalDamping,
        n_modes: usize,
    ) -> Result<Self> {
        beam.validate()?;
        damping.validate()?;
        require_positive("speed_m_s", speed_m_s)?;
        require_mode_count("n_modes", n_modes, MAX_MODES)?;
        if train.loads.is_empty() {
            return Err(Error::invalid("loads", "[]", "needs at least one load"));
        }
        let mut loads = Vec::with_capacity(train.loads.len());
        for (i, &(offset_m, force_n)) in train.loads.iter().enumerate() {
            require_non_negative(&format!("loads[{i}].offset_behind_front_m"), offset_m)?;
            require_finite(&format!("loads[{i}].force_n"), force_n)?;
            loads.push((offset_m / speed_m_s, force_n));
        }
        let passage_s = beam.span_m / speed_m_s;
        let force_per_n = 2.0 / (beam.mass_per_length_kg_m * beam.span_m);
        let modes = (1..=n_modes)
            .map(|n| {
                let omega = beam.omega_rad_s(n);
                let forcing = n as f64 * PI * speed_m_s / beam.span_m;
                ModeResponse::new(omega, damping.zeta(omega), forcing, force_per_n, passage_s)
            })
            .collect();
        Ok(Self {
            beam,
            speed_m_s,
            loads,
            modes,
        })
    }

    /// The beam.
    pub fn beam(&self) -> &SimplySupportedBeam {
        &self.beam
    }

    /// Speed of the loads, m/s.
    pub fn speed_m_s(&self) -> f64 {
        self.speed_m_s
    }

    /// Time for one load to cross the span, `L / v`, s.
    pub fn passage_time_s(&self) -> f64 {
        self.beam.span_m / self.speed_m_s
    }

    /// Time at which the last load leaves the beam, s.
    pub fn exit_time_s(&self) -> f64 {
        let last_entry = self.loads.iter().map(|l| l.0).fold(0.0, f64::max);
        last_entry + self.passage_time_s()
    }

    /// Modal displacement `q_n(t)` of mode `n` (1-based), m (the mode shape has unit
    /// amplitude). Zero for `n` outside `1..=n_modes`.
    pub fn modal_displacement_m(&self, n: usize, t_s: f64) -> f64 {
        match n.checked_sub(1).and_then(|i| self.modes.get(i)) {
            Some(mode) => self
                .loads
                .iter()
                .map(|&(entry_s, force_n)| force_n * mode.state(t_s - entry_s).0)
                .sum(),
            None => 0.0,
        }
    }

    fn evaluate(&self, x_m: f64, t_s: f64, which: Derivative) -> f64 {
        if !(0.0..=self.beam.span_m).contains(&x_m) {
            return 0.0;
        }
        let n = self.modes.len();
        let mut shapes = vec![0.0; n];
        let mut unused = vec![0.0; n];
        harmonics(PI * x_m / self.beam.span_m, &mut shapes, &mut unused);
        let mut total = 0.0;
        for (mode, &shape) in self.modes.iter().zip(&shapes) {
            // Nodes of the mode (e.g. even modes at midspan) contribute nothing.
            if shape.abs() < 1e-13 {
                continue;
            }
            let mut modal = 0.0;
            for &(entry_s, force_n) in &self.loads {
                let (q, v, a) = mode.state(t_s - entry_s);
                modal += force_n
                    * match which {
                        Derivative::Displacement => q,
                        Derivative::Velocity => v,
                        Derivative::Acceleration => a,
                    };
            }
            total += modal * shape;
        }
        total
    }

    /// Deflection at `x_m` and time `t_s` (downward positive), m.
    pub fn deflection_m(&self, x_m: f64, t_s: f64) -> f64 {
        self.evaluate(x_m, t_s, Derivative::Displacement)
    }

    /// Vertical velocity at `x_m`, `t_s` (downward positive), m/s.
    pub fn velocity_m_s(&self, x_m: f64, t_s: f64) -> f64 {
        self.evaluate(x_m, t_s, Derivative::Velocity)
    }

    /// Vertical acceleration at `x_m`, `t_s` (downward positive), m/s^2. Converges slowly
    /// with the mode count (the force's entry excites every mode).
    pub fn acceleration_m_s2(&self, x_m: f64, t_s: f64) -> f64 {
        self.evaluate(x_m, t_s, Derivative::Acceleration)
    }

    /// Largest deflection at `x_m` over `0 <= t <= t_end_s`: `(time_s, deflection_m)`.
    ///
    /// Scans a grid of step `min(T_1, L/v) / 400` and refines the best grid maxima by
    /// golden-section search to ~1e-12 s.
    pub fn peak_deflection_m(&self, x_m: f64, t_end_s: f64) -> (f64, f64) {
        let t1_s = 2.0 * PI / self.beam.omega_rad_s(1);
        let dt = t1_s.min(self.passage_time_s()) / 400.0;
        maximize(|t| self.deflection_m(x_m, t), 0.0, t_end_s.max(0.0), dt)
    }

    /// Largest static midspan deflection while the loads cross (quasi-static influence
    /// line), m. For one force it is `P L^3 / (48 EI)`.
    pub fn static_midspan_peak_m(&self) -> f64 {
        let l = self.beam.span_m;
        if let [(_, force_n)] = self.loads.as_slice() {
            return self.beam.static_midspan_deflection_m(*force_n);
        }
        let v = self.speed_m_s;
        let static_at = |t: f64| -> f64 {
            self.loads
                .iter()
                .map(|&(entry_s, force_n)| {
                    self.beam
                        .static_deflection_m(0.5 * l, v * (t - entry_s), force_n)
                })
                .sum()
        };
        maximize(
            static_at,
            0.0,
            self.exit_time_s(),
            self.passage_time_s() / 2000.0,
        )
        .1
    }

    /// Dynamic amplification of the midspan deflection: the largest midspan deflection for
    /// `0 <= t <= t_end_s` divided by [`MovingForceSolution::static_midspan_peak_m`]
    /// (`P L^3 / (48 EI)` for one force). Pass `t_end_s = exit_time_s()` for the maximum
    /// during the passage only, a later time to include the free vibration.
    pub fn midspan_daf(&self, t_end_s: f64) -> f64 {
        let peak = self.peak_deflection_m(0.5 * self.beam.span_m, t_end_s).1;
        peak / self.static_midspan_peak_m()
    }
}

/// Maximum of `f` on `[t0, t1]`: grid of step `dt`, then golden-section refinement of the
/// five best grid maxima within their neighbouring grid points.
pub(crate) fn maximize<F: Fn(f64) -> f64>(f: F, t0: f64, t1: f64, dt: f64) -> (f64, f64) {
    if t1 <= t0 || dt <= 0.0 {
        return (t0, f(t0));
    }
    let n = ((t1 - t0) / dt).ceil().max(2.0) as usize;
    let step = (t1 - t0) / n as f64;
    let values: Vec<f64> = (0..=n).map(|i| f(t0 + i as f64 * step)).collect();
    let mut candidates: Vec<usize> = (0..=n)
        .filter(|&i| {
            let left = if i == 0 {
                f64::NEG_INFINITY
            } else {
                values[i - 1]
            };
            let right = if i == n {
                f64::NEG_INFINITY
            } else {
                values[i + 1]
            };
            values[i] >= left && values[i] >= right
        })
        .collect();
    candidates.sort_by(|&a, &b| values[b].total_cmp(&values[a]));
    candidates.truncate(5);
    let mut best = (t0, f64::NEG_INFINITY);
    for &i in &candidates {
        let lo = t0 + i.saturating_sub(1) as f64 * step;
        let hi = t0 + (i + 1).min(n) as f64 * step;
        let refined = golden_max(&f, lo, hi);
        let grid = (t0 + i as f64 * step, values[i]);
        for cand in [refined, grid] {
            if cand.1 > best.1 {
                best = cand;
            }
        }
    }
    best
}

/// Golden-section search for the maximum of a unimodal `f` on `[lo, hi]`.
fn golden_max<F: Fn(f64) -> f64>(f: &F, mut lo: f64, mut hi: f64) -> (f64, f64) {
    let ratio = 0.5 * (5f64.sqrt() - 1.0);
    let mut x1 = hi - ratio * (hi - lo);
    let mut x2 = lo + ratio * (hi - lo);
    let mut f1 = f(x1);
    let mut f2 = f(x2);
    for _ in 0..80 {
        if hi - lo < 1e-13 * (1.0 + hi.abs()) {
            break;
        }
        if f1 < f2 {
            lo = x1;
            x1 = x2;
            f1 = f2;
            x2 = lo + ratio * (hi - lo);
            f2 = f(x2);
        } else {
            hi = x2;
            x2 = x1;
            f2 = f1;
            x1 = hi - ratio * (hi - lo);
            f1 = f(x1);
        }
    }
    if f1 > f2 {
        (x1, f1)
    } else {
        (x2, f2)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn paper_beam() -> SimplySupportedBeam {
        SimplySupportedBeam::new(30.0, 5.629e10, 12_000.0).unwrap()
    }

    /// The closed form must satisfy the modal ODE: check by central differences. The
    /// tolerance covers the O(h^2) truncation of the quotients.
    #[test]
    fn modal_closed_form_satisfies_the_ode() {
        for &zeta in &[0.0, 0.05, 1.5] {
            let mode = ModeResponse::new(20.0, zeta, 7.0, 1.0e-3, 1.2);
            let h = 1e-5;
            for i in 1..60 {
                let t = i as f64 * 0.037;
                if (t - 1.2).abs() < 2.0 * h {
                    continue;
                }
                let (q, v, a) = mode.state(t);
                let qp = mode.state(t + h);
                let qm = mode.state(t - h);
                let vel_fd = (qp.0 - qm.0) / (2.0 * h);
                let acc_fd = (qp.1 - qm.1) / (2.0 * h);
                let force = if t <= 1.2 {
                    1.0e-3 * (7.0 * t).sin()
                } else {
                    0.0
                };
                let residual = a + 2.0 * zeta * 20.0 * v + 400.0 * q - force;
                assert!(
                    residual.abs() < 1e-15,
                    "zeta {zeta} t {t} residual {residual}"
                );
                assert!((vel_fd - v).abs() < 1e-9, "zeta {zeta} t {t}");
                assert!((acc_fd - a).abs() < 1e-8, "zeta {zeta} t {t}");
            }
            // At rest before entry, continuous at exit.
            assert_eq!(mode.state(0.0), (0.0, 0.0, 0.0));
            let before = mode.state(1.2 - 1e-12);
            let after = mode.state(1.2 + 1e-12);
            assert!((before.0 - after.0).abs() < 1e-15 && (before.1 - after.1).abs() < 1e-13);
        }
    }

    #[test]
    fn undamped_resonance_is_finite_and_continuous() {
        // W = w exactly: q = f / (2 w^2) (sin w t - w t cos w t).
        let (w, f, t): (f64, f64, f64) = (10.0, 1.0, 0.77);
        let exact = f / (2.0 * w * w) * ((w * t).sin() - w * t * (w * t).cos());
        let at = ModeResponse::new(w, 0.0, w, f, 5.0).state(t).0;
        assert!((at - exact).abs() < 1e-15, "{at} {exact}");
        // Detuned by 1e-12: the true change is ~ f t^2 / (4 w) * dW ~ 1.5e-13.
        let near = ModeResponse::new(w, 0.0, w * (1.0 + 1e-12), f, 5.0)
            .state(t)
            .0;
        assert!((near - exact).abs() < 1e-12, "{near} {exact}");
        // Detuned by 1e-3, the textbook form loses only ~3 digits: compare to it.
        let big_w = w * (1.0 + 1e-3);
        let textbook =
            f / (w * w - big_w * big_w) * ((big_w * t).sin() - big_w / w * (w * t).sin());
        let ours = ModeResponse::new(w, 0.0, big_w, f, 5.0).state(t).0;
        assert!(
            (ours - textbook).abs() < 1e-12 * exact.abs(),
            "{ours} {textbook}"
        );
    }

    #[test]
    fn a_slow_force_gives_the_static_deflection() {
        // v = 0.1 m/s: alpha = 1.3e-4, the response is quasi-static to ~alpha.
        let beam = paper_beam();
        let p = 1.0e5;
        let sol =
            MovingForceSolution::new(beam, p, 0.1, ModalDamping::Constant(0.05), 100).unwrap();
        let t = 7.0 / 0.1;
        let dynamic = sol.deflection_m(20.0, t);
        let statics = beam.static_deflection_m(20.0, 7.0, p);
        assert!(
            (dynamic - statics).abs() < 1e-3 * statics,
            "{dynamic} vs {statics}"
        );
    }

    #[test]
    fn train_is_the_sum_of_delayed_single_forces() {
        let beam = paper_beam();
        let v = 20.0;
        let train = MovingLoadTrain {
            loads: vec![(0.0, 5.0e4), (4.27, 1.2e5)],
        };
        let sol = MovingForceSolution::for_train(beam, &train, v, ModalDamping::Constant(0.02), 50)
            .unwrap();
        let one =
            MovingForceSolution::new(beam, 5.0e4, v, ModalDamping::Constant(0.02), 50).unwrap();
        let two =
            MovingForceSolution::new(beam, 1.2e5, v, ModalDamping::Constant(0.02), 50).unwrap();
        for &t in &[0.1, 0.9, 1.6, 2.5] {
            let sum = one.deflection_m(11.0, t) + two.deflection_m(11.0, t - 4.27 / v);
            assert!((sol.deflection_m(11.0, t) - sum).abs() < 1e-15);
        }
        assert!((sol.exit_time_s() - (30.0 + 4.27) / v).abs() < 1e-12);
    }

    #[test]
    fn velocity_and_acceleration_are_time_derivatives_of_the_deflection() {
        // 20 modes so that central differences with h = 1e-6 s resolve every mode
        // (w_20 h = 0.0095): truncation ~ (w h)^2 / 6 relative on the top mode.
        let beam = paper_beam();
        let sol =
            MovingForceSolution::new(beam, 1.0e5, 25.0, ModalDamping::Constant(0.02), 20).unwrap();
        let h = 1e-6;
        for &(x, t) in &[(7.0, 0.3), (15.0, 0.9), (22.0, 1.5)] {
            let v = sol.velocity_m_s(x, t);
            let a = sol.acceleration_m_s2(x, t);
            let v_fd = (sol.deflection_m(x, t + h) - sol.deflection_m(x, t - h)) / (2.0 * h);
            let a_fd = (sol.velocity_m_s(x, t + h) - sol.velocity_m_s(x, t - h)) / (2.0 * h);
            assert!(
                (v - v_fd).abs() < 1e-6 * v.abs().max(1e-3),
                "x {x} t {t}: {v} {v_fd}"
            );
            assert!(
                (a - a_fd).abs() < 1e-4 * a.abs().max(1e-2),
                "x {x} t {t}: {a} {a_fd}"
            );
        }
    }

    #[test]
    fn maximize_finds_a_smooth_peak() {
        let (t, v) = maximize(|t| -(t - 0.123_456).powi(2) + 2.0, 0.0, 1.0, 0.01);
        assert!((t - 0.123_456).abs() < 1e-6 && (v - 2.0).abs() < 1e-12);
    }
}
