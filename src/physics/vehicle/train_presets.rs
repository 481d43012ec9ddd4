//! Preset railway cars and trains, each with the source of its numbers.

use super::rake::Suspension;
use super::train::{en1991_freight, en1991_type4, hslm_a, CarParams, Train, HSLM_A};

/// The car presets (`cars = [{ preset = ... }]`).
pub const CAR_PRESETS: [&str; 4] = [
    "manchester_benchmark",
    "ice3_end_car",
    "ice3_coach",
    "ice3_middle_coach",
];

/// The train presets (`model = { kind = "train", preset = ... }`).
pub const TRAIN_PRESETS: [&str; 16] = [
    "hslm_a1",
    "hslm_a2",
    "hslm_a3",
    "hslm_a4",
    "hslm_a5",
    "hslm_a6",
    "hslm_a7",
    "hslm_a8",
    "hslm_a9",
    "hslm_a10",
    "ice3",
    "ice3_double",
    "en1991_type4",
    "en1991_type7",
    "en1991_type11",
    "manchester_benchmark",
];

/// The Manchester benchmark vehicle (Iwnicki 1998, Vehicle System Dynamics 30(3-4)
/// 295-313), vertical parameters as given in TTB-2D's TrainProp_Manchester_BenchMark.m
/// (Cantero 2022) and in a CRH380A parameter file; both agree except the primary
/// stiffness per axlebox (1200 vs 1220 kN/m): 1220 is taken, the value of the full 3-D
/// set. Per wheelset (two axleboxes) and per bogie (two sides) here. The body overhang
/// beyond the bogie centres (3.0 m) is TTB-2D's modelling choice.
pub fn manchester_benchmark() -> CarParams {
    CarParams {
        body_mass_kg: 32_000.0,
        body_pitch_inertia_kg_m2: 1.97e6,
        bogie_spacing_m: 19.0,
        front_overhang_m: 3.0,
        rear_overhang_m: 3.0,
        bogie_mass_kg: 2_615.0,
        bogie_pitch_inertia_kg_m2: 1_476.0,
        wheelbase_m: 2.56,
        wheelset_mass_kg: 1_813.0,
        primary: Suspension {
            stiffness_n_m: 2.0 * 1.22e6,
            damping_n_s_m: 2.0 * 4.0e3,
        },
        secondary: Suspension {
            stiffness_n_m: 2.0 * 4.3e5,
            damping_n_s_m: 2.0 * 2.0e4,
        },
        contact_stiffness_n_m: None,
    }
}

/// ICE 3 / Velaro E (AVE S-103) cars: Goicolea (2014), "Simplified mechanical description
/// of AVE S-103 - ICE3 Velaro E", UPM (oa.upm.es/43946), as tabulated in TTB-2D: bogie
/// centres 17.375 m apart, 2.5 m wheelbase, bogie 3500 kg, wheelset 1800 kg, primary
/// 1200 kN/m and 10 kN s/m per axlebox, secondary 350 kN/m and 20 kN s/m per side. The
/// end car's overhangs are 4.76 m (nose) and 3.70 m; the coaches' 3.70 m.
fn ice3(body_mass_kg: f64, pitch_kg_m2: f64, bogie_pitch_kg_m2: f64, nose_m: f64) -> CarParams {
    CarParams {
        body_mass_kg,
        body_pitch_inertia_kg_m2: pitch_kg_m2,
        bogie_spacing_m: 17.375,
        front_overhang_m: nose_m,
        rear_overhang_m: 3.70,
        bogie_mass_kg: 3_500.0,
        bogie_pitch_inertia_kg_m2: bogie_pitch_kg_m2,
        wheelbase_m: 2.5,
        wheelset_mass_kg: 1_800.0,
        primary: Suspension {
            stiffness_n_m: 2.0 * 1.2e6,
            damping_n_s_m: 2.0 * 1.0e4,
        },
        secondary: Suspension {
            stiffness_n_m: 2.0 * 3.5e5,
            damping_n_s_m: 2.0 * 2.0e4,
        },
        contact_stiffness_n_m: None,
    }
}

/// A car preset by name.
pub fn car_preset(name: &str) -> Option<CarParams> {
    match name {
        "manchester_benchmark" => Some(manchester_benchmark()),
        "ice3_end_car" => Some(ice3(47_800.0, 1_957_888.0, 1_715.0, 4.76)),
        "ice3_coach" => Some(ice3(47_800.0, 1_957_888.0, 1_715.0, 3.70)),
        "ice3_middle_coach" => Some(ice3(41_200.0, 1_687_552.0, 1_372.0, 3.70)),
        _ => None,
    }
}

/// One ICE 3 unit: end car, two coaches, two middle coaches, two coaches, end car turned.
fn ice3_cars() -> Vec<CarParams> {
    let [end, coach, middle] =
        ["ice3_end_car", "ice3_coach", "ice3_middle_coach"].map(|n| car_preset(n).unwrap());
    vec![
        end,
        coach,
        coach,
        middle,
        middle,
        coach,
        coach,
        end.reversed(),
    ]
}

/// A train preset by name.
pub fn train_preset(name: &str) -> Option<Train> {
    let of_cars = |cars: Vec<CarParams>| Train {
        name: name.to_string(),
        units: cars.iter().map(CarParams::unit).collect(),
        axles_only: None,
    };
    if let Some(number) = name.strip_prefix("hslm_a") {
        return match number.parse::<usize>() {
            Ok(i) if (1..=HSLM_A.len()).contains(&i) && number == i.to_string() => Some(hslm_a(i)),
            _ => None,
        };
    }
    match name {
        "ice3" => Some(of_cars(ice3_cars())),
        "ice3_double" => Some(of_cars([ice3_cars(), ice3_cars()].concat())),
        "en1991_type4" => Some(en1991_type4()),
        "en1991_type7" => Some(en1991_freight(name, 22.5, 2.5, 12.8, 1.8)),
        "en1991_type11" => Some(en1991_freight(name, 25.0, 2.5, 13.0, 2.0)),
        "manchester_benchmark" => Some(of_cars(vec![manchester_benchmark()])),
        _ => None,
    }
}
