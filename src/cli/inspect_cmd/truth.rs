//! Decoding of the few message types the report needs, with the crate's own prost types.
//! Everything else is only counted: decoding 40 000 accelerometer samples to print one line
//! would cost more than the rest of the scan.

use std::collections::BTreeMap;

use prost::Message as _;

use crate::output::proto::foxglove::Log;
use crate::output::proto::v1::{AxleLoads, BridgeState, SampleBlock, SensorTruthBlock};
use crate::sim::STOP_EVENT_PREFIX;

/// Schema names (fully qualified protobuf message names) the report decodes.
pub(super) const AXLE_LOADS: &str = "bridgetwin.v1.AxleLoads";
pub(super) const BRIDGE_STATE: &str = "bridgetwin.v1.BridgeState";
pub(super) const SAMPLE_BLOCK: &str = "bridgetwin.v1.SampleBlock";
pub(super) const SENSOR_TRUTH_BLOCK: &str = "bridgetwin.v1.SensorTruthBlock";
pub(super) const LOG: &str = "foxglove.Log";

/// Samples carried by the block messages of one channel. A block is stamped with its first
/// sample; the others follow at `sample_period_ns`.
#[derive(Debug, Default, Clone, Copy)]
pub(super) struct BlockStats {
    pub samples: u64,
    pub first_sample_ns: Option<u64>,
    pub last_sample_ns: Option<u64>,
}

impl BlockStats {
    fn add(&mut self, start_ns: u64, sample_period_ns: u64, len: usize) {
        if len == 0 {
            return;
        }
        let end_ns = start_ns.saturating_add(sample_period_ns.saturating_mul(len as u64 - 1));
        self.samples += len as u64;
        self.first_sample_ns = Some(self.first_sample_ns.map_or(start_ns, |t| t.min(start_ns)));
        self.last_sample_ns = Some(self.last_sample_ns.map_or(end_ns, |t| t.max(end_ns)));
    }

    /// Samples per second over the channel's own first..last sample.
    pub fn sample_rate_hz(&self) -> Option<f64> {
        rate_hz(self.samples, self.first_sample_ns?, self.last_sample_ns?)
    }
}

/// Events per second from `count` events spread from `first_ns` to `last_ns`: (n - 1) / span,
/// so that 801 samples 5 ms apart give exactly 200 Hz. `None` for fewer than two events.
pub(super) fn rate_hz(count: u64, first_ns: u64, last_ns: u64) -> Option<f64> {
    let span_s = last_ns.checked_sub(first_ns)? as f64 * 1e-9;
    (count >= 2 && span_s > 0.0).then(|| (count - 1) as f64 / span_s)
}

/// Tyre force statistics of one axle while it is on the bridge.
#[derive(Debug, Default, Clone, Copy)]
pub(super) struct AxleStats {
    pub static_load_n: f64,
    pub samples_on_bridge: u64,
    pub max_force_n: f64,
    /// Sum of ((force - static) / static)^2 over the samples on the bridge.
    sum_sq_dynamic_ratio: f64,
}

impl AxleStats {
    /// Dynamic load coefficient: max force on the bridge / static load.
    pub fn dlc(&self) -> Option<f64> {
        (self.samples_on_bridge > 0 && self.static_load_n > 0.0)
            .then(|| self.max_force_n / self.static_load_n)
    }

    /// RMS of (force - static) / static on the bridge (includes any mean offset, unlike a
    /// standard deviation).
    pub fn rms_dynamic_ratio(&self) -> Option<f64> {
        (self.samples_on_bridge > 0 && self.static_load_n > 0.0)
            .then(|| (self.sum_sq_dynamic_ratio / self.samples_on_bridge as f64).sqrt())
    }
}

/// The truth gathered while scanning.
#[derive(Debug, Default)]
pub(super) struct TruthScan {
    /// Natural frequencies and damping ratios of the first `/truth/bridge` message.
    pub modal: Option<(Vec<f64>, Vec<f64>)>,
    /// Keyed by (vehicle id, axle index).
    pub axles: BTreeMap<(u32, u32), AxleStats>,
    /// The event that says a stop request ended the run, if the file holds one.
    pub stop_event: Option<String>,
    bridge_seen: bool,
}

impl TruthScan {
    /// Decodes a message when its schema is one the report needs; other schemas are ignored.
    /// `blocks` is the channel's block tally, filled for block schemas.
    pub fn message(
        &mut self,
        schema: &str,
        log_time_ns: u64,
        data: &[u8],
        blocks: &mut Option<BlockStats>,
    ) -> Result<(), prost::DecodeError> {
        match schema {
            AXLE_LOADS => self.axle_loads(&AxleLoads::decode(data)?),
            BRIDGE_STATE if !self.bridge_seen => {
                self.bridge_seen = true;
                let state = BridgeState::decode(data)?;
                self.modal = Some((state.natural_frequency_hz, state.damping_ratio));
            }
            SAMPLE_BLOCK => {
                let b = SampleBlock::decode(data)?;
                let tally = blocks.get_or_insert_with(BlockStats::default);
                tally.add(log_time_ns, b.sample_period_ns, b.values.len());
            }
            SENSOR_TRUTH_BLOCK => {
                let b = SensorTruthBlock::decode(data)?;
                let tally = blocks.get_or_insert_with(BlockStats::default);
                tally.add(log_time_ns, b.sample_period_ns, truth_block_len(&b));
            }
            LOG => {
                let log = Log::decode(data)?;
                if log.message.starts_with(STOP_EVENT_PREFIX) {
                    self.stop_event = Some(log.message);
                }
            }
            _ => {}
        }
        Ok(())
    }

    fn axle_loads(&mut self, loads: &AxleLoads) {
        for a in &loads.axles {
            let stats = self.axles.entry((a.vehicle_id, a.axle_index)).or_default();
            stats.static_load_n = a.static_load_n;
            if !a.on_bridge {
                continue;
            }
            if stats.samples_on_bridge == 0 || a.force_n > stats.max_force_n {
                stats.max_force_n = a.force_n;
            }
            stats.samples_on_bridge += 1;
            if a.static_load_n > 0.0 {
                stats.sum_sq_dynamic_ratio +=
                    ((a.force_n - a.static_load_n) / a.static_load_n).powi(2);
            }
        }
    }
}

/// Samples in a truth block: every quantity holds one value per sample.
fn truth_block_len(b: &SensorTruthBlock) -> usize {
    [
        b.displacement_m.len(),
        b.velocity_m_s.len(),
        b.acceleration_m_s2.len(),
        b.strain_microstrain.len(),
        b.moment_n_m.len(),
    ]
    .into_iter()
    .max()
    .unwrap_or(0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rate_counts_intervals_not_events() {
        // 801 samples at 200 Hz span exactly 4 s.
        assert_eq!(rate_hz(801, 0, 4_000_000_000), Some(200.0));
        assert_eq!(rate_hz(1, 5, 5), None);
        assert_eq!(rate_hz(2, 9, 5), None);
    }

    #[test]
    fn blocks_end_at_their_last_sample() {
        let mut b = BlockStats::default();
        b.add(0, 5_000_000, 50);
        b.add(250_000_000, 5_000_000, 50);
        assert_eq!(b.samples, 100);
        assert_eq!(b.last_sample_ns, Some(495_000_000));
        let rate = b.sample_rate_hz().unwrap();
        assert!((rate - 200.0).abs() < 1e-9, "{rate}");
    }
}
