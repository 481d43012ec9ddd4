//! The response quantities at a point of the bridge, and what a sensor measures of them.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// Response quantities at a point, output sign convention: displacement, velocity and
/// acceleration downward positive, strain tension positive, moment sagging positive,
/// rotation the slope of the displacement (positive where the deflection grows towards
/// +x), reaction upward on the girder (compression of the bearing).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Quantities {
    pub displacement_m: f64,
    pub velocity_m_s: f64,
    pub acceleration_m_s2: f64,
    pub strain_microstrain: f64,
    pub moment_n_m: f64,
    /// d(displacement_m)/dx at the point (rad, small angles).
    pub rotation_rad: f64,
    /// The live-load reaction of the support the sensor sits on (N); 0 for a sensor that
    /// does not measure a support (every kind but the load cell).
    pub reaction_n: f64,
    /// The deck (structure) temperature (degC), for a thermometer; 0 for the other kinds.
    pub temperature_c: f64,
}

impl Quantities {
    /// Number of quantities (columns of a truth block).
    pub const COUNT: usize = 8;

    /// The quantities in column order: displacement, velocity, acceleration, strain,
    /// moment, rotation, reaction, temperature (the order of `SensorTruthBlock`'s columns).
    pub fn to_columns(&self) -> [f64; Self::COUNT] {
        [
            self.displacement_m,
            self.velocity_m_s,
            self.acceleration_m_s2,
            self.strain_microstrain,
            self.moment_n_m,
            self.rotation_rad,
            self.reaction_n,
            self.temperature_c,
        ]
    }

    /// The inverse of [`Quantities::to_columns`].
    pub fn from_columns(c: [f64; Self::COUNT]) -> Self {
        Quantities {
            displacement_m: c[0],
            velocity_m_s: c[1],
            acceleration_m_s2: c[2],
            strain_microstrain: c[3],
            moment_n_m: c[4],
            rotation_rad: c[5],
            reaction_n: c[6],
            temperature_c: c[7],
        }
    }

    /// The quantity a sensor of `kind` measures.
    pub fn measured_by(&self, kind: SensorKind) -> f64 {
        match kind {
            SensorKind::Accelerometer => self.acceleration_m_s2,
            SensorKind::Strain => self.strain_microstrain,
            SensorKind::Displacement => self.displacement_m,
            SensorKind::Inclinometer => self.rotation_rad,
            SensorKind::LoadCell => self.reaction_n,
            SensorKind::Thermometer => self.temperature_c,
        }
    }
}

/// What a sensor measures.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum SensorKind {
    Accelerometer,
    Strain,
    Displacement,
    /// Rotation (tilt) of the girder's axis, e.g. at a bearing.
    Inclinometer,
    /// A load cell under a bearing: the support's reaction. Must sit on a support.
    LoadCell,
    /// A thermometer on the deck: the structure temperature (the air lagged), which the
    /// frequency-tracking pipelines regress on.
    Thermometer,
}

impl SensorKind {
    /// Every kind, in declaration order.
    pub const ALL: [SensorKind; 6] = [
        SensorKind::Accelerometer,
        SensorKind::Strain,
        SensorKind::Displacement,
        SensorKind::Inclinometer,
        SensorKind::LoadCell,
        SensorKind::Thermometer,
    ];

    /// The kind as a scenario writes it (`kind = "load_cell"`).
    pub const fn name(self) -> &'static str {
        match self {
            SensorKind::Accelerometer => "accelerometer",
            SensorKind::Strain => "strain",
            SensorKind::Displacement => "displacement",
            SensorKind::Inclinometer => "inclinometer",
            SensorKind::LoadCell => "load_cell",
            SensorKind::Thermometer => "thermometer",
        }
    }

    /// Unit of the recorded value.
    pub fn unit(self) -> &'static str {
        match self {
            SensorKind::Accelerometer => "m/s^2",
            SensorKind::Strain => "microstrain",
            SensorKind::Displacement => "m",
            SensorKind::Inclinometer => "rad",
            SensorKind::LoadCell => "N",
            SensorKind::Thermometer => "degC",
        }
    }

    /// The sign convention of the kind's values, for channel metadata.
    pub const fn sign(self) -> &'static str {
        match self {
            SensorKind::Accelerometer | SensorKind::Displacement => "downward positive",
            SensorKind::Strain => "tension positive",
            SensorKind::Inclinometer => {
                "slope of the downward deflection, positive where it grows towards +x"
            }
            SensorKind::LoadCell => "compression of the bearing positive (upward on the girder)",
            SensorKind::Thermometer => "degrees Celsius",
        }
    }

    /// The measured quantity's name ("acceleration", "strain", "displacement").
    pub const fn quantity(self) -> &'static str {
        match self {
            SensorKind::Accelerometer => "acceleration",
            SensorKind::Strain => "strain",
            SensorKind::Displacement => "displacement",
            SensorKind::Inclinometer => "rotation",
            SensorKind::LoadCell => "reaction",
            SensorKind::Thermometer => "temperature",
        }
    }

    /// The kind whose [`Self::quantity`] is `quantity`.
    pub fn from_quantity(quantity: &str) -> Option<SensorKind> {
        SensorKind::ALL
            .into_iter()
            .find(|k| k.quantity() == quantity)
    }

    /// The value field of the kind's per-sample message, with its unit
    /// ("acceleration_m_s2"): the column name readers give a sensor's values in both
    /// layouts.
    pub const fn value_field(self) -> &'static str {
        match self {
            SensorKind::Accelerometer => "acceleration_m_s2",
            SensorKind::Strain => "strain_microstrain",
            SensorKind::Displacement => "displacement_m",
            SensorKind::Inclinometer => "rotation_rad",
            SensorKind::LoadCell => "reaction_n",
            SensorKind::Thermometer => "temperature_c",
        }
    }
}
