use super::*;

fn truck() -> VehicleDynamics {
    VehicleModelSpec::HalfCar(HalfCarSpec {
        preset: Some("two_axle_truck".into()),
        ..Default::default()
    })
    .build("vehicles.0.model")
    .unwrap()
}

#[test]
fn static_axle_loads_sum_to_the_weight_and_split_by_lever_rule() {
    let v = truck();
    let weight = (17_735.0 + 1_500.0 + 1_000.0) * GRAVITY_M_S2;
    assert!((v.gross_weight_n() - weight).abs() < 1e-9 * weight);
    // CG at mid-wheelbase: the body splits equally; each axle adds its own weight.
    let front = (17_735.0 / 2.0 + 1_500.0) * GRAVITY_M_S2;
    assert!((v.axles[0].static_load_n - front).abs() < 1e-6 * front);
}

#[test]
fn equilibrium_on_a_level_road_offset_moves_everything_rigidly() {
    let v = truck();
    let y = v.equilibrium_on_road(&[0.01, 0.01]);
    // Body bounce, both axles up 10 mm; no pitch.
    assert!((y[0] - 0.01).abs() < 1e-12 && y[1].abs() < 1e-12);
    assert!((y[2] - 0.01).abs() < 1e-12 && (y[3] - 0.01).abs() < 1e-12);
}

#[test]
fn bad_vehicle_inputs_name_field_and_value() {
    let cases = [
        (
            r#"kind = "half_car"
preset = "bus""#,
            "vehicles.0.model.preset",
        ),
        (
            r#"kind = "half_car"
preset = "two_axle_truck"
body_mass_kg = -5.0"#,
            "vehicles.0.model.body_mass_kg",
        ),
        (
            r#"kind = "half_car"
body_mass_kg = 1000.0"#,
            "vehicles.0.model.pitch_inertia_kg_m2",
        ),
        (
            r#"kind = "sprung_mass"
mass_kg = 1000.0
stiffness_n_m = 0.0"#,
            "vehicles.0.model.stiffness_n_m",
        ),
        (
            r#"kind = "moving_force"
axle_loads_n = [1.0, 2.0]"#,
            "vehicles.0.model.axle_spacing_m",
        ),
        (
            r#"kind = "half_car"
preset = "two_axle_truck"
tyre_stiffness_n_m = [1e6, -1.0]"#,
            "vehicles.0.model.tyre_stiffness_n_m.1",
        ),
    ];
    for (text, field) in cases {
        let spec: VehicleModelSpec = toml::from_str(text).unwrap();
        let msg = spec.build("vehicles.0.model").unwrap_err().to_string();
        assert!(msg.starts_with(field), "{msg}");
    }
    let unknown: Result<VehicleModelSpec, _> = toml::from_str("kind = \"half_car\"\nwheels = 3");
    assert!(unknown.unwrap_err().to_string().contains("wheels"));
}
