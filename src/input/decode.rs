//! Messages of the output contract to table rows, one decoder per schema (the generated
//! protobuf types, so a field renamed in `schemas/` fails to compile here instead of
//! silently vanishing). Column names are those `tools/read_run.py` documents: every field
//! by its name (the unit is part of it), a Timestamp `x` as `x_ns`, a map as `name.key`,
//! repeated messages one row per element under `field.name`, and block messages one row
//! per sample, named like the per-sample messages.

use prost::Message;

use super::table::{Table, TableBuilder};
use crate::output::proto::foxglove::Log;
use crate::output::proto::v1::{
    AccelerationSample, AxleDetection, AxleDetectionTruth, AxleLoads, BridgeState,
    DisplacementSample, FaultInterval, GnssFix, ReactionSample, RotationSample, SampleBlock,
    SensorTruth, SensorTruthBlock, StrainSample, TemperatureSample, VehicleState, VehicleTruth,
    WimRecord,
};
use crate::record::SensorKind;

/// How the messages of a schema become rows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Decoder {
    Acceleration,
    Strain,
    Displacement,
    Rotation,
    Reaction,
    Temperature,
    SampleBlock,
    SensorTruth,
    SensorTruthBlock,
    Fault,
    AxleLoads,
    Vehicle,
    Bridge,
    Wim,
    Log,
    Gnss,
    AxleDetection,
    AxleDetectionTruth,
    VehicleState,
}

impl Decoder {
    /// The decoder of a schema (its fully qualified message name); `None`: not one of the
    /// output contract's.
    pub fn for_schema(name: &str) -> Option<Decoder> {
        Some(match name {
            "bridgetwin.v1.AccelerationSample" => Decoder::Acceleration,
            "bridgetwin.v1.StrainSample" => Decoder::Strain,
            "bridgetwin.v1.DisplacementSample" => Decoder::Displacement,
            "bridgetwin.v1.RotationSample" => Decoder::Rotation,
            "bridgetwin.v1.ReactionSample" => Decoder::Reaction,
            "bridgetwin.v1.TemperatureSample" => Decoder::Temperature,
            "bridgetwin.v1.SampleBlock" => Decoder::SampleBlock,
            "bridgetwin.v1.SensorTruth" => Decoder::SensorTruth,
            "bridgetwin.v1.SensorTruthBlock" => Decoder::SensorTruthBlock,
            "bridgetwin.v1.FaultInterval" => Decoder::Fault,
            "bridgetwin.v1.AxleLoads" => Decoder::AxleLoads,
            "bridgetwin.v1.VehicleTruth" => Decoder::Vehicle,
            "bridgetwin.v1.BridgeState" => Decoder::Bridge,
            "bridgetwin.v1.WimRecord" => Decoder::Wim,
            "foxglove.Log" => Decoder::Log,
            "bridgetwin.v1.GnssFix" => Decoder::Gnss,
            "bridgetwin.v1.AxleDetection" => Decoder::AxleDetection,
            "bridgetwin.v1.AxleDetectionTruth" => Decoder::AxleDetectionTruth,
            "bridgetwin.v1.VehicleState" => Decoder::VehicleState,
            _ => return None,
        })
    }

    /// Decodes one message logged at `log_time_ns` into rows of `table`. An error names
    /// what did not decode; the table is then unchanged.
    pub fn decode(
        self,
        data: &[u8],
        log_time_ns: u64,
        table: &mut TableBuilder,
    ) -> Result<(), String> {
        let log = i64::try_from(log_time_ns)
            .map_err(|_| format!("log time {log_time_ns} ns is past the year 2262"))?;
        match self {
            Decoder::Acceleration => {
                let m: AccelerationSample = parse(data)?;
                sample(
                    table,
                    log,
                    stamp(&m.timestamp)?,
                    SensorKind::Accelerometer,
                    m.acceleration_m_s2,
                )
            }
            Decoder::Strain => {
                let m: StrainSample = parse(data)?;
                sample(
                    table,
                    log,
                    stamp(&m.timestamp)?,
                    SensorKind::Strain,
                    m.strain_microstrain,
                )
            }
            Decoder::Displacement => {
                let m: DisplacementSample = parse(data)?;
                sample(
                    table,
                    log,
                    stamp(&m.timestamp)?,
                    SensorKind::Displacement,
                    m.displacement_m,
                )
            }
            Decoder::Rotation => {
                let m: RotationSample = parse(data)?;
                sample(
                    table,
                    log,
                    stamp(&m.timestamp)?,
                    SensorKind::Inclinometer,
                    m.rotation_rad,
                )
            }
            Decoder::Reaction => {
                let m: ReactionSample = parse(data)?;
                sample(
                    table,
                    log,
                    stamp(&m.timestamp)?,
                    SensorKind::LoadCell,
                    m.reaction_n,
                )
            }
            Decoder::Temperature => {
                let m: TemperatureSample = parse(data)?;
                sample(
                    table,
                    log,
                    stamp(&m.timestamp)?,
                    SensorKind::Thermometer,
                    m.temperature_c,
                )
            }
            Decoder::SampleBlock => sample_block(table, log, &parse(data)?),
            Decoder::SensorTruth => sensor_truth(table, log, &parse(data)?),
            Decoder::SensorTruthBlock => truth_block(table, log, &parse(data)?),
            Decoder::Fault => fault(table, log, &parse(data)?),
            Decoder::AxleLoads => axle_loads(table, log, &parse(data)?),
            Decoder::Vehicle => vehicle(table, log, &parse(data)?),
            Decoder::Bridge => bridge(table, log, &parse(data)?),
            Decoder::Wim => wim(table, log, &parse(data)?),
            Decoder::Log => event(table, log, &parse(data)?),
            Decoder::Gnss => gnss(table, log, &parse(data)?),
            Decoder::AxleDetection => axle_detection(table, log, &parse(data)?),
            Decoder::AxleDetectionTruth => axle_detection_truth(table, log, &parse(data)?),
            Decoder::VehicleState => vehicle_state(table, log, &parse(data)?),
        }
    }
}

impl Decoder {
    /// The columns this decoder gives, without rows: the frame of a topic that has no
    /// message in the files read (a part of a split run before the first vehicle) still
    /// has them. A block topic's value column is named from its channel's `unit`.
    pub fn empty_table(self, channel_unit: Option<&str>) -> Table {
        let mut builder = TableBuilder::default();
        let decoded = match self {
            Decoder::SampleBlock => {
                let quantity = SensorKind::ALL
                    .into_iter()
                    .find(|k| Some(k.unit()) == channel_unit)
                    .map_or("", SensorKind::quantity);
                let block = SampleBlock {
                    quantity: quantity.to_string(),
                    ..SampleBlock::default()
                };
                sample_block(&mut builder, 0, &block)
            }
            // The empty encoding is the default message.
            _ => self.decode(&[], 0, &mut builder),
        };
        debug_assert!(decoded.is_ok(), "{self:?}: the default message decodes");
        builder.build().empty_like()
    }
}

fn parse<M: Message + Default>(data: &[u8]) -> Result<M, String> {
    M::decode(data).map_err(|e| format!("message does not decode: {e}"))
}

fn fault(table: &mut TableBuilder, log: i64, m: &FaultInterval) -> Result<(), String> {
    let end = m.end_time.as_ref().map(ns).transpose()?;
    let stamp_ns = stamp(&m.timestamp)?;
    table.rows(1);
    table.i64("log_time_ns", log);
    table.i64("timestamp_ns", stamp_ns);
    table.str("sensor_id", &m.sensor_id);
    table.str("kind", &m.kind);
    table.i64_or_missing("end_time_ns", end);
    table.f64("magnitude", m.magnitude);
    Ok(())
}

fn event(table: &mut TableBuilder, log: i64, m: &Log) -> Result<(), String> {
    let stamp_ns = stamp(&m.timestamp)?;
    table.rows(1);
    table.i64("log_time_ns", log);
    table.i64("timestamp_ns", stamp_ns);
    table.i32("level", m.level);
    table.str("message", &m.message);
    table.str("name", &m.name);
    table.str("file", &m.file);
    table.u32("line", m.line);
    Ok(())
}

/// Name of the value column of a `SampleBlock` of `quantity`: that of the per-sample
/// message ([`SensorKind::value_field`]), so both layouts of a sensor load to the same
/// columns; `values` for a quantity this version does not know.
pub fn block_value_name(quantity: &str) -> &'static str {
    SensorKind::from_quantity(quantity).map_or("values", SensorKind::value_field)
}

/// A Timestamp as Unix-epoch ns; out-of-range values (negative nanos, past 2262) are
/// damage, not numbers.
fn ns(t: &prost_types::Timestamp) -> Result<i64, String> {
    let valid = (0..1_000_000_000).contains(&t.nanos);
    t.seconds
        .checked_mul(1_000_000_000)
        .and_then(|s| s.checked_add(i64::from(t.nanos)))
        .filter(|_| valid)
        .ok_or_else(|| format!("timestamp {}s {}ns is out of range", t.seconds, t.nanos))
}

/// The `timestamp` field (field 1 of every message); unset reads as the epoch, as the
/// protobuf default.
fn stamp(t: &Option<prost_types::Timestamp>) -> Result<i64, String> {
    t.as_ref().map_or(Ok(0), ns)
}

fn sample(
    table: &mut TableBuilder,
    log: i64,
    stamp_ns: i64,
    kind: SensorKind,
    value: f64,
) -> Result<(), String> {
    table.rows(1);
    table.i64("log_time_ns", log);
    table.i64("timestamp_ns", stamp_ns);
    table.f64(kind.value_field(), value);
    Ok(())
}

/// Times of the samples of a block: `start + i * period`, checked not to overflow.
fn sample_times(start_ns: i64, period_ns: u64, n: usize) -> Result<Vec<i64>, String> {
    let period = i64::try_from(period_ns)
        .map_err(|_| format!("sample_period_ns = {period_ns} is out of range"))?;
    let last = i64::try_from(n.saturating_sub(1))
        .ok()
        .and_then(|k| k.checked_mul(period))
        .and_then(|span| span.checked_add(start_ns));
    if last.is_none() {
        return Err(format!(
            "a block of {n} samples of {period_ns} ns from {start_ns} ns runs out of range"
        ));
    }
    Ok((0..n as i64).map(|i| start_ns + i * period).collect())
}

fn sample_block(table: &mut TableBuilder, log: i64, m: &SampleBlock) -> Result<(), String> {
    let n = m.values.len();
    let logs = sample_times(log, m.sample_period_ns, n)?;
    let stamps = sample_times(stamp(&m.timestamp)?, m.sample_period_ns, n)?;
    table.rows(n);
    table.i64s("log_time_ns", logs);
    table.i64s("timestamp_ns", stamps);
    table.f64s(block_value_name(&m.quantity), m.values.iter().copied());
    Ok(())
}

fn sensor_truth(table: &mut TableBuilder, log: i64, m: &SensorTruth) -> Result<(), String> {
    let stamp_ns = stamp(&m.timestamp)?;
    // Unset where it equals the true stamp (the writer saves 8 % that way): filled back in.
    let node = m.node_timestamp.as_ref().map(ns).transpose()?;
    table.rows(1);
    table.i64("log_time_ns", log);
    table.i64("timestamp_ns", stamp_ns);
    table.str("sensor_id", &m.sensor_id);
    table.f64("displacement_m", m.displacement_m);
    table.f64("velocity_m_s", m.velocity_m_s);
    table.f64("acceleration_m_s2", m.acceleration_m_s2);
    table.f64("strain_microstrain", m.strain_microstrain);
    table.f64("moment_n_m", m.moment_n_m);
    table.f64("rotation_rad", m.rotation_rad);
    table.f64("reaction_n", m.reaction_n);
    table.f64("temperature_c", m.temperature_c);
    table.i64("node_timestamp_ns", node.unwrap_or(stamp_ns));
    table.bool("measured_lost", m.measured_lost);
    Ok(())
}

fn truth_block(table: &mut TableBuilder, log: i64, m: &SensorTruthBlock) -> Result<(), String> {
    let n = m.displacement_m.len();
    let columns = [
        ("displacement_m", &m.displacement_m),
        ("velocity_m_s", &m.velocity_m_s),
        ("acceleration_m_s2", &m.acceleration_m_s2),
        ("strain_microstrain", &m.strain_microstrain),
        ("moment_n_m", &m.moment_n_m),
    ];
    if let Some((name, c)) = columns.iter().find(|(_, c)| c.len() != n) {
        return Err(format!(
            "truth block: {name} has {} samples, displacement_m {n}",
            c.len()
        ));
    }
    let logs = sample_times(log, m.sample_period_ns, n)?;
    let stamps = sample_times(stamp(&m.timestamp)?, m.sample_period_ns, n)?;
    table.rows(n);
    table.i64s("log_time_ns", logs);
    table.i64s("timestamp_ns", stamps);
    table.str_repeated("sensor_id", &m.sensor_id, n);
    for (name, c) in columns {
        table.f64s(name, c.iter().copied());
    }
    // Only the kind that measures them fills these (an inclinometer, a load cell, a
    // thermometer); the others leave them empty, meaning zero, as the per-sample layout
    // does.
    for (name, c) in [
        ("rotation_rad", &m.rotation_rad),
        ("reaction_n", &m.reaction_n),
        ("temperature_c", &m.temperature_c),
    ] {
        match c.len() {
            0 => table.f64s(name, std::iter::repeat_n(0.0, n)),
            len if len == n => table.f64s(name, c.iter().copied()),
            len => {
                return Err(format!(
                    "truth block: {name} has {len} samples, displacement_m {n}"
                ))
            }
        }
    }
    Ok(())
}

fn axle_loads(table: &mut TableBuilder, log: i64, m: &AxleLoads) -> Result<(), String> {
    let n = m.axles.len();
    let stamp_ns = stamp(&m.timestamp)?;
    table.rows(n);
    table.i64s("log_time_ns", std::iter::repeat_n(log, n));
    table.i64s("timestamp_ns", std::iter::repeat_n(stamp_ns, n));
    table.u32s("axles.vehicle_id", m.axles.iter().map(|a| a.vehicle_id));
    table.u32s("axles.axle_index", m.axles.iter().map(|a| a.axle_index));
    table.f64s("axles.position_m", m.axles.iter().map(|a| a.position_m));
    table.f64s("axles.force_n", m.axles.iter().map(|a| a.force_n));
    table.f64s(
        "axles.static_load_n",
        m.axles.iter().map(|a| a.static_load_n),
    );
    table.bools("axles.in_contact", m.axles.iter().map(|a| a.in_contact));
    table.bools("axles.on_bridge", m.axles.iter().map(|a| a.on_bridge));
    Ok(())
}

fn gnss(table: &mut TableBuilder, log: i64, m: &GnssFix) -> Result<(), String> {
    let stamp_ns = stamp(&m.timestamp)?;
    table.rows(1);
    table.i64("log_time_ns", log);
    table.i64("timestamp_ns", stamp_ns);
    table.u32("vehicle_id", m.vehicle_id);
    table.f64("position_m", m.position_m);
    table.f64("speed_m_s", m.speed_m_s);
    table.f64("position_sigma_m", m.position_sigma_m);
    Ok(())
}

fn axle_detection(table: &mut TableBuilder, log: i64, m: &AxleDetection) -> Result<(), String> {
    let stamp_ns = stamp(&m.timestamp)?;
    table.rows(1);
    table.i64("log_time_ns", log);
    table.i64("timestamp_ns", stamp_ns);
    table.str("detector_id", &m.detector_id);
    table.i64_or_missing(
        "detected_time_ns",
        m.detected_time.as_ref().map(ns).transpose()?,
    );
    Ok(())
}

fn axle_detection_truth(
    table: &mut TableBuilder,
    log: i64,
    m: &AxleDetectionTruth,
) -> Result<(), String> {
    let stamp_ns = stamp(&m.timestamp)?;
    let detected = m.detected_time.as_ref().map(ns).transpose()?;
    table.rows(1);
    table.i64("log_time_ns", log);
    table.i64("timestamp_ns", stamp_ns);
    table.str("detector_id", &m.detector_id);
    table.u32("vehicle_id", m.vehicle_id);
    table.u32("axle_index", m.axle_index);
    table.u32("lane", m.lane);
    table.f64("speed_m_s", m.speed_m_s);
    table.bool("detected", m.detected);
    table.i64_or_missing("detected_time_ns", detected);
    table.i64_or_missing(
        "crossing_time_ns",
        m.crossing_time.as_ref().map(ns).transpose()?,
    );
    Ok(())
}

/// One row per instant: the DOF arrays and each contact field as lists (axle order; the
/// flag `on_bridge` as 0 / 1).
fn vehicle_state(table: &mut TableBuilder, log: i64, m: &VehicleState) -> Result<(), String> {
    let stamp_ns = stamp(&m.timestamp)?;
    table.rows(1);
    table.i64("log_time_ns", log);
    table.i64("timestamp_ns", stamp_ns);
    table.u32("vehicle_id", m.vehicle_id);
    table.f64("position_m", m.position_m);
    table.f64("speed_m_s", m.speed_m_s);
    table.f64_list("dof_displacement", &m.dof_displacement);
    table.f64_list("dof_velocity", &m.dof_velocity);
    table.f64_list("dof_acceleration", &m.dof_acceleration);
    let c = &m.contacts;
    let list = |f: fn(&crate::output::proto::v1::ContactPoint) -> f64| -> Vec<f64> {
        c.iter().map(f).collect()
    };
    table.f64_list("contacts.position_m", &list(|c| c.position_m));
    table.f64_list("contacts.road_elevation_m", &list(|c| c.road_elevation_m));
    table.f64_list(
        "contacts.bridge_deflection_m",
        &list(|c| c.bridge_deflection_m),
    );
    table.f64_list(
        "contacts.contact_elevation_m",
        &list(|c| c.contact_elevation_m),
    );
    table.f64_list(
        "contacts.bridge_acceleration_m_s2",
        &list(|c| c.bridge_acceleration_m_s2),
    );
    table.f64_list("contacts.force_n", &list(|c| c.force_n));
    let axle: Vec<u32> = c.iter().map(|c| c.axle_index).collect();
    table.u32_list("contacts.axle_index", &axle);
    // Lists of flags are lists of 0 / 1 (the table has no list of booleans).
    let on_bridge: Vec<u32> = c.iter().map(|c| u32::from(c.on_bridge)).collect();
    table.u32_list("contacts.on_bridge", &on_bridge);
    Ok(())
}

fn vehicle(table: &mut TableBuilder, log: i64, m: &VehicleTruth) -> Result<(), String> {
    let entry = m.entry_time.as_ref().map(ns).transpose()?;
    let exit = m.exit_time.as_ref().map(ns).transpose()?;
    let stamp_ns = stamp(&m.timestamp)?;
    table.rows(1);
    table.i64("log_time_ns", log);
    table.i64("timestamp_ns", stamp_ns);
    table.u32("vehicle_id", m.vehicle_id);
    table.str("vehicle_class", &m.vehicle_class);
    table.str("model", &m.model);
    table.u32("lane", m.lane);
    table.i32("direction", m.direction);
    table.f64("speed_m_s", m.speed_m_s);
    table.i64_or_missing("entry_time_ns", entry);
    table.i64_or_missing("exit_time_ns", exit);
    table.f64_list("axle_spacing_m", &m.axle_spacing_m);
    table.f64_list("static_axle_load_n", &m.static_axle_load_n);
    table.f64("gross_weight_n", m.gross_weight_n);
    // A map's keys in sorted order, so that the columns come out in the same order
    // whichever vehicle shows a key first.
    let mut parameters: Vec<_> = m.parameters.iter().collect();
    parameters.sort_by(|a, b| a.0.cmp(b.0));
    for (key, value) in parameters {
        table.f64(&format!("parameters.{key}"), *value);
    }
    Ok(())
}

fn bridge(table: &mut TableBuilder, log: i64, m: &BridgeState) -> Result<(), String> {
    let stamp_ns = stamp(&m.timestamp)?;
    table.rows(1);
    table.i64("log_time_ns", log);
    table.i64("timestamp_ns", stamp_ns);
    table.f64_list("node_position_m", &m.node_position_m);
    table.f64_list("deflection_m", &m.deflection_m);
    table.f64_list("natural_frequency_hz", &m.natural_frequency_hz);
    table.f64_list("damping_ratio", &m.damping_ratio);
    table.f64_list("modal_amplitude_m", &m.modal_amplitude_m);
    table.f64("temperature_c", m.temperature_c);
    table.f64("midspan_deflection_m", m.midspan_deflection_m);
    table.f64_list("stiffness_ratio", &m.stiffness_ratio);
    table.f64("air_temperature_c", m.air_temperature_c);
    table.f64_list("damage_fraction", &m.damage_fraction);
    table.f64_list("support_reaction_n", &m.support_reaction_n);
    table.f64_list("support_stiffness_ratio", &m.support_stiffness_ratio);
    table.f64_list("support_settlement_m", &m.support_settlement_m);
    // Mode shapes come in the first message only: one list per field, empty afterwards.
    let modes: Vec<u32> = m.mode_shapes.iter().map(|s| s.mode_number).collect();
    table.u32_list("mode_shapes.mode_number", &modes);
    let f: Vec<f64> = m
        .mode_shapes
        .iter()
        .map(|s| s.natural_frequency_hz)
        .collect();
    table.f64_list("mode_shapes.natural_frequency_hz", &f);
    let amplitude: Vec<f64> = m
        .mode_shapes
        .iter()
        .flat_map(|s| s.amplitude.iter().copied())
        .collect();
    table.f64_list("mode_shapes.amplitude", &amplitude);
    Ok(())
}

fn wim(table: &mut TableBuilder, log: i64, m: &WimRecord) -> Result<(), String> {
    let stamp_ns = stamp(&m.timestamp)?;
    table.rows(1);
    table.i64("log_time_ns", log);
    table.i64("timestamp_ns", stamp_ns);
    table.str("station_id", &m.station_id);
    table.u32("vehicle_id", m.vehicle_id);
    table.u32("lane", m.lane);
    table.f64("speed_m_s", m.speed_m_s);
    table.u32("axle_count", m.axle_count);
    table.f64_list("axle_spacing_m", &m.axle_spacing_m);
    table.f64_list("axle_load_n", &m.axle_load_n);
    table.f64("gross_weight_n", m.gross_weight_n);
    table.str("axle_pattern", &m.axle_pattern);
    table.str_list("flags", &m.flags);
    let first: Vec<u32> = m.groups.iter().map(|g| g.first_axle).collect();
    table.u32_list("groups.first_axle", &first);
    let count: Vec<u32> = m.groups.iter().map(|g| g.axle_count).collect();
    table.u32_list("groups.axle_count", &count);
    let load: Vec<f64> = m.groups.iter().map(|g| g.load_n).collect();
    table.f64_list("groups.load_n", &load);
    table.u32("fhwa_class", m.fhwa_class);
    table.str("model", &m.model);
    table.str("error_reference", &m.error_reference);
    table.f64("speed_error_rel", m.speed_error_rel);
    table.f64("gross_weight_error_rel", m.gross_weight_error_rel);
    table.f64_list("axle_load_error_rel", &m.axle_load_error_rel);
    Ok(())
}
