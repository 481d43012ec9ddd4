//! The main job end to end: records of a run, and the MCAP file the binary writes.

use std::path::Path;
use std::process::Command;

use bridgetwin::scenario::Scenario;
use bridgetwin::sim::{Record, RunSummary};

use crate::common::run_scenario;

fn records(scenario: &Scenario) -> (Vec<Record>, RunSummary) {
    let run = run_scenario(scenario);
    (run.records, run.summary)
}

fn quiet_default() -> Scenario {
    let mut s = Scenario::default_scenario();
    for sensor in &mut s.sensors {
        sensor.noise_density = Some(0.0);
    }
    s
}

#[test]
fn records_come_in_time_order_with_one_sample_per_period() {
    let s = Scenario::default_scenario();
    let resolved = s.resolve().unwrap();
    let (recs, _) = records(&s);
    let times: Vec<u64> = recs.iter().map(Record::t_ns).collect();
    assert!(
        times.windows(2).all(|w| w[0] <= w[1]),
        "log times must not decrease"
    );
    // Sample instants k / rate for k = 0..=floor(duration * rate): duration x rate + 1.
    let expected = (resolved.duration_s() * 200.0).floor() as usize + 1;
    for i in 0..resolved.sensors.len() {
        let n = recs
            .iter()
            .filter(|r| matches!(r, Record::Sensor { sensor, .. } if *sensor == i))
            .count();
        assert_eq!(n, expected, "sensor {i}");
    }
}

#[test]
fn without_noise_the_measurement_equals_the_truth_at_the_sample_instants() {
    // The anti-alias filter's pass band (0.4 fs = 80 Hz, ripple 1e-4) holds all of the
    // displacement and strain, so measured = truth to 0.1 % of the peak. The truth stream
    // is unfiltered: accelerations also carry bridge modes 5 and up (f5 = 94 Hz, above the
    // 200 Hz DAQ's Nyquist band), which the anti-alias filter rightly removes; there the
    // check is on energy: the rejected part is under 5 % of the RMS.
    let (recs, _) = records(&quiet_default());
    let resolved = quiet_default().resolve().unwrap();
    for (i, sensor) in resolved.sensors.iter().enumerate() {
        let pairs: Vec<(f64, f64)> = recs
            .iter()
            .filter_map(|r| match r {
                Record::Sensor {
                    sensor,
                    measured,
                    truth,
                    ..
                } if *sensor == i => Some((
                    measured.expect("no faults configured"),
                    truth.measured_by(resolved.sensors[i].spec.kind),
                )),
                _ => None,
            })
            .collect();
        let peak = pairs.iter().fold(0.0f64, |a, p| a.max(p.1.abs()));
        let worst = pairs.iter().fold(0.0f64, |a, p| a.max((p.0 - p.1).abs()));
        let rms = |f: &dyn Fn(&(f64, f64)) -> f64| {
            (pairs.iter().map(|p| f(p).powi(2)).sum::<f64>() / pairs.len() as f64).sqrt()
        };
        if sensor.spec.kind == bridgetwin::scenario::SensorKind::Accelerometer {
            let ratio = rms(&|p| p.0 - p.1) / rms(&|p| p.1);
            assert!(
                ratio < 0.05,
                "{}: rejected RMS fraction {ratio:e}",
                sensor.spec.id
            );
        } else {
            assert!(
                peak > 0.0 && worst <= 1e-3 * peak,
                "{}: worst {worst:e} vs peak {peak:e}",
                sensor.spec.id
            );
        }
    }
}

#[test]
fn wim_loads_are_the_tyre_forces_at_the_strip() {
    // A moving force has no dynamics: the strip must read the static loads exactly.
    let mut s = quiet_default();
    s.vehicles[0].model = bridgetwin::physics::vehicle::VehicleModelSpec::MovingForce {
        axle_loads_n: vec![60_000.0, 120_000.0],
        axle_spacing_m: vec![4.0],
    };
    let (recs, _) = records(&s);
    let wim: Vec<_> = recs
        .iter()
        .filter_map(|r| {
            if let Record::Wim { record, .. } = r {
                Some(record.measurement.clone())
            } else {
                None
            }
        })
        .collect();
    assert_eq!(wim.len(), 1);
    assert_eq!(wim[0].axle_load_n, vec![60_000.0, 120_000.0]);
    assert_eq!(wim[0].axle_spacing_m, vec![4.0]);
    // The half car: the ideal strip reads the dynamic tyre force of each axle at the step
    // the axle crosses it (x = -20 m): exactly the force `/truth/axle_loads` carries for
    // that axle at that step, once the truth is written at every solver step.
    let mut s = quiet_default();
    s.output.axle_load_rate_hz = 1.0 / s.solver.dt_s;
    let strip_m = s.wim_stations[0].position_m;
    let (recs, _) = records(&s);
    let wim: Vec<_> = recs
        .iter()
        .filter_map(|r| match r {
            Record::Wim { record, .. } => Some(record.measurement.clone()),
            _ => None,
        })
        .collect();
    assert_eq!(wim.len(), 1);
    let snapshots: Vec<&Vec<bridgetwin::sim::AxleState>> = recs
        .iter()
        .filter_map(|r| match r {
            // One vehicle: its axles, once it is on the road.
            Record::AxleLoads { axles, .. } if !axles.is_empty() => Some(axles),
            _ => None,
        })
        .collect();
    let axle_count = snapshots[0].len();
    assert_eq!(wim[0].axle_load_n.len(), axle_count);
    for (j, load) in wim[0].axle_load_n.iter().enumerate() {
        // The first snapshot at or past the strip, its predecessor still before it.
        let k = snapshots
            .iter()
            .position(|a| a[j].position_m >= strip_m)
            .expect("the axle crosses the strip");
        assert!(k > 0 && snapshots[k - 1][j].position_m < strip_m);
        let at_strip = &snapshots[k][j];
        assert_eq!(
            *load,
            at_strip.force_n,
            "axle {j}: the strip read {load} N, the tyre force at the crossing step is {} N \
             (one step earlier {} N)",
            at_strip.force_n,
            snapshots[k - 1][j].force_n
        );
        assert!(
            (load - at_strip.static_load_n).abs() > 1.0,
            "a rough road makes the force dynamic"
        );
    }
}

#[test]
fn events_mark_entry_and_exit_and_the_vehicle_record_has_both_times() {
    let (recs, summary) = records(&quiet_default());
    let texts: Vec<String> = recs
        .iter()
        .filter_map(|r| {
            if let Record::Event { text, .. } = r {
                Some(text.clone())
            } else {
                None
            }
        })
        .collect();
    assert!(
        texts.iter().any(|t| t.contains("enters the bridge")),
        "{texts:?}"
    );
    assert!(
        texts.iter().any(|t| t.contains("leaves the bridge")),
        "{texts:?}"
    );
    let vehicle = recs
        .iter()
        .find_map(|r| {
            if let Record::Vehicle { vehicle, .. } = r {
                Some(vehicle.clone())
            } else {
                None
            }
        })
        .unwrap();
    let (entry, exit) = (
        vehicle.entry_time_ns.unwrap(),
        vehicle.exit_time_ns.unwrap(),
    );
    // Front axle at x = -100 m at t = 0 at 20 m/s: enters at 5 s, last axle leaves at (130 + 4.27) / 20.
    assert!((entry as f64 * 1e-9 - 5.0).abs() < 2e-3, "{entry}");
    assert!((exit as f64 * 1e-9 - 134.27 / 20.0).abs() < 2e-3, "{exit}");
    assert!(summary
        .dlc
        .iter()
        .all(|&(_, _, d, sigma)| d > 1.0 && d < 2.0 && sigma > 0.0 && sigma < 0.5));
    assert!((summary.natural_frequencies_hz[0] - 3.78).abs() < 0.01);
}

fn simulate(out: &Path, extra: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_bridgetwin"))
        .args(["simulate", "--out"])
        .arg(out)
        .args(extra)
        .output()
        .expect("binary runs")
}

#[test]
fn same_seed_same_bytes_another_seed_differs() {
    let dir = tempfile::tempdir().unwrap();
    let (a, b, c) = (
        dir.path().join("a.mcap"),
        dir.path().join("b.mcap"),
        dir.path().join("c.mcap"),
    );
    for (path, seed) in [(&a, "7"), (&b, "7"), (&c, "8")] {
        let out = simulate(path, &["--seed", seed, "--duration-s", "6"]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    let (a, b, c) = (
        std::fs::read(a).unwrap(),
        std::fs::read(b).unwrap(),
        std::fs::read(c).unwrap(),
    );
    assert_eq!(a, b);
    assert_ne!(a, c);
}

#[test]
fn existing_output_is_kept_without_force_and_bad_input_leaves_no_file() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("run.mcap");
    std::fs::write(&out, b"keep me").unwrap();
    let r = simulate(&out, &["--duration-s", "1"]);
    assert_eq!(r.status.code(), Some(1));
    assert_eq!(std::fs::read(&out).unwrap(), b"keep me");
    let r = simulate(&out, &["--duration-s", "1", "--force"]);
    assert!(r.status.success());
    assert_ne!(std::fs::read(&out).unwrap(), b"keep me");

    let bad = dir.path().join("bad.toml");
    let text = bridgetwin::scenario::DEFAULT_SCENARIO_TOML
        .replace("position_m = 26.25", "position_m = 31.0");
    std::fs::write(&bad, text).unwrap();
    let target = dir.path().join("bad.mcap");
    let r = Command::new(env!("CARGO_BIN_EXE_bridgetwin"))
        .arg("simulate")
        .arg(&bad)
        .arg("--out")
        .arg(&target)
        .output()
        .unwrap();
    assert_eq!(r.status.code(), Some(1));
    let err = String::from_utf8_lossy(&r.stderr);
    assert!(err.contains("sensors.6[A7].position_m = 31"), "{err}");
    assert!(!target.exists() && !dir.path().join("bad.mcap.partial").exists());
}

#[test]
fn scenario_errors_name_the_field() {
    let cases = [
        (
            "rate_hz = 200.0\n\n[[sensors]]\nid = \"A2\"",
            "rate_hz = 5000.0\n\n[[sensors]]\nid = \"A2\"",
            "sensors.0[A1].rate_hz = 5000",
        ),
        (
            "id = \"A2\"",
            "id = \"A1\"",
            "sensors.1[A1].id = \"A1\" is used twice",
        ),
        (
            "speed_m_s = 20.0",
            "speed_m_s = -3.0",
            "vehicles.0[1].speed_m_s = -3",
        ),
        ("span_m = 30.0", "span_m = 0.0", "bridge.span_m = 0"),
        (
            "dt_s = 0.001",
            "dt_s = 0.001\nbogus = 1",
            "unknown field `bogus`",
        ),
    ];
    for (from, to, expected) in cases {
        let text = bridgetwin::scenario::DEFAULT_SCENARIO_TOML.replacen(from, to, 1);
        let err = Scenario::from_toml(&text, "test.toml")
            .and_then(|s| s.resolve().map(|_| ()))
            .unwrap_err()
            .to_string();
        assert!(err.contains(expected), "{err}");
    }
}

#[test]
fn a_diverging_run_stops_naming_time_step_quantity_and_a_hint() {
    // Newmark with beta < gamma / 2 is only conditionally stable: the highest modes of a
    // 30-element FE model (omega dt far above the limit 1/sqrt(gamma/2 - beta) = 2.6)
    // blow up as soon as the truck excites the bridge.
    let dir = tempfile::tempdir().unwrap();
    let text = bridgetwin::scenario::DEFAULT_SCENARIO_TOML.replace(
        "[solver]",
        "[solver]\nnewmark = { gamma = 0.5, beta = 0.1 }",
    );
    let scenario = dir.path().join("unstable.toml");
    std::fs::write(&scenario, text).unwrap();
    let out_path = dir.path().join("run.mcap");
    let out = simulate(&out_path, &[scenario.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    for needle in [
        "divergence at t = ",
        "(step ",
        "bridge deflection (m) = ",
        "solver.newmark (gamma = 0.5, beta = 0.1) is only conditionally stable",
    ] {
        assert!(stderr.contains(needle), "{needle:?} missing from {stderr}");
    }
    assert_eq!(
        std::fs::read_dir(dir.path()).unwrap().count(),
        1,
        "only the scenario is left"
    );
}
