//! Vehicle configuration as written in a scenario, with presets.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::dynamics::VehicleDynamics;
use super::models::{quarter_car, rigid_body_on_axles, sprung_mass, AxleParams};
use super::pitch_plane_spec::{
    named, pitch_plane_spec, positive, preset_or_default, require_within, validated_axles,
};
use super::train_spec::TrainSpec;
use super::truck_spec::{ArticulatedSpec, RigidTruckSpec};
use crate::base::schema as bounds;
use crate::error::{require_non_negative, require_positive, Error, Result};

/// A vehicle model (`kind = "..."` in the scenario).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(remote = "Self", rename_all = "snake_case", deny_unknown_fields)]
#[schemars(tag = "kind")]
pub enum VehicleModelSpec {
    /// Constant forces, no dynamics.
    MovingForce {
        /// Downward axle loads, front first (N), each >= 0; at least one.
        #[schemars(length(min = 1), inner(range(min = 0)))]
        axle_loads_n: Vec<f64>,
        /// Distances between consecutive axles (m), each > 0; one fewer than loads.
        #[serde(default)]
        #[schemars(transform = bounds::positive_items)]
        axle_spacing_m: Vec<f64>,
    },
    /// One mass on a spring and dashpot.
    SprungMass {
        /// Mass (kg).
        #[schemars(transform = bounds::positive)]
        mass_kg: f64,
        /// Spring stiffness (N/m).
        #[schemars(transform = bounds::positive)]
        stiffness_n_m: f64,
        /// Dashpot (N s/m), >= 0. Default 0.
        #[serde(default)]
        #[schemars(range(min = 0))]
        damping_n_s_m: f64,
    },
    /// Body, suspension, axle, tyre.
    QuarterCar {
        /// Sprung mass (kg).
        #[schemars(transform = bounds::positive)]
        body_mass_kg: f64,
        /// Unsprung mass (kg).
        #[schemars(transform = bounds::positive)]
        axle_mass_kg: f64,
        /// Suspension spring (N/m).
        #[schemars(transform = bounds::positive)]
        suspension_stiffness_n_m: f64,
        /// Suspension damper (N s/m), >= 0.
        #[schemars(range(min = 0))]
        suspension_damping_n_s_m: f64,
        /// Tyre spring (N/m).
        #[schemars(transform = bounds::positive)]
        tyre_stiffness_n_m: f64,
        /// Tyre damper (N s/m), >= 0. Default 0.
        #[serde(default)]
        #[schemars(range(min = 0))]
        tyre_damping_n_s_m: f64,
    },
    /// 4-DOF half car: body bounce and pitch, two axles. A `preset` gives every field;
    /// any field given next to it overrides the preset's value.
    HalfCar(HalfCarSpec),
    /// One body (bounce, pitch) on 2-4 suspended axles: cars and rigid trucks. A `preset`
    /// gives every field; fields next to it override it.
    RigidTruck(RigidTruckSpec),
    /// Tractor + semi-trailer: two bodies hinged at the fifth wheel, one unsprung mass
    /// per axle. A `preset` gives every field; fields next to it override it.
    Articulated(ArticulatedSpec),
    /// A railway train: a preset (HSLM-A1..A10, ICE 3, the Manchester benchmark vehicle)
    /// or a composition of cars, as vehicles or as moving forces. Its wheelsets are the
    /// axles, numbered front to rear along the whole train.
    Train(TrainSpec),
}
crate::base::tagged::kind_tagged!(VehicleModelSpec);

pitch_plane_spec! {
    /// Half-car parameters; arrays are (front, rear).
    pub struct HalfCarSpec, axle arrays of [f64; 2] {
        /// `two_axle_truck`, `vbi2d_e01` (docs/physics.md section 6) or `drive_by_van` (a
        /// light instrumented test vehicle for drive-by monitoring).
        #[schemars(transform = bounds::named_choices(&HALF_CAR_PRESETS, |name| {
            HalfCarSpec::preset(name).map(|p| HalfCarSpec { preset: None, ..p })
        }))]
        pub preset: Option<String>,
        /// Sprung mass (kg), axles excluded.
        #[schemars(transform = bounds::positive)]
        pub body_mass_kg: Option<f64>,
        /// Pitch moment of inertia of the body about its centre of gravity (kg m^2).
        #[schemars(transform = bounds::positive)]
        pub pitch_inertia_kg_m2: Option<f64>,
        /// Wheelbase (m).
        #[schemars(transform = bounds::positive)]
        pub axle_spacing_m: Option<f64>,
        /// Centre of gravity behind the front axle (m), between the axles; default
        /// mid-wheelbase.
        #[schemars(range(min = 0))]
        pub cg_behind_front_m: Option<f64>,
    }
}

/// The names `preset` accepts.
pub const HALF_CAR_PRESETS: [&str; 3] = ["two_axle_truck", "vbi2d_e01", "drive_by_van"];

impl HalfCarSpec {
    /// The preset's full parameter set.
    pub fn preset(name: &str) -> Option<HalfCarSpec> {
        match name {
            // Commonly attributed to Law & Zhu (2004); docs/physics.md section 6. CG assumed at
            // mid-wheelbase.
            "two_axle_truck" => Some(
                HalfCarSpec {
                    preset: Some(name.into()),
                    body_mass_kg: Some(17_735.0),
                    pitch_inertia_kg_m2: Some(1.47e5),
                    axle_spacing_m: Some(4.27),
                    cg_behind_front_m: None,
                    ..HalfCarSpec::default()
                }
                .with_axle_arrays([
                    [1_500.0, 1_000.0],
                    [2.47e6, 4.23e6],
                    [3.0e4, 4.0e4],
                    [3.74e6, 4.60e6],
                    [3.9e3, 4.3e3],
                ]),
            ),
            // VBI-2D example E01 (verification vehicle; body damping ~0.2 %).
            "vbi2d_e01" => Some(
                HalfCarSpec {
                    preset: Some(name.into()),
                    body_mass_kg: Some(10_500.0),
                    pitch_inertia_kg_m2: Some(50_000.0),
                    axle_spacing_m: Some(5.0),
                    cg_behind_front_m: None,
                    ..HalfCarSpec::default()
                }
                .with_axle_arrays([
                    [900.0, 900.0],
                    [6.0e6, 6.0e6],
                    [1.0e4, 1.0e4],
                    [1.75e6, 1.75e6],
                    [0.0, 0.0],
                ]),
            ),
            // A light instrumented test vehicle (a loaded van) for drive-by monitoring: its
            // body bounce (1.2 Hz) and wheel hop (10.8 Hz) sit where Gillespie (1992,
            // Fundamentals of Vehicle Dynamics, ch. 6) puts a light vehicle's ride and hop
            // frequencies (1-1.5 Hz, 10-12 Hz), so both stay clear of a short or medium
            // span's f1 (2-8 Hz). Suspension damping ~0.3 of critical. Chosen values, not
            // one published vehicle; tests/suite/vehicle_instruments.rs checks the frequencies.
            "drive_by_van" => Some(
                HalfCarSpec {
                    preset: Some(name.into()),
                    body_mass_kg: Some(1_800.0),
                    pitch_inertia_kg_m2: Some(2_400.0),
                    axle_spacing_m: Some(3.0),
                    cg_behind_front_m: None,
                    ..HalfCarSpec::default()
                }
                .with_axle_arrays([
                    [100.0, 100.0],
                    [6.0e4, 6.0e4],
                    [4.0e3, 4.0e3],
                    [4.0e5, 4.0e5],
                    [0.0, 0.0],
                ]),
            ),
            _ => None,
        }
    }

    /// Fields given here override the preset's.
    fn resolved(&self, path: &str) -> Result<HalfCarSpec> {
        let base = preset_or_default(path, &self.preset, &HALF_CAR_PRESETS, HalfCarSpec::preset)?;
        Ok(self.overriding(base))
    }
}

impl VehicleModelSpec {
    /// Validates and builds the dynamics; `path` is the scenario path ("vehicles.0.model").
    pub fn build(&self, path: &str) -> Result<VehicleDynamics> {
        let f = |name: &str| format!("{path}.{name}");
        match self {
            VehicleModelSpec::MovingForce {
                axle_loads_n,
                axle_spacing_m,
            } => {
                if axle_loads_n.is_empty() {
                    return Err(Error::invalid(
                        f("axle_loads_n"),
                        "[]",
                        "needs at least one load",
                    ));
                }
                if axle_spacing_m.len() + 1 != axle_loads_n.len() {
                    return Err(Error::invalid(
                        f("axle_spacing_m"),
                        format!("{axle_spacing_m:?}"),
                        format!(
                            "must have {} entries (one fewer than axle_loads_n)",
                            axle_loads_n.len() - 1
                        ),
                    ));
                }
                for (i, &p) in axle_loads_n.iter().enumerate() {
                    require_non_negative(&format!("{}.{i}", f("axle_loads_n")), p)?;
                }
                let mut offsets = vec![0.0];
                for (i, &s) in axle_spacing_m.iter().enumerate() {
                    require_positive(&format!("{}.{i}", f("axle_spacing_m")), s)?;
                    offsets.push(offsets[i] + s);
                }
                Ok(VehicleDynamics::moving_forces(axle_loads_n, &offsets))
            }
            VehicleModelSpec::SprungMass {
                mass_kg,
                stiffness_n_m,
                damping_n_s_m,
            } => {
                require_positive(&f("mass_kg"), *mass_kg)?;
                require_positive(&f("stiffness_n_m"), *stiffness_n_m)?;
                require_non_negative(&f("damping_n_s_m"), *damping_n_s_m)?;
                Ok(sprung_mass(*mass_kg, *stiffness_n_m, *damping_n_s_m))
            }
            VehicleModelSpec::QuarterCar {
                body_mass_kg,
                axle_mass_kg,
                suspension_stiffness_n_m,
                suspension_damping_n_s_m,
                tyre_stiffness_n_m,
                tyre_damping_n_s_m,
            } => {
                require_positive(&f("body_mass_kg"), *body_mass_kg)?;
                let axle = AxleParams {
                    mass_kg: require_positive(&f("axle_mass_kg"), *axle_mass_kg)?,
                    suspension_stiffness_n_m: require_positive(
                        &f("suspension_stiffness_n_m"),
                        *suspension_stiffness_n_m,
                    )?,
                    suspension_damping_n_s_m: require_non_negative(
                        &f("suspension_damping_n_s_m"),
                        *suspension_damping_n_s_m,
                    )?,
                    tyre_stiffness_n_m: require_positive(
                        &f("tyre_stiffness_n_m"),
                        *tyre_stiffness_n_m,
                    )?,
                    tyre_damping_n_s_m: require_non_negative(
                        &f("tyre_damping_n_s_m"),
                        *tyre_damping_n_s_m,
                    )?,
                };
                Ok(quarter_car(*body_mass_kg, axle))
            }
            VehicleModelSpec::HalfCar(spec) => build_half_car(spec, path),
            VehicleModelSpec::RigidTruck(spec) => spec.params(path)?.build(&spec.model_name()),
            VehicleModelSpec::Articulated(spec) => spec.params(path)?.build(&spec.model_name()),
            VehicleModelSpec::Train(spec) => spec.build(path),
        }
    }
}

fn build_half_car(spec: &HalfCarSpec, path: &str) -> Result<VehicleDynamics> {
    let f = |name: &str| format!("{path}.{name}");
    let s = spec.resolved(path)?;
    let body = positive(s.body_mass_kg, &f("body_mass_kg"))?;
    let inertia = positive(s.pitch_inertia_kg_m2, &f("pitch_inertia_kg_m2"))?;
    let spacing = positive(s.axle_spacing_m, &f("axle_spacing_m"))?;
    let cg = s.cg_behind_front_m.unwrap_or(spacing / 2.0);
    require_within(&f("cg_behind_front_m"), cg, 0.0, spacing, "the axles")?;
    let axles = validated_axles(path, 2, s.axle_arrays())?;
    rigid_body_on_axles(
        &named("half_car", &s.preset),
        body,
        inertia,
        cg,
        &[0.0, spacing],
        &axles,
    )
}
