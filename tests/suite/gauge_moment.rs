//! The bending moment at a gauge (`physics::bridge::MomentGauge`), the quantity every
//! strain gauge and so every B-WIM calibration rests on: a force crossing a simply
//! supported span slowly must give the static influence line `P a (L - x) / L` at every
//! position, on a node and off it, for every discretization; a passage and its mirror
//! image must read the same; and the gauge must reproduce the statics of a load inside
//! its own element, where interpolating the element's curvature is off by percent.

use bridgetwin::physics::bridge::{
    BeamProperties, BridgeModel, GaugeState, LumpedStiffness, ModelSpec, MomentGauge, PointQuantity,
};
use bridgetwin::physics::road::LevelRoad;
use bridgetwin::physics::solver::{
    ContactLaw, CoupledSolver, CoupledVehicle, NewmarkCoefficients, NewmarkParams, SolveMode,
    Storage,
};
use bridgetwin::physics::vehicle::{HalfCarSpec, VehicleDynamics, VehicleModelSpec};
use nalgebra::DVector;

const SPAN_M: f64 = 30.0;
const FORCE_N: f64 = 1.0e5;

/// The paper's 30 m span with `spec`, 5 % damping (the quasi-static crossing's
/// transients die out within a few periods of mode 1).
fn span(spec: ModelSpec) -> BridgeModel {
    BridgeModel::build(&BeamProperties::paper_default(), &spec, 0.05).unwrap()
}

/// Sagging moment at `x_m` of a simply supported span under a downward `FORCE_N` at
/// `a_m` (zero off the span): `P a (L - x) / L` for a <= x, `P x (L - a) / L` beyond.
fn influence_line_n_m(x_m: f64, a_m: f64) -> f64 {
    if !(0.0..=SPAN_M).contains(&a_m) {
        return 0.0;
    }
    let (near, far) = if a_m <= x_m { (a_m, x_m) } else { (x_m, a_m) };
    FORCE_N * near * (SPAN_M - far) / SPAN_M
}

/// How a gauge's moment is read: the recovered one, or the element's interpolated
/// curvature `EI w''` (the read-out the recovery replaces, kept to show it fails).
#[derive(Clone, Copy, PartialEq)]
enum Reading {
    Recovered,
    Interpolated,
}

/// Largest deviation of the moment at each of `gauges_m` from the influence line over a
/// crossing of one force at 0.25 m/s (alpha = v / (2 f1 L) = 1.1e-3), relative to the
/// gauge's peak `P x (L - x) / L`, once the force is 1 m on the span (the entry's small
/// free vibration has then decayed under 5 % damping, over 15 periods of mode 1).
fn quasi_static_errors(model: &BridgeModel, gauges_m: &[f64], reading: Reading) -> Vec<f64> {
    let speed_m_s = 0.25;
    let dt_s = 0.02;
    let road = LevelRoad;
    let coef = NewmarkCoefficients::new(dt_s, NewmarkParams::default()).unwrap();
    let mode = SolveMode::Prefactored(Storage::Sparse);
    let mut solver = CoupledSolver::new(model, &road, coef, mode, ContactLaw::Full).unwrap();
    let force = VehicleDynamics::moving_forces(&[FORCE_N], &[0.0]);
    solver.add_vehicle(CoupledVehicle::new(1, force, speed_m_s, 0.0, 0));
    let gauges: Vec<MomentGauge> = gauges_m
        .iter()
        .map(|&x| MomentGauge::new(model, x).unwrap())
        .collect();
    let mut loads = Vec::new();
    let mut worst = vec![0.0f64; gauges_m.len()];
    let steps = (SPAN_M / speed_m_s / dt_s) as u64;
    for step in 1..=steps {
        solver.advance().unwrap();
        let a_m = speed_m_s * step as f64 * dt_s;
        if a_m < 1.0 {
            continue;
        }
        solver.deck_loads(&mut loads);
        let s = &solver.bridge.state;
        let state = GaugeState {
            u: &s.u,
            v: &s.v,
            a: &s.a,
            loads: &loads,
        };
        for ((gauge, &x), worst) in gauges.iter().zip(gauges_m).zip(&mut worst) {
            let moment = match reading {
                Reading::Recovered => gauge.read(&state),
                Reading::Interpolated => model.read(x, PointQuantity::Moment, &s.u),
            };
            let peak = FORCE_N * x * (SPAN_M - x) / SPAN_M;
            *worst = worst.max((moment - influence_line_n_m(x, a_m)).abs() / peak);
        }
    }
    worst
}

/// The quasi-static crossing within 0.05 % of the influence line at midspan (a node of
/// every mesh here) and at 15.37 m (inside an element), for finite elements of 30 and
/// 10 elements, the lumped model and a modal model. The error left, 9.3e-5 of the peak
/// for all four, is the damped response's lag behind the moving load (linear in alpha =
/// v / (2 f1 L) = 1.1e-3: four times the speed gives 3.4e-4), the same whatever the
/// discretization; the interpolated curvature misses the same line by 1-6 % (shown
/// failing below). The bound, 5e-4, is 5.4 times the error seen.
#[test]
fn a_slow_force_reads_the_influence_line_at_every_gauge() {
    let gauges_m = [15.0, 15.37];
    let cases = [
        (
            "finite elements, 30",
            ModelSpec::FiniteElement { elements: 30 },
        ),
        (
            "finite elements, 10",
            ModelSpec::FiniteElement { elements: 10 },
        ),
        (
            "lumped mass, 29",
            ModelSpec::LumpedMass {
                nodes: 29,
                stiffness: LumpedStiffness::Flexibility,
            },
        ),
        (
            "modal, 40 modes",
            ModelSpec::Modal {
                modes: 40,
                elements: Some(160),
            },
        ),
    ];
    for (name, spec) in cases {
        let model = span(spec);
        let recovered = quasi_static_errors(&model, &gauges_m, Reading::Recovered);
        let interpolated = quasi_static_errors(&model, &gauges_m, Reading::Interpolated);
        println!("{name}: recovered {recovered:?}, interpolated {interpolated:?}");
        for (x, e) in gauges_m.iter().zip(&recovered) {
            assert!(*e < 5e-4, "{name}, gauge at {x} m: {e:.3e} of the peak");
        }
    }
}

/// The interpolated curvature, the read-out the gauge replaced, fails the same bound on
/// the 30-element mesh: the test above can tell a biased gauge from an exact one.
#[test]
fn the_interpolated_curvature_misses_the_influence_line() {
    let model = span(ModelSpec::FiniteElement { elements: 30 });
    let errors = quasi_static_errors(&model, &[15.0, 15.37], Reading::Interpolated);
    println!("interpolated: {errors:?}");
    assert!(errors.iter().all(|&e| e > 1e-2), "{errors:?}");
}

/// A static point load inside the gauge's own element: the recovered moment equals the
/// statics of the simply supported span to round-off, wherever the load and the gauge sit
/// in the element and on the node the gauge shares with its neighbour. For finite elements
/// because their nodal displacements are exact for static loads on a Hermite mesh; for the
/// lumped and modal models because the gauge adds the static part their state leaves out.
#[test]
fn a_static_load_inside_the_element_gives_the_exact_moment() {
    let specs = [
        ModelSpec::FiniteElement { elements: 10 },
        ModelSpec::LumpedMass {
            nodes: 9,
            stiffness: LumpedStiffness::Flexibility,
        },
        ModelSpec::Modal {
            modes: 6,
            elements: Some(20),
        },
    ];
    for spec in specs {
        let model = span(spec);
        let mut worst = 0.0f64;
        for a_m in [12.1, 13.5, 14.9, 15.0, 16.2] {
            let load = model.point_load_vector(a_m, -FORCE_N);
            let u = model.stiffness.to_dense().lu().solve(&load).unwrap();
            let zero = DVector::zeros(model.n_dof());
            let loads = [(a_m, -FORCE_N)];
            for x_m in [12.0, 12.5, 13.5, 14.99, 15.0, 17.9] {
                let state = GaugeState {
                    u: &u,
                    v: &zero,
                    a: &zero,
                    loads: &loads,
                };
                let moment = MomentGauge::new(&model, x_m).unwrap().read(&state);
                let expected = influence_line_n_m(x_m, a_m);
                worst = worst.max((moment - expected).abs() / (FORCE_N * SPAN_M / 4.0));
            }
        }
        println!(
            "{}: static load in the element {worst:.2e} of P L / 4",
            model.spec.label()
        );
        // Round-off of the solves and of the element's statics: 4e-14 to 1.6e-12 seen; 1e-11
        // leaves a factor of 6 over the worst, far below the 1e-2 of interpolation.
        assert!(worst < 1e-11, "{}: {worst:e}", model.spec.label());
    }
}

/// A two-axle truck crossing the span towards +x and its mirror image, the same truck
/// entering from the far end towards -x, read at midspan (a node) and at gauges placed
/// mirror-wise off the nodes: each pair must read the same at every step, to the
/// round-off of the two runs' sums (3.2e-12 of the peak seen; the bound is 10 times
/// that). The interpolated curvature, which reads a node from one element's side only,
/// is checked in the same runs to differ by more than 1e-3 (the negative control).
#[test]
fn mirror_passages_read_the_same_moment() {
    let model = span(ModelSpec::FiniteElement { elements: 30 });
    let road = LevelRoad;
    let coef = NewmarkCoefficients::new(2e-3, NewmarkParams::default()).unwrap();
    let mode = SolveMode::Prefactored(Storage::Sparse);
    let truck = VehicleModelSpec::HalfCar(HalfCarSpec {
        preset: Some("two_axle_truck".into()),
        ..Default::default()
    })
    .build("vehicle")
    .unwrap();
    let speed_m_s = 20.0;
    let solvers: Vec<CoupledSolver> = [1i8, -1]
        .into_iter()
        .map(|direction| {
            let mut s = CoupledSolver::new(&model, &road, coef, mode, ContactLaw::Full).unwrap();
            let start_m = if direction > 0 { -5.0 } else { SPAN_M + 5.0 };
            let v = CoupledVehicle::new(1, truck.clone(), speed_m_s, start_m, 0);
            s.add_vehicle(v.with_direction(direction));
            s
        })
        .collect();
    let mut solvers = solvers;
    let pairs = [(15.0, 15.0), (15.37, SPAN_M - 15.37), (4.2, SPAN_M - 4.2)];
    let gauges: Vec<[MomentGauge; 2]> = pairs
        .iter()
        .map(|&(a, b)| [a, b].map(|x| MomentGauge::new(&model, x).unwrap()))
        .collect();
    let (mut worst, mut peak, mut interpolated) = (0.0f64, 0.0f64, 0.0f64);
    let mut loads = [Vec::new(), Vec::new()];
    let steps = ((SPAN_M + 20.0) / speed_m_s / 2e-3) as usize;
    for _ in 0..steps {
        let mut readings = [vec![0.0; pairs.len()], vec![0.0; pairs.len()]];
        let mut old = [vec![0.0; pairs.len()], vec![0.0; pairs.len()]];
        for (side, solver) in solvers.iter_mut().enumerate() {
            solver.advance().unwrap();
            solver.deck_loads(&mut loads[side]);
            let s = &solver.bridge.state;
            let state = GaugeState {
                u: &s.u,
                v: &s.v,
                a: &s.a,
                loads: &loads[side],
            };
            for (g, pair) in gauges.iter().enumerate() {
                readings[side][g] = pair[side].read(&state);
                let x = [pairs[g].0, pairs[g].1][side];
                old[side][g] = model.read(x, PointQuantity::Moment, &s.u);
            }
        }
        for g in 0..pairs.len() {
            peak = peak.max(readings[0][g].abs());
            worst = worst.max((readings[0][g] - readings[1][g]).abs());
            interpolated = interpolated.max((old[0][g] - old[1][g]).abs());
        }
    }
    let (worst, interpolated) = (worst / peak, interpolated / peak);
    println!(
        "mirror passages: {worst:.2e} of the peak {peak:.4e} N m (interpolated {interpolated:.2e})"
    );
    assert!(worst < 3e-11, "{worst:e}");
    assert!(interpolated > 1e-3, "{interpolated:e}");
}

/// The same slow crossing through the whole run (scenario, time loop, sensor truth): the
/// truth moment of strain gauges on a node and off it follows the influence line within
/// the bound of the solver-level test, and each gauge's truth strain is that moment times
/// its distance from the neutral axis over EI, from 5 m on the span (the entry transient
/// has then decayed). A run whose probes read the interpolated curvature misses it by 2 %
/// at these gauges (the solver-level negative control).
#[test]
fn a_run_reports_the_recovered_moment_at_its_strain_gauges() {
    let speed_m_s = 1.0;
    let approach_m = 2.0;
    let toml = format!(
        r#"
seed = 1
duration_s = 33.0

[solver]
dt_s = 0.005

[bridge]
span_m = {SPAN_M}
flexural_rigidity_n_m2 = 5.629e10
mass_per_length_kg_m = 12000.0
damping_ratio = 0.05
model = {{ kind = "finite_element", elements = 30 }}

[road]
profile = {{ kind = "smooth" }}
approach_m = {approach_m}

[[vehicles]]
model = {{ kind = "moving_force", axle_loads_n = [{FORCE_N}] }}
speed_m_s = {speed_m_s}

[[sensors]]
id = "S_node"
kind = "strain"
position_m = 15.0
rate_hz = 20.0
gauge_depth_m = 0.8

[[sensors]]
id = "S_off"
kind = "strain"
position_m = 15.37
rate_hz = 20.0
gauge_depth_m = 0.8
"#
    );
    let records = crate::common::records_of(&toml);
    for (index, x_m) in [(0, 15.0), (1, 15.37)] {
        let peak = FORCE_N * x_m * (SPAN_M - x_m) / SPAN_M;
        let mut worst = 0.0f64;
        let mut count = 0;
        for (t_ns, _, _, truth) in crate::common::sensor_samples(&records, index) {
            let a_m = speed_m_s * t_ns as f64 * 1e-9 - approach_m;
            // The gauge 0.8 m from the neutral axis: |eps| = |M| c / EI (the sign is the
            // side of the axis the gauge sits on).
            let strain = truth.moment_n_m.abs() * 0.8 / 5.629e10 * 1e6;
            let read = truth.strain_microstrain.abs();
            assert!(
                (read - strain).abs() <= 1e-12 * strain.max(1.0),
                "{read} against {strain}"
            );
            if (5.0..=SPAN_M).contains(&a_m) {
                worst = worst.max((truth.moment_n_m - influence_line_n_m(x_m, a_m)).abs() / peak);
                count += 1;
            }
        }
        println!("run, gauge at {x_m} m: {worst:.2e} of the peak over {count} samples");
        assert!(count > 500, "{count} samples on the span");
        // What is left is the damped response's lag behind the load, linear in alpha
        // (3.4e-4 of the peak at alpha = 4.4e-3, 9.3e-5 at 1.1e-3 in the solver-level
        // test), odd about midspan and 3.4e-4 still when the force reaches the far
        // support; 5e-4, the bound of the solver-level test, holds it.
        assert!(worst < 5e-4, "gauge at {x_m} m: {worst:.3e} of the peak");
    }
}
