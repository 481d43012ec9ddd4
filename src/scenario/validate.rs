//! Validation and derived values: everything the time loop needs, computed once.

use std::collections::BTreeSet;

use super::{Scenario, SensorKind, SensorSpec};
use crate::error::{require_non_negative, require_positive, Error, Result};
use crate::vehicle::VehicleDynamics;

/// A vehicle ready for the solver.
#[derive(Debug, Clone)]
pub struct ResolvedVehicle {
    pub id: u32,
    pub dynamics: VehicleDynamics,
    pub speed_m_s: f64,
    pub entry_step: u64,
    pub lane: u32,
}

/// A sensor with its defaults filled in.
#[derive(Debug, Clone)]
pub struct ResolvedSensor {
    pub spec: SensorSpec,
    pub noise_density: f64,
    pub gauge_depth_m: f64,
}

/// A validated scenario and its derived values.
#[derive(Debug, Clone)]
pub struct Resolved {
    pub scenario: Scenario,
    pub dt_ns: u64,
    pub steps: u64,
    pub start_time_ns: u64,
    pub vehicles: Vec<ResolvedVehicle>,
    pub sensors: Vec<ResolvedSensor>,
    /// Solver steps between `/truth/axle_loads` messages.
    pub axle_stride: u64,
    /// Solver steps between deflected shapes on `/truth/bridge`.
    pub bridge_stride: u64,
}

impl Resolved {
    /// Duration of the run (s).
    pub fn duration_s(&self) -> f64 {
        self.steps as f64 * self.dt_ns as f64 * 1e-9
    }
}

fn segment_ok(id: &str) -> bool {
    !id.is_empty()
        && id
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
}

/// Steps between two messages of a truth stream at `rate_hz`: must divide the solver rate.
fn stride(field: &str, rate_hz: f64, dt_ns: u64) -> Result<u64> {
    require_positive(field, rate_hz)?;
    let period_ns = 1e9 / rate_hz;
    let stride = (period_ns / dt_ns as f64).round();
    if stride < 1.0 || (stride * dt_ns as f64 - period_ns).abs() > 1e-6 * period_ns {
        return Err(Error::invalid(
            field,
            rate_hz,
            format!("must divide the solver rate {} Hz", 1e9 / dt_ns as f64),
        ));
    }
    Ok(stride as u64)
}

impl Scenario {
    /// Checks every field and computes the derived values.
    pub fn resolve(&self) -> Result<Resolved> {
        let beam = self.bridge.beam();
        beam.validate("bridge")?;
        self.bridge.model.validate("bridge.model")?;
        let zeta = self.bridge.damping_ratio;
        if !(zeta.is_finite() && (0.0..1.0).contains(&zeta)) {
            return Err(Error::invalid(
                "bridge.damping_ratio",
                zeta,
                "must be in [0, 1)",
            ));
        }
        let start_time_ns = parse_start_time(&self.start_time)?;
        let dt_s = require_positive("solver.dt_s", self.solver.dt_s)?;
        let dt_ns = (dt_s * 1e9).round();
        if dt_ns < 1.0 || (dt_ns - dt_s * 1e9).abs() > 1e-6 * dt_ns || dt_s > 0.1 {
            return Err(Error::invalid(
                "solver.dt_s",
                dt_s,
                "must be a whole number of nanoseconds in (0, 0.1] s",
            ));
        }
        let dt_ns = dt_ns as u64;
        crate::solver::NewmarkCoefficients::new(dt_s, self.solver.newmark)?;
        self.road.profile.validate("road.profile")?;
        require_positive("road.approach_m", self.road.approach_m)?;
        require_non_negative("road.exit_m", self.road.exit_m)?;

        let vehicles = self.resolve_vehicles(dt_ns)?;
        let sensors = self.resolve_sensors(dt_ns)?;
        let mut wim_ids = BTreeSet::new();
        for (i, w) in self.wim_stations.iter().enumerate() {
            if !segment_ok(&w.id) {
                return Err(Error::invalid(
                    format!("wim_stations.{i}.id"),
                    format!("\"{}\"", w.id),
                    "must be letters, digits, _ or -",
                ));
            }
            if !wim_ids.insert(w.id.clone()) {
                return Err(Error::invalid(
                    format!("wim_stations.{i}.id"),
                    format!("\"{}\"", w.id),
                    "is used twice",
                ));
            }
            let p = w.position_m;
            if !(p.is_finite() && p > -self.road.approach_m && p < 0.0) {
                return Err(Error::invalid(
                    format!("wim_stations.{i}.position_m"),
                    p,
                    format!(
                        "must lie on the approach, in (-{}, 0) m",
                        self.road.approach_m
                    ),
                ));
            }
        }
        if self.output.block_samples == 0 || self.output.block_samples > 100_000 {
            return Err(Error::invalid(
                "output.block_samples",
                self.output.block_samples,
                "must be in 1..=100000",
            ));
        }
        let axle_stride = stride(
            "output.axle_load_rate_hz",
            self.output.axle_load_rate_hz,
            dt_ns,
        )?;
        let bridge_stride = stride(
            "output.bridge_state_rate_hz",
            self.output.bridge_state_rate_hz,
            dt_ns,
        )?;

        let duration_s = match self.duration_s {
            Some(d) => require_positive("duration_s", d)?,
            None => {
                let leave = vehicles
                    .iter()
                    .map(|v| {
                        let path =
                            self.road.approach_m + self.bridge.span_m + v.dynamics.wheelbase_m();
                        v.entry_step as f64 * dt_s + path / v.speed_m_s
                    })
                    .fold(0.0, f64::max);
                leave + 3.0
            }
        };
        if duration_s > 30.0 * 86_400.0 {
            return Err(Error::invalid(
                "duration_s",
                duration_s,
                "must be at most 30 days",
            ));
        }
        let steps = (duration_s / dt_s).round().max(1.0) as u64;
        Ok(Resolved {
            scenario: self.clone(),
            dt_ns,
            steps,
            start_time_ns,
            vehicles,
            sensors,
            axle_stride,
            bridge_stride,
        })
    }

    fn resolve_vehicles(&self, dt_ns: u64) -> Result<Vec<ResolvedVehicle>> {
        let mut ids = BTreeSet::new();
        let mut out = Vec::new();
        for (i, v) in self.vehicles.iter().enumerate() {
            let path = format!("vehicles.{i}");
            let dynamics = v.model.build(&format!("{path}.model"))?;
            require_positive(&format!("{path}.speed_m_s"), v.speed_m_s)?;
            if v.speed_m_s > 100.0 {
                return Err(Error::invalid(
                    format!("{path}.speed_m_s"),
                    v.speed_m_s,
                    "must be at most 100 m/s",
                ));
            }
            require_non_negative(&format!("{path}.entry_time_s"), v.entry_time_s)?;
            if dynamics.wheelbase_m() >= self.road.approach_m {
                return Err(Error::invalid(
                    "road.approach_m",
                    self.road.approach_m,
                    format!(
                        "must be longer than vehicle {i}'s wheelbase {} m",
                        dynamics.wheelbase_m()
                    ),
                ));
            }
            let id = v.id.unwrap_or(i as u32 + 1);
            if !ids.insert(id) {
                return Err(Error::invalid(format!("{path}.id"), id, "is used twice"));
            }
            let entry_step = (v.entry_time_s * 1e9 / dt_ns as f64).round() as u64;
            out.push(ResolvedVehicle {
                id,
                dynamics,
                speed_m_s: v.speed_m_s,
                entry_step,
                lane: v.lane,
            });
        }
        Ok(out)
    }

    fn resolve_sensors(&self, dt_ns: u64) -> Result<Vec<ResolvedSensor>> {
        let mut ids = BTreeSet::new();
        let solver_rate_hz = 1e9 / dt_ns as f64;
        let mut out = Vec::new();
        for (i, s) in self.sensors.iter().enumerate() {
            let path = format!("sensors.{i}");
            if !segment_ok(&s.id) {
                return Err(Error::invalid(
                    format!("{path}.id"),
                    format!("\"{}\"", s.id),
                    "must be letters, digits, _ or -",
                ));
            }
            if !ids.insert(s.id.clone()) {
                return Err(Error::invalid(
                    format!("{path}.id"),
                    format!("\"{}\"", s.id),
                    "is used twice (sensor ids must be unique)",
                ));
            }
            let p = s.position_m;
            if !(p.is_finite() && (0.0..=self.bridge.span_m).contains(&p)) {
                return Err(Error::invalid(
                    format!("{path}.position_m"),
                    p,
                    format!("must lie on the span [0, {}] m", self.bridge.span_m),
                ));
            }
            require_positive(&format!("{path}.rate_hz"), s.rate_hz)?;
            if s.rate_hz > solver_rate_hz * (1.0 + 1e-12) {
                return Err(Error::invalid(
                    format!("{path}.rate_hz"),
                    s.rate_hz,
                    format!("must not exceed the solver rate 1/dt = {solver_rate_hz} Hz"),
                ));
            }
            let noise_density = match s.noise_density {
                Some(d) => require_non_negative(&format!("{path}.noise_density"), d)?,
                None => s.kind.default_noise_density(),
            };
            let gauge_depth_m = match s.gauge_depth_m {
                Some(d) => require_positive(&format!("{path}.gauge_depth_m"), d)?,
                None => 0.8,
            };
            if s.kind != SensorKind::Strain && s.gauge_depth_m.is_some() {
                return Err(Error::invalid(
                    format!("{path}.gauge_depth_m"),
                    gauge_depth_m,
                    "applies to strain gauges only",
                ));
            }
            out.push(ResolvedSensor {
                spec: s.clone(),
                noise_density,
                gauge_depth_m,
            });
        }
        Ok(out)
    }
}

/// RFC 3339 -> Unix ns (must be after 1970).
fn parse_start_time(text: &str) -> Result<u64> {
    let t = chrono::DateTime::parse_from_rfc3339(text).map_err(|e| {
        Error::invalid(
            "start_time",
            format!("\"{text}\""),
            format!("is not an RFC 3339 time ({e})"),
        )
    })?;
    let ns = t.timestamp_nanos_opt().unwrap_or(-1);
    if ns <= 0 {
        return Err(Error::invalid(
            "start_time",
            format!("\"{text}\""),
            "must be after 1970-01-01",
        ));
    }
    Ok(ns as u64)
}
