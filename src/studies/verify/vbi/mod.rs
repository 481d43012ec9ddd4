//! Checks of the coupled vehicle-bridge solver (VBI) and the road input: equilibrium,
//! static loads, harmonic response on a rigid road, the sprung mass crossing a beam, the
//! moving-force and moving-mass limits, a 20 t truck, ISO 8608 statistics and unilateral
//! contact. docs/physics.md sections 6-9.
//!
//! Sign conventions: the solver is upward positive, the analytical module downward
//! positive; every comparison below negates the solver's deflections.

mod contact;
mod equilibrium;
mod harmonic;
mod limits;
mod road;
mod sprung_mass;
mod static_loads;
mod truck;

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use crate::error::Result;
use crate::physics::bridge::{BeamProperties, BridgeModel, LumpedStiffness, ModelSpec};
use crate::physics::road::{RoadProfile, RoadProfileSpec, RoadSurface};
use crate::physics::solver::{
    ContactLaw, CoupledSolver, NewmarkCoefficients, NewmarkParams, SolveMode, Storage,
};
use crate::physics::vehicle::{HalfCarSpec, VehicleDynamics, VehicleModelSpec};
use crate::studies::analytic::SimplySupportedBeam;

pub use contact::unilateral_contact;
pub use equilibrium::approach_equilibrium;
pub use harmonic::sine_road_response;
pub use limits::suspension_limits;
pub use road::road_profiles;
pub use sprung_mass::sprung_mass_crossing;
pub use static_loads::static_loads;
pub use truck::{truck_vs_moving_forces, TRUCK_COUPLED_REFERENCE};

/// The VBI-2D verification beam (docs/physics.md section 6): 25 m, E 3.5e10 Pa, I 1.3901 m^4,
/// m 18 358 kg/m (f1 = 4.09 Hz).
fn vbi_beam() -> BeamProperties {
    BeamProperties::simply_supported(25.0, 3.5e10 * 1.3901, 18_358.0)
}

fn analytic_beam(beam: &BeamProperties) -> Result<SimplySupportedBeam> {
    SimplySupportedBeam::new(
        beam.length_m(),
        beam.flexural_rigidity_n_m2,
        beam.mass_per_length_kg_m,
    )
}

fn fe(elements: usize) -> ModelSpec {
    ModelSpec::FiniteElement { elements }
}

fn lumped(nodes: usize) -> ModelSpec {
    ModelSpec::LumpedMass {
        nodes,
        stiffness: LumpedStiffness::Auto,
    }
}

/// A half car from its preset, with optional body-mass override.
fn half_car(preset: &str, body_mass_kg: Option<f64>) -> Result<VehicleDynamics> {
    VehicleModelSpec::HalfCar(HalfCarSpec {
        preset: Some(preset.to_string()),
        body_mass_kg,
        ..Default::default()
    })
    .build("vehicle")
}

fn coupled<'a>(
    model: &'a BridgeModel,
    road: &'a dyn RoadSurface,
    dt_s: f64,
    law: ContactLaw,
) -> Result<CoupledSolver<'a>> {
    let coefficients = NewmarkCoefficients::new(dt_s, NewmarkParams::default())?;
    CoupledSolver::new(
        model,
        road,
        coefficients,
        SolveMode::Prefactored(Storage::Dense),
        law,
    )
}

fn max_abs(values: impl IntoIterator<Item = f64>) -> f64 {
    values.into_iter().fold(0.0, |m, v| m.max(v.abs()))
}

fn deterministic_road(spec: &RoadProfileSpec, x_start_m: f64, x_end_m: f64) -> Result<RoadProfile> {
    // Deterministic shapes draw nothing from the generator.
    let mut rng = ChaCha8Rng::seed_from_u64(0);
    RoadProfile::build(spec, x_start_m, x_end_m, &mut rng)
}

/// The largest value (the peak of a downward-positive deflection history).
fn peak(values: &[f64]) -> f64 {
    values.iter().copied().fold(f64::NEG_INFINITY, f64::max)
}
