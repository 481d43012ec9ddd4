//! The streaming generator: one pending vehicle per lane, merged in entry order.

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::Exp1;

use super::arrivals::{mean_min_headway_s, min_headway_s, FreeRate, Leader};
use super::class::{truncated_standard_normal, ClassModel, VehicleClass};
use super::spec::{Lane, TrafficSpec, Validated, HOURS_PER_DAY};
use crate::base::random::child_rng;
use crate::error::{num, require_finite, require_positive, Error, Result};

/// Largest share of a lane's time that minimum headways may block at the peak hour
/// (`flow * mean minimum headway`). Above it vehicles would queue nose to tail: congested
/// traffic, which a free-flow arrival model does not describe.
pub const MAX_LANE_OCCUPANCY: f64 = 0.9;

/// What the generator needs from the rest of the scenario.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrafficRun {
    /// Run seed; lane `i` draws from `child_rng(seed, "traffic/lane/<i>")`.
    pub seed: u64,
    /// Distance the front axle travels from its entry point to where the vehicle is
    /// dropped (approach + span + exit), m: the minimum gap holds over all of it.
    pub road_length_m: f64,
    /// Local time of day at t = 0, s (e.g. 8 h = 28 800 s), selecting the hourly factor.
    pub time_of_day_at_zero_s: f64,
    /// Id of the first generated vehicle; the following ones count up in entry order.
    pub first_id: u32,
}

/// One generated vehicle.
#[derive(Debug, Clone, PartialEq)]
pub struct GeneratedVehicle {
    /// Unique id, in entry order across all lanes.
    pub id: u32,
    /// Index of the lane in `traffic.lanes`.
    pub lane: usize,
    /// Direction of travel of the lane: 1 along the beam axis, -1 against it.
    pub direction: i8,
    /// Class; `class.name()` is the `vehicle::classes` preset to scale.
    pub class: VehicleClass,
    /// Time at which the front axle is at the start of its approach, s.
    pub entry_time_s: f64,
    /// Constant speed, m/s.
    pub speed_m_s: f64,
    /// Static gross weight, N.
    pub gross_weight_n: f64,
    /// Axle spacings front to rear, m (one fewer than the axles).
    pub axle_spacing_m: Vec<f64>,
    /// Static axle loads front to rear, N; they sum to `gross_weight_n`.
    pub axle_load_n: Vec<f64>,
    /// Body ahead of the front axle, m.
    pub front_overhang_m: f64,
    /// Body behind the last axle, m.
    pub rear_overhang_m: f64,
    /// Seed of this vehicle's parameter variation (see [`variation_factors`]).
    pub variation_seed: u64,
}

impl GeneratedVehicle {
    /// Front axle to last axle, m.
    pub fn wheelbase_m(&self) -> f64 {
        self.axle_spacing_m.iter().sum()
    }

    /// Bumper to bumper, m.
    pub fn length_m(&self) -> f64 {
        self.front_overhang_m + self.wheelbase_m() + self.rear_overhang_m
    }
}

/// `count` factors `1 + sd_rel * z`, z standard normal truncated at 3 sd, from the stream
/// `ChaCha8Rng::seed_from_u64(variation_seed)`: multiply a vehicle's suspension stiffness,
/// damping and masses by them (with `sd_rel` = `traffic.parameter_sd_rel`) so that no two
/// vehicles of a class are identical, yet each is reproducible from its record.
pub fn variation_factors(variation_seed: u64, count: usize, sd_rel: f64) -> Vec<f64> {
    let mut rng = ChaCha8Rng::seed_from_u64(variation_seed);
    (0..count)
        .map(|_| 1.0 + sd_rel * truncated_standard_normal(&mut rng))
        .collect()
}

/// Random traffic, generated lazily: each lane holds only its next vehicle, so memory does
/// not grow with the duration of the run.
#[derive(Debug, Clone)]
pub struct TrafficGenerator {
    lanes: Vec<LaneStream>,
    models: [ClassModel; 5],
    min_gap_s: f64,
    road_length_m: f64,
    parameter_sd_rel: f64,
    next_id: u32,
}

#[derive(Debug, Clone)]
struct LaneStream {
    index: usize,
    lane: Lane,
    rate: FreeRate,
    rng: ChaCha8Rng,
    leader: Option<Leader>,
    pending: Option<GeneratedVehicle>,
}

impl TrafficGenerator {
    /// Validates `spec` (errors name `<field_prefix>.<field>`) and `run`, and draws each
    /// lane's first vehicle.
    pub fn new(spec: &TrafficSpec, run: &TrafficRun, field_prefix: &str) -> Result<Self> {
        let valid = spec.validated(field_prefix)?;
        require_positive("road_length_m", run.road_length_m)?;
        require_finite("time_of_day_at_zero_s", run.time_of_day_at_zero_s)?;
        let lanes = valid
            .lanes
            .iter()
            .enumerate()
            .map(|(index, lane)| LaneStream::new(index, lane, &valid, run, field_prefix))
            .collect::<Result<Vec<_>>>()?;
        let mut generator = Self {
            lanes,
            models: valid.models,
            min_gap_s: valid.min_gap_s,
            road_length_m: run.road_length_m,
            parameter_sd_rel: valid.parameter_sd_rel,
            next_id: run.first_id,
        };
        for i in 0..generator.lanes.len() {
            generator.refill(i);
        }
        Ok(generator)
    }

    /// `traffic.parameter_sd_rel`, for [`variation_factors`].
    pub fn parameter_sd_rel(&self) -> f64 {
        self.parameter_sd_rel
    }

    /// Entry time of the next vehicle, s; `None` if every lane is empty.
    pub fn peek_entry_time_s(&self) -> Option<f64> {
        self.next_lane().map(|i| self.pending_entry_s(i))
    }

    /// The next vehicle in entry order across lanes if it enters at or before `t_s`
    /// (ties go to the lower lane index); `None` otherwise, leaving it pending.
    pub fn next_before(&mut self, t_s: f64) -> Option<GeneratedVehicle> {
        let i = self.next_lane()?;
        if self.pending_entry_s(i) > t_s {
            return None;
        }
        let mut vehicle = self.lanes[i].pending.take()?;
        vehicle.id = self.next_id;
        self.next_id = self.next_id.wrapping_add(1);
        self.refill(i);
        Some(vehicle)
    }

    fn pending_entry_s(&self, lane: usize) -> f64 {
        self.lanes[lane]
            .pending
            .as_ref()
            .map_or(f64::INFINITY, |v| v.entry_time_s)
    }

    fn next_lane(&self) -> Option<usize> {
        (0..self.lanes.len())
            .filter(|&i| self.lanes[i].pending.is_some())
            .min_by(|&a, &b| self.pending_entry_s(a).total_cmp(&self.pending_entry_s(b)))
    }

    fn refill(&mut self, lane: usize) {
        let (models, min_gap_s, road_length_m) = (&self.models, self.min_gap_s, self.road_length_m);
        self.lanes[lane].refill(models, min_gap_s, road_length_m);
    }
}

impl Iterator for TrafficGenerator {
    type Item = GeneratedVehicle;

    /// The next vehicle, however late; endless unless every lane is empty.
    fn next(&mut self) -> Option<GeneratedVehicle> {
        self.next_before(f64::INFINITY)
    }
}

impl LaneStream {
    fn new(
        index: usize,
        lane: &Lane,
        valid: &Validated,
        run: &TrafficRun,
        field_prefix: &str,
    ) -> Result<Self> {
        let mean_length_m: f64 = valid
            .models
            .iter()
            .zip(lane.shares)
            .map(|(m, share)| {
                share
                    * (m.front_overhang_m
                        + m.spacing_mean_m.iter().sum::<f64>()
                        + m.rear_overhang_m)
            })
            .sum();
        let headway_s = mean_min_headway_s(
            mean_length_m,
            lane.speed_mean_m_s,
            lane.speed_sd_m_s,
            valid.min_gap_s,
            run.road_length_m,
        );
        let flow_per_s: [f64; HOURS_PER_DAY] = valid.profile.map(|f| f * lane.flow_per_s);
        let rate = FreeRate::new(
            flow_per_s,
            headway_s,
            MAX_LANE_OCCUPANCY,
            run.time_of_day_at_zero_s,
        )
        .ok_or_else(|| saturation_error(lane, &valid.profile, headway_s, index, field_prefix))?;
        Ok(Self {
            index,
            lane: lane.clone(),
            rate,
            rng: child_rng(run.seed, &format!("traffic/lane/{index}")),
            leader: None,
            pending: None,
        })
    }

    /// Draws the vehicle after the last one handed out. Draw order, fixed so a seed always
    /// gives the same traffic: class, body (weight, spacings, load shares), speed,
    /// variation seed, free gap.
    fn refill(&mut self, models: &[ClassModel; 5], min_gap_s: f64, road_length_m: f64) {
        if !self.rate.is_active() {
            return;
        }
        let class = self.draw_class();
        let body = models[class.index()].draw(&mut self.rng);
        let speed_m_s = self.lane.speed_mean_m_s
            + self.lane.speed_sd_m_s * truncated_standard_normal(&mut self.rng);
        let variation_seed: u64 = self.rng.random();
        let free_gap: f64 = self.rng.sample(Exp1);
        let blocked_until_s = self.leader.as_ref().map_or(0.0, |leader| {
            leader.entry_time_s
                + min_headway_s(
                    leader,
                    speed_m_s,
                    body.front_overhang_m,
                    min_gap_s,
                    road_length_m,
                )
        });
        let entry_time_s = self.rate.advance(blocked_until_s, free_gap);
        let vehicle = GeneratedVehicle {
            id: 0,
            lane: self.index,
            direction: self.lane.direction,
            class,
            entry_time_s,
            speed_m_s,
            gross_weight_n: body.gross_weight_n,
            axle_spacing_m: body.axle_spacing_m,
            axle_load_n: body.axle_load_n,
            front_overhang_m: body.front_overhang_m,
            rear_overhang_m: body.rear_overhang_m,
            variation_seed,
        };
        self.leader = Some(Leader {
            entry_time_s,
            speed_m_s,
            axle_to_rear_m: vehicle.wheelbase_m() + vehicle.rear_overhang_m,
        });
        self.pending = Some(vehicle);
    }

    /// Inverse CDF of the lane's class shares; a uniform draw beyond the last cumulative
    /// share (rounding) goes to the last class with a positive share.
    fn draw_class(&mut self) -> VehicleClass {
        let mut u = self.rng.random::<f64>();
        let mut last = VehicleClass::Car;
        for class in VehicleClass::ALL {
            let share = self.lane.shares[class.index()];
            if share <= 0.0 {
                continue;
            }
            if u < share {
                return class;
            }
            u -= share;
            last = class;
        }
        last
    }
}

fn saturation_error(
    lane: &Lane,
    profile: &[f64; HOURS_PER_DAY],
    headway_s: f64,
    index: usize,
    field_prefix: &str,
) -> Error {
    let peak = profile.iter().copied().fold(0.0, f64::max);
    let flow_per_hour = lane.flow_per_s * 3600.0;
    Error::invalid(
        format!("{field_prefix}.lanes.{index}.flow_per_hour"),
        num(flow_per_hour),
        format!(
            "saturates the lane: at the peak factor {peak:.2} its vehicles, each blocking it \
             for a mean minimum headway of {headway_s:.2} s, would occupy {:.2} of the time \
             (at most {MAX_LANE_OCCUPANCY} is free flow)",
            flow_per_hour * peak / 3600.0 * headway_s
        ),
    )
}
