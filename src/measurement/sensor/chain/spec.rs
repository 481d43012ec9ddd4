//! The `[sensors.chain]` table: field-by-field overrides of a sensor preset.
//!
//! Every field is optional; an absent field keeps the preset's value. See the module doc
//! of [`super`] for a complete example.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::base::schema as bounds;

/// Overrides of a preset's measurement chain. Units are the channel's (m/s^2,
/// microstrain, m) unless the name says otherwise.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct ChainSpec {
    /// AC (`{ kind = "ac", highpass_hz = 0.1 }`) or DC (`{ kind = "dc" }`) coupling.
    /// Switching an AC preset to DC starts from bias 0 and no drift.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub coupling: Option<CouplingSpec>,
    /// Fixed bias (DC coupling only). Excludes `bias_sigma`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub bias: Option<f64>,
    /// Bias drawn once per sensor from `N(0, bias_sigma^2)` (DC coupling only, >= 0).
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schemars(range(min = 0))]
    pub bias_sigma: Option<f64>,
    /// Bias drift per degC away from 20 degC (DC coupling only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub bias_tempco_per_degc: Option<f64>,
    /// Fixed relative gain error, in (-1, 1). Excludes `gain_error_sigma`.
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schemars(transform = bounds::above(-1.0), transform = bounds::below(1.0))]
    pub gain_error: Option<f64>,
    /// Relative gain error drawn once per sensor from `N(0, sigma^2)`, sigma in
    /// [0, 0.2]; draws are limited to +/-4 sigma so the gain stays positive.
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schemars(range(min = 0, max = super::MAX_GAIN_ERROR_SIGMA))]
    pub gain_error_sigma: Option<f64>,
    /// White self-noise, one-sided density per sqrt(Hz), >= 0 (0 switches the self-noise
    /// off, flicker included).
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schemars(range(min = 0))]
    pub noise_density: Option<f64>,
    /// 1/f corner frequency, >= 0 (0 = white noise only).
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schemars(range(min = 0))]
    pub flicker_corner_hz: Option<f64>,
    /// Lowest frequency of the 1/f part, >= 1e-6 Hz (default 1e-3 Hz).
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schemars(range(min = super::MIN_FLICKER_LOWEST_HZ))]
    pub flicker_lowest_hz: Option<f64>,
    /// Mains hum; `{ enabled = false }` switches a preset's hum off.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub hum: Option<HumSpec>,
    /// ADC; `{ enabled = false }` records unquantised values.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub adc: Option<AdcSpec>,
}

/// Sensor coupling, tagged by `kind`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(remote = "Self", rename_all = "snake_case", deny_unknown_fields)]
#[schemars(tag = "kind")]
pub enum CouplingSpec {
    /// First-order high-pass; `highpass_hz` (> 0, < fs/2) defaults to the preset's when
    /// the preset is AC-coupled and is required otherwise.
    Ac {
        /// -3 dB corner of the high-pass (Hz), > 0 and below half the sample rate.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        #[schemars(transform = bounds::positive)]
        highpass_hz: Option<f64>,
    },
    /// Passes DC; bias and drift from the `bias*` fields or the preset.
    Dc,
}
crate::base::tagged::kind_tagged!(CouplingSpec);

/// Mains hum overrides. Absent fields keep the preset's values; where the preset has no
/// hum, `frequency_hz` defaults to 50 and `amplitude` is required.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct HumSpec {
    /// Default true; `false` switches the hum off and admits no other field.
    pub enabled: bool,
    /// Mains frequency, > 0 (50 or 60).
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schemars(transform = bounds::positive)]
    pub frequency_hz: Option<f64>,
    /// Peak amplitude before the anti-alias filter, >= 0, channel unit.
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schemars(range(min = 0))]
    pub amplitude: Option<f64>,
    /// Phase at t = 0; default drawn uniformly once per sensor.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub phase_rad: Option<f64>,
}

impl Default for HumSpec {
    fn default() -> Self {
        Self {
            enabled: true,
            frequency_hz: None,
            amplitude: None,
            phase_rad: None,
        }
    }
}

/// ADC overrides. Absent fields keep the preset's; where the preset has no ADC both are
/// required.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct AdcSpec {
    /// Default true; `false` switches the ADC off and admits no other field.
    pub enabled: bool,
    /// Resolution, 1..=32.
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schemars(range(min = 1, max = 32))]
    pub bits: Option<u32>,
    /// Full scale (> 0): codes cover `[-range, range)`, channel unit.
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schemars(transform = bounds::positive)]
    pub range: Option<f64>,
}

impl Default for AdcSpec {
    fn default() -> Self {
        Self {
            enabled: true,
            bits: None,
            range: None,
        }
    }
}
