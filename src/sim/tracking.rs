//! Follows every vehicle along the road: bridge entry and exit, WIM strips, road axle
//! detectors, contact loss, and the largest tyre force on the bridge (for the DLC).

use std::collections::VecDeque;

use rand_chacha::ChaCha8Rng;

use crate::base::random::child_rng;
use crate::error::Result;
use crate::measurement::vehicle::DetectorTiming;
use crate::measurement::wim::{WimPassage, WimStation};
use crate::physics::solver::CoupledSolver;
use crate::record::{AxleHit, AxleState, EventLevel, Record, VehicleRecord, WimRecordData};
use crate::scenario::Resolved;

/// Another vehicle with an axle this close to a WIM strip when a vehicle's last axle
/// crosses it makes the record a multiple presence (m): the strip's loop detectors and
/// the two vehicles' axle sequences overlap.
const MULTIPLE_PRESENCE_WINDOW_M: f64 = 10.0;

struct VehicleTrack {
    lane: u32,
    speed_m_s: f64,
    started: bool,
    prev_x_m: Vec<f64>,
    entry_ns: Option<u64>,
    exit_ns: Option<u64>,
    emitted: bool,
    /// Per station, per axle: (crossing time, tyre force).
    wim: Vec<Vec<Option<(u64, f64)>>>,
    wim_done: Vec<bool>,
    max_force_on_bridge_n: Vec<f64>,
    /// Smallest wheel force over its static load on the bridge, and the axles that lost
    /// contact there (a train's passage event reports them: wheel unloading).
    min_wheel_ratio: f64,
    lifted_axles: usize,
    /// Per axle: (count, sum, sum of squares) of the tyre force while on the bridge.
    force_moments: Vec<(u64, f64, f64)>,
    losing_contact: Vec<bool>,
}

/// Vehicle bookkeeping of a run.
pub struct Tracker {
    span_m: f64,
    dt_ns: u64,
    dt_s: f64,
    wim_positions_m: Vec<f64>,
    /// Each station's model and its random stream (`wim/<id>`).
    stations: Vec<(WimStation, ChaCha8Rng)>,
    /// Road axle detectors: (position m on the road axis, only this lane, timing model).
    detectors: Vec<(f64, Option<u32>, DetectorTiming)>,
    tracks: Vec<VehicleTrack>,
    /// DLC rows of vehicles already dropped, and how many vehicles they cover.
    departed_dlc: Vec<(u32, u32, f64, f64)>,
    dlc_vehicles: usize,
    departed_contact_loss_steps: u64,
    /// Vehicles dropped after leaving (for the progress report).
    departed: u64,
    /// Axle positions of the vehicle being observed (reused: no allocation per step).
    x_m: Vec<f64>,
}

impl Tracker {
    pub fn new(resolved: &Resolved, span_m: f64) -> Result<Self> {
        let seed = resolved.scenario.seed;
        let models = resolved
            .wim_stations
            .iter()
            .zip(&resolved.scenario.wim_stations)
            .map(|(station, w)| (station.clone(), child_rng(seed, &format!("wim/{}", w.id))))
            .collect();
        let stations = resolved.scenario.wim_stations.len();
        let tracks: Vec<VehicleTrack> = resolved
            .vehicles
            .iter()
            .map(|v| new_track(v.lane, v.speed_m_s, v.dynamics.axles.len(), stations))
            .collect();
        let detectors = resolved
            .scenario
            .axle_detectors
            .iter()
            .map(|d| {
                let rng = child_rng(seed, &format!("axle_detector/{}", d.id));
                let timing = DetectorTiming::new(d.jitter_s, d.miss_probability, rng);
                (d.position_m, d.lane, timing)
            })
            .collect();
        Ok(Tracker {
            stations: models,
            detectors,
            span_m,
            dt_ns: resolved.dt_ns,
            dt_s: resolved.dt_s,
            wim_positions_m: resolved
                .scenario
                .wim_stations
                .iter()
                .map(|w| w.position_m)
                .collect(),
            x_m: Vec::with_capacity(tracks.iter().map(|t| t.prev_x_m.len()).max().unwrap_or(0)),
            tracks,
            departed_dlc: Vec::new(),
            dlc_vehicles: 0,
            departed_contact_loss_steps: 0,
            departed: 0,
        })
    }

    /// The axles of every vehicle on the road.
    pub fn axle_states(&self, solver: &CoupledSolver, step: u64) -> Vec<AxleState> {
        let dt_s = self.dt_s;
        let mut out = Vec::new();
        // The tracks follow the solver's vehicles one to one (admitted and dropped together).
        let vehicles = solver.vehicles.iter().zip(&self.tracks);
        for (v, track) in vehicles.filter(|(v, _)| v.is_active()) {
            for (j, axle) in v.dynamics.axles.iter().enumerate() {
                let x = v.axle_x_m(j, step, dt_s);
                out.push(AxleState {
                    vehicle_id: v.id,
                    axle_index: j as u32,
                    lane: track.lane,
                    position_m: x,
                    force_n: v.contact_force_n[j],
                    static_load_n: axle.static_load_n,
                    in_contact: v.in_contact[j] && v.contact_force_n[j] >= 0.0,
                    on_bridge: (0.0..=self.span_m).contains(&x),
                });
            }
        }
        out
    }

    /// Detects crossings since the previous step and queues the records they produce.
    pub fn observe(&mut self, solver: &CoupledSolver, step: u64, queue: &mut VecDeque<Record>) {
        let t_ns = step * self.dt_ns;
        let dt_s = self.dt_s;
        let mut x = std::mem::take(&mut self.x_m);
        for (v, track) in solver.vehicles.iter().zip(&mut self.tracks) {
            if !v.is_active() {
                continue;
            }
            let axles = v.dynamics.axles.len();
            x.clear();
            x.extend((0..axles).map(|j| v.axle_x_m(j, step, dt_s)));
            if !track.started {
                track.started = true;
                track.prev_x_m.copy_from_slice(&x);
                continue;
            }
            // Towards +x a vehicle enters at 0 and leaves at the span; towards -x the
            // other way round, and a WIM strip at p on the left approach sits at span - p
            // on the right one (stations cover every lane).
            let forward = v.direction > 0.0;
            let crossed = |j: usize, at: f64| match forward {
                true => track.prev_x_m[j] < at && x[j] >= at,
                false => track.prev_x_m[j] > at && x[j] <= at,
            };
            let (entry_at, exit_at) = match forward {
                true => (0.0, self.span_m),
                false => (self.span_m, 0.0),
            };
            if crossed(0, entry_at) {
                track.entry_ns = Some(t_ns);
                queue.push_back(event(
                    t_ns,
                    EventLevel::Info,
                    format!("vehicle {} enters the bridge", v.id),
                ));
            }
            for (s, &p) in self.wim_positions_m.iter().enumerate() {
                let p = if forward { p } else { self.span_m - p };
                for j in 0..axles {
                    if crossed(j, p) {
                        track.wim[s][j] = Some((t_ns, v.contact_force_n[j]));
                    }
                }
                if !track.wim_done[s] && track.wim[s].iter().all(Option::is_some) {
                    track.wim_done[s] = true;
                    let near = |o: &crate::physics::solver::CoupledVehicle| {
                        o.id != v.id
                            && o.is_active()
                            && (0..o.dynamics.axles.len()).any(|j| {
                                (o.axle_x_m(j, step, dt_s) - p).abs() < MULTIPLE_PRESENCE_WINDOW_M
                            })
                    };
                    let multiple_presence = solver.vehicles.iter().any(near);
                    let (station, rng) = &mut self.stations[s];
                    let passage = wim_passage(s, v, track, multiple_presence);
                    queue.push_back(Record::Wim {
                        t_ns,
                        record: WimRecordData {
                            station: s,
                            measurement: station.measure(&passage, rng),
                        },
                    });
                }
            }
            // Axle detectors sit where they are on the road (unlike the strips, which
            // cover both directions mirrored): the crossing instant is interpolated in
            // the step, exact at constant speed.
            for (d, (p, lane, timing)) in self.detectors.iter_mut().enumerate() {
                if lane.is_some_and(|l| l != track.lane) {
                    continue;
                }
                for (j, (&now, &before)) in x.iter().zip(&track.prev_x_m).enumerate() {
                    if !crossed(j, *p) {
                        continue;
                    }
                    let share = (*p - before) / (now - before);
                    let true_ns = t_ns - self.dt_ns + (share * self.dt_ns as f64).round() as u64;
                    let hit = AxleHit {
                        vehicle_id: v.id,
                        axle_index: j as u32,
                        lane: track.lane,
                        true_ns,
                        stamp_ns: timing.observe(true_ns),
                        speed_m_s: v.speed_m_s,
                    };
                    queue.push_back(Record::AxleHit {
                        t_ns,
                        detector: d,
                        hit,
                    });
                }
            }
            for (j, &xj) in x.iter().enumerate() {
                if (0.0..=self.span_m).contains(&xj) {
                    let f = v.contact_force_n[j];
                    track.max_force_on_bridge_n[j] = track.max_force_on_bridge_n[j].max(f);
                    let static_n = v.dynamics.axles[j].static_load_n;
                    if static_n > 0.0 {
                        track.min_wheel_ratio = track.min_wheel_ratio.min(f / static_n);
                    }
                    let m = &mut track.force_moments[j];
                    *m = (m.0 + 1, m.1 + f, m.2 + f * f);
                }
                let losing = !v.in_contact[j] || v.contact_force_n[j] < 0.0;
                if losing != track.losing_contact[j] {
                    track.losing_contact[j] = losing;
                    if losing && (0.0..=self.span_m).contains(&xj) {
                        track.lifted_axles += 1;
                    }
                    let what = if losing {
                        "loses contact"
                    } else {
                        "regains contact"
                    };
                    let level = if losing {
                        EventLevel::Warning
                    } else {
                        EventLevel::Info
                    };
                    queue.push_back(event(
                        t_ns,
                        level,
                        format!("vehicle {} axle {} {what} at x = {:.2} m", v.id, j, xj),
                    ));
                }
            }
            if crossed(axles - 1, exit_at) {
                track.exit_ns = Some(t_ns);
                queue.push_back(event(t_ns, EventLevel::Info, leave_text(v, track)));
                queue.push_back(Record::Vehicle {
                    t_ns,
                    vehicle: vehicle_record(v, track),
                });
                track.emitted = true;
            }
            track.prev_x_m.copy_from_slice(&x);
        }
        self.x_m = x;
    }

    /// Starts following a vehicle just added to the solver (traffic arrives during the run).
    pub fn add_vehicle(&mut self, lane: u32, speed_m_s: f64, axles: usize) {
        let stations = self.wim_positions_m.len();
        self.tracks
            .push(new_track(lane, speed_m_s, axles, stations));
        self.x_m.reserve(axles.saturating_sub(self.x_m.capacity()));
    }

    /// Removes from the solver and from the tracks every vehicle that has left the road
    /// and whose truth record is written, keeping its DLC rows (up to
    /// [`MAX_DLC_VEHICLES`] vehicles): memory follows the vehicles on the road, not the
    /// run's length.
    pub fn drop_departed(&mut self, solver: &mut CoupledSolver) {
        let mut i = 0;
        while i < solver.vehicles.len() {
            if solver.vehicles[i].is_retired() && self.tracks[i].emitted {
                if self.dlc_vehicles < MAX_DLC_VEHICLES && self.tracks[i].entry_ns.is_some() {
                    self.dlc_vehicles += 1;
                    let rows = dlc_rows(&solver.vehicles[i], &self.tracks[i]);
                    self.departed_dlc.extend(rows);
                }
                self.departed_contact_loss_steps += solver.vehicles[i].contact_loss_steps;
                solver.vehicles.remove(i);
                self.tracks.remove(i);
                self.departed += 1;
            } else {
                i += 1;
            }
        }
    }

    /// Vehicles that have crossed and been dropped so far.
    pub fn departed(&self) -> u64 {
        self.departed
    }

    /// Queues the records of vehicles that had not left the bridge when the run ended.
    pub fn finish(&mut self, solver: &CoupledSolver, queue: &mut VecDeque<Record>) {
        let t_ns = solver.step * self.dt_ns;
        for (v, track) in solver.vehicles.iter().zip(&mut self.tracks) {
            if !track.emitted {
                track.emitted = true;
                queue.push_back(Record::Vehicle {
                    t_ns,
                    vehicle: vehicle_record(v, track),
                });
            }
        }
    }

    /// Per axle of every vehicle that entered (the first [`MAX_DLC_VEHICLES`] of a long
    /// run): (vehicle id, axle, max tyre force on the bridge / static, standard deviation
    /// of the force on the bridge / static).
    pub fn dlc_ratios(&self, solver: &CoupledSolver) -> Vec<(u32, u32, f64, f64)> {
        let mut out = self.departed_dlc.clone();
        let room = MAX_DLC_VEHICLES.saturating_sub(self.dlc_vehicles);
        let on_road = solver.vehicles.iter().zip(&self.tracks);
        for (v, track) in on_road.filter(|(_, t)| t.entry_ns.is_some()).take(room) {
            out.extend(dlc_rows(v, track));
        }
        out.sort_by_key(|&(id, axle, ..)| (id, axle));
        out
    }
}

impl Tracker {
    /// Steps with a tyre in tension or lifted off, summed over every vehicle of the run.
    pub fn contact_loss_steps(&self, solver: &CoupledSolver) -> u64 {
        let on_road: u64 = solver.vehicles.iter().map(|v| v.contact_loss_steps).sum();
        self.departed_contact_loss_steps + on_road
    }
}

/// Vehicles whose DLC rows a run keeps: a day of traffic has tens of thousands.
pub const MAX_DLC_VEHICLES: usize = 1000;

/// The DLC rows of one vehicle's axles.
fn dlc_rows(
    v: &crate::physics::solver::CoupledVehicle,
    track: &VehicleTrack,
) -> Vec<(u32, u32, f64, f64)> {
    v.dynamics
        .axles
        .iter()
        .enumerate()
        .map(|(j, axle)| {
            let (n, sum, sum_sq) = track.force_moments[j];
            let n = n.max(1) as f64;
            let variance = (sum_sq / n - (sum / n).powi(2)).max(0.0);
            let s = axle.static_load_n;
            (
                v.id,
                j as u32,
                track.max_force_on_bridge_n[j] / s,
                variance.sqrt() / s,
            )
        })
        .collect()
}

fn new_track(lane: u32, speed_m_s: f64, axles: usize, stations: usize) -> VehicleTrack {
    VehicleTrack {
        lane,
        speed_m_s,
        started: false,
        prev_x_m: vec![0.0; axles],
        entry_ns: None,
        exit_ns: None,
        emitted: false,
        wim: vec![vec![None; axles]; stations],
        wim_done: vec![false; stations],
        max_force_on_bridge_n: vec![0.0; axles],
        min_wheel_ratio: f64::INFINITY,
        lifted_axles: 0,
        force_moments: vec![(0, 0.0, 0.0); axles],
        losing_contact: vec![false; axles],
    }
}

/// "vehicle 3 leaves the bridge"; for a train also the passage's wheel unloading
/// (the smallest wheel load over its static one, and the wheels lifted off: a
/// derailment-risk indicator).
fn leave_text(v: &crate::physics::solver::CoupledVehicle, track: &VehicleTrack) -> String {
    let text = format!("vehicle {} leaves the bridge", v.id);
    if !v.dynamics.name.starts_with("train") {
        return text;
    }
    let lifted = match track.lifted_axles {
        0 => "no wheel lifted off".to_string(),
        n => format!("wheels lost contact {n} times"),
    };
    format!(
        "{text} ({}, {} wheelsets, {:.0} km/h): smallest wheel load {:.3} x static, {lifted}",
        v.dynamics.name,
        v.dynamics.axles.len(),
        3.6 * v.speed_m_s,
        track.min_wheel_ratio
    )
}

fn event(t_ns: u64, level: EventLevel, text: String) -> Record {
    Record::Event { t_ns, level, text }
}

fn spacings(v: &crate::physics::solver::CoupledVehicle) -> Vec<f64> {
    v.dynamics
        .axles
        .windows(2)
        .map(|w| w[1].offset_m - w[0].offset_m)
        .collect()
}

/// What the strip of station `station` saw of vehicle `v`.
fn wim_passage(
    station: usize,
    v: &crate::physics::solver::CoupledVehicle,
    track: &VehicleTrack,
    multiple_presence: bool,
) -> WimPassage {
    let crossings = &track.wim[station];
    WimPassage {
        vehicle_id: v.id,
        lane: track.lane,
        t_first_axle_ns: crossings[0].map_or(0, |(t, _)| t),
        speed_m_s: track.speed_m_s,
        axle_spacing_m: spacings(v),
        static_axle_load_n: v.dynamics.axles.iter().map(|a| a.static_load_n).collect(),
        dynamic_axle_load_n: crossings
            .iter()
            .map(|c| c.map(|(_, f)| f).unwrap_or(f64::NAN))
            .collect(),
        multiple_presence,
    }
}

fn vehicle_record(
    v: &crate::physics::solver::CoupledVehicle,
    track: &VehicleTrack,
) -> VehicleRecord {
    VehicleRecord {
        vehicle_id: v.id,
        model: v.dynamics.name.clone(),
        lane: track.lane,
        direction: if v.direction < 0.0 { -1 } else { 1 },
        speed_m_s: track.speed_m_s,
        entry_time_ns: track.entry_ns,
        exit_time_ns: track.exit_ns,
        axle_spacing_m: spacings(v),
        static_axle_load_n: v.dynamics.axles.iter().map(|a| a.static_load_n).collect(),
        gross_weight_n: v.dynamics.gross_weight_n(),
        parameters: v.dynamics.parameters.clone(),
    }
}
