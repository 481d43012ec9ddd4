//! Preset + overrides -> validated chain -> stages.

use std::f64::consts::PI;

use rand::RngExt;
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;

use super::adc::{ClipCounter, Quantiser};
use super::flicker::{FlickerNoise, FIT_TOP_FRACTION};
use super::preset::{
    AdcParameters, ChainParameters, Coupling, Draw, HumParameters, SensorPreset, TransducerKind,
};
use super::spec::{AdcSpec, ChainSpec, CouplingSpec, HumSpec};
use super::stages::{DcOffset, Gain, HighPass, Hum, SelfNoise, TemperatureFn};
use crate::error::{num, require_finite, require_non_negative, require_positive, Error, Result};
use crate::measurement::sensor::resample::field;
use crate::measurement::sensor::{SampleStage, WhiteNoise, WhiteNoiseSource};

/// Largest gain-error sigma: with draws limited to +/-4 sigma the gain stays >= 0.2.
pub const MAX_GAIN_ERROR_SIGMA: f64 = 0.2;

/// Draws of a per-sensor random value are limited to this many sigma, so a rare draw
/// cannot turn a gain negative (the cut removes 6e-5 of the probability).
const DRAW_LIMIT_SIGMA: f64 = 4.0;

/// Lowest accepted start of the 1/f band (11.6 days): bounds the number of AR sections
/// (3 per decade) and the size of the fit.
pub const MIN_FLICKER_LOWEST_HZ: f64 = 1e-6;

/// Hum frequency when neither the preset nor the override gives one (European mains).
pub const DEFAULT_HUM_FREQUENCY_HZ: f64 = 50.0;

/// A preset with its overrides merged and validated, for one sensor.
#[derive(Debug, Clone, PartialEq)]
pub struct ResolvedChain {
    preset: SensorPreset,
    kind: TransducerKind,
    parameters: ChainParameters,
    field_prefix: String,
}

/// One sensor's chain with its values drawn (bias, gain error, hum phase) and its hum
/// scaled by the channel's anti-alias gain: a description, realised once when the
/// scenario is resolved, from which a run builds the running stages.
#[derive(Debug, Clone, PartialEq)]
pub struct RealisedChain {
    chain: ResolvedChain,
    fs_out_hz: f64,
    /// DC coupling: the bias (0 with AC coupling).
    bias: f64,
    gain_error: f64,
    hum: Option<Hum>,
    /// [`ResolvedChain::parameters`] plus the values drawn for this sensor.
    parameters: Vec<(String, f64)>,
}

impl RealisedChain {
    /// [`ResolvedChain::parameters`] plus the values drawn for this sensor
    /// (`gain_error`, `bias`, `hum_phase_rad` where random) and the hum amplitude after
    /// the anti-alias filter: what the channel metadata reports.
    pub fn parameters(&self) -> &[(String, f64)] {
        &self.parameters
    }

    /// The chain it was realised from.
    pub fn chain(&self) -> &ResolvedChain {
        &self.chain
    }

    /// Builds the enabled stages in chain order; the self-noise draws from
    /// `rng_for("noise")` and `rng_for("flicker")`, and `temperature_degc(t_ns)` drives
    /// the DC bias drift.
    pub fn stages(
        &self,
        rng_for: &mut dyn FnMut(&str) -> ChaCha8Rng,
        temperature_degc: TemperatureFn,
    ) -> Result<ChainStages> {
        let p = &self.chain.parameters;
        let fs_out_hz = self.fs_out_hz;
        let mut stages: Vec<Box<dyn SampleStage>> = Vec::new();
        match p.coupling {
            Coupling::Ac { highpass_hz } => {
                stages.push(Box::new(HighPass::new(highpass_hz, fs_out_hz)));
            }
            Coupling::Dc {
                bias_tempco_per_degc,
                ..
            } => {
                if self.bias != 0.0 || bias_tempco_per_degc != 0.0 {
                    let dc = DcOffset::new(self.bias, bias_tempco_per_degc, temperature_degc);
                    stages.push(Box::new(dc));
                }
            }
        }
        if self.gain_error != 0.0 {
            stages.push(Box::new(Gain::new(self.gain_error)));
        }
        if p.noise_density > 0.0 {
            stages.push(Box::new(self.chain.self_noise(fs_out_hz, rng_for)?));
        }
        if let Some(hum) = &self.hum {
            stages.push(Box::new(hum.clone()));
        }
        let clipped = ClipCounter::default();
        if let Some(adc) = p.adc {
            stages.push(Box::new(Quantiser::new(&adc, clipped.clone())));
        }
        Ok(ChainStages {
            stages,
            clipped,
            parameters: self.parameters.clone(),
        })
    }
}

/// The stages of one sensor, ready to append to its channel in order, with the ADC's
/// clip counter.
#[derive(Debug)]
pub struct ChainStages {
    /// Enabled stages in chain order: transfer function, gain, self-noise, hum, ADC.
    pub stages: Vec<Box<dyn SampleStage>>,
    /// Samples clipped by the ADC (stays 0 without an ADC).
    pub clipped: ClipCounter,
    /// The values the stages were built from ([`RealisedChain::parameters`]).
    pub parameters: Vec<(String, f64)>,
}

/// Merges `spec` over `preset` for a sensor of `kind`. `field_prefix` is the sensor's
/// scenario path (e.g. `sensors.3`): errors name `<prefix>.preset` and
/// `<prefix>.chain.<field>` with the offending value.
pub fn resolve(
    preset: SensorPreset,
    kind: TransducerKind,
    spec: &ChainSpec,
    field_prefix: &str,
) -> Result<ResolvedChain> {
    preset.check_kind(kind, &field(field_prefix, "preset"))?;
    let chain = field(field_prefix, "chain");
    let mut p = preset.parameters();
    p.coupling = merge_coupling(p.coupling, spec, &chain)?;
    p.gain_error = merge_gain(p.gain_error, spec, &chain)?;
    merge_noise(&mut p, spec, &chain)?;
    p.hum = merge_hum(p.hum, spec.hum.as_ref(), &field(&chain, "hum"))?;
    p.adc = merge_adc(p.adc, spec.adc.as_ref(), &field(&chain, "adc"))?;
    Ok(ResolvedChain {
        preset,
        kind,
        parameters: p,
        field_prefix: field_prefix.to_string(),
    })
}

fn merge_coupling(preset: Coupling, spec: &ChainSpec, chain: &str) -> Result<Coupling> {
    let coupling_field = field(chain, "coupling");
    let coupling = match (spec.coupling, preset) {
        (None, c) => c,
        (Some(CouplingSpec::Dc), c @ Coupling::Dc { .. }) => c,
        (Some(CouplingSpec::Dc), Coupling::Ac { .. }) => Coupling::Dc {
            bias: Draw::Fixed(0.0),
            bias_tempco_per_degc: 0.0,
        },
        (Some(CouplingSpec::Ac { highpass_hz }), c) => {
            let hp_field = field(&coupling_field, "highpass_hz");
            let preset_hz = match c {
                Coupling::Ac { highpass_hz } => Some(highpass_hz),
                Coupling::Dc { .. } => None,
            };
            let Some(hz) = highpass_hz.or(preset_hz) else {
                return Err(Error::invalid(
                    hp_field,
                    "(missing)",
                    "is required: the preset is DC-coupled",
                ));
            };
            Coupling::Ac {
                highpass_hz: require_positive(&hp_field, hz)?,
            }
        }
    };
    merge_bias(coupling, spec, chain)
}

fn merge_bias(coupling: Coupling, spec: &ChainSpec, chain: &str) -> Result<Coupling> {
    let given = [
        ("bias", spec.bias),
        ("bias_sigma", spec.bias_sigma),
        ("bias_tempco_per_degc", spec.bias_tempco_per_degc),
    ];
    match coupling {
        Coupling::Ac { .. } => {
            if let Some((name, Some(v))) = given.iter().find(|(_, v)| v.is_some()) {
                return Err(Error::invalid(
                    field(chain, name),
                    num(*v),
                    "applies to DC coupling only (coupling = { kind = \"dc\" })",
                ));
            }
            Ok(coupling)
        }
        Coupling::Dc {
            bias,
            bias_tempco_per_degc,
        } => Ok(Coupling::Dc {
            bias: merge_draw(bias, spec.bias, spec.bias_sigma, chain, "bias", None)?,
            bias_tempco_per_degc: match spec.bias_tempco_per_degc {
                Some(v) => require_finite(&field(chain, "bias_tempco_per_degc"), v)?,
                None => bias_tempco_per_degc,
            },
        }),
    }
}

fn merge_gain(preset: Draw, spec: &ChainSpec, chain: &str) -> Result<Draw> {
    let draw = merge_draw(
        preset,
        spec.gain_error,
        spec.gain_error_sigma,
        chain,
        "gain_error",
        Some(MAX_GAIN_ERROR_SIGMA),
    )?;
    if let (Some(v), Draw::Fixed(_)) = (spec.gain_error, draw) {
        if v.abs() >= 1.0 {
            return Err(Error::invalid(
                field(chain, "gain_error"),
                num(v),
                "must be a relative error in (-1, 1)",
            ));
        }
    }
    Ok(draw)
}

/// `<name>` (fixed) or `<name>_sigma` (random) over the preset's draw; not both.
fn merge_draw(
    preset: Draw,
    fixed: Option<f64>,
    sigma: Option<f64>,
    chain: &str,
    name: &str,
    max_sigma: Option<f64>,
) -> Result<Draw> {
    let fixed_field = field(chain, name);
    let sigma_field = format!("{fixed_field}_sigma");
    match (fixed, sigma) {
        (Some(_), Some(s)) => Err(Error::invalid(
            sigma_field,
            num(s),
            format!("conflicts with {name}: give a fixed value or a sigma, not both"),
        )),
        (Some(v), None) => Ok(Draw::Fixed(require_finite(&fixed_field, v)?)),
        (None, Some(s)) => {
            let s = require_non_negative(&sigma_field, s)?;
            match max_sigma {
                Some(max) if s > max => Err(Error::invalid(
                    sigma_field,
                    num(s),
                    format!("must be <= {max}"),
                )),
                _ => Ok(Draw::Normal { sigma: s }),
            }
        }
        (None, None) => Ok(preset),
    }
}

fn merge_noise(p: &mut ChainParameters, spec: &ChainSpec, chain: &str) -> Result<()> {
    if let Some(v) = spec.noise_density {
        p.noise_density = require_non_negative(&field(chain, "noise_density"), v)?;
    }
    if let Some(v) = spec.flicker_corner_hz {
        p.flicker_corner_hz = require_non_negative(&field(chain, "flicker_corner_hz"), v)?;
    }
    if let Some(v) = spec.flicker_lowest_hz {
        let lowest_field = field(chain, "flicker_lowest_hz");
        if !(v >= MIN_FLICKER_LOWEST_HZ && v.is_finite()) {
            return Err(Error::invalid(
                lowest_field,
                num(v),
                format!("must be a finite number >= {MIN_FLICKER_LOWEST_HZ} Hz"),
            ));
        }
        p.flicker_lowest_hz = v;
    }
    Ok(())
}

fn merge_hum(
    preset: Option<HumParameters>,
    spec: Option<&HumSpec>,
    hum: &str,
) -> Result<Option<HumParameters>> {
    let Some(spec) = spec else {
        return Ok(preset);
    };
    if !spec.enabled {
        let others = spec.frequency_hz.is_some() || spec.amplitude.is_some();
        return reject_if(others || spec.phase_rad.is_some(), hum).map(|()| None);
    }
    let frequency_hz = spec
        .frequency_hz
        .or(preset.map(|h| h.frequency_hz))
        .unwrap_or(DEFAULT_HUM_FREQUENCY_HZ);
    let amplitude_field = field(hum, "amplitude");
    let Some(amplitude) = spec.amplitude.or(preset.map(|h| h.amplitude)) else {
        return Err(Error::invalid(
            amplitude_field,
            "(missing)",
            "is required: the preset has no hum",
        ));
    };
    let phase_rad = match spec.phase_rad {
        Some(v) => Some(require_finite(&field(hum, "phase_rad"), v)?),
        None => preset.and_then(|h| h.phase_rad),
    };
    Ok(Some(HumParameters {
        frequency_hz: require_positive(&field(hum, "frequency_hz"), frequency_hz)?,
        amplitude: require_non_negative(&amplitude_field, amplitude)?,
        phase_rad,
    }))
}

fn merge_adc(
    preset: Option<AdcParameters>,
    spec: Option<&AdcSpec>,
    adc: &str,
) -> Result<Option<AdcParameters>> {
    let Some(spec) = spec else {
        return Ok(preset);
    };
    if !spec.enabled {
        return reject_if(spec.bits.is_some() || spec.range.is_some(), adc).map(|()| None);
    }
    let bits_field = field(adc, "bits");
    let range_field = field(adc, "range");
    let missing = |f: String| Error::invalid(f, "(missing)", "is required: the preset has no ADC");
    let bits = spec
        .bits
        .or(preset.map(|a| a.bits))
        .ok_or_else(|| missing(bits_field.clone()))?;
    let range = spec
        .range
        .or(preset.map(|a| a.range))
        .ok_or_else(|| missing(range_field.clone()))?;
    if !(1..=32).contains(&bits) {
        return Err(Error::invalid(bits_field, bits, "must be in 1..=32"));
    }
    Ok(Some(AdcParameters {
        bits,
        range: require_positive(&range_field, range)?,
    }))
}

/// `{ enabled = false }` with other fields set is a contradiction: name `enabled`.
fn reject_if(contradiction: bool, table: &str) -> Result<()> {
    if contradiction {
        Err(Error::invalid(
            field(table, "enabled"),
            false,
            "switches the stage off: remove the other fields of the table",
        ))
    } else {
        Ok(())
    }
}

impl ResolvedChain {
    /// The preset the chain started from.
    pub fn preset(&self) -> SensorPreset {
        self.preset
    }

    /// The sensor kind it was resolved for.
    pub fn kind(&self) -> TransducerKind {
        self.kind
    }

    /// The merged parameters (random ones still as sigma).
    pub fn chain_parameters(&self) -> &ChainParameters {
        &self.parameters
    }

    /// Errors naming `field` when `rate_hz` is not positive or exceeds the preset's
    /// maximum, and naming the chain field when a rate-dependent parameter does not fit
    /// the rate (high-pass at or above fs/2, 1/f band starting above the pass band).
    pub fn check_rate(&self, rate_hz: f64, field_name: &str) -> Result<()> {
        require_positive(field_name, rate_hz)?;
        if let Some(max_hz) = self.parameters.max_rate_hz {
            if rate_hz > max_hz {
                return Err(Error::invalid(
                    field_name,
                    num(rate_hz),
                    format!(
                        "Hz: rate not supported by the preset {} (maximum {} Hz)",
                        self.preset,
                        num(max_hz)
                    ),
                ));
            }
        }
        self.check_rate_dependent(rate_hz)
    }

    fn check_rate_dependent(&self, rate_hz: f64) -> Result<()> {
        let chain = field(&self.field_prefix, "chain");
        if let Coupling::Ac { highpass_hz } = self.parameters.coupling {
            if highpass_hz >= 0.5 * rate_hz {
                return Err(Error::invalid(
                    field(&field(&chain, "coupling"), "highpass_hz"),
                    num(highpass_hz),
                    format!("must be below half the sample rate ({} Hz)", num(rate_hz)),
                ));
            }
        }
        let p = &self.parameters;
        if p.flicker_corner_hz > 0.0 && p.flicker_lowest_hz >= FIT_TOP_FRACTION * rate_hz {
            return Err(Error::invalid(
                field(&chain, "flicker_lowest_hz"),
                num(p.flicker_lowest_hz),
                format!(
                    "must be below {FIT_TOP_FRACTION} x the sample rate ({} Hz)",
                    num(rate_hz)
                ),
            ));
        }
        Ok(())
    }

    /// Configured values for channel metadata, in chain order, in the channel's unit:
    /// `highpass_hz` or `bias`/`bias_sigma` and `bias_tempco_per_degc`,
    /// `gain_error`/`gain_error_sigma`, `noise_density`, `flicker_corner_hz`,
    /// `flicker_lowest_hz`, `hum_frequency_hz`, `hum_amplitude`, `hum_phase_rad` (if
    /// fixed), `adc_bits`, `adc_range`, `adc_lsb`, `max_rate_hz`. Stages that are off
    /// are left out. Values drawn per sensor are in [`ChainStages::parameters`].
    pub fn parameters(&self) -> Vec<(String, f64)> {
        let p = &self.parameters;
        let mut out = Vec::new();
        let mut push = |name: &str, v: f64| out.push((name.to_string(), v));
        match p.coupling {
            Coupling::Ac { highpass_hz } => push("highpass_hz", highpass_hz),
            Coupling::Dc {
                bias,
                bias_tempco_per_degc,
            } => {
                push_draw(&mut push, "bias", bias);
                push("bias_tempco_per_degc", bias_tempco_per_degc);
            }
        }
        push_draw(&mut push, "gain_error", p.gain_error);
        if p.noise_density > 0.0 {
            push("noise_density", p.noise_density);
            push("flicker_corner_hz", p.flicker_corner_hz);
            push("flicker_lowest_hz", p.flicker_lowest_hz);
        }
        if let Some(h) = p.hum {
            push("hum_frequency_hz", h.frequency_hz);
            push("hum_amplitude", h.amplitude);
            if let Some(phase) = h.phase_rad {
                push("hum_phase_rad", phase);
            }
        }
        if let Some(a) = p.adc {
            push("adc_bits", f64::from(a.bits));
            push("adc_range", a.range);
            push("adc_lsb", a.lsb());
        }
        if let Some(max_hz) = p.max_rate_hz {
            push("max_rate_hz", max_hz);
        }
        out
    }

    /// Draws this sensor's values for output rate `fs_out_hz`: the DC bias and the gain
    /// error (when the preset gives a sigma) and the hum phase (when not fixed), each from
    /// its own stream `rng_for(name)` (`"bias"`, `"gain"`, `"hum"`), and scales the hum by
    /// the channel's anti-alias gain `aa_gain_at_hz(f)` (the hum is picked up before the
    /// filter). Errors name `<prefix>.rate_hz` and the chain fields that do not fit the
    /// rate (see [`ResolvedChain::check_rate`], without the preset's maximum).
    pub fn realise(
        &self,
        fs_out_hz: f64,
        rng_for: &mut dyn FnMut(&str) -> ChaCha8Rng,
        aa_gain_at_hz: &dyn Fn(f64) -> f64,
    ) -> Result<RealisedChain> {
        require_positive(&field(&self.field_prefix, "rate_hz"), fs_out_hz)?;
        self.check_rate_dependent(fs_out_hz)?;
        let p = &self.parameters;
        let mut parameters = self.parameters();
        let mut realised = |name: &str, v: f64| parameters.push((name.to_string(), v));
        let bias = match p.coupling {
            Coupling::Ac { .. } => 0.0,
            Coupling::Dc { bias, .. } => realise(bias, "bias", rng_for, &mut realised),
        };
        let gain_error = realise(p.gain_error, "gain", rng_for, &mut realised);
        let hum = match p.hum {
            Some(h) => Some(hum(&h, rng_for, aa_gain_at_hz, &mut realised)?),
            None => None,
        };
        Ok(RealisedChain {
            chain: self.clone(),
            fs_out_hz,
            bias,
            gain_error,
            hum,
            parameters,
        })
    }

    /// [`ResolvedChain::realise`] then [`RealisedChain::stages`]: the stages in one call
    /// (the noise draws from `rng_for("noise")` and `rng_for("flicker")`).
    pub fn stages(
        &self,
        fs_out_hz: f64,
        rng_for: &mut dyn FnMut(&str) -> ChaCha8Rng,
        temperature_degc: TemperatureFn,
        aa_gain_at_hz: &dyn Fn(f64) -> f64,
    ) -> Result<ChainStages> {
        self.realise(fs_out_hz, rng_for, aa_gain_at_hz)?
            .stages(rng_for, temperature_degc)
    }

    fn self_noise(
        &self,
        fs_out_hz: f64,
        rng_for: &mut dyn FnMut(&str) -> ChaCha8Rng,
    ) -> Result<SelfNoise> {
        let p = &self.parameters;
        let white = WhiteNoise {
            density_per_sqrt_hz: p.noise_density,
        };
        let white = WhiteNoiseSource::new(&white, fs_out_hz, rng_for("noise"), "")?;
        let flicker = (p.flicker_corner_hz > 0.0).then(|| {
            let level = p.noise_density.powi(2) * p.flicker_corner_hz;
            FlickerNoise::new(level, p.flicker_lowest_hz, fs_out_hz, rng_for("flicker"))
        });
        Ok(SelfNoise::new(white, flicker))
    }
}

fn push_draw(push: &mut impl FnMut(&str, f64), name: &str, draw: Draw) {
    match draw {
        Draw::Fixed(v) => push(name, v),
        Draw::Normal { sigma } => push(&format!("{name}_sigma"), sigma),
    }
}

/// The value of `draw` for this sensor; a random one comes from `rng_for(stream)` and is
/// reported as `<stream>` (`bias`) or `gain_error`.
fn realise(
    draw: Draw,
    stream: &str,
    rng_for: &mut dyn FnMut(&str) -> ChaCha8Rng,
    realised: &mut impl FnMut(&str, f64),
) -> f64 {
    match draw {
        Draw::Fixed(v) => v,
        Draw::Normal { sigma } => {
            let z: f64 = rng_for(stream).sample(StandardNormal);
            let v = sigma * z.clamp(-DRAW_LIMIT_SIGMA, DRAW_LIMIT_SIGMA);
            let name = if stream == "gain" {
                "gain_error"
            } else {
                stream
            };
            realised(name, v);
            v
        }
    }
}

fn hum(
    h: &HumParameters,
    rng_for: &mut dyn FnMut(&str) -> ChaCha8Rng,
    aa_gain_at_hz: &dyn Fn(f64) -> f64,
    realised: &mut impl FnMut(&str, f64),
) -> Result<Hum> {
    let gain = aa_gain_at_hz(h.frequency_hz);
    if !(gain.is_finite() && gain >= 0.0) {
        return Err(Error::invalid(
            format!("anti-alias gain at {} Hz", num(h.frequency_hz)),
            num(gain),
            "must be a finite number >= 0",
        ));
    }
    let phase_rad = match h.phase_rad {
        Some(phase) => phase,
        None => {
            let phase = 2.0 * PI * rng_for("hum").random::<f64>();
            realised("hum_phase_rad", phase);
            phase
        }
    };
    realised("hum_amplitude_after_anti_alias", h.amplitude * gain);
    Ok(Hum::new(h.frequency_hz, h.amplitude * gain, phase_rad))
}
