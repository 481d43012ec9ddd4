//! The bridge's stiffness condition at one instant, and when it is worth rebuilding the
//! model for it.

use super::support_condition::SupportState;
use crate::physics::bridge::{BeamProperties, StiffnessRegion};

/// Stiffness condition at one time: what temperature and damage do to EI, and the
/// supports' condition.
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
    /// The supports' springs and settlements (`[[support_condition]]`).
    pub supports: SupportState,
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
        self.supports.apply(&mut beam.girder);
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
    /// True when a value of `now` differs from `before` by more than `threshold_rel` of
    /// the larger of the two (settlements: they need no rebuild, but their record does).
    pub fn moved(&self, before: &[f64], now: &[f64]) -> bool {
        before.len() != now.len()
            || before
                .iter()
                .zip(now)
                .any(|(a, b)| (a - b).abs() > self.threshold_rel * a.abs().max(b.abs()))
    }

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
        let (before, after) = (
            &last_built.supports.stiffness_factor,
            &now.supports.stiffness_factor,
        );
        if before.len() != after.len()
            || before
                .iter()
                .zip(after)
                .any(|(a, b)| changed(a.0, b.0) || changed(a.1, b.1))
        {
            return true;
        }
        last_built.regions.iter().zip(&now.regions).any(|(a, b)| {
            a.start_m != b.start_m || a.end_m != b.end_m || changed(a.ei_factor, b.ei_factor)
        })
    }
}
