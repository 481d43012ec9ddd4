//! Monitoring end to end: the measurement chains, DAQ clocks, faults, ambient excitation and
//! WIM models as a run produces them (records of `sim::run`), beyond the unit tests of
//! each module (`tests/suite/sensor_presets.rs`, `tests/suite/daq.rs`, `tests/suite/ambient.rs`,
//! `tests/suite/wim_models.rs`).

use bridgetwin::sim::Record;

use crate::common::records_of as records;
use crate::common::sensor_samples;
use crate::sensor_presets::{density_standard_error, welch_segments};

/// The paper's bridge (FE 20, dt 1 ms) for `duration_s`.
fn bridge(duration_s: f64) -> String {
    format!("seed = 11\nduration_s = {duration_s}\n{BRIDGE}")
}

const BRIDGE: &str = r#"
[bridge]
span_m = 30.0
flexural_rigidity_n_m2 = 5.629e10
mass_per_length_kg_m = 12000.0
damping_ratio = 0.02
model = { kind = "finite_element", elements = 20 }
[solver]
dt_s = 0.001
"#;

fn sensor(id: &str, x: f64, extra: &str) -> String {
    format!(
        "[[sensors]]\nid = \"{id}\"\nkind = \"accelerometer\"\nposition_m = {x}\nrate_hz = 200.0\n{extra}\n"
    )
}

/// One-sided Welch PSD (the library's: Hann, 50 % overlap) of `x` sampled at `fs_hz`:
/// (frequencies, PSD).
fn welch(x: &[f64], fs_hz: f64, segment: usize) -> (Vec<f64>, Vec<f64>) {
    let psd = bridgetwin::base::signal::welch_psd(x, 1.0 / fs_hz, segment).expect("welch");
    (psd.frequencies, psd.density)
}

#[test]
fn an_idle_bridge_records_the_preset_noise_density_once() {
    // No vehicle, no ambient: a mems_lownoise channel records its self-noise only. Its
    // density between 2 and 60 Hz (above the 0.05 Hz 1/f corner, inside the anti-alias
    // pass band) must be the preset's 22.5 ug/sqrt(Hz) within 5 standard errors: a chain
    // whose noise were also added by the channel would read sqrt(2) = +41 %. Welch over
    // 200 s at 200 Hz with 1024-sample segments averages 77 segments per bin over ~300
    // bins: a standard error of ~0.47 % on the density (`density_standard_error`), so
    // ~2.4 %. The 1/f term adds 0.05 Hz / f, 0.07 % on the band mean: in the expected PSD.
    let toml = format!(
        "{}{}",
        bridge(200.0),
        sensor("A1", 15.0, "preset = \"mems_lownoise\"")
    );
    let recs = records(&toml);
    let x: Vec<f64> = sensor_samples(&recs, 0)
        .iter()
        .map(|s| s.2.unwrap())
        .collect();
    let (f, psd) = welch(&x, 200.0, 1024);
    let band: Vec<f64> = f
        .iter()
        .zip(&psd)
        .filter(|(f, _)| (2.0..60.0).contains(*f))
        .map(|(_, p)| *p)
        .collect();
    let nd2 = (22.5e-6 * 9.80665f64).powi(2);
    let expected_psd: f64 = f
        .iter()
        .filter(|f| (2.0..60.0).contains(*f))
        .map(|f| nd2 * (1.0 + 0.05 / f))
        .sum::<f64>()
        / band.len() as f64;
    let density = (band.iter().sum::<f64>() / band.len() as f64).sqrt();
    let expected = expected_psd.sqrt();
    let error = density / expected - 1.0;
    let sigma = density_standard_error(band.len(), welch_segments(x.len(), 1024));
    eprintln!("density {density:e} vs {expected:e}: {error:+.4} (standard error {sigma:.4})");
    assert!(
        error.abs() < 5.0 * sigma,
        "density {density:e} vs {expected:e}: {error:+.4}, 5 standard errors {:.4}",
        5.0 * sigma
    );
}

#[test]
fn adding_a_sensor_does_not_change_the_others_numbers() {
    let chain =
        "preset = \"mems_lownoise\"\nfaults = { loss = { kind = \"random\", probability = 0.05 } }";
    let two = format!(
        "{}[ambient]\ntarget_rms_m_s2 = 0.01\n{}{}",
        bridge(5.0),
        sensor("A1", 10.0, chain),
        sensor("A2", 20.0, chain)
    );
    let three = format!("{two}{}", sensor("A0", 5.0, chain));
    let (a, b) = (records(&two), records(&three));
    for index in [0, 1] {
        let (sa, sb) = (sensor_samples(&a, index), sensor_samples(&b, index));
        assert_eq!(sa.len(), 1001);
        // Bit for bit: noise, gain and bias draws, losses, and the ambient load.
        assert!(sa == sb, "sensor {index} changed when a sensor was added");
        assert!(sa.iter().any(|s| s.2.is_none()), "some losses expected");
        // The random losses are counted once on /events, not one line per sample.
        let lost = sa.iter().filter(|s| s.2.is_none()).count();
        let id = ["A1", "A2"][index];
        let line = format!("sensor {id}: {lost} samples lost at random");
        assert!(
            a.iter()
                .any(|r| matches!(r, Record::Event { text, .. } if text.starts_with(&line))),
            "no event `{line}`"
        );
    }
}

#[test]
fn node_stamps_drift_at_the_configured_ppm_while_the_truth_keeps_true_time() {
    // 200 ppm, free running, no jitter: the true instants run 200 ppm faster than the
    // stamps, which stay on the nominal 5 ms grid plus the offset. A least-squares fit of
    // stamp - true against true gives the drift; rounding to whole ns (0.3 ns rms over
    // 60 s) limits it to ~1e-5 ppm.
    let toml = format!(
        "{}[[daq_nodes]]\nid = \"N1\"\nclock = {{ offset_s = 0.002, drift_ppm = 200.0 }}\n{}",
        bridge(60.0),
        sensor("A1", 15.0, "daq_node = \"N1\"")
    );
    let s = sensor_samples(&records(&toml), 0);
    for (k, sample) in s.iter().enumerate() {
        assert_eq!(sample.1, 5_000_000 * k as i64 + 2_000_000, "stamp {k}");
    }
    let n = s.len() as f64;
    let (xs, ys): (Vec<f64>, Vec<f64>) = s
        .iter()
        .map(|(t, stamp, ..)| (*t as f64, (*stamp - *t as i64) as f64))
        .unzip();
    let (mx, my) = (xs.iter().sum::<f64>() / n, ys.iter().sum::<f64>() / n);
    let sxy: f64 = xs.iter().zip(&ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = xs.iter().map(|x| (x - mx) * (x - mx)).sum();
    // stamp = k/fs + offset, true = k/(fs (1 + d)): stamp - true = d true + offset.
    let ppm = 1e6 * sxy / sxx;
    assert!((ppm - 200.0).abs() < 1e-3, "fitted drift {ppm} ppm");
    // The last sample: 60 s of true time hold 200 ppm more samples than nominal.
    let expected = (60.0 * 200.0 * 1.0002f64).floor() as usize + 1;
    assert_eq!(s.len(), expected);
}

#[test]
fn every_lost_sample_lies_in_a_labelled_fault_and_every_label_is_in_the_file() {
    let faults =
        "faults = { loss = { kind = \"bursty\", probability = 0.02, mean_burst_samples = 8 }, \
                  outages = [{ start_s = 20.0, duration_s = 3.0 }], \
                  spikes = { rate_per_hour = 360.0, amplitude = 5.0 } }";
    let toml = format!("{}{}", bridge(60.0), sensor("A1", 15.0, faults));
    let recs = records(&toml);
    let labels: Vec<(u64, Option<u64>, &str)> = recs
        .iter()
        .filter_map(|r| match r {
            Record::Fault {
                t_ns, end_ns, kind, ..
            } => Some((*t_ns, *end_ns, *kind)),
            _ => None,
        })
        .collect();
    let inside = |t: u64, kinds: &[&str]| {
        labels
            .iter()
            .any(|(s, e, k)| kinds.contains(k) && *s <= t && e.is_none_or(|e| t < e))
    };
    let s = sensor_samples(&recs, 0);
    let lost: Vec<u64> = s.iter().filter(|x| x.2.is_none()).map(|x| x.0).collect();
    assert!(lost.len() > 300, "{} lost", lost.len());
    for t in &lost {
        assert!(
            inside(*t, &["loss_burst", "outage"]),
            "lost at {t} ns, unlabelled"
        );
    }
    // The outage: every sample in [20, 23) s is lost.
    let outage = s
        .iter()
        .filter(|x| (20_000_000_000..23_000_000_000).contains(&x.0));
    assert!(outage.clone().count() == 600 && outage.clone().all(|x| x.2.is_none()));
    // Spikes: each labelled spike sample is off its truth by the amplitude (the noise is
    // tiny next to 5 m/s^2); no other sample is.
    let spikes: Vec<u64> = labels
        .iter()
        .filter(|l| l.2 == "spike")
        .map(|l| l.0)
        .collect();
    assert!(spikes.len() >= 2, "{spikes:?}");
    for x in &s {
        if let Some(m) = x.2 {
            let off = (m - x.3.acceleration_m_s2).abs() > 2.5;
            assert_eq!(off, spikes.contains(&x.0), "sample at {} ns", x.0);
        }
    }
    // Records stay in time order with the labels among them.
    assert!(recs.windows(2).all(|w| w[0].t_ns() <= w[1].t_ns()));
}

#[test]
fn ambient_excitation_reaches_its_target_rms_through_the_whole_run() {
    // The acceleration truth at midspan over 300 s, after 5 s: within 10 % of the target
    // (the statistical error of a 300 s RMS estimate of a 2 %-damped 3.8 Hz mode is ~4 %;
    // tests/suite/ambient.rs checks the calibration itself to 0.01 %).
    let toml = format!(
        "{}[ambient]\ntarget_rms_m_s2 = 0.004\n{}",
        bridge(300.0),
        sensor("A1", 15.0, "preset = \"ideal\"")
    );
    let s = sensor_samples(&records(&toml), 0);
    let a: Vec<f64> = s
        .iter()
        .filter(|x| x.0 > 5_000_000_000)
        .map(|x| x.3.acceleration_m_s2)
        .collect();
    let rms = (a.iter().map(|v| v * v).sum::<f64>() / a.len() as f64).sqrt();
    assert!((rms / 0.004 - 1.0).abs() < 0.10, "rms {rms}");
}

#[test]
fn wim_records_of_a_cost323_station_add_up_and_name_their_vehicle() {
    let toml = format!(
        "{BRIDGE}\n[road]\nprofile = {{ kind = \"iso8608\", class = \"A\" }}\n\
         [[vehicles]]\nid = 4\nmodel = {{ kind = \"half_car\", preset = \"two_axle_truck\" }}\nspeed_m_s = 20.0\n\
         [[wim_stations]]\nid = \"W\"\nposition_m = -20.0\nmodel = {{ kind = \"cost323\", class = \"A(5)\" }}\n\
         [[wim_stations]]\nid = \"P\"\nposition_m = -10.0\nmodel = {{ kind = \"physics\", noise_rel = 0.0, speed_sigma_rel = 0.0 }}\n"
    );
    let recs = records(&toml);
    let wim: Vec<_> = recs
        .iter()
        .filter_map(|r| match r {
            Record::Wim { record, .. } => Some(record.clone()),
            _ => None,
        })
        .collect();
    assert_eq!(wim.len(), 2);
    let truth = recs
        .iter()
        .find_map(|r| match r {
            Record::Vehicle { vehicle, .. } => Some(vehicle.clone()),
            _ => None,
        })
        .expect("vehicle truth");
    for w in &wim {
        let m = &w.measurement;
        assert_eq!(m.vehicle_id, truth.vehicle_id);
        assert_eq!(m.axle_pattern, "1-1");
        let sum: f64 = m.axle_load_n.iter().sum();
        assert!((m.gross_weight_n - sum).abs() < 1e-6 * sum);
    }
    // COST 323 errors are relative to the static loads, so the reported gross weight
    // recovers the truth's through the recorded error exactly.
    let cost = &wim[0].measurement;
    let back = cost.gross_weight_n / (1.0 + cost.truth.gross_rel);
    assert!((back / truth.gross_weight_n - 1.0).abs() < 1e-9, "{back}");
    // A physics strip without noise reads the dynamic tyre force: not the static load.
    let physics = &wim[1].measurement;
    assert!(physics.truth.axle_rel.iter().all(|e| *e == 0.0));
    assert!((physics.gross_weight_n / truth.gross_weight_n - 1.0).abs() > 1e-4);
}

#[test]
fn a_vehicle_in_the_opposite_direction_mirrors_the_response() {
    // A moving force towards -x from the right support is the mirror image of the same
    // force towards +x: the response at x under one equals the response at L - x under
    // the other, to round-off (the mesh is symmetric, the road smooth).
    let run = |direction: i8| {
        let toml = format!(
            "{}[[vehicles]]\nmodel = {{ kind = \"moving_force\", axle_loads_n = [60000.0, 120000.0], \
             axle_spacing_m = [4.0] }}\nspeed_m_s = 20.0\ndirection = {direction}\n{}{}",
            bridge(9.0),
            sensor("Q1", 7.5, "preset = \"ideal\""),
            sensor("Q3", 22.5, "preset = \"ideal\"")
        );
        let recs = records(&toml);
        let times = recs
            .iter()
            .find_map(|r| match r {
                Record::Vehicle { vehicle, .. } => {
                    Some((vehicle.entry_time_ns, vehicle.exit_time_ns))
                }
                _ => None,
            })
            .expect("vehicle truth");
        (sensor_samples(&recs, 0), sensor_samples(&recs, 1), times)
    };
    let (fwd_q1, fwd_q3, fwd_times) = run(1);
    let (rev_q1, rev_q3, rev_times) = run(-1);
    // Both enter their bridge end at the same instant and leave it together.
    assert!(fwd_times.0.is_some() && fwd_times.1.is_some());
    assert_eq!(fwd_times, rev_times);
    let peak = fwd_q1
        .iter()
        .fold(0.0f64, |a, s| a.max(s.3.displacement_m.abs()));
    assert!(peak > 1e-4, "deflection peak {peak}");
    for (a, b) in [(&fwd_q1, &rev_q3), (&fwd_q3, &rev_q1)] {
        assert_eq!(a.len(), b.len());
        for (x, y) in a.iter().zip(b.iter()) {
            assert!(
                (x.3.displacement_m - y.3.displacement_m).abs() < 1e-9 * peak,
                "{} vs {}",
                x.3.displacement_m,
                y.3.displacement_m
            );
        }
    }
}
