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
