//! Runs the numerical models on the verification cases (moving force, manufactured
//! solution) so that checks, studies and benches share one definition of each case.

use std::f64::consts::PI;
use std::time::Instant;

use nalgebra::DVector;

use crate::error::Result;
use crate::physics::bridge::{BeamProperties, BridgeModel, ModelSpec, PointQuantity, SparseVec};
use crate::physics::road::LevelRoad;
use crate::physics::solver::{
    ContactLaw, CoupledSolver, CoupledVehicle, Newmark, NewmarkCoefficients, NewmarkParams,
    SolveMode, Stepper, Storage,
};
use crate::physics::vehicle::VehicleDynamics;
use crate::studies::DIVERGENCE_HINT;

/// A constant force crossing the beam from x = 0 at t = 0.
#[derive(Debug, Clone)]
pub struct MovingForceCase {
    pub beam: BeamProperties,
    pub spec: ModelSpec,
    pub damping_ratio: f64,
    pub force_n: f64,
    pub speed_m_s: f64,
    pub dt_s: f64,
    /// Free vibration simulated after the force leaves (s).
    pub free_time_s: f64,
}

/// Midspan deflection history, DOWNWARD positive (as the analytical module), and the times.
pub fn moving_force_history(case: &MovingForceCase) -> Result<(Vec<f64>, Vec<f64>)> {
    moving_force_history_at(case, case.beam.length_m() / 2.0)
}

/// Deflection history at `probe_m`, DOWNWARD positive, and the times.
pub fn moving_force_history_at(
    case: &MovingForceCase,
    probe_m: f64,
) -> Result<(Vec<f64>, Vec<f64>)> {
    let force = VehicleDynamics::moving_forces(&[case.force_n], &[0.0]);
    history_at(case, &force, probe_m)
}

/// Midspan deflection history, DOWNWARD positive, of `train` (its first axle entering at
/// t = 0) on the case's beam (the case's own force is not used), and the times.
pub fn train_history(
    case: &MovingForceCase,
    train: &VehicleDynamics,
) -> Result<(Vec<f64>, Vec<f64>)> {
    history_at(case, train, case.beam.length_m() / 2.0)
}

fn history_at(
    case: &MovingForceCase,
    train: &VehicleDynamics,
    probe_m: f64,
) -> Result<(Vec<f64>, Vec<f64>)> {
    let model = BridgeModel::build(&case.beam, &case.spec, case.damping_ratio)?;
    let coefficients = NewmarkCoefficients::new(case.dt_s, NewmarkParams::default())?;
    let road = LevelRoad;
    let mut solver = CoupledSolver::new(
        &model,
        &road,
        coefficients,
        SolveMode::Prefactored(Storage::Dense),
        ContactLaw::Full,
    )?;
    solver.add_vehicle(CoupledVehicle::new(
        0,
        train.clone(),
        case.speed_m_s,
        0.0,
        0,
    ));
    let duration_s =
        (case.beam.length_m() + train.wheelbase_m()) / case.speed_m_s + case.free_time_s;
    let steps = (duration_s / case.dt_s).round() as u64;
    let mut op = SparseVec::with_capacity(model.n_dof());
    let mut times = vec![0.0];
    let mut deflection = vec![0.0];
    let stepper = Stepper::new(&model, DIVERGENCE_HINT);
    for _ in 0..steps {
        stepper.advance(&mut solver)?;
        times.push(solver.time_s());
        deflection.push(-solver.bridge_response(probe_m, PointQuantity::Deflection, 0, &mut op));
    }
    Ok((times, deflection))
}

/// `(reference peak, numerical peak, RMS of the difference)` of two histories on the
/// same times: what the moving-force rows compare.
pub fn history_errors(numerical: &[f64], exact: &[f64]) -> (f64, f64, f64) {
    let peak = |h: &[f64]| h.iter().fold(0.0f64, |a, &b| a.max(b.abs()));
    let rms = (numerical
        .iter()
        .zip(exact)
        .map(|(a, b)| (a - b).powi(2))
        .sum::<f64>()
        / numerical.len() as f64)
        .sqrt();
    (peak(exact), peak(numerical), rms)
}

/// The manufactured solution `w(x, t) = sum_k A_k sin(k pi x / L) g_k(t)` with three
/// modes and three forcing frequencies; every g_k starts at rest (g(0) = g'(0) = 0).
#[derive(Debug, Clone)]
pub struct ManufacturedCase {
    pub beam: BeamProperties,
    pub spec: ModelSpec,
    pub damping_ratio: f64,
    pub dt_s: f64,
    pub duration_s: f64,
    pub mode: SolveMode,
}

/// The three components: (mode number k, amplitude m, forcing frequency Hz, kind).
/// Kind 0: g = 1 - cos(W t); kind 1: g = sin^2(W t).
const COMPONENTS: [(usize, f64, f64, u8); 3] =
    [(1, 0.010, 2.0, 0), (2, 0.004, 3.0, 1), (3, 0.002, 7.0, 0)];

/// g, g', g'' of one component at t.
fn time_function(kind: u8, omega: f64, t: f64) -> (f64, f64, f64) {
    if kind == 0 {
        (
            1.0 - (omega * t).cos(),
            omega * (omega * t).sin(),
            omega * omega * (omega * t).cos(),
        )
    } else {
        let s = (omega * t).sin();
        (
            s * s,
            omega * (2.0 * omega * t).sin(),
            2.0 * omega * omega * (2.0 * omega * t).cos(),
        )
    }
}

/// The exact manufactured deflection (upward positive, m).
pub fn manufactured_exact_m(beam: &BeamProperties, x_m: f64, t_s: f64) -> f64 {
    COMPONENTS
        .iter()
        .map(|&(k, amp, f_hz, kind)| {
            let (g, _, _) = time_function(kind, 2.0 * PI * f_hz, t_s);
            amp * (k as f64 * PI * x_m / beam.length_m()).sin() * g
        })
        .sum()
}

/// Result of a manufactured-solution run.
pub struct ManufacturedResult {
    /// Max over time of |numerical - exact| / max |exact|, per requested point.
    pub relative_error: Vec<f64>,
    /// Wall time of the time loop alone (s).
    pub loop_wall_s: f64,
    pub steps: u64,
}

/// Runs the manufactured case and measures the error at `points_m`.
pub fn manufactured_history(
    case: &ManufacturedCase,
    points_m: &[f64],
) -> Result<ManufacturedResult> {
    let beam = &case.beam;
    let model = BridgeModel::build(beam, &case.spec, case.damping_ratio)?;
    let coefficients = NewmarkCoefficients::new(case.dt_s, NewmarkParams::default())?;
    let mut newmark = Newmark::new(
        &model.mass,
        &model.damping,
        &model.stiffness,
        coefficients,
        case.mode,
    )?;
    let l = beam.length_m();
    // Load shapes: the consistent load of sin(k pi x / L).
    let shapes: Vec<DVector<f64>> = COMPONENTS
        .iter()
        .map(|&(k, ..)| model.distributed_load(|x| (k as f64 * PI * x / l).sin()))
        .collect();
    let (a0, a1) = (model.rayleigh.a0_per_s, model.rayleigh.a1_s);
    let ei = beam.flexural_rigidity_n_m2;
    let m = beam.mass_per_length_kg_m;
    let mut load = DVector::zeros(model.n_dof());
    // q = EI w'''' + c w' + m w'' with Rayleigh c = a0 m + a1 EI d4/dx4.
    let fill_load = |t: f64, load: &mut DVector<f64>| {
        load.fill(0.0);
        for (&(k, amp, f_hz, kind), shape) in COMPONENTS.iter().zip(&shapes) {
            let (g, gd, gdd) = time_function(kind, 2.0 * PI * f_hz, t);
            let k4 = (k as f64 * PI / l).powi(4);
            let coeff = amp * (ei * k4 * (g + a1 * gd) + m * (gdd + a0 * gd));
            load.axpy(coeff, shape, 1.0);
        }
    };
    fill_load(0.0, &mut load);
    newmark.initialize_acceleration(&model.mass, &model.stiffness, &load)?;
    let ops = model.point_operators(points_m, PointQuantity::Deflection);
    let steps = (case.duration_s / case.dt_s).round() as u64;
    let mut max_err = vec![0.0f64; points_m.len()];
    let mut max_exact = vec![0.0f64; points_m.len()];
    let start = Instant::now();
    for step in 1..=steps {
        let t = step as f64 * case.dt_s;
        fill_load(t, &mut load);
        newmark.step(&load);
        for (i, (&x, op)) in points_m.iter().zip(&ops).enumerate() {
            let exact = manufactured_exact_m(beam, x, t);
            max_err[i] = max_err[i].max((op.dot(&newmark.state.u) - exact).abs());
            max_exact[i] = max_exact[i].max(exact.abs());
        }
    }
    let loop_wall_s = start.elapsed().as_secs_f64();
    Ok(ManufacturedResult {
        relative_error: max_err.iter().zip(&max_exact).map(|(e, m)| e / m).collect(),
        loop_wall_s,
        steps,
    })
}
