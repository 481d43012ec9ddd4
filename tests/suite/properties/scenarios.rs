//! Random valid scenarios (family 1 of `properties`): resolve never panics; a resolved
//! scenario runs to the end, every f64 of every record is finite, and a second run gives
//! the same records.

use proptest::prelude::*;

use bridgetwin::physics::bridge::{ModelSpec, StiffnessRegion};
use bridgetwin::physics::road::{IsoClass, RoadProfileSpec};
use bridgetwin::physics::solver::ContactLaw;
use bridgetwin::physics::vehicle::{HalfCarSpec, VehicleModelSpec};
use bridgetwin::scenario::{Scenario, SensorKind, SensorSpec, VehicleEntry};
use bridgetwin::sim::Record;
use bridgetwin::studies::analytic::{ModalDamping, MovingForceSolution, SimplySupportedBeam};

use crate::common::try_run;

use super::{beam_strategy, config, ei_for, model_strategy};

/// Time steps whose solver rate is a multiple of the default truth rates (200 Hz axle
/// loads, 20 Hz deflected shape), so that every generated scenario is valid.
const DT_S: [f64; 4] = [0.0005, 0.001, 0.0025, 0.005];

/// The vehicle presets: the two half-car presets, and moving-force, sprung-mass and
/// quarter-car vehicles with typical truck parameters.
fn vehicle_preset(index: usize) -> VehicleModelSpec {
    match index {
        0 => VehicleModelSpec::MovingForce {
            axle_loads_n: vec![60_000.0, 120_000.0],
            axle_spacing_m: vec![4.27],
        },
        1 => VehicleModelSpec::SprungMass {
            mass_kg: 20_000.0,
            stiffness_n_m: 4.0e6,
            damping_n_s_m: 2.0e4,
        },
        2 => VehicleModelSpec::QuarterCar {
            body_mass_kg: 8_000.0,
            axle_mass_kg: 800.0,
            suspension_stiffness_n_m: 1.0e6,
            suspension_damping_n_s_m: 1.5e4,
            tyre_stiffness_n_m: 3.5e6,
            tyre_damping_n_s_m: 2.0e3,
        },
        3 => VehicleModelSpec::HalfCar(HalfCarSpec::preset("two_axle_truck").unwrap()),
        _ => VehicleModelSpec::HalfCar(HalfCarSpec {
            preset: Some("vbi2d_e01".into()),
            ..HalfCarSpec::default()
        }),
    }
}

#[derive(Debug, Clone)]
struct SensorDraw {
    kind: usize,
    position_fraction: f64,
    rate_fraction: f64,
    noise: Option<f64>,
}

#[derive(Debug, Clone)]
struct VehicleDraw {
    preset: usize,
    speed_m_s: f64,
    entry_time_s: f64,
}

fn sensor_strategy() -> impl Strategy<Value = SensorDraw> {
    (
        0usize..3,
        0.001f64..0.999,
        prop_oneof![Just(1.0), Just(0.5), Just(0.2), 0.02f64..=1.0],
        proptest::option::of(0.0f64..1e-3),
    )
        .prop_map(
            |(kind, position_fraction, rate_fraction, noise)| SensorDraw {
                kind,
                position_fraction,
                rate_fraction,
                noise,
            },
        )
}

fn vehicle_strategy() -> impl Strategy<Value = VehicleDraw> {
    (0usize..5, 5.0f64..=40.0, 0.0f64..=0.5).prop_map(|(preset, speed_m_s, entry_time_s)| {
        VehicleDraw {
            preset,
            speed_m_s,
            entry_time_s,
        }
    })
}

fn road_strategy() -> impl Strategy<Value = RoadProfileSpec> {
    prop_oneof![
        Just(RoadProfileSpec::Smooth),
        prop::sample::select(vec![IsoClass::A, IsoClass::B, IsoClass::C, IsoClass::D])
            .prop_map(RoadProfileSpec::iso8608),
    ]
}

/// A random valid scenario, as a mutation of the default one. Approaches are short
/// (6-16 m) and entry times early (0-0.5 s) so that most vehicles reach the bridge within
/// the 0.3-2 s simulated.
fn scenario_strategy() -> impl Strategy<Value = Scenario> {
    let bridge = (
        beam_strategy(),
        0.0f64..=0.05,
        model_strategy(),
        proptest::option::of((0.0f64..0.9, 0.05f64..0.5, 0.3f64..=1.0)),
    );
    let run = (
        prop::sample::select(DT_S.to_vec()),
        prop::sample::select(vec![ContactLaw::Full, ContactLaw::Unilateral]),
        road_strategy(),
        6.0f64..=16.0,
        0.0f64..=30.0,
        0.05f64..=0.95,
        0.3f64..=2.0,
        any::<u64>(),
    );
    let traffic = (
        prop::collection::vec(vehicle_strategy(), 0..=3),
        prop::collection::vec(sensor_strategy(), 0..=4),
    );
    (bridge, run, traffic).prop_map(
        |(
            ((span, mass, f1), zeta, model, region),
            (dt, contact, profile, approach, exit, wim_fraction, duration, seed),
            (vehicles, sensors),
        )| {
            let mut s = Scenario::default_scenario();
            s.seed = seed;
            s.duration_s = Some(duration);
            s.bridge.span_m = Some(span);
            s.bridge.mass_per_length_kg_m = mass;
            s.bridge.flexural_rigidity_n_m2 = ei_for(span, mass, f1);
            s.bridge.damping_ratio = zeta;
            s.bridge.model = model;
            s.bridge.stiffness_regions = region
                .map(|(start, length, factor)| StiffnessRegion {
                    start_m: start * span,
                    end_m: (start + length).min(1.0) * span,
                    ei_factor: factor,
                })
                .into_iter()
                .collect();
            s.solver.dt_s = dt;
            s.solver.contact = contact;
            s.road.profile = profile;
            s.road.approach_m = approach;
            s.road.exit_m = exit;
            s.wim_stations[0].position_m = -wim_fraction * approach;
            s.vehicles = vehicles
                .iter()
                .map(|v| VehicleEntry {
                    id: None,
                    model: vehicle_preset(v.preset),
                    speed_m_s: v.speed_m_s,
                    entry_time_s: v.entry_time_s,
                    lane: 1,
                    direction: 1,
                })
                .collect();
            let solver_rate_hz = 1.0 / dt;
            s.sensors = sensors
                .iter()
                .enumerate()
                .map(|(i, d)| SensorSpec {
                    id: format!("P{i}"),
                    kind: [
                        SensorKind::Accelerometer,
                        SensorKind::Strain,
                        SensorKind::Displacement,
                    ][d.kind],
                    position_m: Some(d.position_fraction * span),
                    vehicle: None,
                    rate_hz: d.rate_fraction * solver_rate_hz,
                    noise_density: d.noise,
                    gauge_depth_m: None,
                    fibre: None,
                    preset: None,
                    chain: None,
                    daq_node: None,
                    faults: None,
                })
                .collect();
            s
        },
    )
}

/// Every f64 of a record, with a name for the failure message.
fn record_floats(record: &Record) -> Vec<(&'static str, f64)> {
    let mut out = Vec::new();
    match record {
        Record::Sensor {
            measured, truth, ..
        } => {
            out.extend(measured.map(|m| ("sensor.measured", m)));
            out.extend(truth.to_columns().iter().map(|&v| ("sensor.truth", v)));
        }
        Record::AxleLoads { axles, .. } => {
            for a in axles {
                out.push(("axle.position_m", a.position_m));
                out.push(("axle.force_n", a.force_n));
                out.push(("axle.static_load_n", a.static_load_n));
            }
        }
        Record::BridgeShape { deflection_m, .. } => {
            out.extend(deflection_m.iter().map(|&v| ("shape.deflection_m", v)));
        }
        Record::Fault { magnitude, .. } => out.push(("fault.magnitude", *magnitude)),
        Record::Vehicle { vehicle, .. } => {
            out.push(("vehicle.speed_m_s", vehicle.speed_m_s));
            out.push(("vehicle.gross_weight_n", vehicle.gross_weight_n));
            out.extend(
                vehicle
                    .axle_spacing_m
                    .iter()
                    .map(|&v| ("vehicle.axle_spacing_m", v)),
            );
            out.extend(
                vehicle
                    .static_axle_load_n
                    .iter()
                    .map(|&v| ("vehicle.static_axle_load_n", v)),
            );
            out.extend(
                vehicle
                    .parameters
                    .iter()
                    .map(|(_, v)| ("vehicle.parameters", *v)),
            );
        }
        Record::Gnss { fix, .. } => {
            out.push(("gnss.position_m", fix.position_m));
            out.push(("gnss.speed_m_s", fix.speed_m_s));
        }
        Record::AxleHit { hit, .. } => out.push(("axle_hit.speed_m_s", hit.speed_m_s)),
        Record::VehicleState { state, .. } => {
            let dofs = state.displacement.iter().chain(&state.velocity);
            out.extend(
                dofs.chain(&state.acceleration)
                    .map(|&v| ("vehicle_state.dof", v)),
            );
            for c in &state.contacts {
                out.push(("vehicle_state.contact_deflection_m", c.bridge_deflection_m));
                out.push(("vehicle_state.contact_force_n", c.force_n));
            }
        }
        Record::Wim { record, .. } => {
            let m = &record.measurement;
            out.push(("wim.speed_m_s", m.speed_m_s));
            out.push(("wim.gross_weight_n", m.gross_weight_n));
            out.extend(m.axle_spacing_m.iter().map(|&v| ("wim.axle_spacing_m", v)));
            out.extend(m.axle_load_n.iter().map(|&v| ("wim.axle_load_n", v)));
            out.push(("wim.truth.speed_rel", m.truth.speed_rel));
            out.push(("wim.truth.gross_rel", m.truth.gross_rel));
            out.extend(m.truth.axle_rel.iter().map(|&v| ("wim.truth.axle_rel", v)));
        }
        Record::Preview {
            measured, truth, ..
        } => {
            out.extend(measured.map(|m| ("preview.measured", m)));
            out.push(("preview.truth", *truth));
        }
        Record::Event { .. } => {}
    }
    out
}

/// The records of one run, or the error of the stage that failed (resolve, prepare or
/// run). A `Divergence` is such an error: every generated scenario is valid (its time
/// step is a multiple of the truth rates, its vehicles and roads are ordinary), so a run
/// that blows up is a bug of the model or the solver, not a scenario to skip.
fn simulate(scenario: &Scenario) -> Result<Vec<Record>, String> {
    try_run(scenario).map(|run| run.records)
}

fn check_run(scenario: &Scenario) -> Result<(), TestCaseError> {
    let first = simulate(scenario).map_err(TestCaseError::fail)?;
    prop_assert!(!first.is_empty(), "a run writes records");
    for r in &first {
        for (name, v) in record_floats(r) {
            prop_assert!(v.is_finite(), "{name} = {v} at t = {} ns", r.t_ns());
        }
    }
    let second = simulate(scenario).map_err(TestCaseError::fail)?;
    prop_assert!(first == second, "two runs of the same scenario differ");
    Ok(())
}

proptest! {
    #![proptest_config(config(48))]

    #[test]
    fn random_valid_scenarios_run_to_finite_deterministic_records(s in scenario_strategy()) {
        // Every generated scenario is valid: resolve must accept it.
        if let Err(e) = s.resolve() {
            return Err(TestCaseError::fail(format!("valid scenario rejected: {e}")));
        }
        check_run(&s)?;
    }
}

// ---------------------------------------------------------------------------------------
// Regressions found by the property above
// ---------------------------------------------------------------------------------------

/// Found by `random_valid_scenarios_run_to_finite_deterministic_records` (7 of 400 cases
/// ended in `Divergence`, all of them modal models): the run's divergence check compares
/// the model DOFs with 0.1 x span as if they were displacements in m, but the DOFs of the
/// modal model are mass-normalized modal coordinates (q = w / phi, phi ~ sqrt(2 / (m L)),
/// here sqrt(m L / 2) = 424 times the deflection). A 1 MN axle on the paper's bridge
/// deflects it by 10.6 mm (L / 2800; FE and lumped agree), and the modal model stops with
/// "divergence at t = 0.891 s: bridge displacement (m) = 3.01".
#[test]
fn modal_model_runs_where_finite_elements_run() {
    let run_with = |model: ModelSpec| {
        let mut s = Scenario::default_scenario();
        s.duration_s = Some(2.5);
        s.road.approach_m = 10.0;
        s.road.profile = RoadProfileSpec::Smooth;
        s.wim_stations[0].position_m = -5.0;
        s.sensors.clear();
        s.vehicles.truncate(1);
        s.vehicles[0].model = VehicleModelSpec::MovingForce {
            axle_loads_n: vec![1.0e6],
            axle_spacing_m: vec![],
        };
        let label = model.label();
        s.bridge.model = model;
        let run = try_run(&s).unwrap_or_else(|e| panic!("{label}: {e}"));
        (s, run.summary)
    };
    let (s, fe) = run_with(ModelSpec::FiniteElement { elements: 30 });
    let fe = fe.peak_midspan_deflection_m;
    // The independent value: Fryba's moving force on the simply supported beam (100
    // modes, the model's Rayleigh damping fitted on modes 1 and 2), i.e. the static
    // P L^3 / (48 EI) = 9.99 mm times the closed-form DAF (~1.06), over the 2 s from the force's
    // entry (10 m of approach at 20 m/s) to the end of the run. The run's peak is taken
    // at every solver step. Predicted difference ~1e-4: Newmark's period error
    // (w1 dt)^2 / 12 = 5e-5 on the dynamic part, the 30-element mesh's modes, and the
    // peak between steps (< 1e-6); 5e-4 is 5x that.
    let b = &s.bridge;
    let beam = SimplySupportedBeam::new(
        b.length_m(),
        b.flexural_rigidity_n_m2,
        b.mass_per_length_kg_m,
    )
    .expect("beam");
    let damping = ModalDamping::rayleigh_from_two_modes(
        b.damping_ratio,
        beam.omega_rad_s(1),
        beam.omega_rad_s(2),
    );
    let speed_m_s = s.vehicles[0].speed_m_s;
    let fryba = MovingForceSolution::new(beam, 1.0e6, speed_m_s, damping, 100).expect("Fryba");
    let entry_s = s.road.approach_m / speed_m_s;
    let (_, reference) = fryba.peak_deflection_m(0.5 * b.length_m(), 2.5 - entry_s);
    let error = fe / reference - 1.0;
    eprintln!(
        "FE peak midspan deflection {fe:.6e} m, Fryba {reference:.6e} m (static {:.6e} m): \
         {error:+.2e}",
        beam.static_midspan_deflection_m(1.0e6)
    );
    assert!(
        error.abs() < 5e-4,
        "FE peak {fe} m vs Fryba {reference} m: {error:+e}"
    );
    let (_, modal) = run_with(ModelSpec::Modal {
        modes: 10,
        elements: None,
    });
    let modal = modal.peak_midspan_deflection_m;
    assert!(
        (modal - fe).abs() < 1e-2 * fe,
        "modal peak {modal} m vs FE {fe} m"
    );
}
