//! Generated traffic entering the run: each vehicle the generator releases becomes a
//! coupled vehicle (its class preset scaled to the drawn weight, spacings and load
//! shares) on its own approach, one step before it appears. Vehicles that have left are
//! dropped by the tracker, so a day of traffic holds only the vehicles on the road.

use std::collections::VecDeque;

use super::tracking::Tracker;
use crate::error::Result;
use crate::physics::solver::{CoupledSolver, CoupledVehicle};
use crate::physics::traffic::{variation_factors, GeneratedVehicle, TrafficGenerator, TrafficRun};
use crate::physics::vehicle::{vehicle_for_traffic, VehicleDynamics};
use crate::record::{EventLevel, Record};
use crate::scenario::Resolved;

/// Longest wheelbase the traffic classes reach (m): the road is synthesized this far
/// beyond its ends so every axle of every vehicle has a surface under it.
pub const MAX_WHEELBASE_M: f64 = 20.0;

/// The traffic of a run (nothing without `[traffic]`).
pub struct Arrivals {
    generator: Option<TrafficGenerator>,
    /// `traffic.parameter_sd_rel`: the spread of each vehicle's springs and dampers.
    parameter_sd_rel: f64,
    dt_ns: u64,
    dt_s: f64,
    approach_m: f64,
    span_m: f64,
}

impl Arrivals {
    pub fn new(resolved: &Resolved) -> Result<Self> {
        let s = &resolved.scenario;
        let parameter_sd_rel = s.traffic.as_ref().map_or(0.0, |t| t.parameter_sd_rel);
        Ok(Arrivals {
            generator: generator(resolved)?,
            parameter_sd_rel,
            dt_ns: resolved.dt_ns,
            dt_s: resolved.dt_s,
            approach_m: s.road.approach_m,
            span_m: s.bridge.length_m(),
        })
    }

    /// Adds every vehicle entering by the end of step `step + 1` to the solver and the
    /// tracker (it activates in the coming step).
    pub fn admit(
        &mut self,
        step: u64,
        solver: &mut CoupledSolver,
        tracker: &mut Tracker,
        events: &mut VecDeque<Record>,
    ) {
        let Some(generator) = self.generator.as_mut() else {
            return;
        };
        let next = step + 1;
        while let Some(g) = generator.next_before(next as f64 * self.dt_s) {
            let (dynamics, note) = dynamics_of(&g, self.parameter_sd_rel);
            if let Some(text) = note {
                events.push_back(Record::Event {
                    t_ns: step * self.dt_ns,
                    level: EventLevel::Warning,
                    text,
                });
            }
            let start_m = match g.direction > 0 {
                true => -self.approach_m,
                false => self.span_m + self.approach_m,
            };
            let entry_step = ((g.entry_time_s / self.dt_s).round() as u64).max(next);
            let axles = dynamics.axles.len();
            solver.add_vehicle(
                CoupledVehicle::new(g.id, dynamics, g.speed_m_s, start_m, entry_step)
                    .with_direction(g.direction),
            );
            tracker.add_vehicle(g.lane as u32, g.speed_m_s, axles);
        }
    }
}

/// The traffic generator of a run (`None` without `[traffic]`): the run draws its
/// vehicles from it, and so does the forecast of what the run will write.
pub(super) fn generator(resolved: &Resolved) -> Result<Option<TrafficGenerator>> {
    let s = &resolved.scenario;
    let Some(spec) = &s.traffic else {
        return Ok(None);
    };
    let run = TrafficRun {
        seed: s.seed,
        road_length_m: s.road.approach_m + s.bridge.length_m() + s.road.exit_m,
        time_of_day_at_zero_s: (resolved.start_time_ns / 1_000_000_000 % 86_400) as f64,
        first_id: resolved.vehicles.iter().map(|v| v.id).max().unwrap_or(0) + 1,
    };
    Ok(Some(TrafficGenerator::new(spec, &run, "traffic")?))
}

/// The vehicle's dynamics: its class preset scaled to the draw. A draw the preset cannot
/// carry on straight springs (rare extreme load shares) runs as moving forces with the
/// drawn loads, and says so on `/events`.
/// Springs and dampers vary from vehicle to vehicle by `parameter_sd_rel`
/// ([`VehicleDynamics::varied`]).
pub(super) fn dynamics_of(
    g: &GeneratedVehicle,
    parameter_sd_rel: f64,
) -> (VehicleDynamics, Option<String>) {
    let shares: Vec<f64> = g.axle_load_n.iter().map(|l| l / g.gross_weight_n).collect();
    let prefix = format!("traffic.vehicle.{}", g.id);
    match vehicle_for_traffic(
        g.class.name(),
        g.gross_weight_n,
        &g.axle_spacing_m,
        &shares,
        &prefix,
    ) {
        Ok(d) => {
            let factors = variation_factors(g.variation_seed, 2, parameter_sd_rel);
            (d.varied(factors[0], factors[1]), None)
        }
        Err(e) => {
            let mut offsets = vec![0.0];
            for s in &g.axle_spacing_m {
                offsets.push(offsets.last().copied().unwrap_or(0.0) + s);
            }
            let mut d = VehicleDynamics::moving_forces(&g.axle_load_n, &offsets);
            d.name = format!("moving_force/{}", g.class.name());
            let text = format!("vehicle {} runs as moving forces: {e}", g.id);
            (d, Some(text))
        }
    }
}
