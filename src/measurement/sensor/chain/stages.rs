//! The analog stages of the chain, applied at the output rate (see the module doc of
//! [`super`] for why that is equivalent).

use std::f64::consts::PI;
use std::fmt;
use std::sync::Arc;

use super::flicker::FlickerNoise;
use super::preset::REFERENCE_TEMPERATURE_DEGC;
use crate::measurement::sensor::{SampleStage, WhiteNoiseSource};

/// Temperature of the sensor in degC at an instant in ns since the run start.
pub type TemperatureFn = Arc<dyn Fn(u64) -> f64 + Send + Sync>;

/// First-order high-pass `H(s) = s / (s + wc)` discretised by the bilinear transform
/// with the cutoff pre-warped, `k = tan(pi fc / fs)`:
/// `H(z) = (1 - z^-1) / (1 + k) / (1 - (1 - k)/(1 + k) z^-1)`
/// (Oppenheim & Schafer, Discrete-Time Signal Processing, 3rd ed., sec. 7.2.3). The
/// pre-warp puts the -3 dB point (|H| = 1/sqrt 2) exactly at `fc`; the transform maps
/// DC to a zero, so a constant input gives no output.
#[derive(Debug, Clone)]
pub struct HighPass {
    b0: f64,
    a1: f64,
    previous_input: Option<f64>,
    previous_output: f64,
}

impl HighPass {
    /// Cutoff `highpass_hz` at sample rate `rate_hz`, `0 < highpass_hz < rate_hz / 2`
    /// (checked by the caller).
    pub fn new(highpass_hz: f64, rate_hz: f64) -> Self {
        let k = (PI * highpass_hz / rate_hz).tan();
        Self {
            b0: 1.0 / (1.0 + k),
            a1: (1.0 - k) / (1.0 + k),
            previous_input: None,
            previous_output: 0.0,
        }
    }

    /// `|H(e^{j 2 pi f / fs})|` of the discrete filter, closed form:
    /// `|sin(w/2)| / sqrt(sin^2(w/2) + k^2 cos^2(w/2))` with `w = 2 pi f / fs`.
    pub fn magnitude(highpass_hz: f64, rate_hz: f64, f_hz: f64) -> f64 {
        let k = (PI * highpass_hz / rate_hz).tan();
        let (s, c) = (PI * f_hz / rate_hz).sin_cos();
        s.abs() / (s * s + k * k * c * c).sqrt()
    }
}

impl SampleStage for HighPass {
    /// The first sample primes the state as if the input had been at that value forever
    /// (the sensor was powered long before the run), so the record starts without a step
    /// transient.
    fn apply(&mut self, _t_ns: u64, value: f64) -> f64 {
        let previous_input = *self.previous_input.get_or_insert(value);
        let y = self.b0 * (value - previous_input) + self.a1 * self.previous_output;
        self.previous_input = Some(value);
        self.previous_output = y;
        y
    }
}

/// DC coupling: adds `bias + tempco (T(t) - 20 degC)`.
#[derive(Clone)]
pub struct DcOffset {
    bias: f64,
    tempco_per_degc: f64,
    temperature_degc: TemperatureFn,
}

impl DcOffset {
    pub fn new(bias: f64, tempco_per_degc: f64, temperature_degc: TemperatureFn) -> Self {
        Self {
            bias,
            tempco_per_degc,
            temperature_degc,
        }
    }
}

impl fmt::Debug for DcOffset {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("DcOffset")
            .field("bias", &self.bias)
            .field("tempco_per_degc", &self.tempco_per_degc)
            .finish_non_exhaustive()
    }
}

impl SampleStage for DcOffset {
    fn apply(&mut self, t_ns: u64, value: f64) -> f64 {
        let drift = if self.tempco_per_degc == 0.0 {
            0.0
        } else {
            self.tempco_per_degc * ((self.temperature_degc)(t_ns) - REFERENCE_TEMPERATURE_DEGC)
        };
        value + self.bias + drift
    }
}

/// Gain (sensitivity) error: multiplies by `1 + gain_error`.
#[derive(Debug, Clone)]
pub struct Gain {
    factor: f64,
}

impl Gain {
    pub fn new(gain_error: f64) -> Self {
        Self {
            factor: 1.0 + gain_error,
        }
    }
}

impl SampleStage for Gain {
    fn apply(&mut self, _t_ns: u64, value: f64) -> f64 {
        value * self.factor
    }
}

/// Self-noise: white (per-sample sigma `ND sqrt(fs / 2)`) plus optional 1/f, each from
/// its own random stream, so switching the 1/f part on or off leaves the white samples
/// unchanged.
#[derive(Debug, Clone)]
pub struct SelfNoise {
    white: WhiteNoiseSource,
    flicker: Option<FlickerNoise>,
}

impl SelfNoise {
    pub fn new(white: WhiteNoiseSource, flicker: Option<FlickerNoise>) -> Self {
        Self { white, flicker }
    }
}

impl SampleStage for SelfNoise {
    fn apply(&mut self, _t_ns: u64, value: f64) -> f64 {
        let flicker = self.flicker.as_mut().map_or(0.0, FlickerNoise::sample);
        value + self.white.sample() + flicker
    }
}

/// Mains hum `amplitude sin(2 pi f t + phase)`, with `amplitude` already scaled by the
/// anti-alias filter's gain at `f`. Sampled at the output instants it aliases exactly as
/// the filter's residual at `f` would.
#[derive(Debug, Clone, PartialEq)]
pub struct Hum {
    frequency_hz: f64,
    amplitude: f64,
    phase_rad: f64,
}

impl Hum {
    pub fn new(frequency_hz: f64, amplitude: f64, phase_rad: f64) -> Self {
        Self {
            frequency_hz,
            amplitude,
            phase_rad,
        }
    }
}

impl SampleStage for Hum {
    fn apply(&mut self, t_ns: u64, value: f64) -> f64 {
        // Whole cycles dropped before the sine: after a day at 60 Hz the phase argument
        // would be ~3e7 rad; the fraction keeps it within 2 pi (error ~1e-9 cycle).
        let cycles = (self.frequency_hz * (t_ns as f64 * 1e-9)).fract();
        value + self.amplitude * (2.0 * PI * cycles + self.phase_rad).sin()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn high_pass_blocks_dc_from_the_first_sample() {
        let mut hp = HighPass::new(0.1, 100.0);
        for i in 0..1000 {
            assert_eq!(hp.apply(i, 3.5), 0.0);
        }
    }

    #[test]
    fn high_pass_step_response_decays_with_the_time_constant() {
        // Analog step response exp(-t wc); the bilinear transform matches it to O((wc
        // dt)^2) per time constant: at fc = 0.1 Hz, fs = 1 kHz, wc dt = 6e-4, so 1e-5
        // relative is ample.
        let (fc, fs) = (0.1, 1000.0);
        let mut hp = HighPass::new(fc, fs);
        hp.apply(0, 0.0);
        let n = 1591; // ~ one time constant, 1/(2 pi 0.1) = 1.5915 s
        let mut y = 0.0;
        for i in 1..=n {
            y = hp.apply(i, 1.0);
        }
        let expected = (-2.0 * PI * fc * (n as f64 - 0.5) / fs).exp();
        assert!((y / expected - 1.0).abs() < 1e-5, "{y} vs {expected}");
    }

    #[test]
    fn dc_offset_follows_the_temperature() {
        let temperature: TemperatureFn = Arc::new(|t_ns| 20.0 + 1e-9 * t_ns as f64);
        let mut dc = DcOffset::new(0.5, 0.25, temperature);
        // At t = 8 s the sensor is at 28 degC: 0.5 + 0.25 * 8 = 2.5 (exact in binary).
        assert_eq!(dc.apply(8_000_000_000, 1.0), 3.5);
        assert_eq!(dc.apply(0, 1.0), 1.5);
    }
}
