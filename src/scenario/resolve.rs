//! Resolution: every field checked once, in a fixed order (errors name the field path:
//! `sensors.2.rate_hz = 5000 ...`), and the derived values computed.

use std::collections::BTreeSet;

use super::resolved::{Resolved, ResolvedVehicle};
use super::Scenario;
use crate::error::{
    is_segment, item_path, num, require_non_negative, require_positive, Error, Result,
};
use crate::measurement::wim::WimStation;
use crate::physics::bridge::{BeamProperties, ModelSpec};
use crate::physics::solver::NewmarkCoefficients;
use crate::physics::vehicle::VehicleModelSpec;

/// Longest run: 30 days (s).
pub const MAX_DURATION_S: f64 = 30.0 * 86_400.0;

/// Most solver steps in one run, 2^32 (30 days at dt = 1 ms are 2.6e9 steps).
pub const MAX_STEPS: u64 = 1 << 32;

/// Longest span (m): the longest bridge spans are about 2 km.
pub const MAX_SPAN_M: f64 = 10_000.0;

/// Longest approach or exit road (m).
pub const MAX_ROAD_M: f64 = 100_000.0;

/// Fastest vehicle (m/s, 360 km/h): beyond any road traffic.
pub const MAX_SPEED_M_S: f64 = 100.0;

/// Fastest train accepted (m/s): 540 km/h, above the 1.2 x line speed of any high-speed
/// line's dynamic check.
pub const MAX_TRAIN_SPEED_M_S: f64 = 150.0;

/// The first natural frequency a bridge may have (Hz, closed form of the uniform beam):
/// road bridges have 0.2-30 Hz, laboratory beams up to a few hundred. Outside this range
/// the input is a typo (an exponent off by orders of magnitude), not a bridge.
pub const F1_RANGE_HZ: (f64, f64) = (0.01, 10_000.0);

/// Checks that `id` (the value of `field`) is a topic segment not in `ids` yet, and adds
/// it; `twice` is the reason given for a repeated id.
pub(super) fn unique_segment(
    ids: &mut BTreeSet<String>,
    field: &str,
    id: &str,
    twice: &str,
) -> Result<()> {
    let reason = match () {
        _ if !is_segment(id) => "must be letters, digits, _ or -",
        _ if !ids.insert(id.to_string()) => twice,
        _ => return Ok(()),
    };
    Err(Error::invalid(field, format!("\"{id}\""), reason))
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
    /// The path of `[[vehicles]]` entry `i` in messages, with its id when the entry sets
    /// one (`vehicles.0[7]`).
    pub(super) fn vehicle_path(&self, i: usize) -> String {
        let id = self.vehicles[i].id.map(|id| id.to_string());
        item_path("vehicles", i, id.as_deref())
    }

    /// Checks every field and computes the derived values.
    pub fn resolve(&self) -> Result<Resolved> {
        self.check_spans()?;
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
        // The integrator steps by the whole-ns step; checked here against the scenario's
        // own value first, so that an error quotes what the user wrote.
        NewmarkCoefficients::new(dt_s, self.solver.newmark)?;
        let step_s = dt_ns as f64 * 1e-9;
        let newmark = NewmarkCoefficients::new(step_s, self.solver.newmark)?;
        self.road.profile.validate("road.profile")?;
        require_positive("road.approach_m", self.road.approach_m)?;
        if let Some(a) = self.road.sleeper_spacing_m {
            if !(0.3..=1.0).contains(&a) {
                return Err(Error::invalid(
                    "road.sleeper_spacing_m",
                    num(a),
                    "must be between 0.3 and 1.0 m (a railway track's sleepers)",
                ));
            }
        }
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
        let node_clocks = self.resolve_daq_nodes()?;
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
            ambient.validate("ambient", self.bridge.length_m(), dt_s)?;
        }
        let sensors = self.resolve_sensors(dt_ns, &vehicles)?;
        self.check_gnss(&vehicles, dt_ns)?;
        self.check_axle_detectors()?;
        let instrumented_vehicles: Vec<u32> = sensors
            .iter()
            .filter_map(|s| s.mount.as_ref().map(|m| m.vehicle_id))
            .chain(self.gnss.iter().map(|g| g.vehicle))
            .collect::<std::collections::BTreeSet<u32>>()
            .into_iter()
            .collect();
        let wim_stations = self.resolve_wim_stations()?;
        if self.output.block_samples == 0 || self.output.block_samples > 100_000 {
            return Err(Error::invalid(
                "output.block_samples",
                self.output.block_samples,
                "must be in 1..=100000",
            ));
        }
        let flush_every_s = self
            .output
            .flush_every_s
            .unwrap_or(super::DEFAULT_FLUSH_EVERY_S);
        if !(flush_every_s.is_finite() && (1e-3..=MAX_DURATION_S).contains(&flush_every_s)) {
            return Err(Error::invalid(
                "output.flush_every_s",
                num(flush_every_s),
                "must be between 0.001 s and 30 days of simulated time",
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
        let scene = self.resolve_scene(&vehicles)?;
        let trigger_windows = self.trigger_windows(&vehicles, dt_ns)?;
        Ok(Resolved {
            scenario: self.clone(),
            dt_ns,
            dt_s: step_s,
            solver_rate_hz: 1e9 / dt_ns as f64,
            newmark,
            steps,
            start_time_ns,
            vehicles,
            sensors,
            node_clocks,
            wim_stations,
            instrumented_vehicles,
            axle_stride,
            bridge_stride,
            flush_every_ns: (flush_every_s * 1e9).round() as u64,
            scene,
            trigger_windows,
            source_toml: String::new(),
            git_revision: crate::base::build_info::run_revision(),
        })
    }

    /// `output.trigger`: a window from `pre_s` before each listed vehicle's first axle
    /// enters the bridge to `post_s` after its last leaves, merged where they overlap.
    fn trigger_windows(
        &self,
        vehicles: &[ResolvedVehicle],
        dt_ns: u64,
    ) -> Result<Vec<crate::record::TriggerWindow>> {
        let Some(trigger) = &self.output.trigger else {
            return Ok(Vec::new());
        };
        for (field, value) in [("pre_s", trigger.pre_s), ("post_s", trigger.post_s)] {
            if !(0.0..=3600.0).contains(&value) {
                return Err(Error::invalid(
                    format!("output.trigger.{field}"),
                    num(value),
                    "must be between 0 and 3600 s",
                ));
            }
        }
        if self.traffic.is_some() {
            return Err(Error::invalid(
                "output.trigger",
                "{ .. }",
                "needs every vehicle listed: [traffic] vehicles arrive at random, so their \
                 passages are not known before the run",
            ));
        }
        let windows = vehicles
            .iter()
            .map(|v| {
                let entry_s = (v.entry_step * dt_ns) as f64 * 1e-9;
                let enters_s = entry_s + self.road.approach_m / v.speed_m_s;
                let leaves_s =
                    enters_s + (self.bridge.length_m() + v.dynamics.wheelbase_m()) / v.speed_m_s;
                crate::record::TriggerWindow {
                    start_ns: ((enters_s - trigger.pre_s).max(0.0) * 1e9).round() as u64,
                    end_ns: ((leaves_s + trigger.post_s) * 1e9).round() as u64,
                    label: format!("vehicle {} ({})", v.id, v.dynamics.name),
                }
            })
            .collect();
        Ok(crate::record::merged_windows(windows))
    }

    /// Station ids unique, models and limits valid, strips on the approach.
    fn resolve_wim_stations(&self) -> Result<Vec<WimStation>> {
        let mut wim_ids = BTreeSet::new();
        let mut stations = Vec::new();
        for (i, w) in self.wim_stations.iter().enumerate() {
            let path = item_path("wim_stations", i, Some(&w.id));
            unique_segment(&mut wim_ids, &format!("{path}.id"), &w.id, "is used twice")?;
            let station = WimStation::new(&w.model, &format!("{path}.model"))?
                .with_limits(w.limits, &format!("{path}.limits"))?;
            let p = w.position_m;
            if !(p.is_finite() && p > -self.road.approach_m && p < 0.0) {
                return Err(Error::invalid(
                    format!("{path}.position_m"),
                    num(p),
                    format!(
                        "must lie on the approach, in (-{}, 0) m",
                        self.road.approach_m
                    ),
                ));
            }
            stations.push(station);
        }
        Ok(stations)
    }

    /// One of `span_m` and `spans_m`, each span > 0 and within `MAX_SPAN_M`, named as the
    /// user wrote it.
    fn check_spans(&self) -> Result<()> {
        let b = &self.bridge;
        let (field, spans) = match (&b.span_m, &b.spans_m) {
            (Some(_), None) => ("bridge.span_m", b.spans()),
            (None, Some(spans)) => ("bridge.spans_m", spans.clone()),
            (Some(span), Some(_)) => {
                return Err(Error::invalid(
                    "bridge.span_m",
                    num(*span),
                    "give either span_m (one span) or spans_m (a continuous girder), not both",
                ))
            }
            (None, None) => {
                return Err(Error::invalid(
                    "bridge",
                    "(no span)",
                    "needs span_m (one span) or spans_m (a continuous girder)",
                ))
            }
        };
        for (i, &span) in spans.iter().enumerate() {
            let field = match &b.spans_m {
                Some(_) => format!("{field}.{i}"),
                None => field.to_string(),
            };
            require_positive(&field, span)?;
            if span > MAX_SPAN_M {
                return Err(Error::invalid(
                    field,
                    num(span),
                    format!("must be at most {MAX_SPAN_M} m (no bridge spans more)"),
                ));
            }
        }
        Ok(())
    }

    /// First natural frequency within `F1_RANGE_HZ`. Out of range, the error names the
    /// field that moves f1 furthest from the paper's bridge in that direction
    /// (f1 ~ sqrt(EI / m) / L^2).
    fn check_bridge_plausible(&self) -> Result<()> {
        let b = &self.bridge;
        let span_m = b.girder().longest_span_m();
        let f1 = b.beam().closed_form_frequency_hz(1);
        let (lo, hi) = F1_RANGE_HZ;
        if f1.is_finite() && (lo..=hi).contains(&f1) {
            return Ok(());
        }
        let paper = BeamProperties::paper_default();
        let shifts = [
            ("span_m", span_m, -2.0 * (span_m / paper.length_m()).ln()),
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
            let path = self.road.approach_m + self.bridge.length_m() + v.dynamics.wheelbase_m();
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
                    format!("{}.{field}", self.vehicle_path(i)),
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

    /// `[environment]`, `[[damage]]` and `[[support_condition]]`: each field, the regions
    /// on the span, the supports named, and a model
    /// that can be rebuilt for a local EI change.
    fn validate_condition(&self) -> Result<()> {
        if let Some(environment) = &self.environment {
            environment.validate("environment")?;
        }
        crate::physics::environment::validate_damage(&self.damage, self.bridge.length_m())?;
        crate::physics::environment::validate_support_conditions(
            &self.support_condition,
            &self.bridge.girder(),
        )?;
        if let (ModelSpec::Modal { .. }, Some(i)) = (
            &self.bridge.model,
            self.support_condition
                .iter()
                .position(|c| c.changes_stiffness()),
        ) {
            // As for damage: the support's stiffness shapes the modes.
            return Err(Error::invalid(
                "bridge.model",
                self.bridge.model.label(),
                format!(
                    "a modal model cannot follow support_condition.{i} (a support's \
                     stiffness changes the mode shapes): use kind = \"finite_element\" \
                     or \"lumped_mass\""
                ),
            ));
        }
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
            let path = self.vehicle_path(i);
            let dynamics = v.model.build(&format!("{path}.model"))?;
            require_positive(&format!("{path}.speed_m_s"), v.speed_m_s)?;
            let is_train = matches!(v.model, VehicleModelSpec::Train(_));
            let (max_speed, what) = match is_train {
                true => (MAX_TRAIN_SPEED_M_S, "for a train"),
                false => (MAX_SPEED_M_S, "for a road vehicle"),
            };
            if v.speed_m_s > max_speed {
                return Err(Error::invalid(
                    format!("{path}.speed_m_s"),
                    num(v.speed_m_s),
                    format!("must be at most {max_speed} m/s {what}"),
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
            // A train's rear cars may wait on the level track before the modelled
            // approach (the profile is held at its first value there).
            if !is_train && dynamics.wheelbase_m() >= self.road.approach_m {
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
