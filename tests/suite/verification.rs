//! Every row of `bridgetwin verify` as a test: a failing row names itself.

use bridgetwin::studies::verify::{ladder, CheckRow};

/// Runs group `name`, which must have exactly `rows` rows (a group that lost a row would
/// otherwise still pass), and fails naming every failing row.
fn assert_group(name: &str, rows_expected: usize) {
    let group = ladder()
        .into_iter()
        .find(|g| g.name == name)
        .expect("group exists");
    let rows: Vec<CheckRow> = (group.run)().expect("group runs");
    assert_eq!(
        rows.len(),
        rows_expected,
        "group {name}: {} rows, expected {rows_expected}",
        rows.len()
    );
    let failed: Vec<String> = rows
        .iter()
        .filter(|r| !r.pass)
        .map(|r| {
            format!(
                "{}: value {} vs {} (error {:e} > {:e})",
                r.check, r.value, r.reference_value, r.error, r.tolerance
            )
        })
        .collect();
    assert!(failed.is_empty(), "{}", failed.join("\n"));
}

#[test]
fn frequencies() {
    assert_group("frequencies", 18);
}

#[test]
fn static_deflection() {
    assert_group("static", 4);
}

#[test]
fn newmark_oscillator() {
    assert_group("newmark", 4);
}

#[test]
fn moving_force_against_fryba() {
    assert_group("moving_force", 24);
}

#[test]
fn daf_table() {
    assert_group("daf", 5);
}

#[test]
fn manufactured_solution() {
    assert_group("manufactured", 4);
}

#[test]
fn vbi_equilibrium() {
    assert_group("vbi_equilibrium", 8);
}

#[test]
fn vbi_static_loads() {
    assert_group("vbi_static_loads", 7);
}

#[test]
fn vbi_harmonic_response() {
    assert_group("vbi_harmonic", 21);
}

#[test]
fn vbi_sprung_mass_against_the_semi_analytical_solution() {
    assert_group("vbi_sprung_mass", 16);
}

#[test]
fn vbi_suspension_limits() {
    assert_group("vbi_limits", 10);
}

#[test]
fn vbi_truck_against_moving_forces() {
    assert_group("vbi_truck", 6);
}

#[test]
fn vbi_road_profiles() {
    assert_group("vbi_road", 15);
}

#[test]
fn vbi_unilateral_contact() {
    assert_group("vbi_contact", 10);
}

#[test]
fn every_group_is_tested_here() {
    // A new group must get a test above.
    let names: Vec<&str> = ladder().iter().map(|g| g.name).collect();
    assert_eq!(
        names,
        [
            "frequencies",
            "static",
            "newmark",
            "moving_force",
            "daf",
            "manufactured",
            "vbi_equilibrium",
            "vbi_static_loads",
            "vbi_harmonic",
            "vbi_sprung_mass",
            "vbi_limits",
            "vbi_truck",
            "vbi_road",
            "vbi_contact",
        ]
    );
}

#[test]
fn a_wrong_reference_fails_its_row() {
    // The rows can fail: the same comparison against a reference off by 1 % fails.
    let row = CheckRow::relative("x", "f1".into(), "closed form", 3.78 * 1.01, 3.78, 1e-3);
    assert!(!row.pass);
    let nan = CheckRow::relative("x", "nan".into(), "closed form", 1.0, f64::NAN, 1e-3);
    assert!(!nan.pass);
}
