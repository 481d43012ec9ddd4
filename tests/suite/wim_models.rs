//! WIM station models against their statistical targets: COST 323 class sigmas per
//! criterion, unbiasedness, the 95 % in-tolerance fraction, load consistency, axle
//! patterns and FHWA classes of a realistic traffic mix, the strip-physics noise, flags and
//! seeding. Run with `--nocapture` for the error table.

use bridgetwin::base::random::child_rng;
use bridgetwin::measurement::wim::{
    axle_groups, AxleGroup, Cost323Class, Criterion, LoadReference, WimMeasurement, WimModelSpec,
    WimPassage, WimStation, GROUP_SPACING_MAX_M,
};
use rand::RngExt;
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;

const TONNE_N: f64 = 9_810.0;
const VEHICLES: usize = 2_000;
/// Dynamic load coefficient of the synthetic dynamic forces: they differ from the static
/// loads by 8 % rms, so a model erring against the wrong reference cannot pass.
const DLC: f64 = 0.08;
/// Statistical checks allow 4 standard errors: a correct model fails one with
/// probability ~6e-5 (and the seeds are fixed), a sigma off by the tolerance fails.
const N_SE: f64 = 4.0;

#[derive(Debug, Clone, Copy, PartialEq)]
enum Kind {
    Car,
    TwoAxle,
    ThreeAxle,
    FiveAxle,
}

impl Kind {
    fn pattern(self) -> &'static str {
        match self {
            Kind::Car | Kind::TwoAxle => "1-1",
            Kind::ThreeAxle => "1-2",
            Kind::FiveAxle => "1-1-3",
        }
    }

    /// FHWA class expected from the class definitions (not from the code's table).
    fn fhwa(self) -> u8 {
        match self {
            Kind::Car => 2,
            Kind::TwoAxle => 5,
            Kind::ThreeAxle => 6,
            Kind::FiveAxle => 9,
        }
    }
}

fn normal(rng: &mut ChaCha8Rng, mean: f64, sd: f64) -> f64 {
    let z: f64 = rng.sample(StandardNormal);
    mean + sd * z
}

/// Cars 40 %, 2-axle trucks 20 %, 3-axle 10 %, 5-axle (2-S3) 30 %. Truck figures from
/// docs/sensors.md section 4 (Auxerre): 2-axle spacing 5.53 +/- 0.51 m (kept within 4.5-6.6 m,
/// a 2-axle single unit), front/rear 1/3 : 2/3; 5-axle spacings 3.24, 5.43, 1.20, 1.21 m,
/// gross 0.16 x N(29.6, 5.5) t + 0.84 x N(41.2, 5.5) t; speed N(89, 3.6) km/h.
fn traffic(seed: u64) -> Vec<(Kind, WimPassage)> {
    let mut rng = child_rng(seed, "test/traffic");
    (0..VEHICLES)
        .map(|i| {
            let u: f64 = rng.random();
            let kind = match u {
                u if u < 0.4 => Kind::Car,
                u if u < 0.6 => Kind::TwoAxle,
                u if u < 0.7 => Kind::ThreeAxle,
                _ => Kind::FiveAxle,
            };
            (kind, passage(kind, i as u32, &mut rng))
        })
        .collect()
}

fn passage(kind: Kind, id: u32, rng: &mut ChaCha8Rng) -> WimPassage {
    let (spacing_m, shares, gross_t) = match kind {
        Kind::Car => {
            let front = rng.random_range(0.52..0.6);
            let gross = normal(rng, 1.5, 0.2).clamp(1.0, 2.2);
            (vec![normal(rng, 2.7, 0.1)], vec![front, 1.0 - front], gross)
        }
        Kind::TwoAxle => {
            let front = normal(rng, 1.0 / 3.0, 0.03);
            let spacing = normal(rng, 5.53, 0.51).clamp(4.5, 6.6);
            let gross = normal(rng, 15.0, 3.0).clamp(7.0, 20.0);
            (vec![spacing], vec![front, 1.0 - front], gross)
        }
        Kind::ThreeAxle => {
            let tandem = 0.7 * normal(rng, 0.5, 0.03);
            let spacings = vec![normal(rng, 4.5, 0.3), normal(rng, 1.35, 0.05)];
            let gross = normal(rng, 24.0, 3.0).clamp(12.0, 30.0);
            (spacings, vec![0.3, tandem, 0.7 - tandem], gross)
        }
        Kind::FiveAxle => {
            let heavy: f64 = rng.random();
            let mean_t = if heavy < 0.16 { 29.6 } else { 41.2 };
            let gross = normal(rng, mean_t, 5.5).clamp(15.0, 50.0);
            let t: Vec<f64> = (0..3).map(|_| normal(rng, 0.19, 0.01)).collect();
            let shares = [0.16, 0.27, t[0], t[1], t[2]];
            let sum: f64 = shares.iter().sum();
            let shares = shares.iter().map(|s| s / sum).collect();
            (vec![3.24, 5.43, 1.20, 1.21], shares, gross)
        }
    };
    let static_axle_load_n: Vec<f64> = shares.iter().map(|s| s * gross_t * TONNE_N).collect();
    let dynamic_axle_load_n = static_axle_load_n
        .iter()
        .map(|l| l * (1.0 + DLC * normal(rng, 0.0, 1.0)))
        .collect();
    WimPassage {
        vehicle_id: id,
        lane: 0,
        t_first_axle_ns: u64::from(id) * 3_000_000_000,
        speed_m_s: normal(rng, 89.0, 3.6) / 3.6,
        axle_spacing_m: spacing_m,
        static_axle_load_n,
        dynamic_axle_load_n,
        multiple_presence: false,
    }
}

fn measure_all(
    spec: &WimModelSpec,
    traffic: &[(Kind, WimPassage)],
    stream: &str,
) -> Vec<WimMeasurement> {
    let station = WimStation::new(spec, "wim_stations.0.model").unwrap();
    let mut rng = child_rng(42, stream);
    traffic
        .iter()
        .map(|(_, p)| station.measure(p, &mut rng))
        .collect()
}

/// Relative errors of one criterion, grouped by vehicle (a vehicle's errors are correlated,
/// so the standard errors count vehicles, not samples).
#[derive(Default)]
struct Sample {
    errors: Vec<f64>,
    vehicles: usize,
}

impl Sample {
    fn add_vehicle(&mut self, errors: impl IntoIterator<Item = f64>) {
        let before = self.errors.len();
        self.errors.extend(errors);
        if self.errors.len() > before {
            self.vehicles += 1;
        }
    }

    fn mean(&self) -> f64 {
        self.errors.iter().sum::<f64>() / self.errors.len() as f64
    }

    fn sigma(&self) -> f64 {
        let mean = self.mean();
        let ss: f64 = self.errors.iter().map(|e| (e - mean).powi(2)).sum();
        (ss / (self.errors.len() - 1) as f64).sqrt()
    }

    fn fraction_within(&self, tolerance: f64) -> f64 {
        let inside = self.errors.iter().filter(|e| e.abs() < tolerance).count();
        inside as f64 / self.errors.len() as f64
    }
}

/// The four criteria's relative errors against the static loads, recomputed from the
/// reported loads (not from the station's truth fields).
fn criteria(traffic: &[(Kind, WimPassage)], records: &[WimMeasurement]) -> [Sample; 4] {
    let mut samples: [Sample; 4] = Default::default();
    for ((_, p), m) in traffic.iter().zip(records) {
        let gross_n: f64 = p.static_axle_load_n.iter().sum();
        samples[0].add_vehicle([m.gross_weight_n / gross_n - 1.0]);
        let rel = |g: &AxleGroup| {
            let truth: f64 = p.static_axle_load_n[g.axles()].iter().sum();
            g.load_n / truth - 1.0
        };
        let axle_rel = |i: usize| m.axle_load_n[i] / p.static_axle_load_n[i] - 1.0;
        let multi = || m.groups.iter().filter(|g| g.axle_count >= 2);
        samples[1].add_vehicle(multi().map(rel).collect::<Vec<_>>());
        let singles = m.groups.iter().filter(|g| g.axle_count == 1).map(rel);
        samples[2].add_vehicle(singles.collect::<Vec<_>>());
        samples[3].add_vehicle(
            multi()
                .flat_map(|g| g.axles())
                .map(axle_rel)
                .collect::<Vec<_>>(),
        );
    }
    samples
}

#[test]
fn cost323_classes_reach_their_sigma_for_every_criterion() {
    let traffic = traffic(1);
    println!(
        "\nCOST 323 synthetic errors, {VEHICLES} vehicles (40 % cars, 20 % 2-axle, 10 % 3-axle, \
         30 % 5-axle 2-S3), relative to static loads"
    );
    println!("| class | criterion | delta % | target sigma % | measured sigma % | mean % | within delta | n (vehicles) |");
    println!("|---|---|---|---|---|---|---|---|");
    for class in Cost323Class::ALL {
        let spec = WimModelSpec::Cost323 {
            class: class.name().into(),
            speed_sigma_rel: 0.01,
        };
        let records = measure_all(&spec, &traffic, class.name());
        let samples = criteria(&traffic, &records);
        for (criterion, sample) in Criterion::ALL.iter().zip(&samples) {
            check_criterion(class, *criterion, sample);
        }
    }
}

fn check_criterion(class: Cost323Class, criterion: Criterion, sample: &Sample) {
    let target = class.sigma_rel(criterion);
    let delta = class.tolerance_pct(criterion) / 100.0;
    let (sigma, mean, within) = (sample.sigma(), sample.mean(), sample.fraction_within(delta));
    let n = sample.vehicles as f64;
    println!(
        "| {} | {} | {} | {:.1} | {:.2} | {:+.2} | {:.3} | {} |",
        class.name(),
        criterion.name(),
        class.tolerance_pct(criterion),
        100.0 * target,
        100.0 * sigma,
        100.0 * mean,
        within,
        sample.vehicles
    );
    // Standard error of a sample sigma: sigma / sqrt(2 n) (Gaussian); n = vehicles, which
    // is conservative since a vehicle's errors in one criterion are not more variable than
    // one error. 400 vehicles or more: 4 SE <= 14 %, 2 000: 6.3 %.
    let sigma_tol = N_SE / (2.0 * n).sqrt();
    // Power: a sigma 15 % off (e.g. the next class's half-way point) must be detectable.
    assert!(
        sigma_tol < 0.15,
        "too few vehicles ({n}) for {}",
        criterion.name()
    );
    assert!(
        (sigma / target - 1.0).abs() < sigma_tol,
        "{} {}: sigma {sigma} vs target {target} (tolerance {sigma_tol})",
        class.name(),
        criterion.name()
    );
    // Standard error of the mean: sigma / sqrt(n).
    assert!(
        mean.abs() < N_SE * target / n.sqrt(),
        "{} {}: mean {mean}",
        class.name(),
        criterion.name()
    );
    // P(|e| < 2 sigma) = 0.9545 for a Gaussian; binomial standard error sqrt(p (1-p) / n)
    // (0.0047 for 2 000 vehicles, ~0.01 for 400).
    let p = 0.9545;
    let within_tol = N_SE * (p * (1.0 - p) / n).sqrt();
    assert!(
        (within - p).abs() < within_tol,
        "{} {}: {within} within delta",
        class.name(),
        criterion.name()
    );
}

#[test]
fn every_vehicle_of_the_mix_gets_the_exact_class_sigmas() {
    // The hierarchical draw is exact per vehicle, not only over the mix: the planned
    // sigmas of every group and axle equal the class sigma (closed form, to rounding).
    let traffic = traffic(2);
    for class in Cost323Class::ALL {
        for (kind, p) in &traffic {
            let groups = axle_groups(
                &p.axle_spacing_m,
                &p.static_axle_load_n,
                GROUP_SPACING_MAX_M,
            );
            let plan = class.plan(&p.static_axle_load_n, &groups);
            for (g, sigma) in groups.iter().zip(plan.group_sigmas()) {
                let want = class.sigma_rel(if g.axle_count >= 2 {
                    Criterion::GroupOfAxles
                } else {
                    Criterion::SingleAxle
                });
                assert!((sigma - want).abs() < 1e-12, "{kind:?} {sigma} vs {want}");
            }
            let axle_sigmas = plan.axle_sigmas();
            for g in groups.iter().filter(|g| g.axle_count >= 2) {
                for i in g.axles() {
                    let want = class.sigma_rel(Criterion::AxleOfGroup);
                    assert!((axle_sigmas[i] - want).abs() < 1e-12, "{kind:?}");
                }
            }
        }
    }
}

#[test]
fn loads_add_up_and_patterns_and_classes_are_recognised() {
    let traffic = traffic(3);
    let spec = WimModelSpec::Cost323 {
        class: "D+(20)".into(),
        speed_sigma_rel: 0.01,
    };
    let records = measure_all(&spec, &traffic, "consistency");
    for ((kind, p), m) in traffic.iter().zip(&records) {
        let sum: f64 = m.axle_load_n.iter().sum();
        assert!((m.gross_weight_n - sum).abs() <= 1e-12 * sum);
        for g in &m.groups {
            let group_sum: f64 = m.axle_load_n[g.axles()].iter().sum();
            assert!((g.load_n - group_sum).abs() <= 1e-12 * group_sum);
        }
        // The gross error is the load-weighted mean of the axle errors it reports.
        let static_gross: f64 = p.static_axle_load_n.iter().sum();
        assert!((m.truth.gross_rel - (m.gross_weight_n / static_gross - 1.0)).abs() < 1e-12);
        assert_eq!(m.truth.reference, LoadReference::Static);
        assert_eq!(m.axle_pattern, kind.pattern(), "{kind:?}");
        assert_eq!(m.fhwa_class, Some(kind.fhwa()), "{kind:?} {m:?}");
        // Spacings carry the speed error: measured / true spacing = measured / true speed.
        let speed_ratio = m.speed_m_s / p.speed_m_s;
        for (measured, truth) in m.axle_spacing_m.iter().zip(&p.axle_spacing_m) {
            assert!((measured / truth - speed_ratio).abs() < 1e-12);
        }
        assert!(m.flags.is_empty());
    }
    // Speed error sigma 1 %: 2 000 draws, 4 SE = 6.3 %.
    let speed = Sample {
        errors: records.iter().map(|m| m.truth.speed_rel).collect(),
        vehicles: VEHICLES,
    };
    assert!((speed.sigma() / 0.01 - 1.0).abs() < N_SE / (2.0 * VEHICLES as f64).sqrt());
}

#[test]
fn physics_model_errs_by_noise_rel_against_the_dynamic_force() {
    let traffic = traffic(4);
    let noise_rel = 0.02;
    let spec = WimModelSpec::Physics {
        noise_rel,
        speed_sigma_rel: 0.01,
    };
    let records = measure_all(&spec, &traffic, "physics");
    let mut dynamic = Sample::default();
    let mut against_static = Sample::default();
    for ((_, p), m) in traffic.iter().zip(&records) {
        let e = m.axle_load_n.iter().zip(&p.dynamic_axle_load_n);
        dynamic.add_vehicle(
            e.map(|(meas, dynamic)| meas / dynamic - 1.0)
                .collect::<Vec<_>>(),
        );
        let gross_n: f64 = p.static_axle_load_n.iter().sum();
        against_static.add_vehicle([m.gross_weight_n / gross_n - 1.0]);
    }
    // Axle draws are independent here, so the standard errors count axles (~5 600).
    let n = dynamic.errors.len() as f64;
    println!(
        "physics noise_rel {noise_rel}: axle error vs dynamic force sigma {:.4}, mean {:+.5} \
         ({n} axles); gross vs static sigma {:.4} (DLC {DLC} emerges)",
        dynamic.sigma(),
        dynamic.mean(),
        against_static.sigma()
    );
    assert!((dynamic.sigma() / noise_rel - 1.0).abs() < N_SE / (2.0 * n).sqrt());
    assert!(dynamic.mean().abs() < N_SE * noise_rel / n.sqrt());
    // Against the static weight the dynamic force dominates: the class is emergent.
    assert!(against_static.sigma() > 2.0 * noise_rel);
}

#[test]
fn same_seed_same_records_and_other_seed_other_records() {
    let traffic = traffic(5);
    for spec in [
        WimModelSpec::Cost323 {
            class: "B(10)".into(),
            speed_sigma_rel: 0.01,
        },
        WimModelSpec::Physics {
            noise_rel: 0.03,
            speed_sigma_rel: 0.01,
        },
    ] {
        let a = measure_all(&spec, &traffic[..50], "wim/W1");
        let b = measure_all(&spec, &traffic[..50], "wim/W1");
        let c = measure_all(&spec, &traffic[..50], "wim/W2");
        assert_eq!(a, b);
        assert_ne!(a[0].axle_load_n, c[0].axle_load_n);
    }
}

#[test]
fn station_flags_and_unknown_class() {
    let mut p = traffic(6).remove(0).1;
    p.speed_m_s = 1.0;
    p.multiple_presence = true;
    let station = WimStation::new(&WimModelSpec::default(), "wim_stations.0.model").unwrap();
    let m = station.measure(&p, &mut child_rng(1, "wim/x"));
    assert_eq!(m.flags, vec!["low_speed", "multiple_presence"]);
    let spec = WimModelSpec::Cost323 {
        class: "E(30)".into(),
        speed_sigma_rel: 0.01,
    };
    let e = WimStation::new(&spec, "wim_stations.3.model").unwrap_err();
    let text = e.to_string();
    assert!(
        text.starts_with("wim_stations.3.model.class = \"E(30)\""),
        "{text}"
    );
    assert!(text.contains("A(5), B+(7), B(10), C(15), D+(20)"), "{text}");
}
