//! Turns the records of a run (`sim::Record`) into protobuf messages on the MCAP topics of
//! the output contract.

use std::collections::BTreeMap;
use std::io::{Seek, Write};
use std::time::{Duration, Instant};

use super::blocks::{ClosedBlock, OpenBlock, Pending, Reorder, Stream};
use super::proto::foxglove::{log::Level, Log};
use super::proto::v1::{
    AccelerationSample, AxleGroup as WimAxleGroup, AxleLoad, AxleLoads, BridgeState,
    DisplacementSample, FaultInterval, SampleBlock, SensorTruth, SensorTruthBlock, StrainSample,
    TravelDirection, VehicleTruth, WimRecord,
};
use super::{metadata, timestamp_from_ns, ChannelId, McapSink, Topics};
use crate::error::Result;
use crate::measurement::wim::{LoadReference, WimModelSpec};
use crate::scenario::{Layout, Resolved, SensorKind};
use crate::sim::{EventLevel, Quantities, Record, Recorder};

/// Channel of one sensor.
struct SensorChannels {
    kind: SensorKind,
    id: String,
    measured: ChannelId,
    truth: ChannelId,
    /// Block layout only: the truth samples waiting to fill the next block.
    block: Option<OpenBlock>,
    /// Block layout only: the measured samples waiting to fill the next block.
    measured_block: Option<OpenBlock>,
}

impl SensorChannels {
    /// The open blocks (none in the sample layout).
    fn open_blocks(&mut self) -> impl Iterator<Item = &mut OpenBlock> {
        self.block.iter_mut().chain(self.measured_block.iter_mut())
    }
}

/// A `Recorder` writing to an MCAP sink.
pub struct McapRecorder<'a, W: Write + Seek> {
    sink: &'a mut McapSink<W>,
    start_time_ns: u64,
    sensors: Vec<SensorChannels>,
    axle_loads: ChannelId,
    bridge: ChannelId,
    vehicles: ChannelId,
    wim: Vec<(String, ChannelId)>,
    /// Each station's model, as written in its records ("cost323 B+(7)").
    wim_models: Vec<String>,
    events: ChannelId,
    /// `/truth/faults`, registered when some sensor has faults configured.
    faults: Option<ChannelId>,
    node_position_m: Vec<f64>,
    span_m: f64,
    /// Block layout: sensor samples go into blocks, every record through `reorder`.
    blocked: bool,
    /// Block layout: records waiting until no open block starts before them.
    reorder: Reorder,
    closed: Vec<ClosedBlock>,
    /// Wall-clock interval between chunk flushes (a killed run stays readable up to the
    /// last flush); `None` flushes only at the end.
    flush_every: Option<Duration>,
    last_flush: Instant,
    /// Messages written.
    pub messages: u64,
    /// Wall time spent encoding and writing (the rest of a run is physics and sensors).
    pub write_time: Duration,
}

impl<'a, W: Write + Seek> McapRecorder<'a, W> {
    /// Registers every channel of the scenario, with units, rates and positions as channel
    /// metadata.
    pub fn new(
        sink: &'a mut McapSink<W>,
        resolved: &Resolved,
        node_position_m: Vec<f64>,
    ) -> Result<Self> {
        let output = &resolved.scenario.output;
        let sensors = resolved
            .sensors
            .iter()
            .map(|s| sensor_channels(sink, resolved, s))
            .collect::<Result<Vec<_>>>()?;
        let axle_rate = format!("{}", output.axle_load_rate_hz);
        let axle_loads = sink.add_channel::<AxleLoads>(
            Topics::AXLE_LOADS,
            metadata([
                ("unit", "N"),
                ("sample_rate_hz", axle_rate.as_str()),
                ("sign", "force on the road positive"),
            ]),
        )?;
        let bridge_rate = format!("{}", output.bridge_state_rate_hz);
        let bridge = sink.add_channel::<BridgeState>(
            Topics::BRIDGE,
            metadata([
                ("unit", "m"),
                ("sample_rate_hz", bridge_rate.as_str()),
                ("sign", "deflection downward positive"),
            ]),
        )?;
        let vehicles = sink.add_channel::<VehicleTruth>(
            Topics::VEHICLES,
            metadata([("content", "one record per vehicle")]),
        )?;
        let mut wim = Vec::new();
        let mut wim_models = Vec::new();
        for w in &resolved.scenario.wim_stations {
            let position = format!("{}", w.position_m);
            let model = wim_model_label(&w.model);
            let ch = sink.add_channel::<WimRecord>(
                &Topics::wim(&w.id)?,
                metadata([
                    ("position_m", position.as_str()),
                    ("station_model", model.as_str()),
                ]),
            )?;
            wim.push((w.id.clone(), ch));
            wim_models.push(model);
        }
        let events = sink.add_channel::<Log>(Topics::EVENTS, BTreeMap::new())?;
        let faults = match resolved.has_faults() {
            true => Some(sink.add_channel::<FaultInterval>(
                Topics::FAULTS,
                metadata([("content", "one record per fault interval, at its start")]),
            )?),
            false => None,
        };
        Ok(McapRecorder {
            sink,
            start_time_ns: resolved.start_time_ns,
            sensors,
            axle_loads,
            bridge,
            vehicles,
            wim,
            wim_models,
            events,
            faults,
            node_position_m,
            span_m: resolved.scenario.bridge.span_m,
            blocked: output.layout == Layout::Block,
            reorder: Reorder::default(),
            closed: Vec::new(),
            flush_every: None,
            last_flush: Instant::now(),
            messages: 0,
            write_time: Duration::ZERO,
        })
    }

    /// Closes the current chunk every `interval` of wall time, so that a run killed
    /// midway leaves a file readable up to the last flush.
    pub fn flush_every(&mut self, interval: Duration) {
        self.flush_every = Some(interval);
    }

    /// Writes the modal state at the start on `/truth/bridge`, with the (structure, air)
    /// temperatures when the run has an environment (so that no message of a run with
    /// temperatures reads 0 degC).
    pub fn write_modal_state(
        &mut self,
        frequencies_hz: &[f64],
        damping_ratios: &[f64],
        temperatures_c: Option<(f64, f64)>,
    ) -> Result<()> {
        let (temperature_c, air_temperature_c) = temperatures_c.unwrap_or_default();
        let time = self.start_time_ns;
        let msg = BridgeState {
            timestamp: Some(timestamp_from_ns(time)),
            node_position_m: self.node_position_m.clone(),
            deflection_m: vec![0.0; self.node_position_m.len()],
            natural_frequency_hz: frequencies_hz.to_vec(),
            damping_ratio: damping_ratios.to_vec(),
            temperature_c,
            air_temperature_c,
            ..Default::default()
        };
        self.messages += 1;
        self.sink.write(self.bridge, time, &msg)
    }

    /// Block layout: queues `record` (sensor samples go into their blocks) and writes
    /// whatever no open block precedes any more.
    fn record_blocked(&mut self, record: Record) -> Result<()> {
        match record {
            Record::Sensor {
                sensor,
                t_ns,
                stamp_ns,
                measured,
                truth,
            } => {
                let channels = &mut self.sensors[sensor];
                if let Some(block) = channels.block.as_mut() {
                    block.push(sensor, (t_ns, t_ns as i64), &truth, &mut self.closed);
                }
                if let (Some(block), Some(m)) = (channels.measured_block.as_mut(), measured) {
                    block.push(sensor, (t_ns, stamp_ns), &[m], &mut self.closed);
                }
            }
            other => self.reorder.push(other.t_ns(), Pending::Record(other)),
        }
        for block in self.closed.drain(..) {
            self.reorder.push(block.start_ns, Pending::Block(block));
        }
        self.release()
    }

    /// Writes queued items up to the earliest start of a block still filling.
    fn release(&mut self) -> Result<()> {
        let watermark = self
            .sensors
            .iter_mut()
            .flat_map(|s| s.open_blocks().filter_map(|b| b.start_ns()))
            .min()
            .unwrap_or(u64::MAX);
        while let Some(item) = self.reorder.pop_until(watermark) {
            match item {
                Pending::Record(r) => self.write_record(r)?,
                Pending::Block(b) => self.write_block(b)?,
            }
        }
        Ok(())
    }

    fn write_block(&mut self, block: ClosedBlock) -> Result<()> {
        let time = self.start_time_ns + block.start_ns;
        let ch = &self.sensors[block.sensor];
        let period = ch.block.as_ref().map_or(0, OpenBlock::period_ns_rounded);
        self.messages += 1;
        match block.stream {
            Stream::Measured => {
                let (quantity, unit) = match ch.kind {
                    SensorKind::Accelerometer => ("acceleration", "m/s^2"),
                    SensorKind::Strain => ("strain", "microstrain"),
                    SensorKind::Displacement => ("displacement", "m"),
                };
                let stamp = self
                    .start_time_ns
                    .saturating_add_signed(block.start_stamp_ns);
                let measured = SampleBlock {
                    timestamp: Some(timestamp_from_ns(stamp)),
                    sample_period_ns: period,
                    quantity: quantity.into(),
                    unit: unit.into(),
                    values: block.columns.into_iter().next().unwrap_or_default(),
                };
                let channel = ch.measured;
                self.sink.write(channel, time, &measured)
            }
            Stream::Truth => {
                let mut columns = block.columns.into_iter();
                let mut next = || columns.next().unwrap_or_default();
                let truth = SensorTruthBlock {
                    timestamp: Some(timestamp_from_ns(time)),
                    sample_period_ns: period,
                    sensor_id: ch.id.clone(),
                    displacement_m: next(),
                    velocity_m_s: next(),
                    acceleration_m_s2: next(),
                    strain_microstrain: next(),
                    moment_n_m: next(),
                };
                let channel = ch.truth;
                self.sink.write(channel, time, &truth)
            }
        }
    }

    /// The measured message (stamped by the node's clock; none when lost) and the truth
    /// message (true time) of one sample; `time` is the true instant, the log time of both.
    fn write_sensor_sample(
        &mut self,
        sensor: usize,
        time: u64,
        stamp_ns: i64,
        measured: Option<f64>,
        truth: &Quantities,
    ) -> Result<()> {
        let ch = &self.sensors[sensor];
        let true_stamp = Some(timestamp_from_ns(time));
        let node_stamp = Some(timestamp_from_ns(
            self.start_time_ns.saturating_add_signed(stamp_ns),
        ));
        if let Some(measured) = measured {
            let timestamp = node_stamp;
            self.messages += 1;
            match ch.kind {
                SensorKind::Accelerometer => self.sink.write(
                    ch.measured,
                    time,
                    &AccelerationSample {
                        timestamp,
                        acceleration_m_s2: measured,
                    },
                )?,
                SensorKind::Strain => self.sink.write(
                    ch.measured,
                    time,
                    &StrainSample {
                        timestamp,
                        strain_microstrain: measured,
                    },
                )?,
                SensorKind::Displacement => self.sink.write(
                    ch.measured,
                    time,
                    &DisplacementSample {
                        timestamp,
                        displacement_m: measured,
                    },
                )?,
            }
        }
        self.messages += 1;
        let msg = SensorTruth {
            timestamp: true_stamp,
            sensor_id: ch.id.clone(),
            displacement_m: truth[0],
            velocity_m_s: truth[1],
            acceleration_m_s2: truth[2],
            strain_microstrain: truth[3],
            moment_n_m: truth[4],
            // Only where a node clock makes it differ: it would add 8 % to the file else.
            node_timestamp: (stamp_ns != time.wrapping_sub(self.start_time_ns) as i64)
                .then_some(node_stamp)
                .flatten(),
            measured_lost: measured.is_none(),
        };
        self.sink.write(ch.truth, time, &msg)
    }

    /// A fault label: on `/truth/faults`, and on `/events` unless it is a single randomly
    /// lost sample (those would flood the log; `/truth/faults` has each of them).
    fn write_fault(
        &mut self,
        time: u64,
        sensor: usize,
        kind: &'static str,
        end_ns: Option<u64>,
        magnitude: f64,
    ) -> Result<()> {
        let Some(channel) = self.faults else {
            return Ok(());
        };
        let id = self.sensors[sensor].id.clone();
        let end = end_ns.map(|e| self.start_time_ns + e);
        let msg = FaultInterval {
            timestamp: Some(timestamp_from_ns(time)),
            sensor_id: id.clone(),
            kind: kind.into(),
            end_time: end.map(timestamp_from_ns),
            magnitude,
        };
        self.sink.write(channel, time, &msg)?;
        if kind == "loss_random" {
            return Ok(());
        }
        self.messages += 1;
        let log = Log {
            timestamp: Some(timestamp_from_ns(time)),
            level: Level::Warning as i32,
            message: match end {
                Some(end) => format!(
                    "fault {kind} on sensor {id}: {:.3} s, magnitude {magnitude}",
                    end.saturating_sub(time) as f64 * 1e-9
                ),
                None => format!(
                    "fault {kind} on sensor {id}: to the end of the run, magnitude {magnitude}"
                ),
            },
            name: "bridgetwin".into(),
            file: String::new(),
            line: 0,
        };
        self.sink.write(self.events, time, &log)
    }

    /// Writes one record as one message (sensor samples: two, measured and truth).
    fn write_record(&mut self, record: Record) -> Result<()> {
        let time = self.start_time_ns + record.t_ns();
        let ts = Some(timestamp_from_ns(time));
        if !matches!(record, Record::Sensor { .. }) {
            self.messages += 1;
        }
        match record {
            Record::Sensor {
                sensor,
                stamp_ns,
                measured,
                truth,
                ..
            } => self.write_sensor_sample(sensor, time, stamp_ns, measured, &truth),
            Record::Fault {
                sensor,
                kind,
                end_ns,
                magnitude,
                ..
            } => self.write_fault(time, sensor, kind, end_ns, magnitude),
            Record::AxleLoads { axles, .. } => {
                let axles = axles
                    .iter()
                    .map(|a| AxleLoad {
                        vehicle_id: a.vehicle_id,
                        axle_index: a.axle_index,
                        position_m: a.position_m,
                        force_n: a.force_n,
                        static_load_n: a.static_load_n,
                        in_contact: a.in_contact,
                        on_bridge: a.on_bridge,
                    })
                    .collect();
                let msg = AxleLoads {
                    timestamp: ts,
                    axles,
                };
                self.sink.write(self.axle_loads, time, &msg)
            }
            Record::BridgeShape {
                deflection_m,
                temperatures_c,
                modal,
                ..
            } => {
                let mid = self.span_m / 2.0;
                let midspan = interpolate(&self.node_position_m, &deflection_m, mid);
                let (temperature_c, air_temperature_c) = temperatures_c.unwrap_or_default();
                let mut msg = BridgeState {
                    timestamp: ts,
                    node_position_m: self.node_position_m.clone(),
                    deflection_m,
                    midspan_deflection_m: midspan,
                    temperature_c,
                    air_temperature_c,
                    ..Default::default()
                };
                if let Some(modal) = modal {
                    let modal = *modal;
                    msg.natural_frequency_hz = modal.natural_frequency_hz;
                    msg.damping_ratio = modal.damping_ratio;
                    msg.stiffness_ratio = modal.stiffness_ratio;
                    msg.damage_fraction = modal.damage_fraction;
                }
                self.sink.write(self.bridge, time, &msg)
            }
            Record::Vehicle { vehicle, .. } => {
                let msg = VehicleTruth {
                    timestamp: ts,
                    vehicle_id: vehicle.vehicle_id,
                    // "half_car/two_axle_truck", "rigid_truck/truck_3axle": the class is
                    // the preset (the last part), the kind the first.
                    vehicle_class: vehicle.model.rsplit('/').next().unwrap_or("").to_string(),
                    model: vehicle.model.clone(),
                    lane: vehicle.lane,
                    direction: match vehicle.direction < 0 {
                        true => TravelDirection::DecreasingX as i32,
                        false => TravelDirection::IncreasingX as i32,
                    },
                    speed_m_s: vehicle.speed_m_s,
                    entry_time: vehicle
                        .entry_time_ns
                        .map(|t| timestamp_from_ns(self.start_time_ns + t)),
                    exit_time: vehicle
                        .exit_time_ns
                        .map(|t| timestamp_from_ns(self.start_time_ns + t)),
                    axle_spacing_m: vehicle.axle_spacing_m.clone(),
                    static_axle_load_n: vehicle.static_axle_load_n.clone(),
                    gross_weight_n: vehicle.gross_weight_n,
                    parameters: vehicle.parameters.iter().cloned().collect(),
                };
                self.sink.write(self.vehicles, time, &msg)
            }
            Record::Wim { record, .. } => {
                let (station_id, ch) = self.wim[record.station].clone();
                let m = record.measurement;
                let msg = WimRecord {
                    timestamp: ts,
                    station_id,
                    vehicle_id: m.vehicle_id,
                    lane: m.lane,
                    speed_m_s: m.speed_m_s,
                    axle_count: m.axle_load_n.len() as u32,
                    axle_spacing_m: m.axle_spacing_m,
                    gross_weight_n: m.gross_weight_n,
                    axle_load_n: m.axle_load_n,
                    axle_pattern: m.axle_pattern,
                    flags: m.flags.iter().map(|f| f.to_string()).collect(),
                    groups: m
                        .groups
                        .iter()
                        .map(|g| WimAxleGroup {
                            first_axle: g.first_axle as u32,
                            axle_count: g.axle_count as u32,
                            load_n: g.load_n,
                        })
                        .collect(),
                    fhwa_class: m.fhwa_class.map_or(0, u32::from),
                    model: self.wim_models[record.station].clone(),
                    error_reference: match m.truth.reference {
                        LoadReference::Static => "static",
                        LoadReference::Dynamic => "dynamic",
                    }
                    .into(),
                    speed_error_rel: m.truth.speed_rel,
                    gross_weight_error_rel: m.truth.gross_rel,
                    axle_load_error_rel: m.truth.axle_rel,
                };
                self.sink.write(ch, time, &msg)
            }
            Record::Event { level, text, .. } => {
                let msg = Log {
                    timestamp: ts,
                    level: match level {
                        EventLevel::Info => Level::Info as i32,
                        EventLevel::Warning => Level::Warning as i32,
                    },
                    message: text,
                    name: "bridgetwin".into(),
                    file: String::new(),
                    line: 0,
                };
                self.sink.write(self.events, time, &msg)
            }
        }
    }

    fn flush_if_due(&mut self) -> Result<()> {
        if let Some(interval) = self.flush_every {
            // Checking the clock every 1024 messages keeps its cost out of the profile.
            if self.messages % 1024 < 2 && self.last_flush.elapsed() >= interval {
                self.sink.flush()?;
                self.last_flush = Instant::now();
            }
        }
        Ok(())
    }
}

impl<W: Write + Seek> Recorder for McapRecorder<'_, W> {
    fn record(&mut self, record: Record) -> Result<()> {
        let started = Instant::now();
        let outcome = if self.blocked {
            self.record_blocked(record)
        } else {
            self.write_record(record)
        };
        let outcome = outcome.and_then(|()| self.flush_if_due());
        self.write_time += started.elapsed();
        outcome
    }

    /// Writes the partly filled blocks and everything still queued.
    fn finish(&mut self) -> Result<()> {
        for (i, s) in self.sensors.iter_mut().enumerate() {
            for block in s.open_blocks() {
                self.closed.extend(block.take(i));
            }
        }
        for block in self.closed.drain(..) {
            self.reorder.push(block.start_ns, Pending::Block(block));
        }
        self.release()
    }
}

/// Registers the measured and truth channels of one sensor in the chosen layout.
fn sensor_channels<W: Write + Seek>(
    sink: &mut McapSink<W>,
    resolved: &Resolved,
    sensor: &crate::scenario::ResolvedSensor,
) -> Result<SensorChannels> {
    let (layout, block_samples) = (
        resolved.scenario.output.layout,
        resolved.scenario.output.block_samples,
    );
    let spec = &sensor.spec;
    let rate = format!("{}", spec.rate_hz);
    let position = format!("{}", spec.position_m);
    let density = match &sensor.chain {
        Some(chain) => format!("{}", chain.chain_parameters().noise_density),
        None => format!("{}", sensor.noise_density),
    };
    let layout_name = match layout {
        Layout::Sample => "sample".to_string(),
        Layout::Block => format!("block of {block_samples} samples"),
    };
    let mut meta = metadata([
        ("unit", spec.kind.unit()),
        ("sample_rate_hz", rate.as_str()),
        ("position_m", position.as_str()),
        ("sensor_model", sensor.model_name()),
        ("noise_density_per_sqrt_hz", density.as_str()),
        ("sign", "downward positive (strain: tension positive)"),
        ("layout", layout_name.as_str()),
    ]);
    if let Some(chain) = crate::sim::chain_stages(resolved, sensor)? {
        for (name, value) in chain.parameters {
            meta.insert(format!("chain.{name}"), format!("{value}"));
        }
    }
    if let Some(node) = sensor.node.map(|i| &resolved.scenario.daq_nodes[i]) {
        let true_rate = spec.rate_hz * (1.0 + 1e-6 * node.clock.drift_ppm);
        meta.insert("daq_node".into(), node.id.clone());
        meta.insert("nominal_sample_rate_hz".into(), rate.clone());
        meta.insert("true_sample_rate_hz".into(), format!("{true_rate}"));
        meta.insert(
            "clock_drift_ppm".into(),
            format!("{}", node.clock.drift_ppm),
        );
        meta.insert("clock_offset_s".into(), format!("{}", node.clock.offset_s));
        meta.insert(
            "timestamps".into(),
            "measured: node clock; truth: true time (node_timestamp holds the node's)".into(),
        );
    }
    if spec.kind == SensorKind::Strain {
        meta.insert("gauge_depth_m".into(), format!("{}", sensor.gauge_depth_m));
    }
    let topic = match spec.kind {
        SensorKind::Accelerometer => Topics::accel(&spec.id)?,
        SensorKind::Strain => Topics::strain(&spec.id)?,
        SensorKind::Displacement => Topics::disp(&spec.id)?,
    };
    let measured = match (layout, spec.kind) {
        (Layout::Block, _) => sink.add_channel::<SampleBlock>(&topic, meta.clone())?,
        (_, SensorKind::Accelerometer) => {
            sink.add_channel::<AccelerationSample>(&topic, meta.clone())?
        }
        (_, SensorKind::Strain) => sink.add_channel::<StrainSample>(&topic, meta.clone())?,
        (_, SensorKind::Displacement) => {
            sink.add_channel::<DisplacementSample>(&topic, meta.clone())?
        }
    };
    meta.insert(
        "sensor_model".into(),
        "truth (noise-free, unfiltered, true time)".into(),
    );
    let truth_topic = Topics::truth_sensor(&spec.id)?;
    let truth = match layout {
        Layout::Sample => sink.add_channel::<SensorTruth>(&truth_topic, meta)?,
        Layout::Block => sink.add_channel::<SensorTruthBlock>(&truth_topic, meta)?,
    };
    Ok(SensorChannels {
        kind: spec.kind,
        id: spec.id.clone(),
        measured,
        truth,
        block: (layout == Layout::Block)
            .then(|| OpenBlock::new(Stream::Truth, spec.rate_hz, block_samples)),
        measured_block: (layout == Layout::Block)
            .then(|| OpenBlock::new(Stream::Measured, spec.rate_hz, block_samples)),
    })
}

/// A station model as one short label.
fn wim_model_label(model: &WimModelSpec) -> String {
    match model {
        WimModelSpec::Ideal => "ideal (dynamic tyre force at the strip)".into(),
        WimModelSpec::Cost323 { class, .. } => format!("cost323 {class}"),
        WimModelSpec::Physics { noise_rel, .. } => {
            format!("physics (dynamic tyre force x (1 + N(0, {noise_rel})))")
        }
    }
}

fn interpolate(xs: &[f64], ys: &[f64], x: f64) -> f64 {
    let i = xs
        .partition_point(|&v| v <= x)
        .clamp(1, xs.len().saturating_sub(1).max(1));
    if xs.len() < 2 {
        return ys.first().copied().unwrap_or(0.0);
    }
    let (x0, x1) = (xs[i - 1], xs[i]);
    let w = if x1 > x0 { (x - x0) / (x1 - x0) } else { 0.0 };
    ys[i - 1] * (1.0 - w) + ys[i] * w
}
