//! A 20 t truck on a smooth road against Fryba's moving forces of its static axle loads.

use crate::error::Result;
use crate::physics::bridge::{BeamProperties, BridgeModel, PointQuantity, SparseVec};
use crate::physics::road::LevelRoad;
use crate::physics::solver::{ContactLaw, CoupledVehicle, Stepper};
use crate::studies::analytic::{ModalDamping, MovingForceSolution, MovingLoadTrain};
use crate::studies::verify::CheckRow;
use crate::studies::DIVERGENCE_HINT;

use super::{analytic_beam, coupled, fe, half_car, lumped};

/// two_axle_truck with its body mass set to 17 500 kg (gross 20 000 kg instead of the
/// preset's 20 235 kg), from 30 m before the paper bridge (30 m, f1 = 3.78 Hz, 2 %
/// Rayleigh damping) at 10, 20 and 30 m/s on a smooth road: peak midspan deflection
/// against Fryba's moving forces with the truck's static axle loads.
pub fn truck_vs_moving_forces() -> Result<Vec<CheckRow>> {
    const GROUP: &str = "vbi_truck";
    let beam = BeamProperties::paper_default();
    let ab = analytic_beam(&beam)?;
    let truck = half_car("two_axle_truck", Some(17_500.0))?;
    let dt_s = 1e-3;
    let approach_m = 30.0;
    let mid = 0.5 * beam.span_m;
    let mut rows = Vec::new();
    for spec in [fe(20), lumped(29)] {
        let model = BridgeModel::build(&beam, &spec, 0.02)?;
        let damping = ModalDamping::Rayleigh {
            a0: model.rayleigh.a0_per_s,
            a1: model.rayleigh.a1_s,
        };
        for speed in [10.0, 20.0, 30.0] {
            let mut solver = coupled(&model, &LevelRoad, dt_s, ContactLaw::Full)?;
            solver.add_vehicle(CoupledVehicle::new(0, truck.clone(), speed, -approach_m, 0));
            let travel_m = approach_m + beam.span_m + truck.wheelbase_m();
            let steps = (travel_m / (speed * dt_s)).ceil() as u64;
            let mut op = SparseVec::with_capacity(model.n_dof());
            let mut value = f64::NEG_INFINITY;
            let stepper = Stepper::new(&model, DIVERGENCE_HINT);
            for _ in 0..steps {
                stepper.advance(&mut solver)?;
                value =
                    value.max(-solver.bridge_response(mid, PointQuantity::Deflection, 0, &mut op));
            }
            let train = MovingLoadTrain {
                loads: truck
                    .axles
                    .iter()
                    .map(|a| (a.offset_m, a.static_load_n))
                    .collect(),
            };
            let reference = MovingForceSolution::for_train(ab, &train, speed, damping, 100)?;
            let (_, ref_peak) = reference.peak_deflection_m(mid, reference.exit_time_s());
            // The difference is the interaction itself, not an error: on a smooth road the
            // truck is excited only through the wheel path on the deflecting bridge, and
            // its dynamic tyre forces relative to its weight are of order
            // (a_bridge + v^2 w'') / g: at 30 m/s the bridge's vibration (DAF - 1) w1^2
            // delta ~ 3e-3 g and the path's curvature v^2 (pi / L)^2 delta ~ 2e-3 g, which
            // the lightly damped body bounce (3.6 %) amplifies; they grow with speed
            // (measured: 5e-5, 3.4e-3, 8.3e-3 at 10, 20, 30 m/s). Allowed: 1 %, the claim
            // under test (a 20 t truck on this 360 t span can be replaced by its static
            // axle loads to 1 %); the discretization adds <= 1e-3 (moving_force group).
            rows.push(CheckRow::relative(
                GROUP,
                format!("peak midspan 20 t truck v={speed} {}", spec.label()),
                "Fryba, static axle loads (m)",
                ref_peak,
                value,
                1e-2,
            ));
        }
    }
    Ok(rows)
}
