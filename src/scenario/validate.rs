//! Validation and derived values: everything the time loop needs, computed once.

use std::collections::BTreeSet;

use super::{Scenario, SensorKind, SensorSpec};
use crate::base::random::child_rng;
use crate::error::{num, require_non_negative, require_positive, Error, Result};
use crate::measurement::sensor::{AntiAliasOptions, ChannelSpec, SensorChannel, WhiteNoise};
use crate::physics::bridge::{BeamProperties, ModelSpec};
use crate::physics::vehicle::VehicleDynamics;

/// Longest run: 30 days (s).
pub const MAX_DURATION_S: f64 = 30.0 * 86_400.0;

/// Most solver steps in one run, 2^32 (30 days at dt = 1 ms are 2.6e9 steps).
pub const MAX_STEPS: u64 = 1 << 32;

/// Longest span (m): the longest bridge spans are about 2 km.
pub const MAX_SPAN_M: f64 = 10_000.0;

/// Longest approach or exit road (m).
pub const MAX_ROAD_M: f64 = 100_000.0;

/// The first natural frequency a bridge may have (Hz, closed form of the uniform beam):
/// road bridges have 0.2-30 Hz, laboratory beams up to a few hundred. Outside this range
/// the input is a typo (an exponent off by orders of magnitude), not a bridge.
pub const F1_RANGE_HZ: (f64, f64) = (0.01, 10_000.0);

/// `warnings`: fewest solver steps per period of the first bridge mode (Newmark's period
/// error is about (2 pi / N)^2 / 12, 0.8 % at N = 20).
pub const MIN_STEPS_PER_MODE_PERIOD: f64 = 20.0;

/// `warnings`: fewest solver steps per period at the edge of a sensor's band.
pub const MIN_STEPS_PER_SENSOR_PERIOD: f64 = 10.0;

/// `warnings`: model sizes above which building the model (dense eigen-decomposition,
/// cost ~ n^3) takes more than a few seconds: FE elements (about 5 s at 500 and 1 min at
/// 1000 on a 2-core machine), lumped masses (about 5 s at 1000).
const SLOW_SETUP_ELEMENTS: usize = 400;
const SLOW_SETUP_NODES: usize = 1000;

/// A vehicle ready for the solver.
#[derive(Debug, Clone)]
pub struct ResolvedVehicle {
    pub id: u32,
    pub dynamics: VehicleDynamics,
    pub speed_m_s: f64,
    pub entry_step: u64,
    pub lane: u32,
    /// +1 towards +x, -1 towards -x.
    pub direction: i8,
}

/// A sensor with its defaults filled in.
#[derive(Debug, Clone)]
pub struct ResolvedSensor {
    pub spec: SensorSpec,
    pub noise_density: f64,
    pub gauge_depth_m: f64,
    /// Index into `scenario.daq_nodes` of the node whose clock samples this sensor.
    pub node: Option<usize>,
    /// The measurement chain when the sensor has a preset or chain table (its white noise
    /// then replaces the channel's plain `noise_density`).
    pub chain: Option<crate::measurement::sensor::chain::ResolvedChain>,
}

impl ResolvedSensor {
    /// The white-noise density the channel itself adds: 0 when the chain has the noise.
    pub fn channel_noise_density(&self) -> f64 {
        match self.chain {
            Some(_) => 0.0,
            None => self.noise_density,
        }
    }

    /// The sensor model's name for channel metadata.
    pub fn model_name(&self) -> &'static str {
        match &self.chain {
            Some(c) => c.preset().name(),
            None => "white_noise",
        }
    }
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

    /// Whether some sensor has faults configured (the run then writes `/truth/faults`).
    pub fn has_faults(&self) -> bool {
        self.sensors
            .iter()
            .any(|s| s.spec.faults.as_ref().is_some_and(|f| !f.is_empty()))
    }

    /// Questionable but legal inputs, one line each, naming the field and its value: a
    /// time step too coarse for the first bridge mode or for a sensor's band, a sensor
    /// whose band stops below the first mode, vehicles that never reach the bridge within
    /// the run, an unusual damping ratio, a model that is slow to build. Empty for the
    /// default scenario.
    pub fn warnings(&self) -> Vec<String> {
        let s = &self.scenario;
        let mut out = Vec::new();
        let dt_s = self.dt_ns as f64 * 1e-9;
        let f1 = s.bridge.beam().closed_form_frequency_hz(1);
        let per_period = 1.0 / (f1 * dt_s);
        if per_period < MIN_STEPS_PER_MODE_PERIOD {
            let w_dt = 2.0 * std::f64::consts::PI / per_period;
            out.push(format!(
                "solver.dt_s = {} gives {per_period:.1} steps per period of the first bridge \
                 mode (f1 = {f1:.3} Hz, closed form): the period error is about {:.1} %; \
                 use dt_s <= {:.3e} for {MIN_STEPS_PER_MODE_PERIOD} steps",
                num(dt_s),
                100.0 * w_dt * w_dt / 12.0,
                1.0 / (MIN_STEPS_PER_MODE_PERIOD * f1),
            ));
        }
        let solver_rate_hz = 1e9 / self.dt_ns as f64;
        for (i, r) in self.sensors.iter().enumerate() {
            let rate = r.spec.rate_hz;
            // Equal rates pass through unfiltered (up to Nyquist); otherwise the
            // anti-alias pass band ends at 0.4 rate.
            let pass_through = rate >= solver_rate_hz * (1.0 - 1e-12);
            let band_edge_hz = if pass_through { 0.5 * rate } else { 0.4 * rate };
            let steps = solver_rate_hz / band_edge_hz;
            if steps < MIN_STEPS_PER_SENSOR_PERIOD {
                out.push(format!(
                    "sensors.{i}.rate_hz = {}: the time step is coarse for this rate: the \
                     recorded band reaches {} Hz, which solver.dt_s = {} samples only \
                     {steps:.1} times per period (time-discretization error dominates \
                     there); use dt_s <= {:.3e}",
                    num(rate),
                    num(band_edge_hz),
                    num(dt_s),
                    1.0 / (MIN_STEPS_PER_SENSOR_PERIOD * band_edge_hz),
                ));
            }
            if band_edge_hz < f1 {
                out.push(format!(
                    "sensors.{i}.rate_hz = {}: the recorded band ends at {} Hz, below the \
                     first bridge mode f1 = {f1:.3} Hz",
                    num(rate),
                    num(band_edge_hz),
                ));
            }
        }
        let duration_s = self.duration_s();
        for (i, (v, entry)) in self.vehicles.iter().zip(&s.vehicles).enumerate() {
            let enters_s = v.entry_step as f64 * dt_s;
            let arrives_s = enters_s + s.road.approach_m / v.speed_m_s;
            if enters_s >= duration_s {
                out.push(format!(
                    "vehicles.{i}.entry_time_s = {} is at or after the end of the run \
                     ({duration_s} s): the vehicle never appears",
                    num(entry.entry_time_s),
                ));
            } else if arrives_s >= duration_s {
                out.push(format!(
                    "vehicles.{i}.speed_m_s = {}: the vehicle reaches the bridge at t = \
                     {arrives_s:.3} s (entry_time_s = {}, road.approach_m = {}), after the \
                     end of the run ({duration_s} s)",
                    num(v.speed_m_s),
                    num(entry.entry_time_s),
                    num(s.road.approach_m),
                ));
            }
        }
        let zeta = s.bridge.damping_ratio;
        if zeta > 0.1 {
            out.push(format!(
                "bridge.damping_ratio = {}: far above bridge values (0.005-0.05)",
                num(zeta)
            ));
        }
        let slow = match s.bridge.model {
            ModelSpec::FiniteElement { elements } if elements > SLOW_SETUP_ELEMENTS => {
                Some(("bridge.model.elements", elements))
            }
            ModelSpec::LumpedMass { nodes, .. } if nodes > SLOW_SETUP_NODES => {
                Some(("bridge.model.nodes", nodes))
            }
            ModelSpec::Modal { modes, elements } => {
                let mesh = elements.unwrap_or((4 * modes).max(40));
                match elements {
                    Some(e) if e > SLOW_SETUP_ELEMENTS => Some(("bridge.model.elements", e)),
                    None if mesh > SLOW_SETUP_ELEMENTS => Some(("bridge.model.modes", modes)),
                    _ => None,
                }
            }
            _ => None,
        };
        if let Some((field, n)) = slow {
            out.push(format!(
                "{field} = {n}: building the model (a dense eigen-decomposition, cost ~ n^3) \
                 takes long: about 5 s for 500 finite elements or 1000 lumped masses, 1 min \
                 for 1000 finite elements on a 2-core machine"
            ));
        }
        out
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
    if period_ns > MAX_DURATION_S * 1e9 {
        return Err(Error::invalid(
            field,
            num(rate_hz),
            "is too low: less than one message in 30 days",
        ));
    }
    if stride < 1.0 || (stride * dt_ns as f64 - period_ns).abs() > 1e-6 * period_ns {
        return Err(Error::invalid(
            field,
            num(rate_hz),
            format!(
                "must divide the solver rate {} Hz (a whole number of solver steps between \
                 messages, and at most the solver rate)",
                1e9 / dt_ns as f64
            ),
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
                num(zeta),
                "must be in [0, 1)",
            ));
        }
        self.check_bridge_plausible()?;
        let start_time_ns = parse_start_time(&self.start_time)?;
        let dt_s = require_positive("solver.dt_s", self.solver.dt_s)?;
        let dt_ns = (dt_s * 1e9).round();
        if dt_ns < 1.0 || (dt_ns - dt_s * 1e9).abs() > 1e-6 * dt_ns || dt_s > 0.1 {
            return Err(Error::invalid(
                "solver.dt_s",
                num(dt_s),
                "must be a whole number of nanoseconds in (0, 0.1] s",
            ));
        }
        let dt_ns = dt_ns as u64;
        crate::physics::solver::NewmarkCoefficients::new(dt_s, self.solver.newmark)?;
        self.road.profile.validate("road.profile")?;
        require_positive("road.approach_m", self.road.approach_m)?;
        require_non_negative("road.exit_m", self.road.exit_m)?;
        for (field, value) in [
            ("road.approach_m", self.road.approach_m),
            ("road.exit_m", self.road.exit_m),
        ] {
            if value > MAX_ROAD_M {
                return Err(Error::invalid(
                    field,
                    num(value),
                    format!("must be at most {MAX_ROAD_M} m"),
                ));
            }
        }

        let vehicles = self.resolve_vehicles(dt_ns)?;
        self.validate_daq_nodes()?;
        if let Some(traffic) = &self.traffic {
            traffic.validate("traffic")?;
            if self.duration_s.is_none() {
                return Err(Error::invalid(
                    "duration_s",
                    "(missing)",
                    "is required with [traffic]: generated traffic has no last vehicle",
                ));
            }
        }
        self.validate_condition()?;
        if let Some(ambient) = &self.ambient {
            ambient.validate("ambient", self.bridge.span_m, dt_s)?;
        }
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
            crate::measurement::wim::WimStation::new(&w.model, &format!("wim_stations.{i}.model"))?
                .with_limits(w.limits, &format!("wim_stations.{i}.limits"))?;
            let p = w.position_m;
            if !(p.is_finite() && p > -self.road.approach_m && p < 0.0) {
                return Err(Error::invalid(
                    format!("wim_stations.{i}.position_m"),
                    num(p),
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
        if let Some(split_s) = self.output.split_every_s {
            if !(split_s.is_finite() && split_s >= 1.0) {
                return Err(Error::invalid(
                    "output.split_every_s",
                    num(split_s),
                    "must be at least 1 s of simulated time per file",
                ));
            }
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
            Some(d) => {
                require_positive("duration_s", d)?;
                if d > MAX_DURATION_S {
                    return Err(Error::invalid(
                        "duration_s",
                        num(d),
                        format!("must be at most 30 days ({MAX_DURATION_S} s)"),
                    ));
                }
                d
            }
            None => self.default_duration_s(&vehicles, dt_s)?,
        };
        let steps = (duration_s / dt_s).round().max(1.0);
        if steps > MAX_STEPS as f64 {
            let (field, value, what) = match self.duration_s {
                Some(d) => ("duration_s", d, format!("with solver.dt_s = {}", num(dt_s))),
                None => (
                    "solver.dt_s",
                    dt_s,
                    format!("over the default duration {} s", num(duration_s)),
                ),
            };
            return Err(Error::invalid(
                field,
                num(value),
                format!(
                    "{what} needs {} solver steps, more than {MAX_STEPS} (2^32): use a larger \
                     time step or a shorter run",
                    num(steps)
                ),
            ));
        }
        let steps = steps as u64;
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

    /// Span within `MAX_SPAN_M`, first natural frequency within `F1_RANGE_HZ`. Out of
    /// range, the error names the field that moves f1 furthest from the paper's bridge
    /// in that direction (f1 ~ sqrt(EI / m) / L^2).
    fn check_bridge_plausible(&self) -> Result<()> {
        let b = &self.bridge;
        if b.span_m > MAX_SPAN_M {
            return Err(Error::invalid(
                "bridge.span_m",
                num(b.span_m),
                format!("must be at most {MAX_SPAN_M} m (no bridge spans more)"),
            ));
        }
        let f1 = b.beam().closed_form_frequency_hz(1);
        let (lo, hi) = F1_RANGE_HZ;
        if f1.is_finite() && (lo..=hi).contains(&f1) {
            return Ok(());
        }
        let paper = BeamProperties::paper_default();
        let shifts = [
            ("span_m", b.span_m, -2.0 * (b.span_m / paper.span_m).ln()),
            (
                "flexural_rigidity_n_m2",
                b.flexural_rigidity_n_m2,
                0.5 * (b.flexural_rigidity_n_m2 / paper.flexural_rigidity_n_m2).ln(),
            ),
            (
                "mass_per_length_kg_m",
                b.mass_per_length_kg_m,
                -0.5 * (b.mass_per_length_kg_m / paper.mass_per_length_kg_m).ln(),
            ),
        ];
        let too_high = if f1.is_nan() {
            shifts.iter().map(|s| s.2).sum::<f64>() > 0.0
        } else {
            f1 > hi
        };
        let by_shift = |a: &&(&str, f64, f64), b: &&(&str, f64, f64)| a.2.total_cmp(&b.2);
        let culprit = if too_high {
            shifts.iter().max_by(by_shift)
        } else {
            shifts.iter().min_by(by_shift)
        }
        .unwrap_or(&shifts[0]);
        let others: Vec<String> = shifts
            .iter()
            .filter(|s| s.0 != culprit.0)
            .map(|(name, value, _)| format!("bridge.{name} = {}", num(*value)))
            .collect();
        Err(Error::invalid(
            format!("bridge.{}", culprit.0),
            num(culprit.1),
            format!(
                "gives a first natural frequency f1 = {} Hz (with {}; uniform beam, closed \
                 form), outside [{lo}, {hi}] Hz: not a bridge or laboratory beam",
                num(f1),
                others.join(", ")
            ),
        ))
    }

    /// Until the last vehicle has left the bridge + 3 s; at most `MAX_DURATION_S`.
    fn default_duration_s(&self, vehicles: &[ResolvedVehicle], dt_s: f64) -> Result<f64> {
        let mut last = (0.0, None);
        for (i, v) in vehicles.iter().enumerate() {
            let path = self.road.approach_m + self.bridge.span_m + v.dynamics.wheelbase_m();
            let entry_s = v.entry_step as f64 * dt_s;
            let leave = entry_s + path / v.speed_m_s;
            if leave > last.0 {
                last = (leave, Some((i, entry_s, path / v.speed_m_s)));
            }
        }
        let duration_s = last.0 + 3.0;
        match last.1 {
            Some((i, entry_s, travel_s)) if duration_s > MAX_DURATION_S => {
                let (field, value) = if entry_s > travel_s {
                    ("entry_time_s", self.vehicles[i].entry_time_s)
                } else {
                    ("speed_m_s", self.vehicles[i].speed_m_s)
                };
                Err(Error::invalid(
                    format!("vehicles.{i}.{field}"),
                    num(value),
                    format!(
                        "makes the default duration (until the last vehicle has left the \
                         bridge + 3 s) {} s, more than 30 days; set duration_s",
                        num(duration_s)
                    ),
                ))
            }
            _ => Ok(duration_s),
        }
    }

    /// `[environment]` and `[[damage]]`: each field, the regions on the span, and a model
    /// that can be rebuilt for a local EI change.
    fn validate_condition(&self) -> Result<()> {
        if let Some(environment) = &self.environment {
            environment.validate("environment")?;
        }
        crate::physics::environment::validate_damage(&self.damage, self.bridge.span_m)?;
        if !self.damage.is_empty() {
            if let ModelSpec::Modal { .. } = self.bridge.model {
                // A local EI loss changes the mode shapes: the modal coordinates of the
                // running state would mean something else in the rebuilt basis.
                return Err(Error::invalid(
                    "bridge.model",
                    self.bridge.model.label(),
                    "a modal model cannot follow [[damage]] (it changes the mode shapes): \
                     use kind = \"finite_element\" or \"lumped_mass\"",
                ));
            }
        }
        Ok(())
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
                    num(v.speed_m_s),
                    "must be at most 100 m/s",
                ));
            }
            require_non_negative(&format!("{path}.entry_time_s"), v.entry_time_s)?;
            if v.entry_time_s > MAX_DURATION_S {
                return Err(Error::invalid(
                    format!("{path}.entry_time_s"),
                    num(v.entry_time_s),
                    "must be at most 30 days",
                ));
            }
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
            if v.direction != 1 && v.direction != -1 {
                return Err(Error::invalid(
                    format!("{path}.direction"),
                    v.direction,
                    "must be 1 (towards +x) or -1 (towards -x)",
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
                direction: v.direction,
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
                    num(p),
                    format!("must lie on the span [0, {}] m", self.bridge.span_m),
                ));
            }
            require_positive(&format!("{path}.rate_hz"), s.rate_hz)?;
            if s.rate_hz > solver_rate_hz * (1.0 + 1e-12) {
                return Err(Error::invalid(
                    format!("{path}.rate_hz"),
                    num(s.rate_hz),
                    format!(
                        "must not exceed the solver rate 1/dt = {solver_rate_hz} Hz \
                         (solver.dt_s = {}): the time step is too coarse for this sensor",
                        num(dt_ns as f64 * 1e-9)
                    ),
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
            let sigma = noise_density * (0.5 * s.rate_hz).sqrt();
            if !sigma.is_finite() {
                return Err(Error::invalid(
                    format!("{path}.noise_density"),
                    num(noise_density),
                    format!(
                        "gives a per-sample noise sigma of {} at {} Hz",
                        num(sigma),
                        s.rate_hz
                    ),
                ));
            }
            // The channel the run will build: checks what only the filter design knows
            // (a rate far below the solver rate needs a kernel too long to run).
            let channel = ChannelSpec {
                rate_hz: s.rate_hz,
                anti_alias: AntiAliasOptions::default(),
                noise: WhiteNoise {
                    density_per_sqrt_hz: noise_density,
                },
            };
            SensorChannel::new(
                solver_rate_hz,
                &channel,
                child_rng(self.seed, "validate"),
                &path,
            )?;
            let node = self.resolve_daq_node(s, &path, solver_rate_hz)?;
            let chain = resolve_chain(s, &path)?;
            if let Some(faults) = &s.faults {
                faults.validate(&format!("{path}.faults"))?;
            }
            out.push(ResolvedSensor {
                spec: s.clone(),
                noise_density,
                gauge_depth_m,
                node,
                chain,
            });
        }
        Ok(out)
    }

    /// Node ids unique, clocks valid.
    fn validate_daq_nodes(&self) -> Result<()> {
        let mut ids = BTreeSet::new();
        for (i, node) in self.daq_nodes.iter().enumerate() {
            node.validate(&format!("daq_nodes.{i}"))?;
            if !ids.insert(node.id.as_str()) {
                return Err(Error::invalid(
                    format!("daq_nodes.{i}.id"),
                    format!("\"{}\"", node.id),
                    "is used twice (node ids must be unique)",
                ));
            }
        }
        Ok(())
    }

    /// The index of the sensor's node; its clock must suit the sensor's rate, and a
    /// clocked sensor must sample at most half the solver rate (drift and jitter move its
    /// instants between solver steps, which the anti-alias filter interpolates).
    fn resolve_daq_node(
        &self,
        s: &SensorSpec,
        path: &str,
        solver_rate_hz: f64,
    ) -> Result<Option<usize>> {
        let Some(id) = &s.daq_node else {
            return Ok(None);
        };
        let Some(index) = self.daq_nodes.iter().position(|n| &n.id == id) else {
            let known: Vec<&str> = self.daq_nodes.iter().map(|n| n.id.as_str()).collect();
            return Err(Error::invalid(
                format!("{path}.daq_node"),
                format!("\"{id}\""),
                format!("is not a [[daq_nodes]] id (known: {known:?})"),
            ));
        };
        if s.rate_hz > 0.5 * solver_rate_hz {
            return Err(Error::invalid(
                format!("{path}.rate_hz"),
                num(s.rate_hz),
                format!(
                    "must be at most half the solver rate ({} Hz) for a sensor on a DAQ node \
                     clock",
                    0.5 * solver_rate_hz
                ),
            ));
        }
        self.daq_nodes[index]
            .clock
            .validate_for_rate(&format!("daq_nodes.{index}.clock"), s.rate_hz)?;
        Ok(Some(index))
    }
}

/// The sensor's measurement chain, when it has a preset or a chain table: the preset's
/// values, overridden by the chain table, then by `noise_density` if given.
fn resolve_chain(
    s: &SensorSpec,
    path: &str,
) -> Result<Option<crate::measurement::sensor::chain::ResolvedChain>> {
    use crate::measurement::sensor::chain::{resolve, TransducerKind};
    if s.preset.is_none() && s.chain.is_none() {
        return Ok(None);
    }
    let kind = match s.kind {
        SensorKind::Accelerometer => TransducerKind::Accelerometer,
        SensorKind::Strain => TransducerKind::Strain,
        SensorKind::Displacement => TransducerKind::Displacement,
    };
    let mut spec = s.chain.clone().unwrap_or_default();
    if let Some(d) = s.noise_density {
        spec.noise_density = Some(d);
    }
    let chain = resolve(s.preset.unwrap_or_default(), kind, &spec, path)?;
    chain.check_rate(s.rate_hz, &format!("{path}.rate_hz"))?;
    Ok(Some(chain))
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
    let Some(ns) = t.timestamp_nanos_opt() else {
        return Err(Error::invalid(
            "start_time",
            format!("\"{text}\""),
            "must be before 2262-04-11 (nanoseconds since 1970 must fit in 64 bits)",
        ));
    };
    if ns <= 0 {
        return Err(Error::invalid(
            "start_time",
            format!("\"{text}\""),
            "must be after 1970-01-01",
        ));
    }
    Ok(ns as u64)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::bridge::ModelSpec;

    fn error_of(edit: impl FnOnce(&mut Scenario)) -> String {
        let mut s = Scenario::default_scenario();
        edit(&mut s);
        match s.resolve() {
            Ok(_) => panic!("accepted"),
            Err(e) => e.to_string(),
        }
    }

    fn warnings_of(edit: impl FnOnce(&mut Scenario)) -> Vec<String> {
        let mut s = Scenario::default_scenario();
        edit(&mut s);
        s.resolve().unwrap().warnings()
    }

    #[test]
    fn the_default_scenario_has_no_warnings() {
        assert_eq!(warnings_of(|_| {}), Vec::<String>::new());
    }

    #[test]
    fn coarse_time_step_for_the_first_mode_is_a_warning() {
        let w = warnings_of(|s| {
            s.solver.dt_s = 0.02;
            s.sensors.retain(|x| x.kind == SensorKind::Displacement);
            s.sensors[0].rate_hz = 10.0;
            s.output.axle_load_rate_hz = 50.0;
            s.output.bridge_state_rate_hz = 10.0;
        });
        assert!(
            w.iter()
                .any(|m| m.starts_with("solver.dt_s = 0.02 gives 13.2 steps per period")),
            "{w:#?}"
        );
    }

    #[test]
    fn sensor_warnings_name_the_sensor() {
        let w = warnings_of(|s| s.sensors[2].rate_hz = 1000.0);
        assert_eq!(w.len(), 1, "{w:#?}");
        assert!(
            w[0].starts_with("sensors.2.rate_hz = 1000: the time step is coarse"),
            "{w:#?}"
        );
        let w = warnings_of(|s| s.sensors[4].rate_hz = 5.0);
        assert_eq!(w.len(), 1, "{w:#?}");
        assert!(
            w[0].starts_with("sensors.4.rate_hz = 5: the recorded band ends at 2 Hz"),
            "{w:#?}"
        );
    }

    #[test]
    fn vehicles_outside_the_run_and_other_oddities_are_warnings() {
        let w = warnings_of(|s| {
            s.duration_s = Some(2.0);
            s.vehicles[0].entry_time_s = 5.0;
        });
        assert_eq!(
            w,
            vec![
                "vehicles.0.entry_time_s = 5 is at or after the end of the run (2 s): \
                  the vehicle never appears"
                    .to_string()
            ]
        );
        let w = warnings_of(|s| s.duration_s = Some(0.5));
        assert!(
            w[0].starts_with(
                "vehicles.0.speed_m_s = 20: the vehicle reaches the bridge at t = 5.000 s"
            ),
            "{w:#?}"
        );
        let w = warnings_of(|s| s.bridge.damping_ratio = 0.5);
        assert!(w[0].starts_with("bridge.damping_ratio = 0.5"), "{w:#?}");
        let w = warnings_of(|s| s.bridge.model = ModelSpec::FiniteElement { elements: 1000 });
        assert!(w[0].starts_with("bridge.model.elements = 1000"), "{w:#?}");
    }

    #[test]
    fn implausible_bridges_blame_the_odd_field() {
        let msg = error_of(|s| s.bridge.flexural_rigidity_n_m2 = 5.629e100);
        assert!(
            msg.starts_with("bridge.flexural_rigidity_n_m2 = 5.629e100 gives a first natural frequency f1 = 3.78"),
            "{msg}"
        );
        let msg = error_of(|s| s.bridge.mass_per_length_kg_m = 1e300);
        assert!(
            msg.starts_with("bridge.mass_per_length_kg_m = 1e300 gives"),
            "{msg}"
        );
        let msg = error_of(|s| s.bridge.span_m = 1e-300);
        assert!(msg.starts_with("bridge.span_m = 1e-300 gives"), "{msg}");
        let msg = error_of(|s| s.bridge.span_m = 1e300);
        assert!(
            msg.starts_with("bridge.span_m = 1e300 must be at most 10000 m"),
            "{msg}"
        );
    }

    #[test]
    fn run_length_limits() {
        let msg = error_of(|s| {
            s.solver.dt_s = 1e-5;
            s.duration_s = Some(1e6);
        });
        assert!(
            msg.starts_with(
                "duration_s = 1000000 with solver.dt_s = 0.00001 needs 100000000000 solver steps"
            ),
            "{msg}"
        );
        let msg = error_of(|s| s.vehicles[0].speed_m_s = 1e-5);
        assert!(
            msg.starts_with("vehicles.0.speed_m_s = 0.00001 makes the default duration"),
            "{msg}"
        );
        let msg = error_of(|s| s.vehicles[0].entry_time_s = 1e300);
        assert!(
            msg.starts_with("vehicles.0.entry_time_s = 1e300 must be at most 30 days"),
            "{msg}"
        );
        let msg = error_of(|s| s.start_time = "9999-12-31T23:59:59Z".into());
        assert!(msg.contains("must be before 2262-04-11"), "{msg}");
    }

    #[test]
    fn sensor_channels_are_checked_before_the_run() {
        let msg = error_of(|s| s.sensors[0].rate_hz = 0.01);
        assert!(
            msg.starts_with("sensors.0.rate_hz = 0.01 is too far below the solver rate"),
            "{msg}"
        );
        let msg = error_of(|s| s.sensors[1].noise_density = Some(1e308));
        assert!(
            msg.starts_with(
                "sensors.1.noise_density = 1e308 gives a per-sample noise sigma of inf"
            ),
            "{msg}"
        );
    }
}
