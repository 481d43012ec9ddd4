//! Topic names of the output contract (`docs/output.md`), built in one place so that a
//! typo cannot create a topic the tools and layouts do not know.

use crate::error::{Error, Result};
use crate::record::SensorKind;

/// Builds and checks topic names. Segments are restricted to `[A-Za-z0-9_-]` so that
/// they are safe in Foxglove message paths, file names and shell globs.
#[derive(Debug, Clone, Copy)]
pub struct Topics;

impl Topics {
    /// Dynamic contact force of every axle (`AxleLoads`).
    pub const AXLE_LOADS: &'static str = "/truth/axle_loads";
    /// One record per vehicle (`VehicleTruth`).
    pub const VEHICLES: &'static str = "/truth/vehicles";
    /// Deflected shape and modal state (`BridgeState`).
    pub const BRIDGE: &'static str = "/truth/bridge";
    /// Labelled fault intervals of the measured streams.
    pub const FAULTS: &'static str = "/truth/faults";
    /// Events as `foxglove.Log`.
    pub const EVENTS: &'static str = "/events";
    /// Every crossing of every road axle detector, detected or missed.
    pub const AXLE_DETECTIONS: &'static str = "/truth/axle_detections";
    /// The 3D scene as `foxglove.SceneUpdate`.
    pub const SCENE: &'static str = "/scene";
    /// Suffix of a sensor's block-layout topic when both layouts are written in one file
    /// (`/sensors/accel/A1/blocks`); a single-layout file uses the plain sensor topic.
    pub const BLOCKS_SUFFIX: &'static str = "/blocks";

    /// `/sensors/accel/<id>`: accelerometer as recorded by the DAQ.
    pub fn accel(id: &str) -> Result<String> {
        Self::with_segment("/sensors/accel/", "sensor id", id)
    }

    /// `/sensors/strain/<id>`: strain gauge as recorded by the DAQ.
    pub fn strain(id: &str) -> Result<String> {
        Self::with_segment("/sensors/strain/", "sensor id", id)
    }

    /// `/sensors/disp/<id>`: displacement transducer as recorded by the DAQ.
    pub fn disp(id: &str) -> Result<String> {
        Self::with_segment("/sensors/disp/", "sensor id", id)
    }

    /// `/sensors/tilt/<id>`: inclinometer as recorded by the DAQ.
    pub fn tilt(id: &str) -> Result<String> {
        Self::with_segment("/sensors/tilt/", "sensor id", id)
    }

    /// `/sensors/load/<id>`: bearing load cell as recorded by the DAQ.
    pub fn load(id: &str) -> Result<String> {
        Self::with_segment("/sensors/load/", "sensor id", id)
    }

    /// `/sensors/temp/<id>`: deck thermometer as recorded by the DAQ.
    pub fn temp(id: &str) -> Result<String> {
        Self::with_segment("/sensors/temp/", "sensor id", id)
    }

    /// The measured topic of a sensor of `kind`: `/sensors/<segment>/<id>`.
    pub fn sensor(kind: SensorKind, id: &str) -> Result<String> {
        match kind {
            SensorKind::Accelerometer => Self::accel(id),
            SensorKind::Strain => Self::strain(id),
            SensorKind::Displacement => Self::disp(id),
            SensorKind::Inclinometer => Self::tilt(id),
            SensorKind::LoadCell => Self::load(id),
            SensorKind::Thermometer => Self::temp(id),
        }
    }

    /// The topic segment of a sensor kind (`accel`, `strain`, `disp`, `tilt`, `load`,
    /// `temp`).
    pub fn segment(kind: SensorKind) -> &'static str {
        match kind {
            SensorKind::Accelerometer => "accel",
            SensorKind::Strain => "strain",
            SensorKind::Displacement => "disp",
            SensorKind::Inclinometer => "tilt",
            SensorKind::LoadCell => "load",
            SensorKind::Thermometer => "temp",
        }
    }

    /// `/vehicles/<vehicle>/<segment>/<id>`: a sensor riding on a vehicle, as recorded.
    pub fn vehicle_sensor(kind: SensorKind, vehicle_id: u32, id: &str) -> Result<String> {
        Self::with_segment(
            &format!("/vehicles/{vehicle_id}/{}/", Self::segment(kind)),
            "sensor id",
            id,
        )
    }

    /// `/vehicles/<vehicle>/gnss/<id>`: a GNSS receiver's fixes.
    pub fn gnss(vehicle_id: u32, id: &str) -> Result<String> {
        Self::with_segment(&format!("/vehicles/{vehicle_id}/gnss/"), "GNSS id", id)
    }

    /// `/sensors/axle/<id>`: the axles a road axle detector reports.
    pub fn axle_detector(id: &str) -> Result<String> {
        Self::with_segment("/sensors/axle/", "axle detector id", id)
    }

    /// `/truth/vehicle_state/<vehicle>`: an instrumented vehicle's DOFs and contact points.
    pub fn vehicle_state(vehicle_id: u32) -> String {
        format!("/truth/vehicle_state/{vehicle_id}")
    }

    /// `/truth/sensors/<id>`: noise-free response at the sensor location.
    pub fn truth_sensor(id: &str) -> Result<String> {
        Self::with_segment("/truth/sensors/", "sensor id", id)
    }

    /// `/preview/<kind>/<id>` (`kind` = accel, strain, disp, tilt, load): the measured stream
    /// decimated for viewers, one sample per message.
    pub fn preview(kind_segment: &str, id: &str) -> Result<String> {
        Self::with_segment(&format!("/preview/{kind_segment}/"), "sensor id", id)
    }

    /// `/preview/truth/<id>`: the truth of the measured quantity, decimated alike.
    pub fn preview_truth(id: &str) -> Result<String> {
        Self::with_segment("/preview/truth/", "sensor id", id)
    }

    /// `/wim/<station>`: records of one weigh-in-motion station.
    pub fn wim(station: &str) -> Result<String> {
        Self::with_segment("/wim/", "WIM station id", station)
    }

    /// The block-layout topic next to a per-sample topic: `topic` + [`Self::BLOCKS_SUFFIX`].
    pub fn blocks(topic: &str) -> Result<String> {
        let blocks = format!("{topic}{}", Self::BLOCKS_SUFFIX);
        validate_topic(&blocks)?;
        Ok(blocks)
    }

    fn with_segment(prefix: &str, what: &str, segment: &str) -> Result<String> {
        validate_segment(what, segment)?;
        Ok(format!("{prefix}{segment}"))
    }
}

/// Checks one topic segment (a sensor or station id): non-empty, `[A-Za-z0-9_-]` only.
/// `what` names the value in the error message.
pub fn validate_segment(what: &str, segment: &str) -> Result<()> {
    let valid = !segment.is_empty()
        && segment
            .bytes()
            .all(|b| b.is_ascii_alphanumeric() || b == b'_' || b == b'-');
    if valid {
        Ok(())
    } else {
        Err(Error::invalid(
            what,
            format!("{segment:?}"),
            "must be non-empty and use only A-Z, a-z, 0-9, '_' and '-'",
        ))
    }
}

/// Checks a whole topic: a leading `/` and valid segments (`/a/b`, no trailing `/`).
pub fn validate_topic(topic: &str) -> Result<()> {
    let segments = topic
        .strip_prefix('/')
        .ok_or_else(|| Error::invalid("topic", format!("{topic:?}"), "must start with '/'"))?;
    segments
        .split('/')
        .try_for_each(|segment| validate_segment("topic segment", segment))
        .map_err(|_| {
            Error::invalid(
                "topic",
                format!("{topic:?}"),
                "segments must be non-empty and use only A-Z, a-z, 0-9, '_' and '-'",
            )
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn builds_contract_topics() {
        assert_eq!(Topics::accel("A3").unwrap(), "/sensors/accel/A3");
        assert_eq!(Topics::strain("S_1").unwrap(), "/sensors/strain/S_1");
        assert_eq!(Topics::disp("D-2").unwrap(), "/sensors/disp/D-2");
        assert_eq!(Topics::truth_sensor("A3").unwrap(), "/truth/sensors/A3");
        assert_eq!(Topics::wim("north").unwrap(), "/wim/north");
        assert_eq!(
            Topics::blocks("/sensors/accel/A3").unwrap(),
            "/sensors/accel/A3/blocks"
        );
        for topic in [
            Topics::AXLE_LOADS,
            Topics::VEHICLES,
            Topics::BRIDGE,
            Topics::EVENTS,
            Topics::SCENE,
        ] {
            validate_topic(topic).unwrap();
        }
    }

    #[test]
    fn rejects_bad_segments() {
        for bad in ["", "a/b", "a b", "a.b", "é", "x{y}"] {
            assert!(Topics::accel(bad).is_err(), "{bad:?} accepted");
        }
        for bad in ["", "/", "no_slash", "/a//b", "/a/", "/a.b"] {
            assert!(validate_topic(bad).is_err(), "{bad:?} accepted");
        }
    }
}
