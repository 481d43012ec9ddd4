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
        Dopri45::new(
            atol.len(),
            Dopri45Options {
                rtol: self.rtol,
                atol,
                max_step_s: self
                    .max_step_s
                    .min(self.step_stability_factor / modes.largest_eigenvalue),
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
