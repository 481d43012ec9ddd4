//! WIM station configuration as written in a scenario.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::cost323::{Cost323Class, COST323_CLASS_NAMES};
use crate::base::schema as bounds;
use crate::base::units::GRAVITY_M_S2;
use crate::error::{num, require_non_negative, require_positive, Error, Result};

/// Default standard deviation of the relative speed error: 1 %, a good inductive-loop or
/// two-strip speed trap (strip spacing known to ~1 cm over 3-5 m, timing to ~0.1 ms).
pub const DEFAULT_SPEED_SIGMA_REL: f64 = 0.01;
/// Default relative noise of a strip's force reading: 2 % (sensor noise and calibration of
/// a piezo-quartz strip; the dynamic tyre force adds the rest).
pub const DEFAULT_NOISE_REL: f64 = 0.02;
/// Largest relative speed error accepted (10 %), beyond any working speed trap.
const MAX_SPEED_SIGMA_REL: f64 = 0.1;
/// Largest relative strip noise accepted (50 %): beyond it readings turn negative.
const MAX_NOISE_REL: f64 = 0.5;

/// How a station turns a passing vehicle into a record (`model = { kind = "..." }`).
/// Default `ideal`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(remote = "Self", rename_all = "snake_case", deny_unknown_fields)]
#[schemars(tag = "kind")]
pub enum WimModelSpec {
    /// The dynamic tyre force at the strip and the true speed, without error.
    #[default]
    Ideal,
    /// Synthetic, unbiased Gaussian errors on the static loads that keep the station in a
    /// COST 323 accuracy class.
    Cost323 {
        /// One of `A(5)`, `B+(7)`, `B(10)`, `C(15)`, `D+(20)`.
        #[schemars(transform = bounds::one_of(&COST323_CLASS_NAMES))]
        class: String,
        /// Standard deviation of the relative speed error (spacings follow it), in
        /// [0, 0.1]; default 1 %, a good speed trap.
        #[serde(default = "default_speed_sigma_rel")]
        #[schemars(range(min = 0, max = MAX_SPEED_SIGMA_REL))]
        speed_sigma_rel: f64,
    },
    /// The strip reads the simulated dynamic tyre force times `1 + N(0, noise_rel)`.
    Physics {
        /// Relative noise of each axle's force reading, in [0, 0.5]; default 2 %, a
        /// piezo-quartz strip.
        #[serde(default = "default_noise_rel")]
        #[schemars(range(min = 0, max = MAX_NOISE_REL))]
        noise_rel: f64,
        /// Standard deviation of the relative speed error, in [0, 0.1]; default 1 %.
        #[serde(default = "default_speed_sigma_rel")]
        #[schemars(range(min = 0, max = MAX_SPEED_SIGMA_REL))]
        speed_sigma_rel: f64,
    },
}
crate::base::tagged::kind_tagged!(WimModelSpec);

fn default_speed_sigma_rel() -> f64 {
    DEFAULT_SPEED_SIGMA_REL
}

fn default_noise_rel() -> f64 {
    DEFAULT_NOISE_REL
}

/// A validated station model.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Model {
    Ideal,
    Cost323 {
        class: Cost323Class,
        speed_sigma_rel: f64,
    },
    Physics {
        noise_rel: f64,
        speed_sigma_rel: f64,
    },
}

impl WimModelSpec {
    /// Validates the spec; errors name `<field_prefix>.<field>` and the value.
    pub(crate) fn validate(&self, field_prefix: &str) -> Result<Model> {
        let field = |name: &str| format!("{field_prefix}.{name}");
        match self {
            WimModelSpec::Ideal => Ok(Model::Ideal),
            WimModelSpec::Cost323 {
                class,
                speed_sigma_rel,
            } => Ok(Model::Cost323 {
                class: parse_class(class, &field("class"))?,
                speed_sigma_rel: bounded(
                    &field("speed_sigma_rel"),
                    *speed_sigma_rel,
                    MAX_SPEED_SIGMA_REL,
                )?,
            }),
            WimModelSpec::Physics {
                noise_rel,
                speed_sigma_rel,
            } => Ok(Model::Physics {
                noise_rel: bounded(&field("noise_rel"), *noise_rel, MAX_NOISE_REL)?,
                speed_sigma_rel: bounded(
                    &field("speed_sigma_rel"),
                    *speed_sigma_rel,
                    MAX_SPEED_SIGMA_REL,
                )?,
            }),
        }
    }
}

fn parse_class(name: &str, field: &str) -> Result<Cost323Class> {
    Cost323Class::from_name(name).ok_or_else(|| {
        Error::invalid(
            field,
            format!("\"{name}\""),
            format!(
                "is not a COST 323 accuracy class; valid: {}",
                COST323_CLASS_NAMES.join(", ")
            ),
        )
    })
}

fn bounded(field: &str, value: f64, max: f64) -> Result<f64> {
    require_non_negative(field, value)?;
    if value > max {
        return Err(Error::invalid(
            field,
            num(value),
            format!("must be <= {}", num(max)),
        ));
    }
    Ok(value)
}

/// Thresholds of a station's quality flags, compared with the measured values.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct WimLimits {
    /// Axle load above which the strip is off scale, N; default 30 t (294.3 kN), above
    /// any legal axle (11.5 t in the EU) with room for overloads.
    #[serde(default = "default_axle_capacity_n")]
    #[schemars(transform = bounds::positive)]
    pub axle_capacity_n: f64,
    /// Gross weight above which the record is off scale, N; default 100 t (981 kN),
    /// exceptional transports only.
    #[serde(default = "default_gross_capacity_n")]
    #[schemars(transform = bounds::positive)]
    pub gross_capacity_n: f64,
    /// Speed below which the record is flagged low speed, m/s; default 10 km/h: WIM
    /// calibrations hold for free-flowing traffic, stop-and-go readings are unreliable.
    #[serde(default = "default_low_speed_m_s")]
    #[schemars(range(min = 0))]
    pub low_speed_m_s: f64,
}

fn default_axle_capacity_n() -> f64 {
    30_000.0 * GRAVITY_M_S2
}

fn default_gross_capacity_n() -> f64 {
    100_000.0 * GRAVITY_M_S2
}

fn default_low_speed_m_s() -> f64 {
    10.0 / 3.6
}

impl Default for WimLimits {
    fn default() -> Self {
        Self {
            axle_capacity_n: default_axle_capacity_n(),
            gross_capacity_n: default_gross_capacity_n(),
            low_speed_m_s: default_low_speed_m_s(),
        }
    }
}

impl WimLimits {
    /// Checks the limits; errors name `<field_prefix>.<field>` and the value.
    pub fn validate(&self, field_prefix: &str) -> Result<()> {
        let field = |name: &str| format!("{field_prefix}.{name}");
        require_positive(&field("axle_capacity_n"), self.axle_capacity_n)?;
        require_positive(&field("gross_capacity_n"), self.gross_capacity_n)?;
        require_non_negative(&field("low_speed_m_s"), self.low_speed_m_s)?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, Deserialize)]
    #[serde(deny_unknown_fields)]
    struct Station {
        #[serde(default)]
        model: WimModelSpec,
    }

    fn parse(text: &str) -> std::result::Result<WimModelSpec, String> {
        toml::from_str::<Station>(text)
            .map(|s| s.model)
            .map_err(|e| e.to_string())
    }

    #[test]
    fn scenario_forms_parse() {
        assert_eq!(parse("").unwrap(), WimModelSpec::Ideal);
        assert_eq!(
            parse("model = { kind = \"ideal\" }").unwrap(),
            WimModelSpec::Ideal
        );
        assert_eq!(
            parse("model = { kind = \"cost323\", class = \"B+(7)\" }").unwrap(),
            WimModelSpec::Cost323 {
                class: "B+(7)".into(),
                speed_sigma_rel: 0.01
            }
        );
        assert_eq!(
            parse("model = { kind = \"physics\", noise_rel = 0.03 }").unwrap(),
            WimModelSpec::Physics {
                noise_rel: 0.03,
                speed_sigma_rel: 0.01
            }
        );
    }

    #[test]
    fn unknown_fields_and_kinds_are_rejected() {
        let e = parse("model = { kind = \"physics\", noise = 0.03 }").unwrap_err();
        assert!(e.contains("noise"), "{e}");
        let e = parse("model = { kind = \"cost323\", class = \"A(5)\", x = 1 }").unwrap_err();
        assert!(e.contains('x'), "{e}");
        assert!(parse("model = { kind = \"bridge_wim\" }").is_err());
    }

    #[test]
    fn validation_names_the_field_and_value() {
        let spec = WimModelSpec::Cost323 {
            class: "B+".into(),
            speed_sigma_rel: 0.01,
        };
        let e = spec
            .validate("wim_stations.0.model")
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "wim_stations.0.model.class = \"B+\" is not a COST 323 accuracy class; \
             valid: A(5), B+(7), B(10), C(15), D+(20)"
        );
        let spec = WimModelSpec::Physics {
            noise_rel: -0.1,
            speed_sigma_rel: 0.01,
        };
        let e = spec
            .validate("wim_stations.2.model")
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "wim_stations.2.model.noise_rel = -0.1 must be a finite number >= 0"
        );
        let spec = WimModelSpec::Physics {
            noise_rel: 0.02,
            speed_sigma_rel: 0.2,
        };
        let e = spec.validate("m").unwrap_err().to_string();
        assert_eq!(e, "m.speed_sigma_rel = 0.2 must be <= 0.1");
        let limits = WimLimits {
            axle_capacity_n: 0.0,
            ..WimLimits::default()
        };
        let e = limits
            .validate("wim_stations.1.limits")
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("wim_stations.1.limits.axle_capacity_n = 0 "),
            "{e}"
        );
    }
}
