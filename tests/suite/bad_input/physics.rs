//! Physical values out of range: bridge, solver, vehicles, sensors, WIM stations, road,
//! stiffness regions and output rates.

use super::harness::{
    Case, Edit,
    Edit::{Remove, Set},
};

const CSV_HEADER: &str = "x_m,elevation_m\n";

fn road_csv(rows: &str) -> Vec<u8> {
    format!("{CSV_HEADER}{rows}").into_bytes()
}

const CSV_ROAD: Edit = Set("road.profile", "{ kind = \"csv\", path = \"road.csv\" }");

pub(super) fn physics_cases() -> Vec<Case> {
    let mut cases = Vec::new();
    // Zero, negative, NaN and infinite values of the physical parameters.
    let numbers = [
        ("0.0", "0", "zero"),
        ("-1.0", "-1", "negative"),
        ("nan", "NaN", "NaN"),
        ("inf", "inf", "infinite"),
    ];
    let fields = [
        "bridge.span_m",
        "bridge.flexural_rigidity_n_m2",
        "bridge.mass_per_length_kg_m",
        "solver.dt_s",
        "vehicles.0.speed_m_s",
        "duration_s",
    ];
    for path in fields {
        // Messages name a vehicle by index and id (the default's has id 1).
        let shown_path = path.replace("vehicles.0.", "vehicles.0[1].");
        for (literal, shown, label) in numbers {
            let expect = format!("{shown_path} = {shown} ");
            let case = Case::edit(
                &format!("{path} {label}"),
                &[Set(path, literal)],
                &[&expect],
            );
            cases.push(if path == "duration_s" {
                case.full_duration()
            } else {
                case
            });
        }
    }
    for (literal, shown) in [
        ("-0.1", "-0.1"),
        ("1.0", "1"),
        ("nan", "NaN"),
        ("inf", "inf"),
    ] {
        let expect = format!("bridge.damping_ratio = {shown} must be in [0, 1)");
        cases.push(Case::edit(
            &format!("bridge.damping_ratio = {literal}"),
            &[Set("bridge.damping_ratio", literal)],
            &[&expect],
        ));
    }
    cases.extend([
        Case::edit(
            "span absurdly small (f1 overflows)",
            &[Set("bridge.span_m", "1e-300")],
            &["bridge.span_m = 1e-300 gives a first natural frequency f1 = inf Hz"],
        ),
        Case::edit(
            "span absurdly large",
            &[Set("bridge.span_m", "1e300")],
            &["bridge.span_m = 1e300 must be at most 10000 m"],
        ),
        Case::edit(
            "EI off by 90 orders of magnitude",
            &[Set("bridge.flexural_rigidity_n_m2", "5.629e100")],
            &["bridge.flexural_rigidity_n_m2 = 5.629e100 gives a first natural frequency"],
        ),
        Case::edit(
            "mass per length absurdly small",
            &[Set("bridge.mass_per_length_kg_m", "1e-300")],
            &["bridge.mass_per_length_kg_m = 1e-300 gives a first natural frequency"],
        ),
        Case::edit(
            "dt above 0.1 s",
            &[Set("solver.dt_s", "0.5")],
            &["solver.dt_s = 0.5 must be a whole number of nanoseconds in (0, 0.1] s"],
        ),
        Case::edit(
            "dt not a whole number of nanoseconds",
            &[Set("solver.dt_s", "1.5e-10")],
            &["solver.dt_s = 0.00000000015 must be a whole number of nanoseconds"],
        ),
        Case::edit(
            "time step too coarse for the sensor rates",
            &[Set("solver.dt_s", "0.01")],
            &["sensors.0[A1].rate_hz = 200 must not exceed the solver rate", "solver.dt_s = 0.01"],
        ),
        Case::edit(
            "speed above 100 m/s",
            &[Set("vehicles.0.speed_m_s", "150.0")],
            &["vehicles.0[1].speed_m_s = 150 must be at most 100 m/s"],
        ),
        Case::edit(
            "speed so low that the default duration exceeds 30 days",
            &[Set("vehicles.0.speed_m_s", "1e-5")],
            &["vehicles.0[1].speed_m_s = 0.00001 makes the default duration"],
        )
        .full_duration(),
        Case::edit(
            "duration above 30 days",
            &[Set("duration_s", "1e12")],
            &["duration_s = 1000000000000 must be at most 30 days"],
        )
        .full_duration(),
        Case::edit(
            "too many steps: dt = 10 us over 1e6 s",
            &[Set("solver.dt_s", "1e-5"), Set("duration_s", "1e6"), Remove("sensors")],
            &["duration_s = 1000000 with solver.dt_s = 0.00001 needs 100000000000 solver steps"],
        )
        .full_duration(),
        Case::edit(
            "too many steps: dt = 1 ns over the default duration",
            &[Set("solver.dt_s", "1e-9"), Remove("sensors")],
            &["solver.dt_s = 0.000000001 over the default duration", "solver steps"],
        )
        .full_duration(),
        Case::edit(
            "Newmark gamma below 0.5",
            &[Set("solver.newmark", "{ gamma = 0.3, beta = 0.25 }")],
            &["solver.newmark.gamma = 0.3"],
        ),
        Case::edit(
            "entry time negative",
            &[Set("vehicles.0.entry_time_s", "-1.0")],
            &["vehicles.0[1].entry_time_s = -1 "],
        ),
        Case::edit(
            "entry time beyond 30 days",
            &[Set("vehicles.0.entry_time_s", "1e300")],
            &["vehicles.0[1].entry_time_s = 1e300 must be at most 30 days"],
        ),
        // Sensors.
        Case::edit(
            "sensor beyond the span",
            &[Set("sensors.6.position_m", "31.0")],
            &["sensors.6[A7].position_m = 31 must lie on the span [0, 30] m"],
        ),
        Case::edit(
            "sensor before the span",
            &[Set("sensors.0.position_m", "-0.5")],
            &["sensors.0[A1].position_m = -0.5 must lie on the span"],
        ),
        Case::edit(
            "sensor position NaN",
            &[Set("sensors.2.position_m", "nan")],
            &["sensors.2[A3].position_m = NaN must lie on the span"],
        ),
        Case::edit(
            "sensor rate above the solver rate",
            &[Set("sensors.2.rate_hz", "5000.0")],
            &["sensors.2[A3].rate_hz = 5000 must not exceed the solver rate 1/dt = 1000 Hz"],
        ),
        Case::edit(
            "sensor rate zero",
            &[Set("sensors.1.rate_hz", "0.0")],
            &["sensors.1[A2].rate_hz = 0 must be a finite number > 0"],
        ),
        Case::edit(
            "sensor rate NaN",
            &[Set("sensors.1.rate_hz", "nan")],
            &["sensors.1[A2].rate_hz = NaN"],
        ),
        Case::edit(
            "sensor rate far below the solver rate (anti-alias kernel too long)",
            &[Set("sensors.3.rate_hz", "0.01")],
            &["sensors.3[A4].rate_hz = 0.01 is too far below the solver rate 1000 Hz"],
        ),
        Case::edit(
            "duplicate sensor id",
            &[Set("sensors.1.id", "\"A1\"")],
            &["sensors.1[A1].id = \"A1\" is used twice"],
        ),
        Case::edit(
            "sensor id with a slash",
            &[Set("sensors.4.id", "\"A/5\"")],
            &["sensors.4.id = \"A/5\" must be letters, digits, _ or -"],
        ),
        Case::edit(
            "sensor id with a space",
            &[Set("sensors.4.id", "\"A 5\"")],
            &["sensors.4.id = \"A 5\" must be letters"],
        ),
        Case::edit(
            "sensor id empty",
            &[Set("sensors.0.id", "\"\"")],
            &["sensors.0.id = \"\" must be letters"],
        ),
        Case::edit(
            "sensor id not ASCII",
            &[Set("sensors.0.id", "\"Ä1\"")],
            &["sensors.0.id = \"Ä1\" must be letters"],
        ),
        Case::edit(
            "sensor noise density negative",
            &[Set("sensors.5.noise_density", "-1e-6")],
            &["sensors.5[A6].noise_density = -0.000001"],
        ),
        Case::edit(
            "sensor noise density overflowing",
            &[Set("sensors.5.noise_density", "1e308")],
            &["sensors.5[A6].noise_density = 1e308 gives a per-sample noise sigma of inf"],
        ),
        Case::edit(
            "gauge depth on an accelerometer",
            &[Set("sensors.0.gauge_depth_m", "0.5")],
            &["sensors.0[A1].gauge_depth_m = 0.5 applies to strain gauges only"],
        ),
        Case::edit(
            "gauge depth negative",
            &[Set("sensors.7.gauge_depth_m", "-0.8")],
            &["sensors.7[S1].gauge_depth_m = -0.8 "],
        ),
        // WIM stations.
        Case::edit(
            "WIM station on the bridge",
            &[Set("wim_stations.0.position_m", "5.0")],
            &["wim_stations.0[WIM1].position_m = 5 must lie on the approach, in (-100, 0) m"],
        ),
        Case::edit(
            "WIM station before the approach",
            &[Set("wim_stations.0.position_m", "-150.0")],
            &["wim_stations.0[WIM1].position_m = -150 must lie on the approach"],
        ),
        Case::edit(
            "WIM stations with the same id",
            &[Set("wim_stations.1", "{ id = \"WIM1\", position_m = -50.0 }")],
            &["wim_stations.1[WIM1].id = \"WIM1\" is used twice"],
        ),
        Case::edit(
            "WIM station id with a dot",
            &[Set("wim_stations.0.id", "\"WIM.1\"")],
            &["wim_stations.0.id = \"WIM.1\" must be letters"],
        ),
        // Vehicles.
        Case::edit(
            "unknown vehicle preset",
            &[Set("vehicles.0.model.preset", "\"three_axle_truck\"")],
            &["vehicles.0[1].model.preset = \"three_axle_truck\" is not a preset"],
        ),
        Case::edit(
            "preset override negative",
            &[Set("vehicles.0.model.body_mass_kg", "-100.0")],
            &["vehicles.0[1].model.body_mass_kg = -100 must be a finite number > 0"],
        ),
        Case::edit(
            "preset override pair with a negative entry",
            &[Set("vehicles.0.model.tyre_stiffness_n_m", "[3.0e6, -1.0]")],
            &["vehicles.0[1].model.tyre_stiffness_n_m.1 = -1 "],
        ),
        Case::edit(
            "centre of gravity outside the wheelbase",
            &[Set("vehicles.0.model.cg_behind_front_m", "9.0")],
            &["vehicles.0[1].model.cg_behind_front_m = 9 must lie between the axles"],
        ),
        Case::edit(
            "half car without preset and fields",
            &[Set("vehicles.0.model", "{ kind = \"half_car\", body_mass_kg = 1000.0 }")],
            &["vehicles.0[1].model.pitch_inertia_kg_m2 = (missing)"],
        ),
        Case::edit(
            "moving force: spacings do not match loads",
            &[Set(
                "vehicles.0.model",
                "{ kind = \"moving_force\", axle_loads_n = [1e5, 1e5], axle_spacing_m = [] }",
            )],
            &["vehicles.0[1].model.axle_spacing_m = [] must have 1 entries"],
        ),
        Case::edit(
            "moving force: negative load",
            &[Set(
                "vehicles.0.model",
                "{ kind = \"moving_force\", axle_loads_n = [-1e5] }",
            )],
            &["vehicles.0[1].model.axle_loads_n.0 = -100000 "],
        ),
        Case::edit(
            "two vehicles with the same id",
            &[Set(
                "vehicles.1",
                "{ id = 1, model = { kind = \"half_car\", preset = \"vbi2d_e01\" }, speed_m_s = 10.0 }",
            )],
            &["vehicles.1[1].id = 1 is used twice"],
        ),
        // Road.
        Case::edit(
            "approach shorter than the wheelbase",
            &[Set("road.approach_m", "3.0"), Set("wim_stations.0.position_m", "-1.0")],
            &["road.approach_m = 3 must be longer than vehicle 0's wheelbase 4.27 m"],
        ),
        Case::edit(
            "approach zero",
            &[Set("road.approach_m", "0.0")],
            &["road.approach_m = 0 "],
        ),
        Case::edit(
            "exit negative",
            &[Set("road.exit_m", "-1.0")],
            &["road.exit_m = -1 "],
        ),
        Case::edit(
            "approach beyond 100 km",
            &[Set("road.approach_m", "1e300")],
            &["road.approach_m = 1e300 must be at most 100000 m"],
        ),
        Case::edit(
            "unknown road class",
            &[Set("road.profile.class", "\"Z\"")],
            &["scenario.toml: road.profile.class: unknown variant `Z`"],
        ),
        Case::edit(
            "unknown road kind",
            &[Set("road.profile.kind", "\"gravel\"")],
            &["scenario.toml: road.profile.kind: unknown variant `gravel`"],
        ),
        Case::edit(
            "ISO 8608 without class or G_d",
            &[Set("road.profile", "{ kind = \"iso8608\" }")],
            &["road.profile.class = (missing)"],
        ),
        Case::edit(
            "ISO 8608 band inverted",
            &[Set("road.profile.n1_cycles_m", "5.0")],
            &["road.profile.n1_cycles_m = 5 must be less than n2_cycles_m = 4"],
        ),
        Case::edit(
            "ISO 8608 G_d beyond any road",
            &[Set("road.profile.gd_n0_m3", "1e300")],
            &["road.profile.gd_n0_m3 = 1e300 is beyond any road"],
        ),
        Case::edit("road CSV missing", &[CSV_ROAD], &["road.csv", "No such file or directory"]),
        Case::edit(
            "road CSV path empty",
            &[Set("road.profile", "{ kind = \"csv\", path = \"\" }")],
            &["road.profile.path = \"\" must name a CSV file"],
        ),
        Case::edit(
            "road CSV non-numeric elevation",
            &[CSV_ROAD],
            &["road.csv: line 3: elevation_m = `abc` is not a number"],
        )
        .file("road.csv", &road_csv("-200,0\n-100,abc\n200,0\n")),
        Case::edit(
            "road CSV NaN x",
            &[CSV_ROAD],
            &["road.csv: line 3: x_m = NaN is not finite"],
        )
        .file("road.csv", &road_csv("-200,0\nNaN,0\n200,0\n")),
        Case::edit(
            "road CSV x not increasing",
            &[CSV_ROAD],
            &["road.csv: line 4: x_m = -150 is not greater than the previous x_m = -100"],
        )
        .file("road.csv", &road_csv("-200,0\n-100,0\n-150,0\n200,0\n")),
        Case::edit(
            "road CSV row with a missing field",
            &[CSV_ROAD],
            &["road.csv: line 3: expected 2 fields as in the header, found 1"],
        )
        .file("road.csv", &road_csv("-200,0\n-100\n200,0\n")),
        Case::edit(
            "road CSV header without x_m",
            &[CSV_ROAD],
            &["road.csv: line 1: header has no column `x_m`"],
        )
        .file("road.csv", b"x,z\n-200,0\n200,0\n"),
        Case::edit(
            "road CSV too short for the run",
            &[CSV_ROAD],
            &["road.csv: the profile covers [-10, 10] m but the simulation needs"],
        )
        .file("road.csv", &road_csv("-10,0\n10,0\n")),
        // Bridge model and damage regions.
        Case::edit(
            "stiffness region beyond the span",
            &[Set(
                "bridge.stiffness_regions",
                "[{ start_m = 25.0, end_m = 35.0, ei_factor = 0.5 }]",
            )],
            &["bridge.stiffness_regions.0.end_m = 35 must lie in (25, 30] m"],
        ),
        Case::edit(
            "stiffness region before the span",
            &[Set(
                "bridge.stiffness_regions",
                "[{ start_m = -5.0, end_m = 5.0, ei_factor = 0.5 }]",
            )],
            &["bridge.stiffness_regions.0.start_m = -5 must lie on the girder [0, 30] m"],
        ),
        Case::edit(
            "elastic support 1e300 times stiffer than a rigid one needs",
            &[Set(
                "bridge.supports",
                "[\"pinned\", { elastic = { vertical_n_m = 1e300, rotational_n_m_rad = 0.0 } }]",
            )],
            &[
                "bridge.supports.1.vertical_n_m = 1e300",
                "times the girder's EI / L^3",
                "a rigid support is \"pinned\"",
            ],
        ),
        Case::edit(
            "haunch with three values",
            &[Set(
                "bridge.sections",
                "[{ start_m = 0.0, end_m = 5.0, flexural_rigidity_n_m2 = [1e10, 2e10, 3e10] }]",
            )],
            &["bridge.sections.0.flexural_rigidity_n_m2: a haunch is [at start, at end]: 2 values, not 3"],
        ),
        Case::edit(
            "stiffness region with EI factor zero",
            &[Set(
                "bridge.stiffness_regions",
                "[{ start_m = 5.0, end_m = 10.0, ei_factor = 0.0 }]",
            )],
            &["bridge.stiffness_regions.0.ei_factor = 0 "],
        ),
        Case::edit(
            "model with zero elements",
            &[Set("bridge.model.elements", "0")],
            &["bridge.model.elements = 0 must be between 1 and 20000"],
        ),
        Case::edit(
            "modal model with more modes than its mesh has DOFs to spare",
            &[Set("bridge.model", "{ kind = \"modal\", modes = 30, elements = 20 }")],
            &["bridge.model.elements = 20 must be at least 2 x modes = 60"],
        ),
        Case::edit(
            "model whose memory estimate is above the limit",
            &[Set(
                "bridge.model",
                "{ kind = \"modal\", modes = 5000, elements = 20000 }",
            )],
            &["bridge.model.modes = 5000 needs about ", "GiB to build and run (estimate), above the limit of 2.0 GiB"],
        ),
        // Output options.
        Case::edit(
            "block_samples zero",
            &[Set("output.layout", "\"block\""), Set("output.block_samples", "0")],
            &["output.block_samples = 0 must be in 1..=100000"],
        ),
        Case::edit(
            "axle-load rate does not divide the solver rate",
            &[Set("output.axle_load_rate_hz", "300.0")],
            &["output.axle_load_rate_hz = 300 must divide the solver rate 1000 Hz"],
        ),
        Case::edit(
            "bridge-state rate above the solver rate",
            &[Set("output.bridge_state_rate_hz", "3000.0")],
            &["output.bridge_state_rate_hz = 3000 must divide the solver rate 1000 Hz"],
        ),
        Case::edit(
            "bridge-state rate NaN",
            &[Set("output.bridge_state_rate_hz", "nan")],
            &["output.bridge_state_rate_hz = NaN "],
        ),
        Case::edit(
            "axle-load rate below one message in 30 days",
            &[Set("output.axle_load_rate_hz", "1e-12")],
            &["output.axle_load_rate_hz = 0.000000000001 is too low"],
        ),
    ]);
    cases
}
