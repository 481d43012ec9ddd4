//! The VBI-2D sprung mass crossing its beam, level and over a ramp, against
//! `analytic::sprung_mass`.

use crate::error::Result;
use crate::physics::bridge::{BridgeModel, PointQuantity, SparseVec};
use crate::physics::road::{LevelRoad, RoadProfileSpec, RoadSurface};
use crate::physics::solver::{ContactLaw, CoupledVehicle, Stepper};
use crate::physics::vehicle::{sprung_mass, VehicleDynamics, GRAVITY_M_S2};
use crate::studies::analytic::{
    RoadIrregularity, SprungMassOptions, SprungMassProblem, SprungMassVehicle,
};
use crate::studies::verify::CheckRow;
use crate::studies::DIVERGENCE_HINT;

use super::{analytic_beam, coupled, deterministic_road, fe, lumped, peak, vbi_beam};

pub(super) const SPRUNG_MASS_KG: f64 = 5_750.0;
pub(super) const SPRUNG_STIFFNESS_N_M: f64 = 1.595e6;
pub(super) const SPRUNG_SPEED_M_S: f64 = 25.0;
/// The VBI-2D ramp: 0 up to x = 5 m, linear to +10 mm at 10 m, +10 mm beyond.
const RAMP_START_M: f64 = 5.0;
const RAMP_END_M: f64 = 10.0;
const RAMP_HEIGHT_M: f64 = 0.010;

/// Midspan deflection history (DOWNWARD positive, one value per step from t = 0 to the
/// exit L / v) of a sprung mass on the numerical model, starting like the analytical
/// mass: at x = 0, t = 0 (front position 0, entry step 0), in static equilibrium.
pub(super) fn sprung_mass_history(
    model: &BridgeModel,
    road: &dyn RoadSurface,
    vehicle: VehicleDynamics,
    speed_m_s: f64,
    dt_s: f64,
) -> Result<Vec<f64>> {
    let mut solver = coupled(model, road, dt_s, ContactLaw::Full)?;
    solver.add_vehicle(CoupledVehicle::new(0, vehicle, speed_m_s, 0.0, 0));
    let span = model.length_m();
    let steps = (span / (speed_m_s * dt_s)).round() as u64;
    let mut op = SparseVec::with_capacity(model.n_dof());
    let mut history = vec![0.0];
    let stepper = Stepper::new(model, DIVERGENCE_HINT);
    for _ in 0..steps {
        stepper.advance(&mut solver)?;
        history.push(-solver.bridge_response(0.5 * span, PointQuantity::Deflection, 0, &mut op));
    }
    Ok(history)
}

/// Modes of the analytical references in the ladder. Cost grows as N^3 (sprung_mass
/// module docs); 25 modes cost 1/8 of 50. Truncation: each solution carries a bound on
/// its mode-truncation error (docs/physics.md section 5.7), at 25 modes <= 7.3e-5 of the
/// peak for the four cases here; the bound rows keep it below [`MAX_REFERENCE_BOUND`].
/// (Measured: 25 and 100 modes differ by <= 3.7e-6.)
pub(super) const REFERENCE_MODES: usize = 25;

/// Largest truncation bound of the reference accepted, relative to its peak: it enters
/// the rows' tolerance, and 1e-4 keeps that tolerance at <= 3e-4 (the ramp's kinks
/// aside), a third of the smallest interaction effect here (9e-4, the dashpot on the
/// level road), so that a reference without the interaction fails.
const MAX_REFERENCE_BOUND: f64 = 1e-4;

/// What the bridge models may leave on the peak and on the history rms, relative to the
/// peak (derived where the rows are built).
const MODEL_ERROR: f64 = 2e-4;

/// The four VBI-2D sprung-mass cases (suspension damping 0 or 400 kN s/m, level road or
/// the 10 mm ramp over x = 5..10 m) on Hermite FE (20 elements) and lumped masses (49),
/// dt = 0.25 ms, against `analytic::sprung_mass` (docs/physics.md section 5.3): peak
/// midspan deflection while the mass is on the beam, and the whole history, from t = 0 to
/// the exit; and per case the reference's truncation bound.
pub fn sprung_mass_crossing() -> Result<Vec<CheckRow>> {
    const GROUP: &str = "vbi_sprung_mass";
    let beam = vbi_beam();
    let ab = analytic_beam(&beam)?;
    let dt_s = 2.5e-4;
    let models = [
        BridgeModel::build(&beam, &fe(20), 0.0)?,
        BridgeModel::build(&beam, &lumped(49), 0.0)?,
    ];
    // The same road for both: the analytical module's closure and the road module's
    // closed-form `ramp` shape.
    let ramp_spec = RoadProfileSpec::Ramp {
        start_m: RAMP_START_M,
        length_m: RAMP_END_M - RAMP_START_M,
        height_m: RAMP_HEIGHT_M,
    };
    let ramp_road = deterministic_road(&ramp_spec, -10.0, 60.0)?;
    let exit_s = beam.length_m() / SPRUNG_SPEED_M_S;
    let steps = (exit_s / dt_s).round() as usize;
    let times: Vec<f64> = (0..=steps).map(|i| i as f64 * dt_s).collect();
    let mut rows = Vec::new();
    for damping in [0.0, 4.0e5] {
        for ramp in [false, true] {
            let problem = SprungMassProblem {
                beam: ab,
                vehicle: SprungMassVehicle {
                    mass_kg: SPRUNG_MASS_KG,
                    stiffness_n_m: SPRUNG_STIFFNESS_N_M,
                    damping_n_s_m: damping,
                },
                speed_m_s: SPRUNG_SPEED_M_S,
                road: if ramp {
                    Some(RoadIrregularity::linear_ramp(
                        RAMP_START_M,
                        RAMP_END_M,
                        RAMP_HEIGHT_M,
                    )?)
                } else {
                    None
                },
                options: SprungMassOptions {
                    n_modes: REFERENCE_MODES,
                    gravity_m_s2: GRAVITY_M_S2,
                    ..Default::default()
                },
            };
            let reference = problem.solve(&times)?;
            let ref_peak = reference.peak_midspan_deflection_on_beam_m;
            let bound = reference.truncation_bound_m / ref_peak;
            rows.push(CheckRow::with_error(
                GROUP,
                format!(
                    "reference truncation bound c={} kN s/m {}",
                    damping / 1e3,
                    if ramp { "10 mm ramp" } else { "level" }
                ),
                "bound / peak",
                0.0,
                bound,
                bound,
                MAX_REFERENCE_BOUND,
            ));
            for model in &models {
                let road: &dyn RoadSurface = if ramp { &ramp_road } else { &LevelRoad };
                let vehicle = sprung_mass(SPRUNG_MASS_KG, SPRUNG_STIFFNESS_N_M, damping);
                let history = sprung_mass_history(model, road, vehicle, SPRUNG_SPEED_M_S, dt_s)?;
                let rms = (history
                    .iter()
                    .zip(&reference.samples)
                    .map(|(w, s)| (w - s.midspan_deflection_m).powi(2))
                    .sum::<f64>()
                    / history.len() as f64)
                    .sqrt();
                let what = format!(
                    "{} c={} kN s/m {}",
                    model.spec.label(),
                    damping / 1e3,
                    if ramp { "10 mm ramp" } else { "level" }
                );
                // Error budget at dt = 0.25 ms: Newmark's period error (w dt)^2/12 is 3e-6
                // on mode 1 and 1e-6 on the mass (2.6 Hz); sampling the peak every dt
                // costs < (w1 dt)^2 / 8 = 5e-6; the moving point load itself converges
                // more slowly than dt^2 (the moving_force harness on this beam, 40 elements:
                // history rms 6e-5, 2.3e-5, 8e-6 of the peak at dt = 0.5, 0.25, 0.125 ms);
                // 49 lumped masses leave ~1e-4 on mode 1, 20 elements far less (frequency
                // rows). Sum 1.3e-4; allowed [`MODEL_ERROR`] = 2e-4 plus the reference's
                // truncation bound (< 1e-4, its own row). Measured: peaks <= 3.6e-5,
                // history rms <= 2.4e-5. The sprung mass's weight as a moving force (a
                // reference without the interaction) is 9e-4 to 0.22 away from these
                // peaks, so the rows can tell (tests/suite/verification.rs checks that they do).
                // With the dashpot on the ramp, the
                // dashpot force jumps by c v dr/dx at the ramp's two kinks, and a jump
                // inside a step is integrated by the trapezoidal rule with an impulse
                // error of up to (jump) dt / 2, i.e. a mode-1 deflection error of
                // (jump) dt / (M_b w1) for both kinks together: added to the tolerance.
                let jump_n =
                    damping * SPRUNG_SPEED_M_S * RAMP_HEIGHT_M / (RAMP_END_M - RAMP_START_M);
                let kinks = if ramp {
                    jump_n * dt_s / (ab.modal_mass_kg() * ab.omega_rad_s(1)) / ref_peak
                } else {
                    0.0
                };
                rows.push(CheckRow::relative(
                    GROUP,
                    format!("peak midspan {what}"),
                    "sprung_mass 25 modes (m)",
                    ref_peak,
                    peak(&history),
                    MODEL_ERROR + bound + kinks,
                ));
                rows.push(CheckRow::with_error(
                    GROUP,
                    format!("history rms {what}"),
                    "sprung_mass 25 modes (rms / peak)",
                    0.0,
                    rms,
                    rms / ref_peak,
                    MODEL_ERROR + bound + kinks,
                ));
            }
        }
    }
    Ok(rows)
}
