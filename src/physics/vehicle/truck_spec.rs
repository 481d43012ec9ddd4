//! Scenario syntax of the multi-axle vehicles (`kind = "rigid_truck"` and
//! `kind = "articulated"`), their presets, and validation with scenario field paths.
//!
//! Like the half car, a `preset` gives every field and any field written next to it
//! overrides the preset's value. Per-axle arrays are front first; `axle_spacing_m` decides
//! the number of axles, and every per-axle array must then have one entry per axle.
//! The parameter table with sources and natural frequencies is in `classes.rs`.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::articulated::ArticulatedParams;
use super::models::{BodyParams, RigidTruckParams};
use super::pitch_plane_spec::{
    named, pitch_plane_spec, positive, preset_or_default, require_within, required, validated_axles,
};
use crate::base::schema as bounds;
use crate::error::{require_positive, Error, Result};

pitch_plane_spec! {
    /// Rigid truck (or car) parameters: one body (bounce, pitch) on 2-4 axles.
    pub struct RigidTruckSpec, axle arrays of Vec<f64> {
        /// `car`, `truck_2axle`, `truck_3axle` or `truck_4axle` (parameters and sources
        /// in docs/physics.md section 6).
        #[schemars(transform = bounds::named_choices(&RIGID_TRUCK_PRESETS, |name| {
            RigidTruckSpec::preset(name).map(|p| RigidTruckSpec { preset: None, ..p })
        }))]
        pub preset: Option<String>,
        /// Sprung mass (kg), axles excluded.
        #[schemars(transform = bounds::positive)]
        pub body_mass_kg: Option<f64>,
        /// Pitch moment of inertia of the body about its centre of gravity (kg m^2).
        #[schemars(transform = bounds::positive)]
        pub pitch_inertia_kg_m2: Option<f64>,
        /// Centre of gravity behind the front axle (m), within the wheelbase; default
        /// mid-wheelbase.
        #[schemars(range(min = 0))]
        pub cg_behind_front_m: Option<f64>,
        /// Distances between consecutive axles (m), each > 0: 1-3 entries for 2-4 axles.
        #[schemars(length(min = 1, max = 3), transform = bounds::positive_items)]
        pub axle_spacing_m: Option<Vec<f64>>,
    }
}

pitch_plane_spec! {
    /// Tractor + semi-trailer parameters: two bodies hinged at the fifth wheel.
    pub struct ArticulatedSpec, axle arrays of Vec<f64> {
        /// `artic_5axle` (parameters and sources in docs/physics.md section 6).
        #[schemars(transform = bounds::named_choices(&ARTICULATED_PRESETS, |name| {
            ArticulatedSpec::preset(name).map(|p| ArticulatedSpec { preset: None, ..p })
        }))]
        pub preset: Option<String>,
        /// Tractor sprung mass (kg), axles excluded.
        #[schemars(transform = bounds::positive)]
        pub tractor_body_mass_kg: Option<f64>,
        /// Tractor pitch moment of inertia about its centre of gravity (kg m^2).
        #[schemars(transform = bounds::positive)]
        pub tractor_pitch_inertia_kg_m2: Option<f64>,
        /// Tractor centre of gravity behind the front axle (m).
        #[schemars(range(min = 0))]
        pub tractor_cg_behind_front_m: Option<f64>,
        /// Trailer sprung mass including payload (kg), axles excluded.
        #[schemars(transform = bounds::positive)]
        pub trailer_body_mass_kg: Option<f64>,
        /// Trailer pitch moment of inertia about its centre of gravity (kg m^2).
        #[schemars(transform = bounds::positive)]
        pub trailer_pitch_inertia_kg_m2: Option<f64>,
        /// Trailer centre of gravity behind the front axle (m), behind the fifth wheel.
        #[schemars(range(min = 0))]
        pub trailer_cg_behind_front_m: Option<f64>,
        /// Fifth wheel (kingpin) behind the front axle (m).
        #[schemars(range(min = 0))]
        pub fifth_wheel_behind_front_m: Option<f64>,
        /// Axles of the tractor (>= 2); the rest (>= 1) are the trailer's. Default 2.
        #[schemars(range(min = 2))]
        pub tractor_axle_count: Option<usize>,
        /// Distances between consecutive axles (m), each > 0, front first.
        #[schemars(length(min = 2), transform = bounds::positive_items)]
        pub axle_spacing_m: Option<Vec<f64>>,
    }
}

/// The names `preset` accepts for `kind = "rigid_truck"`.
pub const RIGID_TRUCK_PRESETS: [&str; 4] = ["car", "truck_2axle", "truck_3axle", "truck_4axle"];

/// The names `preset` accepts for `kind = "articulated"`.
pub const ARTICULATED_PRESETS: [&str; 1] = ["artic_5axle"];

/// Axle counts `kind = "rigid_truck"` accepts: the rigid classes of the traffic mix
/// (more axles are articulated vehicles in docs/sensors.md section 4).
const RIGID_AXLES: std::ops::RangeInclusive<usize> = 2..=4;

/// Suspension damping of the truck presets as a multiple of their suspension stiffness (s):
/// the ratio of the `two_axle_truck` preset (3.0e4 / 2.47e6, 4.0e4 / 4.23e6; docs/physics.md
/// section 6). VBI-2D's `Vehicle_2A3` uses 1 kN s/m, which leaves the body modes ~1 %
/// damped, too little for dynamic load statistics (docs/physics.md section 6, E01 note).
const SUSPENSION_DAMPING_S: f64 = 0.01;

/// Tyre damping of the truck presets (N s/m per axle): VBI-2D `Vehicle_2A3`.
const TRUCK_TYRE_DAMPING_N_S_M: f64 = 1.0e4;

/// Per-axle arrays `[mass, suspension stiffness, suspension damping, tyre stiffness,
/// tyre damping]` of a preset.
fn arrays(m: &[f64], ks: &[f64], cs: &[f64], kt: &[f64], ct: &[f64]) -> [Vec<f64>; 5] {
    [m, ks, cs, kt, ct].map(<[f64]>::to_vec)
}

/// Truck axles with the preset damping rules.
fn truck_arrays(m: &[f64], ks: &[f64], kt: &[f64]) -> [Vec<f64>; 5] {
    let cs: Vec<f64> = ks.iter().map(|k| k * SUSPENSION_DAMPING_S).collect();
    let ct = vec![TRUCK_TYRE_DAMPING_N_S_M; m.len()];
    arrays(m, ks, &cs, kt, &ct)
}

impl RigidTruckSpec {
    /// The preset's full parameter set (table and sources in `classes.rs`).
    pub fn preset(name: &str) -> Option<RigidTruckSpec> {
        let (body, inertia, cg, spacing, axles) = match name {
            // Estimate: a 1 400 kg family car, 57 % on the front axle.
            "car" => (
                1_230.0,
                1_900.0,
                1.1,
                vec![2.6],
                arrays(
                    &[90.0, 80.0],
                    &[50.0e3, 45.0e3],
                    &[3.0e3, 2.4e3],
                    &[400.0e3, 400.0e3],
                    &[200.0, 200.0],
                ),
            ),
            // docs/physics.md section 6 `two_axle_truck` (commonly attributed to Law & Zhu 2004).
            "truck_2axle" => (
                17_735.0,
                1.47e5,
                4.27 / 2.0,
                vec![4.27],
                arrays(
                    &[1_500.0, 1_000.0],
                    &[2.47e6, 4.23e6],
                    &[3.0e4, 4.0e4],
                    &[3.74e6, 4.60e6],
                    &[3.9e3, 4.3e3],
                ),
            ),
            // Estimate: 26 t steer + tandem rigid (table in `classes.rs`).
            "truck_3axle" => (
                23_400.0,
                1.9e5,
                3.75,
                vec![4.5, 1.35],
                truck_arrays(
                    &[600.0, 1_000.0, 1_000.0],
                    &[800.0e3, 1_500.0e3, 1_500.0e3],
                    &[2_000.0e3, 3_500.0e3, 3_500.0e3],
                ),
            ),
            // Estimate: 32 t twin-steer + tandem (8x4) rigid (table in `classes.rs`).
            "truck_4axle" => (
                28_600.0,
                2.4e5,
                3.5,
                vec![1.9, 3.3, 1.35],
                truck_arrays(
                    &[600.0, 600.0, 1_100.0, 1_100.0],
                    &[800.0e3, 800.0e3, 1_500.0e3, 1_500.0e3],
                    &[2_000.0e3, 2_000.0e3, 3_500.0e3, 3_500.0e3],
                ),
            ),
            _ => return None,
        };
        let spec = RigidTruckSpec {
            preset: Some(name.into()),
            body_mass_kg: Some(body),
            pitch_inertia_kg_m2: Some(inertia),
            cg_behind_front_m: Some(cg),
            axle_spacing_m: Some(spacing),
            ..RigidTruckSpec::default()
        };
        Some(spec.with_axle_arrays(axles))
    }

    /// Fields given here override the preset's.
    fn resolved(&self, path: &str) -> Result<RigidTruckSpec> {
        let base = preset_or_default(
            path,
            &self.preset,
            &RIGID_TRUCK_PRESETS,
            RigidTruckSpec::preset,
        )?;
        Ok(self.overriding(base))
    }

    /// Validated model parameters; `path` is the scenario path ("vehicles.0.model").
    pub fn params(&self, path: &str) -> Result<RigidTruckParams> {
        let f = |name: &str| format!("{path}.{name}");
        let s = self.resolved(path)?;
        let offsets = axle_offsets(s.axle_spacing_m.clone(), &f("axle_spacing_m"), RIGID_AXLES)?;
        let wheelbase_m = offsets[offsets.len() - 1];
        let cg = s.cg_behind_front_m.unwrap_or(wheelbase_m / 2.0);
        require_within(&f("cg_behind_front_m"), cg, 0.0, wheelbase_m, "the axles")?;
        Ok(RigidTruckParams {
            body: BodyParams {
                mass_kg: positive(s.body_mass_kg, &f("body_mass_kg"))?,
                pitch_inertia_kg_m2: positive(s.pitch_inertia_kg_m2, &f("pitch_inertia_kg_m2"))?,
                cg_behind_front_m: cg,
            },
            axles: validated_axles(path, offsets.len(), s.axle_arrays())?,
            axle_offsets_m: offsets,
        })
    }

    /// Model name for the truth records: `rigid_truck/<preset>`.
    pub fn model_name(&self) -> String {
        named("rigid_truck", &self.preset)
    }
}

impl ArticulatedSpec {
    /// The preset's full parameter set (table and sources in `classes.rs`).
    pub fn preset(name: &str) -> Option<ArticulatedSpec> {
        match name {
            // VBI-2D `Vehicle_2A3` (docs/sensors.md section 4) on the Auxerre 5-axle spacings.
            // CGs and fifth wheel are estimates: VBI-2D's geometry (tractor CG 0.5 m behind
            // the steer axle of a 3.0 m wheelbase, fifth wheel 0.35 m ahead of the drive
            // axle, trailer CG at 0.68 of the kingpin-to-tridem-centre distance) moved
            // onto these spacings.
            "artic_5axle" => Some(
                ArticulatedSpec {
                    preset: Some(name.into()),
                    tractor_body_mass_kg: Some(4_500.0),
                    tractor_pitch_inertia_kg_m2: Some(4_604.0),
                    tractor_cg_behind_front_m: Some(0.54),
                    trailer_body_mass_kg: Some(31_450.0),
                    trailer_pitch_inertia_kg_m2: Some(16_302.0),
                    trailer_cg_behind_front_m: Some(7.64),
                    fifth_wheel_behind_front_m: Some(2.89),
                    tractor_axle_count: Some(2),
                    axle_spacing_m: Some(vec![3.24, 5.43, 1.20, 1.21]),
                    ..ArticulatedSpec::default()
                }
                .with_axle_arrays(truck_arrays(
                    &[700.0, 1_100.0, 750.0, 750.0, 750.0],
                    &[400.0e3, 1_000.0e3, 750.0e3, 750.0e3, 750.0e3],
                    &[1_750.0e3, 3_500.0e3, 3_500.0e3, 3_500.0e3, 3_500.0e3],
                )),
            ),
            _ => None,
        }
    }

    /// Fields given here override the preset's.
    fn resolved(&self, path: &str) -> Result<ArticulatedSpec> {
        let base = preset_or_default(
            path,
            &self.preset,
            &ARTICULATED_PRESETS,
            ArticulatedSpec::preset,
        )?;
        Ok(self.overriding(base))
    }

    /// Validated model parameters; `path` is the scenario path ("vehicles.0.model").
    pub fn params(&self, path: &str) -> Result<ArticulatedParams> {
        let f = |name: &str| format!("{path}.{name}");
        let s = self.resolved(path)?;
        let offsets = axle_offsets(
            s.axle_spacing_m.clone(),
            &f("axle_spacing_m"),
            3..=usize::MAX,
        )?;
        let n = offsets.len();
        let tractor_axles = s.tractor_axle_count.unwrap_or(2);
        if tractor_axles < 2 || tractor_axles >= n {
            return Err(Error::invalid(
                f("tractor_axle_count"),
                tractor_axles,
                format!("must leave the tractor >= 2 and the trailer >= 1 of the {n} axles"),
            ));
        }
        let last_tractor_m = offsets[tractor_axles - 1];
        let first_trailer_m = offsets[tractor_axles];
        let fifth_wheel = required(
            s.fifth_wheel_behind_front_m,
            &f("fifth_wheel_behind_front_m"),
        )?;
        require_within(
            &f("fifth_wheel_behind_front_m"),
            fifth_wheel,
            0.0,
            first_trailer_m,
            "the front axle and the first trailer axle",
        )?;
        let tractor_cg = required(s.tractor_cg_behind_front_m, &f("tractor_cg_behind_front_m"))?;
        require_within(
            &f("tractor_cg_behind_front_m"),
            tractor_cg,
            0.0,
            last_tractor_m.max(fifth_wheel),
            "the tractor's front axle and its last axle or fifth wheel",
        )?;
        let trailer_cg = required(s.trailer_cg_behind_front_m, &f("trailer_cg_behind_front_m"))?;
        require_within(
            &f("trailer_cg_behind_front_m"),
            trailer_cg,
            fifth_wheel,
            offsets[n - 1],
            "the fifth wheel and the last axle",
        )?;
        Ok(ArticulatedParams {
            tractor: BodyParams {
                mass_kg: positive(s.tractor_body_mass_kg, &f("tractor_body_mass_kg"))?,
                pitch_inertia_kg_m2: positive(
                    s.tractor_pitch_inertia_kg_m2,
                    &f("tractor_pitch_inertia_kg_m2"),
                )?,
                cg_behind_front_m: tractor_cg,
            },
            trailer: BodyParams {
                mass_kg: positive(s.trailer_body_mass_kg, &f("trailer_body_mass_kg"))?,
                pitch_inertia_kg_m2: positive(
                    s.trailer_pitch_inertia_kg_m2,
                    &f("trailer_pitch_inertia_kg_m2"),
                )?,
                cg_behind_front_m: trailer_cg,
            },
            fifth_wheel_behind_front_m: fifth_wheel,
            tractor_axle_count: tractor_axles,
            axles: validated_axles(path, n, s.axle_arrays())?,
            axle_offsets_m: offsets,
        })
    }

    /// Model name for the truth records: `articulated/<preset>`.
    pub fn model_name(&self) -> String {
        named("articulated", &self.preset)
    }
}

/// Axle offsets behind the front axle from the spacings; the axle count must be in `axles`.
pub(crate) fn axle_offsets(
    spacing_m: Option<Vec<f64>>,
    field: &str,
    axles: std::ops::RangeInclusive<usize>,
) -> Result<Vec<f64>> {
    let spacing_m = required(spacing_m, field)?;
    if !axles.contains(&(spacing_m.len() + 1)) {
        let most = if *axles.end() == usize::MAX {
            "or more".to_string()
        } else {
            format!("to {}", axles.end() - 1)
        };
        return Err(Error::invalid(
            field,
            format!("{spacing_m:?}"),
            format!(
                "must have {} {most} entries (one fewer than axles)",
                axles.start() - 1
            ),
        ));
    }
    let mut offsets = vec![0.0];
    for (i, &s) in spacing_m.iter().enumerate() {
        offsets.push(offsets[i] + require_positive(&format!("{field}.{i}"), s)?);
    }
    Ok(offsets)
}
