//! The scenario table of a train (`model = { kind = "train", ... }`): a preset train or a
//! composition of cars, as vehicles or as moving forces.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::dynamics::VehicleDynamics;
use super::pitch_plane_spec::{positive, preset_or_default, required};
use super::rake::Suspension;
use super::train::{CarParams, Representation, Train};
use super::train_presets::{car_preset, train_preset, CAR_PRESETS, TRAIN_PRESETS};
use crate::base::schema as bounds;
use crate::error::{num, require_non_negative, Error, Result};

/// Most cars in one composition entry (`count`) and in one train.
pub const MAX_CARS: u32 = 100;

/// A train: `preset` or `cars`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
#[schemars(transform = bounds::exactly_one_key(&["preset", "cars"]))]
pub struct TrainSpec {
    /// A preset train: `hslm_a1` .. `hslm_a10` (EN 1991-2 Annex E; as vehicles, with
    /// typical high-speed bogies and every axle carrying P), `ice3` (8 cars), `ice3_double`
    /// (16 cars, 64 axles) or `manchester_benchmark` (one car). Or give `cars`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(extend("enum" = TRAIN_PRESETS))]
    pub preset: Option<String>,
    /// The cars front to rear, each a preset car or its own parameters (conventional cars,
    /// each on its own two bogies). Or give `preset`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    #[schemars(length(min = 1))]
    pub cars: Vec<CarSpec>,
    /// `"vehicles"` (default): every car's pitch-plane model on linearised Hertz
    /// contacts; `"moving_forces"`: each wheelset's static load as a constant force.
    #[serde(default)]
    pub representation: RepresentationSpec,
}

/// How a train loads the track.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum RepresentationSpec {
    #[default]
    Vehicles,
    MovingForces,
}

/// One entry of a composition: a car, `count` times. Fields next to `preset` override it.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CarSpec {
    /// `manchester_benchmark`, `ice3_end_car`, `ice3_coach` or `ice3_middle_coach`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(extend("enum" = CAR_PRESETS))]
    pub preset: Option<String>,
    /// How many such cars in a row (default 1, at most 100).
    #[serde(default = "one", skip_serializing_if = "is_one")]
    #[schemars(range(min = 1, max = MAX_CARS))]
    pub count: u32,
    /// Turned round (its overhangs swapped), e.g. the rear end car (default false).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub reversed: bool,
    /// Car body mass (kg).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(transform = bounds::positive)]
    pub body_mass_kg: Option<f64>,
    /// Car body pitch inertia about its centre (kg m^2).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(transform = bounds::positive)]
    pub body_pitch_inertia_kg_m2: Option<f64>,
    /// Distance between the bogie centres (m).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(transform = bounds::positive)]
    pub bogie_spacing_m: Option<f64>,
    /// Front coupler to front bogie centre (m), at least half the wheelbase.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(transform = bounds::positive)]
    pub front_overhang_m: Option<f64>,
    /// Rear bogie centre to rear coupler (m), at least half the wheelbase.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(transform = bounds::positive)]
    pub rear_overhang_m: Option<f64>,
    /// Bogie frame mass (kg).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(transform = bounds::positive)]
    pub bogie_mass_kg: Option<f64>,
    /// Bogie frame pitch inertia (kg m^2).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(transform = bounds::positive)]
    pub bogie_pitch_inertia_kg_m2: Option<f64>,
    /// Bogie wheelbase (m).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(transform = bounds::positive)]
    pub wheelbase_m: Option<f64>,
    /// Wheelset mass (kg).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(transform = bounds::positive)]
    pub wheelset_mass_kg: Option<f64>,
    /// Primary suspension per wheelset, both axleboxes (N/m).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(transform = bounds::positive)]
    pub primary_stiffness_n_m: Option<f64>,
    /// Primary damping per wheelset (N s/m), >= 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(range(min = 0))]
    pub primary_damping_n_s_m: Option<f64>,
    /// Secondary suspension per bogie, both sides (N/m).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(transform = bounds::positive)]
    pub secondary_stiffness_n_m: Option<f64>,
    /// Secondary damping per bogie (N s/m), >= 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(range(min = 0))]
    pub secondary_damping_n_s_m: Option<f64>,
    /// Wheel-rail contact per wheelset (N/m). Default: the linearised Hertz spring at the
    /// wheelset's static load (about 2.5e9 N/m at 170 kN).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(transform = bounds::positive)]
    pub contact_stiffness_n_m: Option<f64>,
}

fn one() -> u32 {
    1
}

fn is_one(n: &u32) -> bool {
    *n == 1
}

impl TrainSpec {
    /// The model name in the truth records.
    pub fn model_name(&self) -> String {
        match &self.preset {
            Some(p) => format!("train/{p}"),
            None => "train".into(),
        }
    }

    /// Validates and builds the train; `path` is its scenario path.
    pub fn build(&self, path: &str) -> Result<VehicleDynamics> {
        let mut train = match (&self.preset, self.cars.is_empty()) {
            (Some(name), true) => train_preset(name).ok_or_else(|| {
                Error::invalid(
                    format!("{path}.preset"),
                    format!("\"{name}\""),
                    format!("is not a train preset; known: {}", TRAIN_PRESETS.join(", ")),
                )
            })?,
            (None, false) => Train {
                name: String::new(),
                units: self.cars(path)?.iter().map(CarParams::unit).collect(),
                axles_only: None,
            },
            (Some(name), false) => {
                return Err(Error::invalid(
                    path,
                    format!(
                        "{{ preset = \"{name}\", cars = [{} entries] }}",
                        self.cars.len()
                    ),
                    "gives both a preset and cars: give preset or cars",
                ))
            }
            // `cars` absent and `cars = []` deserialize alike: the message fits both.
            (None, true) => {
                return Err(Error::invalid(
                    path,
                    "a train without a preset or a car",
                    format!(
                        "needs preset = \"...\" (one of {}) or cars = [ ... ] with at least \
                         one car",
                        TRAIN_PRESETS.join(", ")
                    ),
                ))
            }
        };
        train.name = self.model_name();
        let representation = match self.representation {
            RepresentationSpec::Vehicles => Representation::Vehicles,
            RepresentationSpec::MovingForces => Representation::MovingForces,
        };
        train.build_for(representation, &format!("{path}.representation"))
    }

    /// The composition, car by car, each checked.
    fn cars(&self, path: &str) -> Result<Vec<CarParams>> {
        let mut cars = Vec::new();
        for (i, entry) in self.cars.iter().enumerate() {
            let at = format!("{path}.cars.{i}");
            if entry.count == 0 || entry.count > MAX_CARS {
                return Err(Error::invalid(
                    format!("{at}.count"),
                    entry.count,
                    format!("must be between 1 and {MAX_CARS}"),
                ));
            }
            let car = entry.params(&at)?;
            cars.extend(std::iter::repeat_n(car, entry.count as usize));
            if cars.len() > MAX_CARS as usize {
                return Err(Error::invalid(
                    format!("{at}.count"),
                    entry.count,
                    format!("makes the train longer than {MAX_CARS} cars"),
                ));
            }
        }
        Ok(cars)
    }
}

impl CarSpec {
    /// The car's parameters: the preset's, overridden field by field, each checked.
    fn params(&self, path: &str) -> Result<CarParams> {
        let f = |name: &str| format!("{path}.{name}");
        let base = preset_or_default(path, &self.preset, &CAR_PRESETS, |name| {
            car_preset(name).map(Some)
        })?;
        let pick = |own: Option<f64>, from: fn(&CarParams) -> f64| own.or(base.as_ref().map(from));
        let non_negative = |own, from, name: &str| {
            require_non_negative(&f(name), required(pick(own, from), &f(name))?)
        };
        let wheelbase = positive(pick(self.wheelbase_m, |c| c.wheelbase_m), &f("wheelbase_m"))?;
        let overhang = |own, from, name: &str| -> Result<f64> {
            let value = positive(pick(own, from), &f(name))?;
            if value < 0.5 * wheelbase {
                return Err(Error::invalid(
                    f(name),
                    num(value),
                    format!(
                        "must be at least half the wheelbase ({} m): the wheelsets would \
                         reach past the coupler onto the next car's",
                        num(0.5 * wheelbase)
                    ),
                ));
            }
            Ok(value)
        };
        let car = CarParams {
            body_mass_kg: positive(
                pick(self.body_mass_kg, |c| c.body_mass_kg),
                &f("body_mass_kg"),
            )?,
            body_pitch_inertia_kg_m2: positive(
                pick(self.body_pitch_inertia_kg_m2, |c| {
                    c.body_pitch_inertia_kg_m2
                }),
                &f("body_pitch_inertia_kg_m2"),
            )?,
            bogie_spacing_m: positive(
                pick(self.bogie_spacing_m, |c| c.bogie_spacing_m),
                &f("bogie_spacing_m"),
            )?,
            front_overhang_m: overhang(
                self.front_overhang_m,
                |c| c.front_overhang_m,
                "front_overhang_m",
            )?,
            rear_overhang_m: overhang(
                self.rear_overhang_m,
                |c| c.rear_overhang_m,
                "rear_overhang_m",
            )?,
            bogie_mass_kg: positive(
                pick(self.bogie_mass_kg, |c| c.bogie_mass_kg),
                &f("bogie_mass_kg"),
            )?,
            bogie_pitch_inertia_kg_m2: positive(
                pick(self.bogie_pitch_inertia_kg_m2, |c| {
                    c.bogie_pitch_inertia_kg_m2
                }),
                &f("bogie_pitch_inertia_kg_m2"),
            )?,
            wheelbase_m: wheelbase,
            wheelset_mass_kg: positive(
                pick(self.wheelset_mass_kg, |c| c.wheelset_mass_kg),
                &f("wheelset_mass_kg"),
            )?,
            primary: Suspension {
                stiffness_n_m: positive(
                    pick(self.primary_stiffness_n_m, |c| c.primary.stiffness_n_m),
                    &f("primary_stiffness_n_m"),
                )?,
                damping_n_s_m: non_negative(
                    self.primary_damping_n_s_m,
                    |c: &CarParams| c.primary.damping_n_s_m,
                    "primary_damping_n_s_m",
                )?,
            },
            secondary: Suspension {
                stiffness_n_m: positive(
                    pick(self.secondary_stiffness_n_m, |c| c.secondary.stiffness_n_m),
                    &f("secondary_stiffness_n_m"),
                )?,
                damping_n_s_m: non_negative(
                    self.secondary_damping_n_s_m,
                    |c: &CarParams| c.secondary.damping_n_s_m,
                    "secondary_damping_n_s_m",
                )?,
            },
            contact_stiffness_n_m: match self.contact_stiffness_n_m {
                Some(k) => Some(crate::error::require_positive(
                    &f("contact_stiffness_n_m"),
                    k,
                )?),
                None => base.and_then(|c| c.contact_stiffness_n_m),
            },
        };
        Ok(if self.reversed { car.reversed() } else { car })
    }
}
