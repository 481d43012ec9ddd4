//! Newmark-beta time integration (Newmark 1959; e.g. Chopra, Dynamics of Structures,
//! section 5.4 and 15.3) in displacement form: the effective matrix
//! `K_eff = K + a0 M + a1 C` is constant for a fixed step, so it is factorized once and
//! every step costs matrix-vector products and one solve, with no allocation.

use nalgebra::{DMatrix, DVector};
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::linear::{Factor, Operator, Storage};
use crate::error::{Error, Result};
use crate::physics::linalg::SymMatrix;

/// Newmark parameters; the default is the average-acceleration rule (gamma 1/2, beta 1/4):
/// unconditionally stable, no numerical damping.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct NewmarkParams {
    /// gamma, in [0.5, 1] (default 0.5; below 0.5 the scheme amplifies).
    #[serde(default = "default_gamma")]
    #[schemars(range(min = 0.5, max = 1))]
    pub gamma: f64,
    /// beta, in (0, 0.5] (default 0.25).
    #[serde(default = "default_beta")]
    #[schemars(transform = crate::base::schema::positive, range(max = 0.5))]
    pub beta: f64,
}

fn default_gamma() -> f64 {
    0.5
}
fn default_beta() -> f64 {
    0.25
}

impl Default for NewmarkParams {
    fn default() -> Self {
        NewmarkParams {
            gamma: 0.5,
            beta: 0.25,
        }
    }
}

/// The integration constants of one step size.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NewmarkCoefficients {
    pub dt_s: f64,
    pub gamma: f64,
    pub beta: f64,
    /// 1 / (beta dt^2): acceleration per displacement increment.
    pub a0: f64,
    /// gamma / (beta dt): velocity per displacement increment.
    pub a1: f64,
    pub a2: f64,
    pub a3: f64,
    pub a4: f64,
    pub a5: f64,
}

impl NewmarkCoefficients {
    /// Checks `dt_s > 0`, `gamma` in [0.5, 1] and `beta` in (0, 0.5].
    pub fn new(dt_s: f64, params: NewmarkParams) -> Result<Self> {
        let NewmarkParams { gamma, beta } = params;
        if !(dt_s.is_finite() && dt_s > 0.0) {
            return Err(Error::invalid(
                "solver.dt_s",
                dt_s,
                "must be a finite number > 0",
            ));
        }
        if !(gamma.is_finite() && (0.5..=1.0).contains(&gamma)) {
            return Err(Error::invalid(
                "solver.newmark.gamma",
                gamma,
                "must be in [0.5, 1] (below 0.5 the scheme amplifies)",
            ));
        }
        if !(beta.is_finite() && beta > 0.0 && beta <= 0.5) {
            return Err(Error::invalid(
                "solver.newmark.beta",
                beta,
                "must be in (0, 0.5]",
            ));
        }
        Ok(NewmarkCoefficients {
            dt_s,
            gamma,
            beta,
            a0: 1.0 / (beta * dt_s * dt_s),
            a1: gamma / (beta * dt_s),
            a2: 1.0 / (beta * dt_s),
            a3: 1.0 / (2.0 * beta) - 1.0,
            a4: gamma / beta - 1.0,
            a5: dt_s / 2.0 * (gamma / beta - 2.0),
        })
    }

    /// Velocity at n+1 from the new displacement (the linear map the coupling uses).
    pub fn velocity(&self, u_next: f64, u: f64, v: f64, a: f64) -> f64 {
        self.a1 * (u_next - u) - self.a4 * v - self.a5 * a
    }

    /// Acceleration at n+1 from the new displacement.
    #[inline]
    pub fn acceleration(&self, u_next: f64, u: f64, v: f64, a: f64) -> f64 {
        self.a0 * (u_next - u) - self.a2 * v - self.a3 * a
    }
}

/// Displacement, velocity and acceleration of every DOF.
#[derive(Debug, Clone)]
pub struct State {
    pub u: DVector<f64>,
    pub v: DVector<f64>,
    pub a: DVector<f64>,
}

impl State {
    /// At rest.
    pub fn zeros(n: usize) -> Self {
        State {
            u: DVector::zeros(n),
            v: DVector::zeros(n),
            a: DVector::zeros(n),
        }
    }
}

/// How each step's linear system is solved.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SolveMode {
    /// Factorize once, solve every step (the way to do it).
    Prefactored(Storage),
    /// Assemble and LU-factorize the dense effective matrix every step: the paper's
    /// direct method, kept only as a baseline for studies and benches.
    FactorEachStep,
}

/// A linear structure `M a + C v + K u = f(t)` advanced by Newmark-beta.
pub struct Newmark {
    pub coefficients: NewmarkCoefficients,
    pub state: State,
    mass: Operator,
    damping: Operator,
    factor: Option<Factor>,
    k_eff_dense: DMatrix<f64>,
    scratch: DVector<f64>,
    /// `a1 u + a4 v + a5 a` of the last [`Newmark::add_history`]: minus the part of the
    /// next velocity known before the step.
    velocity_history: DVector<f64>,
    rhs: DVector<f64>,
}

impl Newmark {
    /// Prepares the integrator: builds `K_eff` and factorizes it (unless the mode is the
    /// per-step baseline).
    pub fn new(
        mass: &SymMatrix,
        damping: &SymMatrix,
        stiffness: &SymMatrix,
        coefficients: NewmarkCoefficients,
        mode: SolveMode,
    ) -> Result<Self> {
        let k_eff = SymMatrix::linear_combination(&[
            (1.0, stiffness),
            (coefficients.a0, mass),
            (coefficients.a1, damping),
        ]);
        let storage = match mode {
            SolveMode::Prefactored(s) => s,
            SolveMode::FactorEachStep => Storage::Dense,
        };
        let factor = match mode {
            SolveMode::Prefactored(s) => Some(Factor::new(&k_eff, s, "effective stiffness")?),
            SolveMode::FactorEachStep => None,
        };
        let n = mass.n();
        Ok(Newmark {
            coefficients,
            state: State::zeros(n),
            mass: Operator::new(mass, storage),
            damping: Operator::new(damping, storage),
            factor,
            k_eff_dense: if factor_each_step(mode) {
                k_eff.to_dense()
            } else {
                DMatrix::zeros(0, 0)
            },
            scratch: DVector::zeros(n),
            velocity_history: DVector::zeros(n),
            rhs: DVector::zeros(n),
        })
    }

    /// Adds the history terms `M(a0 u + a2 v + a3 a) + C(a1 u + a4 v + a5 a)` to `rhs`.
    pub fn add_history(&mut self, rhs: &mut DVector<f64>) {
        let c = self.coefficients;
        let s = &self.state;
        // Both combinations in one pass over the state.
        let (p, q) = (
            self.scratch.as_mut_slice(),
            self.velocity_history.as_mut_slice(),
        );
        let (u, v, a) = (s.u.as_slice(), s.v.as_slice(), s.a.as_slice());
        for i in 0..u.len() {
            p[i] = c.a0 * u[i] + c.a2 * v[i] + c.a3 * a[i];
            q[i] = c.a1 * u[i] + c.a4 * v[i] + c.a5 * a[i];
        }
        self.mass.mul_add(1.0, &self.scratch, rhs);
        self.damping.mul_add(1.0, &self.velocity_history, rhs);
    }

    /// `a1 u + a4 v + a5 a` at the last [`Newmark::add_history`] (the new velocity is
    /// `a1 u_next` minus this).
    pub fn velocity_history(&self) -> &DVector<f64> {
        &self.velocity_history
    }

    /// `K_eff^-1` as dense columns when that pays for the coupling's influence vectors:
    /// a banded factor computed once (not the paper's per-step mode) and a model small
    /// enough (n <= 1024: at most 8 MiB). `None` else.
    pub fn inverse_columns(&self) -> Option<Vec<DVector<f64>>> {
        const MAX_DOF: usize = 1024;
        let n = self.state.u.len();
        match &self.factor {
            // Only banded models: their wheel operators touch 4 DOFs, so Z is 4 axpys.
            // A lumped model's operator touches every mass (n axpys, slower than the
            // dense solve), a modal solve is already O(n).
            Some(f @ (Factor::Sparse(_) | Factor::Band(_))) if n <= MAX_DOF => Some(
                (0..n)
                    .map(|k| {
                        let mut e = DVector::zeros(n);
                        e[k] = 1.0;
                        f.solve_in_place(&mut e);
                        e
                    })
                    .collect(),
            ),
            _ => None,
        }
    }

    /// Overwrites `b` with `K_eff^-1 b`.
    pub fn solve_in_place(&self, b: &mut DVector<f64>) {
        match &self.factor {
            Some(f) => f.solve_in_place(b),
            None => {
                // The paper's way: a fresh dense factorization of the effective matrix.
                let lu = self.k_eff_dense.clone().lu();
                lu.solve_mut(b);
            }
        }
    }

    /// Accepts `u_next` as the displacement at n+1 and updates velocity and acceleration.
    pub fn commit(&mut self, u_next: &DVector<f64>) {
        let c = self.coefficients;
        let s = &mut self.state;
        // a_next = a0 (u_next - u) - a2 v - a3 a ; v_next = v + dt ((1 - gamma) a + gamma a_next)
        for i in 0..u_next.len() {
            let a_next = c.acceleration(u_next[i], s.u[i], s.v[i], s.a[i]);
            s.v[i] += c.dt_s * ((1.0 - c.gamma) * s.a[i] + c.gamma * a_next);
            s.a[i] = a_next;
            s.u[i] = u_next[i];
        }
    }

    /// One step of the uncoupled structure under the load `f_next` at t_{n+1}.
    pub fn step(&mut self, f_next: &DVector<f64>) {
        let mut rhs = std::mem::take(&mut self.rhs);
        rhs.copy_from(f_next);
        self.add_history(&mut rhs);
        self.solve_in_place(&mut rhs);
        self.commit(&rhs);
        self.rhs = rhs;
    }

    /// Sets the initial acceleration consistent with `f0` and the current u, v:
    /// `M a = f0 - C v - K u`.
    pub fn initialize_acceleration(
        &mut self,
        mass: &SymMatrix,
        stiffness: &SymMatrix,
        f0: &DVector<f64>,
    ) -> Result<()> {
        let mut r = f0.clone();
        stiffness.mul_add(-1.0, &self.state.u, &mut r);
        self.damping.mul_add(-1.0, &self.state.v, &mut r);
        Factor::new(mass, Storage::Sparse, "mass matrix")?.solve_in_place(&mut r);
        self.state.a = r;
        Ok(())
    }
}

fn factor_each_step(mode: SolveMode) -> bool {
    mode == SolveMode::FactorEachStep
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    fn oscillator(omega: f64, zeta: f64, dt: f64) -> Newmark {
        let one = |v: f64| SymMatrix::Dense(DMatrix::from_element(1, 1, v));
        let (m, k, c) = (one(1.0), one(omega * omega), one(2.0 * zeta * omega));
        let coef = NewmarkCoefficients::new(dt, NewmarkParams::default()).unwrap();
        Newmark::new(&m, &c, &k, coef, SolveMode::Prefactored(Storage::Dense)).unwrap()
    }

    /// Period of the free response, from the up-crossings of the displacement.
    fn measured_period(omega: f64, dt: f64) -> f64 {
        let mut nm = oscillator(omega, 0.0, dt);
        nm.state.u[0] = 1.0;
        nm.state.a[0] = -omega * omega;
        let zero = DVector::zeros(1);
        let mut crossings = Vec::new();
        let mut prev = nm.state.u[0];
        for step in 1..2_000_000 {
            nm.step(&zero);
            let u = nm.state.u[0];
            if prev < 0.0 && u >= 0.0 {
                // Linear interpolation of the crossing time.
                crossings.push((step as f64 - 1.0 + prev / (prev - u)) * dt);
                if crossings.len() == 201 {
                    break;
                }
            }
            prev = u;
        }
        (crossings[200] - crossings[0]) / 200.0
    }

    #[test]
    fn period_elongation_matches_closed_form() {
        // Average acceleration: T_num / T = w dt / (2 atan(w dt / 2)) exactly
        // (the discrete map is a rotation by 2 atan(w dt / 2) per step). Linear
        // interpolation of the first and last zero crossings errs by O((w dt)^3) of a
        // period; over 200 periods that is < 1e-6.
        let omega = 2.0 * PI;
        for dt_over_t in [0.02, 0.05, 0.1] {
            let dt = dt_over_t;
            let ratio = measured_period(omega, dt) / 1.0;
            let expected = omega * dt / (2.0 * (omega * dt / 2.0).atan());
            assert!(
                (ratio - expected).abs() < 1e-6 * expected,
                "dt/T {dt_over_t}: {ratio} vs {expected}"
            );
        }
    }

    #[test]
    fn undamped_energy_is_conserved() {
        // The average-acceleration rule conserves m v^2/2 + k u^2/2 exactly for a linear
        // undamped system; round-off only over 10^4 steps.
        let omega = 7.0;
        let mut nm = oscillator(omega, 0.0, 0.01);
        nm.state.u[0] = 0.3;
        nm.state.v[0] = -1.1;
        nm.state.a[0] = -omega * omega * 0.3;
        let energy = |s: &State| 0.5 * s.v[0].powi(2) + 0.5 * omega * omega * s.u[0].powi(2);
        let e0 = energy(&nm.state);
        let zero = DVector::zeros(1);
        for _ in 0..10_000 {
            nm.step(&zero);
        }
        assert!((energy(&nm.state) - e0).abs() < 1e-11 * e0);
    }

    #[test]
    fn damped_free_decay_follows_the_exact_envelope() {
        // zeta = 5 %, dt/T = 0.01: the amplitude after 10 periods is exp(-2 pi zeta 10)
        // within the O((w dt)^2) phase/amplitude error of the scheme: 0.5 %.
        let (omega, zeta) = (2.0 * PI, 0.05);
        let dt = 0.01;
        let mut nm = oscillator(omega, zeta, dt);
        nm.state.u[0] = 1.0;
        nm.state.a[0] = -omega * omega;
        let zero = DVector::zeros(1);
        let mut peak_late: f64 = 0.0;
        for step in 1..=1100 {
            nm.step(&zero);
            if step >= 950 {
                peak_late = peak_late.max(nm.state.u[0]);
            }
        }
        // The peak near t = 10 T of the exact response.
        let wd = omega * (1.0 - zeta * zeta).sqrt();
        let exact_peak = (950..=1100)
            .map(|s| {
                let t = s as f64 * dt;
                (-zeta * omega * t).exp() * ((wd * t).cos() + zeta * omega / wd * (wd * t).sin())
            })
            .fold(f64::MIN, f64::max);
        assert!(
            (peak_late - exact_peak).abs() < 5e-3 * exact_peak,
            "{peak_late} vs {exact_peak}"
        );
    }

    #[test]
    fn prefactored_and_per_step_solves_agree() {
        let m = DMatrix::from_row_slice(2, 2, &[2.0, 0.1, 0.1, 1.0]);
        let k = DMatrix::from_row_slice(2, 2, &[300.0, -100.0, -100.0, 100.0]);
        let c = SymMatrix::from(&k * 0.01);
        let (m, k) = (SymMatrix::from(m), SymMatrix::from(k));
        let coef = NewmarkCoefficients::new(0.01, NewmarkParams::default()).unwrap();
        let mut a =
            Newmark::new(&m, &c, &k, coef, SolveMode::Prefactored(Storage::Sparse)).unwrap();
        let mut b = Newmark::new(&m, &c, &k, coef, SolveMode::FactorEachStep).unwrap();
        for step in 0..500 {
            let f = DVector::from_vec(vec![(step as f64 * 0.05).sin(), 1.0]);
            a.step(&f);
            b.step(&f);
        }
        assert!((&a.state.u - &b.state.u).norm() < 1e-10 * b.state.u.norm());
    }

    #[test]
    fn bad_parameters_are_rejected_with_their_field() {
        let p = NewmarkParams::default();
        for (dt, params, field) in [
            (0.0, p, "solver.dt_s"),
            (-1e-3, p, "solver.dt_s"),
            (f64::NAN, p, "solver.dt_s"),
            (
                1e-3,
                NewmarkParams {
                    gamma: 0.4,
                    beta: 0.25,
                },
                "solver.newmark.gamma",
            ),
            (
                1e-3,
                NewmarkParams {
                    gamma: 0.5,
                    beta: 0.0,
                },
                "solver.newmark.beta",
            ),
        ] {
            let msg = NewmarkCoefficients::new(dt, params)
                .unwrap_err()
                .to_string();
            assert!(msg.starts_with(field), "{msg}");
        }
    }
}
