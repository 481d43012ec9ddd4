//! A railway car in the pitch plane (`physics::vehicle::RailwayCarParams`): its matrices
//! against the free-body diagrams, its static wheel loads against the lever rule, its rest
//! on a rigid track and its body bounce against the series-spring estimate.

use nalgebra::DMatrix;

use bridgetwin::physics::solver::vehicle_natural_frequencies_hz;
use bridgetwin::physics::vehicle::{RailwayCarParams, Suspension, GRAVITY_M_S2};

/// Values of the order of a passenger coach (not a published vehicle: the checks are
/// against hand-derived matrices and statics, which hold for any values).
fn coach() -> RailwayCarParams {
    RailwayCarParams {
        body_mass_kg: 40_000.0,
        body_pitch_inertia_kg_m2: 2.0e6,
        bogie_half_spacing_m: 9.0,
        bogie_mass_kg: 3_000.0,
        bogie_pitch_inertia_kg_m2: 3_000.0,
        wheelbase_half_m: 1.25,
        wheelset_mass_kg: 1_800.0,
        secondary: Suspension {
            stiffness_n_m: 6.0e5,
            damping_n_s_m: 2.0e4,
        },
        primary: Suspension {
            stiffness_n_m: 2.4e6,
            damping_n_s_m: 3.0e4,
        },
        contact_stiffness_n_m: 1.4e9,
    }
}

#[test]
fn the_stiffness_is_the_hand_derived_one() {
    // Written out from the free-body diagrams, not from the B vectors: the body sees
    // 2 ks in bounce and 2 ks lc^2 in pitch; a bogie ks + 2 kp in bounce, 2 kp lt^2 in
    // pitch; each coupling with the opposite sign and its lever.
    let p = coach();
    let k = p.build("coach").unwrap().stiffness;
    let (ks, kp) = (p.secondary.stiffness_n_m, p.primary.stiffness_n_m);
    let (lc, lt) = (p.bogie_half_spacing_m, p.wheelbase_half_m);
    let mut h = DMatrix::<f64>::zeros(10, 10);
    h[(0, 0)] = 2.0 * ks;
    h[(1, 1)] = 2.0 * ks * lc * lc;
    for (i, l) in [(2usize, lc), (4, -lc)] {
        h[(0, i)] = -ks;
        h[(1, i)] = -ks * l;
        h[(i, i)] = ks + 2.0 * kp;
        h[(i + 1, i + 1)] = 2.0 * kp * lt * lt;
        let w = 6 + (i - 2);
        for (j, m) in [(w, lt), (w + 1, -lt)] {
            h[(i, j)] = -kp;
            h[(i + 1, j)] = -kp * m;
            h[(j, j)] = kp;
        }
    }
    let h = h.clone() + h.transpose() - DMatrix::from_diagonal(&h.diagonal());
    assert!(
        (&k - &h).abs().max() <= 1e-9 * h.abs().max(),
        "{k}\nvs\n{h}"
    );
}

#[test]
fn static_wheel_loads_follow_the_lever_rule() {
    // Symmetric car: each wheelset carries a quarter of the body, half a bogie and
    // itself.
    let p = coach();
    let car = p.build("coach").unwrap();
    let expected =
        (p.body_mass_kg / 4.0 + p.bogie_mass_kg / 2.0 + p.wheelset_mass_kg) * GRAVITY_M_S2;
    for a in &car.axles {
        assert!(
            (a.static_load_n / expected - 1.0).abs() < 1e-12,
            "{}",
            a.static_load_n
        );
    }
    assert_eq!(p.wheelset_offsets_m(), [0.0, 2.5, 18.0, 20.5]);
}

#[test]
fn on_a_rigid_level_track_the_car_rests_and_its_modes_are_the_expected_ones() {
    let p = coach();
    let car = p.build("coach").unwrap();
    // A uniform rise of the rail lifts every DOF by it and pitches nothing.
    let y = car.equilibrium_on_road(&[0.01; 4]);
    for (d, &v) in y.iter().enumerate() {
        let want = if matches!(d, 1 | 3 | 5) { 0.0 } else { 0.01 };
        assert!((v - want).abs() < 1e-12, "DOF {d}: {v}");
    }
    // Body bounce on the secondary, the primaries and contacts in series (per bogie):
    // the stiff levels below it barely move, so f ~ sqrt(2 k_eq / M) / 2 pi within a
    // few percent (the bogies' mass adds a little).
    let series = 1.0
        / (1.0 / p.secondary.stiffness_n_m
            + 1.0 / (2.0 * p.primary.stiffness_n_m)
            + 1.0 / (2.0 * p.contact_stiffness_n_m));
    let bounce_hz = (2.0 * series / p.body_mass_kg).sqrt() / (2.0 * std::f64::consts::PI);
    // Undamped, ascending.
    let hz = vehicle_natural_frequencies_hz(&car).unwrap();
    assert_eq!(hz.len(), 10, "{hz:?}");
    assert!(
        (hz[0] / bounce_hz - 1.0).abs() < 0.05,
        "{} vs {bounce_hz}",
        hz[0]
    );
}
