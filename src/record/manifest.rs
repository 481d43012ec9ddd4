//! The run manifest: everything an output needs to know before the first record, as
//! the run realised it (rates, units, positions, the chain values drawn for each sensor,
//! the clocks' true rates, the model's modes, the road). The time loop builds it once
//! from the resolved scenario and the model; an output registers its channels and
//! writes its metadata from it alone.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::quantities::SensorKind;
use crate::base::rate::ExactRate;

/// How sensor samples are laid out in messages.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum Layout {
    /// One sample per message: every field plottable as a time series.
    Sample,
    /// Blocks of `block_samples` samples per message, as DAQ packets.
    Block,
}

/// The run as a whole.
#[derive(Debug, Clone, PartialEq)]
pub struct RunInfo {
    pub seed: u64,
    /// The scenario's `start_time`, RFC 3339 as written.
    pub start_time: String,
    /// Unix-epoch ns of t = 0.
    pub start_time_ns: u64,
    /// The resolved scenario as TOML (every default filled in).
    pub scenario_toml: String,
    /// The scenario as the user wrote it (empty for a scenario built in code).
    pub source_toml: String,
    /// The source revision of the software that wrote the run.
    pub git_revision: String,
}

/// The bridge model the run starts with.
#[derive(Debug, Clone, PartialEq)]
pub struct BridgeSummary {
    /// The model's label (`finite_element(50)`, `lumped_mass(100)`, ...).
    pub model: String,
    /// Lowest natural frequencies (Hz), at most 10, lowest first.
    pub natural_frequencies_hz: Vec<f64>,
    /// Their damping ratios (Rayleigh).
    pub damping_ratios: Vec<f64>,
    /// The scenario's damping ratio (on modes 1 and 2).
    pub damping_ratio: f64,
    pub rayleigh_a0_per_s: f64,
    pub rayleigh_a1_s: f64,
    pub flexural_rigidity_n_m2: f64,
    pub mass_per_length_kg_m: f64,
    /// Length of the girder, overhangs included (m): the span of a single span.
    pub length_m: f64,
    /// The girder's layout when it is not one simply supported span: span lengths,
    /// support positions (m from the left end) and support kinds.
    pub layout: Option<GirderSummary>,
    /// Positions of the deflected-shape nodes on `/truth/bridge` (m from the left end).
    pub shape_position_m: Vec<f64>,
    /// (structure, air) temperatures at t = 0 (degC) when the run has an environment.
    pub temperatures_c: Option<(f64, f64)>,
}

impl BridgeSummary {
    /// The middle of the longest span (m from the left end); of the girder for one span.
    pub fn midspan_m(&self) -> f64 {
        let Some(layout) = &self.layout else {
            return 0.5 * self.length_m;
        };
        layout
            .support_position_m
            .windows(2)
            .max_by(|a, b| (a[1] - a[0]).total_cmp(&(b[1] - b[0])))
            .map_or(0.5 * self.length_m, |w| 0.5 * (w[0] + w[1]))
    }
}

/// Spans and supports of a continuous girder.
#[derive(Debug, Clone, PartialEq)]
pub struct GirderSummary {
    pub spans_m: Vec<f64>,
    pub support_position_m: Vec<f64>,
    /// `pinned`, `roller`, `fixed` or `elastic`, one per support.
    pub supports: Vec<String>,
}

/// The road profile.
#[derive(Debug, Clone, PartialEq)]
pub struct RoadSummary {
    /// One line: the profile's kind, class, band and extent.
    pub description: String,
    /// The profile as CSV (`x_m,elevation_m`), shared: a kilometre of track is a
    /// megabyte of text, and a run builds its manifest more than once (the estimate).
    pub csv: std::sync::Arc<str>,
}

/// One realised value of a sensor's measurement chain (`gain_error`, `bias`,
/// `adc_lsb`, ...), in the channel's unit where it has one.
pub type ChainParameter = (String, f64);

/// The DAQ node clock of a sensor.
#[derive(Debug, Clone, PartialEq)]
pub struct DaqClockInfo {
    pub node_id: String,
    pub drift_ppm: f64,
    pub offset_s: f64,
    /// The rate the node really samples at, `nominal (1 + drift)`, Hz.
    pub true_rate_hz: f64,
}

/// One sensor's channels.
#[derive(Debug, Clone, PartialEq)]
pub struct SensorChannelInfo {
    pub id: String,
    pub kind: SensorKind,
    /// Nominal sample rate, exact.
    pub rate: ExactRate,
    /// The rate as the scenario wrote it (Hz), for metadata.
    pub rate_hz: f64,
    /// Position along the girder (m); 0 for a sensor on a vehicle.
    pub position_m: f64,
    /// The vehicle the sensor rides on, if not the bridge.
    pub vehicle: Option<VehicleMountInfo>,
    /// The measurement chain preset, or `white_noise`.
    pub model: String,
    /// White-noise density of the chain (unit per sqrt(Hz)).
    pub noise_density_per_sqrt_hz: f64,
    /// The chain's parameters as realised for this sensor (empty without a chain).
    pub chain: Vec<ChainParameter>,
    /// The node clock that samples and stamps it; `None`: an ideal clock.
    pub clock: Option<DaqClockInfo>,
    /// Strain gauges: distance below the neutral axis (m).
    pub gauge_depth_m: Option<f64>,
    /// Whether the sensor has faults configured.
    pub has_faults: bool,
    /// The preview channels of the sensor, if the run writes them.
    pub preview: Option<PreviewInfo>,
}

/// Where a sensor rides on a vehicle.
#[derive(Debug, Clone, PartialEq)]
pub struct VehicleMountInfo {
    pub vehicle_id: u32,
    /// "axle 1", "body, 1.5 m behind the front axle".
    pub mount: String,
}

/// A sensor's preview: its streams decimated by a whole factor for viewers.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PreviewInfo {
    /// Sensor samples per preview sample.
    pub factor: u64,
    /// The preview's nominal rate, the sensor's over `factor` (Hz).
    pub rate_hz: f64,
}

/// The 3D scene of the run (`/scene`): the deck following the deflected shape, the
/// supports, the vehicles and the sensors, at a low rate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SceneInfo {
    /// Deflected shapes (`Record::BridgeShape`) per scene update, >= 1; the first shape
    /// of the run gets one.
    pub every_shapes: u64,
    /// The scene's nominal rate, the shape rate over `every_shapes` (Hz).
    pub rate_hz: f64,
    /// Factor on the deflections drawn (no unit).
    pub exaggeration: f64,
    /// The deflection the factor was chosen from: static midspan deflection under the
    /// heaviest vehicle the scenario can put on the bridge (m).
    pub expected_peak_m: f64,
    /// Lanes the deck is drawn wide enough for (count, >= 1).
    pub lanes: u32,
}

/// One weigh-in-motion station.
#[derive(Debug, Clone, PartialEq)]
pub struct WimStationInfo {
    pub id: String,
    pub position_m: f64,
    /// The station model as one short label (`cost323 B+(7)`).
    pub model: String,
}

/// A GNSS receiver on a vehicle.
#[derive(Debug, Clone, PartialEq)]
pub struct GnssInfo {
    pub id: String,
    pub vehicle_id: u32,
    pub rate_hz: f64,
    pub position_noise_m: f64,
    pub correlation_s: f64,
    pub speed_noise_m_s: f64,
}

/// A road axle detector.
#[derive(Debug, Clone, PartialEq)]
pub struct AxleDetectorInfo {
    pub id: String,
    pub position_m: f64,
    /// Only this lane's vehicles; `None`: every lane.
    pub lane: Option<u32>,
    pub jitter_s: f64,
    pub miss_probability: f64,
}

/// A vehicle carrying instruments: its state is written at the axle-load rate.
#[derive(Debug, Clone, PartialEq)]
pub struct InstrumentedVehicleInfo {
    pub vehicle_id: u32,
    /// The model's name ("half_car/drive_by_van").
    pub model: String,
    /// Names of its DOFs, the order of the state's DOF arrays.
    pub dof_names: Vec<String>,
    /// Its axles (contact points per state).
    pub axles: usize,
}

/// Rates of the truth streams.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StreamRates {
    pub axle_load_rate_hz: f64,
    pub bridge_state_rate_hz: f64,
}

/// Everything an output needs before the first record.
#[derive(Debug, Clone, PartialEq)]
pub struct RunManifest {
    pub run: RunInfo,
    pub bridge: BridgeSummary,
    pub road: RoadSummary,
    /// In scenario order: `Record::Sensor { sensor, .. }` indexes this list.
    pub sensors: Vec<SensorChannelInfo>,
    /// In scenario order: `WimRecordData::station` indexes this list.
    pub wim_stations: Vec<WimStationInfo>,
    /// In scenario order: `Record::Gnss { receiver, .. }` indexes this list.
    pub gnss: Vec<GnssInfo>,
    /// In scenario order: `Record::AxleHit { detector, .. }` indexes this list.
    pub axle_detectors: Vec<AxleDetectorInfo>,
    /// The vehicles whose state goes to `/truth/vehicle_state/<id>`, ascending id.
    pub instrumented_vehicles: Vec<InstrumentedVehicleInfo>,
    pub rates: StreamRates,
    pub layout: Layout,
    /// Samples per block message (block layout).
    pub block_samples: usize,
    /// The 3D scene, if the run writes it.
    pub scene: Option<SceneInfo>,
}

impl RunManifest {
    /// A run with no sensors or stations on a 30 m bridge (unit tests of outputs).
    #[cfg(test)]
    pub(crate) fn minimal() -> Self {
        RunManifest {
            run: RunInfo {
                seed: 42,
                start_time: "2026-01-01T00:00:00Z".into(),
                start_time_ns: 1_767_225_600_000_000_000,
                scenario_toml: String::new(),
                source_toml: String::new(),
                git_revision: String::new(),
            },
            bridge: BridgeSummary {
                model: "finite_element n=2".into(),
                natural_frequencies_hz: vec![3.78],
                damping_ratios: vec![0.02],
                damping_ratio: 0.02,
                rayleigh_a0_per_s: 0.0,
                rayleigh_a1_s: 0.0,
                flexural_rigidity_n_m2: 5.629e10,
                mass_per_length_kg_m: 12_000.0,
                length_m: 30.0,
                layout: None,
                shape_position_m: vec![0.0, 15.0, 30.0],
                temperatures_c: None,
            },
            road: RoadSummary {
                description: "smooth".into(),
                csv: "".into(),
            },
            sensors: Vec::new(),
            wim_stations: Vec::new(),
            gnss: Vec::new(),
            axle_detectors: Vec::new(),
            instrumented_vehicles: Vec::new(),
            rates: StreamRates {
                axle_load_rate_hz: 200.0,
                bridge_state_rate_hz: 20.0,
            },
            layout: Layout::Sample,
            block_samples: 50,
            scene: None,
        }
    }

    /// Whether some sensor has faults configured (the run then writes `/truth/faults`).
    pub fn has_faults(&self) -> bool {
        self.sensors.iter().any(|s| s.has_faults)
    }
}
