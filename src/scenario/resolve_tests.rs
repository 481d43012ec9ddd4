//! Resolution: warnings and errors of the derived checks.

use super::*;
use crate::physics::bridge::ModelSpec;
use crate::scenario::Fibre;

fn error_of(edit: impl FnOnce(&mut Scenario)) -> String {
    let mut s = Scenario::default_scenario();
    edit(&mut s);
    match s.resolve() {
        Ok(_) => panic!("accepted"),
        Err(e) => e.to_string(),
    }
}

fn warnings_of(edit: impl FnOnce(&mut Scenario)) -> Vec<String> {
    let mut s = Scenario::default_scenario();
    edit(&mut s);
    s.resolve().unwrap().warnings()
}

#[test]
fn the_default_scenario_has_no_warnings() {
    assert_eq!(warnings_of(|_| {}), Vec::<String>::new());
}

#[test]
fn coarse_time_step_for_the_first_mode_is_a_warning() {
    let w = warnings_of(|s| {
        s.solver.dt_s = 0.02;
        s.sensors.retain(|x| x.kind == SensorKind::Displacement);
        s.sensors[0].rate_hz = 10.0;
        s.output.axle_load_rate_hz = 50.0;
        s.output.bridge_state_rate_hz = 10.0;
    });
    assert!(
        w.iter()
            .any(|m| m.starts_with("solver.dt_s = 0.02 gives 13.2 steps per period")),
        "{w:#?}"
    );
}

#[test]
fn sensor_warnings_name_the_sensor() {
    let w = warnings_of(|s| s.sensors[2].rate_hz = 1000.0);
    assert_eq!(w.len(), 1, "{w:#?}");
    assert!(
        w[0].starts_with("sensors.2[A3].rate_hz = 1000: the time step is coarse"),
        "{w:#?}"
    );
    let w = warnings_of(|s| s.sensors[4].rate_hz = 5.0);
    assert_eq!(w.len(), 1, "{w:#?}");
    assert!(
        w[0].starts_with("sensors.4[A5].rate_hz = 5: the recorded band ends at 2 Hz"),
        "{w:#?}"
    );
}

#[test]
fn a_sensor_on_a_support_is_a_warning_and_one_a_millimetre_off_it_is_not() {
    let w = warnings_of(|s| s.sensors[0].position_m = Some(0.0));
    assert_eq!(w.len(), 1, "{w:#?}");
    let id = &Scenario::default_scenario().sensors[0].id;
    assert!(
        w[0].starts_with(&format!(
            "sensors.0[{id}].position_m = 0: on the support at x = 0 m"
        )),
        "{w:#?}"
    );
    let w = warnings_of(|s| s.sensors[3].position_m = Some(30.0));
    assert!(w[0].contains("on the support at x = 30 m"), "{w:#?}");
    // 2 mm in: a small but real response (sin(pi x / L) = 2e-4), no warning.
    assert_eq!(
        warnings_of(|s| s.sensors[0].position_m = Some(0.002)),
        Vec::<String>::new()
    );
}

#[test]
fn vehicles_outside_the_run_and_other_oddities_are_warnings() {
    let w = warnings_of(|s| {
        s.duration_s = Some(2.0);
        s.vehicles[0].entry_time_s = 5.0;
    });
    assert_eq!(
        w,
        vec![
            "vehicles.0[1].entry_time_s = 5 is at or after the end of the run (2 s): \
              the vehicle never appears"
                .to_string()
        ]
    );
    let w = warnings_of(|s| s.duration_s = Some(0.5));
    assert!(
        w[0].starts_with(
            "vehicles.0[1].speed_m_s = 20: the vehicle reaches the bridge at t = 5.000 s"
        ),
        "{w:#?}"
    );
    let w = warnings_of(|s| s.bridge.damping_ratio = 0.5);
    assert!(w[0].starts_with("bridge.damping_ratio = 0.5"), "{w:#?}");
    // A big finite-element model builds in milliseconds (banded modes): no warning; a big
    // lumped one is still dense.
    let w = warnings_of(|s| s.bridge.model = ModelSpec::FiniteElement { elements: 1000 });
    assert!(w.is_empty(), "{w:#?}");
    let w = warnings_of(|s| {
        s.bridge.model = ModelSpec::LumpedMass {
            nodes: 1500,
            stiffness: Default::default(),
        }
    });
    assert!(
        w[0].starts_with("bridge.model.nodes = 1500: building a lumped-mass model is dense"),
        "{w:#?}"
    );
}

#[test]
fn implausible_bridges_blame_the_odd_field() {
    let msg = error_of(|s| s.bridge.flexural_rigidity_n_m2 = 5.629e100);
    assert!(
        msg.starts_with(
            "bridge.flexural_rigidity_n_m2 = 5.629e100 gives a first natural frequency f1 = 3.78"
        ),
        "{msg}"
    );
    let msg = error_of(|s| s.bridge.mass_per_length_kg_m = 1e300);
    assert!(
        msg.starts_with("bridge.mass_per_length_kg_m = 1e300 gives"),
        "{msg}"
    );
    let msg = error_of(|s| s.bridge.span_m = Some(1e-300));
    assert!(msg.starts_with("bridge.span_m = 1e-300 gives"), "{msg}");
    let msg = error_of(|s| s.bridge.span_m = Some(1e300));
    assert!(
        msg.starts_with("bridge.span_m = 1e300 must be at most 10000 m"),
        "{msg}"
    );
}

#[test]
fn run_length_limits() {
    let msg = error_of(|s| {
        s.solver.dt_s = 1e-5;
        s.duration_s = Some(1e6);
    });
    assert!(
        msg.starts_with(
            "duration_s = 1000000 with solver.dt_s = 0.00001 needs 100000000000 solver steps"
        ),
        "{msg}"
    );
    let msg = error_of(|s| s.vehicles[0].speed_m_s = 1e-5);
    assert!(
        msg.starts_with("vehicles.0[1].speed_m_s = 0.00001 makes the default duration"),
        "{msg}"
    );
    let msg = error_of(|s| s.vehicles[0].entry_time_s = 1e300);
    assert!(
        msg.starts_with("vehicles.0[1].entry_time_s = 1e300 must be at most 30 days"),
        "{msg}"
    );
    let msg = error_of(|s| s.start_time = "9999-12-31T23:59:59Z".into());
    assert!(msg.contains("must be before 2262-04-11"), "{msg}");
}

#[test]
fn sensor_channels_are_checked_before_the_run() {
    let msg = error_of(|s| s.sensors[0].rate_hz = 0.01);
    assert!(
        msg.starts_with("sensors.0[A1].rate_hz = 0.01 is too far below the solver rate"),
        "{msg}"
    );
    let msg = error_of(|s| s.sensors[1].noise_density = Some(1e308));
    assert!(
        msg.starts_with(
            "sensors.1[A2].noise_density = 1e308 gives a per-sample noise sigma of inf"
        ),
        "{msg}"
    );
}

#[test]
fn a_top_fibre_gauge_reads_hogging_as_tension_and_fibre_is_for_gauges_only() {
    let mut s = Scenario::default_scenario();
    let strain = s
        .sensors
        .iter()
        .position(|x| x.kind == SensorKind::Strain)
        .unwrap();
    s.sensors[strain].fibre = Some(Fibre::Top);
    s.sensors[strain].gauge_depth_m = Some(0.5);
    let resolved = s.resolve().unwrap();
    // Signed depth: eps = M c / EI is then negative (compression) under sagging.
    assert_eq!(resolved.sensors[strain].gauge_depth_m, -0.5);
    let msg = error_of(|s| s.sensors[0].fibre = Some(Fibre::Top));
    assert!(
        msg.contains("sensors.0[A1].fibre = top applies to strain gauges only"),
        "{msg}"
    );
}

#[test]
fn girders_name_their_spans_and_supports_in_errors() {
    let msg = error_of(|s| {
        s.bridge.span_m = None;
        s.bridge.spans_m = Some(vec![20.0, 0.0]);
    });
    assert!(
        msg.starts_with("bridge.spans_m.1 = 0 must be a finite number > 0"),
        "{msg}"
    );
    let msg = error_of(|s| s.bridge.spans_m = Some(vec![20.0, 20.0]));
    assert!(
        msg.contains("bridge.span_m = 30 give either span_m"),
        "{msg}"
    );
    let msg = error_of(|s| {
        s.bridge.span_m = None;
        s.bridge.spans_m = Some(vec![20.0, 20.0]);
        s.bridge.supports = Some(vec![crate::physics::bridge::Support::Pinned; 2]);
    });
    assert!(
        msg.contains("bridge.supports = 2 needs one support per span end: 3"),
        "{msg}"
    );
    let msg = error_of(|s| s.bridge.overhang_right_m = 40.0);
    assert!(
        msg.contains("bridge.overhang_right_m = 40 must not be longer"),
        "{msg}"
    );
}
