//! The resolved run description: a validated scenario with every derived value computed
//! once (exact rates, the time step in ns and s, the Newmark coefficients, each sensor's
//! channel design, its chain's drawn values and its node clock, the WIM stations), carried
//! to the time loop and never derived again.

use crate::base::rate::ExactRate;
use crate::error::{item_path, num};
use crate::measurement::daq::{ClockError, NodeClock};
use crate::measurement::sensor::chain::{RealisedChain, ResolvedChain};
use crate::measurement::sensor::ChannelDesign;
use crate::measurement::wim::WimStation;
use crate::physics::bridge::{Girder, ModelSpec};
use crate::physics::solver::NewmarkCoefficients;
use crate::physics::vehicle::VehicleDynamics;
use crate::record::{SceneInfo, TriggerWindow};

use super::{Scenario, SensorKind, SensorSpec};

/// `warnings`: fewest solver steps per period of the first bridge mode (Newmark's period
/// error is about (2 pi / N)^2 / 12, 0.8 % at N = 20).
pub const MIN_STEPS_PER_MODE_PERIOD: f64 = 20.0;

/// `warnings`: fewest solver steps per period at the edge of a sensor's band.
pub const MIN_STEPS_PER_SENSOR_PERIOD: f64 = 10.0;

/// `warnings`: lumped-mass models above this many masses take more than a few seconds to
/// build (the flexibility matrix and the condensation are dense, cost ~ n^3).
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

/// Where a sensor rides on a vehicle.
#[derive(Debug, Clone, PartialEq)]
pub struct ResolvedMount {
    pub vehicle_id: u32,
    /// The vehicle DOFs whose combination is the mount's vertical motion (upward
    /// positive): `[(dof, coefficient)]`.
    pub dofs: Vec<(usize, f64)>,
    /// "axle 1", "body, 1.5 m behind the front axle".
    pub label: String,
}

/// A sensor with its defaults filled in.
#[derive(Debug, Clone)]
pub struct ResolvedSensor {
    pub spec: SensorSpec,
    /// Position along the girder (m); 0 for a sensor on a vehicle.
    pub position_m: f64,
    /// The vehicle it rides on, if not the bridge.
    pub mount: Option<ResolvedMount>,
    pub noise_density: f64,
    /// Distance of a strain gauge from the neutral axis (m): positive below it (bottom
    /// fibre), negative above it (top fibre).
    pub gauge_depth_m: f64,
    /// Index into `scenario.daq_nodes` of the node whose clock samples this sensor.
    pub node: Option<usize>,
    /// The measurement chain when the sensor has a preset or chain table (its white noise
    /// then replaces the channel's plain `noise_density`), with this sensor's values drawn.
    pub chain: Option<RealisedChain>,
    /// The sample rate as an exact fraction.
    pub rate: ExactRate,
    /// The channel's rates and anti-alias kernel.
    pub design: ChannelDesign,
    /// The node clock that samples and stamps this sensor, before its first sample.
    pub clock: Option<NodeClock>,
    /// Sensor samples per preview sample, when the run writes a preview.
    pub preview_factor: Option<u64>,
}

impl ResolvedSensor {
    /// The chain as resolved from the preset and the overrides (before the draws).
    pub fn resolved_chain(&self) -> Option<&ResolvedChain> {
        self.chain.as_ref().map(RealisedChain::chain)
    }

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
            Some(c) => c.chain().preset().name(),
            None => "white_noise",
        }
    }
}

/// A validated scenario and its derived values.
#[derive(Debug, Clone)]
pub struct Resolved {
    pub scenario: Scenario,
    /// The solver time step (ns): time is `step * dt_ns`, never accumulated.
    pub dt_ns: u64,
    /// The same step in seconds, `dt_ns * 1e-9` (what the integrator uses).
    pub dt_s: f64,
    /// The solver rate `1 / dt`, Hz.
    pub solver_rate_hz: f64,
    /// Newmark coefficients for `dt_s` and the scenario's gamma and beta.
    pub newmark: NewmarkCoefficients,
    pub steps: u64,
    pub start_time_ns: u64,
    pub vehicles: Vec<ResolvedVehicle>,
    pub sensors: Vec<ResolvedSensor>,
    /// Each DAQ node's clock error (resynchronisations), scenario order.
    pub node_clocks: Vec<ClockError>,
    /// The weigh-in-motion stations, scenario order.
    pub wim_stations: Vec<WimStation>,
    /// Ids of the vehicles carrying a sensor or a GNSS receiver, ascending: their DOFs and
    /// contact points go to `/truth/vehicle_state/<id>`.
    pub instrumented_vehicles: Vec<u32>,
    /// Solver steps between `/truth/axle_loads` messages.
    pub axle_stride: u64,
    /// Solver steps between deflected shapes on `/truth/bridge`.
    pub bridge_stride: u64,
    /// Simulated time between the output's chunk flushes (ns).
    pub flush_every_ns: u64,
    /// The 3D scene on `/scene`, `None` when `output.scene_rate_hz` is 0.
    pub scene: Option<SceneInfo>,
    /// `output.trigger`'s windows, merged; empty: everything is written.
    pub trigger_windows: Vec<TriggerWindow>,
    /// The scenario as the user wrote it (stored in the output); empty for a scenario
    /// built in code. Set by the caller that read the file.
    pub source_toml: String,
    /// The source revision written into the output's `bridgetwin` metadata: the build's,
    /// or the one given at run time (see `base::build_info::REVISION_OVERRIDE_VAR`).
    pub git_revision: String,
}

impl Resolved {
    /// Duration of the run (s).
    pub fn duration_s(&self) -> f64 {
        self.steps as f64 * self.dt_s
    }

    /// Run-relative time of solver step `step` (ns).
    pub fn t_ns(&self, step: u64) -> u64 {
        step * self.dt_ns
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
        let dt_s = self.dt_s;
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
        let solver_rate_hz = self.solver_rate_hz;
        for (i, r) in self.sensors.iter().enumerate() {
            let rate = r.spec.rate_hz;
            // Equal rates pass through unfiltered (up to Nyquist); otherwise the
            // anti-alias pass band ends at 0.4 rate.
            let pass_through = rate >= solver_rate_hz * (1.0 - 1e-12);
            let band_edge_hz = if pass_through { 0.5 * rate } else { 0.4 * rate };
            let steps = solver_rate_hz / band_edge_hz;
            if steps < MIN_STEPS_PER_SENSOR_PERIOD {
                out.push(format!(
                    "{}.rate_hz = {}: the time step is coarse for this rate: the \
                     recorded band reaches {} Hz, which solver.dt_s = {} samples only \
                     {steps:.1} times per period (time-discretization error dominates \
                     there); use dt_s <= {:.3e}",
                    sensor_path(i, r),
                    num(rate),
                    num(band_edge_hz),
                    num(dt_s),
                    1.0 / (MIN_STEPS_PER_SENSOR_PERIOD * band_edge_hz),
                ));
            }
            if let Some(warning) = on_a_support(i, r, &s.bridge.girder()) {
                out.push(warning);
            }
            // A thermometer records a quantity that drifts over hours, not the vibration.
            if band_edge_hz < f1 && r.spec.kind != SensorKind::Thermometer {
                out.push(format!(
                    "{}.rate_hz = {}: the recorded band ends at {} Hz, below the \
                     first bridge mode f1 = {f1:.3} Hz",
                    sensor_path(i, r),
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
                    "{}.entry_time_s = {} is at or after the end of the run \
                     ({duration_s} s): the vehicle never appears",
                    s.vehicle_path(i),
                    num(entry.entry_time_s),
                ));
            } else if arrives_s >= duration_s {
                out.push(format!(
                    "{}.speed_m_s = {}: the vehicle reaches the bridge at t = \
                     {arrives_s:.3} s (entry_time_s = {}, road.approach_m = {}), after the \
                     end of the run ({duration_s} s)",
                    s.vehicle_path(i),
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
        if let ModelSpec::LumpedMass { nodes, .. } = s.bridge.model {
            if nodes > SLOW_SETUP_NODES {
                out.push(format!(
                    "bridge.model.nodes = {nodes}: building a lumped-mass model is dense (cost \
                     ~ n^3: about 5 s for 1000 masses on a 2-core machine); a finite-element \
                     model of the same size builds in milliseconds"
                ));
            }
        }
        out
    }
}

/// The path of sensor `i` in messages: `sensors.2[A1]`.
fn sensor_path(i: usize, sensor: &ResolvedSensor) -> String {
    item_path("sensors", i, Some(&sensor.spec.id))
}

/// A sensor within this distance of a support reads (nearly) nothing: the deflection,
/// the acceleration and, on a simply supported span, the bending strain vanish there.
const ON_SUPPORT_M: f64 = 1e-3;

/// The warning for sensor `i` placed on a rigid support, where the girder does not move
/// (every mode shape is zero) and, at a pinned end, bends nothing either. A strain gauge
/// over an interior or clamped support reads the hogging moment: no warning for it there.
fn on_a_support(i: usize, sensor: &ResolvedSensor, girder: &Girder) -> Option<String> {
    if sensor.mount.is_some() {
        return None;
    }
    let x = sensor.position_m;
    let supports = girder.support_positions_m();
    let last = supports.len() - 1;
    let (k, support_m) = supports
        .iter()
        .copied()
        .enumerate()
        .filter(|(k, _)| girder.supports[*k].rigid_vertical())
        .min_by(|a, b| (a.1 - x).abs().total_cmp(&(b.1 - x).abs()))?;
    // A load cell belongs there; an inclinometer reads the support's rotation unless the
    // support is clamped.
    match sensor.spec.kind {
        SensorKind::LoadCell | SensorKind::Thermometer => return None,
        SensorKind::Inclinometer if !girder.supports[k].rigid_rotation() => return None,
        _ => {}
    }
    let free_end =
        (k == 0 && girder.overhang_left_m == 0.0) || (k == last && girder.overhang_right_m == 0.0);
    let bends = !free_end || girder.supports[k].rigid_rotation();
    if (x - support_m).abs() > ON_SUPPORT_M || (bends && sensor.spec.kind == SensorKind::Strain) {
        return None;
    }
    let reads = if bends {
        "where the girder does not move: the channel will read zero and noise"
    } else {
        "where the bridge does not move and bends nothing: the channel will read zero and \
         noise"
    };
    Some(format!(
        "{}.position_m = {}: on the support at x = {} m, {reads}",
        sensor_path(i, sensor),
        num(x),
        num(support_m),
    ))
}
