//! Traffic in a run: generated two-way traffic and multi-axle vehicles through the time
//! loop (the generator's statistics are in `tests/suite/traffic.rs`, the vehicle models in
//! `tests/suite/multi_axle.rs`).

use std::collections::BTreeMap;

use bridgetwin::sim::{AxleState, Record};

use crate::common::records_of as records;

const BRIDGE: &str = r#"
[bridge]
span_m = 30.0
flexural_rigidity_n_m2 = 5.629e10
mass_per_length_kg_m = 12000.0
damping_ratio = 0.02
model = { kind = "finite_element", elements = 20 }
"#;

fn axle_snapshots(recs: &[Record]) -> Vec<&Vec<AxleState>> {
    recs.iter()
        .filter_map(|r| match r {
            Record::AxleLoads { axles, .. } => Some(axles),
            _ => None,
        })
        .collect()
}

#[test]
fn two_way_traffic_flows_without_overlaps_and_keeps_every_weight() {
    let toml = format!(
        "seed = 9\nduration_s = 240.0\nstart_time = \"2026-06-01T08:00:00Z\"\n{BRIDGE}\
         [traffic]\nlanes = [{{ direction = 1, flow_per_hour = 700.0 }}, \
         {{ direction = -1, flow_per_hour = 700.0 }}]\n"
    );
    let recs = records(&toml);
    let vehicles: BTreeMap<u32, (u32, i8, f64)> = recs
        .iter()
        .filter_map(|r| match r {
            Record::Vehicle { vehicle, .. } => Some((
                vehicle.vehicle_id,
                (vehicle.lane, vehicle.direction, vehicle.gross_weight_n),
            )),
            _ => None,
        })
        .collect();
    assert!(vehicles.len() > 40, "{} vehicles", vehicles.len());
    for dir in [1, -1] {
        assert!(
            vehicles.values().any(|v| v.1 == dir),
            "no vehicle towards {dir}"
        );
    }
    // Each vehicle's springs and dampers vary (traffic.parameter_sd_rel, default 0.1):
    // the sample sd of ~80 factors lies within 0.1 +/- 25 % (3 sd of the estimate).
    let factors: Vec<f64> = recs
        .iter()
        .filter_map(|r| match r {
            Record::Vehicle { vehicle, .. } => vehicle
                .parameters
                .iter()
                .find(|(name, _)| name == "variation_stiffness_factor")
                .map(|p| p.1),
            _ => None,
        })
        .collect();
    assert!(
        factors.len() + 2 >= vehicles.len(),
        "{} factors",
        factors.len()
    );
    let mean = factors.iter().sum::<f64>() / factors.len() as f64;
    let sd = (factors.iter().map(|f| (f - mean).powi(2)).sum::<f64>() / (factors.len() - 1) as f64)
        .sqrt();
    assert!((0.075..0.125).contains(&sd), "sd {sd}, mean {mean}");
    assert!((mean - 1.0).abs() < 0.04, "mean {mean}");
    let mut several_on_bridge = 0;
    for axles in axle_snapshots(&recs) {
        // Static axle loads add up to each vehicle's weight (1e-9: the same numbers).
        let mut static_by_vehicle: BTreeMap<u32, f64> = BTreeMap::new();
        let mut extent: BTreeMap<u32, (f64, f64)> = BTreeMap::new();
        for a in axles {
            *static_by_vehicle.entry(a.vehicle_id).or_default() += a.static_load_n;
            let e = extent.entry(a.vehicle_id).or_insert((f64::MAX, f64::MIN));
            *e = (e.0.min(a.position_m), e.1.max(a.position_m));
        }
        for (id, sum) in &static_by_vehicle {
            let weight = vehicles[id].2;
            assert!(
                (sum / weight - 1.0).abs() < 1e-9,
                "vehicle {id}: {sum} vs {weight}"
            );
        }
        // No two vehicles of a lane overlap: their axle spans are disjoint.
        let ids: Vec<u32> = extent.keys().copied().collect();
        for (i, a) in ids.iter().enumerate() {
            for b in &ids[i + 1..] {
                if vehicles[a].0 == vehicles[b].0 {
                    let (ea, eb) = (extent[a], extent[b]);
                    assert!(ea.1 < eb.0 || eb.1 < ea.0, "vehicles {a} and {b} overlap");
                }
            }
        }
        // With several vehicles on the bridge the tyre forces carry their weight: on a
        // smooth road the dynamic part (bridge interaction only) stays within 10 % of the
        // static sum.
        let on: Vec<&AxleState> = axles.iter().filter(|a| a.on_bridge).collect();
        let on_ids: std::collections::BTreeSet<u32> = on.iter().map(|a| a.vehicle_id).collect();
        if on_ids.len() >= 2 {
            several_on_bridge += 1;
            let dynamic: f64 = on.iter().map(|a| a.force_n).sum();
            let stat: f64 = on.iter().map(|a| a.static_load_n).sum();
            assert!((dynamic / stat - 1.0).abs() < 0.10, "{dynamic} vs {stat}");
        }
    }
    assert!(
        several_on_bridge > 100,
        "{several_on_bridge} snapshots with 2+ vehicles"
    );
}

#[test]
fn a_slow_articulated_truck_gives_the_static_influence_line_plus_a_small_dynamic_part() {
    // Midspan deflection of a simply supported beam under a load P at x (x <= L/2):
    // P x (3 L^2 - 4 x^2) / (48 EI), mirrored for x > L/2. At 5 m/s on a smooth road the
    // response must follow the sum over the five axles within 5 % of its peak (the
    // dynamic part of a slow crossing, and FE 20's static error of ~1e-3).
    let toml = format!(
        "seed = 1\nduration_s = 12.0\n{BRIDGE}[road]\napproach_m = 15.0\n\
         [[vehicles]]\nmodel = {{ kind = \"articulated\", preset = \"artic_5axle\" }}\nspeed_m_s = 5.0\n\
         [[sensors]]\nid = \"D\"\nkind = \"displacement\"\nposition_m = 15.0\nrate_hz = 200.0\n\
         [output]\naxle_load_rate_hz = 200.0\n"
    );
    let recs = records(&toml);
    let (l, ei) = (30.0, 5.629e10);
    let influence = |x: f64| {
        let x = if x > l / 2.0 { l - x } else { x };
        if !(0.0..=l / 2.0).contains(&x) {
            return 0.0;
        }
        x * (3.0 * l * l - 4.0 * x * x) / (48.0 * ei)
    };
    let static_at: BTreeMap<u64, f64> = recs
        .iter()
        .filter_map(|r| match r {
            Record::AxleLoads { t_ns, axles } => Some((
                *t_ns,
                axles
                    .iter()
                    .filter(|a| a.on_bridge)
                    .map(|a| a.static_load_n * influence(a.position_m))
                    .sum(),
            )),
            _ => None,
        })
        .collect();
    let measured: Vec<(u64, f64)> = recs
        .iter()
        .filter_map(|r| match r {
            Record::Sensor { t_ns, truth, .. } => Some((*t_ns, truth.displacement_m)),
            _ => None,
        })
        .collect();
    let peak = static_at.values().fold(0.0f64, |a, v| a.max(*v));
    assert!(peak > 1e-3, "static peak {peak}");
    let mut worst = 0.0f64;
    for (t, w) in &measured {
        if let Some(s) = static_at.get(t) {
            worst = worst.max((w - s).abs());
        }
    }
    assert!(
        worst < 0.05 * peak,
        "largest dynamic part {worst:e} of {peak:e}"
    );
}
