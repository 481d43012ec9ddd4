//! What the modal crossings ([`super::sprung_mass`], [`super::moving_mass`]) share: their
//! settings, the checks of the settings and sample times, the beam's modal coefficients,
//! and the Dormand-Prince set-up with its stability cap (the reason for the cap is in the
//! module docs of [`super::sprung_mass`]).

use std::fmt;
use std::marker::PhantomData;

use super::beam::{require_mode_count, ModalDamping, SimplySupportedBeam};
use super::dopri45::{Dopri45, Dopri45Options};
use crate::error::{require_non_negative, require_positive, Error, Result};

/// Largest mode count accepted (cost grows as N^3: steps ~ w_N ~ N^2, work per step ~ N).
pub const MAX_MODES: usize = 400;

/// The defaults in which the crossings' settings differ.
pub trait CrossingDefaults {
    /// Default number of beam modes.
    const N_MODES: usize;
    /// Default largest integration step, s.
    const MAX_STEP_S: f64;
}

/// Model and integration settings of the crossing `P` (`SprungMassOptions`,
/// `MovingMassOptions`); the defaults are `P`'s [`CrossingDefaults`] and the common ones
/// given at each field.
pub struct CrossingOptions<P> {
    /// Number of beam modes (default: `P::N_MODES`).
    pub n_modes: usize,
    /// Modal damping of the beam. Default none.
    pub damping: ModalDamping,
    /// Gravitational acceleration, m/s^2. Default 9.81.
    pub gravity_m_s2: f64,
    /// Relative tolerance of the integrator. Default 1e-9.
    pub rtol: f64,
    /// Absolute tolerance on modal (and vehicle) displacements, m. Default 1e-12.
    pub atol_displacement_m: f64,
    /// Absolute tolerance on modal (and vehicle) velocities, m/s. Default 1e-9.
    pub atol_velocity_m_s: f64,
    /// Largest integration step, s (default: `P::MAX_STEP_S`); the step is always also
    /// capped at `step_stability_factor / |lambda|_max` of the beam modes.
    pub max_step_s: f64,
    /// Step cap as a fraction `y = |lambda|_max h` of the top modal eigenvalue, in
    /// `(0, 0.95]`. The method damps a mode at `y` by ~`y^6 / 10 700` per step. Default 0.5
    /// (top mode: 1.5e-6 per step; peaks converged to ~1e-8).
    pub step_stability_factor: f64,
    /// Which crossing these settings are for (no data).
    pub problem: PhantomData<fn() -> P>,
}

impl<P: CrossingDefaults> Default for CrossingOptions<P> {
    fn default() -> Self {
        Self {
            n_modes: P::N_MODES,
            damping: ModalDamping::None,
            gravity_m_s2: 9.81,
            rtol: 1e-9,
            atol_displacement_m: 1e-12,
            atol_velocity_m_s: 1e-9,
            max_step_s: P::MAX_STEP_S,
            step_stability_factor: 0.5,
            problem: PhantomData,
        }
    }
}

// By hand rather than derived: a derive would require `P` (the problem) to be `Clone`,
// `PartialEq` and `Debug` too, though the settings hold none of it.
impl<P> Clone for CrossingOptions<P> {
    fn clone(&self) -> Self {
        Self {
            problem: PhantomData,
            ..*self
        }
    }
}

impl<P> PartialEq for CrossingOptions<P> {
    fn eq(&self, other: &Self) -> bool {
        self.n_modes == other.n_modes
            && self.damping == other.damping
            && self.gravity_m_s2 == other.gravity_m_s2
            && self.rtol == other.rtol
            && self.atol_displacement_m == other.atol_displacement_m
            && self.atol_velocity_m_s == other.atol_velocity_m_s
            && self.max_step_s == other.max_step_s
            && self.step_stability_factor == other.step_stability_factor
    }
}

impl<P> fmt::Debug for CrossingOptions<P> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("CrossingOptions")
            .field("n_modes", &self.n_modes)
            .field("damping", &self.damping)
            .field("gravity_m_s2", &self.gravity_m_s2)
            .field("rtol", &self.rtol)
            .field("atol_displacement_m", &self.atol_displacement_m)
            .field("atol_velocity_m_s", &self.atol_velocity_m_s)
            .field("max_step_s", &self.max_step_s)
            .field("step_stability_factor", &self.step_stability_factor)
            .finish()
    }
}

impl<P> CrossingOptions<P> {
    /// Checks every setting; errors name `options.<field>`.
    pub fn validate(&self) -> Result<()> {
        require_mode_count("options.n_modes", self.n_modes, MAX_MODES)?;
        self.damping.validate()?;
        require_non_negative("options.gravity_m_s2", self.gravity_m_s2)?;
        require_positive("options.rtol", self.rtol)?;
        require_positive("options.atol_displacement_m", self.atol_displacement_m)?;
        require_positive("options.atol_velocity_m_s", self.atol_velocity_m_s)?;
        if !(self.step_stability_factor > 0.0 && self.step_stability_factor <= 0.95) {
            return Err(Error::invalid(
                "options.step_stability_factor",
                self.step_stability_factor,
                "must be in (0, 0.95]",
            ));
        }
        if self.max_step_s.is_nan() || self.max_step_s <= 0.0 {
            return Err(Error::invalid(
                "options.max_step_s",
                self.max_step_s,
                "must be > 0",
            ));
        }
        Ok(())
    }

    /// The integrator on `atol` (one entry per state), its step capped at `max_step_s`
    /// and at `step_stability_factor / |lambda|_max` of `modes`.
    pub(crate) fn integrator(&self, modes: &BeamModes, atol: Vec<f64>) -> Result<Dopri45> {
        self.integrator_covering(modes, 0.0, atol)
    }

    /// As [`Self::integrator`], with the cap also covering `other_eigenvalue` (1/s): the
    /// fastest mode of what rides on the beam, when it could be faster than the beam's top
    /// mode.
    pub(crate) fn integrator_covering(
        &self,
        modes: &BeamModes,
        other_eigenvalue: f64,
        atol: Vec<f64>,
    ) -> Result<Dopri45> {
        let fastest = modes.largest_eigenvalue.max(other_eigenvalue);
        Dopri45::new(
            atol.len(),
            Dopri45Options {
                rtol: self.rtol,
                atol,
                max_step_s: self.max_step_s.min(self.step_stability_factor / fastest),
                ..Default::default()
            },
        )
    }
}

/// Checks sample times: finite, >= 0 and not decreasing; errors name `sample_times_s[i]`.
pub(crate) fn validate_sample_times(sample_times_s: &[f64]) -> Result<()> {
    for (i, &t) in sample_times_s.iter().enumerate() {
        if !(t.is_finite() && t >= 0.0) {
            return Err(Error::invalid(
                format!("sample_times_s[{i}]"),
                t,
                "must be finite and >= 0",
            ));
        }
        if i > 0 && t < sample_times_s[i - 1] {
            return Err(Error::invalid(
                format!("sample_times_s[{i}]"),
                t,
                "must not decrease",
            ));
        }
    }
    Ok(())
}

/// The first `n` modes of a beam as the crossings' ODEs use them.
pub(crate) struct BeamModes {
    pub n: usize,
    /// `pi / L`, 1/m: mode j's shape is `sin((j + 1) pi x / L)`.
    pub wavenumber_per_m: f64,
    pub omega_sq: Vec<f64>,
    pub two_zeta_omega: Vec<f64>,
    /// Mode shapes at midspan.
    pub midspan_shape: Vec<f64>,
    /// `m L / 2`, kg.
    pub modal_mass_kg: f64,
    /// Largest modal eigenvalue magnitude, 1/s: `w` for under-damped modes, the fast root
    /// `zeta w + w sqrt(zeta^2 - 1)` for over-damped ones.
    pub largest_eigenvalue: f64,
}

impl BeamModes {
    pub fn new(beam: &SimplySupportedBeam, n: usize, damping: &ModalDamping) -> Self {
        let omega: Vec<f64> = (1..=n).map(|j| beam.omega_rad_s(j)).collect();
        let largest_eigenvalue = omega
            .iter()
            .map(|&w| {
                let zeta = damping.zeta(w);
                if zeta <= 1.0 {
                    w
                } else {
                    w * (zeta + ((zeta - 1.0) * (zeta + 1.0)).sqrt())
                }
            })
            .fold(0.0, f64::max);
        BeamModes {
            n,
            wavenumber_per_m: std::f64::consts::PI / beam.span_m,
            omega_sq: omega.iter().map(|w| w * w).collect(),
            two_zeta_omega: omega.iter().map(|&w| 2.0 * damping.zeta(w) * w).collect(),
            midspan_shape: (1..=n)
                .map(|j| beam.mode_shape(j, 0.5 * beam.span_m))
                .collect(),
            modal_mass_kg: beam.modal_mass_kg(),
            largest_eigenvalue,
        }
    }

    /// Midspan deflection of the modal displacements `q` (the first `n` states).
    pub fn midspan(&self, q: &[f64]) -> f64 {
        q[..self.n]
            .iter()
            .zip(&self.midspan_shape)
            .map(|(q, s)| q * s)
            .sum()
    }
}

/// What [`midspan_truncation_bound_m`] needs to know about one load crossing the beam (a
/// wheel or a sprung mass), from a solution with the modes kept.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactTail {
    /// Largest |downward contact force| while the load is on the beam plus the sum of the
    /// |jumps| of that force on the beam (a dashpot crossing a kink of the road), N.
    pub force_bound_n: f64,
    /// Spring between the contact point and the vehicle above it (tyre, or the suspension
    /// of a sprung mass), N/m.
    pub stiffness_n_m: f64,
    /// Dashpot in parallel with it, N s/m.
    pub damping_n_s_m: f64,
}

/// Bound on the mode-truncation error of the midspan deflection of an `n_modes` crossing
/// (m), at any instant while the loads are on the beam. `f64::INFINITY` when `n_modes`
/// is too small for the bound (the first missing mode not well above its forcing).
///
/// # Derivation
///
/// With `gamma = 2 / (m L)`, mode `n` obeys
/// `q_n'' + 2 zeta_n w_n q_n' + w_n^2 q_n = gamma sum_j F_j(t) sin(n pi x_j(t) / L)`,
/// `w_n = n^2 w_1`, and midspan sees `sum_n q_n sin(n pi / 2)`: the odd modes, each with
/// a weight of magnitude one. Cutting the series after `N` modes misses (a) the modes
/// above `N` and (b) the change those modes cause in the contact forces, which the kept
/// modes then respond to.
///
/// (a) Load `j` drives mode `n` at `Omega_n = n pi v / L`. A constant force started from
/// rest gives the undamped `q = gamma F / (w_n^2 - Omega_n^2) (sin Omega_n t - (Omega_n /
/// w_n) sin w_n t)`, at most `gamma F / (w_n^2 (1 - Omega_n / w_n))`. A force that varies
/// at frequencies up to `w_c` moves the forcing to at most `Omega_n + w_c`; while that is
/// below `w_n` the mode still follows quasi-statically with the same kind of
/// amplification, and each jump `dF` of a force adds a free vibration of at most
/// `gamma |dF| / w_n^2` (damping only shrinks both). So `|q_n| <= gamma sum_j F^_j /
/// (w_n^2 (1 - rho_n))` with `rho_n = (Omega_n + w_c) / w_n` and `F^_j` =
/// [`ContactTail::force_bound_n`], and
/// `e_a <= gamma sum_j F^_j sum_{n > N, odd} 1 / (w_n^2 (1 - rho_n))`.
///
/// (b) The missing modes move each contact point by at most
/// `du = gamma sum F^ sum_{n > N} 1 / (w_n^2 (1 - rho_n))` (every mode), and their
/// quasi-static part `gamma F sin(Omega_n (t - t_i)) sin(n pi x_j / L) / w_n^2` moves at a
/// rate of at most `2 Omega_n` times its size, so
/// `du' <= gamma sum F^ sum_{n > N} 2 Omega_n / (w_n^2 (1 - rho_n))`. A spring `k_j` and
/// dashpot `c_j` turn that into a force change of at most `k_j du + c_j du'` (the vehicle
/// mass above follows these small motions only partly, which can only reduce it), and
/// the kept modes carry a force change to midspan by at most `D L^3 / (48 EI)` per newton
/// with `D = 2`, the largest amplification of a suddenly applied force on an undamped
/// oscillator: `e_b <= 2 L^3 / (48 EI) sum_j (k_j du + c_j du')`. The free vibrations of
/// the missing modes (from the entry and from force jumps) oscillate at `w_n > w_N`, where
/// the kept modes respond only by `gamma dF / w_n^2`, the order of (a) times
/// `k / (m L w_n^2)`: left out.
///
/// The bound is `e_a + e_b`. Its sums are taken term by term up to `n = 50 N + 2000`, and
/// the rest by the integral bound `sum_{n > M} n^-p <= M^(1 - p) / (p - 1)`.
/// `force_frequency_rad_s` is `w_c`: the fastest frequency at which the contact forces
/// vary (vehicle modes, the first beam modes). Tested against crossings with more modes in
/// `tests/suite/analytic_references.rs`.
pub fn midspan_truncation_bound_m(
    beam: &SimplySupportedBeam,
    n_modes: usize,
    speed_m_s: f64,
    force_frequency_rad_s: f64,
    contacts: &[ContactTail],
) -> f64 {
    let w1 = beam.omega_rad_s(1);
    let omega1 = std::f64::consts::PI * speed_m_s / beam.span_m;
    let rho = |n: f64| (n * omega1 + force_frequency_rad_s) / (n * n * w1);
    let first = n_modes as f64 + 1.0;
    if rho(first) >= 1.0 {
        return f64::INFINITY;
    }
    let last = 50 * n_modes + 2000;
    // Sums over the missing modes of 1 / (n^4 (1 - rho_n)) (odd n, every n) and of
    // 1 / (n^3 (1 - rho_n)) (every n); w_n^2 = n^4 w1^2 is taken out.
    let (mut odd4, mut all4, mut all3) = (0.0, 0.0, 0.0);
    for n in (n_modes + 1)..=last {
        let nf = n as f64;
        let amplification = 1.0 / (1.0 - rho(nf));
        let t4 = amplification / nf.powi(4);
        all4 += t4;
        all3 += amplification / nf.powi(3);
        if n % 2 == 1 {
            odd4 += t4;
        }
    }
    let m = last as f64;
    let tail_amplification = 1.0 / (1.0 - rho(m));
    odd4 += tail_amplification / (3.0 * m.powi(3));
    all4 += tail_amplification / (3.0 * m.powi(3));
    all3 += tail_amplification / (2.0 * m.powi(2));

    let gamma_over_w1_sq = 2.0 / (beam.mass_per_length_kg_m * beam.span_m * w1 * w1);
    let total_force_n: f64 = contacts.iter().map(|c| c.force_bound_n.abs()).sum();
    let direct_m = gamma_over_w1_sq * total_force_n * odd4;
    let contact_shift_m = gamma_over_w1_sq * total_force_n * all4;
    let contact_rate_m_s = gamma_over_w1_sq * total_force_n * 2.0 * omega1 * all3;
    let force_change_n: f64 = contacts
        .iter()
        .map(|c| c.stiffness_n_m * contact_shift_m + c.damping_n_s_m * contact_rate_m_s)
        .sum();
    let feedback_m = 2.0 * beam.static_midspan_deflection_m(force_change_n);
    direct_m + feedback_m
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::studies::analytic::MovingForceSolution;

    /// Part (a) alone (a constant force: no spring, no dashpot) against Fryba's closed
    /// form with 2 000 modes: the bound holds at every mode count and speed, and it is
    /// tight where the peak comes with the force near midspan, where every missing odd
    /// mode adds with the same sign.
    #[test]
    fn truncation_bound_holds_for_a_moving_force() {
        let beam = SimplySupportedBeam::new(25.0, 3.5e10 * 1.3901, 18_358.0).unwrap();
        let force_n = 5.64e4;
        for speed in [5.0, 25.0, 60.0] {
            let fine =
                MovingForceSolution::new(beam, force_n, speed, ModalDamping::None, 2000).unwrap();
            let exit_s = fine.exit_time_s();
            let (_, reference) = fine.peak_deflection_m(12.5, exit_s);
            for n in [3, 6, 12, 25, 50] {
                let coarse =
                    MovingForceSolution::new(beam, force_n, speed, ModalDamping::None, n).unwrap();
                let (_, peak) = coarse.peak_deflection_m(12.5, exit_s);
                let bound = midspan_truncation_bound_m(
                    &beam,
                    n,
                    speed,
                    0.0,
                    &[ContactTail {
                        force_bound_n: force_n,
                        stiffness_n_m: 0.0,
                        damping_n_s_m: 0.0,
                    }],
                );
                let error = (peak - reference).abs();
                println!(
                    "v {speed} m/s, {n} modes: peak error {:.3e}, bound {:.3e} (ratio {:.2})",
                    error / reference,
                    bound / reference,
                    bound / error
                );
                assert!(error <= bound, "v {speed}, {n} modes: {error} > {bound}");
            }
        }
    }

    /// Too few modes for the missing ones to follow quasi-statically: no bound.
    #[test]
    fn truncation_bound_refuses_a_mode_below_its_forcing() {
        let beam = SimplySupportedBeam::new(25.0, 3.5e10 * 1.3901, 18_358.0).unwrap();
        let contact = ContactTail {
            force_bound_n: 1.0,
            stiffness_n_m: 0.0,
            damping_n_s_m: 0.0,
        };
        // Mode 2 at 103 rad/s against a contact force varying at 200 rad/s.
        let bound = midspan_truncation_bound_m(&beam, 1, 25.0, 200.0, &[contact]);
        assert_eq!(bound, f64::INFINITY);
    }
}
