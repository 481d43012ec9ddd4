//! The MCAP output: a [`Recorder`] that registers its channels from the run manifest and
//! turns every record into messages on the topics of the output contract.
//!
//! Chunks close at the `mcap` crate's chunk size and, with
//! [`McapRecorder::flush_every_ns`], every so much simulated time (the records' own
//! times), so that a run killed midway leaves a file readable up to a recent flush. No
//! decision follows the wall clock: the bytes never depend on the machine's speed.

use std::io::{Seek, Write};
use std::time::{Duration, Instant};

use super::blocks::{ClosedBlock, Pending, Reorder, Stream};
use super::channels::{register, Channels};
use super::messages;
use super::proto::v1::{
    AccelerationSample, BridgeState, DisplacementSample, ReactionSample, RotationSample,
    SampleBlock, SensorTruth, SensorTruthBlock, StrainSample, TemperatureSample,
};
use super::scene::{interpolate, SceneGeometry};
use super::{timestamp_from_ns, ChannelId, McapSink};
use crate::error::{Error, Result};
use crate::record::{AxleState, Layout, Quantities, Record, Recorder, RunManifest, SensorKind};

/// What the recorder knows once the manifest has arrived.
struct Run {
    channels: Channels,
    start_time_ns: u64,
    shape_position_m: Vec<f64>,
    /// Where `midspan_deflection_m` is read: the middle of the longest span (m).
    midspan_m: f64,
    /// Block layout: sensor samples go into blocks, every record through `reorder`.
    blocked: bool,
    /// The 3D scene, if the run writes it.
    scene: Option<SceneState>,
    /// Each GNSS receiver's configured position sigma (m), manifest order.
    gnss_sigma_m: Vec<f64>,
}

/// The scene's inputs between updates.
struct SceneState {
    geometry: SceneGeometry,
    /// The axles of the latest `AxleLoads` record (written before the shape of the same
    /// instant, so an update sees the axles of its own instant when the rates allow).
    axles: Vec<AxleState>,
    /// Deflected shapes seen so far.
    shapes: u64,
}

/// A [`Recorder`] writing to an MCAP sink.
pub struct McapRecorder<'a, W: Write + Seek> {
    sink: &'a mut McapSink<W>,
    run: Option<Run>,
    /// Block layout: records waiting until no open block starts before them.
    reorder: Reorder,
    closed: Vec<ClosedBlock>,
    /// Simulated time between chunk flushes (ns); `None` flushes only at the end.
    flush_every_ns: Option<u64>,
    /// Run-relative time of the next flush (ns).
    next_flush_ns: u64,
    /// Messages written.
    pub messages: u64,
    /// Wall time spent encoding and writing (the rest of a run is physics and sensors).
    pub write_time: Duration,
}

impl<'a, W: Write + Seek> McapRecorder<'a, W> {
    /// A recorder writing into `sink`; its channels are registered when the run's
    /// manifest arrives ([`Recorder::begin`]). Chunks close at the sink's chunk size only
    /// (see [`McapRecorder::flush_every_ns`]).
    pub fn new(sink: &'a mut McapSink<W>) -> Self {
        McapRecorder {
            sink,
            run: None,
            reorder: Reorder::default(),
            closed: Vec::new(),
            flush_every_ns: None,
            next_flush_ns: u64::MAX,
            messages: 0,
            write_time: Duration::ZERO,
        }
    }

    /// Closes the current chunk every `interval_ns` of simulated time (`None`: only at
    /// the end), so that a run killed midway leaves a file readable up to the last flush.
    pub fn flush_every_ns(mut self, interval_ns: Option<u64>) -> Self {
        self.flush_every_ns = interval_ns.filter(|&i| i > 0);
        self.next_flush_ns = self.flush_every_ns.unwrap_or(u64::MAX);
        self
    }

    /// The sink written to (the estimate's probe reads its per-channel totals).
    pub(super) fn sink(&self) -> &McapSink<W> {
        self.sink
    }

    fn run(&self) -> Result<&Run> {
        self.run.as_ref().ok_or_else(not_begun)
    }

    /// Writes the modal state at the start on `/truth/bridge`, with the (structure, air)
    /// temperatures when the run has an environment (so that no message of a run with
    /// temperatures reads 0 degC).
    fn write_modal_state(&mut self, manifest: &RunManifest) -> Result<()> {
        let b = &manifest.bridge;
        let (temperature_c, air_temperature_c) = b.temperatures_c.unwrap_or_default();
        let time = manifest.run.start_time_ns;
        let msg = BridgeState {
            timestamp: Some(timestamp_from_ns(time)),
            node_position_m: b.shape_position_m.clone(),
            deflection_m: vec![0.0; b.shape_position_m.len()],
            natural_frequency_hz: b.natural_frequencies_hz.clone(),
            damping_ratio: b.damping_ratios.clone(),
            temperature_c,
            air_temperature_c,
            ..Default::default()
        };
        self.messages += 1;
        let channel = self.run()?.channels.bridge;
        self.sink.write(channel, time, &msg)
    }

    /// Block layout: queues `record` (sensor samples go into their blocks) and writes
    /// whatever no open block precedes any more.
    fn record_blocked(&mut self, record: Record) -> Result<()> {
        let run = self.run.as_mut().ok_or_else(not_begun)?;
        match record {
            Record::Sensor {
                sensor,
                t_ns,
                stamp_ns,
                measured,
                truth,
            } => {
                let channels = &mut run.channels.sensors[sensor];
                if let Some(block) = channels.block.as_mut() {
                    let columns = truth.to_columns();
                    block.push(sensor, (t_ns, t_ns as i64), &columns, &mut self.closed);
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
        let run = self.run.as_mut().ok_or_else(not_begun)?;
        let watermark = run
            .channels
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
        let run = self.run.as_ref().ok_or_else(not_begun)?;
        let time = run.start_time_ns + block.start_ns;
        let ch = &run.channels.sensors[block.sensor];
        let period = ch.block.as_ref().map_or(0, |b| b.period_ns_rounded());
        self.messages += 1;
        match block.stream {
            Stream::Measured => {
                let stamp = run
                    .start_time_ns
                    .saturating_add_signed(block.start_stamp_ns);
                let measured = SampleBlock {
                    timestamp: Some(timestamp_from_ns(stamp)),
                    sample_period_ns: period,
                    quantity: ch.kind.quantity().into(),
                    unit: ch.kind.unit().into(),
                    values: block.columns.into_iter().next().unwrap_or_default(),
                };
                self.sink.write(ch.measured, time, &measured)
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
                    // The kinds that measure them carry these columns; the others leave
                    // them empty (their values are zero) rather than grow every block.
                    rotation_rad: only_for(ch.kind, SensorKind::Inclinometer, next()),
                    reaction_n: only_for(ch.kind, SensorKind::LoadCell, next()),
                    temperature_c: only_for(ch.kind, SensorKind::Thermometer, next()),
                };
                self.sink.write(ch.truth, time, &truth)
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
        let run = self.run.as_ref().ok_or_else(not_begun)?;
        let ch = &run.channels.sensors[sensor];
        let true_stamp = Some(timestamp_from_ns(time));
        let node_stamp = Some(timestamp_from_ns(
            run.start_time_ns.saturating_add_signed(stamp_ns),
        ));
        if let Some(value) = measured {
            self.messages += 1;
            let stamp = run.start_time_ns.saturating_add_signed(stamp_ns);
            write_sample(self.sink, ch.measured, ch.kind, time, stamp, value)?;
        }
        self.messages += 1;
        let msg = SensorTruth {
            timestamp: true_stamp,
            sensor_id: ch.id.clone(),
            displacement_m: truth.displacement_m,
            velocity_m_s: truth.velocity_m_s,
            acceleration_m_s2: truth.acceleration_m_s2,
            strain_microstrain: truth.strain_microstrain,
            moment_n_m: truth.moment_n_m,
            rotation_rad: truth.rotation_rad,
            reaction_n: truth.reaction_n,
            temperature_c: truth.temperature_c,
            // Only where a node clock makes it differ: it would add 8 % to the file else.
            node_timestamp: (stamp_ns != time.wrapping_sub(run.start_time_ns) as i64)
                .then_some(node_stamp)
                .flatten(),
            measured_lost: measured.is_none(),
        };
        self.sink.write(ch.truth, time, &msg)
    }

    /// One preview sample: the measured value (stamped by the node's clock; none when the
    /// centre sample was lost) and the truth (true time), each in the sensor's per-sample
    /// message type. Counted here: `write_record` counts no sensor-like record.
    fn write_preview(
        &mut self,
        sensor: usize,
        time: u64,
        stamp_ns: i64,
        measured: Option<f64>,
        truth: f64,
    ) -> Result<()> {
        let run = self.run.as_ref().ok_or_else(not_begun)?;
        let ch = &run.channels.sensors[sensor];
        let Some((measured_channel, truth_channel)) = ch.preview else {
            return Ok(());
        };
        let kind = ch.kind;
        let node_stamp = run.start_time_ns.saturating_add_signed(stamp_ns);
        if let Some(value) = measured {
            self.messages += 1;
            write_sample(self.sink, measured_channel, kind, time, node_stamp, value)?;
        }
        self.messages += 1;
        write_sample(self.sink, truth_channel, kind, time, time, truth)
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
        let run = self.run.as_ref().ok_or_else(not_begun)?;
        let Some(channel) = run.channels.faults else {
            return Ok(());
        };
        let end = end_ns.map(|e| run.start_time_ns + e);
        let id = &run.channels.sensors[sensor].id;
        let (interval, line) = messages::fault(time, id, kind, end, magnitude);
        let events = run.channels.events;
        self.sink.write(channel, time, &interval)?;
        if kind == "loss_random" {
            return Ok(());
        }
        self.messages += 1;
        self.sink.write(events, time, &line)
    }

    /// Writes one record as one message (sensor samples: two, measured and truth).
    fn write_record(&mut self, record: Record) -> Result<()> {
        let run = self.run.as_ref().ok_or_else(not_begun)?;
        let start_time_ns = run.start_time_ns;
        let time = start_time_ns + record.t_ns();
        let ts = Some(timestamp_from_ns(time));
        if !matches!(record, Record::Sensor { .. } | Record::Preview { .. }) {
            self.messages += 1;
        }
        let ch = &run.channels;
        match record {
            Record::Sensor {
                sensor,
                stamp_ns,
                measured,
                truth,
                ..
            } => self.write_sensor_sample(sensor, time, stamp_ns, measured, &truth),
            Record::Preview {
                sensor,
                stamp_ns,
                measured,
                truth,
                ..
            } => self.write_preview(sensor, time, stamp_ns, measured, truth),
            Record::Fault {
                sensor,
                kind,
                end_ns,
                magnitude,
                ..
            } => self.write_fault(time, sensor, kind, end_ns, magnitude),
            Record::AxleLoads { axles, .. } => {
                let channel = ch.axle_loads;
                self.sink
                    .write(channel, time, &messages::axle_loads(ts, &axles))?;
                if let Some(scene) = self.run.as_mut().and_then(|r| r.scene.as_mut()) {
                    scene.axles = axles;
                }
                Ok(())
            }
            Record::BridgeShape {
                deflection_m,
                temperatures_c,
                modal,
                support_reaction_n,
                ..
            } => {
                let midspan = interpolate(&run.shape_position_m, &deflection_m, run.midspan_m);
                let (temperature_c, air_temperature_c) = temperatures_c.unwrap_or_default();
                let scene = run.scene.as_ref().and_then(|scene| {
                    let due = scene
                        .shapes
                        .is_multiple_of(scene.geometry.info.every_shapes);
                    due.then(|| scene.geometry.update(time, &deflection_m, &scene.axles))
                });
                let mut msg = BridgeState {
                    timestamp: ts,
                    node_position_m: run.shape_position_m.clone(),
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
                    msg.support_stiffness_ratio = modal.support_stiffness_ratio;
                    msg.support_settlement_m = modal.support_settlement_m;
                }
                msg.support_reaction_n = support_reaction_n;
                let channel = ch.bridge;
                let scene_channel = ch.scene;
                self.sink.write(channel, time, &msg)?;
                if let Some(scene) = self.run.as_mut().and_then(|r| r.scene.as_mut()) {
                    scene.shapes += 1;
                }
                match (scene, scene_channel) {
                    (Some(update), Some(channel)) => {
                        self.messages += 1;
                        self.sink.write(channel, time, &update)
                    }
                    _ => Ok(()),
                }
            }
            Record::Vehicle { vehicle, .. } => {
                let channel = ch.vehicles;
                let msg = messages::vehicle(ts, start_time_ns, vehicle);
                self.sink.write(channel, time, &msg)
            }
            Record::Wim { record, .. } => {
                let (station_id, channel, model) = ch.wim[record.station].clone();
                let msg = messages::wim(ts, station_id, model, record.measurement);
                self.sink.write(channel, time, &msg)
            }
            Record::Event { level, text, .. } => {
                let channel = ch.events;
                self.sink
                    .write(channel, time, &messages::log(ts, level, text))
            }
            Record::Gnss { receiver, fix, .. } => {
                let channel = ch.gnss[receiver];
                let sigma_m = run.gnss_sigma_m[receiver];
                self.sink
                    .write(channel, time, &messages::gnss(ts, &fix, sigma_m))
            }
            Record::AxleHit { detector, hit, .. } => {
                let (id, channel) = &ch.axle_detectors[detector];
                let (measured, truth) = messages::axle_hit(ts, start_time_ns, id, &hit);
                let (channel, truth_channel) = (*channel, ch.axle_detections);
                if let Some(truth_channel) = truth_channel {
                    // Both are written at the solver instant after the crossing; the
                    // crossing's true and detected times are fields.
                    self.sink.write(truth_channel, time, &truth)?;
                }
                match measured {
                    Some(m) => {
                        self.messages += 1;
                        self.sink.write(channel, time, &m)
                    }
                    None => Ok(()),
                }
            }
            Record::VehicleState { state, .. } => {
                let Some(&(_, channel)) = ch
                    .vehicle_states
                    .iter()
                    .find(|(id, _)| *id == state.vehicle_id)
                else {
                    return Ok(());
                };
                self.sink
                    .write(channel, time, &messages::vehicle_state(ts, *state))
            }
        }
    }

    /// Closes the chunk once the records have passed the next flush time.
    fn flush_if_due(&mut self, t_ns: u64) -> Result<()> {
        if t_ns < self.next_flush_ns {
            return Ok(());
        }
        self.sink.flush()?;
        if let Some(interval) = self.flush_every_ns {
            // The next multiple of the interval after `t_ns`: a quiet stretch does not
            // cause a burst of empty flushes.
            self.next_flush_ns = (t_ns / interval + 1).saturating_mul(interval);
        }
        Ok(())
    }
}

/// Writes one value in the per-sample message type of a sensor of `kind`, at log time
/// `time`, stamped `stamp` (both Unix-epoch ns).
fn write_sample<W: Write + Seek>(
    sink: &mut McapSink<W>,
    channel: ChannelId,
    kind: SensorKind,
    time: u64,
    stamp: u64,
    value: f64,
) -> Result<()> {
    let timestamp = Some(timestamp_from_ns(stamp));
    match kind {
        SensorKind::Accelerometer => sink.write(
            channel,
            time,
            &AccelerationSample {
                timestamp,
                acceleration_m_s2: value,
            },
        ),
        SensorKind::Strain => sink.write(
            channel,
            time,
            &StrainSample {
                timestamp,
                strain_microstrain: value,
            },
        ),
        SensorKind::Displacement => sink.write(
            channel,
            time,
            &DisplacementSample {
                timestamp,
                displacement_m: value,
            },
        ),
        SensorKind::Inclinometer => sink.write(
            channel,
            time,
            &RotationSample {
                timestamp,
                rotation_rad: value,
            },
        ),
        SensorKind::LoadCell => sink.write(
            channel,
            time,
            &ReactionSample {
                timestamp,
                reaction_n: value,
            },
        ),
        SensorKind::Thermometer => sink.write(
            channel,
            time,
            &TemperatureSample {
                timestamp,
                temperature_c: value,
            },
        ),
    }
}

/// A truth block's column for sensors of kind `owner` only (empty for the others).
fn only_for(kind: SensorKind, owner: SensorKind, column: Vec<f64>) -> Vec<f64> {
    match kind == owner {
        true => column,
        false => Vec::new(),
    }
}

fn not_begun() -> Error {
    Error::Output {
        path: "MCAP recorder".into(),
        reason: "a record arrived before the run manifest (Recorder::begin)".into(),
    }
}

impl<W: Write + Seek> Recorder for McapRecorder<'_, W> {
    /// Writes the run's metadata and attachments, registers every channel and writes the
    /// modal state at the start.
    fn begin(&mut self, manifest: &RunManifest) -> Result<()> {
        let channels = register(self.sink, manifest)?;
        self.run = Some(Run {
            channels,
            start_time_ns: manifest.run.start_time_ns,
            shape_position_m: manifest.bridge.shape_position_m.clone(),
            midspan_m: manifest.bridge.midspan_m(),
            blocked: manifest.layout == Layout::Block,
            scene: SceneGeometry::new(manifest).map(|geometry| SceneState {
                geometry,
                axles: Vec::new(),
                shapes: 0,
            }),
            gnss_sigma_m: manifest.gnss.iter().map(|g| g.position_noise_m).collect(),
        });
        self.write_modal_state(manifest)
    }

    fn record(&mut self, record: Record) -> Result<()> {
        let started = Instant::now();
        let t_ns = record.t_ns();
        let outcome = match self.run()?.blocked {
            true => self.record_blocked(record),
            false => self.write_record(record),
        };
        let outcome = outcome.and_then(|()| self.flush_if_due(t_ns));
        self.write_time += started.elapsed();
        outcome
    }

    /// Writes the partly filled blocks and everything still queued.
    fn finish(&mut self) -> Result<()> {
        let run = self.run.as_mut().ok_or_else(not_begun)?;
        for (i, s) in run.channels.sensors.iter_mut().enumerate() {
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
