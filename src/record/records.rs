//! The records of a run, in time order: what the time loop emits and every output
//! consumes.

use super::manifest::RunManifest;
use super::quantities::Quantities;
use super::wim::WimMeasurement;

/// Severity of an event.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EventLevel {
    Info,
    Warning,
}

/// One axle's state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxleState {
    pub vehicle_id: u32,
    pub axle_index: u32,
    /// The vehicle's lane (count from 0).
    pub lane: u32,
    pub position_m: f64,
    pub force_n: f64,
    pub static_load_n: f64,
    pub in_contact: bool,
    pub on_bridge: bool,
}

/// The truth of one vehicle, written when it leaves the bridge (or at the end of the run).
#[derive(Debug, Clone, PartialEq)]
pub struct VehicleRecord {
    pub vehicle_id: u32,
    pub model: String,
    pub lane: u32,
    /// +1 towards +x, -1 towards -x.
    pub direction: i8,
    pub speed_m_s: f64,
    pub entry_time_ns: Option<u64>,
    pub exit_time_ns: Option<u64>,
    pub axle_spacing_m: Vec<f64>,
    pub static_axle_load_n: Vec<f64>,
    pub gross_weight_n: f64,
    pub parameters: Vec<(String, f64)>,
}

/// One WIM record: what station `station` (index into `wim_stations`) reports.
#[derive(Debug, Clone, PartialEq)]
pub struct WimRecordData {
    pub station: usize,
    pub measurement: WimMeasurement,
}

/// The modal state of the running bridge model and its stiffness condition.
#[derive(Debug, Clone, PartialEq)]
pub struct ModalRecord {
    /// Lowest modes first (at most 10).
    pub natural_frequency_hz: Vec<f64>,
    pub damping_ratio: Vec<f64>,
    /// EI over the scenario's EI at the midpoint of each interval between the shape nodes.
    pub stiffness_ratio: Vec<f64>,
    /// Fraction of EI lost by each `[[damage]]` entry, scenario order.
    pub damage_fraction: Vec<f64>,
    /// With `[[support_condition]]`: each support's vertical spring factor and downward
    /// settlement (m), girder order; empty otherwise.
    pub support_stiffness_ratio: Vec<f64>,
    pub support_settlement_m: Vec<f64>,
}

/// One fix of a GNSS receiver: what it reports (measured) and the truth beside it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GnssFix {
    pub vehicle_id: u32,
    /// Front-axle position on the road axis as measured (m, the bridge's x).
    pub position_m: f64,
    /// Speed over ground as measured (m/s, >= 0 up to noise).
    pub speed_m_s: f64,
    pub true_position_m: f64,
    pub true_speed_m_s: f64,
}

/// One axle crossing a road axle detector.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxleHit {
    pub vehicle_id: u32,
    /// Axle number from the front, from 0.
    pub axle_index: u32,
    pub lane: u32,
    /// The true instant of the crossing (ns since the run start).
    pub true_ns: u64,
    /// The detector's stamp (ns since the run start; the jitter may put it before
    /// `true_ns`), `None` when it missed the axle.
    pub stamp_ns: Option<i64>,
    pub speed_m_s: f64,
}

/// Where one wheel of an instrumented vehicle touches the road.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactPoint {
    /// Position on the road axis (m, the bridge's x).
    pub position_m: f64,
    /// Road profile elevation there (m, upward positive).
    pub road_elevation_m: f64,
    /// Deflection of the deck there (m, downward positive; 0 off the bridge).
    pub bridge_deflection_m: f64,
    /// Deck acceleration at the fixed point under the wheel (m/s^2, downward positive;
    /// 0 off the bridge).
    pub bridge_acceleration_m_s2: f64,
    /// Tyre force (N, compression positive).
    pub force_n: f64,
    pub on_bridge: bool,
}

/// The state of an instrumented vehicle at one instant.
#[derive(Debug, Clone, PartialEq)]
pub struct VehicleStateRecord {
    pub vehicle_id: u32,
    /// Front-axle position (m).
    pub position_m: f64,
    pub speed_m_s: f64,
    /// DOF displacements, velocities, accelerations (upward positive; manifest order).
    pub displacement: Vec<f64>,
    pub velocity: Vec<f64>,
    pub acceleration: Vec<f64>,
    /// One per axle, front first.
    pub contacts: Vec<ContactPoint>,
}

/// A record with its time.
#[derive(Debug, Clone, PartialEq)]
pub enum Record {
    /// One sensor sample. `t_ns` is the true instant the DAQ node sampled (the log time of
    /// both messages and the truth's stamp); `stamp_ns` is the node clock's reading then
    /// (the measured message's stamp; equal to `t_ns` without a clock model, negative
    /// only with a negative clock offset); `measured` is `None` when a fault lost it.
    Sensor {
        sensor: usize,
        t_ns: u64,
        stamp_ns: i64,
        measured: Option<f64>,
        truth: Quantities,
    },
    /// One sample of a sensor's preview: its measured and true stream decimated with
    /// the anti-alias filter (see the manifest's `preview`), for viewers. Stamped like
    /// the sensor's own samples; `measured` is `None` where the centre sample was lost.
    Preview {
        sensor: usize,
        t_ns: u64,
        stamp_ns: i64,
        measured: Option<f64>,
        truth: f64,
    },
    /// A labelled fault interval of one sensor's measured stream, written at its start;
    /// `end_ns` (exclusive) is `None` for a fault lasting to the end of the run.
    Fault {
        t_ns: u64,
        sensor: usize,
        kind: &'static str,
        end_ns: Option<u64>,
        magnitude: f64,
    },
    AxleLoads {
        t_ns: u64,
        axles: Vec<AxleState>,
    },
    /// The deflected shape and the support reactions; with `[environment]` or `[[damage]]`
    /// also the (structure, air)
    /// temperatures (degC), and after a model rebuild (and once a minute) the modal state.
    BridgeShape {
        t_ns: u64,
        deflection_m: Vec<f64>,
        temperatures_c: Option<(f64, f64)>,
        modal: Option<Box<ModalRecord>>,
        /// Live-load reaction of each support, girder order (N, upward on the girder).
        support_reaction_n: Vec<f64>,
    },
    Vehicle {
        t_ns: u64,
        vehicle: VehicleRecord,
    },
    Wim {
        t_ns: u64,
        record: WimRecordData,
    },
    Event {
        t_ns: u64,
        level: EventLevel,
        text: String,
    },
    /// A fix of GNSS receiver `receiver` (index into the manifest's `gnss`).
    Gnss {
        t_ns: u64,
        receiver: usize,
        fix: GnssFix,
    },
    /// An axle crossing detector `detector` (index into the manifest's `axle_detectors`);
    /// `t_ns` is the solver instant at or after the true crossing.
    AxleHit {
        t_ns: u64,
        detector: usize,
        hit: AxleHit,
    },
    /// The state of an instrumented vehicle.
    VehicleState {
        t_ns: u64,
        state: Box<VehicleStateRecord>,
    },
}

impl Record {
    /// Time of the record (ns since the run start).
    pub fn t_ns(&self) -> u64 {
        match self {
            Record::Sensor { t_ns, .. }
            | Record::Preview { t_ns, .. }
            | Record::Fault { t_ns, .. }
            | Record::AxleLoads { t_ns, .. }
            | Record::BridgeShape { t_ns, .. }
            | Record::Vehicle { t_ns, .. }
            | Record::Wim { t_ns, .. }
            | Record::Event { t_ns, .. }
            | Record::Gnss { t_ns, .. }
            | Record::AxleHit { t_ns, .. }
            | Record::VehicleState { t_ns, .. } => *t_ns,
        }
    }
}

/// Receives the records of a run in non-decreasing time order: the seam between the time
/// loop and every output (an MCAP file, memory, a live stream).
pub trait Recorder {
    /// Called once before the first record with the description of every channel.
    fn begin(&mut self, manifest: &RunManifest) -> crate::Result<()> {
        let _ = manifest;
        Ok(())
    }

    fn record(&mut self, record: Record) -> crate::Result<()>;

    /// Called once after the last record (and after an interrupted run's last record):
    /// write what is still buffered.
    fn finish(&mut self) -> crate::Result<()> {
        Ok(())
    }
}

/// Collects the manifest and the records in memory (tests, small runs, bindings).
#[derive(Debug, Default)]
pub struct VecRecorder {
    pub manifest: Option<RunManifest>,
    pub records: Vec<Record>,
}

impl Recorder for VecRecorder {
    fn begin(&mut self, manifest: &RunManifest) -> crate::Result<()> {
        self.manifest = Some(manifest.clone());
        Ok(())
    }

    fn record(&mut self, record: Record) -> crate::Result<()> {
        self.records.push(record);
        Ok(())
    }
}
