//! One crossing of the paper's case on one solver path, recorded step by step: the
//! midspan deflection and acceleration and both tyre forces. The histories of different
//! paths and time steps are compared afterwards on a common time grid.

use std::time::Instant;

use crate::error::Result;
use crate::physics::bridge::{BridgeModel, MomentGauge, PointQuantity, SparseVec};
use crate::physics::road::RoadSurface;
use crate::physics::solver::{
    ContactLaw, CoupledSolver, CoupledVehicle, NewmarkCoefficients, NewmarkParams, SolveMode,
    Stepper, Storage,
};
use crate::physics::vehicle::VehicleDynamics;
use crate::studies::DIVERGENCE_HINT;

/// The histories of one crossing, sample `i` at `t = i dt` (sample 0: the initial state).
/// Signs as in the solver: deflection and acceleration upward positive.
#[derive(Debug, Clone)]
pub struct History {
    pub dt_s: f64,
    pub deflection_m: Vec<f64>,
    pub acceleration_m_s2: Vec<f64>,
    /// Midspan bending moment (N m, sagging positive): what the strain gauge reads.
    pub moment_n_m: Vec<f64>,
    /// Total tyre force of the front and the rear axle (N, compression positive).
    pub force_n: [Vec<f64>; 2],
    /// Whether the front / rear axle is on the span.
    pub on_span: [Vec<bool>; 2],
    /// Static axle loads (N).
    pub static_n: [f64; 2],
    /// Wall time of the time loop (s).
    pub loop_wall_s: f64,
}

impl History {
    fn with_capacity(dt_s: f64, samples: usize, static_n: [f64; 2]) -> Self {
        let v = || Vec::with_capacity(samples);
        History {
            dt_s,
            deflection_m: v(),
            acceleration_m_s2: v(),
            moment_n_m: v(),
            force_n: [v(), v()],
            on_span: [Vec::with_capacity(samples), Vec::with_capacity(samples)],
            static_n,
            loop_wall_s: 0.0,
        }
    }

    /// Number of samples (steps + 1).
    pub fn len(&self) -> usize {
        self.deflection_m.len()
    }

    /// True when nothing was recorded.
    pub fn is_empty(&self) -> bool {
        self.deflection_m.is_empty()
    }
}

/// What one crossing needs besides the bridge model.
pub struct CrossingInput<'a> {
    pub vehicle: &'a VehicleDynamics,
    pub road: &'a dyn RoadSurface,
    pub speed_m_s: f64,
    /// Front axle this far before the bridge at t = 0 (m).
    pub approach_m: f64,
    /// Simulated time (s); a whole number of steps of every dt compared.
    pub duration_s: f64,
    pub dt_s: f64,
}

/// The linear algebra each discretization deserves: banded sparse Cholesky for Hermite FE,
/// dense Cholesky for the lumped K = F^-1, diagonal for modal (picked by `Operator`).
pub fn storage_for(model: &BridgeModel) -> Storage {
    match model.spec {
        crate::physics::bridge::ModelSpec::FiniteElement { .. } => Storage::Sparse,
        _ => Storage::Dense,
    }
}

/// Runs the crossing with the low-rank contact coupling (`CoupledSolver`, full contact).
pub fn run_crossing(model: &BridgeModel, input: &CrossingInput) -> Result<History> {
    let coefficients = NewmarkCoefficients::new(input.dt_s, NewmarkParams::default())?;
    let mode = SolveMode::Prefactored(storage_for(model));
    let mut solver = CoupledSolver::new(model, input.road, coefficients, mode, ContactLaw::Full)?;
    solver.add_vehicle(CoupledVehicle::new(
        0,
        input.vehicle.clone(),
        input.speed_m_s,
        -input.approach_m,
        0,
    ));
    let steps = (input.duration_s / input.dt_s).round() as usize;
    let axles = &input.vehicle.axles;
    let static_n = [axles[0].static_load_n, axles[axles.len() - 1].static_load_n];
    let mut history = History::with_capacity(input.dt_s, steps + 1, static_n);
    let mut midspan = Midspan::new(model)?;
    let stepper = Stepper::new(model, DIVERGENCE_HINT);
    let started = Instant::now();
    record(&solver, &mut midspan, &mut history);
    for _ in 0..steps {
        stepper.advance(&mut solver)?;
        record(&solver, &mut midspan, &mut history);
    }
    history.loop_wall_s = started.elapsed().as_secs_f64();
    Ok(history)
}

/// What is read at midspan: the deflection's weights, the moment gauge and the deck
/// loads' buffer it reads.
struct Midspan {
    deflection: SparseVec,
    moment: MomentGauge,
    loads: Vec<(f64, f64)>,
}

impl Midspan {
    fn new(model: &BridgeModel) -> Result<Self> {
        let mid = 0.5 * model.length_m();
        let mut deflection = SparseVec::with_capacity(model.n_dof());
        model.point_operator(mid, PointQuantity::Deflection, &mut deflection);
        Ok(Midspan {
            deflection,
            moment: MomentGauge::new(model, mid)?,
            loads: Vec::new(),
        })
    }
}

/// Appends the current state of `solver` to `history`.
fn record(solver: &CoupledSolver, midspan: &mut Midspan, history: &mut History) {
    let state = &solver.bridge.state;
    history.deflection_m.push(midspan.deflection.dot(&state.u));
    history
        .acceleration_m_s2
        .push(midspan.deflection.dot(&state.a));
    let moment_n_m = solver.gauge_moment_n_m(&midspan.moment, &mut midspan.loads);
    history.moment_n_m.push(moment_n_m);
    let v = &solver.vehicles[0];
    let last = v.dynamics.axles.len() - 1;
    let dt = solver.bridge.coefficients.dt_s;
    for (k, axle) in [0, last].into_iter().enumerate() {
        history.force_n[k].push(v.contact_force_n[axle]);
        let x = v.axle_x_m(axle, solver.step, dt);
        history.on_span[k].push(solver.model.on_girder(x));
    }
}
