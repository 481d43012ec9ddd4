//! A sensor tap: the DAQ channel of one sensor (anti-alias, resampling, measurement
//! chain, node clock) plus the noise-free truth of every response quantity at the same
//! sample instants.
//!
//! The truth needs no schedule of its own: the tap keeps the last solver samples of all
//! five quantities in a ring as long as the channel's filter window, and when the channel
//! hands over a sample at position `n0 + frac` (solver samples; with a node clock, the
//! node's true sampling instant), it interpolates each quantity there (cubic Hermite,
//! [`crate::sensor::hermite`]). Work per solver step is five stores; the interpolation runs
//! at the sensor rate.

use std::collections::VecDeque;

use crate::sensor::{hermite, SensorChannel, HERMITE_LOOKAHEAD, HERMITE_LOOKBACK};

/// Response quantities at a point, output sign convention (downward positive).
/// Order: displacement (m), velocity (m/s), acceleration (m/s^2), strain (microstrain), moment (N m).
pub type Quantities = [f64; 5];

/// One sample ready for output.
#[derive(Debug, Clone, Copy)]
pub struct TapSample {
    /// True sampling instant (ns since the run start).
    pub t_ns: u64,
    /// The node's stamp for it (ns since the run start).
    pub stamp_ns: i64,
    /// Output sample index.
    pub k: u64,
    pub measured: f64,
    pub truth: Quantities,
}

/// The last `cap` solver samples of the five quantities, addressed by solver index.
struct History {
    buf: Vec<Quantities>,
    pushed: u64,
}

impl History {
    fn new(cap: usize) -> Self {
        History {
            buf: vec![[0.0; 5]; cap.max(HERMITE_LOOKBACK + HERMITE_LOOKAHEAD + 1)],
            pushed: 0,
        }
    }

    fn push(&mut self, values: &Quantities) {
        let cap = self.buf.len() as u64;
        self.buf[(self.pushed % cap) as usize] = *values;
        self.pushed += 1;
    }

    /// Sample `n` (may be before the first or after the last: those hold the first and
    /// the last sample, as the channel's filter does).
    fn at(&self, n: i64) -> &Quantities {
        let newest = self.pushed.saturating_sub(1) as i64;
        let n = n.clamp(0, newest) as u64;
        &self.buf[(n % self.buf.len() as u64) as usize]
    }

    /// The five quantities interpolated at `n0 + frac`.
    fn interpolate(&self, n0: u64, frac: f64) -> Quantities {
        let start = n0 as i64 - HERMITE_LOOKBACK as i64;
        let mut window = [[0.0; HERMITE_LOOKBACK + HERMITE_LOOKAHEAD + 1]; 5];
        for (j, n) in (start..=n0 as i64 + HERMITE_LOOKAHEAD as i64).enumerate() {
            for (q, v) in self.at(n).iter().enumerate() {
                window[q][j] = *v;
            }
        }
        std::array::from_fn(|q| hermite(frac, &window[q], HERMITE_LOOKBACK))
    }
}

/// Channel + truth history of one sensor.
pub struct SensorTap {
    channel: SensorChannel,
    history: History,
    /// Index into `Quantities` of what the sensor measures.
    pub measured_index: usize,
    ready: VecDeque<TapSample>,
    emitted: u64,
}

impl SensorTap {
    /// A tap around `channel` (built with the sensor's rate, chain and clock), measuring
    /// quantity `measured_index` of [`Quantities`].
    pub fn new(channel: SensorChannel, measured_index: usize) -> Self {
        let (_, width) = channel.window_geometry();
        SensorTap {
            channel,
            // The channel's window reaches HERMITE_LOOKBACK (or more) samples behind n0.
            history: History::new(width),
            measured_index,
            ready: VecDeque::with_capacity(8),
            emitted: 0,
        }
    }

    /// Feeds one solver step of all quantities at the sensor's point.
    pub fn push(&mut self, values: &Quantities) {
        self.history.push(values);
        let measured = values[self.measured_index];
        let Self {
            channel,
            history,
            ready,
            emitted,
            ..
        } = self;
        channel.push(measured, |s| {
            ready.push_back(TapSample {
                t_ns: s.t_ns,
                stamp_ns: s.stamp_ns,
                k: *emitted,
                measured: s.measured,
                truth: history.interpolate(s.n0, s.frac),
            });
            *emitted += 1;
        });
    }

    /// Flushes the filter at the end of the run.
    pub fn flush(&mut self) {
        let Self {
            channel,
            history,
            ready,
            emitted,
            ..
        } = self;
        channel.flush(|s| {
            ready.push_back(TapSample {
                t_ns: s.t_ns,
                stamp_ns: s.stamp_ns,
                k: *emitted,
                measured: s.measured,
                truth: history.interpolate(s.n0, s.frac),
            });
            *emitted += 1;
        });
    }

    /// The time of the next sample, if any.
    pub fn next_time_ns(&self) -> Option<u64> {
        self.ready.front().map(|s| s.t_ns)
    }

    /// Removes the next sample.
    pub fn pop(&mut self) -> Option<TapSample> {
        self.ready.pop_front()
    }

    /// Worst-case delay between an instant and the emission of its sample (ns).
    pub fn latency_ns(&self) -> u64 {
        self.channel.latency_ns()
    }

    /// The channel (rate, taps, noise).
    pub fn channel(&self) -> &SensorChannel {
        &self.channel
    }
}
