//! Vehicles: linear pitch-plane models seen by the solver as matrices plus tyre contacts.

mod dynamics;
mod models;
mod spec;

pub use dynamics::{Axle, VehicleDynamics, GRAVITY_M_S2};
pub use models::{quarter_car, rigid_body_on_axles, sprung_mass, AxleParams};
pub use spec::{HalfCarSpec, VehicleModelSpec, HALF_CAR_PRESETS};

#[cfg(test)]
mod tests;
