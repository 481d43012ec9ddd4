//! A 20 t truck on the paper bridge: against Fryba's moving forces of its static axle
//! loads, and against the coupled modal reference `analytic::vehicle_crossing` on a level
//! road and over a 10 mm bump, where the interaction is what is checked.

use nalgebra::{DMatrix, DVector};

use crate::error::{Error, Result};
use crate::physics::bridge::{BeamProperties, BridgeModel, PointQuantity, SparseVec};
use crate::physics::road::{LevelRoad, RoadProfileSpec, RoadSurface};
use crate::physics::solver::{ContactLaw, CoupledVehicle, Stepper};
use crate::physics::vehicle::{VehicleDynamics, GRAVITY_M_S2};
use crate::studies::analytic::{
    LinearVehicle, ModalDamping, MovingForceSolution, MovingLoadTrain, RoadIrregularity,
    SimplySupportedBeam, Tyre, VehicleCrossingOptions, VehicleCrossingProblem,
};
use crate::studies::verify::CheckRow;
use crate::studies::DIVERGENCE_HINT;

use super::{analytic_beam, coupled, deterministic_road, fe, half_car, lumped};

const GROUP: &str = "vbi_truck";
const SPEEDS_M_S: [f64; 3] = [10.0, 20.0, 30.0];
const DT_S: f64 = 1e-3;
const APPROACH_M: f64 = 30.0;
/// The bump of the rough-road rows: 10 mm high, 3 m long, crest 6 m onto the span. At 20
/// and 30 m/s it passes in 0.15 and 0.1 s, between the body modes (1.6-2.3 Hz) and the
/// axle hop (10-15 Hz), and drives the tyre forces 15-50 % off static.
const BUMP_POSITION_M: f64 = 6.0;
const BUMP_LENGTH_M: f64 = 3.0;
const BUMP_HEIGHT_M: f64 = 0.010;
/// Modes of the coupled reference. With the bridge's Rayleigh damping the top mode is
/// overdamped with |lambda| ~ a1 w_N^2, which caps the explicit step: cost grows as N^5
/// (N = 25 costs 15x N = 12). 12 modes leave a truncation bound of <= 1.6e-4 of the peak
/// (the bound row below keeps it there).
const REFERENCE_MODES: usize = 12;
/// Largest truncation bound of the reference accepted, relative to its peak: it enters the
/// tolerance of the coupled rows, and 2e-4 keeps that tolerance below a tenth of the
/// interaction at 20 m/s on the level road (3.4e-3), so that a solver without the
/// interaction fails there.
const MAX_REFERENCE_BOUND: f64 = 2e-4;
/// The error the bridge models leave on the peak at dt = 1 ms, relative: sampling the
/// peak once per step misses at most (w1 dt)^2 / 8 = 7e-5 of mode 1's part of it; mode
/// 1's period error (w1 dt)^2 / 12 = 4.7e-5 per radian over the < 1 rad of vibration
/// before the peak, on a dynamic part of < 25 % of the peak, adds ~1e-5; the vehicle's
/// modes (body 1.6-2.3 Hz: 1.8e-5 per radian; axle hop, whose forces reach the span
/// far above its resonance) less; 20 Hermite elements and 29 lumped masses leave < 2.5e-5
/// on the static axle loads (the moving-force comparison below measures it: Fryba rows at
/// 10 m/s). Sum rounded up: 1e-4 (measured against 50 reference modes: <= 3.8e-5).
const MODEL_ERROR: f64 = 1e-4;

/// two_axle_truck with its body mass set to 17 500 kg (gross 20 000 kg instead of the
/// preset's 20 235 kg), from 30 m before the paper bridge (30 m, f1 = 3.78 Hz, 2 %
/// Rayleigh damping) at 10, 20 and 30 m/s, on FE 20 and lumped 29:
/// - on a smooth road, against Fryba's moving forces with the truck's static axle loads
///   (docs/physics.md section 5.1): the claim that this truck can be replaced by its
///   static loads to 1 %;
/// - on a smooth road and over the bump, against the coupled half car of
///   `analytic::vehicle_crossing` (docs/physics.md section 5.8), with the same Rayleigh
///   curve: the interaction itself. Tolerance: the reference's truncation bound plus
///   [`MODEL_ERROR`].
///
/// Plus one row per reference case: its truncation bound against
/// [`MAX_REFERENCE_BOUND`].
pub fn truck_vs_moving_forces() -> Result<Vec<CheckRow>> {
    let beam = BeamProperties::paper_default();
    let ab = analytic_beam(&beam)?;
    let truck = half_car("two_axle_truck", Some(17_500.0))?;
    let reference_vehicle = pitch_plane_reference(&truck)?;
    let bump_road = deterministic_road(
        &RoadProfileSpec::Bump {
            position_m: BUMP_POSITION_M,
            length_m: BUMP_LENGTH_M,
            height_m: BUMP_HEIGHT_M,
        },
        -APPROACH_M - 10.0,
        2.0 * beam.length_m() + 10.0,
    )?;
    let models = [
        BridgeModel::build(&beam, &fe(20), 0.02)?,
        BridgeModel::build(&beam, &lumped(29), 0.02)?,
    ];
    let mid = 0.5 * beam.length_m();
    let mut rows = Vec::new();
    // The models' peaks on the level road serve both comparisons.
    let mut level_peaks = Vec::new();
    // Fryba's moving forces, per model (each model's own Rayleigh curve) and speed.
    for model in &models {
        let damping = rayleigh(model);
        for speed in SPEEDS_M_S {
            let value = truck_peak(model, &LevelRoad, &truck, speed)?;
            level_peaks.push(value);
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
            // Whether the solver has the interaction at all is checked by the coupled rows.
            rows.push(CheckRow::relative(
                GROUP,
                format!("peak midspan 20 t truck v={speed} {}", model.spec.label()),
                "Fryba, static axle loads (m)",
                ref_peak,
                value,
                1e-2,
            ));
        }
    }
    // The coupled reference, per road and speed, shared by both models: the FE and lumped
    // models fit their Rayleigh curves on their own modes 1 and 2, which agree to < 1e-4,
    // so the reference takes FE 20's; the difference in damping this leaves is < 1e-6 of
    // the peak (2 % damping, a 1e-4 change of it, on a dynamic part of < 25 %).
    let damping = rayleigh(&models[0]);
    for bumpy in [false, true] {
        let road_label = if bumpy { "10 mm bump" } else { "level" };
        for (k, speed) in SPEEDS_M_S.into_iter().enumerate() {
            let reference = coupled_reference(ab, &reference_vehicle, damping, speed, bumpy)?;
            let ref_peak = reference.peak_midspan_deflection_m;
            let bound = reference.truncation_bound_m / ref_peak;
            rows.push(CheckRow::with_error(
                GROUP,
                format!("reference truncation bound v={speed} {road_label}"),
                "bound / peak",
                0.0,
                bound,
                bound,
                MAX_REFERENCE_BOUND,
            ));
            for (m, model) in models.iter().enumerate() {
                let value = if bumpy {
                    truck_peak(model, &bump_road, &truck, speed)?
                } else {
                    level_peaks[m * SPEEDS_M_S.len() + k]
                };
                rows.push(CheckRow::relative(
                    GROUP,
                    format!(
                        "peak midspan 20 t truck v={speed} {road_label} {}",
                        model.spec.label()
                    ),
                    TRUCK_COUPLED_REFERENCE,
                    ref_peak,
                    value,
                    bound + MODEL_ERROR,
                ));
            }
        }
    }
    Ok(rows)
}

/// The `reference` of the coupled rows (tests find them by it).
pub const TRUCK_COUPLED_REFERENCE: &str = "coupled half car, 12 modes (m)";

fn rayleigh(model: &BridgeModel) -> ModalDamping {
    ModalDamping::Rayleigh {
        a0: model.rayleigh.a0_per_s,
        a1: model.rayleigh.a1_s,
    }
}

/// Peak midspan deflection (downward positive) of the truck crossing `model` from 30 m
/// before it, at dt = 1 ms, until its rear axle has left.
fn truck_peak(
    model: &BridgeModel,
    road: &dyn RoadSurface,
    truck: &VehicleDynamics,
    speed_m_s: f64,
) -> Result<f64> {
    let span = model.length_m();
    let mut solver = coupled(model, road, DT_S, ContactLaw::Full)?;
    solver.add_vehicle(CoupledVehicle::new(
        0,
        truck.clone(),
        speed_m_s,
        -APPROACH_M,
        0,
    ));
    let travel_m = APPROACH_M + span + truck.wheelbase_m();
    let steps = (travel_m / (speed_m_s * DT_S)).ceil() as u64;
    let mut op = SparseVec::with_capacity(model.n_dof());
    let mut value = f64::NEG_INFINITY;
    let stepper = Stepper::new(model, DIVERGENCE_HINT);
    for _ in 0..steps {
        stepper.advance(&mut solver)?;
        value =
            value.max(-solver.bridge_response(0.5 * span, PointQuantity::Deflection, 0, &mut op));
    }
    Ok(value)
}

/// The coupled modal reference: the truck's front axle starts at the entry (on the level
/// approach it sits in static equilibrium, so the 30 m the models run first change
/// nothing), the bump is the analytic module's own cosine bump.
fn coupled_reference(
    beam: SimplySupportedBeam,
    vehicle: &LinearVehicle,
    damping: ModalDamping,
    speed_m_s: f64,
    bumpy: bool,
) -> Result<crate::studies::analytic::VehicleCrossingSolution> {
    let problem = VehicleCrossingProblem {
        beam,
        vehicle: vehicle.clone(),
        speed_m_s,
        start_front_m: 0.0,
        road: if bumpy {
            Some(RoadIrregularity::cosine_bump(
                BUMP_POSITION_M,
                BUMP_LENGTH_M,
                BUMP_HEIGHT_M,
            )?)
        } else {
            None
        },
        options: VehicleCrossingOptions {
            n_modes: REFERENCE_MODES,
            damping,
            gravity_m_s2: GRAVITY_M_S2,
            ..Default::default()
        },
    };
    problem.solve(&[problem.exit_time_s()])
}

/// The truck as the reference's linear vehicle, assembled here from its named parameters
/// by docs/physics.md section 6.1 (not from the model's matrices, so that an error in
/// those would show): DOFs body bounce, body pitch and one hop per axle, downward
/// positive; static axle loads by the lever rule. Two axles only.
fn pitch_plane_reference(truck: &VehicleDynamics) -> Result<LinearVehicle> {
    let parameter = |name: &str| {
        truck
            .parameters
            .iter()
            .find(|(n, _)| n == name)
            .map(|&(_, v)| v)
            .ok_or_else(|| {
                Error::invalid(
                    format!("vehicle.parameters.{name}"),
                    "missing",
                    "the coupled reference needs every half-car parameter",
                )
            })
    };
    if truck.axles.len() != 2 {
        return Err(Error::invalid(
            "vehicle.axles",
            truck.axles.len(),
            "the coupled reference takes a two-axle half car",
        ));
    }
    let body_kg = parameter("body_mass_kg")?;
    let cg_m = parameter("cg_behind_front_m")?;
    let mut mass = DMatrix::zeros(4, 4);
    mass[(0, 0)] = body_kg;
    mass[(1, 1)] = parameter("pitch_inertia_kg_m2")?;
    let mut stiffness = DMatrix::zeros(4, 4);
    let mut damping = DMatrix::zeros(4, 4);
    let mut offsets = [0.0; 2];
    let mut tyres = Vec::new();
    for j in 0..2 {
        let p = |what: &str| parameter(&format!("axle_{}_{what}", j + 1));
        offsets[j] = p("offset_m")?;
        mass[(2 + j, 2 + j)] = p("mass_kg")?;
        // The body point above axle j moves y_B + d_j theta (d_j ahead of the CG); the
        // suspension couples it to the axle hop y_j.
        let d = cg_m - offsets[j];
        let lever = DVector::from_vec(vec![
            1.0,
            d,
            if j == 0 { -1.0 } else { 0.0 },
            if j == 1 { -1.0 } else { 0.0 },
        ]);
        let outer = &lever * lever.transpose();
        stiffness += &outer * p("suspension_stiffness_n_m")?;
        damping += &outer * p("suspension_damping_n_s_m")?;
        tyres.push(Tyre {
            offset_m: offsets[j],
            dof: 2 + j,
            stiffness_n_m: p("tyre_stiffness_n_m")?,
            damping_n_s_m: p("tyre_damping_n_s_m")?,
            static_load_n: 0.0,
        });
    }
    // Lever rule: the body's weight splits in the ratio of the CG's distances to the
    // axles; each axle carries its own.
    let wheelbase_m = offsets[1] - offsets[0];
    let front_share = (offsets[1] - cg_m) / wheelbase_m;
    for (j, share) in [front_share, 1.0 - front_share].into_iter().enumerate() {
        tyres[j].static_load_n = GRAVITY_M_S2 * (share * body_kg + mass[(2 + j, 2 + j)]);
    }
    Ok(LinearVehicle {
        mass,
        damping,
        stiffness,
        tyres,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The reference's vehicle has the model's matrices and static loads (built
    /// independently, so a disagreement would show here first).
    #[test]
    fn reference_vehicle_matches_the_model() {
        let truck = half_car("two_axle_truck", Some(17_500.0)).unwrap();
        let reference = pitch_plane_reference(&truck).unwrap();
        let close =
            |a: &DMatrix<f64>, b: &DMatrix<f64>| (a - b).abs().max() <= 1e-9 * b.abs().max();
        assert!(close(&reference.mass, &truck.mass));
        assert!(close(&reference.stiffness, &truck.stiffness));
        assert!(close(&reference.damping, &truck.damping));
        for (tyre, axle) in reference.tyres.iter().zip(&truck.axles) {
            assert_eq!(Some(tyre.dof), axle.dof);
            assert_eq!(tyre.offset_m, axle.offset_m);
            assert_eq!(tyre.stiffness_n_m, axle.tyre_stiffness_n_m);
            assert_eq!(tyre.damping_n_s_m, axle.tyre_damping_n_s_m);
            assert!((tyre.static_load_n - axle.static_load_n).abs() < 1e-6);
        }
    }
}
