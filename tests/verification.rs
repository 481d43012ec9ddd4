//! Every row of `bridgetwin verify` as a test: a failing row names itself.

use bridgetwin::verify::{ladder, CheckRow};

fn assert_group(name: &str) {
    let group = ladder()
        .into_iter()
        .find(|g| g.name == name)
        .expect("group exists");
    let rows: Vec<CheckRow> = (group.run)().expect("group runs");
    assert!(!rows.is_empty(), "group {name} has no rows");
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
    assert_group("frequencies");
}

#[test]
fn static_deflection() {
    assert_group("static");
}

#[test]
fn newmark_oscillator() {
    assert_group("newmark");
}

#[test]
fn moving_force_against_fryba() {
    assert_group("moving_force");
}

#[test]
fn daf_table() {
    assert_group("daf");
}

#[test]
fn manufactured_solution() {
    assert_group("manufactured");
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
            "manufactured"
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
