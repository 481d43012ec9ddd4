//! Damage: local EI loss with an onset time and a growth law (`[[damage]]`).

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::base::schema as bounds;
use crate::error::{num, require_non_negative, require_positive, Error, Result};

/// One damaged region (`damage.N`): EI over `[start_m, end_m]` loses `reduction` times the
/// growth law's progress, which goes from 0 before `onset_s` to 1.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DamageSpec {
    /// Start of the region (m from the left support), on the span.
    #[schemars(range(min = 0))]
    pub start_m: f64,
    /// End of the region (m), after `start_m`, on the span.
    #[schemars(transform = bounds::positive)]
    pub end_m: f64,
    /// Fraction of EI lost once fully grown, in (0, 1).
    #[schemars(transform = bounds::positive, transform = bounds::below(1.0))]
    pub reduction: f64,
    /// Simulation time when the damage starts (s), >= 0.
    #[schemars(range(min = 0))]
    pub onset_s: f64,
    /// How the loss grows after the onset (default `step`: all at once).
    #[serde(default)]
    pub growth: Growth,
}

/// Progress of a damage from 0 to 1 after its onset.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(remote = "Self", rename_all = "snake_case", deny_unknown_fields)]
#[schemars(tag = "kind")]
pub enum Growth {
    /// Complete at the onset (a sudden event: impact, bearing failure).
    #[default]
    Step,
    /// Linear from 0 at the onset to 1 after `duration_s`.
    Linear {
        /// Time to full damage (s), > 0.
        #[schemars(transform = bounds::positive)]
        duration_s: f64,
    },
    /// `1 - exp(-(t - onset) / time_constant_s)`: fast then slowing (crack growth
    /// arrested by redistribution, scour reaching equilibrium).
    Exponential {
        /// Time constant (s), > 0; 63.2 % of the loss after one.
        #[schemars(transform = bounds::positive)]
        time_constant_s: f64,
    },
}
crate::base::tagged::kind_tagged!(Growth);

impl Growth {
    /// Progress in [0, 1] at `since_onset_s` after the onset (0 before it).
    pub fn progress(&self, since_onset_s: f64) -> f64 {
        if since_onset_s < 0.0 {
            return 0.0;
        }
        match *self {
            Growth::Step => 1.0,
            Growth::Linear { duration_s } => (since_onset_s / duration_s).min(1.0),
            Growth::Exponential { time_constant_s } => -(-since_onset_s / time_constant_s).exp_m1(),
        }
    }

    pub(super) fn validate(&self, path: &str) -> Result<()> {
        match *self {
            Growth::Step => Ok(()),
            Growth::Linear { duration_s } => {
                require_positive(&format!("{path}.duration_s"), duration_s).map(|_| ())
            }
            Growth::Exponential { time_constant_s } => {
                require_positive(&format!("{path}.time_constant_s"), time_constant_s).map(|_| ())
            }
        }
    }

    pub(super) fn label(&self) -> String {
        match *self {
            Growth::Step => "step".into(),
            Growth::Linear { duration_s } => format!("linear over {duration_s} s"),
            Growth::Exponential { time_constant_s } => {
                format!("exponential, time constant {time_constant_s} s")
            }
        }
    }
}

impl DamageSpec {
    /// Checks the entry against a span of `span_m`; `path` is `damage.N`.
    pub fn validate(&self, path: &str, span_m: f64) -> Result<()> {
        let on_span = |x: f64| x.is_finite() && (0.0..=span_m).contains(&x);
        if !on_span(self.start_m) {
            return Err(Error::invalid(
                format!("{path}.start_m"),
                num(self.start_m),
                format!("must lie on the span [0, {span_m}] m"),
            ));
        }
        if !on_span(self.end_m) || self.end_m <= self.start_m {
            return Err(Error::invalid(
                format!("{path}.end_m"),
                num(self.end_m),
                format!("must lie in ({}, {span_m}] m", self.start_m),
            ));
        }
        if !(self.reduction.is_finite() && self.reduction > 0.0 && self.reduction < 1.0) {
            return Err(Error::invalid(
                format!("{path}.reduction"),
                num(self.reduction),
                "must be a fraction of EI in (0, 1)",
            ));
        }
        require_non_negative(&format!("{path}.onset_s"), self.onset_s)?;
        self.growth.validate(&format!("{path}.growth"))
    }

    /// Fraction of EI lost at `t_s`, in [0, reduction].
    pub fn ei_loss_at(&self, t_s: f64) -> f64 {
        self.reduction * self.growth.progress(t_s - self.onset_s)
    }
}

/// Checks every `[[damage]]` entry against the span; errors name `damage.N.field`.
pub fn validate_damage(damage: &[DamageSpec], span_m: f64) -> Result<()> {
    damage
        .iter()
        .enumerate()
        .try_for_each(|(i, d)| d.validate(&format!("damage.{i}"), span_m))
}

/// A labelled change of condition for `/events`.
#[derive(Debug, Clone, PartialEq)]
pub struct ConditionEvent {
    /// Simulation time (ns), the onset rounded to the nanosecond.
    pub t_ns: u64,
    /// Human-readable description naming the scenario entry.
    pub text: String,
}

/// The onset of each damage (and the end of a linear growth), sorted by time; entries at
/// the same time keep the scenario order.
pub fn damage_events(damage: &[DamageSpec]) -> Vec<ConditionEvent> {
    let mut events: Vec<ConditionEvent> = damage
        .iter()
        .enumerate()
        .flat_map(|(i, d)| {
            let onset = ConditionEvent {
                t_ns: seconds_to_ns(d.onset_s),
                text: format!(
                    "damage.{i} begins: EI -{:.1} % over [{}, {}] m, growth {}",
                    100.0 * d.reduction,
                    d.start_m,
                    d.end_m,
                    d.growth.label()
                ),
            };
            let complete = match d.growth {
                Growth::Linear { duration_s } => Some(ConditionEvent {
                    t_ns: seconds_to_ns(d.onset_s + duration_s),
                    text: format!("damage.{i} fully grown: EI -{:.1} %", 100.0 * d.reduction),
                }),
                _ => None,
            };
            std::iter::once(onset).chain(complete)
        })
        .collect();
    // Stable sort: entries with equal times keep the scenario order.
    events.sort_by_key(|e| e.t_ns);
    events
}

pub(super) fn seconds_to_ns(t_s: f64) -> u64 {
    (t_s * 1e9).round() as u64
}
