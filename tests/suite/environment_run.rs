//! The environment in a run: temperature and damage change the bridge the time loop
//! integrates. The frequency is read from the simulated response itself (the free
//! vibration after a vehicle has left, timed by zero crossings) and compared with the
//! closed form of a simply supported beam under the temperature law, and with the
//! eigen-analysis of the damaged beam. The model pieces (laws, lag, growth) are tested
//! on their own in `tests/suite/environment.rs`.

use std::io::Write;

use bridgetwin::physics::bridge::{BeamProperties, BridgeModel, ModelSpec, StiffnessRegion};
use bridgetwin::physics::environment::TemperatureStiffnessLaw;
use bridgetwin::sim::{ModalRecord, Record};

use crate::common::records_in;

const SPAN_M: f64 = 30.0;
const EI_N_M2: f64 = 5.629e10;
const MASS_KG_M: f64 = 12000.0;
const DAMPING: f64 = 0.02;

/// The bridge and two trucks: one crossing at once, one 30 s later, each followed by some
/// 8 s of free vibration; a midspan displacement sensor at 500 Hz (ideal).
fn scenario_toml(extra: &str) -> String {
    format!(
        r#"
seed = 5
duration_s = 42.0
{extra}
[bridge]
span_m = {SPAN_M}
flexural_rigidity_n_m2 = {EI_N_M2}
mass_per_length_kg_m = {MASS_KG_M}
damping_ratio = {DAMPING}
model = {{ kind = "finite_element", elements = 20 }}

[road]
approach_m = 10.0
exit_m = 10.0

[[vehicles]]
model = {{ kind = "half_car", preset = "two_axle_truck" }}
speed_m_s = 20.0

[[vehicles]]
model = {{ kind = "half_car", preset = "two_axle_truck" }}
speed_m_s = 20.0
entry_time_s = 30.0

[[sensors]]
id = "D_mid"
kind = "displacement"
position_m = 15.0
rate_hz = 500.0
"#
    )
}

/// Damped frequency of the midspan displacement truth over [from_s, to_s], from the
/// first and last upward zero crossings (linearly interpolated).
fn free_vibration_hz(records: &[Record], from_s: f64, to_s: f64) -> f64 {
    let samples: Vec<(f64, f64)> = records
        .iter()
        .filter_map(|r| match r {
            Record::Sensor { t_ns, truth, .. } => Some((*t_ns as f64 * 1e-9, truth.displacement_m)),
            _ => None,
        })
        .filter(|(t, _)| (from_s..=to_s).contains(t))
        .collect();
    let crossings: Vec<f64> = samples
        .windows(2)
        .filter(|w| w[0].1 < 0.0 && w[1].1 >= 0.0)
        .map(|w| w[0].0 + (w[1].0 - w[0].0) * (-w[0].1) / (w[1].1 - w[0].1))
        .collect();
    assert!(crossings.len() > 20, "{} crossings", crossings.len());
    (crossings.len() - 1) as f64 / (crossings[crossings.len() - 1] - crossings[0])
}

/// f1 of a simply supported Euler-Bernoulli beam with flexural rigidity `ei`.
fn f1_closed_form_hz(ei: f64) -> f64 {
    std::f64::consts::PI / (2.0 * SPAN_M * SPAN_M) * (ei / MASS_KG_M).sqrt()
}

/// Damped natural frequency for the Rayleigh ratio on mode 1.
fn damped(f_hz: f64) -> f64 {
    f_hz * (1.0 - DAMPING * DAMPING).sqrt()
}

/// The modal records on `/truth/bridge` with their time and the structure temperature.
fn modal_records(records: &[Record]) -> Vec<(f64, f64, &ModalRecord)> {
    records
        .iter()
        .filter_map(|r| match r {
            Record::BridgeShape {
                t_ns,
                temperatures_c: Some((structure_c, _)),
                modal: Some(modal),
                ..
            } => Some((*t_ns as f64 * 1e-9, *structure_c, modal.as_ref())),
            _ => None,
        })
        .collect()
}

#[test]
fn f1_follows_the_temperature_law_through_model_rebuilds() {
    let dir = tempfile::tempdir().expect("temp dir");
    // Air at 20 degC, falling to -10 degC between 12 and 20 s; a 1 s lag into the deck,
    // so the second truck crosses a bridge at -10 degC (settled to 1e-4 degC).
    let mut csv = std::fs::File::create(dir.path().join("air.csv")).expect("csv");
    writeln!(csv, "time_s,temperature_c\n0,20\n12,20\n20,-10\n60,-10").expect("write");
    let toml = scenario_toml(
        "[environment]\ntemperature = { kind = \"csv\", path = \"air.csv\" }\nlag_s = 1.0\n",
    );
    let recs = records_in(&toml, dir.path());
    let law = TemperatureStiffnessLaw::default();
    let cold_factor = law.factor(-10.0);
    assert!(cold_factor > 1.05, "E(-10 degC)/E_ref = {cold_factor}");

    // From the response: 0.1 % covers the zero-crossing timing at 500 Hz, the higher
    // modes' share of the midspan signal and Newmark's period error (5e-5 at 1 ms).
    let warm = free_vibration_hz(&recs, 3.0, 11.0);
    let cold = free_vibration_hz(&recs, 33.0, 41.0);
    let warm_expected = damped(f1_closed_form_hz(EI_N_M2));
    let cold_expected = damped(f1_closed_form_hz(EI_N_M2 * cold_factor));
    assert!(
        (warm / warm_expected - 1.0).abs() < 1e-3,
        "warm {warm} Hz vs {warm_expected}"
    );
    assert!(
        (cold / cold_expected - 1.0).abs() < 1e-3,
        "cold {cold} Hz vs {cold_expected}"
    );

    // The published modal state follows the law: each record's f1 within half the
    // rebuild threshold (0.2 % on EI, 0.1 % on f) of the law at its deck temperature,
    // plus the 20-element model's 1e-5 discretisation error.
    let modal = modal_records(&recs);
    assert!(modal.len() >= 10, "{} modal records", modal.len());
    for (t_s, structure_c, m) in &modal {
        let expected = f1_closed_form_hz(EI_N_M2 * law.factor(*structure_c));
        let f1 = m.natural_frequency_hz[0];
        assert!(
            (f1 / expected - 1.0).abs() < 1e-3 + 1e-5,
            "t = {t_s} s, deck {structure_c} degC: f1 {f1} Hz vs {expected}"
        );
        let ratio = law.factor(*structure_c);
        assert!(m
            .stiffness_ratio
            .iter()
            .all(|r| (r / ratio - 1.0).abs() < 2.1e-3));
    }
    // Sharper: the response follows the model in use, which lags the law by up to the
    // rebuild threshold; against that model's published f1 the only errors left are
    // those of the measurement (2e-4).
    let in_use = modal
        .iter()
        .rfind(|(t, _, _)| *t <= 33.0)
        .expect("a modal record before the cold window")
        .2
        .natural_frequency_hz[0];
    assert!(
        (cold / damped(in_use) - 1.0).abs() < 2e-4,
        "cold {cold} Hz vs the model in use {}",
        damped(in_use)
    );
    let deck_at_end_c = recs
        .iter()
        .rev()
        .find_map(|r| match r {
            Record::BridgeShape {
                temperatures_c: Some((structure_c, _)),
                ..
            } => Some(*structure_c),
            _ => None,
        })
        .expect("shapes carry temperatures");
    assert!(
        (deck_at_end_c + 10.0).abs() < 1e-3,
        "deck at the end {deck_at_end_c} degC"
    );
    eprintln!(
        "temperature: f_d warm {warm:.5} Hz (closed form {warm_expected:.5}), cold {cold:.5} Hz \
         ({cold_expected:.5}); {} modal records",
        modal.len()
    );
}

#[test]
fn damage_lowers_f1_as_the_eigen_analysis_of_the_damaged_beam_says() {
    let dir = tempfile::tempdir().expect("temp dir");
    let toml = scenario_toml(
        "[[damage]]\nstart_m = 12.0\nend_m = 18.0\nreduction = 0.4\nonset_s = 15.0\n",
    );
    let recs = records_in(&toml, dir.path());

    // The eigen-analysis of the damaged beam, independent of the run: EI x 0.6 over
    // [12, 18] m, a 60-element model (finer than the run's 20).
    let damaged_beam = BeamProperties {
        stiffness_regions: vec![StiffnessRegion {
            start_m: 12.0,
            end_m: 18.0,
            ei_factor: 0.6,
        }],
        ..BeamProperties::simply_supported(SPAN_M, EI_N_M2, MASS_KG_M)
    };
    let fine = BridgeModel::build(
        &damaged_beam,
        &ModelSpec::FiniteElement { elements: 60 },
        DAMPING,
    )
    .expect("damaged model");
    let f1_damaged = fine.frequency_hz(1);
    let f1_sound = f1_closed_form_hz(EI_N_M2);
    assert!(f1_damaged < 0.95 * f1_sound, "{f1_damaged} vs {f1_sound}");

    let before = free_vibration_hz(&recs, 3.0, 11.0);
    let after = free_vibration_hz(&recs, 33.0, 41.0);
    assert!(
        (before / damped(f1_sound) - 1.0).abs() < 1e-3,
        "before: {before} Hz vs {}",
        damped(f1_sound)
    );
    // 0.1 % as above plus the 20- vs 60-element difference for a region edge on nodes
    // (both meshes have nodes at 12 and 18 m: the difference is discretisation, < 1e-4).
    assert!(
        (after / damped(f1_damaged) - 1.0).abs() < 1.1e-3,
        "after: {after} Hz vs {}",
        damped(f1_damaged)
    );

    eprintln!(
        "damage: f_d before {before:.5} Hz ({:.5}), after {after:.5} Hz (eigen-analysis {:.5})",
        damped(f1_sound),
        damped(f1_damaged)
    );
    // The onset is announced at 15 s, the modal state published then says the same.
    let onset = recs.iter().find_map(|r| match r {
        Record::Event { t_ns, text, .. } if text.contains("damage.0 begins") => Some(*t_ns),
        _ => None,
    });
    assert_eq!(onset, Some(15_000_000_000));
    let modal = modal_records(&recs);
    let first_after = modal
        .iter()
        .find(|(t, _, _)| *t >= 15.0)
        .expect("modal record after the onset");
    assert!(first_after.0 < 15.1, "published at {} s", first_after.0);
    assert!((first_after.2.natural_frequency_hz[0] / f1_damaged - 1.0).abs() < 1e-4);
    assert_eq!(first_after.2.damage_fraction, vec![0.4]);
    let (min_ratio, max_ratio) = first_after
        .2
        .stiffness_ratio
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), &r| (a.min(r), b.max(r)));
    assert!((min_ratio - 0.6).abs() < 1e-12 && (max_ratio - 1.0).abs() < 1e-12);
    // Before the onset the published model is the sound one.
    assert!((modal[0].2.natural_frequency_hz[0] / f1_sound - 1.0).abs() < 1e-5);
}

#[test]
fn a_deck_thermometer_reads_the_structure_temperature() {
    // The thermometer's truth is the structure temperature of /truth/bridge at the same
    // instants (exact: the same value); the Pt100 preset's reading is within 5 sigma of
    // its bias (0.1 degC) plus the 24-bit noise. An accelerometer carries no temperature.
    let toml = r#"
seed = 2
duration_s = 120.0
[bridge]
span_m = 30.0
flexural_rigidity_n_m2 = 5.629e10
mass_per_length_kg_m = 12000.0
model = { kind = "finite_element", elements = 20 }
[environment]
temperature = { kind = "daily", mean_c = 18.0, amplitude_c = 6.0, peak_hour = 15.0, noise_sd_c = 1.0 }
lag_s = 600.0
[[sensors]]
id = "T1"
kind = "thermometer"
position_m = 15.0
rate_hz = 1.0
preset = "thermometer_pt100"
[[sensors]]
id = "A1"
kind = "accelerometer"
position_m = 15.0
rate_hz = 10.0
"#;
    let records = crate::common::records_of(toml);
    let shapes: std::collections::BTreeMap<u64, f64> = records
        .iter()
        .filter_map(|r| match r {
            bridgetwin::sim::Record::BridgeShape {
                t_ns,
                temperatures_c: Some((structure, _)),
                ..
            } => Some((*t_ns, *structure)),
            _ => None,
        })
        .collect();
    let samples = crate::common::sensor_samples(&records, 0);
    assert!(samples.len() >= 120, "{} samples", samples.len());
    let mut compared = 0;
    for (t, _, measured, truth) in &samples {
        if let Some(structure) = shapes.get(t) {
            assert_eq!(truth.temperature_c, *structure, "t {t}");
            compared += 1;
        }
        let m = measured.expect("no faults");
        assert!(
            (m - truth.temperature_c).abs() < 0.55,
            "{m} vs {}",
            truth.temperature_c
        );
        assert!((10.0..30.0).contains(&truth.temperature_c));
    }
    assert!(
        compared >= 100,
        "{compared} instants shared with /truth/bridge"
    );
    for (_, _, _, truth) in crate::common::sensor_samples(&records, 1) {
        assert_eq!(truth.temperature_c, 0.0);
    }
}
