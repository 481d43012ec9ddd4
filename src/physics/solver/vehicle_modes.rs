//! Natural frequencies of a vehicle on a rigid road. The generalized eigen solver is the
//! bridge's (`bridge::generalized_modes`) and the matrices are the vehicle's: bridge and
//! vehicle meet only here in the solver, so neither imports the other.

use crate::error::Result;
use crate::physics::bridge::generalized_modes;
use crate::physics::vehicle::VehicleDynamics;

/// Undamped natural frequencies (Hz, ascending) of `vehicle` with its tyres on a rigid
/// road: `K_t phi = omega^2 M phi`, `K_t` the suspension stiffness with the tyre springs
/// attached. None for a moving force (no DOFs).
pub fn vehicle_natural_frequencies_hz(vehicle: &VehicleDynamics) -> Result<Vec<f64>> {
    if vehicle.n_dof() == 0 {
        return Ok(Vec::new());
    }
    let modes = generalized_modes(&vehicle.stiffness_with_tyres(), &vehicle.mass)?;
    Ok(modes
        .omega_rad_s
        .iter()
        .map(|w| w / (2.0 * std::f64::consts::PI))
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::vehicle::{HalfCarSpec, VehicleModelSpec};

    #[test]
    fn two_axle_truck_frequencies_match_physics_md() {
        // docs/physics.md: modes about 1.6, 2.3, 10.3, 15.1 Hz (derived; two significant digits).
        let truck = VehicleModelSpec::HalfCar(HalfCarSpec {
            preset: Some("two_axle_truck".into()),
            ..Default::default()
        })
        .build("vehicles.0.model")
        .unwrap();
        let f = vehicle_natural_frequencies_hz(&truck).unwrap();
        for (got, want) in f.iter().zip([1.6, 2.3, 10.3, 15.1]) {
            assert!((got - want).abs() < 0.05 * want, "{f:?}");
        }
    }

    #[test]
    fn a_moving_force_has_no_modes() {
        let force = VehicleDynamics::moving_forces(&[1e5], &[0.0]);
        assert!(vehicle_natural_frequencies_hz(&force).unwrap().is_empty());
    }
}
