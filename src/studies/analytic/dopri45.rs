//! Adaptive explicit Runge-Kutta integration with the Dormand-Prince 5(4) pair.
//!
//! Source: J. R. Dormand and P. J. Prince, "A family of embedded Runge-Kutta formulae",
//! J. Comp. Appl. Math. 6 (1980) 19-26 (the tableau), and Hairer, Norsett & Wanner,
//! Solving Ordinary Differential Equations I, 2nd ed., section II.4 (error norm, step-size
//! control with the PI stabilization of section IV.2 as in their DOPRI5 code).
//! Local extrapolation: the 5th-order solution is propagated, the 4th-order one only
//! estimates the error. Written for the reference solutions of [`crate::studies::analytic`]; it is
//! deliberately not shared with the production time integrators.

use crate::error::{require_positive, Error, Result};

/// Tolerances and limits of the integrator.
#[derive(Debug, Clone, PartialEq)]
pub struct Dopri45Options {
    /// Relative tolerance. Default 1e-9.
    pub rtol: f64,
    /// Absolute tolerance per state component (same length as the state); an empty vector
    /// means `1e-12` for every component.
    pub atol: Vec<f64>,
    /// Largest step, s. Default infinity.
    pub max_step_s: f64,
    /// First trial step, s. Default 1e-6 (the controller grows it by up to 10x a step).
    pub initial_step_s: f64,
    /// Give up after this many steps (accepted + rejected). Default 50 million.
    pub max_steps: u64,
}

impl Default for Dopri45Options {
    fn default() -> Self {
        Self {
            rtol: 1e-9,
            atol: Vec::new(),
            max_step_s: f64::INFINITY,
            initial_step_s: 1e-6,
            max_steps: 50_000_000,
        }
    }
}

/// Work counters.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Dopri45Stats {
    /// Accepted steps.
    pub accepted_steps: u64,
    /// Rejected steps.
    pub rejected_steps: u64,
    /// Right-hand-side evaluations.
    pub rhs_evaluations: u64,
}

const C2: f64 = 1.0 / 5.0;
const C3: f64 = 3.0 / 10.0;
const C4: f64 = 4.0 / 5.0;
const C5: f64 = 8.0 / 9.0;
const A21: f64 = 1.0 / 5.0;
const A31: f64 = 3.0 / 40.0;
const A32: f64 = 9.0 / 40.0;
const A41: f64 = 44.0 / 45.0;
const A42: f64 = -56.0 / 15.0;
const A43: f64 = 32.0 / 9.0;
const A51: f64 = 19372.0 / 6561.0;
const A52: f64 = -25360.0 / 2187.0;
const A53: f64 = 64448.0 / 6561.0;
const A54: f64 = -212.0 / 729.0;
const A61: f64 = 9017.0 / 3168.0;
const A62: f64 = -355.0 / 33.0;
const A63: f64 = 46732.0 / 5247.0;
const A64: f64 = 49.0 / 176.0;
const A65: f64 = -5103.0 / 18656.0;
// 5th-order weights (also the 7th stage, "first same as last").
const B1: f64 = 35.0 / 384.0;
const B3: f64 = 500.0 / 1113.0;
const B4: f64 = 125.0 / 192.0;
const B5: f64 = -2187.0 / 6784.0;
const B6: f64 = 11.0 / 84.0;
// 5th minus 4th-order weights.
const E1: f64 = 71.0 / 57600.0;
const E3: f64 = -71.0 / 16695.0;
const E4: f64 = 71.0 / 1920.0;
const E5: f64 = -17253.0 / 339200.0;
const E6: f64 = 22.0 / 525.0;
const E7: f64 = -1.0 / 40.0;

/// Dormand-Prince 5(4) integrator with reusable work buffers.
#[derive(Debug, Clone)]
pub struct Dopri45 {
    options: Dopri45Options,
    atol: Vec<f64>,
    k: [Vec<f64>; 7],
    stage: Vec<f64>,
    next: Vec<f64>,
    /// Step proposed for the next call, s.
    step_s: f64,
    /// Previous accepted error norm (PI controller memory).
    previous_error: f64,
    stats: Dopri45Stats,
}

impl Dopri45 {
    /// An integrator for states of dimension `dim`.
    pub fn new(dim: usize, options: Dopri45Options) -> Result<Self> {
        require_positive("rtol", options.rtol)?;
        if options.max_step_s.is_nan() || options.max_step_s <= 0.0 {
            return Err(Error::invalid(
                "max_step_s",
                options.max_step_s,
                "must be > 0",
            ));
        }
        require_positive("initial_step_s", options.initial_step_s)?;
        let atol = if options.atol.is_empty() {
            vec![1e-12; dim]
        } else if options.atol.len() == dim {
            for (i, &a) in options.atol.iter().enumerate() {
                require_positive(&format!("atol[{i}]"), a)?;
            }
            options.atol.clone()
        } else {
            return Err(Error::invalid(
                "atol.len()",
                options.atol.len(),
                format!("must equal the state dimension {dim}"),
            ));
        };
        let step_s = options.initial_step_s.min(options.max_step_s);
        Ok(Self {
            options,
            atol,
            k: std::array::from_fn(|_| vec![0.0; dim]),
            stage: vec![0.0; dim],
            next: vec![0.0; dim],
            step_s,
            previous_error: 1e-4,
            stats: Dopri45Stats::default(),
        })
    }

    /// Work counters so far.
    pub fn stats(&self) -> Dopri45Stats {
        self.stats
    }

    /// Advances `y` from `t0_s` to exactly `t1_s`, calling `rhs(t, y, dydt)` for the
    /// derivative and `observer(t, y)` after every accepted step.
    ///
    /// The derivative is re-evaluated at `t0_s` (no first-same-as-last carry-over between
    /// calls), so a caller may split the interval at discontinuities of `rhs` and change
    /// `rhs` between calls.
    pub fn advance<F, O>(
        &mut self,
        rhs: &mut F,
        t0_s: f64,
        t1_s: f64,
        y: &mut [f64],
        observer: &mut O,
    ) -> Result<()>
    where
        F: FnMut(f64, &[f64], &mut [f64]),
        O: FnMut(f64, &[f64]),
    {
        let dim = self.stage.len();
        if y.len() != dim {
            return Err(Error::invalid(
                "state.len()",
                y.len(),
                format!("must be {dim}"),
            ));
        }
        if t1_s <= t0_s {
            return Ok(());
        }
        let mut t = t0_s;
        rhs(t, y, &mut self.k[0]);
        self.stats.rhs_evaluations += 1;
        let mut h = self.step_s.min(self.options.max_step_s);
        loop {
            let remaining = t1_s - t;
            let proposal = h;
            let last = h >= remaining * (1.0 - 1e-12);
            if last {
                h = remaining;
            }
            if self.stats.accepted_steps + self.stats.rejected_steps >= self.options.max_steps {
                return Err(Error::Divergence {
                    time_s: t,
                    step: self.stats.accepted_steps,
                    quantity: "step count".into(),
                    value: self.options.max_steps as f64,
                    hint: "the problem is too stiff for the tolerances; lower n_modes or \
                           loosen rtol/atol"
                        .into(),
                });
            }
            let err = self.trial_step(rhs, t, h, y);
            if !err.is_finite() {
                // Treat overflow as a huge error: shrink hard and retry.
                if h < 1e-15 * (1.0 + t.abs()) {
                    return Err(Error::Divergence {
                        time_s: t,
                        step: self.stats.accepted_steps,
                        quantity: "error norm".into(),
                        value: err,
                        hint: "non-finite state in the Dormand-Prince step".into(),
                    });
                }
                self.stats.rejected_steps += 1;
                h *= 0.1;
                continue;
            }
            // PI step-size control (Hairer, Norsett & Wanner, DOPRI5 defaults:
            // beta = 0.04, safety 0.9, factor limited to [0.2, 10]).
            let beta = 0.04;
            let fac11 = err.powf(0.2 - 0.75 * beta);
            if err <= 1.0 {
                let fac = (fac11 / self.previous_error.powf(beta) / 0.9).clamp(0.1, 5.0);
                let h_new = (h / fac).min(self.options.max_step_s);
                self.previous_error = err.max(1e-4);
                self.stats.accepted_steps += 1;
                t = if last { t1_s } else { t + h };
                y.copy_from_slice(&self.next);
                let (first, rest) = self.k.split_at_mut(1);
                first[0].copy_from_slice(&rest[5]);
                observer(t, y);
                if last {
                    // A step shortened to land on t1 says little about the step the
                    // solution allows: keep the larger of the two proposals.
                    self.step_s = h_new.max(proposal).min(self.options.max_step_s);
                    return Ok(());
                }
                h = h_new;
            } else {
                self.stats.rejected_steps += 1;
                h /= (fac11 / 0.9).min(5.0);
            }
        }
    }

    /// One trial step of size `h` from `(t, y)`, with `k[0] = f(t, y)` already set. Leaves
    /// the 5th-order result in `next` and `f(t + h, next)` in `k[6]`; returns the scaled
    /// RMS error norm (<= 1 accepts).
    fn trial_step<F>(&mut self, rhs: &mut F, t: f64, h: f64, y: &[f64]) -> f64
    where
        F: FnMut(f64, &[f64], &mut [f64]),
    {
        let dim = y.len();
        let [k1, k2, k3, k4, k5, k6, k7] = &mut self.k;
        let stage = &mut self.stage;
        for i in 0..dim {
            stage[i] = y[i] + h * A21 * k1[i];
        }
        rhs(t + C2 * h, stage, k2);
        for i in 0..dim {
            stage[i] = y[i] + h * (A31 * k1[i] + A32 * k2[i]);
        }
        rhs(t + C3 * h, stage, k3);
        for i in 0..dim {
            stage[i] = y[i] + h * (A41 * k1[i] + A42 * k2[i] + A43 * k3[i]);
        }
        rhs(t + C4 * h, stage, k4);
        for i in 0..dim {
            stage[i] = y[i] + h * (A51 * k1[i] + A52 * k2[i] + A53 * k3[i] + A54 * k4[i]);
        }
        rhs(t + C5 * h, stage, k5);
        for i in 0..dim {
            stage[i] =
                y[i] + h * (A61 * k1[i] + A62 * k2[i] + A63 * k3[i] + A64 * k4[i] + A65 * k5[i]);
        }
        rhs(t + h, stage, k6);
        let next = &mut self.next;
        for i in 0..dim {
            next[i] = y[i] + h * (B1 * k1[i] + B3 * k3[i] + B4 * k4[i] + B5 * k5[i] + B6 * k6[i]);
        }
        rhs(t + h, next, k7);
        self.stats.rhs_evaluations += 6;
        let mut sum = 0.0;
        for i in 0..dim {
            let e =
                h * (E1 * k1[i] + E3 * k3[i] + E4 * k4[i] + E5 * k5[i] + E6 * k6[i] + E7 * k7[i]);
            let scale = self.atol[i] + self.options.rtol * y[i].abs().max(next[i].abs());
            sum += (e / scale).powi(2);
        }
        (sum / dim.max(1) as f64).sqrt()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn harmonic_oscillator_matches_closed_form() {
        let w = 3.0;
        let mut rhs = |_t: f64, y: &[f64], d: &mut [f64]| {
            d[0] = y[1];
            d[1] = -w * w * y[0];
        };
        let options = Dopri45Options {
            rtol: 1e-10,
            atol: vec![1e-12, 1e-12],
            ..Default::default()
        };
        let mut solver = Dopri45::new(2, options).unwrap();
        let mut y = [1.0, 0.0];
        solver
            .advance(&mut rhs, 0.0, 10.0, &mut y, &mut |_, _| {})
            .unwrap();
        // Global error ~ a few hundred local tolerances over 5 periods.
        assert!((y[0] - (30.0f64).cos()).abs() < 1e-8, "{}", y[0]);
        assert!((y[1] + w * (30.0f64).sin()).abs() < 3e-8);
        let stats = solver.stats();
        assert!(
            stats.accepted_steps > 50 && stats.accepted_steps < 5000,
            "{stats:?}"
        );
    }

    #[test]
    fn fifth_order_convergence_on_exponential() {
        // y' = y on [0, 1] in fixed steps h = 1/8, 1/16, 1/32 (the step capped at h and
        // the tolerance so loose that no step is rejected or shortened): the propagated
        // 5th-order solution has a global error C h^5, so halving h divides it by 2^5 = 32
        // and the observed order log2(e(h) / e(h/2)) is 5 up to the next term, O(h):
        // measured 4.96 and 4.98. Propagating the embedded 4th-order solution (or a wrong
        // weight) gives 4 (or less), outside [4.8, 5.2].
        let steps_of = |h: f64| -> (f64, Dopri45Stats) {
            let options = Dopri45Options {
                rtol: 1e6,
                atol: vec![1e6],
                max_step_s: h,
                initial_step_s: h,
                ..Default::default()
            };
            let mut solver = Dopri45::new(1, options).unwrap();
            let mut y = [1.0];
            solver
                .advance(
                    &mut |_t, y: &[f64], d: &mut [f64]| d[0] = y[0],
                    0.0,
                    1.0,
                    &mut y,
                    &mut |_, _| {},
                )
                .unwrap();
            ((y[0] - 1f64.exp()).abs(), solver.stats())
        };
        let hs = [1.0 / 8.0, 1.0 / 16.0, 1.0 / 32.0];
        let mut errors = Vec::new();
        for h in hs {
            let (error, stats) = steps_of(h);
            assert_eq!(stats.accepted_steps, (1.0 / h) as u64, "fixed steps of {h}");
            assert_eq!(stats.rejected_steps, 0);
            errors.push(error);
        }
        for pair in errors.windows(2) {
            let order = (pair[0] / pair[1]).log2();
            assert!((4.8..=5.2).contains(&order), "order {order}: {errors:?}");
        }
    }

    #[test]
    fn lands_exactly_on_the_end_time_and_observes_every_step() {
        let mut solver = Dopri45::new(1, Dopri45Options::default()).unwrap();
        let mut y = [0.0];
        let mut last_t = 0.0;
        let mut count = 0u64;
        solver
            .advance(
                &mut |t, _y: &[f64], d: &mut [f64]| d[0] = t.cos(),
                0.0,
                0.7,
                &mut y,
                &mut |t, _| {
                    last_t = t;
                    count += 1;
                },
            )
            .unwrap();
        assert_eq!(last_t, 0.7);
        assert_eq!(count, solver.stats().accepted_steps);
        assert!((y[0] - 0.7f64.sin()).abs() < 1e-11);
    }

    #[test]
    fn wrong_tolerance_length_is_rejected() {
        let options = Dopri45Options {
            atol: vec![1.0; 3],
            ..Default::default()
        };
        assert!(Dopri45::new(2, options).is_err());
    }
}
