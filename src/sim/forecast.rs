//! What the time loop will emit, forecast before it runs (see [`RecordForecast`]): the
//! loop's own rules (strides, sample schedules, the tracker's events) applied to the
//! resolved scenario, without stepping the solver.
//!
//! - Sensor samples: every instant `t_k <= duration` of the sensor's rate (on a node
//!   clock, of its true rate): exact for an ideal clock. Faults: their expected losses,
//!   labels and interruptions from the fault table (rates times the duration).
//! - Axle loads and deflected shapes: one record per stride, exact.
//! - Vehicles: the scheduled ones, and the traffic drawn from the run's own generator
//!   (the same seeded streams, so the same vehicles the run will carry), each on the road
//!   from its entry until its last axle is `exit_m` past the bridge. From their speeds
//!   and wheelbases follow the mean number of axles per axle-load record, the bridge
//!   entries and exits on `/events`, the vehicle records, the WIM records and the
//!   vehicles a scene update draws.
//! - Instruments on vehicles and the road: GNSS fixes and vehicle states while their
//!   vehicle is on the road, one axle detection per axle crossing a detector.
//! - Not forecast: contact loss and regain events and ADC clipping notes (they depend on
//!   the response), and a vehicle run as moving forces (rare draws).

use super::traffic::{dynamics_of, generator, MAX_WHEELBASE_M};
use super::Prepared;
use crate::base::random::child_rng;
use crate::error::Result;
use crate::measurement::daq::{FaultSpec, LossSpec};
use crate::measurement::wim::WimPassage;
use crate::physics::vehicle::VehicleDynamics;
use crate::record::{
    AxleState, EventLevel, ForecastRecords, ModalRecord, Quantities, Record, RecordForecast,
    SensorForecast, SensorKind, VehicleRecord, WimRecordData,
};
use crate::scenario::{Resolved, ResolvedSensor};

/// Vehicles drawn from the traffic generator at most. Past them (a run of weeks), the
/// rest of the run is taken to carry the same traffic per second as the part drawn: the
/// draws cost about a microsecond each, so the forecast stays well under a second.
pub const MAX_DRAWN_VEHICLES: usize = 200_000;

/// Seconds per hour, for the fault rates given per hour.
const S_PER_HOUR: f64 = 3600.0;

/// Half the span on either side of the bridge: the stretch a scene update draws vehicles
/// on (`output::scene`).
const SCENE_WINDOW_SPANS: f64 = 0.5;

/// A representative sample's values: non-zero, so that every field is encoded as in a
/// real message (protobuf leaves zeros out).
const TYPICAL_QUANTITIES: Quantities = Quantities {
    displacement_m: 1.25e-3,
    velocity_m_s: 2.5e-3,
    acceleration_m_s2: 3.5e-2,
    strain_microstrain: 12.5,
    moment_n_m: 2.5e5,
    rotation_rad: 2.5e-4,
    reaction_n: 0.0,
    temperature_c: 0.0,
};

/// The typical truth of a sensor of `kind`: only a load cell's carries a reaction, only
/// a thermometer's a temperature.
fn typical_quantities(kind: SensorKind) -> Quantities {
    match kind {
        SensorKind::LoadCell => Quantities {
            reaction_n: 1.25e5,
            ..TYPICAL_QUANTITIES
        },
        SensorKind::Thermometer => Quantities {
            temperature_c: 18.25,
            ..TYPICAL_QUANTITIES
        },
        _ => TYPICAL_QUANTITIES,
    }
}

/// One vehicle's passage over the road, as the forecast needs it.
struct Passage {
    /// Vehicles this passage stands for: 1, or more past [`MAX_DRAWN_VEHICLES`].
    weight: f64,
    axles: usize,
    speed_m_s: f64,
    entry_s: f64,
    wheelbase_m: f64,
}

/// A vehicle of each model the run carries, with how many of that model.
struct Representative {
    dynamics: VehicleDynamics,
    id: u32,
    lane: u32,
    direction: i8,
    speed_m_s: f64,
    count: f64,
}

/// The forecast of the run `resolved` on the model and road of `prepared`.
pub fn forecast(resolved: &Resolved, prepared: &Prepared) -> Result<RecordForecast> {
    let s = &resolved.scenario;
    let duration_ns = resolved.steps * resolved.dt_ns;
    let duration_s = duration_ns as f64 * 1e-9;
    let (passages, representatives) = vehicles(resolved)?;
    let vehicle_count: f64 = representatives.iter().map(|r| r.count).sum();
    let approach_m = s.road.approach_m;
    // The bridge rests, its response exactly zero, until the first vehicle reaches it
    // (ambient excitation moves it from the start).
    let rest_s = match s.ambient {
        Some(_) => 0.0,
        None => passages
            .iter()
            .map(|p| p.entry_s + approach_m / p.speed_m_s)
            .fold(duration_s, f64::min)
            .max(0.0),
    };
    let sensors = resolved
        .sensors
        .iter()
        .map(|sensor| sensor_forecast(sensor, duration_ns, rest_s))
        .collect();

    let mut records = Vec::new();
    let mut push = |record: Record, count: f64| {
        if count > 0.0 {
            records.push(ForecastRecords {
                record,
                count,
                at_rest: false,
            });
        }
    };

    // Axle loads: one record per stride; its axles are those of the vehicles on the road.
    let axle_records = (resolved.steps / resolved.axle_stride + 1) as f64;
    let on_road_m = s.road.approach_m + s.bridge.length_m() + s.road.exit_m;
    let axle_seconds: f64 = passages
        .iter()
        .map(|p| {
            p.weight * p.axles as f64 * overlap_s(p, 0.0, on_road_m + p.wheelbase_m, duration_s)
        })
        .sum();
    let mean_axles = axle_seconds / duration_s.max(f64::MIN_POSITIVE);
    let typical = representatives
        .iter()
        .max_by(|a, b| a.count.total_cmp(&b.count));
    for (axles, weight) in split_mean(mean_axles) {
        let record = Record::AxleLoads {
            t_ns: 0,
            axles: axle_states(typical, axles, s.bridge.length_m()),
        };
        push(record, axle_records * weight);
    }

    // Deflected shapes, with the modal state once a minute and after each rebuild.
    let shapes = resolved.steps / resolved.bridge_stride + 1;
    let nodes = prepared.model.shape_positions_m().len();
    let supports = prepared.model.beam.girder.supports.len();
    let (frequencies_hz, damping) = prepared.model.modal_summary(10);
    let temperatures_c = prepared
        .condition
        .as_ref()
        .map(|c| (c.state.temperature_structure_c, c.state.temperature_air_c));
    let modal_shapes = match &prepared.condition {
        Some(_) => ((duration_s / 60.0).floor() + 1.0).min(shapes as f64),
        None => 0.0,
    };
    let shape = |modal: Option<Box<ModalRecord>>, scale: f64| Record::BridgeShape {
        t_ns: 0,
        deflection_m: (0..nodes)
            .map(|i| scale * 1e-4 * (i as f64 + 1.0))
            .collect(),
        temperatures_c,
        modal,
        support_reaction_n: vec![scale * 1.25e5; supports],
    };
    let modal = ModalRecord {
        natural_frequency_hz: frequencies_hz.clone(),
        damping_ratio: damping.clone(),
        stiffness_ratio: vec![0.99; nodes.saturating_sub(1)],
        damage_fraction: vec![0.1; s.damage.len()],
        support_stiffness_ratio: vec![0.9; supports * usize::from(!s.support_condition.is_empty())],
        support_settlement_m: vec![1e-3; supports * usize::from(!s.support_condition.is_empty())],
    };
    let rest_shapes = ((rest_s / (resolved.bridge_stride as f64 * resolved.dt_s)).floor()
        + f64::from(rest_s > 0.0))
    .min(shapes as f64 - modal_shapes);
    push(shape(Some(Box::new(modal)), 1.0), modal_shapes);
    push(shape(None, 1.0), shapes as f64 - modal_shapes - rest_shapes);
    let rest_shape = ForecastRecords {
        record: shape(None, 0.0),
        count: rest_shapes,
        at_rest: true,
    };

    // Per vehicle: bridge entry and exit on /events, the vehicle record, WIM records.
    let span_m = s.bridge.length_m();
    // Passages whose front axle has covered `distance_m(p)` of its road by the end.
    let reaching = |distance_m: &dyn Fn(&Passage) -> f64| -> f64 {
        passages
            .iter()
            .filter(|p| p.entry_s + distance_m(p) / p.speed_m_s <= duration_s)
            .map(|p| p.weight)
            .sum()
    };
    let entries = reaching(&|_| approach_m);
    let exits = reaching(&|p| approach_m + span_m + p.wheelbase_m);
    let mid_id = (vehicle_count / 2.0).round().max(1.0) as u32;
    let event = |text: String| Record::Event {
        t_ns: 0,
        level: EventLevel::Info,
        text,
    };
    push(
        event(format!("vehicle {mid_id} enters the bridge")),
        entries,
    );
    push(event(format!("vehicle {mid_id} leaves the bridge")), exits);
    for r in &representatives {
        let record = Record::Vehicle {
            t_ns: 0,
            vehicle: vehicle_record(r, mid_id, duration_ns),
        };
        push(record, r.count);
    }
    for (station, (spec, model)) in s
        .wim_stations
        .iter()
        .zip(&resolved.wim_stations)
        .enumerate()
    {
        // A record when the last axle crosses the strip.
        let count = reaching(&|p| approach_m + spec.position_m + p.wheelbase_m);
        if let Some(t) = typical {
            let mut rng = child_rng(s.seed, &format!("wim/{}", spec.id));
            let measurement = model.measure(&wim_passage(t, mid_id), &mut rng);
            let record = Record::Wim {
                t_ns: 0,
                record: WimRecordData {
                    station,
                    measurement,
                },
            };
            push(record, count);
        }
    }

    // GNSS fixes, axle detections and instrumented vehicles' states.
    let axles_past = |x_m: f64| -> f64 {
        passages
            .iter()
            .filter(|p| p.entry_s + (approach_m + x_m + p.wheelbase_m) / p.speed_m_s <= duration_s)
            .map(|p| p.weight * p.axles as f64)
            .sum()
    };
    for (record, count) in super::instruments::forecast(resolved, duration_s, &axles_past) {
        push(record, count);
    }

    // Other events: the run's first line, clock resyncs, damage onsets.
    push(event(super::start_text(resolved, &prepared.model)), 1.0);
    for (node, error) in s.daq_nodes.iter().zip(&resolved.node_clocks) {
        let text = format!(
            "DAQ node {}: clock resynchronised (#{}), error {:.1} us -> {:.1} us",
            node.id, 100, 123.4, -12.3
        );
        push(event(text), error.resyncs_before(duration_s) as f64);
    }
    if let Some(condition) = &prepared.condition {
        for e in condition.environment.events() {
            if e.t_ns <= duration_ns {
                push(event(e.text.clone()), 1.0);
            }
        }
    }

    // Fault labels (and the end-of-run line of sensors that lose samples at random).
    for (index, sensor) in resolved.sensors.iter().enumerate() {
        if let Some(spec) = sensor.spec.faults.as_ref() {
            for (kind, count) in fault_labels(spec, sensor.spec.rate_hz, duration_s) {
                let record = Record::Fault {
                    t_ns: 0,
                    sensor: index,
                    kind,
                    end_ns: Some(duration_ns / 2),
                    magnitude: 1.5,
                };
                push(record, count);
                if kind == "loss_random" && count > 0.0 {
                    let text = format!(
                        "sensor {}: {} samples lost at random (each labelled on /truth/faults)",
                        sensor.spec.id,
                        count.round()
                    );
                    push(event(text), 1.0);
                }
            }
        }
    }

    if rest_shape.count > 0.0 {
        records.push(rest_shape);
    }

    // The vehicles a scene update draws: those with an axle within half a span of the
    // bridge, on average.
    let window_m = SCENE_WINDOW_SPANS * span_m;
    let in_view_s: f64 = passages
        .iter()
        .map(|p| {
            let from_m = approach_m - window_m;
            let to_m = approach_m + span_m + window_m + p.wheelbase_m;
            p.weight * overlap_s(p, from_m, to_m, duration_s)
        })
        .sum();
    let in_view = in_view_s / duration_s.max(f64::MIN_POSITIVE);
    let per_vehicle = typical.map_or(0, |t| t.dynamics.axles.len());
    let scene_axles = match typical {
        Some(_) => axle_states(typical, (in_view.round() as usize) * per_vehicle, span_m),
        None => Vec::new(),
    };

    let mut forecast = RecordForecast {
        duration_ns,
        sensors,
        records,
        scene_axles,
        vehicles: vehicle_count,
    };
    if !resolved.trigger_windows.is_empty() {
        triggered(&mut forecast, &resolved.trigger_windows);
    }
    Ok(forecast)
}

/// `output.trigger`: the sampled streams only within the windows (their share of the
/// run, the samples spread evenly over it), one event opening each window. The share
/// makes the sensor counts approximate (within a sample per window and stream).
fn triggered(forecast: &mut RecordForecast, windows: &[crate::record::TriggerWindow]) {
    let duration_ns = forecast.duration_ns;
    let covered_ns: u64 = windows
        .iter()
        .map(|w| {
            w.end_ns
                .min(duration_ns)
                .saturating_sub(w.start_ns.min(duration_ns))
        })
        .sum();
    let share = covered_ns as f64 / duration_ns.max(1) as f64;
    let scaled = |n: u64| (n as f64 * share).round() as u64;
    for s in &mut forecast.sensors {
        s.samples = scaled(s.samples);
        s.preview_samples = scaled(s.preview_samples);
        s.lost_samples *= share;
        s.rest_samples = s.rest_samples.min(s.samples as f64);
    }
    for r in &mut forecast.records {
        if matches!(
            r.record,
            Record::AxleLoads { .. }
                | Record::BridgeShape { .. }
                | Record::VehicleState { .. }
                | Record::Gnss { .. }
        ) {
            r.count *= share;
        }
    }
    let opened = windows.iter().filter(|w| w.start_ns <= duration_ns).count();
    forecast.records.push(ForecastRecords {
        record: Record::Event {
            t_ns: 0,
            level: EventLevel::Info,
            text: "triggered record 1 of 10: 0.000 s to 100.000 s (vehicle 1 (train/ice3))".into(),
        },
        count: opened as f64,
        at_rest: false,
    });
}

/// Seconds of `[0, duration_s]` during which vehicle `p`'s front axle is between
/// `from_m` and `to_m` along its road (measured from the start of its approach).
fn overlap_s(p: &Passage, from_m: f64, to_m: f64, duration_s: f64) -> f64 {
    let start = p.entry_s + from_m / p.speed_m_s;
    let end = p.entry_s + to_m / p.speed_m_s;
    (end.min(duration_s) - start.max(0.0)).max(0.0)
}

/// `mean` as two whole numbers and their weights: (floor, 1 - frac), (floor + 1, frac).
fn split_mean(mean: f64) -> Vec<(usize, f64)> {
    let low = mean.max(0.0).floor();
    let frac = mean - low;
    let mut out = vec![(low as usize, 1.0 - frac)];
    if frac > 0.0 {
        out.push((low as usize + 1, frac));
    }
    out
}

/// `count` axle states of the typical vehicle (repeated as more vehicles, one id each),
/// half of them on the bridge.
fn axle_states(typical: Option<&Representative>, count: usize, span_m: f64) -> Vec<AxleState> {
    let Some(t) = typical else {
        return Vec::new();
    };
    let per_vehicle = t.dynamics.axles.len().max(1);
    (0..count)
        .map(|k| {
            let axle = &t.dynamics.axles[k % per_vehicle];
            let vehicle = (k / per_vehicle) as u32;
            AxleState {
                vehicle_id: t.id + vehicle,
                axle_index: (k % per_vehicle) as u32,
                lane: t.lane,
                position_m: 0.37 * span_m + axle.offset_m + 7.0 * f64::from(vehicle),
                force_n: 1.01 * axle.static_load_n,
                static_load_n: axle.static_load_n,
                in_contact: true,
                on_bridge: k % 2 == 0,
            }
        })
        .collect()
}

/// The vehicle record of a representative vehicle, with the run's middle id.
fn vehicle_record(r: &Representative, id: u32, duration_ns: u64) -> VehicleRecord {
    let offsets: Vec<f64> = r.dynamics.axles.iter().map(|a| a.offset_m).collect();
    VehicleRecord {
        vehicle_id: id,
        model: r.dynamics.name.clone(),
        lane: r.lane,
        direction: r.direction,
        speed_m_s: r.speed_m_s,
        entry_time_ns: Some(duration_ns / 3),
        exit_time_ns: Some(duration_ns / 2),
        axle_spacing_m: offsets.windows(2).map(|w| w[1] - w[0]).collect(),
        static_axle_load_n: r.dynamics.axles.iter().map(|a| a.static_load_n).collect(),
        gross_weight_n: r.dynamics.gross_weight_n(),
        parameters: r.dynamics.parameters.clone(),
    }
}

/// What a WIM strip sees of the representative vehicle.
fn wim_passage(r: &Representative, id: u32) -> WimPassage {
    let offsets: Vec<f64> = r.dynamics.axles.iter().map(|a| a.offset_m).collect();
    let loads: Vec<f64> = r.dynamics.axles.iter().map(|a| a.static_load_n).collect();
    WimPassage {
        vehicle_id: id,
        lane: r.lane,
        t_first_axle_ns: 1,
        speed_m_s: r.speed_m_s,
        axle_spacing_m: offsets.windows(2).map(|w| w[1] - w[0]).collect(),
        dynamic_axle_load_n: loads.iter().map(|l| 1.02 * l).collect(),
        static_axle_load_n: loads,
        multiple_presence: false,
    }
}

/// The run's vehicles: every passage (scheduled, then drawn; past
/// [`MAX_DRAWN_VEHICLES`] the drawn ones weigh for the rest of the run too) and a
/// representative vehicle of each model with its count.
fn vehicles(resolved: &Resolved) -> Result<(Vec<Passage>, Vec<Representative>)> {
    let s = &resolved.scenario;
    let duration_s = resolved.duration_s();
    let mut passages = Vec::new();
    let mut representatives: Vec<Representative> = Vec::new();
    let mut count_model =
        |dynamics: &VehicleDynamics, id, lane, direction, speed_m_s| match representatives
            .iter_mut()
            .find(|r| r.dynamics.name == dynamics.name)
        {
            Some(r) => r.count += 1.0,
            None => representatives.push(Representative {
                dynamics: dynamics.clone(),
                id,
                lane,
                direction,
                speed_m_s,
                count: 1.0,
            }),
        };
    for v in &resolved.vehicles {
        passages.push(Passage {
            weight: 1.0,
            axles: v.dynamics.axles.len(),
            speed_m_s: v.speed_m_s,
            entry_s: v.entry_step as f64 * resolved.dt_s,
            wheelbase_m: v.dynamics.wheelbase_m(),
        });
        count_model(&v.dynamics, v.id, v.lane, v.direction, v.speed_m_s);
    }
    let scheduled = passages.len();
    if let Some(mut traffic) = generator(resolved)? {
        let sd_rel = s.traffic.as_ref().map_or(0.0, |t| t.parameter_sd_rel);
        // The loop admits every vehicle entering by the end of the step after the last.
        let until_s = duration_s + resolved.dt_s;
        let mut last_entry_s = 0.0;
        let mut drawn = 0usize;
        let mut by_class: Vec<(String, f64)> = Vec::new();
        while let Some(g) = traffic.next_before(until_s) {
            last_entry_s = g.entry_time_s;
            passages.push(Passage {
                weight: 1.0,
                axles: g.axle_load_n.len(),
                speed_m_s: g.speed_m_s,
                entry_s: g.entry_time_s,
                wheelbase_m: g.wheelbase_m().min(MAX_WHEELBASE_M),
            });
            let class = g.class.name().to_string();
            match by_class.iter_mut().find(|(c, _)| *c == class) {
                Some((_, n)) => *n += 1.0,
                None => {
                    // The first vehicle of a class stands for the class.
                    let (dynamics, _) = dynamics_of(&g, sd_rel);
                    representatives.push(Representative {
                        dynamics,
                        id: g.id,
                        lane: g.lane as u32,
                        direction: g.direction,
                        speed_m_s: g.speed_m_s,
                        count: 0.0,
                    });
                    by_class.push((class, 1.0));
                }
            }
            drawn += 1;
            if drawn >= MAX_DRAWN_VEHICLES {
                break;
            }
        }
        let scale = match drawn >= MAX_DRAWN_VEHICLES && last_entry_s > 0.0 {
            true => (until_s / last_entry_s).max(1.0),
            false => 1.0,
        };
        for p in &mut passages[scheduled..] {
            p.weight = scale;
        }
        // The drawn representatives follow the scheduled ones, one per class in order.
        let first = representatives.len() - by_class.len();
        for (r, (_, n)) in representatives[first..].iter_mut().zip(&by_class) {
            r.count = n * scale;
        }
    }
    Ok((passages, representatives))
}

/// The records of one sensor over `duration_ns`, the bridge at rest for its first
/// `rest_s`.
fn sensor_forecast(sensor: &ResolvedSensor, duration_ns: u64, rest_s: f64) -> SensorForecast {
    let samples = match &sensor.clock {
        // The node samples at its true rate from t = 0.
        Some(clock) => (duration_ns as f64 * 1e-9 * clock.true_rate_hz()).floor() as u64 + 1,
        None => sensor.rate.count_until_ns(duration_ns),
    };
    let duration_s = duration_ns as f64 * 1e-9;
    let (lost_samples, interruptions) = match sensor.spec.faults.as_ref() {
        Some(spec) => losses(spec, sensor.spec.rate_hz, samples, duration_s),
        None => (0.0, 0.0),
    };
    let preview_samples = sensor
        .preview_factor
        .map_or(0, |factor| samples.div_ceil(factor.max(1)));
    let truth = typical_quantities(sensor.spec.kind);
    let measured = truth.measured_by(sensor.spec.kind);
    let noisy = sensor.chain.is_some() || sensor.channel_noise_density() > 0.0;
    SensorForecast {
        samples,
        lost_samples,
        rest_samples: (rest_s * sensor.spec.rate_hz).min(samples as f64),
        rest_measured: if noisy { measured } else { 0.0 },
        interruptions,
        preview_samples,
        measured,
        truth,
    }
}

/// Expected lost samples and interruptions of the measured stream of a sensor with
/// faults `spec` sampling `samples` times at `rate_hz` over `duration_s`.
fn losses(spec: &FaultSpec, rate_hz: f64, samples: u64, duration_s: f64) -> (f64, f64) {
    let n = samples as f64;
    let mut lost = 0.0;
    let mut interruptions = 0.0;
    if let Some(loss) = &spec.loss {
        let p = loss.probability();
        lost += p * n;
        // A random loss interrupts at every lost sample; a bursty one once per burst.
        interruptions += match *loss {
            LossSpec::Bursty {
                mean_burst_samples, ..
            } => p * n / mean_burst_samples.max(1.0),
            LossSpec::Random { .. } => p * n,
        };
    }
    for window in &spec.outages {
        let inside_s = (window.start_s + window.duration_s).min(duration_s) - window.start_s;
        if inside_s > 0.0 {
            lost += inside_s * rate_hz;
            interruptions += 1.0;
        }
    }
    if let Some(mean_s) = spec.outage_mean_duration_s {
        let outages = spec.outage_rate_per_hour * duration_s / S_PER_HOUR;
        lost += outages * mean_s * rate_hz;
        interruptions += outages;
    }
    (lost.min(n), interruptions)
}

/// Expected fault labels of each kind of a sensor with faults `spec` at `rate_hz` over
/// `duration_s`.
fn fault_labels(spec: &FaultSpec, rate_hz: f64, duration_s: f64) -> Vec<(&'static str, f64)> {
    let per_run = |rate_per_hour: f64| rate_per_hour * duration_s / S_PER_HOUR;
    let samples = duration_s * rate_hz;
    let mut out = Vec::new();
    if let Some(loss) = &spec.loss {
        let p = loss.probability();
        match *loss {
            LossSpec::Bursty {
                mean_burst_samples, ..
            } => out.push(("loss_burst", p * samples / mean_burst_samples.max(1.0))),
            LossSpec::Random { .. } => out.push(("loss_random", p * samples)),
        }
    }
    let scheduled = spec
        .outages
        .iter()
        .filter(|w| w.start_s < duration_s)
        .count() as f64;
    out.push(("outage", scheduled + per_run(spec.outage_rate_per_hour)));
    if let Some(spikes) = &spec.spikes {
        out.push(("spike", per_run(spikes.rate_per_hour)));
    }
    if let Some(stuck) = &spec.stuck {
        out.push(("stuck", per_run(stuck.rate_per_hour)));
    }
    if let Some(steps) = &spec.offset_steps {
        out.push(("offset_step", per_run(steps.rate_per_hour)));
    }
    if let Some(dead) = &spec.dead {
        out.push(("dead", f64::from(dead.from_s < duration_s)));
    }
    out
}
