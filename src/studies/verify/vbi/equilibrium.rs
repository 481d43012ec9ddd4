//! Vehicles on the rigid approach stay in their static equilibrium (docs/physics.md section 9).

use nalgebra::DVector;

use crate::error::Result;
use crate::physics::bridge::BridgeModel;
use crate::physics::road::ConstantRoad;
use crate::physics::solver::{ContactLaw, CoupledVehicle, Stepper};
use crate::studies::verify::CheckRow;
use crate::studies::DIVERGENCE_HINT;

use super::{coupled, fe, half_car, max_abs, vbi_beam};

/// Vehicles driving 5 s on a rigid smooth approach (the bridge 300 m ahead) stay in their
/// static equilibrium: a level road and a road raised by 50 mm everywhere (the vehicle
/// starts translated by 50 mm, `equilibrium_on_road`).
pub fn approach_equilibrium() -> Result<Vec<CheckRow>> {
    const GROUP: &str = "vbi_equilibrium";
    let model = BridgeModel::build(&vbi_beam(), &fe(4), 0.02)?;
    let mut rows = Vec::new();
    for preset in ["two_axle_truck", "vbi2d_e01"] {
        for raise_m in [0.0, 0.05] {
            let road = ConstantRoad {
                elevation_m: raise_m,
            };
            let mut solver = coupled(&model, &road, 1e-3, ContactLaw::Full)?;
            let vehicle = half_car(preset, None)?;
            // A raised rigid road translates every DOF by the same amount (no pitch).
            let expected = DVector::from_vec(vec![raise_m, 0.0, raise_m, raise_m]);
            let statics: Vec<f64> = vehicle.axles.iter().map(|a| a.static_load_n).collect();
            solver.add_vehicle(CoupledVehicle::new(0, vehicle, 20.0, -400.0, 0));
            let (mut max_y, mut max_force) = (0.0f64, 0.0f64);
            let stepper = Stepper::new(&model, DIVERGENCE_HINT);
            for _ in 0..5000 {
                stepper.advance(&mut solver)?;
                let v = &solver.vehicles[0];
                max_y = max_y.max(max_abs((&v.state.u - &expected).iter().copied()));
                for (f, s) in v.contact_force_n.iter().zip(&statics) {
                    max_force = max_force.max(((f - s) / s).abs());
                }
            }
            let what = format!("{preset}, road at {raise_m} m, 20 m/s for 5 s");
            // Round-off only: the state starts exactly at equilibrium and the step maps
            // equilibrium to itself; the residual is the LU solve's, ~1e-16 of the 50 mm
            // offset per step, and a stable step does not accumulate it.
            rows.push(CheckRow::with_error(
                GROUP,
                format!("max |y - y_eq| {what}"),
                "static equilibrium (m)",
                0.0,
                max_y,
                max_y,
                1e-12,
            ));
            rows.push(CheckRow::with_error(
                GROUP,
                format!("max |F - F_static| / F_static {what}"),
                "static axle loads",
                0.0,
                max_force,
                max_force,
                1e-10,
            ));
        }
    }
    Ok(rows)
}
