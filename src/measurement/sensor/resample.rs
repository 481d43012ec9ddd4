//! Anti-alias filtering and resampling from the solver rate to a sensor rate.

use std::sync::Arc;

use serde::{Deserialize, Serialize};

use super::kaiser::{KaiserDesign, PolyphaseKernel};
use super::schedule::OutputSchedule;
use crate::base::rate::{ExactRate, NS_PER_S};
use crate::error::{require_positive, Error, Result};

/// Largest anti-alias kernel: 2^20 + 1 taps (about 8 MiB of ring buffer; reached near
/// 0.05 Hz out of 1 kHz at 80 dB).
const MAX_TAPS: usize = (1 << 20) + 1;

/// Largest polyphase table, 2^24 entries (128 MiB); the automatic phase count keeps
/// tables near 0.1 M entries.
const MAX_TABLE_ENTRIES: usize = 1 << 24;

/// `prefix.name`, or `name` alone for an empty prefix.
pub(crate) fn field(prefix: &str, name: &str) -> String {
    if prefix.is_empty() {
        name.to_string()
    } else {
        format!("{prefix}.{name}")
    }
}

/// Anti-alias low-pass of a sensor channel. Band edges are fractions of the sensor's
/// output rate `fs_out`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct AntiAliasOptions {
    /// Upper edge of the pass band, fraction of `fs_out`. Default 0.4.
    pub passband_edge_fraction: f64,
    /// Lower edge of the stop band, fraction of `fs_out`. Default 0.5. Must not exceed
    /// `1 - passband_edge_fraction`, so that nothing aliases into the pass band.
    pub stopband_edge_fraction: f64,
    /// Design stop-band attenuation in dB, 30..=200. Default 80: pass-band ripple ~1e-4
    /// (measured 1.2e-4 over 0..0.4 `fs_out`) and >= 82 dB measured from 0.5 `fs_out` on,
    /// margin over the 60 dB that keeps aliases under a 20-bit sensor's noise. Taps grow
    /// as `(A - 8) / (2.285 * 2 pi * 0.1 fs_out / fs_in)`: 253 for 200 Hz out of 1 kHz.
    pub stopband_attenuation_db: f64,
    /// Number of polyphase table phases. Default `None`: chosen from the cutoff so that the
    /// linear interpolation between phases stays 40 dB below the stop-band ripple (512
    /// phases for 200 Hz out of 1 kHz at 80 dB).
    pub table_phases: Option<usize>,
}

impl AntiAliasOptions {
    /// The Kaiser design of these band edges for an output at `ratio` times the input
    /// rate (edges scale with the output rate), with `phases` table phases.
    pub(crate) fn kaiser_design(&self, ratio: f64, phases: Option<usize>) -> KaiserDesign {
        let pass = self.passband_edge_fraction;
        let stop = self.stopband_edge_fraction;
        KaiserDesign {
            cutoff: 0.5 * (pass + stop) * ratio,
            transition: (stop - pass) * ratio,
            attenuation_db: self.stopband_attenuation_db,
            phases,
        }
    }

    /// The filter's gain at `f_hz` for output rate `rate_hz`, approximated: 1 in the pass
    /// band (ripple ~1e-4), 0 from the stop-band edge (80 dB down), a raised cosine
    /// between (the shape of the Kaiser design's transition). Used for signals picked up
    /// before the filter that the chain adds after it (mains hum).
    pub fn approximate_gain(&self, rate_hz: f64, f_hz: f64) -> f64 {
        let pass = self.passband_edge_fraction * rate_hz;
        let stop = self.stopband_edge_fraction * rate_hz;
        if f_hz <= pass {
            1.0
        } else if f_hz >= stop {
            0.0
        } else {
            0.5 * (1.0 + (std::f64::consts::PI * (f_hz - pass) / (stop - pass)).cos())
        }
    }
}

impl Default for AntiAliasOptions {
    fn default() -> Self {
        Self {
            passband_edge_fraction: 0.4,
            stopband_edge_fraction: 0.5,
            stopband_attenuation_db: 80.0,
            table_phases: None,
        }
    }
}

impl AntiAliasOptions {
    /// Checks the options; `prefix` is the field path of the options table.
    pub fn validate(&self, prefix: &str) -> Result<()> {
        let pass_field = field(prefix, "passband_edge_fraction");
        let stop_field = field(prefix, "stopband_edge_fraction");
        let pass = require_positive(&pass_field, self.passband_edge_fraction)?;
        let stop = require_positive(&stop_field, self.stopband_edge_fraction)?;
        if stop <= pass {
            return Err(Error::invalid(
                stop_field,
                stop,
                format!("must be > {pass_field} = {pass}"),
            ));
        }
        if stop > 1.0 - pass {
            return Err(Error::invalid(
                stop_field,
                stop,
                format!(
                    "must be <= 1 - {pass_field} = {} so that nothing aliases into the pass band",
                    1.0 - pass
                ),
            ));
        }
        let a_field = field(prefix, "stopband_attenuation_db");
        let a = self.stopband_attenuation_db;
        if !(30.0..=200.0).contains(&a) {
            return Err(Error::invalid(a_field, a, "must be within 30..=200 dB"));
        }
        if let Some(p) = self.table_phases {
            if !(1..=1 << 20).contains(&p) {
                return Err(Error::invalid(
                    field(prefix, "table_phases"),
                    p,
                    "must be within 1..=1048576",
                ));
            }
        }
        Ok(())
    }
}

/// Solver step and output rate of a rate-changing stage, validated.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Rates {
    pub dt_ns: u64,
    pub out: ExactRate,
    /// `fs_out == fs_in` exactly.
    pub same: bool,
}

impl Rates {
    /// `fs_in_hz` must give a whole number of ns per solver step (the solver's clock is
    /// `step * dt_ns`); `fs_out_hz` is the field `<prefix>.rate_hz`, `0 < fs_out <= fs_in`.
    pub(crate) fn new(fs_in_hz: f64, fs_out_hz: f64, prefix: &str) -> Result<Self> {
        let input = ExactRate::from_hz("fs_in_hz", fs_in_hz)?;
        let dt_ns = input.whole_period_ns().ok_or_else(|| {
            Error::invalid(
                "fs_in_hz",
                fs_in_hz,
                format!(
                    "must give a whole number of ns per solver step (1e9 / fs_in_hz = {} ns)",
                    NS_PER_S as f64 / fs_in_hz
                ),
            )
        })?;
        let rate_field = field(prefix, "rate_hz");
        let out = ExactRate::from_hz(&rate_field, fs_out_hz)?;
        let ordering = out.cmp_rate(&input);
        if ordering == std::cmp::Ordering::Greater {
            return Err(Error::invalid(
                rate_field,
                fs_out_hz,
                format!("must be <= the solver rate 1/dt = {fs_in_hz} Hz"),
            ));
        }
        Ok(Self {
            dt_ns,
            out,
            same: ordering == std::cmp::Ordering::Equal,
        })
    }

    /// The anti-alias kernel, `None` when the rates are equal (pass-through). Errors when
    /// the kernel would exceed `MAX_TAPS` taps (`rate_hz` far below the solver rate) or
    /// `MAX_TABLE_ENTRIES` table entries (an explicit `table_phases`).
    pub(crate) fn kernel(
        &self,
        options: &AntiAliasOptions,
        prefix: &str,
    ) -> Result<Option<Arc<PolyphaseKernel>>> {
        if self.same {
            return Ok(None);
        }
        let ratio = self.out.hz() * self.dt_ns as f64 / NS_PER_S as f64;
        let design = options.kaiser_design(ratio, options.table_phases);
        let (half_width, phases) = PolyphaseKernel::planned_size(&design);
        let taps = 2 * half_width + 1;
        if taps > MAX_TAPS {
            return Err(Error::invalid(
                field(prefix, "rate_hz"),
                self.out.hz(),
                format!(
                    "is too far below the solver rate {} Hz: the anti-alias kernel would need \
                     {taps} taps (at most {MAX_TAPS}); record at a higher rate and decimate \
                     downstream, or relax anti_alias.stopband_attenuation_db",
                    NS_PER_S as f64 / self.dt_ns as f64
                ),
            ));
        }
        if (phases + 1).saturating_mul(taps) > MAX_TABLE_ENTRIES {
            return Err(Error::invalid(
                field(prefix, "anti_alias.table_phases"),
                phases,
                format!(
                    "gives a table of {taps} taps x {} phases, more than {MAX_TABLE_ENTRIES} \
                     entries",
                    phases + 1
                ),
            ));
        }
        Ok(Some(PolyphaseKernel::shared(&design)))
    }
}

/// Streaming anti-alias filter and resampler from the solver rate `fs_in` to any rate
/// `fs_out <= fs_in`.
///
/// Output `k` is at `t_k = round(k * 1e9 / fs_out)` ns (integers, from `k`); solver sample
/// `i` at `i * dt_ns`. The value at `t_k` is the continuous Kaiser-windowed-sinc kernel
/// (see [`AntiAliasOptions`]) centred on `t_k`, applied to the `2L + 1` surrounding solver
/// samples: symmetric, hence zero phase. It is handed over when solver sample
/// `floor(t_k / dt) + L` is pushed, i.e. `L` solver steps late at most
/// ([`Resampler::latency_ns`]).
///
/// Ends: solver samples before the first are taken equal to it; [`Resampler::flush`]
/// completes the last outputs by holding the last value (hold, not zeros, so a static
/// offset such as dead-load strain has no end transient). After `flush` the outputs are
/// exactly the `t_k <= t_last` (the last solver instant): `floor(t_last * fs_out) + 1` of
/// them, the first at 0.
///
/// `fs_out == fs_in` passes the solver samples through unchanged (no filter, no latency):
/// the solver output then is the recorded signal.
#[derive(Debug)]
pub struct Resampler {
    schedule: OutputSchedule,
    kernel: Option<Arc<PolyphaseKernel>>,
}

impl Resampler {
    /// A resampler from `fs_in_hz` (the solver rate `1/dt`, a whole number of ns per step) to
    /// `fs_out_hz`. Errors name `<field_prefix>.rate_hz` (e.g. `sensors.3.rate_hz`) and
    /// `<field_prefix>.anti_alias.*`.
    pub fn new(
        fs_in_hz: f64,
        fs_out_hz: f64,
        options: &AntiAliasOptions,
        field_prefix: &str,
    ) -> Result<Self> {
        options.validate(&field(field_prefix, "anti_alias"))?;
        let rates = Rates::new(fs_in_hz, fs_out_hz, field_prefix)?;
        let kernel = rates.kernel(options, field_prefix)?;
        let half = kernel.as_ref().map_or(0, |k| k.half_width());
        Ok(Self {
            schedule: OutputSchedule::new(rates.out, rates.dt_ns, half, half),
            kernel,
        })
    }

    /// Pushes the next solver sample; calls `emit(t_ns, value)` for each output completed
    /// by it (0 or 1; more only after a [`Resampler::flush`]). Returns how many.
    pub fn push(&mut self, value: f64, mut emit: impl FnMut(u64, f64)) -> usize {
        let Self { schedule, kernel } = self;
        let centre = schedule.centre();
        schedule.push(value, |due| emit(due.t_ns, filter(kernel, centre, &due)))
    }

    /// Emits the outputs up to the last pushed solver instant, holding the last value for
    /// the samples the kernel still lacks. The stream may continue afterwards.
    pub fn flush(&mut self, mut emit: impl FnMut(u64, f64)) -> usize {
        let Self { schedule, kernel } = self;
        let centre = schedule.centre();
        schedule.flush(|due| emit(due.t_ns, filter(kernel, centre, &due)))
    }

    /// `true` when `fs_out == fs_in` and samples pass unfiltered.
    pub fn is_passthrough(&self) -> bool {
        self.kernel.is_none()
    }

    /// Kernel taps `2L + 1` (1 for pass-through).
    pub fn taps(&self) -> usize {
        self.kernel.as_ref().map_or(1, |k| k.taps())
    }

    /// Polyphase table phases (0 for pass-through).
    pub fn table_phases(&self) -> usize {
        self.kernel.as_ref().map_or(0, |k| k.phases())
    }

    /// Largest delay between an output instant and the push that emits it: `L * dt_ns`.
    pub fn latency_ns(&self) -> u64 {
        self.schedule.lookahead() as u64 * self.schedule.dt_ns()
    }

    /// Solver step `dt_ns`.
    pub fn input_step_ns(&self) -> u64 {
        self.schedule.dt_ns()
    }

    /// Output rate in Hz.
    pub fn rate_hz(&self) -> f64 {
        self.schedule.rate().hz()
    }

    /// Instant of output `k`, `round(k * 1e9 / fs_out)` ns.
    pub fn output_instant_ns(&self, k: u64) -> u64 {
        self.schedule.rate().instant_ns(k)
    }

    /// Outputs emitted so far.
    pub fn emitted(&self) -> u64 {
        self.schedule.emitted()
    }
}

/// Filtered value of a due output; the window is centred on index `centre`.
pub(crate) fn filter(
    kernel: &Option<Arc<PolyphaseKernel>>,
    centre: usize,
    due: &super::schedule::Due<'_>,
) -> f64 {
    match kernel {
        Some(k) => {
            let l = k.half_width();
            k.apply(due.frac, &due.window[centre - l..=centre + l])
        }
        None => due.window[centre],
    }
}
