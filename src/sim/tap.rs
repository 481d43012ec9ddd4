//! A sensor tap: the DAQ channel of one sensor (anti-alias, resampling, noise) plus the
//! noise-free truth of every response quantity at the same sample instants.

use std::collections::VecDeque;

use crate::error::Result;
use crate::sensor::{
    child_rng, AntiAliasOptions, ChannelSpec, SensorChannel, TruthInterpolator, WhiteNoise,
};

/// Response quantities at a point, output sign convention (downward positive).
/// Order: displacement (m), velocity (m/s), acceleration (m/s^2), strain (microstrain), moment (N m).
pub type Quantities = [f64; 5];

/// One sample ready for output.
#[derive(Debug, Clone, Copy)]
pub struct TapSample {
    pub t_ns: u64,
    pub measured: f64,
    pub truth: Quantities,
}

/// Channel + truth interpolators of one sensor.
pub struct SensorTap {
    channel: SensorChannel,
    truth: Vec<TruthInterpolator>,
    /// Index into `Quantities` of what the sensor measures.
    pub measured_index: usize,
    measured: VecDeque<(u64, f64)>,
    truth_queues: Vec<VecDeque<(u64, f64)>>,
}

impl SensorTap {
    /// `field_prefix` is the scenario path of the sensor ("sensors.3").
    pub fn new(
        solver_rate_hz: f64,
        rate_hz: f64,
        noise_density: f64,
        measured_index: usize,
        seed: u64,
        id: &str,
        field_prefix: &str,
    ) -> Result<Self> {
        let spec = ChannelSpec {
            rate_hz,
            anti_alias: AntiAliasOptions::default(),
            noise: WhiteNoise {
                density_per_sqrt_hz: noise_density,
            },
        };
        let channel = SensorChannel::new(
            solver_rate_hz,
            &spec,
            child_rng(seed, &format!("sensor/{id}")),
            field_prefix,
        )?;
        let truth = (0..5)
            .map(|_| TruthInterpolator::new(solver_rate_hz, rate_hz, field_prefix))
            .collect::<Result<Vec<_>>>()?;
        Ok(SensorTap {
            channel,
            truth,
            measured_index,
            measured: VecDeque::with_capacity(8),
            truth_queues: (0..5).map(|_| VecDeque::with_capacity(8)).collect(),
        })
    }

    /// Feeds one solver step of all quantities at the sensor's point.
    pub fn push(&mut self, values: &Quantities) {
        let measured = &mut self.measured;
        self.channel.push(values[self.measured_index], |s| {
            measured.push_back((s.t_ns, s.measured))
        });
        for (k, interp) in self.truth.iter_mut().enumerate() {
            let queue = &mut self.truth_queues[k];
            interp.push(values[k], |t, v| queue.push_back((t, v)));
        }
    }

    /// Flushes the filters at the end of the run.
    pub fn flush(&mut self) {
        let measured = &mut self.measured;
        self.channel
            .flush(|s| measured.push_back((s.t_ns, s.measured)));
        for (k, interp) in self.truth.iter_mut().enumerate() {
            let queue = &mut self.truth_queues[k];
            interp.flush(|t, v| queue.push_back((t, v)));
        }
    }

    /// The time of the next complete sample, if any.
    pub fn next_time_ns(&self) -> Option<u64> {
        let (t, _) = *self.measured.front()?;
        self.truth_queues
            .iter()
            .all(|q| q.front().is_some_and(|&(tq, _)| tq == t))
            .then_some(t)
    }

    /// Removes the next complete sample.
    pub fn pop(&mut self) -> Option<TapSample> {
        let t_ns = self.next_time_ns()?;
        let (_, measured) = self.measured.pop_front()?;
        let mut truth = [0.0; 5];
        for (k, q) in self.truth_queues.iter_mut().enumerate() {
            truth[k] = q.pop_front().map(|(_, v)| v).unwrap_or(f64::NAN);
        }
        Some(TapSample {
            t_ns,
            measured,
            truth,
        })
    }

    /// Worst-case delay between an instant and the emission of its sample (ns).
    pub fn latency_ns(&self) -> u64 {
        self.channel.latency_ns()
    }
}
