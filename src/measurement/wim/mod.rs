//! Weigh-in-motion station models: COST 323 accuracy classes and strip physics.
//!
//! A station turns a vehicle passage (true speed, spacings, static loads and the dynamic
//! tyre forces at the strip) into the record a WIM system reports: measured speed,
//! spacings, axle and group loads, gross weight, axle pattern, FHWA class and quality
//! flags, plus the errors applied as truth. Three models (`model = { kind = ... }`):
//! `ideal` (the dynamic force, no error), `cost323` (synthetic errors on the static loads
//! that keep an accuracy class, [`cost323`]) and `physics` (the strip's reading of the
//! dynamic force with sensor noise, [`physics`]). Every random draw comes from the rng the
//! caller passes, in a fixed order per vehicle.

pub mod cost323;
mod fhwa;
mod groups;
pub mod physics;
mod spec;
pub mod split;
mod station;

pub use cost323::{Cost323Class, Criterion, VehicleErrorPlan, COST323_CLASS_NAMES};
pub use fhwa::fhwa_class;
pub use groups::{axle_groups, axle_pattern, AxleGroup, GROUP_SPACING_MAX_M};
pub use spec::{WimLimits, WimModelSpec, DEFAULT_NOISE_REL, DEFAULT_SPEED_SIGMA_REL};
pub use split::ErrorSplit;
pub use station::{
    AppliedErrors, LoadReference, WimMeasurement, WimPassage, WimStation, FLAG_LOW_SPEED,
    FLAG_MULTIPLE_PRESENCE, FLAG_OFF_SCALE,
};
