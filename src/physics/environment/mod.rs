//! Environment and condition: temperature and damage driving the bridge stiffness.
//!
//! Air temperature (constant, daily cycle with red noise, or a measured record) lags into
//! the structure temperature, which scales E through a bilinear law with a knee at 0 degC
//! (the Z24 shape, docs/sensors.md section 5). Damage removes a growing fraction of EI over
//! parts of the span. [`EnvironmentModel::state_at`] combines both into a
//! [`StiffnessState`]; [`RebuildPolicy`] says when the bridge model is worth rebuilding
//! and [`StiffnessState::beam_at`] gives the beam to rebuild it from.

mod csv_series;
mod damage;
mod lag;
mod state;
mod stiffness_law;
mod support_condition;
mod temperature;

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

pub use csv_series::{TemperatureTable, CSV_HEADER};
pub use damage::{damage_events, validate_damage, ConditionEvent, DamageSpec, Growth};
pub use lag::ThermalLag;
pub use state::{RebuildPolicy, StiffnessState};
pub use stiffness_law::{TemperatureStiffnessLaw, LAW_RANGE_C};
pub use support_condition::{
    support_at, validate_support_conditions, SupportChange, SupportConditionSpec,
    SupportConditions, SupportState,
};
pub use temperature::{
    AirTemperature, DailySpec, OrnsteinUhlenbeck, TemperatureSpec, DAY_S, DEFAULT_AIR_C,
};

use crate::error::{require_positive, Result};
use crate::physics::bridge::{Girder, StiffnessRegion};

/// The scenario's `[environment]` section.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct EnvironmentSpec {
    /// Air temperature (default: constant 20 degC, where E = E_ref by default).
    #[serde(default)]
    pub temperature: TemperatureSpec,
    /// Time constant of the structure temperature behind the air (s) (default 10 800,
    /// 3 h: an estimate for a concrete deck some 0.3-0.5 m thick), > 0.
    #[serde(default = "default_lag_s")]
    #[schemars(transform = crate::base::schema::positive)]
    pub lag_s: f64,
    /// E(T)/E_ref as a function of the structure temperature (defaults on the type).
    #[serde(default)]
    pub stiffness: TemperatureStiffnessLaw,
    /// Relative change of any stiffness factor that triggers a model rebuild, > 0
    /// (default 0.002: frequencies then drift by at most 0.1 % between rebuilds).
    #[serde(default = "default_rebuild_threshold_rel")]
    #[schemars(transform = crate::base::schema::positive)]
    pub rebuild_threshold_rel: f64,
}

fn default_lag_s() -> f64 {
    10_800.0
}
fn default_rebuild_threshold_rel() -> f64 {
    RebuildPolicy::default().threshold_rel
}

impl Default for EnvironmentSpec {
    fn default() -> Self {
        Self {
            temperature: TemperatureSpec::default(),
            lag_s: default_lag_s(),
            stiffness: TemperatureStiffnessLaw::default(),
            rebuild_threshold_rel: default_rebuild_threshold_rel(),
        }
    }
}

impl EnvironmentSpec {
    /// Checks every field; `path` is the section's scenario path (`environment`).
    pub fn validate(&self, path: &str) -> Result<()> {
        self.temperature.validate(&format!("{path}.temperature"))?;
        require_positive(&format!("{path}.lag_s"), self.lag_s)?;
        self.stiffness.validate(&format!("{path}.stiffness"))?;
        require_positive(
            &format!("{path}.rebuild_threshold_rel"),
            self.rebuild_threshold_rel,
        )?;
        Ok(())
    }

    /// The rebuild policy this section asks for.
    pub fn rebuild_policy(&self) -> RebuildPolicy {
        RebuildPolicy {
            threshold_rel: self.rebuild_threshold_rel,
        }
    }
}

/// Streams the stiffness condition over a run: air temperature, its lag into the
/// structure, the temperature law and the damage growth.
#[derive(Debug, Clone)]
pub struct EnvironmentModel {
    air: AirTemperature,
    lag: ThermalLag,
    law: TemperatureStiffnessLaw,
    damage: Vec<DamageSpec>,
    supports: SupportConditions,
}

impl EnvironmentModel {
    /// Validates `spec` (as `environment`), `damage` (as `damage.N`, against the
    /// girder's length) and `supports` (as `support_condition.N`, against its supports)
    /// and starts the structure temperature on its settled value
    /// ([`AirTemperature::settled_structure_c`]), so a run begins without a thermal
    /// transient. Build `air` with [`AirTemperature::new`], its random stream named
    /// `"environment/temperature"`.
    pub fn new(
        spec: &EnvironmentSpec,
        damage: &[DamageSpec],
        supports: &[SupportConditionSpec],
        girder: &Girder,
        mut air: AirTemperature,
    ) -> Result<Self> {
        spec.validate("environment")?;
        validate_damage(damage, girder.length_m())?;
        let supports = SupportConditions::new(supports, girder)?;
        let structure_c = air.settled_structure_c(spec.lag_s);
        Ok(Self {
            air,
            lag: ThermalLag::new(spec.lag_s, structure_c),
            law: spec.stiffness.clone(),
            damage: damage.to_vec(),
            supports,
        })
    }

    /// The condition at `t_s` (non-decreasing across calls; O(1) work plus one entry per
    /// damage).
    pub fn state_at(&mut self, t_s: f64) -> StiffnessState {
        let mut state = StiffnessState {
            global_factor: 1.0,
            regions: Vec::with_capacity(self.damage.len()),
            temperature_air_c: 0.0,
            temperature_structure_c: 0.0,
            damage_fraction: Vec::with_capacity(self.damage.len()),
            supports: SupportState::default(),
        };
        self.update(t_s, &mut state);
        state
    }

    /// [`Self::state_at`] into an existing state, reusing its vectors: no allocation
    /// once they have grown, for calling every time step.
    pub fn update(&mut self, t_s: f64, state: &mut StiffnessState) {
        let air_c = self.air.air_c(t_s);
        let structure_c = self.lag.step(t_s, air_c);
        state.global_factor = self.law.factor(structure_c);
        state.temperature_air_c = air_c;
        state.temperature_structure_c = structure_c;
        state.damage_fraction.clear();
        state.regions.clear();
        for d in &self.damage {
            let loss = d.ei_loss_at(t_s);
            state.damage_fraction.push(loss);
            state.regions.push(StiffnessRegion {
                start_m: d.start_m,
                end_m: d.end_m,
                ei_factor: 1.0 - loss,
            });
        }
        self.supports.update(t_s, &mut state.supports);
    }

    /// Damage and support-condition onsets (and completions of linear growth) for
    /// `/events`, sorted by time (damage first at equal times, each in scenario order).
    pub fn events(&self) -> Vec<ConditionEvent> {
        let mut events = damage_events(&self.damage);
        events.extend(self.supports.events());
        events.sort_by_key(|e| e.t_ns);
        events
    }
}
