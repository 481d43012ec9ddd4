//! Sensor self-noise.

use rand::RngExt;
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;
use serde::{Deserialize, Serialize};

use super::resample::field;
use super::SampleStage;
use crate::error::{require_non_negative, require_positive, Result};

/// White self-noise of a sensor, given as a one-sided amplitude spectral density in the
/// channel's unit per sqrt(Hz) (e.g. 22.5 ug/sqrt(Hz) = 2.2e-4 m/s^2/sqrt(Hz) for an
/// ADXL355). Default 0 (no noise).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WhiteNoise {
    /// One-sided density, unit/sqrt(Hz), >= 0.
    pub density_per_sqrt_hz: f64,
}

impl WhiteNoise {
    /// Per-sample standard deviation at sample rate `rate_hz`: `density * sqrt(rate / 2)`
    /// (white noise over `[0, rate / 2]`, docs/sensors.md section 1).
    pub fn sigma(&self, rate_hz: f64) -> f64 {
        self.density_per_sqrt_hz * (0.5 * rate_hz).sqrt()
    }

    /// Checks the density; `prefix` is the field path of the noise table.
    pub fn validate(&self, prefix: &str) -> Result<()> {
        require_non_negative(
            &field(prefix, "density_per_sqrt_hz"),
            self.density_per_sqrt_hz,
        )?;
        Ok(())
    }
}

/// Draws white Gaussian noise of a fixed per-sample sigma from its own stream.
#[derive(Debug, Clone)]
pub struct WhiteNoiseSource {
    sigma: f64,
    rng: ChaCha8Rng,
}

impl WhiteNoiseSource {
    /// Noise `noise` sampled at `rate_hz`, drawing from `rng` (see [`child_rng`]). Errors
    /// name `<field_prefix>.density_per_sqrt_hz` and `rate_hz`.
    pub fn new(
        noise: &WhiteNoise,
        rate_hz: f64,
        rng: ChaCha8Rng,
        field_prefix: &str,
    ) -> Result<Self> {
        noise.validate(field_prefix)?;
        require_positive("rate_hz", rate_hz)?;
        Ok(Self {
            sigma: noise.sigma(rate_hz),
            rng,
        })
    }

    /// Per-sample standard deviation.
    pub fn sigma(&self) -> f64 {
        self.sigma
    }

    /// One sample, `sigma * z` with `z ~ N(0, 1)` (ziggurat, `rand_distr::StandardNormal`).
    pub fn sample(&mut self) -> f64 {
        let z: f64 = self.rng.sample(StandardNormal);
        self.sigma * z
    }
}

impl SampleStage for WhiteNoiseSource {
    fn apply(&mut self, _t_ns: u64, value: f64) -> f64 {
        value + self.sample()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sigma_follows_the_one_sided_density() {
        // ADXL355, 22.5 ug/sqrt(Hz) at 250 Hz: 22.5 * sqrt(125) = 251.6 ug per sample over
        // 0..125 Hz; docs/sensors.md's ~225 ug is the part in the 0..100 Hz band,
        // 22.5 * sqrt(100).
        let n = WhiteNoise {
            density_per_sqrt_hz: 22.5e-6,
        };
        let expected = 22.5e-6 * 125f64.sqrt();
        assert!(
            (n.sigma(250.0) - expected).abs() < 1e-15,
            "{}",
            n.sigma(250.0)
        );
        assert!((n.sigma(200.0) - 22.5e-5).abs() < 1e-15);
    }

    #[test]
    fn negative_density_names_the_field() {
        let n = WhiteNoise {
            density_per_sqrt_hz: -1.0,
        };
        let e = n.validate("sensors.2.noise").unwrap_err().to_string();
        assert!(
            e.starts_with("sensors.2.noise.density_per_sqrt_hz = -1"),
            "{e}"
        );
    }
}
