//! Instruments that see the vehicles rather than the bridge: a GNSS receiver riding on a
//! vehicle, and the axle detectors on the road that a B-WIM system times axles with.

mod axle_detector;
mod gnss;

pub use axle_detector::DetectorTiming;
pub use gnss::{GnssError, GnssNoise};
