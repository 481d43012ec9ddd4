//! Vehicles: linear pitch-plane models seen by the solver as matrices plus tyre contacts.

mod articulated;
mod classes;
mod dynamics;
mod models;
mod mounts;
mod pitch_plane_spec;
mod railway;
mod rake;
mod spec;
mod train;
mod train_presets;
mod train_spec;
mod truck_spec;

pub use articulated::ArticulatedParams;
pub use classes::{vehicle_for_traffic, TRAFFIC_CLASSES};
pub use dynamics::{Axle, VehicleDynamics, GRAVITY_M_S2};
pub use models::{
    quarter_car, rigid_body_on_axles, sprung_mass, AxleParams, BodyParams, RigidTruckParams,
};
pub use mounts::{MountError, MountPoint, BODY_OVERHANG_M};
pub use railway::RailwayCarParams;
pub use rake::{Bogie, CarBody, Pivot, RakeLayout, Suspension};
pub use spec::{HalfCarSpec, VehicleModelSpec, HALF_CAR_PRESETS};
pub use train::{hertz_contact_stiffness_n_m, CarParams, Representation, Train, TrainUnit, HSLM_A};
pub use train_presets::{car_preset, train_preset, CAR_PRESETS, TRAIN_PRESETS};
pub use train_spec::{CarSpec, RepresentationSpec, TrainSpec, MAX_CARS};
pub use truck_spec::{ArticulatedSpec, RigidTruckSpec, ARTICULATED_PRESETS, RIGID_TRUCK_PRESETS};

#[cfg(test)]
mod tests;
