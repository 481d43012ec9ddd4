//! Trains: presets, compositions, speeds and timetable entries.

use super::harness::{Case, Edit::Set};

/// The one vehicle of the default scenario, id 1, made a train.
pub(super) fn railway_cases() -> Vec<Case> {
    vec![
        Case::edit(
            "unknown train preset",
            &[Set(
                "vehicles.0.model",
                "{ kind = \"train\", preset = \"hslm_a11\" }",
            )],
            &[
                "vehicles.0[1].model.preset = \"hslm_a11\"",
                "is not a train preset",
                "hslm_a10",
            ],
        ),
        Case::edit(
            "a load model as vehicles",
            &[Set(
                "vehicles.0.model",
                "{ kind = \"train\", preset = \"en1991_type7\" }",
            )],
            &[
                "vehicles.0[1].model.representation = \"vehicles\"",
                "en1991_type7",
                "use representation = \"moving_forces\"",
            ],
        ),
        Case::edit(
            "unknown car preset",
            &[Set(
                "vehicles.0.model",
                "{ kind = \"train\", cars = [{ preset = \"tgv\" }] }",
            )],
            &[
                "vehicles.0[1].model.cars.0.preset = \"tgv\"",
                "ice3_end_car",
            ],
        ),
        Case::edit(
            "composition with no cars",
            &[Set("vehicles.0.model", "{ kind = \"train\", cars = [] }")],
            &[
                "vehicles.0[1].model = a train without a preset or a car",
                "at least one car",
            ],
        ),
        Case::edit(
            "train with neither a preset nor cars",
            &[Set("vehicles.0.model", "{ kind = \"train\" }")],
            &[
                "vehicles.0[1].model = a train without a preset or a car",
                "needs preset = \"...\" (one of hslm_a1",
            ],
        ),
        Case::edit(
            "preset and cars together",
            &[Set(
                "vehicles.0.model",
                "{ kind = \"train\", preset = \"ice3\", cars = [{ preset = \"ice3_coach\" }] }",
            )],
            &[
                "vehicles.0[1].model = { preset = \"ice3\", cars = [1 entries] }",
                "give preset or cars",
            ],
        ),
        Case::edit(
            "overlapping axles",
            &[Set(
                "vehicles.0.model",
                "{ kind = \"train\", cars = [{ preset = \"manchester_benchmark\", \
                 front_overhang_m = 1.0 }] }",
            )],
            &[
                "vehicles.0[1].model.cars.0.front_overhang_m = 1",
                "at least half the wheelbase (1.28 m)",
            ],
        ),
        Case::edit(
            "car count of zero",
            &[Set(
                "vehicles.0.model",
                "{ kind = \"train\", cars = [{ preset = \"ice3_coach\", count = 0 }] }",
            )],
            &["vehicles.0[1].model.cars.0.count = 0", "between 1 and 100"],
        ),
        Case::edit(
            "car without its parameters",
            &[Set(
                "vehicles.0.model",
                "{ kind = \"train\", cars = [{ body_mass_kg = 3e4 }] }",
            )],
            &["vehicles.0[1].model.cars.0.wheelbase_m = (missing)"],
        ),
        Case::edit(
            "train faster than 150 m/s",
            &[
                Set(
                    "vehicles.0.model",
                    "{ kind = \"train\", preset = \"ice3\" }",
                ),
                Set("vehicles.0.speed_m_s", "160.0"),
            ],
            &[
                "vehicles.0[1].speed_m_s = 160",
                "at most 150 m/s for a train",
            ],
        ),
        Case::edit(
            "unknown track irregularity class",
            &[Set("road.profile", "{ kind = \"track\", class = \"fra_7\" }")],
            &["road.profile.class", "unknown variant `fra_7`", "german_low"],
        ),
        Case::edit(
            "dipped joint of negative depth",
            &[Set(
                "road.profile",
                "{ kind = \"track\", class = \"german_low\", features = [{ kind = \"dipped_joint\", \
                 position_m = 10.0, length_m = 2.0, depth_m = -0.002 }] }",
            )],
            &["road.profile.features.0.depth_m = -0.002"],
        ),
        Case::edit(
            "trigger with generated traffic",
            &[
                Set("output.trigger", "{ pre_s = 5.0 }"),
                Set("traffic", "{ lanes = [{ flow_per_hour = 100.0 }] }"),
                Set("duration_s", "60.0"),
            ],
            &["output.trigger", "needs every vehicle listed"],
        ),
        Case::edit(
            "trigger window longer than an hour",
            &[Set("output.trigger", "{ post_s = 4000.0 }")],
            &["output.trigger.post_s = 4000", "between 0 and 3600 s"],
        ),
        Case::edit(
            "sleeper spacing out of range",
            &[Set("road.sleeper_spacing_m", "0.1")],
            &["road.sleeper_spacing_m = 0.1", "between 0.3 and 1.0 m"],
        ),
        Case::edit(
            "timetable entry after 30 days",
            &[
                Set(
                    "vehicles.0.model",
                    "{ kind = \"train\", preset = \"ice3\" }",
                ),
                Set("vehicles.0.entry_time_s", "3.0e6"),
            ],
            &["vehicles.0[1].entry_time_s = 3000000", "at most 30 days"],
        ),
    ]
}
