//! What the coupled-step benches time, shared by `bridgetwin bench` and the criterion
//! bench `benches/coupled_step.rs` so both measure the same thing: the two-axle truck at
//! 20 m/s with dt = 1 ms on a level road, timed from 4.5 m (both axles on the span) to
//! 29.5 m; a fresh solver (untimed) takes over when the truck gets there, so every timed
//! step has both contacts on the bridge.

use std::hint::black_box;
use std::time::{Duration, Instant};

use serde::Serialize;

use crate::error::Result;
use crate::physics::bridge::{BeamProperties, BridgeModel, LumpedStiffness, ModelSpec};
use crate::physics::road::LevelRoad;
use crate::physics::solver::{
    ContactLaw, CoupledSolver, CoupledVehicle, DirectSolver, NewmarkCoefficients, NewmarkParams,
    SolveMode, Storage,
};
use crate::physics::vehicle::{HalfCarSpec, VehicleDynamics, VehicleModelSpec};

pub const SPEED_M_S: f64 = 20.0;
pub const DT_S: f64 = 1e-3;
/// Front axle at the first timed step (the rear axle, 4.27 m behind, is on the span).
pub const START_M: f64 = 4.5;
/// Front axle at the last timed step (still on the 30 m span).
pub const END_M: f64 = 29.5;
/// Modes kept by the modal path of the bench.
pub const BENCH_MODES: usize = 10;

/// The level road of the timed steps (the road does not change the cost of a step).
pub static ROAD: LevelRoad = LevelRoad;

/// The `two_axle_truck` half car (docs/physics.md section 6).
pub fn truck() -> Result<VehicleDynamics> {
    VehicleModelSpec::HalfCar(HalfCarSpec {
        preset: Some("two_axle_truck".into()),
        ..Default::default()
    })
    .build("vehicle")
}

/// Newmark average acceleration at `DT_S`.
pub fn coefficients() -> NewmarkCoefficients {
    NewmarkCoefficients::new(DT_S, NewmarkParams::default()).expect("DT_S is a valid step")
}

/// A way of doing the coupled step, as the bench names it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum BenchPath {
    /// N lumped masses, dense K factorized once, low-rank contact coupling.
    LumpedLowRank,
    /// N Hermite elements, banded sparse Cholesky, low-rank contact coupling.
    FeBanded,
    /// `BENCH_MODES` modes of an FE model with N elements, low-rank contact coupling.
    #[serde(rename = "modal_10")]
    Modal,
    /// The paper's method: N lumped masses, the full coupled system assembled and
    /// LU-factorized every step (`DirectSolver`): the baseline.
    #[serde(rename = "direct_paper")]
    Direct,
}

impl BenchPath {
    /// The low-rank paths, then the baseline.
    pub const ALL: [BenchPath; 4] = [
        BenchPath::LumpedLowRank,
        BenchPath::FeBanded,
        BenchPath::Modal,
        BenchPath::Direct,
    ];

    /// Name in tables, JSON and criterion ids.
    pub fn name(self) -> &'static str {
        match self {
            BenchPath::LumpedLowRank => "lumped_low_rank",
            BenchPath::FeBanded => "fe_banded",
            // Keep in step with the serde names above.
            BenchPath::Modal => "modal_10",
            BenchPath::Direct => "direct_paper",
        }
    }

    /// The bridge model of this path at `nodes` (masses, elements, or the elements the
    /// modes are taken from).
    pub fn spec(self, nodes: usize) -> ModelSpec {
        match self {
            BenchPath::LumpedLowRank | BenchPath::Direct => ModelSpec::LumpedMass {
                nodes,
                stiffness: LumpedStiffness::Auto,
            },
            BenchPath::FeBanded => ModelSpec::FiniteElement { elements: nodes },
            BenchPath::Modal => ModelSpec::Modal {
                modes: BENCH_MODES,
                elements: Some(nodes),
            },
        }
    }

    /// Storage of the prefactored effective matrix: banded for FE, dense otherwise (the
    /// lumped K = F^-1 is dense; modal matrices are diagonal whatever the storage).
    pub fn storage(self) -> Storage {
        match self {
            BenchPath::FeBanded => Storage::Sparse,
            _ => Storage::Dense,
        }
    }

    /// Paths with the same key run on the same model (the direct method on the lumped one).
    pub fn model_key(self) -> &'static str {
        match self {
            BenchPath::LumpedLowRank | BenchPath::Direct => "lumped",
            BenchPath::FeBanded => "fe",
            BenchPath::Modal => "modal",
        }
    }

    /// The model of this path at `nodes` on the paper's beam with 2 % Rayleigh damping.
    pub fn model(self, nodes: usize) -> Result<BridgeModel> {
        BridgeModel::build(&BeamProperties::paper_default(), &self.spec(nodes), 0.02)
    }
}

/// A `CoupledSolver` (effective matrix factorized here) with the truck at `START_M`.
pub fn low_rank_solver<'a>(
    model: &'a BridgeModel,
    storage: Storage,
    vehicle: &VehicleDynamics,
) -> CoupledSolver<'a> {
    let mode = SolveMode::Prefactored(storage);
    let mut s = CoupledSolver::new(model, &ROAD, coefficients(), mode, ContactLaw::Full)
        .expect("the effective matrix of a bench model factorizes");
    s.add_vehicle(CoupledVehicle::new(
        0,
        vehicle.clone(),
        SPEED_M_S,
        START_M,
        0,
    ));
    s
}

/// A `DirectSolver` (nothing factorized up front) with the truck at `START_M`.
pub fn direct_solver<'a>(model: &'a BridgeModel, vehicle: &VehicleDynamics) -> DirectSolver<'a> {
    let mut s = DirectSolver::new(model, &ROAD, coefficients()).expect("the solver builds");
    s.add_vehicle(CoupledVehicle::new(
        0,
        vehicle.clone(),
        SPEED_M_S,
        START_M,
        0,
    ));
    s
}

/// Steps a fresh solver takes before the truck reaches `END_M`.
pub fn steps_per_solver() -> u64 {
    ((END_M - START_M) / (SPEED_M_S * DT_S)) as u64
}

/// Times steps of one solver after another: a solver (built untimed) is stepped until
/// the truck would leave the stretch where both axles are on the span, then replaced.
/// The current solver carries over between calls, so repeated short measurements do not
/// pay (or skip) the construction, which factorizes, and for n <= 1024 also forms the
/// columns of `K_eff^-1`.
pub struct StepTimer<S, M: Fn() -> S, F: Fn(&mut S)> {
    make: M,
    step: F,
    current: Option<(S, u64)>,
}

impl<S, M: Fn() -> S, F: Fn(&mut S)> StepTimer<S, M, F> {
    pub fn new(make: M, step: F) -> Self {
        StepTimer {
            make,
            step,
            current: None,
        }
    }

    /// Wall time of the next `iters` steps (solver replacements excluded).
    pub fn time(&mut self, iters: u64) -> Duration {
        let mut total = Duration::ZERO;
        let mut done = 0;
        while done < iters {
            let (mut solver, taken) = match self.current.take() {
                Some((s, taken)) if taken < steps_per_solver() => (s, taken),
                _ => ((self.make)(), 0),
            };
            let chunk = (steps_per_solver() - taken).min(iters - done);
            let start = Instant::now();
            for _ in 0..chunk {
                (self.step)(&mut solver);
            }
            total += start.elapsed();
            black_box(&mut solver);
            done += chunk;
            self.current = Some((solver, taken + chunk));
        }
        total
    }
}

/// Times `iters` steps with fresh solvers (see [`StepTimer`]).
pub fn time_steps<S>(iters: u64, make: impl Fn() -> S, step: impl Fn(&mut S)) -> Duration {
    StepTimer::new(make, step).time(iters)
}

/// A timer of the coupled steps of `path` on `model`: call it with a step count, it
/// returns their wall time.
pub fn path_timer<'a>(
    path: BenchPath,
    model: &'a BridgeModel,
    vehicle: &'a VehicleDynamics,
) -> Box<dyn FnMut(u64) -> Duration + 'a> {
    match path {
        BenchPath::Direct => {
            let mut t = StepTimer::new(
                move || direct_solver(model, vehicle),
                |s: &mut DirectSolver| s.advance().expect("step"),
            );
            Box::new(move |iters| t.time(iters))
        }
        _ => {
            let mut t = StepTimer::new(
                move || low_rank_solver(model, path.storage(), vehicle),
                |s: &mut CoupledSolver| s.advance().expect("step"),
            );
            Box::new(move |iters| t.time(iters))
        }
    }
}
