//! One sensor channel: resampler + truth interpolation + per-sample stages (noise).

use std::sync::Arc;

use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

use super::kaiser::PolyphaseKernel;
use super::noise::{WhiteNoise, WhiteNoiseSource};
use super::resample::{field, filter, AntiAliasOptions, Rates};
use super::schedule::{Due, OutputSchedule};
use super::truth::{hermite, HERMITE_LOOKAHEAD, HERMITE_LOOKBACK};
use super::SampleStage;
use crate::base::rate::ExactRate;
use crate::error::Result;

/// What a channel records, in the caller's unit (m/s^2, strain, m).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ChannelSpec {
    /// Output (DAQ) sample rate in Hz, `0 < rate_hz <= 1/dt`.
    pub rate_hz: f64,
    /// Anti-alias filter; default [`AntiAliasOptions::default`].
    #[serde(default)]
    pub anti_alias: AntiAliasOptions,
    /// White self-noise; default none.
    #[serde(default)]
    pub noise: WhiteNoise,
}

/// The fixed part of a channel: its rates and its anti-alias kernel (shared by every
/// channel of the same design), validated and designed once, when the scenario is
/// resolved. A run builds its stateful channels from it ([`SensorChannel::from_design`]).
#[derive(Debug, Clone)]
pub struct ChannelDesign {
    rates: Rates,
    kernel: Option<Arc<PolyphaseKernel>>,
}

impl ChannelDesign {
    /// The design for output rate `rate_hz` from the solver rate `fs_in_hz` (a whole
    /// number of ns per step) with filter `anti_alias`. Errors name
    /// `<field_prefix>.rate_hz` and `<field_prefix>.anti_alias.*`.
    pub fn new(
        fs_in_hz: f64,
        rate_hz: f64,
        anti_alias: &AntiAliasOptions,
        field_prefix: &str,
    ) -> Result<Self> {
        anti_alias.validate(&field(field_prefix, "anti_alias"))?;
        let rates = Rates::new(fs_in_hz, rate_hz, field_prefix)?;
        let kernel = rates.kernel(anti_alias, field_prefix)?;
        Ok(Self { rates, kernel })
    }

    /// The output rate, exact.
    pub fn rate(&self) -> ExactRate {
        self.rates.out
    }
}

/// One output sample: the instant (ns since the run start, exact `round(k * 1e9 / rate)`;
/// with a node clock, the true sampling instant rounded to ns), the node's stamp (= `t_ns`
/// without a clock), the position `n0 + frac` in solver samples, the recorded value and
/// the noise-free, unfiltered truth at the same instant.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ChannelSample {
    pub t_ns: u64,
    pub stamp_ns: i64,
    pub n0: u64,
    pub frac: f64,
    pub measured: f64,
    pub truth: f64,
}

/// Resampler + truth interpolator + stages, fed one solver sample at a time, on one ring
/// buffer and one schedule: `measured` is the anti-alias filtered value (see
/// [`super::Resampler`]) passed through the stages in order (first the white noise), `truth`
/// the Hermite interpolant (see [`super::TruthInterpolator`]) at the same `t_ns`. Both are
/// handed over together, `max(L, 3)` solver steps after the instant at most
/// ([`SensorChannel::latency_ns`]); with `rate_hz == 1/dt` both are the solver samples
/// (plus noise for `measured`) without delay.
#[derive(Debug)]
pub struct SensorChannel {
    schedule: OutputSchedule,
    kernel: Option<Arc<PolyphaseKernel>>,
    noise_sigma: f64,
    stages: Vec<Box<dyn SampleStage>>,
}

impl SensorChannel {
    /// A channel from the solver rate `fs_in_hz` (a whole number of ns per step) described
    /// by `spec`; noise draws from `rng` (give each sensor its own, see
    /// [`super::child_rng`]; no draws when the density is 0). Errors name
    /// `<field_prefix>.rate_hz`, `<field_prefix>.anti_alias.*`, `<field_prefix>.noise.*`.
    pub fn new(
        fs_in_hz: f64,
        spec: &ChannelSpec,
        rng: ChaCha8Rng,
        field_prefix: &str,
    ) -> Result<Self> {
        let design = ChannelDesign::new(fs_in_hz, spec.rate_hz, &spec.anti_alias, field_prefix)?;
        Self::from_design(&design, &spec.noise, rng, &field(field_prefix, "noise"))
    }

    /// A channel of `design` with white self-noise `noise` drawn from `rng` (no draws
    /// when the density is 0). Errors name `<noise_prefix>.*`.
    pub fn from_design(
        design: &ChannelDesign,
        noise: &WhiteNoise,
        rng: ChaCha8Rng,
        noise_prefix: &str,
    ) -> Result<Self> {
        noise.validate(noise_prefix)?;
        let ChannelDesign { rates, kernel } = design.clone();
        let (back, ahead) = match &kernel {
            Some(k) => (
                k.half_width().max(HERMITE_LOOKBACK),
                k.half_width().max(HERMITE_LOOKAHEAD),
            ),
            None => (0, 0),
        };
        let mut stages: Vec<Box<dyn SampleStage>> = Vec::new();
        let mut noise_sigma = 0.0;
        if noise.density_per_sqrt_hz > 0.0 {
            let source = WhiteNoiseSource::new(noise, rates.out.hz(), rng, noise_prefix)?;
            noise_sigma = source.sigma();
            stages.push(Box::new(source));
        }
        Ok(Self {
            schedule: OutputSchedule::new(rates.out, rates.dt_ns, back, ahead),
            kernel,
            noise_sigma,
            stages,
        })
    }

    /// The same channel sampling at a DAQ node's instants (see [`super::InstantSource`]);
    /// the rate must then be at most half the solver rate (checked by the caller), so that
    /// drift and jitter never put two outputs in one solver step.
    pub fn with_clock(mut self, clock: Box<dyn super::InstantSource>) -> Self {
        self.schedule = self.schedule.with_clock(clock);
        self
    }

    /// Index of sample `n0` in the window of the last pushed solver samples the channel
    /// evaluates (its look-back), and the window's length.
    pub fn window_geometry(&self) -> (usize, usize) {
        (
            self.schedule.centre(),
            self.schedule.centre() + self.schedule.lookahead() + 1,
        )
    }

    /// Appends a stage after the existing ones (applied to `measured` only).
    pub fn add_stage(&mut self, stage: Box<dyn SampleStage>) {
        self.stages.push(stage);
    }

    /// Pushes the next solver sample; `emit` receives each sample it completes (0 or 1;
    /// more only after a [`SensorChannel::flush`]). Returns how many.
    pub fn push(&mut self, value: f64, mut emit: impl FnMut(ChannelSample)) -> usize {
        let Self {
            schedule,
            kernel,
            stages,
            ..
        } = self;
        let centre = schedule.centre();
        schedule.push(value, |due| emit(evaluate(kernel, stages, centre, &due)))
    }

    /// Emits the samples up to the last solver instant, holding the last value where the
    /// kernel reaches beyond it. After `flush` the channel has emitted exactly the instants
    /// `t_k <= t_last`: `floor(t_last * rate_hz) + 1` samples. The stream may continue.
    pub fn flush(&mut self, mut emit: impl FnMut(ChannelSample)) -> usize {
        let Self {
            schedule,
            kernel,
            stages,
            ..
        } = self;
        let centre = schedule.centre();
        schedule.flush(|due| emit(evaluate(kernel, stages, centre, &due)))
    }

    /// Largest delay between a sample's instant and the push that emits it.
    pub fn latency_ns(&self) -> u64 {
        self.schedule.lookahead() as u64 * self.schedule.dt_ns()
    }

    /// Output rate in Hz.
    pub fn rate_hz(&self) -> f64 {
        self.schedule.rate().hz()
    }

    /// Anti-alias kernel taps (1 for pass-through).
    pub fn taps(&self) -> usize {
        self.kernel.as_ref().map_or(1, |k| k.taps())
    }

    /// Per-sample white-noise sigma (0 without noise).
    pub fn noise_sigma(&self) -> f64 {
        self.noise_sigma
    }

    /// Instant of sample `k`, `round(k * 1e9 / rate_hz)` ns.
    pub fn output_instant_ns(&self, k: u64) -> u64 {
        self.schedule.rate().instant_ns(k)
    }

    /// Solver samples pushed so far.
    pub fn pushed(&self) -> u64 {
        self.schedule.pushed()
    }
}

fn evaluate(
    kernel: &Option<Arc<PolyphaseKernel>>,
    stages: &mut [Box<dyn SampleStage>],
    centre: usize,
    due: &Due<'_>,
) -> ChannelSample {
    let truth = hermite(due.frac, due.window, centre);
    let mut measured = filter(kernel, centre, due);
    for stage in stages.iter_mut() {
        measured = stage.apply(due.t_ns, measured);
    }
    ChannelSample {
        t_ns: due.t_ns,
        stamp_ns: due.stamp_ns,
        n0: due.n0,
        frac: due.frac,
        measured,
        truth,
    }
}
