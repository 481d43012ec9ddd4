//! Instruments beyond the bridge sensors: accelerometers riding on vehicles (drive-by
//! monitoring), GNSS receivers on vehicles, and axle detectors on the road (B-WIM). Their
//! scenario tables, and the checks that tie each to a vehicle or a place on the road.

use std::collections::BTreeSet;

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::resolve::unique_segment;
use super::resolved::{ResolvedMount, ResolvedVehicle};
use super::Scenario;
use crate::base::schema as bounds;
use crate::error::{item_path, num, require_non_negative, require_positive, Error, Result};
use crate::measurement::vehicle::GnssNoise;
use crate::physics::vehicle::{MountError, MountPoint, BODY_OVERHANG_M};

/// Where a sensor rides on a vehicle: on an axle or on the body (give exactly one).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
#[schemars(transform = bounds::exactly_one_key(&["axle", "body_offset_m"]))]
pub struct VehicleMountSpec {
    /// The vehicle's id (`vehicles.N.id`; without one, its 1-based place in the list).
    pub id: u32,
    /// On the unsprung mass of this axle (1 = the front axle): what drive-by studies
    /// instrument, since the axle follows the road and the deck closely.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(range(min = 1))]
    pub axle: Option<u32>,
    /// On the body, this far behind the front axle (m): it bounces and pitches.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(range(min = -30, max = 30))]
    pub body_offset_m: Option<f64>,
}

/// A GNSS receiver on a vehicle: `/vehicles/<vehicle>/gnss/<id>`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct GnssSpec {
    /// Receiver name in the topic: letters, digits, `_` and `-`; unique.
    #[schemars(regex(pattern = bounds::TOPIC_SEGMENT))]
    pub id: String,
    /// The vehicle carrying it (`vehicles.N.id`).
    pub vehicle: u32,
    /// Fixes per second (Hz, default 10), at most the solver rate.
    #[serde(default = "default_gnss_rate_hz")]
    #[schemars(transform = bounds::positive)]
    pub rate_hz: f64,
    /// Standard deviation of the position error along the road (m, default 0.02: an RTK
    /// fix; a phone or a standalone receiver is 2-5 m).
    #[serde(default = "default_position_noise_m")]
    #[schemars(range(min = 0))]
    pub position_noise_m: f64,
    /// Correlation time of the position error (s, default 0: white; standalone
    /// receivers wander over tens of seconds).
    #[serde(default)]
    #[schemars(range(min = 0))]
    pub correlation_s: f64,
    /// Standard deviation of the speed error (m/s, default 0.02: Doppler speed).
    #[serde(default = "default_speed_noise_m_s")]
    #[schemars(range(min = 0))]
    pub speed_noise_m_s: f64,
}

fn default_gnss_rate_hz() -> f64 {
    10.0
}
fn default_position_noise_m() -> f64 {
    0.02
}
fn default_speed_noise_m_s() -> f64 {
    0.02
}

impl GnssSpec {
    /// The receiver's noise.
    pub fn noise(&self) -> GnssNoise {
        GnssNoise {
            position_sigma_m: self.position_noise_m,
            correlation_s: self.correlation_s,
            speed_sigma_m_s: self.speed_noise_m_s,
        }
    }
}

/// A road axle detector (tape switch): `/sensors/axle/<id>` gets one message per axle it
/// detects, `/truth/axle_detections` every crossing.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct AxleDetectorSpec {
    /// Detector name in the topic: letters, digits, `_` and `-`; unique.
    #[schemars(regex(pattern = bounds::TOPIC_SEGMENT))]
    pub id: String,
    /// Position on the road axis (m, the bridge's x: negative on the approach), on the
    /// modelled road [-road.approach_m, length + road.exit_m].
    pub position_m: f64,
    /// Only vehicles in this lane (default: every lane, a tape across the carriageway).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lane: Option<u32>,
    /// Standard deviation of the timing error (s, default 0.0005: a tape switch logged
    /// at a few kHz).
    #[serde(default = "default_jitter_s")]
    #[schemars(range(min = 0, max = 1))]
    pub jitter_s: f64,
    /// Probability of missing an axle (default 0), in [0, 1).
    #[serde(default)]
    #[schemars(range(min = 0), transform = bounds::below(1.0))]
    pub miss_probability: f64,
}

fn default_jitter_s() -> f64 {
    5e-4
}

impl Scenario {
    /// The mount of a sensor riding on a vehicle, checked against that vehicle's model.
    pub(super) fn resolve_mount(
        &self,
        mount: &VehicleMountSpec,
        path: &str,
        vehicles: &[ResolvedVehicle],
    ) -> Result<ResolvedMount> {
        let vehicle = find_vehicle(vehicles, mount.id, &format!("{path}.vehicle.id"))?;
        let (point, field, value, label) = match (mount.axle, mount.body_offset_m) {
            (Some(axle), None) => (
                MountPoint::Axle {
                    index: axle.saturating_sub(1) as usize,
                },
                "axle",
                axle.to_string(),
                format!("axle {axle}"),
            ),
            (None, Some(offset)) if offset.is_finite() => (
                MountPoint::Body { offset_m: offset },
                "body_offset_m",
                num(offset),
                format!("body, {} m behind the front axle", num(offset)),
            ),
            (None, Some(offset)) => {
                return Err(Error::invalid(
                    format!("{path}.vehicle.body_offset_m"),
                    num(offset),
                    "must be a finite offset behind the front axle (m)",
                ))
            }
            (Some(axle), Some(offset)) => {
                return Err(Error::invalid(
                    format!("{path}.vehicle"),
                    format!(
                        "{{ id = {}, axle = {axle}, body_offset_m = {} }}",
                        mount.id,
                        num(offset)
                    ),
                    "needs exactly one of axle (1 = front) or body_offset_m, not both",
                ))
            }
            (None, None) => {
                return Err(Error::invalid(
                    format!("{path}.vehicle"),
                    format!("{{ id = {} }}", mount.id),
                    "needs one of axle (1 = front) or body_offset_m",
                ))
            }
        };
        if mount.axle == Some(0) {
            return Err(Error::invalid(
                format!("{path}.vehicle.axle"),
                0,
                "counts from 1 (the front axle)",
            ));
        }
        let model = &vehicle.dynamics.name;
        let dofs = vehicle.dynamics.mount_point(point).map_err(|e| {
            let reason = match e {
                MountError::NoSuchAxle { axles } => {
                    format!(
                        "is not an axle of vehicle {} ({model} has {axles})",
                        mount.id
                    )
                }
                MountError::RigidAxle => format!(
                    "is a moving force on vehicle {} ({model}): nothing moves there to \
                     measure; use a model with suspension",
                    mount.id
                ),
                MountError::NoSingleBody => format!(
                    "needs one rigid body, which vehicle {} ({model}) has not: mount the \
                     sensor on an axle",
                    mount.id
                ),
                MountError::OffBody { from_m, to_m } => format!(
                    "is off the body of vehicle {} ({model}, axles over {} m): a body point \
                     lies from {} to {} m behind the front axle",
                    mount.id,
                    num(to_m - BODY_OVERHANG_M),
                    num(from_m),
                    num(to_m)
                ),
            };
            Error::invalid(format!("{path}.vehicle.{field}"), value, reason)
        })?;
        Ok(ResolvedMount {
            vehicle_id: mount.id,
            dofs,
            label,
        })
    }

    /// The GNSS receivers: ids unique, each on a listed vehicle, rates within the solver's.
    pub(super) fn check_gnss(&self, vehicles: &[ResolvedVehicle], dt_ns: u64) -> Result<()> {
        let mut ids = BTreeSet::new();
        let solver_rate_hz = 1e9 / dt_ns as f64;
        for (i, g) in self.gnss.iter().enumerate() {
            let path = item_path("gnss", i, Some(&g.id));
            unique_segment(
                &mut ids,
                &format!("{path}.id"),
                &g.id,
                "is used twice (GNSS ids must be unique)",
            )?;
            find_vehicle(vehicles, g.vehicle, &format!("{path}.vehicle"))?;
            require_positive(&format!("{path}.rate_hz"), g.rate_hz)?;
            if g.rate_hz > solver_rate_hz * (1.0 + 1e-12) {
                return Err(Error::invalid(
                    format!("{path}.rate_hz"),
                    num(g.rate_hz),
                    format!(
                        "is above the solver rate 1/dt = {solver_rate_hz} Hz: a fix needs \
                         a solver step of its own"
                    ),
                ));
            }
            require_non_negative(&format!("{path}.position_noise_m"), g.position_noise_m)?;
            require_non_negative(&format!("{path}.correlation_s"), g.correlation_s)?;
            require_non_negative(&format!("{path}.speed_noise_m_s"), g.speed_noise_m_s)?;
        }
        Ok(())
    }

    /// The axle detectors: ids unique, each on the modelled road, jitter and miss rate
    /// sensible.
    pub(super) fn check_axle_detectors(&self) -> Result<()> {
        let mut ids = BTreeSet::new();
        let (start_m, end_m) = (
            -self.road.approach_m,
            self.bridge.length_m() + self.road.exit_m,
        );
        for (i, d) in self.axle_detectors.iter().enumerate() {
            let path = item_path("axle_detectors", i, Some(&d.id));
            unique_segment(
                &mut ids,
                &format!("{path}.id"),
                &d.id,
                "is used twice (axle detector ids must be unique)",
            )?;
            if !(d.position_m.is_finite() && (start_m..=end_m).contains(&d.position_m)) {
                return Err(Error::invalid(
                    format!("{path}.position_m"),
                    num(d.position_m),
                    format!(
                        "is off the road: axles pass only on the modelled road [{}, {}] m \
                         (road.approach_m before the bridge, road.exit_m after it)",
                        num(start_m),
                        num(end_m)
                    ),
                ));
            }
            if !(d.jitter_s.is_finite() && (0.0..=1.0).contains(&d.jitter_s)) {
                return Err(Error::invalid(
                    format!("{path}.jitter_s"),
                    num(d.jitter_s),
                    "must be in [0, 1] s",
                ));
            }
            if !(0.0..1.0).contains(&d.miss_probability) {
                return Err(Error::invalid(
                    format!("{path}.miss_probability"),
                    num(d.miss_probability),
                    "must be in [0, 1)",
                ));
            }
        }
        Ok(())
    }
}

/// The listed vehicle with id `id`, or an error naming `field` and the known ids.
fn find_vehicle<'a>(
    vehicles: &'a [ResolvedVehicle],
    id: u32,
    field: &str,
) -> Result<&'a ResolvedVehicle> {
    vehicles.iter().find(|v| v.id == id).ok_or_else(|| {
        let known: Vec<u32> = vehicles.iter().map(|v| v.id).collect();
        Error::invalid(
            field,
            id,
            format!(
                "is not the id of a [[vehicles]] entry (known: {known:?}); instruments ride \
                 on listed vehicles, which may enter amid generated traffic"
            ),
        )
    })
}
