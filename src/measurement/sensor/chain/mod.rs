//! Measurement-chain stages and sensor presets (docs/sensors.md section 2).
//!
//! A sensor's chain, after the true response (in this order):
//!
//! ```text
//! transfer function -> gain error -> self-noise -> mains hum -> ADC
//! (AC high-pass, or    (1 + e)       white + 1/f    sin, scaled    quantise,
//!  DC bias + drift)                                 by AA gain     clip, count
//! ```
//!
//! A [`SensorPreset`] gives datasheet-class values per sensor type; a [`ChainSpec`]
//! (`[sensors.chain]`) overrides them field by field and switches stages on or off;
//! [`resolve`] merges and validates both into a [`ResolvedChain`], whose
//! [`ResolvedChain::realise`] draws one sensor's values into a [`RealisedChain`],
//! whose [`RealisedChain::stages`] builds the [`SampleStage`](crate::measurement::sensor::SampleStage)s to
//! append to the sensor's channel.
//!
//! # Why the analog stages run at the output rate
//!
//! Physically the chain sits before the anti-alias filter. The transfer function and the
//! gain are linear and time-invariant, so they commute with the filter; their responses
//! are evaluated at the output rate, which matches the analog ones in the pass band (the
//! high-pass is pre-warped to its exact -3 dB point). The self-noise is additive and is
//! generated directly with the band-limited PSD the filter would leave (white and 1/f up
//! to fs_out/2). The hum is additive and deterministic: its amplitude is multiplied by
//! the filter's gain at its frequency, and sampled at the output instants it aliases as
//! the filter's residual would. This costs a few operations per output sample instead of
//! per solver step. Not modelled: sensors' own low-pass (ADXL355 ODR/4, piezo 450 Hz,
//! EpiSensor 200 Hz); the channel's anti-alias filter is the only low-pass.
//!
//! # Random streams
//!
//! Every random value comes from `rng_for(name)`, one ChaCha8 stream per stage
//! (`"bias"`, `"gain"`, `"noise"`, `"flicker"`, `"hum"`), so switching one stage on or off
//! never changes another's numbers and the same seed gives the same bytes.
//!
//! # Scenario shape
//!
//! ```toml
//! [[sensors]]
//! id = "A3"
//! kind = "accelerometer"
//! preset = "mems_lownoise"      # ideal, mems_lownoise, piezo_seismic, force_balance,
//!                               # mems_consumer (accelerometers), strain_foil (strain)
//! rate_hz = 200
//!
//! [sensors.chain]                          # every field optional: the preset's value
//! coupling = { kind = "ac", highpass_hz = 0.1 }   # or { kind = "dc" }
//! bias_tempco_per_degc = 0.0               # DC only; also bias = .. or bias_sigma = ..
//! gain_error_sigma = 0.02                  # drawn per sensor; or gain_error = 0.01 fixed
//! noise_density = 2.2e-4                   # m/s^2/sqrt(Hz); 0 = no self-noise
//! flicker_corner_hz = 0.1                  # 0 = white only
//! flicker_lowest_hz = 1e-3
//! hum = { frequency_hz = 50, amplitude = 1e-3 }   # or hum = { enabled = false }
//! adc = { bits = 24, range = 19.6 }        # or adc = { enabled = false }
//! ```
//!
//! Units are the channel's: m/s^2 for accelerometers, microstrain for strain, m for
//! displacement. Errors name the full field, e.g.
//! `sensors.3.chain.noise_density = -1 must be a finite number >= 0`.

mod adc;
mod flicker;
mod preset;
mod resolve;
mod spec;
mod stages;

pub use adc::{ClipCounter, Quantiser};
pub use flicker::{
    bank_psd, design_bank, ArSection, FlickerNoise, DESIGN_RIPPLE_DB, FIT_TOP_FRACTION,
    NYQUIST_EXCESS_DB, SECTIONS_PER_DECADE,
};
pub use preset::{
    AdcParameters, ChainParameters, Coupling, Draw, HumParameters, SensorPreset, TransducerKind,
    DEFAULT_FLICKER_LOWEST_HZ, REFERENCE_TEMPERATURE_DEGC, STANDARD_GRAVITY_M_S2,
};
pub use resolve::{
    resolve, ChainStages, RealisedChain, ResolvedChain, DEFAULT_HUM_FREQUENCY_HZ,
    MAX_GAIN_ERROR_SIGMA, MIN_FLICKER_LOWEST_HZ,
};
pub use spec::{AdcSpec, ChainSpec, CouplingSpec, HumSpec};
pub use stages::{DcOffset, Gain, HighPass, Hum, SelfNoise, TemperatureFn};
