//! What the time loop records of the instrumented vehicles beyond their axle loads: the
//! fixes of GNSS receivers riding on them, and the state of each (its DOFs and where its
//! wheels touch the road) that drive-by monitoring is scored against; and the forecast of
//! these records and of the road axle detectors' (which the tracker times, with the other
//! crossings). Built once; reading allocates only the records.

use std::collections::VecDeque;

use crate::base::random::child_rng;
use crate::measurement::vehicle::GnssError;
use crate::physics::bridge::{PointQuantity, SparseVec};
use crate::physics::road::RoadProfile;
use crate::physics::solver::{CoupledSolver, CoupledVehicle};
use crate::record::{AxleHit, ContactPoint, GnssFix, Record, VehicleStateRecord};
use crate::scenario::Resolved;

/// One GNSS receiver and its next fix.
struct Receiver {
    vehicle_id: u32,
    /// Fixes per solver step (the rate over the solver rate, <= 1).
    fixes_per_step: f64,
    /// Index of the next fix; fix k falls on solver step round(k / fixes_per_step).
    next: u64,
    error: GnssError,
}

/// The instruments of a run that see the vehicles.
pub(super) struct Instruments {
    receivers: Vec<Receiver>,
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
        Self {
            receivers,
            instrumented: resolved.instrumented_vehicles.clone(),
            dt_ns: resolved.dt_ns,
            dt_s: resolved.dt_s,
            deflection: SparseVec::default(),
        }
    }

    /// Whether the run has any of these instruments (else the loop skips them).
    pub(super) fn any(&self) -> bool {
        !(self.receivers.is_empty() && self.instrumented.is_empty())
    }

    /// Queues this step's records: the fixes due and (when `state_due`) the instrumented
    /// vehicles' states.
    pub(super) fn observe(
        &mut self,
        solver: &CoupledSolver,
        road: &RoadProfile,
        step: u64,
        state_due: bool,
        queue: &mut VecDeque<Record>,
    ) {
        let t_ns = step * self.dt_ns;
        self.fixes(solver, step, t_ns, queue);
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

/// The instruments' records a run will emit, forecast (`sim::forecast`): each with its
/// expected count. `axles_past(x_m)` is the number of axles expected to cross road
/// position `x_m` by the end of the run (all lanes).
pub(super) fn forecast(
    resolved: &Resolved,
    duration_s: f64,
    axles_past: &dyn Fn(f64) -> f64,
) -> Vec<(Record, f64)> {
    let s = &resolved.scenario;
    let on_road_s = |id: u32| -> f64 {
        resolved
            .vehicles
            .iter()
            .find(|v| v.id == id)
            .map_or(0.0, |v| {
                let start_s = v.entry_step as f64 * resolved.dt_s;
                let road_m = s.road.approach_m + s.bridge.length_m() + s.road.exit_m;
                let end_s = start_s + (road_m + v.dynamics.wheelbase_m()) / v.speed_m_s;
                (end_s.min(duration_s) - start_s).max(0.0)
            })
    };
    let mut out = Vec::new();
    for (receiver, g) in s.gnss.iter().enumerate() {
        let fix = GnssFix {
            vehicle_id: g.vehicle,
            position_m: 12.345,
            speed_m_s: 15.25,
            true_position_m: 12.345,
            true_speed_m_s: 15.25,
        };
        let record = Record::Gnss {
            t_ns: 0,
            receiver,
            fix,
        };
        out.push((record, on_road_s(g.vehicle) * g.rate_hz));
    }
    for (detector, d) in s.axle_detectors.iter().enumerate() {
        let hit = AxleHit {
            vehicle_id: 12,
            axle_index: 1,
            lane: 1,
            true_ns: 1_234_567_890,
            stamp_ns: Some(1_234_567_999),
            speed_m_s: 15.25,
        };
        let record = Record::AxleHit {
            t_ns: 0,
            detector,
            hit,
        };
        out.push((record, axles_past(d.position_m)));
    }
    let state_rate_hz = 1.0 / (resolved.axle_stride as f64 * resolved.dt_s);
    for &id in &resolved.instrumented_vehicles {
        let Some(v) = resolved.vehicles.iter().find(|v| v.id == id) else {
            continue;
        };
        let n = v.dynamics.n_dof();
        let typical = |scale: f64| (0..n).map(|i| scale * (i as f64 + 1.25)).collect();
        let contact = ContactPoint {
            position_m: 12.345,
            road_elevation_m: 1.25e-3,
            bridge_deflection_m: 1.25e-3,
            bridge_acceleration_m_s2: 0.125,
            force_n: 1.25e4,
            on_bridge: true,
        };
        let state = VehicleStateRecord {
            vehicle_id: id,
            position_m: 12.345,
            speed_m_s: v.speed_m_s,
            displacement: typical(1e-3),
            velocity: typical(1e-2),
            acceleration: typical(1e-1),
            contacts: vec![contact; v.dynamics.axles.len()],
        };
        let record = Record::VehicleState {
            t_ns: 0,
            state: Box::new(state),
        };
        out.push((record, on_road_s(id) * state_rate_hz));
    }
    out
}
