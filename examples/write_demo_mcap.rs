//! Writes a small synthetic MCAP with the shape of a real run, to exercise the Python tools
//! and the Foxglove layout before the simulation exists. Every message type appears.
//!
//!     cargo run --example write_demo_mcap -- demo.mcap [--force]
//!
//! A two-axle vehicle crosses a 30 m simply supported span at 20 m/s. Deflection and
//! moment come from the static influence lines (no dynamics); the "acceleration" is a
//! 2.5 Hz sine that grows while the vehicle is on the bridge. Only the format is meaningful.

use std::collections::BTreeMap;
use std::f64::consts::PI;
use std::path::PathBuf;

use anyhow::{bail, Context, Result};
use bridgetwin::output::proto::{foxglove, v1};
use bridgetwin::output::{metadata, timestamp_from_ns, ChannelId, McapSink, SinkOptions, Topics};

/// 2026-01-01T00:00:00Z, the default scenario start.
const START_NS: u64 = 1_767_225_600_000_000_000;
const SAMPLE_PERIOD_NS: u64 = 5_000_000; // 200 Hz
const DURATION_NS: u64 = 4_000_000_000;
const BLOCK_LEN: u64 = 100; // samples per DAQ packet (0.5 s)
const SPAN_M: f64 = 30.0;
const EI_N_M2: f64 = 5.629e10;
const NEUTRAL_AXIS_TO_BOTTOM_M: f64 = 0.8;
const SPEED_M_S: f64 = 20.0;
const ENTRY_NS: u64 = 1_000_000_000; // front axle at x = 0
const AXLE_OFFSETS_M: [f64; 2] = [0.0, 4.0]; // behind the front axle
const AXLE_LOADS_N: [f64; 2] = [40e3, 80e3];
const WIM_POSITION_M: f64 = -10.0;
const SENSOR_POSITION_M: f64 = 15.0;
const NODES: usize = 31;

/// Deflection (positive downward) and bending moment (positive sagging) at `x_m` of a
/// simply supported beam under a point load `p_n` at `a_m` (Euler-Bernoulli closed form,
/// e.g. Roark's Formulas for Stress and Strain, Table 8.1 case 1e).
fn beam_response(x_m: f64, a_m: f64, p_n: f64) -> (f64, f64) {
    if !(0.0..=SPAN_M).contains(&a_m) {
        return (0.0, 0.0);
    }
    // Mirror so that the section is left of the load.
    let (x, a) = if x_m <= a_m {
        (x_m, a_m)
    } else {
        (SPAN_M - x_m, SPAN_M - a_m)
    };
    let b = SPAN_M - a;
    let deflection_m = p_n * b * x * (SPAN_M * SPAN_M - b * b - x * x) / (6.0 * EI_N_M2 * SPAN_M);
    (deflection_m, p_n * b * x / SPAN_M)
}

/// Axle positions along the bridge at `t_ns` since the start of the run.
fn axle_positions_m(t_ns: u64) -> [f64; 2] {
    let front_m = (t_ns as f64 - ENTRY_NS as f64) * 1e-9 * SPEED_M_S;
    AXLE_OFFSETS_M.map(|offset| front_m - offset)
}

/// (deflection_m, moment_n_m) at `x_m` under the whole vehicle.
fn response_at(x_m: f64, t_ns: u64) -> (f64, f64) {
    let positions = axle_positions_m(t_ns);
    (0..2)
        .map(|k| beam_response(x_m, positions[k], AXLE_LOADS_N[k]))
        .fold((0.0, 0.0), |(w, m), (dw, dm)| (w + dw, m + dm))
}

fn strain_microstrain(moment_n_m: f64) -> f64 {
    moment_n_m * NEUTRAL_AXIS_TO_BOTTOM_M / EI_N_M2 * 1e6
}

fn acceleration_m_s2(t_ns: u64) -> f64 {
    let on_bridge = axle_positions_m(t_ns)
        .iter()
        .any(|x| (0.0..=SPAN_M).contains(x));
    let amplitude = if on_bridge { 0.05 } else { 0.01 };
    amplitude * (2.0 * PI * 2.5 * t_ns as f64 * 1e-9).sin()
}

/// Time since the start at which the front axle is at `x_m`.
fn front_axle_time_ns(x_m: f64) -> u64 {
    (ENTRY_NS as f64 + x_m / SPEED_M_S * 1e9).round() as u64
}

struct Channels {
    accel: ChannelId,
    accel_blocks: ChannelId,
    strain: ChannelId,
    disp: ChannelId,
    truth_a1: ChannelId,
    truth_d1: ChannelId,
    axles: ChannelId,
    vehicles: ChannelId,
    bridge: ChannelId,
    wim: ChannelId,
    events: ChannelId,
}

fn add_channels(sink: &mut McapSink) -> Result<Channels> {
    let sensor_meta = |unit: &str| {
        metadata([
            ("unit", unit),
            ("sample_rate_hz", "200"),
            ("position_m", "15"),
            ("sensor_model", "synthetic"),
        ])
    };
    let accel_topic = Topics::accel("A1")?;
    let none = BTreeMap::new;
    Ok(Channels {
        accel: sink.add_channel::<v1::AccelerationSample>(&accel_topic, sensor_meta("m/s^2"))?,
        accel_blocks: sink
            .add_channel::<v1::SampleBlock>(&Topics::blocks(&accel_topic)?, sensor_meta("m/s^2"))?,
        strain: sink
            .add_channel::<v1::StrainSample>(&Topics::strain("S1")?, sensor_meta("microstrain"))?,
        disp: sink.add_channel::<v1::DisplacementSample>(&Topics::disp("D1")?, sensor_meta("m"))?,
        truth_a1: sink.add_channel::<v1::SensorTruth>(&Topics::truth_sensor("A1")?, none())?,
        truth_d1: sink.add_channel::<v1::SensorTruthBlock>(&Topics::truth_sensor("D1")?, none())?,
        axles: sink.add_channel::<v1::AxleLoads>(Topics::AXLE_LOADS, none())?,
        vehicles: sink.add_channel::<v1::VehicleTruth>(Topics::VEHICLES, none())?,
        bridge: sink.add_channel::<v1::BridgeState>(Topics::BRIDGE, none())?,
        wim: sink.add_channel::<v1::WimRecord>(&Topics::wim("W1")?, none())?,
        events: sink.add_channel::<foxglove::Log>(Topics::EVENTS, none())?,
    })
}

fn main() -> Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some(path) = args.first().map(PathBuf::from) else {
        bail!("usage: write_demo_mcap OUT.mcap [--force]");
    };
    let options = SinkOptions {
        force: args.iter().any(|a| a == "--force"),
        ..SinkOptions::default()
    };
    let mut sink = McapSink::create(&path, options)?;

    let run = metadata([
        ("version", env!("CARGO_PKG_VERSION")),
        ("seed", "0"),
        ("start_time", "2026-01-01T00:00:00Z"),
        ("generator", "examples/write_demo_mcap.rs"),
    ]);
    sink.write_metadata("bridgetwin", run)?;
    let scenario = "# synthetic demo, not a simulation\nseed = 0\n";
    sink.write_metadata("scenario", metadata([("toml", scenario)]))?;
    let model = metadata([("span_m", "30"), ("flexural_rigidity_n_m2", "5.629e10")]);
    sink.write_metadata("bridge_model", model)?;
    sink.attach(
        "scenario.toml",
        "application/toml",
        scenario.as_bytes(),
        START_NS,
    )?;

    let ch = add_channels(&mut sink)?;
    let exit_ns = front_axle_time_ns(SPAN_M + AXLE_OFFSETS_M[1]);
    for i in 0..DURATION_NS / SAMPLE_PERIOD_NS {
        write_step(&mut sink, &ch, i, exit_ns)?;
    }

    let profile = "x_m,elevation_m\n-100,0\n30,0\n";
    sink.attach(
        "road_profile.csv",
        "text/csv",
        profile.as_bytes(),
        START_NS + DURATION_NS,
    )?;
    let done = sink
        .finish()
        .with_context(|| format!("finishing {}", path.display()))?;
    println!("wrote {}", done.display());
    Ok(())
}

/// Everything due at sample `i`, in a fixed order (the sink only requires time order).
fn write_step(sink: &mut McapSink, ch: &Channels, i: u64, exit_ns: u64) -> Result<()> {
    let t_ns = i * SAMPLE_PERIOD_NS;
    let log_time_ns = START_NS + t_ns;
    let timestamp = Some(timestamp_from_ns(log_time_ns));
    let due = |event_ns: u64| (t_ns..t_ns + SAMPLE_PERIOD_NS).contains(&event_ns);
    // Events at the sample that contains them, stamped with the sample time.
    for (event_ns, text) in [
        (ENTRY_NS, "vehicle 1 enters the bridge"),
        (exit_ns, "vehicle 1 leaves the bridge"),
    ] {
        if due(event_ns) {
            let log = foxglove::Log {
                timestamp,
                level: foxglove::log::Level::Info as i32,
                message: text.into(),
                name: "traffic".into(),
                ..Default::default()
            };
            sink.write(ch.events, log_time_ns, &log)?;
        }
    }
    if due(front_axle_time_ns(WIM_POSITION_M)) {
        let record = v1::WimRecord {
            timestamp,
            station_id: "W1".into(),
            vehicle_id: 1,
            speed_m_s: SPEED_M_S * 1.01,
            axle_count: 2,
            axle_spacing_m: vec![AXLE_OFFSETS_M[1]],
            axle_load_n: AXLE_LOADS_N.iter().map(|p| p * 0.97).collect(),
            gross_weight_n: AXLE_LOADS_N.iter().sum::<f64>() * 0.97,
            axle_pattern: "1-1".into(),
            ..Default::default()
        };
        sink.write(ch.wim, log_time_ns, &record)?;
    }

    let acceleration = acceleration_m_s2(t_ns);
    let (displacement_m, moment_n_m) = response_at(SENSOR_POSITION_M, t_ns);
    let strain = strain_microstrain(moment_n_m);
    let sample = v1::AccelerationSample {
        timestamp,
        acceleration_m_s2: acceleration,
    };
    sink.write(ch.accel, log_time_ns, &sample)?;
    let sample = v1::StrainSample {
        timestamp,
        strain_microstrain: strain,
    };
    sink.write(ch.strain, log_time_ns, &sample)?;
    let sample = v1::DisplacementSample {
        timestamp,
        displacement_m,
    };
    sink.write(ch.disp, log_time_ns, &sample)?;
    let velocity_m_s = (response_at(SENSOR_POSITION_M, t_ns + 1_000_000).0
        - response_at(SENSOR_POSITION_M, t_ns.saturating_sub(1_000_000)).0)
        / 2e-3;
    let truth = v1::SensorTruth {
        timestamp,
        sensor_id: "A1".into(),
        displacement_m,
        velocity_m_s,
        acceleration_m_s2: acceleration,
        strain_microstrain: strain,
        moment_n_m,
        ..Default::default()
    };
    sink.write(ch.truth_a1, log_time_ns, &truth)?;

    if i.is_multiple_of(BLOCK_LEN) {
        let times_ns: Vec<u64> = (i..i + BLOCK_LEN).map(|k| k * SAMPLE_PERIOD_NS).collect();
        let block = v1::SampleBlock {
            timestamp,
            sample_period_ns: SAMPLE_PERIOD_NS,
            quantity: "acceleration".into(),
            unit: "m/s^2".into(),
            values: times_ns.iter().map(|&t| acceleration_m_s2(t)).collect(),
        };
        sink.write(ch.accel_blocks, log_time_ns, &block)?;
        let responses: Vec<(f64, f64)> = times_ns
            .iter()
            .map(|&t| response_at(SENSOR_POSITION_M, t))
            .collect();
        let block = v1::SensorTruthBlock {
            timestamp,
            sample_period_ns: SAMPLE_PERIOD_NS,
            sensor_id: "D1".into(),
            displacement_m: responses.iter().map(|r| r.0).collect(),
            moment_n_m: responses.iter().map(|r| r.1).collect(),
            strain_microstrain: responses.iter().map(|r| strain_microstrain(r.1)).collect(),
            ..Default::default()
        };
        sink.write(ch.truth_d1, log_time_ns, &block)?;
    }
    if i.is_multiple_of(2) {
        let positions = axle_positions_m(t_ns);
        let axles = (0..2)
            .map(|k| v1::AxleLoad {
                vehicle_id: 1,
                axle_index: k as u32,
                position_m: positions[k],
                force_n: AXLE_LOADS_N[k]
                    * (1.0 + 0.05 * (12.0 * t_ns as f64 * 1e-9 + k as f64).sin()),
                static_load_n: AXLE_LOADS_N[k],
                in_contact: true,
                on_bridge: (0.0..=SPAN_M).contains(&positions[k]),
            })
            .collect();
        sink.write(ch.axles, log_time_ns, &v1::AxleLoads { timestamp, axles })?;
    }
    if i.is_multiple_of(20) {
        let node_position_m: Vec<f64> = (0..NODES)
            .map(|n| SPAN_M * n as f64 / (NODES - 1) as f64)
            .collect();
        let deflection_m: Vec<f64> = node_position_m
            .iter()
            .map(|&x| response_at(x, t_ns).0)
            .collect();
        let state = v1::BridgeState {
            timestamp,
            midspan_deflection_m: deflection_m[NODES / 2],
            node_position_m,
            deflection_m,
            natural_frequency_hz: vec![2.5, 10.0],
            damping_ratio: vec![0.02, 0.02],
            temperature_c: 15.0,
            ..Default::default()
        };
        sink.write(ch.bridge, log_time_ns, &state)?;
    }
    if due(exit_ns) {
        let parameters = [("body_mass_kg", 11e3), ("suspension_stiffness_n_m", 1.2e6)]
            .map(|(k, v)| (k.to_owned(), v))
            .into();
        let vehicle = v1::VehicleTruth {
            timestamp,
            vehicle_id: 1,
            vehicle_class: "two_axle_truck".into(),
            model: "moving_force".into(),
            direction: v1::TravelDirection::IncreasingX as i32,
            speed_m_s: SPEED_M_S,
            entry_time: Some(timestamp_from_ns(START_NS + ENTRY_NS)),
            exit_time: Some(timestamp_from_ns(START_NS + exit_ns)),
            axle_spacing_m: vec![AXLE_OFFSETS_M[1]],
            static_axle_load_n: AXLE_LOADS_N.to_vec(),
            gross_weight_n: AXLE_LOADS_N.iter().sum(),
            parameters,
            ..Default::default()
        };
        sink.write(ch.vehicles, log_time_ns, &vehicle)?;
    }
    Ok(())
}
