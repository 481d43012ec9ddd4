//! Sensors and DAQ nodes: ids, positions and rates checked; each sensor's channel
//! design, chain (preset + overrides, its values drawn) and node clock built once.

use std::collections::BTreeSet;

use rand_chacha::ChaCha8Rng;

use super::resolved::{ResolvedMount, ResolvedSensor, ResolvedVehicle};
use super::{
    default_noise_density, unique_segment, Layout, Scenario, SensorKind, SensorSpec,
    DEFAULT_PREVIEW_RATE_HZ,
};
use crate::base::random::child_rng;
use crate::error::{item_path, num, require_non_negative, require_positive, Error, Result};
use crate::measurement::daq::{ClockError, NodeClock};
use crate::measurement::sensor::chain::{resolve, RealisedChain, ResolvedChain, TransducerKind};
use crate::measurement::sensor::{AntiAliasOptions, ChannelDesign};

/// How far a load cell may sit from its support (m): a survey's rounding.
const LOAD_CELL_TOLERANCE_M: f64 = 1e-3;

/// The stream of node `id`'s clock, shared by all its channels (the resync draws are the
/// node's, not a channel's).
fn node_stream(seed: u64, id: &str) -> ChaCha8Rng {
    child_rng(seed, &format!("daq/{id}/clock"))
}

/// The named streams of sensor `id`'s chain stages (`sensor/<id>/<stage>`): one per
/// stage, so switching a stage on or off never changes another's numbers.
pub fn sensor_streams(seed: u64, id: &str) -> impl FnMut(&str) -> ChaCha8Rng + '_ {
    move |name: &str| child_rng(seed, &format!("sensor/{id}/{name}"))
}

impl Scenario {
    pub(super) fn resolve_sensors(
        &self,
        dt_ns: u64,
        vehicles: &[ResolvedVehicle],
    ) -> Result<Vec<ResolvedSensor>> {
        let mut ids = BTreeSet::new();
        let solver_rate_hz = 1e9 / dt_ns as f64;
        let preview_rate_hz = self.preview_rate_hz()?;
        let mut out = Vec::new();
        for (i, s) in self.sensors.iter().enumerate() {
            let path = item_path("sensors", i, Some(&s.id));
            unique_segment(
                &mut ids,
                &format!("{path}.id"),
                &s.id,
                "is used twice (sensor ids must be unique)",
            )?;
            let (position_m, mount) = self.sensor_place(s, &path, vehicles)?;
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
                None => default_noise_density(s.kind),
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
            if let (true, Some(fibre)) = (s.kind != SensorKind::Strain, s.fibre) {
                return Err(Error::invalid(
                    format!("{path}.fibre"),
                    format!("{fibre:?}").to_lowercase(),
                    "applies to strain gauges only",
                ));
            }
            // Signed: negative above the neutral axis, so eps = M c / EI holds for both.
            let gauge_depth_m = match s.fibre {
                Some(super::Fibre::Top) => -gauge_depth_m,
                _ => gauge_depth_m,
            };
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
            // The channel design the run will use: checks what only the filter design
            // knows (a rate far below the solver rate needs a kernel too long to run).
            let anti_alias = AntiAliasOptions::default();
            let design = ChannelDesign::new(solver_rate_hz, s.rate_hz, &anti_alias, &path)?;
            let node = self.resolve_daq_node(s, &path, solver_rate_hz)?;
            let chain = resolve_chain(s, &path)?;
            if let Some(faults) = &s.faults {
                faults.validate(&format!("{path}.faults"))?;
            }
            let chain = match chain {
                Some(chain) => Some(self.realise_chain(&chain, s, &anti_alias)?),
                None => None,
            };
            let clock = match node {
                Some(index) => Some(self.node_clock(index, s.rate_hz)?),
                None => None,
            };
            // Whole sensor samples per preview sample: a preview at or above the sensor's
            // rate is the stream itself.
            let preview_factor = preview_rate_hz.map(|p| (s.rate_hz / p).round().max(1.0) as u64);
            out.push(ResolvedSensor {
                position_m,
                mount,
                preview_factor,
                rate: design.rate(),
                spec: s.clone(),
                noise_density,
                gauge_depth_m,
                node,
                chain,
                design,
                clock,
            });
        }
        Ok(out)
    }

    /// Where sensor `s` sits: a position on the girder, or a mount on a vehicle (an
    /// accelerometer only, with no position).
    fn sensor_place(
        &self,
        s: &SensorSpec,
        path: &str,
        vehicles: &[ResolvedVehicle],
    ) -> Result<(f64, Option<ResolvedMount>)> {
        match (&s.vehicle, s.position_m) {
            (Some(mount), None) => {
                if s.kind != SensorKind::Accelerometer {
                    return Err(Error::invalid(
                        format!("{path}.kind"),
                        format!("\"{}\"", s.kind.name()),
                        "cannot ride on a vehicle: only accelerometers do (the vehicle's \
                         DOFs and contact points are on /truth/vehicle_state)",
                    ));
                }
                Ok((0.0, Some(self.resolve_mount(mount, path, vehicles)?)))
            }
            (Some(_), Some(p)) => Err(Error::invalid(
                format!("{path}.position_m"),
                num(p),
                "is for a bridge sensor: a sensor on a vehicle moves with it (give one of \
                 position_m or vehicle)",
            )),
            (None, None) => Err(Error::invalid(
                format!("{path}.position_m"),
                "(missing)",
                "is required for a sensor on the bridge (or give vehicle = { id = .., axle = .. })",
            )),
            (None, Some(p)) => {
                if !(p.is_finite() && (0.0..=self.bridge.length_m()).contains(&p)) {
                    return Err(Error::invalid(
                        format!("{path}.position_m"),
                        num(p),
                        format!("must lie on the span [0, {}] m", self.bridge.length_m()),
                    ));
                }
                if s.kind == SensorKind::LoadCell {
                    self.check_on_support(&format!("{path}.position_m"), p)?;
                }
                Ok((p, None))
            }
        }
    }

    /// A load cell measures a support's reaction: `x_m` must be a support's position
    /// (to 1 mm).
    fn check_on_support(&self, field: &str, x_m: f64) -> Result<()> {
        let supports = self.bridge.girder().support_positions_m();
        if supports
            .iter()
            .any(|&s| (s - x_m).abs() <= LOAD_CELL_TOLERANCE_M)
        {
            return Ok(());
        }
        let list: Vec<String> = supports.iter().map(|&s| num(s)).collect();
        Err(Error::invalid(
            field,
            num(x_m),
            format!(
                "is not on a support: a load cell measures a support's reaction, so it \
                 must sit at one of the supports [{}] m",
                list.join(", ")
            ),
        ))
    }

    /// The preview rate in force (`output.preview_rate_hz`, its default for the layout),
    /// `None` for no preview.
    fn preview_rate_hz(&self) -> Result<Option<f64>> {
        let rate = match (self.output.preview_rate_hz, self.output.layout) {
            (Some(rate), _) => rate,
            (None, Layout::Block) => DEFAULT_PREVIEW_RATE_HZ,
            (None, Layout::Sample) => 0.0,
        };
        if !(rate.is_finite() && (0.0..=1e6).contains(&rate)) {
            return Err(Error::invalid(
                "output.preview_rate_hz",
                num(rate),
                "must be a finite rate in [0, 1e6] Hz (0: no preview)",
            ));
        }
        Ok((rate > 0.0).then_some(rate))
    }

    /// Node ids unique, clocks valid: each node's clock error (its resynchronisations).
    pub(super) fn resolve_daq_nodes(&self) -> Result<Vec<ClockError>> {
        let mut ids = BTreeSet::new();
        let mut clocks = Vec::new();
        for (i, node) in self.daq_nodes.iter().enumerate() {
            let path = item_path("daq_nodes", i, Some(&node.id));
            node.validate(&path)?;
            if !ids.insert(node.id.as_str()) {
                return Err(Error::invalid(
                    format!("{path}.id"),
                    format!("\"{}\"", node.id),
                    "is used twice (node ids must be unique)",
                ));
            }
            clocks.push(ClockError::new(
                &node.clock,
                node_stream(self.seed, &node.id),
                &format!("{path}.clock"),
            )?);
        }
        Ok(clocks)
    }

    /// The clock of node `index` sampling at `rate_hz` (validated for that rate).
    fn node_clock(&self, index: usize, rate_hz: f64) -> Result<NodeClock> {
        let node = &self.daq_nodes[index];
        NodeClock::new(
            &node.clock,
            rate_hz,
            node_stream(self.seed, &node.id),
            &format!("{}.clock", item_path("daq_nodes", index, Some(&node.id))),
        )
    }

    /// Draws sensor `s`'s chain values (gain error, bias, hum phase) from its own streams
    /// (`sensor/<id>/<stage>`), with the hum scaled by its anti-alias filter's gain.
    fn realise_chain(
        &self,
        chain: &ResolvedChain,
        s: &SensorSpec,
        anti_alias: &AntiAliasOptions,
    ) -> Result<RealisedChain> {
        let mut rng_for = sensor_streams(self.seed, &s.id);
        let rate_hz = s.rate_hz;
        chain.realise(rate_hz, &mut rng_for, &|f| {
            anti_alias.approximate_gain(rate_hz, f)
        })
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
        let node = &self.daq_nodes[index];
        let clock_path = format!("{}.clock", item_path("daq_nodes", index, Some(&node.id)));
        node.clock.validate_for_rate(&clock_path, s.rate_hz)?;
        Ok(Some(index))
    }
}

/// The sensor's measurement chain, when it has a preset or a chain table: the preset's
/// values, overridden by the chain table, then by `noise_density` if given.
fn resolve_chain(s: &SensorSpec, path: &str) -> Result<Option<ResolvedChain>> {
    if s.preset.is_none() && s.chain.is_none() {
        return Ok(None);
    }
    let kind = match s.kind {
        SensorKind::Accelerometer => TransducerKind::Accelerometer,
        SensorKind::Strain => TransducerKind::Strain,
        SensorKind::Displacement => TransducerKind::Displacement,
        SensorKind::Inclinometer => TransducerKind::Inclinometer,
        SensorKind::LoadCell => TransducerKind::LoadCell,
        SensorKind::Thermometer => TransducerKind::Thermometer,
    };
    let mut spec = s.chain.clone().unwrap_or_default();
    if let Some(d) = s.noise_density {
        spec.noise_density = Some(d);
    }
    let chain = resolve(s.preset.unwrap_or_default(), kind, &spec, path)?;
    chain.check_rate(s.rate_hz, &format!("{path}.rate_hz"))?;
    Ok(Some(chain))
}
