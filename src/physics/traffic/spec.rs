//! The scenario's `[traffic]` table and its validation.

use std::collections::BTreeMap;

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::class::{
    require_relative_sd, ClassModel, VehicleClass, MAX_RELATIVE_SD, SHARE_SUM_TOLERANCE,
};
use crate::base::schema as bounds;
use crate::error::{num, require_finite, require_non_negative, require_positive, Error, Result};

/// Hours in the flow profile.
pub const HOURS_PER_DAY: usize = 24;

/// Default hourly flow factors, hour 0 = 00:00-01:00 local time: a weekday two-peak shape
/// (morning peak 08:00, evening peak 16:00-18:00 at 1.65, night minimum 0.17 at
/// 02:00-04:00), the shape of inter-urban counts such as the day/night pattern of
/// docs/sensors.md section 5 (estimated, not a measured site). The factors sum to 24 (mean 1).
pub const DEFAULT_HOURLY_PROFILE: [f64; HOURS_PER_DAY] = [
    0.25, 0.2, 0.17, 0.17, 0.22, 0.45, 1.0, 1.55, 1.65, 1.5, 1.35, 1.35, 1.4, 1.4, 1.45, 1.5, 1.65,
    1.65, 1.4, 1.2, 0.95, 0.65, 0.5, 0.39,
];

/// Default share of cars among all vehicles (docs/sensors.md section 4: ~80 %).
pub const DEFAULT_CAR_SHARE: f64 = 0.8;

/// Default split of the trucks (Auxerre, direction 1; docs/sensors.md section 4): 2-axle 23 %,
/// 3-axle 2.8 %, 4-axle 31.7 %, 5-axle 42.5 %.
pub const DEFAULT_TRUCK_SPLIT: [(VehicleClass, f64); 4] = [
    (VehicleClass::Truck2Axle, 0.23),
    (VehicleClass::Truck3Axle, 0.028),
    (VehicleClass::Truck4Axle, 0.317),
    (VehicleClass::Artic5Axle, 0.425),
];

/// Default mean speed: 89 km/h (Auxerre, docs/sensors.md section 4).
pub const DEFAULT_SPEED_MEAN_M_S: f64 = 89.0 / 3.6;
/// Default speed standard deviation: 3.6 km/h = 1 m/s (Auxerre).
pub const DEFAULT_SPEED_SD_M_S: f64 = 1.0;
/// Default minimum time gap between the rear of a vehicle and the front of the next one
/// on its lane, s: well below the 2 s rule, about the shortest gaps seen in free flow.
pub const DEFAULT_MIN_GAP_S: f64 = 1.0;
/// Default relative sd of a vehicle's suspension parameters around its class model.
pub const DEFAULT_PARAMETER_SD_REL: f64 = 0.1;

/// Random traffic on the bridge (`[traffic]`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TrafficSpec {
    /// The lanes, each with its own flow, direction and speeds; the beam carries them
    /// all. At least one.
    #[schemars(length(min = 1))]
    pub lanes: Vec<LaneSpec>,
    /// 24 relative flow factors, each >= 0, hour 0 = midnight to 01:00 local time. They
    /// are divided by their mean, so each lane's `flow_per_hour` stays its daily mean
    /// flow; default a weekday with peaks at 08:00 and 16:00-18:00.
    #[serde(default = "default_hourly_profile")]
    #[schemars(length(equal = HOURS_PER_DAY), inner(range(min = 0)))]
    pub hourly_profile: Vec<f64>,
    /// Share of each class among all vehicles, >= 0, summing to 1, keyed by class name;
    /// absent classes have share 0. Default 80 % cars and the Auxerre truck split
    /// (docs/sensors.md section 4). A lane's own `classes` overrides it.
    #[serde(default = "default_class_shares")]
    #[schemars(transform = class_shares_schema)]
    pub classes: BTreeMap<String, f64>,
    /// Minimum time gap between the rear of a vehicle and the front of the follower on a
    /// lane, at the follower's speed, s, > 0 (default: about the shortest gaps seen in
    /// free flow).
    #[serde(default = "default_min_gap_s")]
    #[schemars(transform = bounds::positive)]
    pub min_gap_s: f64,
    /// Relative sd, in [0, 0.3], of the factors on each vehicle's springs (suspension
    /// and tyres, one factor) and dampers (another), drawn from its `variation_seed`
    /// (the static axle loads do not change).
    #[serde(default = "default_parameter_sd_rel")]
    #[schemars(range(min = 0, max = MAX_RELATIVE_SD))]
    pub parameter_sd_rel: f64,
    /// Class models replacing the built-in ones (docs/sensors.md section 4), whole, keyed
    /// by class name; default none.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    #[schemars(transform = bounds::keys_among(class_names()))]
    pub models: BTreeMap<String, ClassModel>,
}

/// One lane (`[[traffic.lanes]]`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct LaneSpec {
    /// Direction of travel: 1 = along the beam axis (entering at x = 0), -1 = against it;
    /// default 1.
    #[serde(default = "default_direction")]
    #[schemars(extend("enum" = [1, -1]))]
    pub direction: i8,
    /// Daily mean flow of all classes, vehicles per hour, >= 0 (0: an empty lane).
    #[schemars(range(min = 0))]
    pub flow_per_hour: f64,
    /// Mean speed, m/s, > 0 (default 89 km/h, Auxerre).
    #[serde(default = "default_speed_mean_m_s")]
    #[schemars(transform = bounds::positive)]
    pub speed_mean_m_s: f64,
    /// Speed standard deviation, m/s, >= 0; draws are truncated at 3 sd, so it must be
    /// below a third of the mean (default 3.6 km/h, Auxerre).
    #[serde(default = "default_speed_sd_m_s")]
    #[schemars(range(min = 0))]
    pub speed_sd_m_s: f64,
    /// Class shares of this lane (as `traffic.classes`); default the global ones.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(transform = class_shares_schema)]
    pub classes: Option<BTreeMap<String, f64>>,
}

fn class_names() -> Vec<&'static str> {
    VehicleClass::ALL.map(VehicleClass::name).to_vec()
}

/// The schema of a class-share table (`classes = { car = 0.8, ... }`): keys are class
/// names, shares >= 0 (their sum is checked by `parse_shares`).
fn class_shares_schema(schema: &mut schemars::Schema) {
    bounds::keys_among(class_names())(schema);
    if let Some(share) = schema
        .get_mut("additionalProperties")
        .and_then(serde_json::Value::as_object_mut)
    {
        share.insert("minimum".into(), 0.into());
    }
}

fn default_hourly_profile() -> Vec<f64> {
    DEFAULT_HOURLY_PROFILE.to_vec()
}

/// The default class shares as a scenario would write them.
pub fn default_class_shares() -> BTreeMap<String, f64> {
    let truck_share = 1.0 - DEFAULT_CAR_SHARE;
    std::iter::once((VehicleClass::Car.name().to_string(), DEFAULT_CAR_SHARE))
        .chain(
            DEFAULT_TRUCK_SPLIT
                .iter()
                .map(|&(class, split)| (class.name().to_string(), truck_share * split)),
        )
        .collect()
}

fn default_min_gap_s() -> f64 {
    DEFAULT_MIN_GAP_S
}
fn default_parameter_sd_rel() -> f64 {
    DEFAULT_PARAMETER_SD_REL
}
fn default_direction() -> i8 {
    1
}
fn default_speed_mean_m_s() -> f64 {
    DEFAULT_SPEED_MEAN_M_S
}
fn default_speed_sd_m_s() -> f64 {
    DEFAULT_SPEED_SD_M_S
}

/// A validated lane.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Lane {
    pub direction: i8,
    pub flow_per_s: f64,
    pub speed_mean_m_s: f64,
    pub speed_sd_m_s: f64,
    /// Share of each class, indexed by [`VehicleClass::index`].
    pub shares: [f64; 5],
}

/// A validated `[traffic]` table.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Validated {
    pub lanes: Vec<Lane>,
    /// Hourly factors divided by their mean.
    pub profile: [f64; HOURS_PER_DAY],
    pub min_gap_s: f64,
    pub parameter_sd_rel: f64,
    /// Model of each class, indexed by [`VehicleClass::index`].
    pub models: [ClassModel; 5],
}

impl TrafficSpec {
    /// Checks every field; errors name `<field_prefix>.<field>` (e.g.
    /// `traffic.lanes.1.flow_per_hour`) and the value.
    pub fn validate(&self, field_prefix: &str) -> Result<()> {
        self.validated(field_prefix).map(|_| ())
    }

    /// The largest gross weight this traffic can put on the bridge (t): the top of the
    /// truncation range of every class with a positive share on a lane with traffic.
    pub fn heaviest_gross_weight_t(&self, field_prefix: &str) -> Result<f64> {
        let v = self.validated(field_prefix)?;
        let present = |class: &VehicleClass| {
            v.lanes
                .iter()
                .any(|lane| lane.flow_per_s > 0.0 && lane.shares[class.index()] > 0.0)
        };
        Ok(VehicleClass::ALL
            .iter()
            .filter(|c| present(c))
            .map(|c| v.models[c.index()].weight_max_t)
            .fold(0.0, f64::max))
    }

    pub(crate) fn validated(&self, field_prefix: &str) -> Result<Validated> {
        let field = |name: &str| format!("{field_prefix}.{name}");
        if self.lanes.is_empty() {
            return Err(Error::invalid(
                field("lanes"),
                "[]",
                "must list at least one lane",
            ));
        }
        let global_shares = parse_shares(&self.classes, &field("classes"))?;
        let lanes = self
            .lanes
            .iter()
            .enumerate()
            .map(|(i, lane)| lane.validated(global_shares, &format!("{field_prefix}.lanes.{i}")))
            .collect::<Result<Vec<_>>>()?;
        require_positive(&field("min_gap_s"), self.min_gap_s)?;
        Ok(Validated {
            lanes,
            profile: normalised_profile(&self.hourly_profile, &field("hourly_profile"))?,
            min_gap_s: self.min_gap_s,
            parameter_sd_rel: require_relative_sd(
                &field("parameter_sd_rel"),
                self.parameter_sd_rel,
            )?,
            models: class_models(&self.models, &field("models"))?,
        })
    }
}

impl LaneSpec {
    fn validated(&self, global_shares: [f64; 5], field_prefix: &str) -> Result<Lane> {
        let field = |name: &str| format!("{field_prefix}.{name}");
        if self.direction != 1 && self.direction != -1 {
            return Err(Error::invalid(
                field("direction"),
                self.direction,
                "must be 1 (along the beam axis) or -1 (against it)",
            ));
        }
        require_non_negative(&field("flow_per_hour"), self.flow_per_hour)?;
        require_positive(&field("speed_mean_m_s"), self.speed_mean_m_s)?;
        require_non_negative(&field("speed_sd_m_s"), self.speed_sd_m_s)?;
        if self.speed_sd_m_s * super::class::TRUNCATION_SD >= self.speed_mean_m_s {
            return Err(Error::invalid(
                field("speed_sd_m_s"),
                num(self.speed_sd_m_s),
                format!(
                    "must be below speed_mean_m_s / 3 = {} (speeds are truncated at 3 sd and \
                     must stay positive)",
                    num(self.speed_mean_m_s / 3.0)
                ),
            ));
        }
        let shares = match &self.classes {
            Some(classes) => parse_shares(classes, &field("classes"))?,
            None => global_shares,
        };
        Ok(Lane {
            direction: self.direction,
            flow_per_s: self.flow_per_hour / 3600.0,
            speed_mean_m_s: self.speed_mean_m_s,
            speed_sd_m_s: self.speed_sd_m_s,
            shares,
        })
    }
}

/// Class shares by index; every name known, every share finite and >= 0, the sum 1.
fn parse_shares(classes: &BTreeMap<String, f64>, field: &str) -> Result<[f64; 5]> {
    let mut shares = [0.0; 5];
    for (name, &share) in classes {
        let class = known_class(name, &format!("{field}.{name}"), share)?;
        shares[class.index()] = require_non_negative(&format!("{field}.{name}"), share)?;
    }
    let total: f64 = shares.iter().sum();
    if (total - 1.0).abs() > SHARE_SUM_TOLERANCE {
        let listed: Vec<String> = classes.iter().map(|(k, v)| format!("{k} = {v}")).collect();
        return Err(Error::invalid(
            field,
            format!("{{ {} }}", listed.join(", ")),
            format!("must have shares summing to 1 (sum {})", num(total)),
        ));
    }
    Ok(shares)
}

fn known_class(name: &str, field: &str, value: impl std::fmt::Display) -> Result<VehicleClass> {
    VehicleClass::from_name(name).ok_or_else(|| {
        Error::invalid(
            field,
            value,
            format!("names no vehicle class; valid: {}", VehicleClass::names()),
        )
    })
}

fn normalised_profile(factors: &[f64], field: &str) -> Result<[f64; HOURS_PER_DAY]> {
    let profile: [f64; HOURS_PER_DAY] = factors.try_into().map_err(|_| {
        Error::invalid(
            field,
            format!("{} values", factors.len()),
            format!("must have {HOURS_PER_DAY}, one per hour from midnight"),
        )
    })?;
    for (hour, &factor) in profile.iter().enumerate() {
        require_finite(&format!("{field}.{hour}"), factor)?;
        require_non_negative(&format!("{field}.{hour}"), factor)?;
    }
    let mean = profile.iter().sum::<f64>() / HOURS_PER_DAY as f64;
    if mean <= 0.0 {
        return Err(Error::invalid(
            field,
            "all 0",
            "must have at least one positive factor",
        ));
    }
    Ok(profile.map(|f| f / mean))
}

fn class_models(overrides: &BTreeMap<String, ClassModel>, field: &str) -> Result<[ClassModel; 5]> {
    let mut models = VehicleClass::ALL.map(VehicleClass::default_model);
    for (name, model) in overrides {
        let model_field = format!("{field}.{name}");
        let class = known_class(name, &model_field, "{ ... }")?;
        model.validate(class, &model_field)?;
        models[class.index()] = model.clone();
    }
    Ok(models)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_match_the_reference() {
        let shares = default_class_shares();
        let total: f64 = shares.values().sum();
        assert!((total - 1.0).abs() < 1e-12, "{total}");
        assert!((shares["artic_5axle"] - 0.085).abs() < 1e-12);
        let profile_mean = DEFAULT_HOURLY_PROFILE.iter().sum::<f64>() / 24.0;
        assert!((profile_mean - 1.0).abs() < 1e-12, "{profile_mean}");
    }
}
