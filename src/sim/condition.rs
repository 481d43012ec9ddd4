//! Temperature and damage in the time loop.
//!
//! The condition (air and structure temperature, damage growth) is re-evaluated once per
//! simulated second: it drifts over minutes to hours, so a finer update would only cost
//! time. The bridge model is rebuilt (eigen-analysis, damping, one factorization) only
//! when a stiffness factor has moved by more than the rebuild threshold
//! ([`RebuildPolicy`]); between rebuilds the solver runs on a fixed, prefactored model,
//! so no step pays for a factorization. Every deflected shape on `/truth/bridge` carries
//! the temperatures; the next one after a rebuild, and one a minute, also carries the
//! modal state and the stiffness along the span. Riding on the shape messages keeps every
//! scalar of every `/truth/bridge` message meaningful, so plots of the midspan deflection
//! or the temperature have no false zeros.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;

use crate::base::random::child_rng;
use crate::error::Result;
use crate::measurement::sensor::chain::TemperatureFn;
use crate::physics::bridge::{BeamProperties, BridgeModel};
use crate::physics::environment::{
    AirTemperature, ConditionEvent, EnvironmentModel, EnvironmentSpec, RebuildPolicy,
    StiffnessState, DAY_S,
};
use crate::physics::solver::{CoupledSolver, SolveMode};
use crate::record::{EventLevel, ModalRecord, Record};
use crate::scenario::Resolved;

/// Simulated time between evaluations of the condition (s).
const UPDATE_INTERVAL_S: f64 = 1.0;
/// Simulated time between modal records on `/truth/bridge` between rebuilds (s).
const PUBLISH_INTERVAL_S: f64 = 60.0;
/// Modes whose frequencies and damping ratios are published.
const PUBLISHED_MODES: usize = 10;

/// The condition of a run at t = 0, built before the time loop (and before the output
/// file, so that a bad temperature file fails without leaving one).
#[derive(Debug, Clone)]
pub struct ConditionStart {
    /// The environment, already evaluated at t = 0.
    pub environment: EnvironmentModel,
    /// The condition at t = 0: the bridge model of the run is built for it.
    pub state: StiffnessState,
}

/// The condition at t = 0 of a scenario with `[environment]` or `[[damage]]`, `None`
/// without either (EI is then the scenario's for the whole run).
pub fn condition_start(resolved: &Resolved) -> Result<Option<ConditionStart>> {
    let s = &resolved.scenario;
    if s.environment.is_none() && s.damage.is_empty() && s.support_condition.is_empty() {
        return Ok(None);
    }
    let spec = s.environment.clone().unwrap_or_default();
    let time_of_day_s = (resolved.start_time_ns as f64 * 1e-9).rem_euclid(DAY_S);
    // Relative CSV paths were joined to the scenario's folder when it was loaded.
    let air = AirTemperature::new(
        &spec.temperature,
        time_of_day_s,
        std::path::Path::new(""),
        child_rng(s.seed, "environment/temperature"),
    )?;
    let mut environment = EnvironmentModel::new(
        &spec,
        &s.damage,
        &s.support_condition,
        &s.bridge.girder(),
        air,
    )?;
    let state = environment.state_at(0.0);
    Ok(Some(ConditionStart { environment, state }))
}

/// The air temperature the sensors' bias drift reads, shared with their chains: the
/// condition writes it once per update, the chains read it per sample.
#[derive(Debug, Clone)]
pub(super) struct SensorTemperature(Arc<AtomicU64>);

impl SensorTemperature {
    pub(super) fn new(value_c: f64) -> Self {
        Self(Arc::new(AtomicU64::new(value_c.to_bits())))
    }

    fn set(&self, value_c: f64) {
        self.0.store(value_c.to_bits(), Ordering::Relaxed);
    }

    /// The function the chains call (the time argument is not needed: the value is the
    /// current one, and the loop evaluates chains and condition in step order).
    pub(super) fn function(&self) -> TemperatureFn {
        let cell = Arc::clone(&self.0);
        Arc::new(move |_| f64::from_bits(cell.load(Ordering::Relaxed)))
    }
}

/// The running condition: evaluates the environment, rebuilds the model when needed and
/// makes the `/truth/bridge` condition records and the `/events` damage entries.
pub(super) struct Condition {
    environment: EnvironmentModel,
    policy: RebuildPolicy,
    /// The scenario's beam, before temperature and damage.
    base: BeamProperties,
    damping_ratio: f64,
    mode: SolveMode,
    /// The condition the running model was built for.
    built: StiffnessState,
    now: StiffnessState,
    update_stride: u64,
    publish_stride: u64,
    /// Damage onsets not yet announced, latest first.
    pending_events: Vec<ConditionEvent>,
    sensor_temperature: SensorTemperature,
    /// The modal record waiting for the next deflected shape.
    pending_modal: Option<Box<ModalRecord>>,
    pub(super) rebuilds: u64,
    /// The run has `[[support_condition]]`: the modal records carry the supports' state.
    with_supports: bool,
    /// The settlements of the last modal record (m).
    published_settlement_m: Vec<f64>,
}

impl Condition {
    pub(super) fn new(
        resolved: &Resolved,
        start: &ConditionStart,
        mode: SolveMode,
        sensor_temperature: SensorTemperature,
    ) -> Self {
        let s = &resolved.scenario;
        let steps_per_s = resolved.solver_rate_hz;
        let policy = s
            .environment
            .as_ref()
            .map(EnvironmentSpec::rebuild_policy)
            .unwrap_or_default();
        let mut pending_events = start.environment.events();
        pending_events.reverse();
        sensor_temperature.set(start.state.temperature_air_c);
        Self {
            environment: start.environment.clone(),
            policy,
            base: s.bridge.beam(),
            damping_ratio: s.bridge.damping_ratio,
            mode,
            built: start.state.clone(),
            now: start.state.clone(),
            update_stride: ((UPDATE_INTERVAL_S * steps_per_s).round() as u64).max(1),
            publish_stride: ((PUBLISH_INTERVAL_S * steps_per_s).round() as u64).max(1),
            pending_events,
            sensor_temperature,
            pending_modal: None,
            rebuilds: 0,
            with_supports: !s.support_condition.is_empty(),
            published_settlement_m: start.state.supports.settlement_m.clone(),
        }
    }

    /// The structure (deck) temperature now (degC).
    pub(super) fn structure_c(&self) -> f64 {
        self.now.temperature_structure_c
    }

    /// The supports' downward settlements now (m, girder order).
    pub(super) fn settlement_m(&self) -> &[f64] {
        &self.now.supports.settlement_m
    }

    /// The modal record of the model the run starts with, for the first shape.
    pub(super) fn announce_start(&mut self, model: &BridgeModel) {
        self.pending_modal = Some(Box::new(self.record(model)));
    }

    /// For a deflected shape now: the (structure, air) temperatures and the modal record
    /// when one is due.
    pub(super) fn for_shape(&mut self) -> ((f64, f64), Option<Box<ModalRecord>>) {
        let temperatures = (self.now.temperature_structure_c, self.now.temperature_air_c);
        (temperatures, self.pending_modal.take())
    }

    /// At `step` (time `t_ns`), announces the damage onsets that are due and, every
    /// update interval, evaluates the condition and rebuilds the model when it has moved.
    /// Returns true when the model was rebuilt: the caller then refreshes its point
    /// operators. Queues a modal record for the next shape when rebuilt or when one is due.
    pub(super) fn advance(
        &mut self,
        step: u64,
        t_ns: u64,
        solver: &mut CoupledSolver,
        out: &mut std::collections::VecDeque<Record>,
    ) -> Result<bool> {
        while self.pending_events.last().is_some_and(|e| e.t_ns <= t_ns) {
            if let Some(event) = self.pending_events.pop() {
                out.push_back(Record::Event {
                    t_ns,
                    level: EventLevel::Warning,
                    text: event.text,
                });
            }
        }
        if step == 0 || !step.is_multiple_of(self.update_stride) {
            return Ok(false);
        }
        self.environment.update(t_ns as f64 * 1e-9, &mut self.now);
        self.sensor_temperature.set(self.now.temperature_air_c);
        let rebuild = self.policy.needs_rebuild(&self.built, &self.now);
        if rebuild {
            let model = BridgeModel::build(
                &self.now.beam_at(&self.base),
                &solver.model.spec,
                self.damping_ratio,
            )?;
            solver.replace_model(model, self.mode)?;
            self.built.clone_from(&self.now);
            self.rebuilds += 1;
        }
        // A settlement needs no rebuild, but its progress is announced on the same rule.
        let settled = self.policy.moved(
            &self.published_settlement_m,
            &self.now.supports.settlement_m,
        );
        if rebuild || settled || step.is_multiple_of(self.publish_stride) {
            self.pending_modal = Some(Box::new(self.record(&solver.model)));
            self.published_settlement_m
                .clone_from(&self.now.supports.settlement_m);
        }
        Ok(rebuild)
    }

    /// The modal record of the running model.
    fn record(&self, model: &BridgeModel) -> ModalRecord {
        modal_record(model, &self.base, &self.now, self.with_supports)
    }
}

/// The model's modal state and EI over its nominal value at the midpoint of each interval
/// between the shape nodes (temperature and damage together).
/// With `with_supports` (a run with `[[support_condition]]`) the supports' state too.
fn modal_record(
    model: &BridgeModel,
    base: &BeamProperties,
    state: &StiffnessState,
    with_supports: bool,
) -> ModalRecord {
    let (natural_frequency_hz, damping_ratio) = model.modal_summary(PUBLISHED_MODES);
    let nodes = model.shape_positions_m();
    let stiffness_ratio = nodes
        .windows(2)
        .map(|w| {
            let x = 0.5 * (w[0] + w[1]);
            model.beam.ei_at_n_m2(x) / base.ei_at_n_m2(x)
        })
        .collect();
    let (support_stiffness_ratio, support_settlement_m) = match with_supports {
        true => (
            state
                .supports
                .stiffness_factor
                .iter()
                .map(|f| f.0)
                .collect(),
            state.supports.settlement_m.clone(),
        ),
        false => (Vec::new(), Vec::new()),
    };
    ModalRecord {
        natural_frequency_hz,
        damping_ratio,
        stiffness_ratio,
        damage_fraction: state.damage_fraction.clone(),
        support_stiffness_ratio,
        support_settlement_m,
    }
}
