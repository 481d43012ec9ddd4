//! The `[sensors.faults]` table: which faults a channel suffers, and their validation.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::draws::{field, require_duration, require_probability, seconds_to_ns, MAX_SECONDS};
use crate::base::schema as bounds;
use crate::error::{num, require_finite, require_non_negative, require_positive, Error, Result};

/// Packet loss (`loss = { kind = "random", ... }` or `{ kind = "bursty", ... }`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(remote = "Self", rename_all = "snake_case", deny_unknown_fields)]
#[schemars(tag = "kind")]
pub enum LossSpec {
    /// Each sample is lost independently with `probability`.
    Random {
        /// Per-sample loss probability, in [0, 1].
        #[schemars(range(min = 0, max = 1))]
        probability: f64,
    },
    /// Gilbert-Elliott two-state chain, every sample of the bad state lost: long-run loss
    /// rate `probability`, mean burst `mean_burst_samples`.
    Bursty {
        /// Long-run fraction of lost samples, `0 <= p <= B / (1 + B)` for a mean burst `B`
        /// (a good spell lasts at least one sample).
        #[schemars(range(min = 0, max = 1))]
        probability: f64,
        /// Mean number of consecutive lost samples, >= 1.
        #[schemars(range(min = 1))]
        mean_burst_samples: f64,
    },
}
crate::base::tagged::kind_tagged!(LossSpec);

/// A scheduled outage: every sample with `start_s <= t < start_s + duration_s` is lost.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct OutageWindow {
    /// Start, s since the run start, >= 0.
    #[schemars(range(min = 0, max = MAX_SECONDS))]
    pub start_s: f64,
    /// Length, s, > 0.
    #[schemars(transform = bounds::positive, range(max = MAX_SECONDS))]
    pub duration_s: f64,
}

/// Single-sample spikes of `amplitude` with a random sign, at Poisson instants.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SpikeSpec {
    /// Mean number per hour, >= 0.
    #[schemars(range(min = 0))]
    pub rate_per_hour: f64,
    /// Size, in the channel's unit, > 0.
    #[schemars(transform = bounds::positive)]
    pub amplitude: f64,
}

/// Stuck values: the channel repeats its last good value for an exponential duration.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct StuckSpec {
    /// Mean number of onsets per hour, >= 0.
    #[schemars(range(min = 0))]
    pub rate_per_hour: f64,
    /// Mean duration, s, > 0.
    #[schemars(transform = bounds::positive, range(max = MAX_SECONDS))]
    pub mean_duration_s: f64,
}

/// Offset steps: persistent jumps `N(0, sigma)` added to everything after them.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct OffsetStepSpec {
    /// Mean number per hour, >= 0.
    #[schemars(range(min = 0))]
    pub rate_per_hour: f64,
    /// Standard deviation of each jump, in the channel's unit, > 0.
    #[schemars(transform = bounds::positive)]
    pub sigma: f64,
}

/// The channel dies: from `from_s` on it reports `value` (still subject to loss).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DeadSpec {
    /// Instant of death, s since the run start, >= 0.
    #[schemars(range(min = 0, max = MAX_SECONDS))]
    pub from_s: f64,
    /// The constant reported, in the channel's unit.
    pub value: f64,
}

/// Faults of one sensor channel (`[sensors.faults]`); every part is optional and absent by
/// default, so the default is a fault-free channel.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct FaultSpec {
    /// Packet loss. Default none.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub loss: Option<LossSpec>,
    /// Scheduled outages. Default none.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub outages: Vec<OutageWindow>,
    /// Random outages per hour (Poisson onsets), >= 0. Default 0.
    #[schemars(range(min = 0))]
    pub outage_rate_per_hour: f64,
    /// Mean length of a random outage (exponential), s, > 0; required when
    /// `outage_rate_per_hour > 0`.
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schemars(transform = bounds::positive, range(max = MAX_SECONDS))]
    pub outage_mean_duration_s: Option<f64>,
    /// Spikes. Default none.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub spikes: Option<SpikeSpec>,
    /// Stuck values. Default none.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub stuck: Option<StuckSpec>,
    /// Offset steps. Default none.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub offset_steps: Option<OffsetStepSpec>,
    /// Dead channel. Default none.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub dead: Option<DeadSpec>,
}

impl FaultSpec {
    /// Whether no fault is configured (the channel needs no injector).
    pub fn is_empty(&self) -> bool {
        self.loss.is_none()
            && self.outages.is_empty()
            && self.outage_rate_per_hour == 0.0
            && self.spikes.is_none()
            && self.stuck.is_none()
            && self.offset_steps.is_none()
            && self.dead.is_none()
    }

    /// Checks every part; `prefix` is the path of the table, e.g. `sensors.3.faults`, and
    /// errors name the full path of the offending field and its value.
    pub fn validate(&self, prefix: &str) -> Result<()> {
        if let Some(loss) = &self.loss {
            loss.validate(&field(prefix, "loss"))?;
        }
        for (i, window) in self.outages.iter().enumerate() {
            let window_prefix = field(prefix, &format!("outages.{i}"));
            seconds_to_ns(&field(&window_prefix, "start_s"), window.start_s)?;
            require_duration(&field(&window_prefix, "duration_s"), window.duration_s)?;
        }
        self.validate_random_outages(prefix)?;
        if let Some(s) = &self.spikes {
            let p = field(prefix, "spikes");
            require_non_negative(&field(&p, "rate_per_hour"), s.rate_per_hour)?;
            require_positive(&field(&p, "amplitude"), s.amplitude)?;
        }
        if let Some(s) = &self.stuck {
            let p = field(prefix, "stuck");
            require_non_negative(&field(&p, "rate_per_hour"), s.rate_per_hour)?;
            require_duration(&field(&p, "mean_duration_s"), s.mean_duration_s)?;
        }
        if let Some(s) = &self.offset_steps {
            let p = field(prefix, "offset_steps");
            require_non_negative(&field(&p, "rate_per_hour"), s.rate_per_hour)?;
            require_positive(&field(&p, "sigma"), s.sigma)?;
        }
        if let Some(d) = &self.dead {
            let p = field(prefix, "dead");
            seconds_to_ns(&field(&p, "from_s"), d.from_s)?;
            require_finite(&field(&p, "value"), d.value)?;
        }
        Ok(())
    }

    fn validate_random_outages(&self, prefix: &str) -> Result<()> {
        let rate_field = field(prefix, "outage_rate_per_hour");
        require_non_negative(&rate_field, self.outage_rate_per_hour)?;
        let duration_field = field(prefix, "outage_mean_duration_s");
        match self.outage_mean_duration_s {
            Some(d) => {
                require_duration(&duration_field, d)?;
            }
            None if self.outage_rate_per_hour > 0.0 => {
                return Err(Error::invalid(
                    duration_field,
                    "none",
                    format!(
                        "must be given when outage_rate_per_hour = {} > 0",
                        num(self.outage_rate_per_hour)
                    ),
                ));
            }
            None => {}
        }
        Ok(())
    }
}

impl LossSpec {
    /// Long-run fraction of lost samples.
    pub fn probability(&self) -> f64 {
        match *self {
            LossSpec::Random { probability } | LossSpec::Bursty { probability, .. } => probability,
        }
    }

    fn validate(&self, prefix: &str) -> Result<()> {
        let p_field = field(prefix, "probability");
        let p = require_probability(&p_field, self.probability())?;
        if let LossSpec::Bursty {
            mean_burst_samples, ..
        } = *self
        {
            let b_field = field(prefix, "mean_burst_samples");
            if !(mean_burst_samples.is_finite() && mean_burst_samples >= 1.0) {
                return Err(Error::invalid(
                    b_field,
                    num(mean_burst_samples),
                    "must be a finite number >= 1 (samples)",
                ));
            }
            let p_max = mean_burst_samples / (1.0 + mean_burst_samples);
            if p > p_max {
                return Err(Error::invalid(
                    p_field,
                    num(p),
                    format!(
                        "must be <= mean_burst_samples / (1 + mean_burst_samples) = {} (good \
                         spells between bursts last at least one sample)",
                        num(p_max)
                    ),
                ));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> FaultSpec {
        toml::from_str(text).unwrap()
    }

    #[test]
    fn the_documented_keys_parse() {
        let spec = parse(
            r#"
            loss = { kind = "bursty", probability = 0.02, mean_burst_samples = 20 }
            outages = [{ start_s = 100.0, duration_s = 30.0 }]
            outage_rate_per_hour = 0.5
            outage_mean_duration_s = 60.0
            spikes = { rate_per_hour = 2.0, amplitude = 0.5 }
            stuck = { rate_per_hour = 1.0, mean_duration_s = 10.0 }
            offset_steps = { rate_per_hour = 0.1, sigma = 0.01 }
            dead = { from_s = 500.0, value = 0.0 }
            "#,
        );
        assert_eq!(
            spec.loss,
            Some(LossSpec::Bursty {
                probability: 0.02,
                mean_burst_samples: 20.0
            })
        );
        assert_eq!(spec.outages.len(), 1);
        assert!(!spec.is_empty());
        spec.validate("sensors.0.faults").unwrap();
        let round_trip: FaultSpec = toml::from_str(&toml::to_string(&spec).unwrap()).unwrap();
        assert_eq!(round_trip, spec);
        assert!(parse("").is_empty());
    }

    #[test]
    fn unknown_keys_and_kinds_are_rejected() {
        for text in [
            "loss = { kind = \"random\", probability = 0.1, burst = 2 }",
            "loss = { kind = \"gilbert\", probability = 0.1 }",
            "spike = { rate_per_hour = 1.0, amplitude = 1.0 }",
        ] {
            assert!(toml::from_str::<FaultSpec>(text).is_err(), "{text}");
        }
    }

    fn error_of(text: &str) -> String {
        parse(text)
            .validate("sensors.3.faults")
            .unwrap_err()
            .to_string()
    }

    #[test]
    fn bad_values_name_the_full_field_path() {
        let cases = [
            (
                "loss = { kind = \"random\", probability = 1.5 }",
                "sensors.3.faults.loss.probability = 1.5 ",
            ),
            (
                "loss = { kind = \"bursty\", probability = 0.1, mean_burst_samples = 0.5 }",
                "sensors.3.faults.loss.mean_burst_samples = 0.5 ",
            ),
            (
                "loss = { kind = \"bursty\", probability = 0.6, mean_burst_samples = 1 }",
                "sensors.3.faults.loss.probability = 0.6 must be <= ",
            ),
            (
                "outages = [{ start_s = 1.0, duration_s = 1.0 }, { start_s = 5.0, duration_s = 0.0 }]",
                "sensors.3.faults.outages.1.duration_s = 0 ",
            ),
            ("outage_rate_per_hour = -1.0", "sensors.3.faults.outage_rate_per_hour = -1 "),
            (
                "outage_rate_per_hour = 1.0",
                "sensors.3.faults.outage_mean_duration_s = none ",
            ),
            (
                "spikes = { rate_per_hour = 1.0, amplitude = -2.0 }",
                "sensors.3.faults.spikes.amplitude = -2 ",
            ),
            (
                "stuck = { rate_per_hour = -3.0, mean_duration_s = 1.0 }",
                "sensors.3.faults.stuck.rate_per_hour = -3 ",
            ),
            (
                "offset_steps = { rate_per_hour = 1.0, sigma = 0.0 }",
                "sensors.3.faults.offset_steps.sigma = 0 ",
            ),
            (
                "dead = { from_s = -5.0, value = 0.0 }",
                "sensors.3.faults.dead.from_s = -5 ",
            ),
            (
                "dead = { from_s = 5.0, value = nan }",
                "sensors.3.faults.dead.value = NaN ",
            ),
        ];
        for (text, expected) in cases {
            let e = error_of(text);
            assert!(e.starts_with(expected), "{text}: {e}");
        }
    }
}
