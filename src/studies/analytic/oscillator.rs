//! The linear single-degree-of-freedom oscillator in closed form, and the period
//! elongation of the Newmark average-acceleration rule.

use crate::error::{require_non_negative, require_positive, Result};

/// Ratio of the numerical to the exact period of an undamped oscillator integrated with the
/// Newmark average-acceleration rule (gamma = 1/2, beta = 1/4, the trapezoidal rule):
/// `T_num / T = (w dt / 2) / atan(w dt / 2)`, about `1 + (w dt)^2 / 12` for small steps.
///
/// Source: the rule's amplification matrix has eigenvalues `(1 + i w dt/2) / (1 - i w dt/2)`
/// of unit modulus and phase `2 atan(w dt / 2)` per step (Hughes, The Finite Element
/// Method, 2000, section 9.3; Bathe, Finite Element Procedures, 1996, section 9.4.4).
/// Returns 1 for `w dt = 0`.
pub fn newmark_average_acceleration_period_ratio(omega_rad_s: f64, dt_s: f64) -> f64 {
    let half = 0.5 * omega_rad_s * dt_s;
    if half.abs() < 1e-8 {
        // atan(x) = x - x^3/3 + ..., so x / atan(x) = 1 + x^2/3 + O(x^4).
        1.0 + half * half / 3.0
    } else {
        half / half.atan()
    }
}

/// Displacement, velocity and acceleration of an oscillator at one instant.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OscillatorState {
    /// Displacement (units of the initial displacement).
    pub displacement: f64,
    /// Velocity.
    pub velocity: f64,
    /// Acceleration.
    pub acceleration: f64,
}

/// The free oscillator `q'' + 2 zeta w q' + w^2 q = 0`, any damping ratio `zeta >= 0`
/// (under-, critically and over-damped).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DampedOscillator {
    /// Undamped circular frequency w, rad/s.
    pub omega_rad_s: f64,
    /// Damping ratio zeta (0 = undamped, 1 = critical).
    pub zeta: f64,
}

impl DampedOscillator {
    /// A validated oscillator: `omega_rad_s > 0`, `zeta >= 0`.
    pub fn new(omega_rad_s: f64, zeta: f64) -> Result<Self> {
        require_positive("omega_rad_s", omega_rad_s)?;
        require_non_negative("zeta", zeta)?;
        Ok(Self { omega_rad_s, zeta })
    }

    /// The two basis functions `(C(t), S(t))` of the free response,
    /// `q(t) = q0 (C + zeta w S) + v0 S`, `q'(t) = v0 (C - zeta w S) - w^2 q0 S`, with
    /// `S` the impulse response (`S(0) = 0, S'(0) = 1`) and `C = S' + zeta w S`:
    ///
    /// - `zeta < 1`: `C = e^(-zeta w t) cos(w_d t)`, `S = e^(-zeta w t) sin(w_d t) / w_d`,
    ///   `w_d = w sqrt(1 - zeta^2)`;
    /// - `zeta = 1`: `C = e^(-w t)`, `S = t e^(-w t)`;
    /// - `zeta > 1`: `C = e^(-zeta w t) cosh(mu t)`, `S = e^(-zeta w t) sinh(mu t) / mu`,
    ///   `mu = w sqrt(zeta^2 - 1)`
    ///
    /// (Clough & Penzien, Dynamics of Structures, section 2-5). The over-damped case is
    /// evaluated as `e^(lambda t) (1 + e^(-2 mu t)) / 2` and
    /// `e^(lambda t) (-expm1(-2 mu t)) / (2 mu)` with the slow root
    /// `lambda = -w^2 / (zeta w + mu)`: no overflow and no cancellation for any `zeta`.
    pub fn basis(&self, t_s: f64) -> (f64, f64) {
        let w = self.omega_rad_s;
        let z = self.zeta;
        if z < 1.0 {
            let wd = w * ((1.0 - z) * (1.0 + z)).sqrt();
            let decay = (-z * w * t_s).exp();
            let (s, c) = (wd * t_s).sin_cos();
            (decay * c, decay * s / wd)
        } else if z == 1.0 {
            let decay = (-w * t_s).exp();
            (decay, t_s * decay)
        } else {
            let mu = w * ((z - 1.0) * (z + 1.0)).sqrt();
            let slow = -w * w / (z * w + mu);
            let e_slow = (slow * t_s).exp();
            let ratio = (-2.0 * mu * t_s).exp();
            let c = 0.5 * e_slow * (1.0 + ratio);
            let s = e_slow * (-(-2.0 * mu * t_s).exp_m1()) / (2.0 * mu);
            (c, s)
        }
    }

    /// Exact free response at time `t_s` from displacement `q0` and velocity `v0` at t = 0
    /// (see [`DampedOscillator::basis`]). The acceleration is `-2 zeta w q' - w^2 q`.
    pub fn free_response(&self, q0: f64, v0: f64, t_s: f64) -> OscillatorState {
        let w = self.omega_rad_s;
        let zw = self.zeta * w;
        let (c, s) = self.basis(t_s);
        let displacement = q0 * (c + zw * s) + v0 * s;
        let velocity = v0 * (c - zw * s) - w * w * q0 * s;
        OscillatorState {
            displacement,
            velocity,
            acceleration: -2.0 * zw * velocity - w * w * displacement,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Central differences of the free response must satisfy the ODE; the tolerance is the
    /// O(h^2) truncation of the difference quotients plus rounding, relative.
    fn check_ode(osc: &DampedOscillator, q0: f64, v0: f64) {
        let w = osc.omega_rad_s;
        let h = 1e-4 / w;
        for i in 1..40 {
            let t = i as f64 * 0.173 / w;
            let s = osc.free_response(q0, v0, t);
            let sp = osc.free_response(q0, v0, t + h);
            let sm = osc.free_response(q0, v0, t - h);
            let vel_fd = (sp.displacement - sm.displacement) / (2.0 * h);
            let acc_fd = (sp.velocity - sm.velocity) / (2.0 * h);
            let scale = (q0.abs() * w + v0.abs()).max(1e-30);
            assert!(
                (vel_fd - s.velocity).abs() < 1e-6 * scale,
                "zeta {}",
                osc.zeta
            );
            assert!((acc_fd - s.acceleration).abs() < 1e-6 * scale * w);
        }
        let s0 = osc.free_response(q0, v0, 0.0);
        assert!((s0.displacement - q0).abs() < 1e-15 * q0.abs().max(1.0));
        assert!((s0.velocity - v0).abs() < 1e-14 * (v0.abs() + w * q0.abs()));
    }

    #[test]
    fn free_response_solves_the_ode_for_all_damping_regimes() {
        for &zeta in &[0.0, 0.02, 0.5, 0.999_999, 1.0, 1.000_001, 2.0, 50.0] {
            let osc = DampedOscillator::new(7.3, zeta).unwrap();
            check_ode(&osc, 0.01, -0.2);
        }
    }

    #[test]
    fn near_critical_damping_is_continuous() {
        let (q0, v0, t) = (1.0, 0.5, 0.8);
        let crit = DampedOscillator::new(3.0, 1.0)
            .unwrap()
            .free_response(q0, v0, t);
        for &zeta in &[1.0 - 1e-9, 1.0 + 1e-9] {
            let near = DampedOscillator::new(3.0, zeta)
                .unwrap()
                .free_response(q0, v0, t);
            assert!((near.displacement - crit.displacement).abs() < 1e-8);
            assert!((near.velocity - crit.velocity).abs() < 1e-8);
        }
    }

    #[test]
    fn undamped_response_is_harmonic() {
        let osc = DampedOscillator::new(2.0, 0.0).unwrap();
        let s = osc.free_response(1.0, 0.0, 1.3);
        assert!((s.displacement - (2.6f64).cos()).abs() < 1e-15);
    }

    #[test]
    fn heavily_overdamped_response_does_not_overflow() {
        let osc = DampedOscillator::new(1.0e5, 1.0e3).unwrap();
        let s = osc.free_response(1.0, 0.0, 10.0);
        assert!(s.displacement.is_finite() && s.displacement > 0.0 && s.displacement < 1.0);
    }

    #[test]
    fn newmark_period_elongation_matches_physics_md() {
        // docs/physics.md section 4: 0.13 % at dt/T = 0.02, 3.2 % at dt/T = 0.1.
        let w = 2.0 * std::f64::consts::PI;
        let e1 = newmark_average_acceleration_period_ratio(w, 0.02) - 1.0;
        let e2 = newmark_average_acceleration_period_ratio(w, 0.1) - 1.0;
        assert!((e1 - 0.0013).abs() < 0.00005, "{e1}");
        assert!((e2 - 0.032).abs() < 0.0005, "{e2}");
        assert_eq!(newmark_average_acceleration_period_ratio(w, 0.0), 1.0);
    }
}
