//! Every example scenario still parses, validates and prepares (bridge model, road,
//! temperature) with the current code: the long ones are not run by CI, so this is what
//! keeps them from drifting. Runs in well under a second.

use std::path::{Path, PathBuf};

use bridgetwin::scenario::Scenario;

fn example_scenarios() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    let mut paths: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("examples folder")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    paths.sort();
    paths
}

/// Resolves and prepares `scenario`, panicking with `label` and the error.
fn prepares(scenario: Scenario, label: &str) {
    let resolved = scenario
        .resolve()
        .unwrap_or_else(|e| panic!("{label}: {e}"));
    bridgetwin::sim::prepare(&resolved).unwrap_or_else(|e| panic!("{label}: {e}"));
}

#[test]
fn every_example_scenario_resolves_and_prepares() {
    let paths = example_scenarios();
    let names: Vec<String> = paths
        .iter()
        .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    for wanted in [
        "day_of_traffic.toml",
        "hour_of_traffic.toml",
        "paper_case.toml",
    ] {
        assert!(names.iter().any(|n| n == wanted), "{wanted} in {names:?}");
    }
    for path in &paths {
        let label = path.display().to_string();
        let (scenario, _) = Scenario::from_file(path).unwrap_or_else(|e| panic!("{label}: {e}"));
        prepares(scenario, &label);
    }
}

#[test]
fn the_day_example_with_its_damage_block_uncommented_prepares() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/day_of_traffic.toml");
    let text = std::fs::read_to_string(path).expect("day example");
    let block = text
        .find("# [[damage]]")
        .expect("the day example has a commented [[damage]] block");
    let uncommented = format!("{}{}", &text[..block], text[block..].replace("# ", ""));
    assert!(uncommented.contains("\n[[damage]]\n"));
    let label = "day_of_traffic.toml with damage";
    let scenario = Scenario::from_toml(&uncommented, label).unwrap_or_else(|e| panic!("{e}"));
    prepares(scenario, label);
}

/// The first frequency of example `name` as the run builds it.
fn example_f1_hz(name: &str) -> f64 {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("examples")
        .join(format!("{name}.toml"));
    let (scenario, _) = Scenario::from_file(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
    let resolved = scenario.resolve().unwrap_or_else(|e| panic!("{name}: {e}"));
    let prepared = bridgetwin::sim::prepare(&resolved).unwrap_or_else(|e| panic!("{name}: {e}"));
    prepared.model.frequency_hz(1)
}

/// The exact first frequency of a uniform girder on rigid pinned supports.
fn exact_f1_hz(spans_m: &[f64], ei: f64, mass: f64) -> f64 {
    use bridgetwin::studies::analytic::continuous_beam::{Condition, ContinuousBeam};
    ContinuousBeam {
        pieces_m: spans_m.to_vec(),
        conditions: vec![Condition::Pinned; spans_m.len() + 1],
        flexural_rigidity_n_m2: ei,
        mass_per_length_kg_m: mass,
    }
    .frequencies_hz(1)
    .expect("exact modes")[0]
}

#[test]
fn the_bridge_presets_have_their_documented_first_frequency() {
    // Each preset's header derives f1; the model (1 m Hermite elements) is within 1e-4 of
    // the exact continuous-beam determinant, and the documented figures are quoted to
    // three digits (0.2 %). The steel-composite unit's EI was fitted to the published
    // 2.48 Hz of the I-40 bridge (Farrar et al. 1994).
    let cases = [
        (
            "two_span_concrete",
            vec![31.0, 31.0],
            8.628e10,
            21650.0,
            3.26,
        ),
        (
            "three_span_concrete",
            vec![30.0, 40.0, 30.0],
            1.5796e11,
            23352.0,
            3.38,
        ),
        (
            "steel_composite_three_span",
            vec![39.9, 49.7, 39.9],
            6.2e10,
            6500.0,
            2.48,
        ),
    ];
    for (name, spans, ei, mass, documented) in cases {
        let model = example_f1_hz(name);
        let exact = exact_f1_hz(&spans, ei, mass);
        assert!(
            (model / exact - 1.0).abs() < 1e-4,
            "{name}: {model} vs exact {exact}"
        );
        assert!(
            (exact / documented - 1.0).abs() < 2e-3,
            "{name}: exact {exact} vs documented {documented}"
        );
    }
}
