//! What the time loop records of the vehicles beyond their axle loads: the fixes of GNSS
//! receivers riding on them, the axles road detectors time, and the state of each
//! instrumented vehicle (its DOFs and where its wheels touch the road) that drive-by
//! monitoring is scored against. Built once; reading allocates only the records.

use std::collections::VecDeque;

use crate::base::random::child_rng;
use crate::measurement::vehicle::{DetectorTiming, GnssError};
use crate::physics::bridge::{PointQuantity, SparseVec};
use crate::physics::road::RoadProfile;
use crate::physics::solver::{CoupledSolver, CoupledVehicle};
use crate::record::{AxleHit, ContactPoint, GnssFix, Record, VehicleStateRecord};
use crate::scenario::Resolved;

use super::tracking::Tracker;

/// One GNSS receiver and its next fix.
struct Receiver {
    vehicle_id: u32,
    /// Fixes per solver step (the rate over the solver rate, <= 1).
    fixes_per_step: f64,
    /// Index of the next fix; fix k falls on solver step round(k / fixes_per_step).
    next: u64,
    error: GnssError,
}

/// One road axle detector.
struct Detector {
    position_m: f64,
    lane: Option<u32>,
    timing: DetectorTiming,
}

/// The instruments of a run that see the vehicles.
pub(super) struct Instruments {
    receivers: Vec<Receiver>,
    detectors: Vec<Detector>,
    /// Ids of the vehicles whose state is recorded, ascending.
    instrumented: Vec<u32>,
    dt_ns: u64,
    dt_s: f64,
    /// Scratch for the deck operators under the wheels.
    deflection: SparseVec,
}

impl Instruments {
    pub(super) fn new(resolved: &Resolved) -> Self {
        let s = &resolved.scenario;
        let receivers = s
            .gnss
            .iter()
            .map(|g| Receiver {
                vehicle_id: g.vehicle,
                fixes_per_step: g.rate_hz / resolved.solver_rate_hz,
                next: 0,
                error: GnssError::new(
                    g.noise(),
                    1.0 / g.rate_hz,
                    child_rng(s.seed, &format!("gnss/{}", g.id)),
                ),
            })
            .collect();
        let detectors = s
            .axle_detectors
            .iter()
            .map(|d| Detector {
                position_m: d.position_m,
                lane: d.lane,
                timing: DetectorTiming::new(
                    d.jitter_s,
                    d.miss_probability,
                    child_rng(s.seed, &format!("axle_detector/{}", d.id)),
                ),
            })
            .collect();
        Self {
            receivers,
            detectors,
            instrumented: resolved.instrumented_vehicles.clone(),
            dt_ns: resolved.dt_ns,
            dt_s: resolved.dt_s,
            deflection: SparseVec::default(),
        }
    }

    /// Whether the run has any of these instruments (else the loop skips them).
    pub(super) fn any(&self) -> bool {
        !(self.receivers.is_empty() && self.detectors.is_empty() && self.instrumented.is_empty())
    }

    /// Queues this step's records: the fixes due, the axles that crossed a detector since
    /// the last step, and (when `state_due`) the instrumented vehicles' states.
    pub(super) fn observe(
        &mut self,
        solver: &CoupledSolver,
        road: &RoadProfile,
        tracker: &Tracker,
        step: u64,
        state_due: bool,
        queue: &mut VecDeque<Record>,
    ) {
        let t_ns = step * self.dt_ns;
        self.fixes(solver, step, t_ns, queue);
        if !self.detectors.is_empty() && step > 0 {
            self.crossings(solver, tracker, step, queue);
        }
        if state_due {
            for i in 0..self.instrumented.len() {
                let id = self.instrumented[i];
                let found = solver.vehicles.iter().find(|v| v.id == id && v.is_active());
                if let Some(v) = found {
                    let state = self.state(solver, road, v, step);
                    queue.push_back(Record::VehicleState {
                        t_ns,
                        state: Box::new(state),
                    });
                }
            }
        }
    }

    /// The GNSS fixes that fall on this step; a receiver on a vehicle not on the modelled
    /// road has no fix (its draws are skipped too, so they never depend on traffic).
    fn fixes(
        &mut self,
        solver: &CoupledSolver,
        step: u64,
        t_ns: u64,
        queue: &mut VecDeque<Record>,
    ) {
        for (index, r) in self.receivers.iter_mut().enumerate() {
            let due = (r.next as f64 / r.fixes_per_step).round() as u64;
            if due > step {
                continue;
            }
            r.next += 1;
            let (position_error_m, speed_error_m_s) = r.error.draw();
            let Some(v) = solver
                .vehicles
                .iter()
                .find(|v| v.id == r.vehicle_id && v.is_active())
            else {
                continue;
            };
            let true_position_m = v.axle_x_m(0, step, self.dt_s);
            queue.push_back(Record::Gnss {
                t_ns,
                receiver: index,
                fix: GnssFix {
                    vehicle_id: v.id,
                    position_m: true_position_m + position_error_m,
                    speed_m_s: v.speed_m_s + speed_error_m_s,
                    true_position_m,
                    true_speed_m_s: v.speed_m_s,
                },
            });
        }
    }

    /// Axles that passed a detector between the last step and this one: the crossing
    /// instant is interpolated in the step (the vehicles move at constant speed, so it is
    /// exact), then the detector's timing applied.
    fn crossings(
        &mut self,
        solver: &CoupledSolver,
        tracker: &Tracker,
        step: u64,
        queue: &mut VecDeque<Record>,
    ) {
        let t_ns = step * self.dt_ns;
        for (index, v) in solver.vehicles.iter().enumerate() {
            if !v.is_active() || step <= v.entry_step {
                continue;
            }
            let lane = tracker.lane_of(index);
            for (d, detector) in self.detectors.iter_mut().enumerate() {
                if detector.lane.is_some_and(|l| l != lane) {
                    continue;
                }
                for j in 0..v.dynamics.axles.len() {
                    let before = v.axle_x_m(j, step - 1, self.dt_s);
                    let now = v.axle_x_m(j, step, self.dt_s);
                    let p = detector.position_m;
                    let crossed = match v.direction > 0.0 {
                        true => before < p && p <= now,
                        false => before > p && p >= now,
                    };
                    if !crossed {
                        continue;
                    }
                    let share = (p - before) / (now - before);
                    let true_ns = t_ns - self.dt_ns + (share * self.dt_ns as f64).round() as u64;
                    queue.push_back(Record::AxleHit {
                        t_ns,
                        detector: d,
                        hit: AxleHit {
                            vehicle_id: v.id,
                            axle_index: j as u32,
                            lane,
                            true_ns,
                            stamp_ns: detector.timing.observe(true_ns),
                            speed_m_s: v.speed_m_s,
                        },
                    });
                }
            }
        }
    }

    /// Vehicle `v`'s DOFs and contact points now.
    fn state(
        &mut self,
        solver: &CoupledSolver,
        road: &RoadProfile,
        v: &CoupledVehicle,
        step: u64,
    ) -> VehicleStateRecord {
        let length_m = solver.model.length_m();
        let b = &solver.bridge.state;
        let contacts = (0..v.dynamics.axles.len())
            .map(|j| {
                let x = v.axle_x_m(j, step, self.dt_s);
                let on_bridge = (0.0..=length_m).contains(&x);
                let (deflection_m, acceleration_m_s2) = match on_bridge {
                    true => {
                        solver.model.point_operator(
                            x,
                            PointQuantity::Deflection,
                            &mut self.deflection,
                        );
                        (-self.deflection.dot(&b.u), -self.deflection.dot(&b.a))
                    }
                    false => (0.0, 0.0),
                };
                ContactPoint {
                    position_m: x,
                    road_elevation_m: road.elevation_m(x),
                    bridge_deflection_m: deflection_m,
                    bridge_acceleration_m_s2: acceleration_m_s2,
                    force_n: v.contact_force_n[j],
                    on_bridge,
                }
            })
            .collect();
        VehicleStateRecord {
            vehicle_id: v.id,
            position_m: v.axle_x_m(0, step, self.dt_s),
            speed_m_s: v.speed_m_s,
            displacement: v.state.u.iter().copied().collect(),
            velocity: v.state.v.iter().copied().collect(),
            acceleration: v.state.a.iter().copied().collect(),
            contacts,
        }
    }
}
