//! What a run is expected to emit, known before it starts: the time loop's side of the
//! estimate `simulate` prints (and checks against the free disk space). The loop
//! (`sim::forecast`) says how many records of each kind the run will hand its recorder,
//! with a representative record of each; an output turns that into messages and bytes
//! with its own encoders (`output::estimate`), as it would the records themselves.

use super::quantities::Quantities;
use super::records::Record;

/// The records of one sensor over the run.
#[derive(Debug, Clone, PartialEq)]
pub struct SensorForecast {
    /// Samples the channel hands over (`Record::Sensor`), lost ones included: exact for
    /// an ideal clock (`floor(duration * rate) + 1`), within a few samples on a drifting
    /// node clock.
    pub samples: u64,
    /// Of them, the expected number lost to faults (`measured: None`).
    pub lost_samples: f64,
    /// Of them, those taken while the bridge is still at rest (before the first vehicle
    /// reaches it, without ambient excitation): their truth is exactly zero.
    pub rest_samples: f64,
    /// The measured value at rest: the sensor's noise, or 0 for a noise-free channel.
    pub rest_measured: f64,
    /// Expected interruptions of the measured stream (loss bursts, outages): each one
    /// closes a block early in the block layout.
    pub interruptions: f64,
    /// Preview samples (`Record::Preview`), 0 without a preview.
    pub preview_samples: u64,
    /// A representative sample: the measured value and the truth (non-zero values, so
    /// that every field is encoded as it is in a real message).
    pub measured: f64,
    pub truth: Quantities,
}

/// A representative record and how many of its kind the run is expected to emit.
#[derive(Debug, Clone, PartialEq)]
pub struct ForecastRecords {
    pub record: Record,
    /// Expected count (a mean over the random parts: traffic, faults), >= 0.
    pub count: f64,
    /// Records of a bridge at rest (every number zero), which compress far better.
    pub at_rest: bool,
}

/// Everything a run is expected to hand its recorder after the manifest.
#[derive(Debug, Clone, PartialEq)]
pub struct RecordForecast {
    /// Run-relative time of the last record (ns): the run's duration.
    pub duration_ns: u64,
    /// Per sensor, in manifest order.
    pub sensors: Vec<SensorForecast>,
    /// The other records (axle loads, deflected shapes, vehicles, WIM, events, faults),
    /// each kind with its expected count. Several entries may share a kind (axle-load
    /// records with fewer and with more axles, for a mean between them).
    pub records: Vec<ForecastRecords>,
    /// The axles a 3D scene update draws, on average: the vehicles within view of the
    /// bridge (the scene draws those near it from the latest axle-load record).
    pub scene_axles: Vec<super::AxleState>,
    /// Vehicles the run is expected to carry in all (scheduled and drawn).
    pub vehicles: f64,
}

impl RecordForecast {
    /// Expected records of every kind, sensor samples and previews included.
    pub fn record_count(&self) -> f64 {
        let sensor: f64 = self
            .sensors
            .iter()
            .map(|s| (s.samples + s.preview_samples) as f64)
            .sum();
        sensor + self.records.iter().map(|r| r.count).sum::<f64>()
    }
}
