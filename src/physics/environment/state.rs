//! The bridge's stiffness condition at one instant, and when it is worth rebuilding the
//! model for it.

use crate::physics::bridge::{BeamProperties, StiffnessRegion};

/// Stiffness condition at one time: what temperature and damage do to EI.
#[derive(Debug, Clone, PartialEq)]
pub struct StiffnessState {
    /// E(T)/E_ref of the whole beam from the structure temperature.
    pub global_factor: f64,
    /// One region per `[[damage]]` entry, in scenario order, with EI factor
    /// `1 - damage_fraction` (1 before the onset).
    pub regions: Vec<StiffnessRegion>,
    /// Air temperature (degC).
    pub temperature_air_c: f64,
    /// Structure temperature, the lagged air (degC).
    pub temperature_structure_c: f64,
    /// Fraction of EI lost by each `[[damage]]` entry now, in [0, reduction].
    pub damage_fraction: Vec<f64>,
}

impl StiffnessState {
    /// The beam in this condition: EI times `global_factor`, and each damaged region
    /// appended to `base`'s own regions. Regions multiply where they overlap
    /// ([`BeamProperties::ei_at_n_m2`]), so two damages on one spot compound. Regions at
    /// factor 1 are left out, so an undamaged beam stays uniform and keeps the
    /// closed-form flexibility route.
    pub fn beam_at(&self, base: &BeamProperties) -> BeamProperties {
        let mut beam = base.clone();
        beam.flexural_rigidity_n_m2 *= self.global_factor;
        beam.stiffness_regions
            .extend(self.regions.iter().filter(|r| r.ei_factor != 1.0).cloned());
        beam
    }
}

/// When to rebuild the bridge model: a factorization per time step would be wasteful,
/// while a stale model misplaces the frequencies the monitoring is meant to track.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RebuildPolicy {
    /// Rebuild when any factor (global or a region's) has changed by more than this
    /// fraction since the last build (default 0.002: 0.1 % on frequencies, an estimate
    /// of the scatter of frequencies identified from ambient records).
    pub threshold_rel: f64,
}

impl Default for RebuildPolicy {
    fn default() -> Self {
        Self {
            threshold_rel: 0.002,
        }
    }
}

impl RebuildPolicy {
    /// True when `now` differs from `last_built` by more than `threshold_rel` in any
    /// factor, or has a different list of regions.
    pub fn needs_rebuild(&self, last_built: &StiffnessState, now: &StiffnessState) -> bool {
        let changed = |before: f64, after: f64| (after / before - 1.0).abs() > self.threshold_rel;
        if changed(last_built.global_factor, now.global_factor) {
            return true;
        }
        if last_built.regions.len() != now.regions.len() {
            return true;
        }
        last_built.regions.iter().zip(&now.regions).any(|(a, b)| {
            a.start_m != b.start_m || a.end_m != b.end_m || changed(a.ei_factor, b.ei_factor)
        })
    }
}
