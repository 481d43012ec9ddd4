//! What a run produces, as plain data, and the one seam between the time loop and every
//! output: the loop (`sim`) hands [`Record`]s to a [`Recorder`] in time order, after a
//! [`RunManifest`] that describes every channel it will fill. An output (the MCAP file,
//! an in-memory run, a live stream) needs nothing else: it never reads the scenario or
//! the models.
//!
//! Times are ns since the start of the run; signs follow the output convention (vertical
//! displacement, velocity and acceleration downward positive; strain tension positive;
//! forces pressing on the road positive).

mod forecast;
mod manifest;
mod quantities;
mod records;
mod trigger;
mod wim;

pub use forecast::{ForecastRecords, RecordForecast, SensorForecast};
pub use manifest::{
    AxleDetectorInfo, BridgeSummary, ChainParameter, DaqClockInfo, GirderSummary, GnssInfo,
    InstrumentedVehicleInfo, Layout, PreviewInfo, RoadSummary, RunInfo, RunManifest, SceneInfo,
    SensorChannelInfo, StreamRates, VehicleMountInfo, WimStationInfo,
};
pub use quantities::{Quantities, SensorKind};
pub use records::{
    AxleHit, AxleState, ContactPoint, EventLevel, GnssFix, ModalRecord, Record, Recorder,
    VecRecorder, VehicleRecord, VehicleStateRecord, WimRecordData,
};
pub use trigger::{merged_windows, TriggerWindow, Triggered};
pub use wim::{AppliedErrors, AxleGroup, LoadReference, WimMeasurement};
