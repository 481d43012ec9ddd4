//! Instruments that see the vehicles: accelerometers riding on a vehicle, its GNSS fixes,
//! the road axle detectors, and the vehicle-state truth they are scored against. Each is
//! checked against what it must equal: the vehicle's own DOFs through the mount's lever,
//! the analytic motion at constant speed, the deck's deflected shape, the configured
//! noise.

use bridgetwin::record::{AxleHit, ContactPoint, GnssFix, VehicleStateRecord};
use bridgetwin::sim::Record;

use crate::common::{records_of, sensor_samples};

/// A drive-by van (vehicle 1) at `speed_m_s` and a truck behind it over the 30 m span
/// of the paper, with accelerometers on the van's front axle and body, a GNSS receiver and
/// two tape switches; noise-free sensors unless `noise` gives their tables.
fn drive_by(speed_m_s: f64, road: &str, extra: &str) -> String {
    format!(
        r#"
seed = 5
[bridge]
span_m = 30.0
flexural_rigidity_n_m2 = 5.629e10
mass_per_length_kg_m = 12000.0
damping_ratio = 0.02
model = {{ kind = "finite_element", elements = 30 }}
[road]
profile = {road}
approach_m = 20.0
exit_m = 10.0
[output]
axle_load_rate_hz = 1000.0
bridge_state_rate_hz = 1000.0
[[vehicles]]
id = 1
model = {{ kind = "half_car", preset = "drive_by_van" }}
speed_m_s = {speed_m_s}
entry_time_s = 1.0
[[vehicles]]
id = 2
model = {{ kind = "half_car", preset = "two_axle_truck" }}
speed_m_s = 15.0
entry_time_s = 0.0
[[sensors]]
id = "VA1"
kind = "accelerometer"
vehicle = {{ id = 1, axle = 1 }}
rate_hz = 1000.0
noise_density = 0.0
[[sensors]]
id = "VB"
kind = "accelerometer"
vehicle = {{ id = 1, body_offset_m = 0.5 }}
rate_hz = 1000.0
noise_density = 0.0
{extra}
"#
    )
}

fn states(records: &[Record]) -> Vec<(u64, VehicleStateRecord)> {
    records
        .iter()
        .filter_map(|r| match r {
            Record::VehicleState { t_ns, state } => Some((*t_ns, (**state).clone())),
            _ => None,
        })
        .collect()
}

#[test]
fn a_vehicle_accelerometer_reads_its_mount_through_the_lever_and_zero_off_the_road() {
    let records = records_of(&drive_by(8.0, r#"{ kind = "iso8608", class = "B" }"#, ""));
    let states = states(&records);
    assert!(states.len() > 1000, "{} states", states.len());
    // The van's DOFs: body bounce, body pitch, axle 1, axle 2; CG mid-wheelbase (1.5 m),
    // so a body point 0.5 m behind the front axle moves y_B + (1.5 - 0.5) theta. Sensors
    // are downward positive, the DOFs upward.
    let at = |index: usize| {
        sensor_samples(&records, index)
            .into_iter()
            .map(|(t_ns, _, _, truth)| (t_ns, truth.acceleration_m_s2))
            .collect::<std::collections::BTreeMap<u64, f64>>()
    };
    let (axle, body) = (at(0), at(1));
    let mut compared = 0;
    let mut peak = 0.0f64;
    for (t, s) in &states {
        let a = &s.acceleration;
        let (Some(&axle_read), Some(&body_read)) = (axle.get(t), body.get(t)) else {
            continue;
        };
        assert_eq!(axle_read, -a[2], "axle 1 at {t} ns");
        let expected = -(a[0] + 1.0 * a[1]);
        assert!(
            (body_read - expected).abs() <= 1e-12 * expected.abs().max(1.0),
            "{t}"
        );
        peak = peak.max(axle_read.abs());
        compared += 1;
    }
    assert!(compared > 1000, "{compared} instants compared");
    // Rough road class B at 8 m/s: the axle hops by m/s^2, not by rounding errors.
    assert!(peak > 0.5, "axle peak {peak} m/s^2");
    // Before the van appears (t < 1 s) its sensors read nothing at all.
    let before: Vec<f64> = axle.range(..900_000_000).map(|(_, &v)| v).collect();
    assert!(!before.is_empty() && before.iter().all(|&v| v == 0.0));
}

#[test]
fn contact_points_sit_on_the_road_and_the_deflected_deck() {
    let records = records_of(&drive_by(10.0, r#"{ kind = "iso8608", class = "A" }"#, ""));
    let shapes: std::collections::BTreeMap<u64, Vec<f64>> = records
        .iter()
        .filter_map(|r| match r {
            Record::BridgeShape {
                t_ns, deflection_m, ..
            } => Some((*t_ns, deflection_m.clone())),
            _ => None,
        })
        .collect();
    let mut on_deck = 0;
    let mut peak_m = 0.0f64;
    let mut worst_m = 0.0f64;
    for (t, s) in states(&records) {
        // The front axle at constant speed: x = -approach + v (t - entry).
        let x = -20.0 + 10.0 * (t as f64 * 1e-9 - 1.0);
        assert!((s.position_m - x).abs() < 1e-9, "{} vs {x}", s.position_m);
        for c in &s.contacts {
            let ContactPoint {
                position_m,
                on_bridge,
                bridge_deflection_m,
                ..
            } = *c;
            if !on_bridge {
                assert_eq!(bridge_deflection_m, 0.0);
                continue;
            }
            // The deck's shape nodes lie every metre (30 elements): linear interpolation
            // between them is within (1 m)^2 / 8 x curvature of the FE deflection, under 1 %
            // of its peak for these loads (the curvature is at most ~8 peak / L^2).
            let shape = &shapes[&t];
            let k = (position_m.floor() as usize).min(29);
            let w = position_m - k as f64;
            let interpolated = shape[k] * (1.0 - w) + shape[k + 1] * w;
            worst_m = worst_m.max((interpolated - bridge_deflection_m).abs());
            peak_m = peak_m.max(bridge_deflection_m.abs());
            on_deck += 1;
        }
    }
    assert!(on_deck > 2000, "{on_deck} contacts on the deck");
    assert!(peak_m > 1e-4, "peak {peak_m} m");
    assert!(
        worst_m < 0.01 * peak_m,
        "worst {worst_m} m of a peak {peak_m} m"
    );
}

#[test]
fn gnss_fixes_carry_the_configured_noise() {
    let gnss = r#"[[gnss]]
id = "G"
vehicle = 1
rate_hz = 50.0
position_noise_m = 0.5
speed_noise_m_s = 0.05
"#;
    let records = records_of(&drive_by(3.0, r#"{ kind = "smooth" }"#, gnss));
    let fixes: Vec<(u64, GnssFix)> = records
        .iter()
        .filter_map(|r| match r {
            Record::Gnss { t_ns, fix, .. } => Some((*t_ns, *fix)),
            _ => None,
        })
        .collect();
    // The van appears at 1 s and fixes come while it is on the road: the run ends 3 s
    // after its rear axle leaves the bridge (20 + 30 + 3 m from its start at 3 m/s, at
    // 18.67 s), before it reaches the end of the road: 20.67 s of fixes at 50 Hz, one
    // every 20 solver steps.
    assert!(
        (1032..=1035).contains(&fixes.len()),
        "{} fixes",
        fixes.len()
    );
    assert!(fixes.windows(2).all(|w| w[1].0 - w[0].0 == 20_000_000));
    let rms = |e: &dyn Fn(&GnssFix) -> f64| {
        (fixes.iter().map(|(_, f)| e(f).powi(2)).sum::<f64>() / fixes.len() as f64).sqrt()
    };
    // 1000 white draws: the RMS is within 3 x 1/sqrt(2000) = 6.7 % of the sigma.
    let position = rms(&|f| f.position_m - f.true_position_m);
    let speed = rms(&|f| f.speed_m_s - f.true_speed_m_s);
    assert!(
        (position / 0.5 - 1.0).abs() < 0.067,
        "position rms {position}"
    );
    assert!((speed / 0.05 - 1.0).abs() < 0.067, "speed rms {speed}");
    for (t, f) in &fixes {
        let x = -20.0 + 3.0 * (*t as f64 * 1e-9 - 1.0);
        assert!((f.true_position_m - x).abs() < 1e-9);
    }
}

#[test]
fn axle_detectors_time_every_axle_within_their_jitter() {
    let detectors = r#"[[axle_detectors]]
id = "T1"
position_m = -5.0
[[axle_detectors]]
id = "T2"
position_m = 12.3456
jitter_s = 0.002
miss_probability = 0.25
"#;
    let records = records_of(&drive_by(7.0, r#"{ kind = "smooth" }"#, detectors));
    let hits: Vec<(u64, usize, AxleHit)> = records
        .iter()
        .filter_map(|r| match r {
            Record::AxleHit {
                t_ns,
                detector,
                hit,
            } => Some((*t_ns, *detector, *hit)),
            _ => None,
        })
        .collect();
    // Two vehicles of two axles over two detectors: eight crossings, each once.
    assert_eq!(hits.len(), 8);
    for (t_ns, detector, hit) in &hits {
        let p = [-5.0, 12.3456][*detector];
        let (entry_s, speed, spacing) = match hit.vehicle_id {
            1 => (1.0, 7.0, 3.0),
            _ => (0.0, 15.0, 4.27),
        };
        // Front axle at -20 m at entry; axle j trails it by its offset.
        let offset = spacing * f64::from(hit.axle_index);
        let exact_ns = (entry_s + (p + 20.0 + offset) / speed) * 1e9;
        assert!(
            (hit.true_ns as f64 - exact_ns).abs() <= 1.0,
            "{hit:?} vs {exact_ns}"
        );
        assert!(
            *t_ns >= hit.true_ns && t_ns - hit.true_ns < 1_000_000,
            "{t_ns}"
        );
        match (*detector, hit.stamp_ns) {
            (0, stamp) => {
                // Default jitter 0.5 ms: within 5 sigma.
                let e = stamp.expect("T1 misses nothing") - hit.true_ns as i64;
                assert!(e.abs() < 2_500_000, "{e} ns");
            }
            (_, Some(stamp)) => assert!((stamp - hit.true_ns as i64).abs() < 10_000_000),
            (_, None) => {}
        }
    }
}

#[test]
fn the_drive_by_van_rides_and_hops_where_its_preset_says() {
    use bridgetwin::physics::solver::vehicle_natural_frequencies_hz;
    use bridgetwin::physics::vehicle::VehicleModelSpec;
    let spec: VehicleModelSpec = toml::from_str(
        r#"kind = "half_car"
preset = "drive_by_van""#,
    )
    .unwrap();
    let van = spec.build("van").unwrap();
    // Natural frequencies (undamped) of the free van on a rigid road,
    // against the uncoupled estimates: body on the suspension and tyres in series per
    // axle, sqrt(2 k_eq / m_body) / 2 pi = 1.21 Hz (bounce); an axle between its spring
    // and its tyre, sqrt((k_s + k_t) / m_axle) / 2 pi = 10.8 Hz (hop). Coupling and
    // damping move them by a few percent: the bands say where a drive-by method must not
    // look for the bridge.
    let hz = vehicle_natural_frequencies_hz(&van).unwrap();
    assert_eq!(hz.len(), 4, "{hz:?}");
    assert!((1.0..1.5).contains(&hz[0]), "bounce {hz:?}");
    assert!((1.2..2.0).contains(&hz[1]), "pitch {hz:?}");
    assert!(
        hz[2..].iter().all(|f| (10.0..11.5).contains(f)),
        "hop {hz:?}"
    );
    let g = bridgetwin::physics::vehicle::GRAVITY_M_S2;
    assert!((van.gross_weight_n() - 2000.0 * g).abs() < 1e-6);
}

#[test]
fn an_instrumented_van_amid_generated_traffic_is_the_only_one_recorded() {
    // The van (id 1) enters at 5 s among two lanes of generated traffic: the traffic's ids
    // start after the listed ones, so only the van has a state and fixes, while the tape
    // across the road times every vehicle's axles.
    let extra = r#"duration_s = 40.0
[traffic]
lanes = [{ direction = 1, flow_per_hour = 900.0 }, { direction = -1, flow_per_hour = 900.0 }]
[[gnss]]
id = "G"
vehicle = 1
[[axle_detectors]]
id = "T"
position_m = 15.0
"#;
    let toml = drive_by(10.0, r#"{ kind = "iso8608", class = "A" }"#, "")
        .replace("seed = 5\n", &format!("seed = 5\n{extra}"))
        .replace("entry_time_s = 1.0", "entry_time_s = 5.0");
    // Tables after [traffic] must not fall into it: move the sections to the end.
    let (head, tables) = toml.split_once("[traffic]").unwrap();
    let (traffic, rest) = tables.split_once("[[gnss]]").unwrap();
    let toml = format!(
        "{head}{}\n[traffic]{traffic}",
        format_args!("[[gnss]]{rest}")
    );
    let records = records_of(&toml);
    let mut state_ids = std::collections::BTreeSet::new();
    let mut fix_ids = std::collections::BTreeSet::new();
    let mut hit_ids = std::collections::BTreeSet::new();
    for r in &records {
        match r {
            Record::VehicleState { state, .. } => {
                state_ids.insert(state.vehicle_id);
            }
            Record::Gnss { fix, .. } => {
                fix_ids.insert(fix.vehicle_id);
            }
            Record::AxleHit { hit, .. } => {
                hit_ids.insert(hit.vehicle_id);
            }
            _ => {}
        }
    }
    assert_eq!(state_ids, [1].into());
    assert_eq!(fix_ids, [1].into());
    // The van, the truck and generated vehicles (ids from 3) cross the tape.
    assert!(hit_ids.contains(&1) && hit_ids.contains(&2), "{hit_ids:?}");
    assert!(
        hit_ids.iter().any(|&id| id > 2),
        "no traffic on the tape: {hit_ids:?}"
    );
}
