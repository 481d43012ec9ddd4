//! Traffic generator: statistical checks of weights, headways, hourly counts and class
//! shares against the model's distributions; the minimum gap checked geometrically;
//! determinism and lane independence; bad inputs.
//!
//! Statistical tests use a fixed seed, so they are deterministic; the stated level is the
//! chance that a correct generator would fail them for a seed picked at random.

use std::collections::BTreeMap;

use bridgetwin::physics::traffic::{
    variation_factors, ClassModel, GeneratedVehicle, TrafficGenerator, TrafficRun, TrafficSpec,
    VehicleClass, DEFAULT_HOURLY_PROFILE,
};

const GRAVITY_M_S2: f64 = 9.81;
/// Approach 100 m + span 30 m + exit 30 m: the default scenario's road.
const ROAD_LENGTH_M: f64 = 160.0;
/// Kolmogorov-Smirnov level of every KS test here.
const KS_ALPHA: f64 = 0.01;

fn spec(toml_text: &str) -> TrafficSpec {
    toml::from_str(toml_text).expect("test spec parses")
}

fn run(seed: u64) -> TrafficRun {
    TrafficRun {
        seed,
        road_length_m: ROAD_LENGTH_M,
        time_of_day_at_zero_s: 0.0,
        first_id: 1,
    }
}

fn generator(spec: &TrafficSpec, seed: u64) -> TrafficGenerator {
    TrafficGenerator::new(spec, &run(seed), "traffic").expect("valid spec")
}

/// All vehicles entering before `end_s`.
fn until(generator: &mut TrafficGenerator, end_s: f64) -> Vec<GeneratedVehicle> {
    std::iter::from_fn(|| generator.next_before(end_s)).collect()
}

// ---- statistics, written independently of the library ----

/// Standard normal CDF from Abramowitz & Stegun 7.1.26 (|error of erf| < 1.5e-7), far
/// below the KS critical values used (> 0.02).
fn normal_cdf(z: f64) -> f64 {
    let x = z.abs() / std::f64::consts::SQRT_2;
    let t = 1.0 / (1.0 + 0.327_591_1 * x);
    let poly = t
        * (0.254_829_592
            + t * (-0.284_496_736
                + t * (1.421_413_741 + t * (-1.453_152_027 + t * 1.061_405_429))));
    let erf = 1.0 - poly * (-x * x).exp();
    if z >= 0.0 {
        0.5 * (1.0 + erf)
    } else {
        0.5 * (1.0 - erf)
    }
}

/// Kolmogorov-Smirnov statistic `D_n = sup |F_n - F|` of `samples` against `cdf`.
fn ks_statistic(mut samples: Vec<f64>, cdf: impl Fn(f64) -> f64) -> f64 {
    samples.sort_by(f64::total_cmp);
    let n = samples.len() as f64;
    samples
        .iter()
        .enumerate()
        .map(|(i, &x)| {
            let f = cdf(x);
            ((i + 1) as f64 / n - f).max(f - i as f64 / n)
        })
        .fold(0.0, f64::max)
}

/// Asymptotic critical value of `D_n` at level `alpha`: `sqrt(-ln(alpha / 2) / 2) / sqrt(n)`
/// (Kolmogorov's limit distribution; 1.628 / sqrt(n) at alpha = 0.01), accurate for
/// n > 100.
fn ks_critical(n: usize, alpha: f64) -> f64 {
    (-(alpha / 2.0).ln() / 2.0).sqrt() / (n as f64).sqrt()
}

/// CDF of the class model's gross-weight mixture truncated to its range, t.
fn truncated_mixture_cdf(model: &ClassModel) -> impl Fn(f64) -> f64 + '_ {
    let mass_below = move |w: f64| -> f64 {
        model
            .weight
            .iter()
            .map(|c| c.share * normal_cdf((w - c.mean_t) / c.sd_t))
            .sum()
    };
    move |w: f64| {
        let lo = mass_below(model.weight_min_t);
        (mass_below(w) - lo) / (mass_below(model.weight_max_t) - lo)
    }
}

fn single_class_spec(class: VehicleClass) -> TrafficSpec {
    spec(&format!(
        "lanes = [{{ flow_per_hour = 300 }}]\nclasses = {{ {} = 1.0 }}",
        class.name()
    ))
}

// ---- weights and axles ----

#[test]
fn reference_values_of_sensors_md_are_the_defaults() {
    let artic = VehicleClass::Artic5Axle.default_model();
    let w: Vec<(f64, f64, f64)> = artic
        .weight
        .iter()
        .map(|c| (c.share, c.mean_t, c.sd_t))
        .collect();
    assert_eq!(w, vec![(0.16, 29.6, 5.5), (0.834, 41.2, 5.5)]);
    assert_eq!(artic.spacing_mean_m, vec![3.24, 5.43, 1.20, 1.21]);
    let two = VehicleClass::Truck2Axle.default_model();
    assert_eq!((two.spacing_mean_m[0], two.spacing_sd_m[0]), (5.53, 0.51));
    let shares = bridgetwin::physics::traffic::default_class_shares();
    let trucks = 1.0 - shares["car"];
    assert!((shares["car"] - 0.8).abs() < 1e-12);
    for (name, split) in [
        ("truck_2axle", 0.23),
        ("truck_3axle", 0.028),
        ("truck_4axle", 0.317),
        ("artic_5axle", 0.425),
    ] {
        assert!((shares[name] / trucks - split).abs() < 1e-12, "{name}");
    }
}

#[test]
fn gross_weights_follow_the_truncated_mixtures() {
    // 4000 vehicles per class: the KS critical value at alpha = 0.01 is 0.026, so a
    // component mean off by 1 t in the 5-axle mix (a CDF shift of ~0.06) would fail.
    let n = 4000;
    for class in VehicleClass::ALL {
        let model = class.default_model();
        let weights_t: Vec<f64> = generator(&single_class_spec(class), 11)
            .take(n)
            .map(|v| {
                assert_eq!(v.class, class);
                v.gross_weight_n / (1000.0 * GRAVITY_M_S2)
            })
            .collect();
        assert!(weights_t
            .iter()
            .all(|w| (model.weight_min_t..=model.weight_max_t).contains(w)));
        let d = ks_statistic(weights_t, truncated_mixture_cdf(&model));
        let critical = ks_critical(n, KS_ALPHA);
        println!("{}: D = {d:.4}, critical {critical:.4}", class.name());
        assert!(d < critical, "{}: D = {d} >= {critical}", class.name());
    }
    // Power check: the 5-axle weights fail against the untruncated mixture shifted by 1 t.
    let model = VehicleClass::Artic5Axle.default_model();
    let mut shifted = model.clone();
    shifted.weight.iter_mut().for_each(|c| c.mean_t += 1.0);
    let weights_t: Vec<f64> = generator(&single_class_spec(VehicleClass::Artic5Axle), 11)
        .take(n)
        .map(|v| v.gross_weight_n / (1000.0 * GRAVITY_M_S2))
        .collect();
    assert!(ks_statistic(weights_t, truncated_mixture_cdf(&shifted)) > ks_critical(n, KS_ALPHA));
}

#[test]
fn axle_layouts_and_loads_follow_the_class_models() {
    let n = 4000;
    for class in VehicleClass::ALL {
        let model = class.default_model();
        let vehicles: Vec<GeneratedVehicle> =
            generator(&single_class_spec(class), 5).take(n).collect();
        for v in &vehicles {
            assert_eq!(v.axle_load_n.len(), class.axle_count());
            assert_eq!(v.axle_spacing_m.len(), class.axle_count() - 1);
            let total: f64 = v.axle_load_n.iter().sum();
            assert!((total - v.gross_weight_n).abs() < 1e-9 * v.gross_weight_n);
            assert!(v.axle_load_n.iter().all(|&f| f > 0.0));
        }
        // Means within 4 standard errors (two-sided level 6e-5 per quantity); the sd
        // used is the untruncated one, an upper bound for the truncated draws.
        for (k, (&mean, &sd)) in model
            .spacing_mean_m
            .iter()
            .zip(&model.spacing_sd_m)
            .enumerate()
        {
            let got = vehicles.iter().map(|v| v.axle_spacing_m[k]).sum::<f64>() / n as f64;
            assert!(
                (got - mean).abs() <= 4.0 * sd / (n as f64).sqrt() + 1e-12,
                "{got}"
            );
        }
        let front = vehicles
            .iter()
            .map(|v| v.axle_load_n[0] / v.gross_weight_n)
            .sum::<f64>()
            / n as f64;
        // Renormalisation biases the mean share by O(sd_rel^2) ~ 0.6 %: 2 % tolerance.
        let expected = model.load_share[0];
        assert!((front - expected).abs() < 0.02 * expected, "{front}");
    }
}

#[test]
fn variation_factors_are_reproducible_and_bounded() {
    let a = variation_factors(123, 2000, 0.1);
    assert_eq!(a, variation_factors(123, 2000, 0.1));
    assert_ne!(a, variation_factors(124, 2000, 0.1));
    assert!(a.iter().all(|f| (0.7..=1.3).contains(f)));
    let mean = a.iter().sum::<f64>() / 2000.0;
    // sd of the mean 0.1 / sqrt(2000) = 0.0022; 4 sd.
    assert!((mean - 1.0).abs() < 0.009, "{mean}");
}

// ---- arrivals ----

/// A lane of identical cars at one speed: every minimum headway is the same, so headways
/// are exactly `h_req + Exp(r)` with `r = q / (1 - q * h_req)`.
fn uniform_car_spec(flow_per_hour: f64, speed_m_s: f64) -> TrafficSpec {
    let mut s = spec(&format!(
        "lanes = [{{ flow_per_hour = {flow_per_hour}, speed_mean_m_s = {speed_m_s}, \
         speed_sd_m_s = 0.0 }}]\nclasses = {{ car = 1.0 }}\nhourly_profile = [{}]",
        ["1.0"; 24].join(", ")
    ));
    let mut car = VehicleClass::Car.default_model();
    car.spacing_sd_m = vec![0.0];
    s.models = BTreeMap::from([("car".to_string(), car)]);
    s
}

#[test]
fn headways_at_constant_flow_are_shifted_exponential() {
    let (flow_per_hour, speed_m_s, min_gap_s) = (900.0, 25.0, 1.0);
    let car = VehicleClass::Car.default_model();
    let length_m = car.front_overhang_m + car.spacing_mean_m[0] + car.rear_overhang_m;
    let shift_s = (length_m + min_gap_s * speed_m_s) / speed_m_s;
    let q = flow_per_hour / 3600.0;
    let rate = q / (1.0 - q * shift_s);
    let n = 6000;
    let vehicles: Vec<GeneratedVehicle> = generator(&uniform_car_spec(flow_per_hour, speed_m_s), 3)
        .take(n + 1)
        .collect();
    let headways_s: Vec<f64> = vehicles
        .windows(2)
        .map(|p| p[1].entry_time_s - p[0].entry_time_s)
        .collect();
    let shortest = headways_s.iter().copied().fold(f64::INFINITY, f64::min);
    assert!(shortest >= shift_s - 1e-9, "{shortest} < {shift_s}");
    // The shortest of 6000 gaps exceeds the shift by Exp(n r): ~ 1e-4 s.
    assert!(shortest < shift_s + 0.01, "{shortest}");
    let cdf = |h: f64| 1.0 - (-rate * (h - shift_s).max(0.0)).exp();
    let d = ks_statistic(headways_s.clone(), cdf);
    let critical = ks_critical(n, KS_ALPHA);
    println!("headways: D = {d:.4}, critical {critical:.4}");
    assert!(d < critical, "D = {d} >= {critical}");
    // Power check: the plain exponential of the same mean fails.
    let plain = |h: f64| 1.0 - (-q * h).exp();
    assert!(ks_statistic(headways_s.clone(), plain) > critical);
    // The flow is the requested one: mean headway 1/q within 4 standard errors (sd of a
    // headway = 1/r).
    let mean_s = headways_s.iter().sum::<f64>() / n as f64;
    assert!(
        (mean_s - 1.0 / q).abs() < 4.0 / rate / (n as f64).sqrt(),
        "{mean_s}"
    );
}

#[test]
fn mixed_traffic_keeps_its_mean_flow() {
    // Default class mix, default speeds, 400 veh/h for 100 h: 40 000 vehicles. The count
    // of a renewal process with headway CV < 1 varies less than a Poisson count, so
    // sqrt(q T) bounds its sd; 3.29 sd (alpha = 0.001) plus 0.5 % for the first-order
    // mean-headway estimate (its neglected terms are O(sd^2 / v^2) ~ 0.2 %).
    let s = spec(&format!(
        "lanes = [{{ flow_per_hour = 400 }}]\nhourly_profile = [{}]",
        ["1.0"; 24].join(", ")
    ));
    let hours = 100.0;
    let count = until(&mut generator(&s, 8), hours * 3600.0).len() as f64;
    let expected = 400.0 * hours;
    let bound = 3.29 * expected.sqrt() + 0.005 * expected;
    println!("mixed flow: {count} vehicles, expected {expected} +/- {bound:.0}");
    assert!((count - expected).abs() < bound, "{count}");
}

#[test]
fn hourly_counts_follow_the_profile() {
    // 20 days of one lane at 300 veh/h, counted by hour of day. Pearson chi-square with
    // 24 degrees of freedom (expected counts fixed by the spec, none estimated); critical
    // value 42.98 at alpha = 0.01. Conservative: min-gap headways make counts less
    // dispersed than Poisson.
    let (days, flow_per_hour) = (20.0, 300.0);
    let s = spec(&format!("lanes = [{{ flow_per_hour = {flow_per_hour} }}]"));
    let mut counts = [0.0; 24];
    for v in until(&mut generator(&s, 21), days * 86_400.0) {
        counts[((v.entry_time_s / 3600.0) as usize) % 24] += 1.0;
    }
    let chi_square = |profile: &[f64]| -> f64 {
        counts
            .iter()
            .zip(profile)
            .map(|(&o, &p)| {
                let e = days * flow_per_hour * p;
                (o - e) * (o - e) / e
            })
            .sum()
    };
    const CHI2_24_CRITICAL_0_01: f64 = 42.98;
    let fitted = chi_square(&DEFAULT_HOURLY_PROFILE);
    println!("hourly counts: chi2 = {fitted:.1}, critical {CHI2_24_CRITICAL_0_01}");
    assert!(fitted < CHI2_24_CRITICAL_0_01, "chi2 = {fitted}");
    // Power check: the counts reject a flat day and the profile shifted by one hour.
    assert!(chi_square(&[1.0; 24]) > 100.0 * CHI2_24_CRITICAL_0_01);
    let mut shifted = DEFAULT_HOURLY_PROFILE;
    shifted.rotate_right(1);
    assert!(chi_square(&shifted) > CHI2_24_CRITICAL_0_01);
}

#[test]
fn the_clock_offset_selects_the_hour() {
    // Starting at 03:00 (factor 0.17) versus 08:00 (1.65): the first hour's counts differ
    // by the ratio of the factors.
    let s = spec("lanes = [{ flow_per_hour = 1000 }]");
    let count_from = |hour: f64| {
        let mut r = run(4);
        r.time_of_day_at_zero_s = hour * 3600.0;
        let mut g = TrafficGenerator::new(&s, &r, "traffic").unwrap();
        until(&mut g, 3600.0).len() as f64
    };
    let (night, peak) = (count_from(3.0), count_from(8.0));
    // Expected 170 and 1650; 5 Poisson sd each.
    assert!((night - 170.0).abs() < 5.0 * 170f64.sqrt(), "{night}");
    assert!((peak - 1650.0).abs() < 5.0 * 1650f64.sqrt(), "{peak}");
}

#[test]
fn class_shares_stay_within_binomial_bounds() {
    // 20 000 vehicles; each class count within 3.29 binomial sd (two-sided 0.001 per
    // class, 0.005 over the five, Bonferroni).
    let s = spec("lanes = [{ flow_per_hour = 1000 }]");
    let n = 20_000;
    let mut counts = BTreeMap::<&str, f64>::new();
    for v in generator(&s, 17).take(n) {
        *counts.entry(v.class.name()).or_default() += 1.0;
    }
    for (name, p) in bridgetwin::physics::traffic::default_class_shares() {
        let expected = n as f64 * p;
        let sd = (n as f64 * p * (1.0 - p)).sqrt();
        let got = counts.get(name.as_str()).copied().unwrap_or(0.0);
        println!(
            "{name}: {got} (expected {expected:.0} +/- {:.0})",
            3.29 * sd
        );
        assert!((got - expected).abs() < 3.29 * sd, "{name}: {got}");
    }
}

#[test]
fn a_lane_can_have_its_own_class_mix() {
    let s = spec(
        "lanes = [{ flow_per_hour = 300 }, { direction = -1, flow_per_hour = 300, \
         classes = { car = 0.5, artic_5axle = 0.5 } }]",
    );
    let vehicles = until(&mut generator(&s, 2), 6.0 * 3600.0);
    let lane1: Vec<_> = vehicles.iter().filter(|v| v.lane == 1).collect();
    assert!(lane1.iter().all(|v| v.direction == -1));
    assert!(lane1
        .iter()
        .all(|v| matches!(v.class, VehicleClass::Car | VehicleClass::Artic5Axle)));
    assert!(vehicles
        .iter()
        .any(|v| v.lane == 0 && v.class == VehicleClass::Truck4Axle && v.direction == 1));
}

// ---- the minimum gap, checked geometrically ----

/// Smallest time gap (clear distance / follower speed) between `ahead` and `behind` while
/// both are on the road (front axle in [0, road]), or `None` if never together.
fn smallest_gap_s(ahead: &GeneratedVehicle, behind: &GeneratedVehicle, road_m: f64) -> Option<f64> {
    let start = ahead.entry_time_s.max(behind.entry_time_s);
    let end = (ahead.entry_time_s + road_m / ahead.speed_m_s)
        .min(behind.entry_time_s + road_m / behind.speed_m_s);
    if start > end {
        return None;
    }
    let clear_m = |t: f64| {
        let rear_ahead = ahead.speed_m_s * (t - ahead.entry_time_s)
            - ahead.axle_spacing_m.iter().sum::<f64>()
            - ahead.rear_overhang_m;
        let front_behind = behind.speed_m_s * (t - behind.entry_time_s) + behind.front_overhang_m;
        rear_ahead - front_behind
    };
    // Linear in t: the extremes are at the ends.
    Some(clear_m(start).min(clear_m(end)) / behind.speed_m_s)
}

#[test]
fn vehicles_on_a_lane_never_come_closer_than_the_minimum_gap() {
    // A day on two lanes, speed sd 3 m/s so that fast followers often catch up with slow
    // leaders; every pair within 6 places on a lane is checked over the time both are on
    // the road (vehicles further apart are separated by those in between).
    let s = spec(
        "min_gap_s = 1.0\nlanes = [{ flow_per_hour = 600, speed_sd_m_s = 3.0 }, \
         { direction = -1, flow_per_hour = 400, speed_sd_m_s = 3.0 }]",
    );
    let vehicles = until(&mut generator(&s, 99), 86_400.0);
    let mut tightest_s = f64::INFINITY;
    let mut pairs = 0;
    for lane in 0..2 {
        let on_lane: Vec<&GeneratedVehicle> = vehicles.iter().filter(|v| v.lane == lane).collect();
        for (i, behind) in on_lane.iter().enumerate() {
            for ahead in &on_lane[i.saturating_sub(6)..i] {
                if let Some(gap_s) = smallest_gap_s(ahead, behind, ROAD_LENGTH_M) {
                    pairs += 1;
                    tightest_s = tightest_s.min(gap_s);
                }
            }
        }
    }
    println!(
        "{} vehicles, {pairs} pairs together on the road, tightest gap {tightest_s:.4} s",
        vehicles.len()
    );
    assert!(pairs > 10_000, "{pairs}");
    assert!(tightest_s >= 1.0 - 1e-9, "{tightest_s}");
    // The bound is active (not vacuous): some follower comes within 2 % of it.
    assert!(tightest_s < 1.02, "{tightest_s}");
}

// ---- determinism ----

#[test]
fn same_seed_same_traffic_and_lanes_are_independent() {
    let one = spec("lanes = [{ flow_per_hour = 300 }]");
    let two = spec("lanes = [{ flow_per_hour = 300 }, { direction = -1, flow_per_hour = 200 }]");
    let a = until(&mut generator(&one, 7), 6.0 * 3600.0);
    assert_eq!(a, until(&mut generator(&one, 7), 6.0 * 3600.0));
    assert_ne!(a, until(&mut generator(&one, 8), 6.0 * 3600.0));
    let b = until(&mut generator(&two, 7), 6.0 * 3600.0);
    let without_id = |v: &GeneratedVehicle| GeneratedVehicle { id: 0, ..v.clone() };
    let lane0_alone: Vec<_> = a.iter().map(without_id).collect();
    let lane0_with_other: Vec<_> = b.iter().filter(|v| v.lane == 0).map(without_id).collect();
    assert_eq!(lane0_alone, lane0_with_other);
    assert!(b.iter().any(|v| v.lane == 1));
}

#[test]
fn vehicles_come_in_entry_order_with_sequential_ids() {
    let s = spec("lanes = [{ flow_per_hour = 500 }, { direction = -1, flow_per_hour = 500 }]");
    let mut g = generator(&s, 1);
    assert!(g.next_before(-1.0).is_none());
    let first = g.peek_entry_time_s().unwrap();
    let vehicles = until(&mut g, 3600.0);
    assert_eq!(vehicles[0].entry_time_s, first);
    assert!(vehicles
        .windows(2)
        .all(|p| p[0].entry_time_s <= p[1].entry_time_s));
    assert!(vehicles.iter().zip(1..).all(|(v, id)| v.id == id));
    assert!(vehicles.iter().all(|v| v.entry_time_s <= 3600.0));
    assert!(g.peek_entry_time_s().unwrap() > 3600.0);
    // The withheld vehicle comes next.
    let next = g.next_before(f64::INFINITY).unwrap();
    assert_eq!(next.id, vehicles.len() as u32 + 1);
}

#[test]
fn an_empty_lane_and_an_empty_road() {
    let s = spec("lanes = [{ flow_per_hour = 0 }, { flow_per_hour = 100 }]");
    let vehicles = until(&mut generator(&s, 3), 86_400.0);
    assert!(vehicles.iter().all(|v| v.lane == 1));
    let empty = spec("lanes = [{ flow_per_hour = 0 }]");
    assert!(generator(&empty, 3).next().is_none());
}

// ---- bad inputs ----

fn error_of(toml_text: &str) -> String {
    let s = spec(toml_text);
    let message = TrafficGenerator::new(&s, &run(1), "traffic")
        .expect_err("invalid spec")
        .to_string();
    assert!(
        s.validate("traffic").is_err() || message.contains("saturates"),
        "validate agrees: {message}"
    );
    message
}

#[test]
fn bad_inputs_name_the_field() {
    let cases = [
        (
            "lanes = [{ flow_per_hour = 100 }, { flow_per_hour = -5 }]",
            "traffic.lanes.1.flow_per_hour = -5 ",
        ),
        (
            "lanes = [{ flow_per_hour = 100 }]\nclasses = { car = 0.7, truck_2axle = 0.2 }",
            "traffic.classes = { car = 0.7, truck_2axle = 0.2 } must have shares summing to 1",
        ),
        (
            "lanes = [{ flow_per_hour = 100 }]\nclasses = { car = 0.9, bus = 0.1 }",
            "traffic.classes.bus = 0.1 names no vehicle class",
        ),
        (
            "lanes = [{ flow_per_hour = 100, speed_sd_m_s = -1 }]",
            "traffic.lanes.0.speed_sd_m_s = -1 ",
        ),
        (
            "lanes = [{ flow_per_hour = 100, speed_sd_m_s = 10 }]",
            "traffic.lanes.0.speed_sd_m_s = 10 must be below",
        ),
        (
            "lanes = [{ flow_per_hour = 100 }]\nhourly_profile = [1.0, 2.0]",
            "traffic.hourly_profile = 2 values must have 24",
        ),
        (
            "lanes = [{ flow_per_hour = 100, direction = 0 }]",
            "traffic.lanes.0.direction = 0 ",
        ),
        (
            "lanes = [{ flow_per_hour = 100, classes = { car = 1.1, truck_2axle = -0.1 } }]",
            "traffic.lanes.0.classes.truck_2axle = -0.1 ",
        ),
        ("lanes = []", "traffic.lanes = [] "),
        (
            "lanes = [{ flow_per_hour = 100 }]\nmin_gap_s = 0",
            "traffic.min_gap_s = 0 ",
        ),
        (
            "lanes = [{ flow_per_hour = 3000 }]",
            "traffic.lanes.0.flow_per_hour = 3000 saturates the lane",
        ),
    ];
    for (text, expected) in cases {
        let message = error_of(text);
        assert!(message.starts_with(expected), "{text}\n  gave: {message}");
    }
}

#[test]
fn bad_class_models_name_the_field() {
    let mut s = spec("lanes = [{ flow_per_hour = 100 }]");
    let mut two = VehicleClass::Truck2Axle.default_model();
    two.spacing_sd_m = vec![-0.1];
    s.models = BTreeMap::from([("truck_2axle".to_string(), two)]);
    let e = s.validate("traffic").unwrap_err().to_string();
    assert!(
        e.starts_with("traffic.models.truck_2axle.spacing_sd_m.0 = -0.1 "),
        "{e}"
    );

    let mut artic = VehicleClass::Artic5Axle.default_model();
    artic.load_share = vec![0.5, 0.5];
    s.models = BTreeMap::from([("artic_5axle".to_string(), artic)]);
    let e = s.validate("traffic").unwrap_err().to_string();
    assert!(
        e.starts_with("traffic.models.artic_5axle.load_share = 2 values must have 5"),
        "{e}"
    );

    s.models = BTreeMap::from([("tram".to_string(), VehicleClass::Car.default_model())]);
    let e = s.validate("traffic").unwrap_err().to_string();
    assert!(
        e.starts_with("traffic.models.tram = { ... } names no vehicle class"),
        "{e}"
    );
}

#[test]
fn unknown_fields_are_rejected_when_parsing() {
    let e = toml::from_str::<TrafficSpec>("lanes = [{ flow_per_hour = 100, speed = 3 }]")
        .unwrap_err()
        .to_string();
    assert!(e.contains("speed"), "{e}");
    let e = toml::from_str::<TrafficSpec>("lanes = []\nflow = 3")
        .unwrap_err()
        .to_string();
    assert!(e.contains("flow"), "{e}");
}
