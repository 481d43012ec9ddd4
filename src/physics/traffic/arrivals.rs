//! Entry times on one lane: a shifted (Cowan M1) non-homogeneous Poisson process.
//!
//! Each vehicle blocks its lane for the follower's minimum headway `h_req` (below); after
//! it the follower arrives at the free rate `r(t)`. Arrivals are drawn by time change, not
//! thinning: with `R(t) = integral of r`, the follower enters at
//! `R^-1(R(t_leader + h_req) + E)`, `E ~ Exp(1)`. The rate is constant within each hour,
//! so `R^-1` is exact and each vehicle costs exactly one exponential draw (no rejected
//! candidates whose number would depend on the rate).
//!
//! At a constant flow `q` the headways are then `h_req + Exp(r)`: a shifted exponential.
//! `r = q / (1 - q * mean(h_req))` makes the mean headway `1 / q`, so each lane carries
//! its `flow_per_hour` times the hourly factor.

use super::spec::HOURS_PER_DAY;

const SECONDS_PER_HOUR: f64 = 3600.0;

/// What a follower needs to know about the vehicle ahead on its lane.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Leader {
    pub entry_time_s: f64,
    pub speed_m_s: f64,
    /// Front axle to the rear of the body: wheelbase plus rear overhang, m.
    pub axle_to_rear_m: f64,
}

/// Smallest headway (entry to entry) of a follower at `speed_m_s` with `front_overhang_m`
/// behind `leader`, so that the clear distance from the leader's rear to the follower's
/// front is at least `min_gap_s * speed_m_s` from the follower's entry until its front
/// axle has covered `road_length_m`, the leader driving on at constant speed.
///
/// The clear distance is linear in time, so checking both ends suffices:
/// at entry `v_L * h >= axle_to_rear_L + front_overhang_F + g * v_F`; at the end the
/// follower has gained `road_length_m * (1 / v_L - 1 / v_F)` seconds on the leader when it
/// is faster. A faster follower therefore enters later; its speed is never capped.
pub(crate) fn min_headway_s(
    leader: &Leader,
    speed_m_s: f64,
    front_overhang_m: f64,
    min_gap_s: f64,
    road_length_m: f64,
) -> f64 {
    let at_entry_s =
        (leader.axle_to_rear_m + front_overhang_m + min_gap_s * speed_m_s) / leader.speed_m_s;
    let catch_up_s = road_length_m * (1.0 / leader.speed_m_s - 1.0 / speed_m_s);
    at_entry_s + catch_up_s.max(0.0)
}

/// Mean of [`min_headway_s`] over a lane's vehicles, to first order in the speed scatter:
/// `(mean length + g * v) / v` at the mean speed `v`, plus the mean catch-up term
/// `road * E[max(0, v_F - v_L)] / v^2 = road * sd / (sqrt(pi) * v^2)` (the speed difference
/// of two vehicles is N(0, 2 sd^2)). The neglected terms are O(sd^2 / v^2), below 0.2 %
/// at the default 1 m/s around 24.7 m/s.
pub(crate) fn mean_min_headway_s(
    mean_length_m: f64,
    speed_mean_m_s: f64,
    speed_sd_m_s: f64,
    min_gap_s: f64,
    road_length_m: f64,
) -> f64 {
    let v = speed_mean_m_s;
    (mean_length_m + min_gap_s * v) / v
        + road_length_m * speed_sd_m_s / (std::f64::consts::PI.sqrt() * v * v)
}

/// The free arrival rate of a lane, hour by hour of the local day.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct FreeRate {
    per_s: [f64; HOURS_PER_DAY],
    /// Local time of day at t = 0, s.
    day_offset_s: f64,
}

impl FreeRate {
    /// The rate giving flows `flow_per_s[h]` when each vehicle blocks the lane for
    /// `mean_headway_s` on average: `r = q / (1 - q * h)`. `None` if some hour's flow
    /// needs `q * h >= max_occupancy` (the lane would be saturated).
    pub fn new(
        flow_per_s: [f64; HOURS_PER_DAY],
        mean_headway_s: f64,
        max_occupancy: f64,
        day_offset_s: f64,
    ) -> Option<Self> {
        if flow_per_s
            .iter()
            .any(|&q| q * mean_headway_s >= max_occupancy)
        {
            return None;
        }
        Some(Self {
            per_s: flow_per_s.map(|q| q / (1.0 - q * mean_headway_s)),
            day_offset_s,
        })
    }

    /// Whether the lane ever has traffic.
    pub fn is_active(&self) -> bool {
        self.per_s.iter().any(|&r| r > 0.0)
    }

    /// `R^-1(R(t_s) + budget)`: the time at which the integrated rate from `t_s` reaches
    /// `budget` (an Exp(1) draw). Walks hour by hour with an integer hour counter, so
    /// rounding can never stall it on a boundary. Call only on an active lane.
    pub fn advance(&self, t_s: f64, mut budget: f64) -> f64 {
        let mut hour = ((t_s + self.day_offset_s) / SECONDS_PER_HOUR).floor() as i64;
        let mut t = t_s;
        loop {
            let end_s = (hour + 1) as f64 * SECONDS_PER_HOUR - self.day_offset_s;
            let rate = self.per_s[hour.rem_euclid(HOURS_PER_DAY as i64) as usize];
            let span_s = (end_s - t).max(0.0);
            if rate > 0.0 && rate * span_s >= budget {
                return t + budget / rate;
            }
            budget -= rate * span_s;
            t = end_s;
            hour += 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn time_change_crosses_hours_exactly() {
        // 1/s in hour 0, 0 in hour 1, 2/s in hour 2: a budget of 3600 + 100 from t = 0
        // uses hour 0 whole, skips hour 1 and needs 50 s of hour 2.
        let mut q = [0.0; HOURS_PER_DAY];
        q[0] = 1.0;
        q[2] = 2.0;
        let rate = FreeRate {
            per_s: q,
            day_offset_s: 0.0,
        };
        let t = rate.advance(0.0, 3700.0);
        assert!((t - (7200.0 + 50.0)).abs() < 1e-9, "{t}");
        // From 7300 s, the rest of hour 2 holds 2 * 3500 = 7000; the next rate is hour 0
        // of the next day, after 21 empty hours.
        let t = rate.advance(7300.0, 7000.0 + 10.0);
        assert!((t - (86_400.0 + 10.0)).abs() < 1e-6, "{t}");
    }

    #[test]
    fn a_faster_follower_waits_for_the_catch_up() {
        let leader = Leader {
            entry_time_s: 0.0,
            speed_m_s: 20.0,
            axle_to_rear_m: 10.0,
        };
        // Equal speeds: (10 + 1 + 20) / 20.
        assert!((min_headway_s(&leader, 20.0, 1.0, 1.0, 200.0) - 1.55).abs() < 1e-12);
        // Faster follower: + 200 * (1/20 - 1/25) = 2 s.
        let h = min_headway_s(&leader, 25.0, 1.0, 1.0, 200.0);
        assert!((h - (36.0 / 20.0 + 2.0)).abs() < 1e-12, "{h}");
    }
}
