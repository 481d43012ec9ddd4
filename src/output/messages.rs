//! Records to protobuf messages: one function per message type, plain conversions
//! (Unix-epoch stamps from run-relative times, enums to their wire values).

use prost_types::Timestamp;

use super::proto::foxglove::{log::Level, Log};
use super::proto::v1::{
    AxleDetection, AxleDetectionTruth, AxleGroup as WimAxleGroup, AxleLoad, AxleLoads,
    ContactPoint as ContactMessage, FaultInterval, GnssFix as GnssMessage, TravelDirection,
    VehicleState, VehicleTruth, WimRecord,
};
use super::timestamp_from_ns;
use crate::record::{
    AxleHit, AxleState, EventLevel, GnssFix, LoadReference, VehicleRecord, VehicleStateRecord,
    WimMeasurement,
};

/// A `foxglove.Log` entry from bridgetwin.
pub(super) fn log(timestamp: Option<Timestamp>, level: EventLevel, message: String) -> Log {
    Log {
        timestamp,
        level: match level {
            EventLevel::Info => Level::Info as i32,
            EventLevel::Warning => Level::Warning as i32,
        },
        message,
        name: "bridgetwin".into(),
        file: String::new(),
        line: 0,
    }
}

/// Every axle at one instant.
pub(super) fn axle_loads(timestamp: Option<Timestamp>, axles: &[AxleState]) -> AxleLoads {
    AxleLoads {
        timestamp,
        axles: axles
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
            .collect(),
    }
}

/// One vehicle's truth; `start_time_ns` turns its run-relative times into stamps.
pub(super) fn vehicle(
    timestamp: Option<Timestamp>,
    start_time_ns: u64,
    vehicle: VehicleRecord,
) -> VehicleTruth {
    let stamp = |t: Option<u64>| t.map(|t| timestamp_from_ns(start_time_ns + t));
    VehicleTruth {
        timestamp,
        vehicle_id: vehicle.vehicle_id,
        // "half_car/two_axle_truck", "rigid_truck/truck_3axle": the class is the preset
        // (the last part), the kind the first.
        vehicle_class: vehicle.model.rsplit('/').next().unwrap_or("").to_string(),
        lane: vehicle.lane,
        direction: match vehicle.direction < 0 {
            true => TravelDirection::DecreasingX as i32,
            false => TravelDirection::IncreasingX as i32,
        },
        speed_m_s: vehicle.speed_m_s,
        entry_time: stamp(vehicle.entry_time_ns),
        exit_time: stamp(vehicle.exit_time_ns),
        gross_weight_n: vehicle.gross_weight_n,
        parameters: vehicle.parameters.into_iter().collect(),
        model: vehicle.model,
        axle_spacing_m: vehicle.axle_spacing_m,
        static_axle_load_n: vehicle.static_axle_load_n,
    }
}

/// One station's record of one vehicle.
pub(super) fn wim(
    timestamp: Option<Timestamp>,
    station_id: String,
    model: String,
    m: WimMeasurement,
) -> WimRecord {
    WimRecord {
        timestamp,
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
        model,
        error_reference: match m.truth.reference {
            LoadReference::Static => "static",
            LoadReference::Dynamic => "dynamic",
        }
        .into(),
        speed_error_rel: m.truth.speed_rel,
        gross_weight_error_rel: m.truth.gross_rel,
        axle_load_error_rel: m.truth.axle_rel,
    }
}

/// A fault interval of sensor `sensor_id` from `time` (Unix-epoch ns) to `end` (or the
/// end of the run), and its `/events` line.
pub(super) fn fault(
    time: u64,
    sensor_id: &str,
    kind: &str,
    end: Option<u64>,
    magnitude: f64,
) -> (FaultInterval, Log) {
    let interval = FaultInterval {
        timestamp: Some(timestamp_from_ns(time)),
        sensor_id: sensor_id.to_string(),
        kind: kind.into(),
        end_time: end.map(timestamp_from_ns),
        magnitude,
    };
    let text = match end {
        Some(end) => format!(
            "fault {kind} on sensor {sensor_id}: {:.3} s, magnitude {magnitude}",
            end.saturating_sub(time) as f64 * 1e-9
        ),
        None => {
            format!(
                "fault {kind} on sensor {sensor_id}: to the end of the run, magnitude {magnitude}"
            )
        }
    };
    let line = log(Some(timestamp_from_ns(time)), EventLevel::Warning, text);
    (interval, line)
}

/// One GNSS fix as the receiver reports it (the truth is on the vehicle's state).
pub(super) fn gnss(timestamp: Option<Timestamp>, fix: &GnssFix, sigma_m: f64) -> GnssMessage {
    GnssMessage {
        timestamp,
        vehicle_id: fix.vehicle_id,
        position_m: fix.position_m,
        speed_m_s: fix.speed_m_s,
        position_sigma_m: sigma_m,
    }
}

/// A detector's report of one axle (`None` when it missed it) and the truth of the
/// crossing, both written at `timestamp` (the solver instant after the crossing);
/// `start_time_ns` turns run times into stamps.
pub(super) fn axle_hit(
    timestamp: Option<Timestamp>,
    start_time_ns: u64,
    detector_id: &str,
    hit: &AxleHit,
) -> (Option<AxleDetection>, AxleDetectionTruth) {
    let detected = hit
        .stamp_ns
        .map(|s| timestamp_from_ns(start_time_ns.saturating_add_signed(s)));
    let measured = detected.map(|t| AxleDetection {
        timestamp,
        detector_id: detector_id.to_string(),
        detected_time: Some(t),
    });
    let truth = AxleDetectionTruth {
        timestamp,
        detector_id: detector_id.to_string(),
        vehicle_id: hit.vehicle_id,
        axle_index: hit.axle_index,
        lane: hit.lane,
        speed_m_s: hit.speed_m_s,
        detected: detected.is_some(),
        detected_time: detected,
        crossing_time: Some(timestamp_from_ns(start_time_ns + hit.true_ns)),
    };
    (measured, truth)
}

/// An instrumented vehicle's state.
pub(super) fn vehicle_state(timestamp: Option<Timestamp>, s: VehicleStateRecord) -> VehicleState {
    VehicleState {
        timestamp,
        vehicle_id: s.vehicle_id,
        position_m: s.position_m,
        speed_m_s: s.speed_m_s,
        dof_displacement: s.displacement,
        dof_velocity: s.velocity,
        dof_acceleration: s.acceleration,
        contacts: s
            .contacts
            .iter()
            .enumerate()
            .map(|(j, c)| ContactMessage {
                axle_index: j as u32,
                position_m: c.position_m,
                road_elevation_m: c.road_elevation_m,
                bridge_deflection_m: c.bridge_deflection_m,
                contact_elevation_m: c.road_elevation_m - c.bridge_deflection_m,
                bridge_acceleration_m_s2: c.bridge_acceleration_m_s2,
                force_n: c.force_n,
                on_bridge: c.on_bridge,
            })
            .collect(),
    }
}
