//! The one time loop: advances the coupled system, feeds the sensor taps, tracks vehicles
//! (bridge entry and exit, WIM strips, contact loss) and hands time-ordered records to a
//! `Recorder`. Sensor samples come out of their filters late (a fixed latency), so every
//! record waits in a small merge buffer until no earlier record can still appear: memory
//! is bounded by that latency, not by the run length.

mod condition;
mod daq;
mod forecast;
mod instruments;
mod manifest;
mod preview;
mod probes;
mod tap;
mod tracking;
mod traffic;

use std::collections::VecDeque;
use std::sync::atomic::{AtomicBool, Ordering};

use crate::base::random::child_rng;
use crate::error::Result;
use crate::physics::bridge::{BridgeModel, ModelSpec};
use crate::physics::excitation::{AmbientField, AMBIENT_STREAM};
use crate::physics::road::RoadProfile;
use crate::physics::solver::{
    check_state, divergence_hint, CoupledSolver, CoupledVehicle, SolveMode, Storage,
};
use crate::scenario::Resolved;

pub use crate::record::Quantities;
pub use crate::record::{
    AxleState, EventLevel, ModalRecord, Record, Recorder, VecRecorder, VehicleRecord, WimRecordData,
};
pub use condition::{condition_start, ConditionStart};
use condition::{Condition, SensorTemperature};
pub use forecast::{forecast, MAX_DRAWN_VEHICLES};
pub use manifest::manifest;
use probes::Probes;
pub use tap::SensorTap;

/// How the last event of a run that a stop request (Ctrl-C, SIGTERM, a sweep's stop) ended
/// before its scenario's end begins; readers (`inspect`) find a stopped run's file by it.
pub const STOP_EVENT_PREFIX: &str = "run stopped on request at t = ";
use tracking::Tracker;

/// Headline results of a run.
#[derive(Debug, Clone)]
pub struct RunSummary {
    pub steps: u64,
    pub duration_s: f64,
    pub natural_frequencies_hz: Vec<f64>,
    pub damping_ratios: Vec<f64>,
    /// (vehicle id, axle index, max force on the bridge / static, sigma / static).
    pub dlc: Vec<(u32, u32, f64, f64)>,
    pub contact_loss_steps: u64,
    pub road_description: String,
    /// Simulated time at which a stop request ended the run early (s).
    pub stopped_at_s: Option<f64>,
    /// Largest midspan deflection, either sign, at the solver rate (m).
    pub peak_midspan_deflection_m: f64,
    /// Times the bridge model was rebuilt for temperature or damage.
    pub model_rebuilds: u64,
    /// Natural frequencies of the model at the end of the run (Hz), lowest first.
    pub final_frequencies_hz: Vec<f64>,
}

/// Where a run is, for a progress display.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RunProgress {
    pub step: u64,
    pub steps: u64,
    /// Simulated time reached (s).
    pub time_s: f64,
    /// Vehicles admitted and not yet dropped (on the approach, the bridge or the exit).
    pub vehicles_on_road: usize,
    /// Vehicles that have crossed and been dropped.
    pub vehicles_passed: u64,
    /// Bridge model rebuilds for temperature or damage so far.
    pub model_rebuilds: u64,
}

/// How the caller follows and steers a run.
pub struct Control<'a> {
    /// Called every few thousand steps, and once at the end.
    pub progress: &'a mut dyn FnMut(&RunProgress),
    /// Checked every step: when set, the run stops, writes what it has (an `/events`
    /// entry says where) and returns normally with `stopped_at_s`.
    pub stop: Option<&'a AtomicBool>,
}

/// Everything built before the time loop.
pub struct Prepared {
    /// The bridge at t = 0 (in its condition then, with `[environment]` or `[[damage]]`).
    pub model: BridgeModel,
    pub road: RoadProfile,
    /// Temperature and damage: `None` when the scenario has neither.
    pub condition: Option<ConditionStart>,
}

/// Builds the bridge model and the road of a resolved scenario.
pub fn prepare(resolved: &Resolved) -> Result<Prepared> {
    let s = &resolved.scenario;
    let condition = condition_start(resolved)?;
    let beam = match &condition {
        Some(c) => c.state.beam_at(&s.bridge.beam()),
        None => s.bridge.beam(),
    };
    let model = BridgeModel::build(&beam, &s.bridge.model, s.bridge.damping_ratio)?;
    let wheelbase = resolved
        .vehicles
        .iter()
        .map(|v| v.dynamics.wheelbase_m())
        .fold(
            traffic::MAX_WHEELBASE_M * f64::from(s.traffic.is_some()),
            f64::max,
        );
    // The road under every axle: the left approach, the bridge and the exit towards +x;
    // for vehicles towards -x the right side holds their approach.
    let reverse = resolved.vehicles.iter().any(|v| v.direction < 0)
        || s.traffic
            .as_ref()
            .is_some_and(|t| t.lanes.iter().any(|l| l.direction < 0));
    let (left_m, right_m) = match reverse {
        true => {
            let side = s.road.exit_m.max(s.road.approach_m);
            (side, side)
        }
        false => (s.road.approach_m, s.road.exit_m),
    };
    let x_start = -(left_m + wheelbase + 5.0);
    let x_end = s.bridge.length_m() + right_m + wheelbase + 5.0;
    let mut rng = child_rng(s.seed, "road");
    let road = RoadProfile::build(&s.road.profile, x_start, x_end, &mut rng)?;
    Ok(Prepared {
        model,
        road,
        condition,
    })
}

fn solve_mode(spec: &ModelSpec) -> SolveMode {
    match spec {
        // Banded: sparse Cholesky keeps the band, O(n) per solve.
        ModelSpec::FiniteElement { .. } => SolveMode::Prefactored(Storage::Sparse),
        _ => SolveMode::Prefactored(Storage::Dense),
    }
}

/// Runs the scenario: hands `recorder` the run's manifest, then every record in
/// non-decreasing time, then calls its `finish`.
/// `progress(step, steps)` is called every few thousand steps.
pub fn run(
    resolved: &Resolved,
    prepared: &Prepared,
    recorder: &mut dyn Recorder,
    progress: &mut dyn FnMut(u64, u64),
) -> Result<RunSummary> {
    let mut report = |p: &RunProgress| progress(p.step, p.steps);
    let mut control = Control {
        progress: &mut report,
        stop: None,
    };
    run_controlled(resolved, prepared, recorder, &mut control)
}

/// [`run`] with a stop flag (set by a signal handler, a GUI, a time limit).
pub fn run_controlled(
    resolved: &Resolved,
    prepared: &Prepared,
    recorder: &mut dyn Recorder,
    control: &mut Control,
) -> Result<RunSummary> {
    let mut gate;
    let recorder: &mut dyn Recorder = if resolved.trigger_windows.is_empty() {
        recorder
    } else {
        gate = crate::record::Triggered::new(recorder, &resolved.trigger_windows);
        &mut gate
    };
    recorder.begin(&manifest(resolved, prepared)?)?;
    let s = &resolved.scenario;
    let model = &prepared.model;
    let dt_s = resolved.dt_s;
    let mut solver = CoupledSolver::new(
        model,
        &prepared.road,
        resolved.newmark,
        solve_mode(&s.bridge.model),
        s.solver.contact,
    )?;
    solver.sleeper_spacing_m = s.road.sleeper_spacing_m;
    solver.retire_after_m = s.road.exit_m;
    for v in &resolved.vehicles {
        // Each direction has its own approach: the left one towards +x, the right one
        // towards -x.
        let start_m = match v.direction > 0 {
            true => -s.road.approach_m,
            false => s.bridge.length_m() + s.road.approach_m,
        };
        solver.add_vehicle(
            CoupledVehicle::new(v.id, v.dynamics.clone(), v.speed_m_s, start_m, v.entry_step)
                .with_direction(v.direction),
        );
    }
    let sensor_temperature = SensorTemperature::new(crate::physics::environment::DEFAULT_AIR_C);
    let mut condition = prepared.condition.as_ref().map(|start| {
        Condition::new(
            resolved,
            start,
            solve_mode(&s.bridge.model),
            sensor_temperature.clone(),
        )
    });
    if let Some(c) = condition.as_mut() {
        c.announce_start(model);
    }
    let mut taps = Vec::new();
    let mut probes = Probes::new(model, resolved)?;
    if let Some(c) = condition.as_ref() {
        probes.settle(model, resolved, c.settlement_m())?;
        probes.set_temperature(c.structure_c());
    }
    for (i, sensor) in resolved.sensors.iter().enumerate() {
        let (channel, clipped) =
            daq::sensor_channel(resolved, sensor, i, sensor_temperature.function())?;
        taps.push(
            SensorTap::new(
                i,
                channel,
                sensor.spec.kind,
                daq::fault_injector(resolved, sensor, i)?,
            )
            .with_clip_counter(clipped)
            .with_preview(match sensor.preview_factor {
                Some(factor) => Some(preview::Preview::new(i, factor)?),
                None => None,
            }),
        );
    }
    let max_latency_ns = taps.iter().map(|t| t.latency_ns()).max().unwrap_or(0) + resolved.dt_ns;
    let mut merger = Merger {
        truth: VecDeque::new(),
    };
    merger.truth.push_back(Record::Event {
        t_ns: 0,
        level: EventLevel::Info,
        text: start_text(resolved, model),
    });
    let mut tracker = Tracker::new(resolved, model.length_m())?;
    let mut instruments = instruments::Instruments::new(resolved);
    let hint = divergence_hint(&resolved.newmark);
    let mut peak_midspan_m = 0.0f64;
    let mut resyncs = daq::Resyncs::new(resolved);
    let mut ambient = match &s.ambient {
        Some(spec) => Some(AmbientField::new(
            spec,
            model,
            dt_s,
            child_rng(s.seed, AMBIENT_STREAM),
            "ambient",
        )?),
        None => None,
    };

    let mut traffic = traffic::Arrivals::new(resolved)?;

    let mut stopped_at = None;
    for step in 0..=resolved.steps {
        if step > 0 {
            if control
                .stop
                .is_some_and(|flag| flag.load(Ordering::Relaxed))
            {
                stopped_at = Some(step - 1);
                break;
            }
            if let Some(field) = ambient.as_mut() {
                field.fill(&mut solver.external_load);
            }
            traffic.admit(step, &mut solver, &mut tracker, &mut merger.truth);
            solver.advance()?;
        }
        let t_ns = step * resolved.dt_ns;
        if let Some(c) = condition.as_mut() {
            if c.advance(step, t_ns, &mut solver, &mut merger.truth)? {
                // EI changed: the moment, strain and reaction operators (and, for lumped
                // masses, the interpolated deflections) belong to the new model.
                probes.rebuild(&solver.model, resolved)?;
            }
            probes.settle(&solver.model, resolved, c.settlement_m())?;
            probes.set_temperature(c.structure_c());
        }
        resyncs.announce_until(t_ns, &mut merger.truth);
        check_state(&solver, &probes.shape, &hint)?;
        peak_midspan_m = peak_midspan_m.max(probes.midspan.dot(&solver.bridge.state.u).abs());
        let shape_due = step % resolved.bridge_stride == 0;
        probes.update_loads(&solver, shape_due);
        for (i, tap) in taps.iter_mut().enumerate() {
            tap.push(&probes.quantities(i, &solver));
        }
        if step % resolved.axle_stride == 0 {
            merger.truth.push_back(Record::AxleLoads {
                t_ns,
                axles: tracker.axle_states(&solver, step),
            });
        }
        if shape_due {
            let deflection_m = probes.deflected_shape(&solver);
            let (temperatures_c, modal) = match condition.as_mut() {
                Some(c) => {
                    let (temperatures, modal) = c.for_shape();
                    (Some(temperatures), modal)
                }
                None => (None, None),
            };
            merger.truth.push_back(Record::BridgeShape {
                t_ns,
                deflection_m,
                temperatures_c,
                modal,
                support_reaction_n: probes.reaction_n.clone(),
            });
        }
        if instruments.any() {
            let state_due = step % resolved.axle_stride == 0;
            instruments.observe(&solver, &prepared.road, step, state_due, &mut merger.truth);
        }
        tracker.observe(&solver, step, &mut merger.truth);
        tracker.drop_departed(&mut solver);
        merger.release(&mut taps, t_ns.saturating_sub(max_latency_ns), recorder)?;
        if step % 5000 == 0 {
            let rebuilds = condition.as_ref().map_or(0, |c| c.rebuilds);
            (control.progress)(&run_progress(step, resolved, &solver, &tracker, rebuilds));
        }
    }
    for tap in &mut taps {
        tap.flush();
    }
    tracker.finish(&solver, &mut merger.truth);
    let end_ns = stopped_at.unwrap_or(resolved.steps) * resolved.dt_ns;
    for (tap, sensor) in taps.iter().zip(&resolved.sensors) {
        for text in tap.end_notes(&sensor.spec.id) {
            merger.truth.push_back(Record::Event {
                t_ns: end_ns,
                level: EventLevel::Warning,
                text,
            });
        }
    }
    if let Some(step) = stopped_at {
        merger.truth.push_back(Record::Event {
            t_ns: step * resolved.dt_ns,
            level: EventLevel::Warning,
            text: format!(
                "{STOP_EVENT_PREFIX}{:.3} s (step {step} of {}): the data ends here",
                step as f64 * dt_s,
                resolved.steps
            ),
        });
    }
    merger.release(&mut taps, u64::MAX, recorder)?;
    recorder.finish()?;
    let steps_done = stopped_at.unwrap_or(resolved.steps);
    let rebuilds = condition.as_ref().map_or(0, |c| c.rebuilds);
    (control.progress)(&run_progress(
        steps_done, resolved, &solver, &tracker, rebuilds,
    ));

    let (natural_frequencies_hz, damping_ratios) = model.modal_summary(10);
    Ok(RunSummary {
        steps: steps_done,
        duration_s: steps_done as f64 * dt_s,
        natural_frequencies_hz,
        damping_ratios,
        dlc: tracker.dlc_ratios(&solver),
        contact_loss_steps: tracker.contact_loss_steps(&solver),
        road_description: prepared.road.describe().to_string(),
        stopped_at_s: stopped_at.map(|step| step as f64 * dt_s),
        peak_midspan_deflection_m: peak_midspan_m,
        model_rebuilds: condition.map_or(0, |c| c.rebuilds),
        final_frequencies_hz: solver.model.modal_summary(10).0,
    })
}

/// The first line of `/events`: what the run holds, so that a viewer opened at the start
/// shows it.
fn start_text(resolved: &Resolved, model: &BridgeModel) -> String {
    let s = &resolved.scenario;
    let plural = |n: usize, one: &str, many: &str| match n {
        1 => format!("1 {one}"),
        n => format!("{n} {many}"),
    };
    let traffic = match &s.traffic {
        Some(t) => format!(
            ", random traffic on {}",
            plural(t.lanes.len(), "lane", "lanes")
        ),
        None => String::new(),
    };
    let scene = match &resolved.scene {
        Some(scene) => format!("; 3D scene deflections drawn x{}", scene.exaggeration),
        None => String::new(),
    };
    format!(
        "run starts: {} s simulated; bridge {}, span {} m, f1 = {:.3} Hz; {}, {}; {} listed{traffic}{scene}",
        resolved.duration_s(),
        s.bridge.model.label(),
        s.bridge.length_m(),
        model.frequency_hz(1),
        plural(s.sensors.len(), "sensor", "sensors"),
        plural(s.wim_stations.len(), "WIM station", "WIM stations"),
        plural(resolved.vehicles.len(), "vehicle", "vehicles"),
    )
}

fn run_progress(
    step: u64,
    resolved: &Resolved,
    solver: &CoupledSolver,
    tracker: &Tracker,
    model_rebuilds: u64,
) -> RunProgress {
    RunProgress {
        step,
        steps: resolved.steps,
        time_s: (step * resolved.dt_ns) as f64 * 1e-9,
        vehicles_on_road: solver.vehicles.len(),
        vehicles_passed: tracker.departed(),
        model_rebuilds,
    }
}

/// Merges the sensor streams (each late by its filter latency) with the truth stream.
struct Merger {
    truth: VecDeque<Record>,
}

impl Merger {
    /// Writes every record with time <= `watermark_ns`, in time order (ties: truth first,
    /// then sensors in scenario order).
    fn release(
        &mut self,
        taps: &mut [SensorTap],
        watermark_ns: u64,
        recorder: &mut dyn Recorder,
    ) -> Result<()> {
        loop {
            let mut best: Option<(u64, usize)> = self.truth.front().map(|r| (r.t_ns(), 0));
            for (i, tap) in taps.iter().enumerate() {
                if let Some(t) = tap.next_time_ns() {
                    if best.is_none_or(|(bt, _)| t < bt) {
                        best = Some((t, i + 1));
                    }
                }
            }
            let Some((t, source)) = best else {
                return Ok(());
            };
            if t > watermark_ns {
                return Ok(());
            }
            let record = if source == 0 {
                self.truth.pop_front()
            } else {
                taps[source - 1].pop()
            };
            if let Some(r) = record {
                recorder.record(r)?;
            }
        }
    }
}
