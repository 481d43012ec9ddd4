//! Monitoring (sensor chains, DAQ nodes, faults, ambient, WIM models), traffic, and the
//! bridge's condition (temperature, damage).

use super::harness::{
    Case, Edit,
    Edit::{Remove, Set},
};

/// Sensor presets and chains, DAQ nodes, faults, ambient excitation, WIM models.
/// Instruments riding on vehicles and on the road (drive-by, B-WIM).
pub(super) fn instrument_cases() -> Vec<Case> {
    // sensors.0 is A1, an accelerometer at x = 3.75 m; the one vehicle is id 1, a half car.
    const ON_AXLE: Edit = Set("sensors.0.vehicle", "{ id = 1, axle = 1 }");
    vec![
        Case::edit(
            "vehicle sensor on a vehicle that does not exist",
            &[
                Remove("sensors.0.position_m"),
                Set("sensors.0.vehicle", "{ id = 9, axle = 1 }"),
            ],
            &[
                "sensors.0[A1].vehicle.id = 9",
                "is not the id of a [[vehicles]] entry",
                "[1]",
            ],
        ),
        Case::edit(
            "vehicle sensor on an axle the model lacks",
            &[
                Remove("sensors.0.position_m"),
                Set("sensors.0.vehicle", "{ id = 1, axle = 3 }"),
            ],
            &[
                "sensors.0[A1].vehicle.axle = 3",
                "is not an axle of vehicle 1",
                "has 2",
            ],
        ),
        Case::edit(
            "vehicle sensor on axle 0",
            &[
                Remove("sensors.0.position_m"),
                Set("sensors.0.vehicle", "{ id = 1, axle = 0 }"),
            ],
            &["sensors.0[A1].vehicle.axle = 0", "counts from 1"],
        ),
        Case::edit(
            "vehicle sensor on a moving force",
            &[
                Set(
                    "vehicles.0.model",
                    "{ kind = \"moving_force\", axle_loads_n = [1e5] }",
                ),
                Remove("sensors.0.position_m"),
                ON_AXLE,
            ],
            &["sensors.0[A1].vehicle.axle = 1", "is a moving force"],
        ),
        Case::edit(
            "vehicle sensor with both an axle and a body offset",
            &[
                Remove("sensors.0.position_m"),
                Set(
                    "sensors.0.vehicle",
                    "{ id = 1, axle = 1, body_offset_m = 1.0 }",
                ),
            ],
            &[
                "sensors.0[A1].vehicle = { id = 1, axle = 1, body_offset_m = 1 }",
                "needs exactly one of axle",
            ],
        ),
        Case::edit(
            "vehicle sensor with neither an axle nor a body offset",
            &[
                Remove("sensors.0.position_m"),
                Set("sensors.0.vehicle", "{ id = 1 }"),
            ],
            &["sensors.0[A1].vehicle = { id = 1 }", "needs one of axle"],
        ),
        Case::edit(
            "vehicle sensor on the body 20 m behind the front axle of a half car",
            &[
                Remove("sensors.0.position_m"),
                Set("sensors.0.vehicle", "{ id = 1, body_offset_m = 20.0 }"),
            ],
            &[
                "sensors.0[A1].vehicle.body_offset_m = 20",
                "is off the body of vehicle 1",
            ],
        ),
        Case::edit(
            "vehicle sensor with a position on the bridge too",
            &[ON_AXLE],
            &["sensors.0[A1].position_m = 3.75", "is for a bridge sensor"],
        ),
        Case::edit(
            "strain gauge on a vehicle",
            &[
                Remove("sensors.7.position_m"),
                Set("sensors.7.vehicle", "{ id = 1, axle = 1 }"),
            ],
            &["sensors.7[S1].kind = \"strain\"", "only accelerometers"],
        ),
        Case::edit(
            "bridge sensor without a position",
            &[Remove("sensors.0.position_m")],
            &["sensors.0[A1].position_m = (missing)", "is required"],
        ),
        Case::edit(
            "GNSS rate above the solver rate",
            &[Set(
                "gnss",
                "[{ id = \"G\", vehicle = 1, rate_hz = 2000.0 }]",
            )],
            &[
                "gnss.0[G].rate_hz = 2000",
                "above the solver rate 1/dt = 1000 Hz",
            ],
        ),
        Case::edit(
            "GNSS on a vehicle that does not exist",
            &[Set("gnss", "[{ id = \"G\", vehicle = 4 }]")],
            &[
                "gnss.0[G].vehicle = 4",
                "is not the id of a [[vehicles]] entry",
            ],
        ),
        Case::edit(
            "GNSS with a negative noise",
            &[Set(
                "gnss",
                "[{ id = \"G\", vehicle = 1, position_noise_m = -1.0 }]",
            )],
            &["gnss.0[G].position_noise_m = -1"],
        ),
        Case::edit(
            "axle detector off the road",
            &[Set(
                "axle_detectors",
                "[{ id = \"T1\", position_m = -150.0 }]",
            )],
            &[
                "axle_detectors.0[T1].position_m = -150",
                "is off the road",
                "[-100, 60] m",
            ],
        ),
        Case::edit(
            "axle detector that misses every axle",
            &[Set(
                "axle_detectors",
                "[{ id = \"T1\", position_m = -5.0, miss_probability = 1.0 }]",
            )],
            &["axle_detectors.0[T1].miss_probability = 1", "[0, 1)"],
        ),
        Case::edit(
            "two axle detectors with one id",
            &[Set(
                "axle_detectors",
                "[{ id = \"T1\", position_m = -5.0 }, { id = \"T1\", position_m = -3.0 }]",
            )],
            &["axle_detectors.1[T1].id = \"T1\"", "is used twice"],
        ),
    ]
}

pub(super) fn monitoring_cases() -> Vec<Case> {
    const LOWNOISE: Edit = Set("sensors.0.preset", "\"mems_lownoise\"");
    const NODE: Edit = Set(
        "daq_nodes",
        "[{ id = \"N1\", clock = { drift_ppm = 20.0 } }]",
    );
    vec![
        Case::edit(
            "unknown sensor preset",
            &[Set("sensors.0.preset", "\"mems_fancy\"")],
            &["unknown variant `mems_fancy`", "mems_lownoise"],
        ),
        Case::edit(
            "accelerometer preset on a strain gauge",
            &[Set("sensors.7.preset", "\"mems_lownoise\"")],
            &["sensors.7[S1].preset", "mems_lownoise"],
        ),
        Case::edit(
            "load cell off a support",
            &[Set("sensors.0.kind", "\"load_cell\"")],
            &[
                "sensors.0[A1].position_m = ",
                "is not on a support",
                "[0, 30] m",
            ],
        ),
        Case::edit(
            "inclinometer preset on an accelerometer",
            &[Set("sensors.0.preset", "\"inclinometer_mems\"")],
            &["sensors.0[A1].preset = inclinometer_mems is a preset for inclinometer"],
        ),
        Case::edit(
            "negative chain noise density",
            &[LOWNOISE, Set("sensors.0.chain.noise_density", "-1.0")],
            &["sensors.0[A1].chain.noise_density = -1"],
        ),
        Case::edit(
            "rate not supported by the preset",
            &[
                Set("solver.dt_s", "0.0001"),
                LOWNOISE,
                Set("sensors.0.rate_hz", "5000.0"),
            ],
            &["sensors.0[A1].rate_hz = 5000", "mems_lownoise"],
        ),
        Case::edit(
            "ADC with 40 bits",
            &[
                LOWNOISE,
                Set("sensors.0.chain.adc", "{ bits = 40, range = 1.0 }"),
            ],
            &["sensors.0[A1].chain.adc.bits = 40"],
        ),
        Case::edit(
            "clock drift beyond 1000 ppm",
            &[
                Set(
                    "daq_nodes",
                    "[{ id = \"N1\", clock = { drift_ppm = 2000.0 } }]",
                ),
                Set("sensors.0.daq_node", "\"N1\""),
            ],
            &["daq_nodes.0[N1].clock.drift_ppm = 2000"],
        ),
        Case::edit(
            "sensor on an unknown DAQ node",
            &[NODE, Set("sensors.0.daq_node", "\"N9\"")],
            &["sensors.0[A1].daq_node = \"N9\" is not a [[daq_nodes]] id"],
        ),
        Case::edit(
            "clocked sensor at the solver rate",
            &[
                NODE,
                Set("sensors.0.daq_node", "\"N1\""),
                Set("sensors.0.rate_hz", "1000.0"),
            ],
            &["sensors.0[A1].rate_hz = 1000 must be at most half the solver rate"],
        ),
        Case::edit(
            "loss probability above 1",
            &[Set(
                "sensors.0.faults",
                "{ loss = { kind = \"random\", probability = 1.5 } }",
            )],
            &["sensors.0[A1].faults.loss.probability = 1.5"],
        ),
        Case::edit(
            "negative spike rate",
            &[Set(
                "sensors.0.faults",
                "{ spikes = { rate_per_hour = -1.0, amplitude = 1.0 } }",
            )],
            &["sensors.0[A1].faults.spikes.rate_per_hour = -1"],
        ),
        Case::edit(
            "ambient target negative",
            &[Set("ambient", "{ target_rms_m_s2 = -1.0 }")],
            &["ambient.target_rms_m_s2 = -1"],
        ),
        Case::edit(
            "ambient band above the Nyquist frequency",
            &[Set(
                "ambient",
                "{ target_rms_m_s2 = 0.01, band_hz = [1.0, 600.0] }",
            )],
            &["ambient.band_hz", "600"],
        ),
        Case::edit(
            "unknown COST 323 class",
            &[Set(
                "wim_stations.0.model",
                "{ kind = \"cost323\", class = \"E(30)\" }",
            )],
            &["wim_stations.0[WIM1].model.class = \"E(30)\"", "B+(7)"],
        ),
        Case::edit(
            "negative WIM noise",
            &[Set(
                "wim_stations.0.model",
                "{ kind = \"physics\", noise_rel = -0.1 }",
            )],
            &["wim_stations.0[WIM1].model.noise_rel = -0.1"],
        ),
    ]
}

/// Generated traffic.
pub(super) fn traffic_cases() -> Vec<Case> {
    const DURATION: Edit = Set("duration_s", "60.0");
    vec![
        Case::edit(
            "negative lane flow",
            &[DURATION, Set("traffic", "{ lanes = [{ flow_per_hour = -5.0 }] }")],
            &["traffic.lanes.0.flow_per_hour = -5"],
        ),
        Case::edit(
            "class shares not summing to 1",
            &[
                DURATION,
                Set(
                    "traffic",
                    "{ lanes = [{ flow_per_hour = 100.0 }], classes = { car = 0.5, truck_2axle = 0.2 } }",
                ),
            ],
            &["traffic.classes"],
        ),
        Case::edit(
            "unknown traffic class",
            &[
                DURATION,
                Set(
                    "traffic",
                    "{ lanes = [{ flow_per_hour = 100.0 }], classes = { car = 0.5, hovercraft = 0.5 } }",
                ),
            ],
            &["hovercraft"],
        ),
        Case::edit(
            "traffic without a duration",
            &[Set("traffic", "{ lanes = [{ flow_per_hour = 100.0 }] }")],
            &["duration_s = (missing) is required with [traffic]"],
        )
        .full_duration(),
        Case::edit(
            "vehicle direction 2",
            &[Set("vehicles.0.direction", "2")],
            &["vehicles.0[1].direction = 2 must be 1 (towards +x) or -1"],
        ),
    ]
}

/// Temperature and damage.
pub(super) fn condition_cases() -> Vec<Case> {
    const CSV_AIR: Edit = Set(
        "environment",
        "{ temperature = { kind = \"csv\", path = \"air.csv\" } }",
    );
    vec![
        Case::edit(
            "temperature CSV with a word for a value",
            &[CSV_AIR],
            &["air.csv", "line 3", "abc"],
        )
        .file("air.csv", b"time_s,temperature_c\n0,20\n60,abc\n"),
        Case::edit(
            "temperature CSV with the wrong header",
            &[CSV_AIR],
            &["air.csv", "time_s,temperature_c"],
        )
        .file("air.csv", b"t,T\n0,20\n60,21\n"),
        Case::edit(
            "temperature CSV going back in time",
            &[CSV_AIR],
            &["air.csv", "line 4"],
        )
        .file("air.csv", b"time_s,temperature_c\n0,20\n60,21\n30,22\n"),
        Case::edit("temperature CSV missing", &[CSV_AIR], &["air.csv"]),
        Case::edit(
            "settlement where there is no support",
            &[Set(
                "support_condition",
                "[{ position_m = 15.0, kind = \"settlement\", settlement_m = 0.01, onset_s = 0.0 }]",
            )],
            &["support_condition.0.position_m = 15 is not a support (supports at [0, 30] m"],
        ),
        Case::edit(
            "bearing degradation of a rigid support",
            &[Set(
                "support_condition",
                "[{ position_m = 30.0, kind = \"bearing_degradation\", reduction = 0.5, onset_s = 0.0 }]",
            )],
            &[
                "support_condition.0.kind = bearing_degradation needs an elastic support",
                "x = 30 m is roller",
            ],
        ),
        Case::edit(
            "settlement without its size",
            &[Set(
                "support_condition",
                "[{ position_m = 0.0, kind = \"settlement\", onset_s = 0.0 }]",
            )],
            &["support_condition.0.settlement_m = (missing) is needed by kind = settlement"],
        ),
        Case::edit(
            "scour on a modal model",
            &[
                Set(
                    "bridge.supports",
                    "[\"pinned\", { elastic = { vertical_n_m = 1e9 } }]",
                ),
                Set("bridge.model", "{ kind = \"modal\", modes = 10, elements = 40 }"),
                Set(
                    "support_condition",
                    "[{ position_m = 30.0, kind = \"scour\", reduction = 0.3, onset_s = 0.0 }]",
                ),
            ],
            &["bridge.model = modal", "cannot follow support_condition.0"],
        ),
        Case::edit(
            "damage region beyond the span",
            &[Set(
                "damage",
                "[{ start_m = 20.0, end_m = 40.0, reduction = 0.2, onset_s = 0.1 }]",
            )],
            &["damage.0.end_m = 40"],
        ),
        Case::edit(
            "damage reduction of 1",
            &[Set(
                "damage",
                "[{ start_m = 10.0, end_m = 12.0, reduction = 1.0, onset_s = 0.1 }]",
            )],
            &["damage.0.reduction = 1", "(0, 1)"],
        ),
        Case::edit(
            "damage reduction negative",
            &[Set(
                "damage",
                "[{ start_m = 10.0, end_m = 12.0, reduction = -0.1, onset_s = 0.1 }]",
            )],
            &["damage.0.reduction = -0.1"],
        ),
        Case::edit(
            "negative thermal lag",
            &[Set("environment", "{ lag_s = -3.0 }")],
            &["environment.lag_s = -3"],
        ),
        Case::edit(
            "damage on a modal model",
            &[
                Set("bridge.model", "{ kind = \"modal\", modes = 4 }"),
                Set(
                    "damage",
                    "[{ start_m = 10.0, end_m = 12.0, reduction = 0.2, onset_s = 0.1 }]",
                ),
            ],
            &["bridge.model", "modal"],
        ),
    ]
}
