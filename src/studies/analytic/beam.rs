//! The simply supported, uniform Euler-Bernoulli beam in closed form, and modal damping.
//!
//! Deflections and loads are positive downward (see the module docs of [`crate::studies::analytic`]).

use std::f64::consts::PI;

use crate::error::{require_non_negative, require_positive, Error, Result};

/// A uniform simply supported Euler-Bernoulli beam.
///
/// Plain data; [`SimplySupportedBeam::new`] validates it, and every solver in
/// [`crate::studies::analytic`] validates again before use.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SimplySupportedBeam {
    /// Span between the supports, m.
    pub span_m: f64,
    /// Bending stiffness E I, N m^2.
    pub ei_n_m2: f64,
    /// Mass per unit length, kg/m.
    pub mass_per_length_kg_m: f64,
}

impl SimplySupportedBeam {
    /// A validated beam: all three properties must be finite and positive.
    pub fn new(span_m: f64, ei_n_m2: f64, mass_per_length_kg_m: f64) -> Result<Self> {
        let beam = Self {
            span_m,
            ei_n_m2,
            mass_per_length_kg_m,
        };
        beam.validate()?;
        Ok(beam)
    }

    /// Checks that all properties are finite and positive.
    pub fn validate(&self) -> Result<()> {
        require_positive("span_m", self.span_m)?;
        require_positive("ei_n_m2", self.ei_n_m2)?;
        require_positive("mass_per_length_kg_m", self.mass_per_length_kg_m)?;
        Ok(())
    }

    /// Circular frequency of mode `n` (1-based), rad/s:
    /// `w_n = (n pi / L)^2 sqrt(EI / m)` (Clough & Penzien, Dynamics of Structures,
    /// eq. 18-16; Fryba 1972, eq. 1.11). `n = 0` gives 0.
    pub fn omega_rad_s(&self, n: usize) -> f64 {
        let k = n as f64 * PI / self.span_m;
        k * k * (self.ei_n_m2 / self.mass_per_length_kg_m).sqrt()
    }

    /// Natural frequency of mode `n` (1-based), Hz: `f_n = n^2 pi / (2 L^2) sqrt(EI / m)`.
    pub fn natural_frequency_hz(&self, n: usize) -> f64 {
        self.omega_rad_s(n) / (2.0 * PI)
    }

    /// Mode shape `sin(n pi x / L)` (unit amplitude; zero outside `[0, L]`).
    pub fn mode_shape(&self, n: usize, x_m: f64) -> f64 {
        if (0.0..=self.span_m).contains(&x_m) {
            (n as f64 * PI * x_m / self.span_m).sin()
        } else {
            0.0
        }
    }

    /// Modal mass of every mode shape `sin(n pi x / L)`: `m L / 2`, kg.
    pub fn modal_mass_kg(&self) -> f64 {
        0.5 * self.mass_per_length_kg_m * self.span_m
    }

    /// Static midspan deflection under a point force at midspan: `P L^3 / (48 EI)`, m.
    pub fn static_midspan_deflection_m(&self, force_n: f64) -> f64 {
        force_n * self.span_m.powi(3) / (48.0 * self.ei_n_m2)
    }

    /// Static deflection at `x_m` under a point force `force_n` at `load_position_m`, m.
    ///
    /// With `a` the load position and `b = L - a`:
    /// `x <= a: P b x (L^2 - b^2 - x^2) / (6 EI L)`,
    /// `x >= a: P a (L - x) (2 L x - x^2 - a^2) / (6 EI L)`
    /// (Gere & Timoshenko, Mechanics of Materials, Appendix G, case 5). Zero when either
    /// point lies outside the span.
    pub fn static_deflection_m(&self, x_m: f64, load_position_m: f64, force_n: f64) -> f64 {
        let l = self.span_m;
        if !(0.0..=l).contains(&x_m) || !(0.0..=l).contains(&load_position_m) {
            return 0.0;
        }
        let a = load_position_m;
        let b = l - a;
        let scale = force_n / (6.0 * self.ei_n_m2 * l);
        if x_m <= a {
            scale * b * x_m * (l * l - b * b - x_m * x_m)
        } else {
            scale * a * (l - x_m) * (2.0 * l * x_m - x_m * x_m - a * a)
        }
    }
}

/// Damping ratio of each beam mode.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum ModalDamping {
    /// Undamped.
    #[default]
    None,
    /// The same damping ratio on every mode.
    Constant(f64),
    /// Rayleigh damping `C = a0 M + a1 K`: `zeta_n = a0 / (2 w_n) + a1 w_n / 2`
    /// (Clough & Penzien, eq. 12-37). Over-damps the high modes.
    Rayleigh {
        /// Mass-proportional coefficient, 1/s.
        a0: f64,
        /// Stiffness-proportional coefficient, s.
        a1: f64,
    },
}

impl ModalDamping {
    /// Rayleigh coefficients giving `zeta` at the two circular frequencies `w1`, `w2`:
    /// `a0 = 2 zeta w1 w2 / (w1 + w2)`, `a1 = 2 zeta / (w1 + w2)`.
    pub fn rayleigh_from_two_modes(zeta: f64, omega1_rad_s: f64, omega2_rad_s: f64) -> Self {
        let sum = omega1_rad_s + omega2_rad_s;
        ModalDamping::Rayleigh {
            a0: 2.0 * zeta * omega1_rad_s * omega2_rad_s / sum,
            a1: 2.0 * zeta / sum,
        }
    }

    /// Damping ratio of a mode of circular frequency `omega_rad_s`.
    pub fn zeta(&self, omega_rad_s: f64) -> f64 {
        match *self {
            ModalDamping::None => 0.0,
            ModalDamping::Constant(zeta) => zeta,
            ModalDamping::Rayleigh { a0, a1 } => 0.5 * a0 / omega_rad_s + 0.5 * a1 * omega_rad_s,
        }
    }

    /// Checks that the coefficients are finite and non-negative.
    pub fn validate(&self) -> Result<()> {
        match *self {
            ModalDamping::None => Ok(()),
            ModalDamping::Constant(zeta) => require_non_negative("damping.zeta", zeta).map(|_| ()),
            ModalDamping::Rayleigh { a0, a1 } => {
                require_non_negative("damping.a0", a0)?;
                require_non_negative("damping.a1", a1)?;
                Ok(())
            }
        }
    }
}

/// Checks a mode count: at least one mode, at most `max`.
pub(crate) fn require_mode_count(field: &str, n_modes: usize, max: usize) -> Result<usize> {
    if (1..=max).contains(&n_modes) {
        Ok(n_modes)
    } else {
        Err(Error::invalid(
            field,
            n_modes,
            format!("must be in 1..={max}"),
        ))
    }
}

/// Fills `sin_out[i] = sin((i + 1) theta)` and `cos_out[i] = cos((i + 1) theta)` by the
/// Chebyshev recurrence `s_{n+1} = 2 cos(theta) s_n - s_{n-1}`: one sine and one cosine
/// call for all harmonics. Rounding grows about linearly with `n`, so a few hundred
/// harmonics keep ~1e-13 absolute accuracy.
pub(crate) fn harmonics(theta: f64, sin_out: &mut [f64], cos_out: &mut [f64]) {
    let (s1, c1) = theta.sin_cos();
    let two_c = 2.0 * c1;
    let (mut s_prev, mut c_prev) = (0.0, 1.0);
    let (mut s, mut c) = (s1, c1);
    for (so, co) in sin_out.iter_mut().zip(cos_out.iter_mut()) {
        *so = s;
        *co = c;
        let s_next = two_c * s - s_prev;
        let c_next = two_c * c - c_prev;
        s_prev = s;
        c_prev = c;
        s = s_next;
        c = c_next;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn paper_beam() -> SimplySupportedBeam {
        SimplySupportedBeam::new(30.0, 5.629e10, 12_000.0).unwrap()
    }

    #[test]
    fn frequencies_match_physics_md() {
        let beam = paper_beam();
        // docs/physics.md section 1 prints f1..f3 = 3.780, 15.12, 34.02 Hz to 4 digits.
        assert!((beam.natural_frequency_hz(1) - 3.780).abs() < 5e-4);
        assert!((beam.natural_frequency_hz(2) - 15.12).abs() < 5e-3);
        assert!((beam.natural_frequency_hz(3) - 34.02).abs() < 5e-3);
    }

    #[test]
    fn static_deflection_is_symmetric_and_matches_midspan_formula() {
        let beam = paper_beam();
        let p = 1.0e5;
        let mid = beam.static_midspan_deflection_m(p);
        assert!((beam.static_deflection_m(15.0, 15.0, p) - mid).abs() < 1e-15);
        // Maxwell-Betti reciprocity: deflection at x under load at a equals the reverse.
        for &(x, a) in &[(3.0, 21.0), (12.5, 4.0), (29.0, 1.0)] {
            let d1 = beam.static_deflection_m(x, a, p);
            let d2 = beam.static_deflection_m(a, x, p);
            assert!((d1 - d2).abs() < 1e-12 * d1.abs().max(1e-30));
        }
        // The modal series sum 2 P / (m L w_n^2) sin(n pi x/L) sin(n pi a/L) is the same
        // static deflection (Fourier expansion of the Green's function).
        let (x, a) = (7.0, 19.0);
        let series: f64 = (1..2000)
            .map(|n| {
                2.0 * p / (beam.mass_per_length_kg_m * beam.span_m * beam.omega_rad_s(n).powi(2))
                    * beam.mode_shape(n, x)
                    * beam.mode_shape(n, a)
            })
            .sum();
        let exact = beam.static_deflection_m(x, a, p);
        assert!((series - exact).abs() < 1e-9 * exact);
    }

    #[test]
    fn rayleigh_hits_target_damping_at_both_frequencies() {
        let damping = ModalDamping::rayleigh_from_two_modes(0.02, 23.75, 95.0);
        assert!((damping.zeta(23.75) - 0.02).abs() < 1e-15);
        assert!((damping.zeta(95.0) - 0.02).abs() < 1e-15);
        assert!(damping.zeta(50.0) < 0.02);
    }

    #[test]
    fn harmonics_recurrence_matches_direct_evaluation() {
        let mut s = vec![0.0; 300];
        let mut c = vec![0.0; 300];
        let theta = 0.123_456_789;
        harmonics(theta, &mut s, &mut c);
        for (i, (si, ci)) in s.iter().zip(&c).enumerate() {
            let arg = (i + 1) as f64 * theta;
            assert!((si - arg.sin()).abs() < 1e-12);
            assert!((ci - arg.cos()).abs() < 1e-12);
        }
    }

    #[test]
    fn invalid_beam_is_rejected() {
        assert!(SimplySupportedBeam::new(0.0, 1.0, 1.0).is_err());
        assert!(SimplySupportedBeam::new(1.0, f64::NAN, 1.0).is_err());
        assert!(ModalDamping::Constant(-0.1).validate().is_err());
    }
}
