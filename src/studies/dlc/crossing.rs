//! One crossing of the truck over the bridge: the time loop and what it records (tyre
//! force statistics on the span, the midspan peaks).

use crate::error::Result;
use crate::physics::bridge::{BridgeModel, ModelSpec, PointQuantity, SparseVec};
use crate::physics::road::RoadSurface;
use crate::physics::solver::{
    ContactLaw, CoupledSolver, CoupledVehicle, NewmarkCoefficients, NewmarkParams, SolveMode,
    Stepper, Storage,
};
use crate::physics::vehicle::VehicleDynamics;
use crate::studies::DIVERGENCE_HINT;

use super::DlcSetup;

/// What one crossing gives. Forces are total tyre forces over the static axle load, taken
/// while the axle is on the span; the bridge peaks are at midspan over the whole run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Crossing {
    /// max F / F_static per axle (front, rear): the paper's DLC.
    pub dlc: [f64; 2],
    /// std(F) / F_static per axle: the classic DLC.
    pub sigma_ratio: [f64; 2],
    /// min F / F_static per axle (negative: the linear tyre pulls, contact lost).
    pub min_ratio: [f64; 2],
    /// Largest downward midspan deflection (m, positive down).
    pub peak_deflection_m: f64,
    /// Largest |midspan acceleration| (m/s^2).
    pub peak_acceleration_m_s2: f64,
}

pub(super) fn storage_for(spec: &ModelSpec) -> Storage {
    match spec {
        // Hermite FE matrices are banded: sparse Cholesky keeps the band.
        ModelSpec::FiniteElement { .. } => Storage::Sparse,
        _ => Storage::Dense,
    }
}

/// Runs one crossing of `vehicle` at `speed_m_s`, from `approach_m` before the bridge until
/// the rear axle leaves it (plus `free_time_s` of free vibration).
pub fn simulate_crossing(
    setup: &DlcSetup,
    model: &BridgeModel,
    vehicle: &VehicleDynamics,
    road: &dyn RoadSurface,
    speed_m_s: f64,
    free_time_s: f64,
) -> Result<Crossing> {
    let coefficients = NewmarkCoefficients::new(setup.dt_s, NewmarkParams::default())?;
    let mode = SolveMode::Prefactored(storage_for(&model.spec));
    let mut solver = CoupledSolver::new(model, road, coefficients, mode, ContactLaw::Full)?;
    let stepper = Stepper::new(model, DIVERGENCE_HINT);
    let start_m = -setup.approach_m;
    solver.add_vehicle(CoupledVehicle::new(
        0,
        vehicle.clone(),
        speed_m_s,
        start_m,
        0,
    ));
    let span = model.length_m();
    let travel_m = span + vehicle.wheelbase_m() - start_m + speed_m_s * free_time_s;
    let steps = (travel_m / (speed_m_s * setup.dt_s)).ceil() as u64;
    let mut mid = SparseVec::with_capacity(model.n_dof());
    model.point_operator(0.5 * span, PointQuantity::Deflection, &mut mid);
    let axles = vehicle.axles.len().min(2);
    let mut force = [Moments::default(); 2];
    let (mut peak_u, mut peak_a) = (0.0f64, 0.0f64);
    for _ in 0..steps {
        stepper.advance(&mut solver)?;
        let v = &solver.vehicles[0];
        for (j, moments) in force.iter_mut().enumerate().take(axles) {
            if model.on_girder(v.axle_x_m(j, solver.step, setup.dt_s)) {
                moments.push(v.contact_force_n[j] / v.dynamics.axles[j].static_load_n);
            }
        }
        let u = mid.dot(&solver.bridge.state.u);
        let a = mid.dot(&solver.bridge.state.a);
        peak_u = peak_u.max(-u);
        peak_a = peak_a.max(a.abs());
    }
    Ok(Crossing {
        dlc: [force[0].max, force[1].max],
        sigma_ratio: [force[0].std(), force[1].std()],
        min_ratio: [force[0].min, force[1].min],
        peak_deflection_m: peak_u,
        peak_acceleration_m_s2: peak_a,
    })
}

/// Running max, min, mean and variance (Welford).
#[derive(Debug, Clone, Copy)]
struct Moments {
    n: u64,
    mean: f64,
    m2: f64,
    max: f64,
    min: f64,
}

impl Default for Moments {
    fn default() -> Self {
        Moments {
            n: 0,
            mean: 0.0,
            m2: 0.0,
            max: f64::NAN,
            min: f64::NAN,
        }
    }
}

impl Moments {
    fn push(&mut self, x: f64) {
        self.n += 1;
        let d = x - self.mean;
        self.mean += d / self.n as f64;
        self.m2 += d * (x - self.mean);
        self.max = if self.n == 1 { x } else { self.max.max(x) };
        self.min = if self.n == 1 { x } else { self.min.min(x) };
    }

    /// Population standard deviation over the samples.
    fn std(&self) -> f64 {
        if self.n == 0 {
            f64::NAN
        } else {
            (self.m2 / self.n as f64).sqrt()
        }
    }
}
