//! The response quantities at a point of the bridge, and what a sensor measures of them.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// Response quantities at a point, output sign convention: displacement, velocity and
/// acceleration downward positive, strain tension positive, moment sagging positive.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Quantities {
    pub displacement_m: f64,
    pub velocity_m_s: f64,
    pub acceleration_m_s2: f64,
    pub strain_microstrain: f64,
    pub moment_n_m: f64,
}

impl Quantities {
    /// Number of quantities (columns of a truth block).
    pub const COUNT: usize = 5;

    /// The quantities in column order: displacement, velocity, acceleration, strain,
    /// moment (the order of `SensorTruthBlock`'s columns).
    pub fn to_columns(&self) -> [f64; Self::COUNT] {
        [
            self.displacement_m,
            self.velocity_m_s,
            self.acceleration_m_s2,
            self.strain_microstrain,
            self.moment_n_m,
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
        }
    }

    /// The quantity a sensor of `kind` measures.
    pub fn measured_by(&self, kind: SensorKind) -> f64 {
        match kind {
            SensorKind::Accelerometer => self.acceleration_m_s2,
            SensorKind::Strain => self.strain_microstrain,
            SensorKind::Displacement => self.displacement_m,
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
}

impl SensorKind {
    /// Unit of the recorded value.
    pub fn unit(self) -> &'static str {
        match self {
            SensorKind::Accelerometer => "m/s^2",
            SensorKind::Strain => "microstrain",
            SensorKind::Displacement => "m",
        }
    }

    /// The measured quantity's name ("acceleration", "strain", "displacement").
    pub const fn quantity(self) -> &'static str {
        match self {
            SensorKind::Accelerometer => "acceleration",
            SensorKind::Strain => "strain",
            SensorKind::Displacement => "displacement",
        }
    }

    /// The kind whose [`Self::quantity`] is `quantity`.
    pub fn from_quantity(quantity: &str) -> Option<SensorKind> {
        [
            SensorKind::Accelerometer,
            SensorKind::Strain,
            SensorKind::Displacement,
        ]
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
        }
    }
}
