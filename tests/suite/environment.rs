//! Temperature and damage driving the bridge stiffness: each law against
//! its closed form, the noise against its statistics, and the frequencies of rebuilt
//! models against sqrt(E) scaling and the exact stepped beam.

use std::f64::consts::{PI, TAU};
use std::path::Path;

use bridgetwin::physics::bridge::{
    BeamProperties, BridgeModel, Girder, ModelSpec, StiffnessRegion,
};
use bridgetwin::physics::environment::{
    damage_events, validate_damage, AirTemperature, DailySpec, DamageSpec, EnvironmentModel,
    EnvironmentSpec, Growth, OrnsteinUhlenbeck, RebuildPolicy, StiffnessState, TemperatureSpec,
    TemperatureStiffnessLaw, TemperatureTable, ThermalLag, DAY_S,
};
use bridgetwin::studies::analytic::{Segment, SteppedBeam};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

fn rng(seed: u64) -> ChaCha8Rng {
    ChaCha8Rng::seed_from_u64(seed)
}

fn daily(mean_c: f64, amplitude_c: f64, peak_hour: f64, noise_sd_c: f64) -> TemperatureSpec {
    TemperatureSpec::Daily(DailySpec {
        mean_c,
        amplitude_c,
        peak_hour,
        noise_sd_c,
        noise_correlation_s: 3600.0,
    })
}

// ---------------------------------------------------------------- scenario parsing

#[test]
fn scenario_section_parses_every_kind_and_rejects_unknown_fields() {
    #[derive(serde::Deserialize)]
    struct Doc {
        environment: EnvironmentSpec,
        #[serde(default)]
        damage: Vec<DamageSpec>,
    }
    let doc: Doc = toml::from_str(
        r#"
        [environment]
        temperature = { kind = "daily", mean_c = 10, amplitude_c = 8, peak_hour = 15, noise_sd_c = 0.5, noise_correlation_s = 3600 }
        lag_s = 7200
        [[damage]]
        start_m = 14
        end_m = 15.5
        reduction = 0.2
        onset_s = 600
        growth = { kind = "linear", duration_s = 300 }
        [[damage]]
        start_m = 3
        end_m = 4
        reduction = 0.1
        onset_s = 60
        "#,
    )
    .unwrap();
    assert_eq!(doc.environment.temperature, daily(10.0, 8.0, 15.0, 0.5));
    assert_eq!(doc.environment.lag_s, 7200.0);
    assert_eq!(doc.damage[0].growth, Growth::Linear { duration_s: 300.0 });
    assert_eq!(doc.damage[1].growth, Growth::Step);
    doc.environment.validate("environment").unwrap();
    validate_damage(&doc.damage, 30.0).unwrap();

    let csv: EnvironmentSpec =
        toml::from_str(r#"temperature = { kind = "csv", path = "temps.csv" }"#).unwrap();
    assert_eq!(
        csv.temperature,
        TemperatureSpec::Csv {
            path: "temps.csv".into()
        }
    );
    let default: EnvironmentSpec = toml::from_str("").unwrap();
    assert_eq!(default, EnvironmentSpec::default());
    assert_eq!(
        default.temperature,
        TemperatureSpec::Constant { value_c: 20.0 }
    );

    let typo = toml::from_str::<EnvironmentSpec>("lag_hours = 3")
        .unwrap_err()
        .to_string();
    assert!(typo.contains("lag_hours"), "{typo}");
    let typo =
        toml::from_str::<EnvironmentSpec>(r#"temperature = { kind = "constant", value = 20 }"#)
            .unwrap_err()
            .to_string();
    assert!(typo.contains("value"), "{typo}");
}

#[test]
fn default_environment_leaves_the_beam_unchanged() {
    // Constant 20 degC = the default reference temperature: factor exactly 1, no regions.
    let spec = EnvironmentSpec::default();
    let air = AirTemperature::new(&spec.temperature, 0.0, Path::new("."), rng(1)).unwrap();
    let mut env =
        EnvironmentModel::new(&spec, &[], &[], &Girder::simply_supported(30.0), air).unwrap();
    let base = BeamProperties::paper_default();
    for t_s in [0.0, 10.0, 1e5] {
        let state = env.state_at(t_s);
        assert_eq!(state.global_factor, 1.0);
        assert_eq!(state.beam_at(&base), base);
    }
}

#[test]
fn invalid_environment_fields_are_named() {
    let cases: Vec<(EnvironmentSpec, &str)> = vec![
        (
            EnvironmentSpec {
                lag_s: 0.0,
                ..Default::default()
            },
            "environment.lag_s",
        ),
        (
            EnvironmentSpec {
                temperature: daily(10.0, -1.0, 15.0, 0.0),
                ..Default::default()
            },
            "environment.temperature.amplitude_c",
        ),
        (
            EnvironmentSpec {
                temperature: daily(10.0, 8.0, 24.0, 0.0),
                ..Default::default()
            },
            "environment.temperature.peak_hour",
        ),
        (
            EnvironmentSpec {
                stiffness: TemperatureStiffnessLaw {
                    slope_above_knee_per_c: -0.02,
                    ..Default::default()
                },
                ..Default::default()
            },
            "environment.stiffness.slope_above_knee_per_c",
        ),
    ];
    for (spec, field) in cases {
        let msg = spec.validate("environment").unwrap_err().to_string();
        assert!(msg.starts_with(field), "{field}: {msg}");
    }
}

// ---------------------------------------------------------------- air temperature

#[test]
fn daily_cycle_has_its_mean_amplitude_and_peak_hour() {
    // Noise-free, sampled every minute over 3 days starting at 06:00: the mean of whole
    // days of a sampled cosine is exact (sum of a full period of roots of unity = 0), so
    // the tolerance is round-off.
    let start_time_of_day_s = 6.0 * 3600.0;
    let spec = daily(10.0, 8.0, 15.0, 0.0);
    let mut air = AirTemperature::new(&spec, start_time_of_day_s, Path::new("."), rng(1)).unwrap();
    let step_s = 60.0;
    let samples: Vec<(f64, f64)> = (0..3 * 1440)
        .map(|i| {
            let t_s = i as f64 * step_s;
            (t_s, air.air_c(t_s))
        })
        .collect();
    let mean_c = samples.iter().map(|s| s.1).sum::<f64>() / samples.len() as f64;
    assert!((mean_c - 10.0).abs() < 1e-12, "mean {mean_c}");
    for day in 0..3 {
        let one_day = &samples[day * 1440..(day + 1) * 1440];
        let (t_max_s, max_c) =
            one_day
                .iter()
                .copied()
                .fold((0.0, f64::MIN), |a, b| if b.1 > a.1 { b } else { a });
        let min_c = one_day.iter().map(|s| s.1).fold(f64::MAX, f64::min);
        let hour_of_day = ((start_time_of_day_s + t_max_s) % DAY_S) / 3600.0;
        assert!(
            (hour_of_day - 15.0).abs() < 1e-9,
            "day {day}: peak at {hour_of_day} h"
        );
        assert!((max_c - 18.0).abs() < 1e-12 && (min_c - 2.0).abs() < 1e-12);
    }
}

#[test]
fn red_noise_has_its_variance_and_correlation_time_at_any_step() {
    // sd 0.5 degC, tau 3600 s. At step tau/10 over 1e5 tau: about 5e4 independent
    // stretches, so the variance is known to sqrt(2 * 2 tau / T) = 0.6 % (1 sd) and the
    // lag-1 correlation exp(-0.1) to about 1e-3; tolerances are 5 sd. At step 2 tau the
    // correlation exp(-2) = 0.135 checks the exact transition (Euler would give -1).
    let (sd_c, tau_s) = (0.5, 3600.0);
    for (step_s, n, seed) in [(tau_s / 10.0, 1_000_000, 7), (2.0 * tau_s, 200_000, 8)] {
        let mut noise = OrnsteinUhlenbeck::new(sd_c, tau_s, 0.0, rng(seed));
        let x: Vec<f64> = (0..n).map(|i| noise.at(i as f64 * step_s)).collect();
        let mean = x.iter().sum::<f64>() / n as f64;
        let var = x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n as f64;
        let lag1 = x
            .windows(2)
            .map(|w| (w[0] - mean) * (w[1] - mean))
            .sum::<f64>()
            / ((n - 1) as f64 * var);
        let rho = (-step_s / tau_s).exp();
        let var_rel_sd = (2.0 * 2.0 * tau_s.max(step_s) / (n as f64 * step_s)).sqrt();
        assert!(
            (var / (sd_c * sd_c) - 1.0).abs() < 5.0 * var_rel_sd,
            "step {step_s}: variance {var}"
        );
        let rho_sd = ((1.0 - rho * rho) / n as f64).sqrt().max(1e-3);
        assert!(
            (lag1 - rho).abs() < 5.0 * rho_sd,
            "step {step_s}: lag-1 {lag1} vs {rho}"
        );
        let tau_est_s = -step_s / lag1.ln();
        if step_s < tau_s {
            assert!((tau_est_s / tau_s - 1.0).abs() < 0.02, "tau {tau_est_s}");
        }
    }
}

#[test]
fn noise_is_reproducible_and_repeated_times_draw_nothing() {
    let spec = daily(10.0, 8.0, 15.0, 0.5);
    let series = |seed| {
        let mut air = AirTemperature::new(&spec, 0.0, Path::new("."), rng(seed)).unwrap();
        (0..100)
            .map(|i| air.air_c(f64::from(i / 2) * 60.0))
            .collect::<Vec<_>>()
    };
    let a = series(3);
    assert_eq!(a, series(3));
    assert_ne!(a, series(4));
    assert!(a.chunks(2).all(|pair| pair[0] == pair[1]));
}

// ---------------------------------------------------------------- CSV records

const CSV: &str = "time_s,temperature_c\n# comment\n0,10\n3600,12\n\n7200,6.5\n";

#[test]
fn csv_interpolates_exactly_at_nodes_and_midpoints() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("temps.csv"), CSV).unwrap();
    let spec = TemperatureSpec::Csv {
        path: "temps.csv".into(),
    };
    let mut air = AirTemperature::new(&spec, 0.0, dir.path(), rng(1)).unwrap();
    let expected = [
        (-5.0, 10.0),
        (0.0, 10.0),
        (1800.0, 11.0),
        (3600.0, 12.0),
        (5400.0, 9.25),
        (7200.0, 6.5),
        (9000.0, 6.5),
    ];
    for (t_s, value_c) in expected {
        assert_eq!(air.air_c(t_s), value_c, "t = {t_s}");
    }
    // Going back in time is answered too (searched, not streamed).
    assert_eq!(air.air_c(900.0), 10.5);
    assert_eq!(air.air_c(5400.0), 9.25);
}

#[test]
fn csv_errors_name_the_file_and_line() {
    let cases = [
        (
            "time_s,temperature_c\n0,10\n60,abc\n",
            "line 3",
            "temperature_c = `abc`",
        ),
        ("time_s,temperature_c\n0,10\n60,NaN\n", "line 3", "finite"),
        ("time_s,temperature_c\n0,10\n60\n", "line 3", "2 columns"),
        (
            "time_s,temperature_c\n0,10\n60,11\n60,12\n",
            "line 4",
            "must exceed",
        ),
        (
            "time_s,temperature_c\n0,10\n60,11\n30,12\n",
            "line 4",
            "must exceed",
        ),
        ("temperature_c,time_s\n0,10\n", "line 1", "header"),
        ("time_s,temperature_c\n", "", "no data rows"),
        ("", "", "empty"),
    ];
    for (text, line, reason) in cases {
        let msg = TemperatureTable::parse(text, "temps.csv")
            .unwrap_err()
            .to_string();
        assert!(
            msg.starts_with("temps.csv: ") && msg.contains(line) && msg.contains(reason),
            "{msg}"
        );
    }
    let missing = TemperatureSpec::Csv {
        path: "missing.csv".into(),
    };
    let msg = AirTemperature::new(&missing, 0.0, Path::new("/nonexistent"), rng(1))
        .unwrap_err()
        .to_string();
    assert!(
        msg.contains("missing.csv") && msg.contains("environment.temperature.path"),
        "{msg}"
    );
}

// ---------------------------------------------------------------- thermal lag

#[test]
fn lag_step_response_is_the_exact_exponential_at_any_step() {
    // Air jumps to 1 degC at t = 0 with the structure at 0: T(t) = 1 - exp(-t / tau),
    // 63.2 % at one tau, whether reached in 1 or 1000 steps.
    let tau_s = 3.0 * 3600.0;
    for steps in [1, 7, 1000] {
        let mut lag = ThermalLag::new(tau_s, 0.0);
        lag.step(0.0, 1.0);
        let mut structure_c = 0.0;
        for k in 1..=steps {
            structure_c = lag.step(tau_s * k as f64 / steps as f64, 1.0);
        }
        let exact = 1.0 - (-1.0f64).exp();
        assert!(
            (structure_c - exact).abs() < 1e-14,
            "{steps} steps: {structure_c}"
        );
        assert!((structure_c - 0.632).abs() < 5e-4);
    }
}

#[test]
fn lag_of_a_ramp_is_exact_for_any_step() {
    // Air a(t) = r t from equilibrium: T(t) = r t - r tau (1 - exp(-t / tau)).
    let (tau_s, r_c_per_s) = (1000.0, 1e-3);
    let exact = |t_s: f64| r_c_per_s * t_s - r_c_per_s * tau_s * (1.0 - (-t_s / tau_s).exp());
    for step_s in [1.0, 250.0, 5000.0] {
        let mut lag = ThermalLag::new(tau_s, 0.0);
        for k in 0..=(20_000.0 / step_s) as u32 {
            let t_s = f64::from(k) * step_s;
            let structure_c = lag.step(t_s, r_c_per_s * t_s);
            // Round-off: up to 20 000 steps of 1e-16 relative on values up to 19 degC.
            let error_c = (structure_c - exact(t_s)).abs();
            assert!(error_c < 1e-11, "step {step_s}, t {t_s}: error {error_c}");
        }
    }
}

#[test]
fn settled_start_follows_the_periodic_lag_of_the_daily_cycle() {
    // Started on the settled value, the noise-free structure temperature is the periodic
    // solution mean + A cos(phase - phi) / sqrt(1 + (w tau)^2) from the first step; the
    // first-order hold of a cosine sampled every 60 s errs by O((w h)^2) ~ 2e-5 of A.
    let (tau_s, start_s) = (3.0 * 3600.0, 2.0 * 3600.0);
    let spec = DailySpec {
        mean_c: 10.0,
        amplitude_c: 8.0,
        peak_hour: 15.0,
        noise_sd_c: 0.0,
        noise_correlation_s: 3600.0,
    };
    let mut air = AirTemperature::new(
        &TemperatureSpec::Daily(spec),
        start_s,
        Path::new("."),
        rng(1),
    )
    .unwrap();
    let mut lag = ThermalLag::new(tau_s, air.settled_structure_c(tau_s));
    let w_tau = TAU / DAY_S * tau_s;
    for i in 0..2 * 1440 {
        let t_s = 60.0 * f64::from(i);
        let structure_c = lag.step(t_s, air.air_c(t_s));
        let phase = TAU * (start_s + t_s - 15.0 * 3600.0) / DAY_S;
        let periodic_c = 10.0 + 8.0 * (phase - w_tau.atan()).cos() / (1.0 + w_tau * w_tau).sqrt();
        assert!(
            (structure_c - periodic_c).abs() < 1e-3,
            "t {t_s}: {structure_c} vs {periodic_c}"
        );
    }
}

// ---------------------------------------------------------------- stiffness law

#[test]
fn bilinear_law_is_continuous_at_the_knee_with_its_slopes() {
    let law = TemperatureStiffnessLaw {
        reference_c: 10.0,
        knee_c: 0.0,
        slope_above_knee_per_c: -0.0015,
        slope_below_knee_per_c: -0.03,
    };
    law.validate("environment.stiffness").unwrap();
    assert_eq!(law.factor(10.0), 1.0);
    let at_knee = law.factor(0.0);
    assert!((at_knee - 1.015).abs() < 1e-15);
    let eps = 1e-9;
    assert!(
        (law.factor(eps) - at_knee).abs() < 1e-10 && (law.factor(-eps) - at_knee).abs() < 1e-10
    );
    // Slopes by finite differences on each side (exact for linear pieces up to round-off).
    let above = (law.factor(25.0) - law.factor(5.0)) / 20.0;
    let below = (law.factor(-2.0) - law.factor(-12.0)) / 10.0;
    assert!((above + 0.0015).abs() < 1e-14 && (below + 0.03).abs() < 1e-14);
    // -10 degC: 1.015 + 0.30 on E.
    assert!((law.factor(-10.0) - 1.315).abs() < 1e-14);
    // Held at the ends of the validated range.
    assert_eq!(law.factor(-500.0), law.factor(-60.0));
}

// ---------------------------------------------------------------- damage laws

#[test]
fn damage_growth_laws_are_exact() {
    let at = |growth, t_s| {
        DamageSpec {
            start_m: 10.0,
            end_m: 11.0,
            reduction: 0.2,
            onset_s: 100.0,
            growth,
        }
        .ei_loss_at(t_s)
    };
    assert_eq!(at(Growth::Step, 99.999), 0.0);
    assert_eq!(at(Growth::Step, 100.0), 0.2);
    let linear = Growth::Linear { duration_s: 50.0 };
    assert_eq!(at(linear, 100.0), 0.0);
    assert!((at(linear, 125.0) - 0.1).abs() < 1e-16);
    assert_eq!(at(linear, 150.0), 0.2);
    assert_eq!(at(linear, 1e6), 0.2);
    let exponential = Growth::Exponential {
        time_constant_s: 40.0,
    };
    assert_eq!(at(exponential, 50.0), 0.0);
    assert!((at(exponential, 140.0) - 0.2 * (1.0 - (-1.0f64).exp())).abs() < 1e-16);
    assert!((at(exponential, 180.0) - 0.2 * (1.0 - (-2.0f64).exp())).abs() < 1e-16);
}

#[test]
fn damage_validation_names_the_entry_and_field() {
    let ok = DamageSpec {
        start_m: 10.0,
        end_m: 11.0,
        reduction: 0.2,
        onset_s: 0.0,
        growth: Growth::Step,
    };
    let cases = [
        (
            DamageSpec {
                start_m: -1.0,
                ..ok.clone()
            },
            "damage.1.start_m = -1",
        ),
        (
            DamageSpec {
                end_m: 31.0,
                ..ok.clone()
            },
            "damage.1.end_m = 31",
        ),
        (
            DamageSpec {
                end_m: 10.0,
                ..ok.clone()
            },
            "damage.1.end_m = 10",
        ),
        (
            DamageSpec {
                reduction: 1.0,
                ..ok.clone()
            },
            "damage.1.reduction = 1",
        ),
        (
            DamageSpec {
                reduction: 0.0,
                ..ok.clone()
            },
            "damage.1.reduction = 0",
        ),
        (
            DamageSpec {
                onset_s: f64::NAN,
                ..ok.clone()
            },
            "damage.1.onset_s = NaN",
        ),
        (
            DamageSpec {
                growth: Growth::Linear { duration_s: 0.0 },
                ..ok.clone()
            },
            "damage.1.growth.duration_s = 0",
        ),
        (
            DamageSpec {
                growth: Growth::Exponential {
                    time_constant_s: -1.0,
                },
                ..ok.clone()
            },
            "damage.1.growth.time_constant_s = -1",
        ),
    ];
    for (bad, expected) in cases {
        let msg = validate_damage(&[ok.clone(), bad], 30.0)
            .unwrap_err()
            .to_string();
        assert!(msg.starts_with(expected), "{msg}");
    }
}

#[test]
fn damage_onsets_are_listed_as_sorted_events() {
    let damage = [
        DamageSpec {
            start_m: 14.0,
            end_m: 15.5,
            reduction: 0.2,
            onset_s: 600.0,
            growth: Growth::Linear { duration_s: 300.0 },
        },
        DamageSpec {
            start_m: 3.0,
            end_m: 4.0,
            reduction: 0.1,
            onset_s: 60.5,
            growth: Growth::Step,
        },
    ];
    let events = damage_events(&damage);
    let times: Vec<u64> = events.iter().map(|e| e.t_ns).collect();
    assert_eq!(times, [60_500_000_000, 600_000_000_000, 900_000_000_000]);
    assert!(events[0]
        .text
        .starts_with("damage.1 begins: EI -10.0 % over [3, 4] m"));
    assert!(
        events[2].text.starts_with("damage.0 fully grown"),
        "{}",
        events[2].text
    );
}

// ---------------------------------------------------------------- frequencies

fn f1_hz(beam: &BeamProperties) -> f64 {
    // 60 Hermite elements of 0.5 m: region edges on nodes, so each element's EI is exact.
    BridgeModel::build(beam, &ModelSpec::FiniteElement { elements: 60 }, 0.02)
        .unwrap()
        .frequency_hz(1)
}

fn state(global_factor: f64, regions: Vec<StiffnessRegion>) -> StiffnessState {
    let damage_fraction = regions.iter().map(|r| 1.0 - r.ei_factor).collect();
    StiffnessState {
        global_factor,
        regions,
        temperature_air_c: 0.0,
        temperature_structure_c: 0.0,
        damage_fraction,
        supports: Default::default(),
    }
}

#[test]
fn global_factor_scales_the_first_frequency_by_its_square_root() {
    // K scales by the factor and M not, so omega^2 scales exactly; what is left is the
    // eigen-solver's round-off, eps times the condition of K (~ n^4): 1e-12 for these
    // sizes, 4e-9 for 60 elements (hence the small models here).
    let base = BeamProperties::paper_default();
    let specs = [
        ModelSpec::LumpedMass {
            nodes: 15,
            stiffness: Default::default(),
        },
        ModelSpec::FiniteElement { elements: 20 },
    ];
    for spec in specs {
        let f1 = |beam: &BeamProperties| {
            BridgeModel::build(beam, &spec, 0.02)
                .unwrap()
                .frequency_hz(1)
        };
        let f0 = f1(&base);
        for factor in [0.9, 0.985, 1.315] {
            let ratio = f1(&state(factor, vec![]).beam_at(&base)) / f0;
            let label = spec.label();
            assert!(
                (ratio - factor.sqrt()).abs() < 1e-9,
                "{label}, factor {factor}: {ratio}"
            );
        }
    }
}

/// Rayleigh quotient with the undamaged mode sin(pi x / L): omega^2 / omega0^2 =
/// 1 - r * integral over [a, b] of sin^2(pi x / L) dx / (L / 2).
fn rayleigh_ratio(span_m: f64, a_m: f64, b_m: f64, reduction: f64) -> f64 {
    let k = PI / span_m;
    let integral = 0.5 * (b_m - a_m) - ((2.0 * k * b_m).sin() - (2.0 * k * a_m).sin()) / (4.0 * k);
    (1.0 - reduction * integral / (0.5 * span_m)).sqrt()
}

/// f1 of the paper beam with EI times `1 - reduction` over `[a_m, b_m]`, exact (no mesh):
/// the transfer-matrix solution of the stepped beam.
fn stepped_beam_f1_hz(base: &BeamProperties, a_m: f64, b_m: f64, reduction: f64) -> f64 {
    let ei = base.flexural_rigidity_n_m2;
    let segment = |length_m: f64, factor: f64| Segment {
        length_m,
        flexural_rigidity_n_m2: ei * factor,
    };
    SteppedBeam {
        mass_per_length_kg_m: base.mass_per_length_kg_m,
        segments: vec![
            segment(a_m, 1.0),
            segment(b_m - a_m, 1.0 - reduction),
            segment(base.length_m() - b_m, 1.0),
        ],
    }
    .frequency_hz(1)
}

#[test]
fn local_damage_lowers_f1_as_the_stepped_beam_predicts() {
    // 5 % of the 30 m span near midspan, EI reduced by 10 to 30 %. The reference is the exact
    // frequency of the stepped beam (transfer matrices, no mesh). The model's 60-element
    // Hermite mesh has its region edges on nodes, so it errs as a uniform mesh does:
    // (pi / 60)^4 / 1440 = 5.2e-9 from discretization plus eps (omega_max / omega_1)^2 =
    // 7.4e-8 from round-off (docs/physics.md section 3); the tolerance is their sum.
    // The Rayleigh quotient with the undamaged shape is exact to first order only and
    // bounds f1 from above; its gap (second order in the loss) is reported, not allowed for.
    let base = BeamProperties::paper_default();
    let (a_m, b_m) = (14.0, 15.5);
    let f0 = f1_hz(&base);
    let tolerance = (PI / 60.0).powi(4) / 1440.0 + f64::EPSILON * 25.9 * 60f64.powi(4);
    let mut previous = f0;
    for reduction in [0.1, 0.2, 0.3] {
        let damage = [DamageSpec {
            start_m: a_m,
            end_m: b_m,
            reduction,
            onset_s: 0.0,
            growth: Growth::Step,
        }];
        let spec = EnvironmentSpec::default();
        let mut env = EnvironmentModel::new(
            &spec,
            &damage,
            &[],
            &Girder::simply_supported(30.0),
            AirTemperature::constant(20.0),
        )
        .unwrap();
        let beam = env.state_at(1.0).beam_at(&base);
        let f = f1_hz(&beam);
        // The same region written by hand: the model's own eigen-analysis, same number.
        let mut by_hand = base.clone();
        by_hand.stiffness_regions.push(StiffnessRegion {
            start_m: a_m,
            end_m: b_m,
            ei_factor: 1.0 - reduction,
        });
        assert_eq!(f, f1_hz(&by_hand));
        assert!(
            f < previous,
            "f1 must fall with the reduction: {f} after {previous}"
        );
        previous = f;
        let exact = stepped_beam_f1_hz(&base, a_m, b_m, reduction);
        let err = f / exact - 1.0;
        let rayleigh = rayleigh_ratio(30.0, a_m, b_m, reduction) * f0;
        println!(
            "reduction {reduction}: f1 {f:.9} Hz, stepped beam {exact:.9} Hz ({err:+.2e}), \
             Rayleigh gap {:.2e}",
            rayleigh / exact - 1.0
        );
        assert!(
            err.abs() <= tolerance,
            "reduction {reduction}: f1 {f} Hz vs the stepped beam's {exact} Hz ({err:e})"
        );
        assert!(
            rayleigh > exact,
            "the Rayleigh quotient bounds f1 from above"
        );
    }
}

#[test]
fn overlapping_damage_regions_compound() {
    let base = BeamProperties::paper_default();
    let regions = vec![
        StiffnessRegion {
            start_m: 10.0,
            end_m: 12.0,
            ei_factor: 0.8,
        },
        StiffnessRegion {
            start_m: 11.0,
            end_m: 13.0,
            ei_factor: 0.5,
        },
    ];
    let beam = state(0.9, regions).beam_at(&base);
    let ei = base.flexural_rigidity_n_m2;
    assert!((beam.ei_at_n_m2(11.5) - 0.9 * 0.8 * 0.5 * ei).abs() < 1e-12 * ei);
    assert!((beam.ei_at_n_m2(12.5) - 0.9 * 0.5 * ei).abs() < 1e-12 * ei);
}

// ---------------------------------------------------------------- rebuild policy

#[test]
fn rebuild_is_needed_just_past_the_threshold() {
    let policy = RebuildPolicy::default();
    assert_eq!(policy.threshold_rel, 0.002);
    let region = |ei_factor| {
        vec![StiffnessRegion {
            start_m: 14.0,
            end_m: 15.5,
            ei_factor,
        }]
    };
    let built = state(1.0, region(0.9));
    assert!(!policy.needs_rebuild(&built, &built));
    assert!(!policy.needs_rebuild(&built, &state(1.0019, region(0.9))));
    assert!(!policy.needs_rebuild(&built, &state(0.9981, region(0.9))));
    assert!(policy.needs_rebuild(&built, &state(1.0021, region(0.9))));
    assert!(policy.needs_rebuild(&built, &state(0.9979, region(0.9))));
    assert!(!policy.needs_rebuild(&built, &state(1.0, region(0.9 * 1.0019))));
    assert!(policy.needs_rebuild(&built, &state(1.0, region(0.9 * 0.9979))));
    assert!(policy.needs_rebuild(&built, &state(1.0, vec![])));
}

#[test]
fn cold_snap_and_damage_drive_state_and_rebuilds() {
    // Air falls from 20 to -10 degC over the first second, then stays: piecewise linear,
    // so the lag is exact. After the ramp the structure is
    // T1 = -10 + 30 tau (1 - e^(-1/tau)), then decays to -10 as e^(-(t - 1)/tau): about
    // 1.04 degC at t = tau.
    let tau_s = 3600.0;
    let spec = EnvironmentSpec {
        lag_s: tau_s,
        ..Default::default()
    };
    let table = TemperatureTable::parse("time_s,temperature_c\n0,20\n1,-10\n", "t.csv").unwrap();
    let damage = [DamageSpec {
        start_m: 14.0,
        end_m: 15.5,
        reduction: 0.2,
        onset_s: 1800.0,
        growth: Growth::Step,
    }];
    let mut env = EnvironmentModel::new(
        &spec,
        &damage,
        &[],
        &Girder::simply_supported(30.0),
        AirTemperature::from_table(table),
    )
    .unwrap();
    let start = env.state_at(0.0);
    assert_eq!(start.temperature_structure_c, 20.0);
    assert_eq!(start.global_factor, 1.0);
    let policy = spec.rebuild_policy();
    let mut built = start.clone();
    let (mut now, mut rebuilds) = (start.clone(), 0);
    for k in 0..=3600 {
        env.update(f64::from(k), &mut now);
        if policy.needs_rebuild(&built, &now) {
            rebuilds += 1;
            built = now.clone();
        }
    }
    // A repeated time changes nothing (the lag and the table hold).
    let end = env.state_at(tau_s);
    assert_eq!(end, now);
    let after_ramp_c = -10.0 - 30.0 * tau_s * (-1.0 / tau_s).exp_m1();
    let expected_c = -10.0 + (after_ramp_c + 10.0) * (-(tau_s - 1.0) / tau_s).exp();
    assert!((end.temperature_structure_c - expected_c).abs() < 1e-12);
    assert!((expected_c - 1.04).abs() < 0.01);
    assert_eq!(end.damage_fraction, vec![0.2]);
    assert_eq!(end.regions[0].ei_factor, 0.8);
    // Default law, reference 20 degC: factor 1 + 0.0015 * (20 - T) above the knee.
    assert!((end.global_factor - (1.0 + 0.0015 * (20.0 - expected_c))).abs() < 1e-9);
    // The count is deterministic: the same rule (a rebuild when the global factor has
    // moved by more than 0.2 % since the last build, or the damage has changed) applied to
    // the closed-form temperature above gives it exactly. E rises by 2.9 % over the hour:
    // about 2.9 % / 0.2 % = 14 temperature rebuilds, plus the damage onset.
    let structure_c = |t_s: f64| match t_s {
        t if t <= 0.0 => 20.0,
        // The lag of the ramp 20 - 30 t: T = 20 - 30 t + 30 tau (1 - e^(-t / tau)).
        t if t <= 1.0 => 20.0 - 30.0 * t - 30.0 * tau_s * (-t / tau_s).exp_m1(),
        t => -10.0 + (after_ramp_c + 10.0) * (-(t - 1.0) / tau_s).exp(),
    };
    let factor = |t_s: f64| 1.0 + 0.0015 * (20.0 - structure_c(t_s));
    let (mut built_factor, mut built_damaged, mut expected) = (1.0, false, 0);
    for k in 0..=3600 {
        let (f, damaged) = (factor(f64::from(k)), k >= 1800);
        if (f / built_factor - 1.0).abs() > 0.002 || damaged != built_damaged {
            expected += 1;
            (built_factor, built_damaged) = (f, damaged);
        }
    }
    assert!(
        (14..=16).contains(&expected),
        "{expected} predicted rebuilds"
    );
    assert_eq!(
        rebuilds, expected,
        "rebuilds of the model vs the rule on the closed form"
    );
}
