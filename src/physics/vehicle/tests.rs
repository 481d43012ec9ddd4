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

#[test]
fn every_pitch_plane_spec_takes_the_shared_axle_arrays_and_rejects_unknown_keys() {
    // The per-axle arrays are written once (pitch_plane_spec!) for three tables: each
    // table must accept every one of them and still name an unknown key.
    let arrays = "axle_mass_kg = [1.0, 2.0]\nsuspension_stiffness_n_m = [1.0, 2.0]\n\
                  suspension_damping_n_s_m = [1.0, 2.0]\ntyre_stiffness_n_m = [1.0, 2.0]\n\
                  tyre_damping_n_s_m = [1.0, 2.0]\n";
    let half: HalfCarSpec = toml::from_str(arrays).unwrap();
    let rigid: RigidTruckSpec = toml::from_str(arrays).unwrap();
    let artic: ArticulatedSpec = toml::from_str(arrays).unwrap();
    assert_eq!(half.tyre_damping_n_s_m, Some([1.0, 2.0]));
    assert_eq!(rigid.tyre_damping_n_s_m, Some(vec![1.0, 2.0]));
    assert_eq!(artic.axle_mass_kg, Some(vec![1.0, 2.0]));
    let wings = format!("{arrays}wings = 2\n");
    for e in [
        toml::from_str::<HalfCarSpec>(&wings).unwrap_err(),
        toml::from_str::<RigidTruckSpec>(&wings).unwrap_err(),
        toml::from_str::<ArticulatedSpec>(&wings).unwrap_err(),
    ] {
        let msg = e.to_string();
        assert!(
            msg.contains("unknown field `wings`, expected one of `preset`"),
            "{msg}"
        );
        assert!(msg.contains("`tyre_damping_n_s_m`"), "{msg}");
    }
}

#[test]
fn fields_given_next_to_a_preset_override_it_one_by_one() {
    let spec = HalfCarSpec {
        preset: Some("two_axle_truck".into()),
        body_mass_kg: Some(10_000.0),
        tyre_stiffness_n_m: Some([1e6, 2e6]),
        ..Default::default()
    };
    let v = VehicleModelSpec::HalfCar(spec)
        .build("vehicles.0.model")
        .unwrap();
    let p = |name: &str| v.parameters.iter().find(|(n, _)| n == name).unwrap().1;
    assert_eq!(p("body_mass_kg"), 10_000.0);
    assert_eq!(p("axle_2_tyre_stiffness_n_m"), 2e6);
    // Not given: the preset's.
    assert_eq!(p("axle_1_mass_kg"), 1_500.0);
    assert_eq!(p("axle_2_suspension_stiffness_n_m"), 4.23e6);
}
