//! Traffic generation: lanes, arrivals, classes, weights and axle layouts.
//!
//! [`TrafficGenerator`] turns a scenario's `[traffic]` table ([`TrafficSpec`]) into a
//! stream of [`GeneratedVehicle`]s in entry order, lazily: each lane holds one pending
//! vehicle, so a day of traffic costs the memory of a few vehicles.
//!
//! - Arrivals per lane: a shifted non-homogeneous Poisson process (Cowan M1), the flow
//!   `flow_per_hour` times an hourly factor, drawn by time change (`arrivals`).
//! - Minimum gap, guaranteed: on a lane, from the follower's entry until its front axle has
//!   covered `road_length_m` (approach + span + exit), the clear distance from the rear of
//!   the vehicle ahead to the follower's front is at least `min_gap_s` times the
//!   follower's speed, the vehicle ahead taken at its constant speed. A faster follower
//!   enters later rather than driving slower, so speeds keep their distribution.
//! - Classes, weights, axle spacings and load shares: `class` (Auxerre defaults, docs/sensors.md
//!   section 4).
//! - Randomness: lane `i` draws only from `child_rng(seed, "traffic/lane/<i>")`, so adding
//!   a lane never changes another lane's vehicles (only the ids, which count in entry order
//!   across lanes).

mod arrivals;
mod class;
mod generator;
mod spec;

pub use class::{ClassModel, VehicleClass, WeightComponent, MAX_RELATIVE_SD, TRUNCATION_SD};
pub use generator::{
    variation_factors, GeneratedVehicle, TrafficGenerator, TrafficRun, MAX_LANE_OCCUPANCY,
};
pub use spec::{
    default_class_shares, LaneSpec, TrafficSpec, DEFAULT_CAR_SHARE, DEFAULT_HOURLY_PROFILE,
    DEFAULT_MIN_GAP_S, DEFAULT_PARAMETER_SD_REL, DEFAULT_SPEED_MEAN_M_S, DEFAULT_SPEED_SD_M_S,
    DEFAULT_TRUCK_SPLIT, HOURS_PER_DAY,
};
