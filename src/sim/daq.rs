//! The DAQ side of a run: each sensor's running channel (anti-alias filter, measurement
//! chain, node clock) and fault injector, built from the resolved description, and the
//! node clocks' resynchronisations for `/events`. Every random part draws from its own
//! named stream of the run seed, so adding a sensor or a stage never changes another's
//! numbers.

use std::collections::VecDeque;

use crate::base::random::child_rng;
use crate::error::item_path;
use crate::error::Result;
use crate::measurement::daq::{ClockError, FaultInjector, NodeClock};
use crate::measurement::sensor::chain::{ClipCounter, TemperatureFn};
use crate::measurement::sensor::{InstantSource, SensorChannel, WhiteNoise};
use crate::record::{EventLevel, Record};
use crate::scenario::{sensor_streams, Resolved, ResolvedSensor};

impl InstantSource for NodeClock {
    fn next_instant(&mut self) -> (f64, i64) {
        let s = self.next_sample();
        (s.true_ns, s.stamp_ns)
    }
}

/// The running DAQ channel of sensor `index`: its design, its measurement chain (or plain
/// white self-noise) on the sensor's own streams, and its node's clock. Also the chain's
/// clipped-sample counter. The chain's bias drift reads `temperature_degc`.
pub(super) fn sensor_channel(
    resolved: &Resolved,
    sensor: &ResolvedSensor,
    index: usize,
    temperature_degc: TemperatureFn,
) -> Result<(SensorChannel, Option<ClipCounter>)> {
    let seed = resolved.scenario.seed;
    let noise = WhiteNoise {
        density_per_sqrt_hz: sensor.channel_noise_density(),
    };
    let mut channel = SensorChannel::from_design(
        &sensor.design,
        &noise,
        child_rng(seed, &format!("sensor/{}", sensor.spec.id)),
        &format!(
            "{}.noise",
            item_path("sensors", index, Some(&sensor.spec.id))
        ),
    )?;
    let mut clipped = None;
    if let Some(chain) = &sensor.chain {
        let chain = chain.stages(&mut sensor_streams(seed, &sensor.spec.id), temperature_degc)?;
        for stage in chain.stages {
            channel.add_stage(stage);
        }
        clipped = Some(chain.clipped);
    }
    Ok(match &sensor.clock {
        Some(clock) => (channel.with_clock(Box::new(clock.clone())), clipped),
        None => (channel, clipped),
    })
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
        &format!("{}.faults", item_path("sensors", index, Some(id))),
    )
    .map(Some)
}

/// The resynchronisations of every node clock, announced on `/events` in time order.
pub(super) struct Resyncs {
    nodes: Vec<(String, ClockError, u64)>,
}

impl Resyncs {
    pub fn new(resolved: &Resolved) -> Self {
        let nodes = resolved
            .scenario
            .daq_nodes
            .iter()
            .zip(&resolved.node_clocks)
            .map(|(node, error)| (node.id.clone(), error.clone(), 1))
            .collect();
        Resyncs { nodes }
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
