//! The DAQ side of a run: each sensor's channel (anti-alias filter, measurement chain,
//! node clock), its fault injector, and the node clocks' resynchronisations for
//! `/events`. Every random part draws from its own named stream of the run seed, so
//! adding a sensor or a stage never changes another's numbers.

use std::collections::VecDeque;

use rand_chacha::ChaCha8Rng;

use crate::base::random::child_rng;
use crate::error::Result;
use crate::measurement::daq::{ClockError, FaultInjector, NodeClock};
use crate::measurement::sensor::chain::{ChainStages, TemperatureFn};
use crate::measurement::sensor::{
    AntiAliasOptions, ChannelSpec, InstantSource, SensorChannel, WhiteNoise,
};
use crate::record::{EventLevel, Record};
use crate::scenario::{Resolved, ResolvedSensor};

impl InstantSource for NodeClock {
    fn next_instant(&mut self) -> (f64, i64) {
        let s = self.next_sample();
        (s.true_ns, s.stamp_ns)
    }
}

/// The stream of node `id`'s clock, shared by all its channels (the resync draws are the
/// node's, not a channel's).
fn node_stream(seed: u64, id: &str) -> ChaCha8Rng {
    child_rng(seed, &format!("daq/{id}/clock"))
}

/// Gain of the channel's anti-alias filter at `f_hz` for output rate `rate_hz`: 1 in the
/// pass band (to 0.4 rate, ripple 1e-4), 0 from the stop band edge (0.5 rate, 80 dB
/// down), a raised cosine between (the Kaiser design's transition). Used for the hum,
/// which is picked up before the filter.
fn anti_alias_gain(rate_hz: f64, f_hz: f64) -> f64 {
    let (pass, stop) = (0.4 * rate_hz, 0.5 * rate_hz);
    if f_hz <= pass {
        1.0
    } else if f_hz >= stop {
        0.0
    } else {
        0.5 * (1.0 + (std::f64::consts::PI * (f_hz - pass) / (stop - pass)).cos())
    }
}

/// The measurement-chain stages of sensor `index` (`None` without a chain). Every call
/// draws the same realised values (gain error, bias, hum phase) from the sensor's
/// streams, so the recorder can describe the chain the run uses. The DC bias drift reads
/// the reference temperature here (the realised bias is the value at it).
pub fn chain_stages(resolved: &Resolved, sensor: &ResolvedSensor) -> Result<Option<ChainStages>> {
    let reference: TemperatureFn =
        std::sync::Arc::new(|_| crate::physics::environment::DEFAULT_AIR_C);
    chain_stages_at(resolved, sensor, reference)
}

/// [`chain_stages`] with the bias drift reading `temperature_degc` (the air temperature
/// of the run's environment).
fn chain_stages_at(
    resolved: &Resolved,
    sensor: &ResolvedSensor,
    temperature_degc: TemperatureFn,
) -> Result<Option<ChainStages>> {
    let Some(chain) = &sensor.chain else {
        return Ok(None);
    };
    let seed = resolved.scenario.seed;
    let id = &sensor.spec.id;
    let rate_hz = sensor.spec.rate_hz;
    let mut rng_for = |name: &str| child_rng(seed, &format!("sensor/{id}/{name}"));
    chain
        .stages(rate_hz, &mut rng_for, temperature_degc, &|f| {
            anti_alias_gain(rate_hz, f)
        })
        .map(Some)
}

/// The DAQ channel of sensor `index`: anti-alias filter and resampling to its rate, its
/// measurement chain (or plain white self-noise) on the sensor's own streams, and its
/// node's clock. Also the chain's clipped-sample counter. The chain's bias drift reads
/// `temperature_degc`.
pub(super) fn sensor_channel(
    resolved: &Resolved,
    sensor: &ResolvedSensor,
    index: usize,
    temperature_degc: TemperatureFn,
) -> Result<(
    SensorChannel,
    Option<crate::measurement::sensor::chain::ClipCounter>,
)> {
    let solver_rate_hz = 1e9 / resolved.dt_ns as f64;
    let seed = resolved.scenario.seed;
    let spec = ChannelSpec {
        rate_hz: sensor.spec.rate_hz,
        anti_alias: AntiAliasOptions::default(),
        noise: WhiteNoise {
            density_per_sqrt_hz: sensor.channel_noise_density(),
        },
    };
    let mut channel = SensorChannel::new(
        solver_rate_hz,
        &spec,
        child_rng(seed, &format!("sensor/{}", sensor.spec.id)),
        &format!("sensors.{index}"),
    )?;
    let mut clipped = None;
    if let Some(chain) = chain_stages_at(resolved, sensor, temperature_degc)? {
        for stage in chain.stages {
            channel.add_stage(stage);
        }
        clipped = Some(chain.clipped);
    }
    let Some(node_index) = sensor.node else {
        return Ok((channel, clipped));
    };
    let node = &resolved.scenario.daq_nodes[node_index];
    let clock = NodeClock::new(
        &node.clock,
        sensor.spec.rate_hz,
        node_stream(seed, &node.id),
        &format!("daq_nodes.{node_index}.clock"),
    )?;
    Ok((channel.with_clock(Box::new(clock)), clipped))
}

/// The fault injector of sensor `index` (`None` without faults).
pub(super) fn fault_injector(
    resolved: &Resolved,
    sensor: &ResolvedSensor,
    index: usize,
) -> Result<Option<FaultInjector>> {
    let Some(spec) = sensor.spec.faults.as_ref().filter(|f| !f.is_empty()) else {
        return Ok(None);
    };
    let seed = resolved.scenario.seed;
    let id = &sensor.spec.id;
    let mut rng_for = |kind: &str| child_rng(seed, &format!("sensor/{id}/faults/{kind}"));
    FaultInjector::new(
        spec,
        sensor.spec.rate_hz,
        &mut rng_for,
        &format!("sensors.{index}.faults"),
    )
    .map(Some)
}

/// The resynchronisations of every node clock, announced on `/events` in time order.
pub(super) struct Resyncs {
    nodes: Vec<(String, ClockError, u64)>,
}

impl Resyncs {
    pub fn new(resolved: &Resolved) -> Result<Self> {
        let seed = resolved.scenario.seed;
        let nodes = resolved
            .scenario
            .daq_nodes
            .iter()
            .enumerate()
            .map(|(i, node)| {
                let error = ClockError::new(
                    &node.clock,
                    node_stream(seed, &node.id),
                    &format!("daq_nodes.{i}.clock"),
                )?;
                Ok((node.id.clone(), error, 1))
            })
            .collect::<Result<Vec<_>>>()?;
        Ok(Resyncs { nodes })
    }

    /// Queues the resyncs at or before `t_ns` as info events.
    pub fn announce_until(&mut self, t_ns: u64, out: &mut VecDeque<Record>) {
        for (id, error, next) in &mut self.nodes {
            while let Some(event) = error.resync_event(*next).filter(|e| e.true_ns <= t_ns) {
                out.push_back(Record::Event {
                    t_ns: event.true_ns,
                    level: EventLevel::Info,
                    text: format!(
                        "DAQ node {id}: clock resynchronised (#{}), error {:.1} us -> {:.1} us",
                        event.index,
                        1e6 * event.error_before_s,
                        1e6 * event.error_after_s
                    ),
                });
                *next += 1;
            }
        }
    }
}
