//! What a weigh-in-motion station reports for one vehicle (the station models that
//! produce it are in `measurement::wim`).

use std::ops::Range;

/// Consecutive axles close enough to form a group (tandem, tridem), with their summed load.
#[derive(Debug, Clone, PartialEq)]
pub struct AxleGroup {
    /// Index of the group's front axle (0 = the vehicle's front axle).
    pub first_axle: usize,
    /// Number of axles in the group (>= 1).
    pub axle_count: usize,
    /// Sum of the group's axle loads, N.
    pub load_n: f64,
}

impl AxleGroup {
    /// Indices of the group's axles.
    pub fn axles(&self) -> Range<usize> {
        self.first_axle..self.first_axle + self.axle_count
    }
}

/// The load a model's errors are relative to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LoadReference {
    /// The static axle loads (`cost323`: the classes are defined against static weights).
    Static,
    /// The dynamic tyre force at the strip (`physics`, `ideal`).
    Dynamic,
}

/// The errors a station applied to one vehicle: truth for scoring, unknown to a real WIM.
#[derive(Debug, Clone, PartialEq)]
pub struct AppliedErrors {
    /// What the load errors are relative to.
    pub reference: LoadReference,
    /// Relative speed error (spacings carry the same).
    pub speed_rel: f64,
    /// Relative error of the gross weight against the reference gross weight.
    pub gross_rel: f64,
    /// Relative error of each axle load against its reference, front to rear.
    pub axle_rel: Vec<f64>,
}

/// One vehicle as a WIM station reports it.
#[derive(Debug, Clone, PartialEq)]
pub struct WimMeasurement {
    pub vehicle_id: u32,
    pub lane: u32,
    /// Time the first axle crossed the strip, ns since the run start.
    pub t_ns: u64,
    /// Measured speed, m/s.
    pub speed_m_s: f64,
    /// Measured spacings (true spacing scaled by the speed error), front to rear, m.
    pub axle_spacing_m: Vec<f64>,
    /// Measured axle loads, front to rear, N.
    pub axle_load_n: Vec<f64>,
    /// Sum of the measured axle loads, N.
    pub gross_weight_n: f64,
    /// Axle groups from the measured spacings, with measured loads.
    pub groups: Vec<AxleGroup>,
    /// Group sizes, e.g. "1-1-3".
    pub axle_pattern: String,
    /// FHWA 13-class class from the measured values, `None` if undecided.
    pub fhwa_class: Option<u8>,
    /// Quality flags, sorted: `low_speed`, `multiple_presence`, `off_scale`
    /// (the station model's flag names).
    pub flags: Vec<&'static str>,
    /// The errors applied (truth).
    pub truth: AppliedErrors,
}
