//! The sensor tables of a scenario: what a bridge (or vehicle) sensor is, as written.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::{instruments, resolve, SensorKind};
use crate::base::schema as bounds;

/// Default white-noise density in the unit of a sensor of `kind` per sqrt(Hz):
/// ADXL355-class 22.5 ug/sqrt(Hz); foil strain gauge ~0.5 ue rms at 1 kHz; 1 um/sqrt(Hz)
/// for displacement (docs/sensors.md sections 1-2); the inclinometer and load-cell
/// presets' densities for those kinds.
pub fn default_noise_density(kind: SensorKind) -> f64 {
    use crate::measurement::sensor::chain::SensorPreset;
    match kind {
        SensorKind::Accelerometer => 22.5e-6 * crate::base::units::GRAVITY_M_S2,
        SensorKind::Strain => 0.02,
        SensorKind::Displacement => 1e-6,
        SensorKind::Inclinometer => SensorPreset::InclinometerMems.parameters().noise_density,
        SensorKind::LoadCell => SensorPreset::LoadCellBearing.parameters().noise_density,
        SensorKind::Thermometer => SensorPreset::ThermometerPt100.parameters().noise_density,
    }
}

/// The fibre of a strain gauge, above or below the neutral axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum Fibre {
    /// Below the neutral axis: sagging moments stretch it.
    Bottom,
    /// Above the neutral axis: hogging moments (over piers) stretch it.
    Top,
}

/// One bridge sensor.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SensorSpec {
    /// Topic segment: letters, digits, `_` and `-`; unique.
    #[schemars(regex(pattern = bounds::TOPIC_SEGMENT))]
    pub id: String,
    /// What the sensor measures.
    pub kind: SensorKind,
    /// Position along the girder (m, in [0, length]); a load cell's is a support's.
    /// Required for a bridge sensor, refused for one on a vehicle.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(range(min = 0, max = resolve::MAX_SPAN_M))]
    pub position_m: Option<f64>,
    /// An accelerometer riding on a vehicle instead of the bridge: `{ id = 1, axle = 1 }`
    /// (on the unsprung mass of axle 1, the front) or `{ id = 1, body_offset_m = 1.5 }`
    /// (on the body, 1.5 m behind the front axle). Its topic is
    /// `/vehicles/<vehicle id>/accel/<id>`; the vehicle's DOFs and contact points go to
    /// `/truth/vehicle_state/<vehicle id>`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub vehicle: Option<instruments::VehicleMountSpec>,
    /// DAQ sample rate (Hz, <= 1/dt; need not divide it).
    #[schemars(transform = bounds::positive)]
    pub rate_hz: f64,
    /// White-noise density in the unit of the sensor per sqrt(Hz), >= 0 (default by kind;
    /// with a preset or chain, it overrides the chain's `noise_density`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(range(min = 0))]
    pub noise_density: Option<f64>,
    /// Strain gauges: distance of the gauge from the neutral axis (m, > 0, default 0.8),
    /// below it unless `fibre = "top"`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(transform = bounds::positive)]
    pub gauge_depth_m: Option<f64>,
    /// Strain gauges: the fibre the gauge sits on, `bottom` (default: sagging stretches
    /// it) or `top` (over a pier, where hogging stretches it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fibre: Option<Fibre>,
    /// Measurement-chain preset (`ideal`, `mems_lownoise`, `piezo_seismic`,
    /// `force_balance`, `mems_consumer`, `strain_foil`, `inclinometer_mems`,
    /// `load_cell_bearing`, `thermometer_pt100`); with neither `preset` nor `chain` the channel adds white
    /// noise only (`noise_density`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub preset: Option<crate::measurement::sensor::chain::SensorPreset>,
    /// Overrides of the preset, field by field (`[sensors.chain]`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub chain: Option<crate::measurement::sensor::chain::ChainSpec>,
    /// Id of the DAQ node (`[[daq_nodes]]`) whose clock samples and stamps this sensor;
    /// none: an ideal clock (stamps = true instants).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(regex(pattern = bounds::TOPIC_SEGMENT))]
    pub daq_node: Option<String>,
    /// Faults of the measured stream, each labelled on `/truth/faults` and `/events`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub faults: Option<crate::measurement::daq::FaultSpec>,
}
