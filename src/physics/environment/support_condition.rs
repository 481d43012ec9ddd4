//! The condition of the supports (`[[support_condition]]`): a bearing losing its stiffness,
//! a pier losing its foundation to scour, a support settling. Scheduled like `[[damage]]`:
//! an onset and a growth law.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::damage::{seconds_to_ns, ConditionEvent, Growth};
use crate::base::schema as bounds;
use crate::error::{num, require_non_negative, Error, Result};
use crate::physics::bridge::{Girder, Support};

/// How far a condition's `position_m` may sit from its support (m): a survey's rounding.
const ON_SUPPORT_M: f64 = 1e-3;

/// What happens to the support.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum SupportChange {
    /// An elastic bearing's vertical stiffness falls by `reduction` (elastomer ageing,
    /// a pot bearing's wear): the support softens, the frequencies fall.
    BearingDegradation,
    /// A pier's foundation loses support to scour: the elastic support's vertical and
    /// rotational stiffness fall together by `reduction`.
    Scour,
    /// The support sinks by `settlement_m` (downward positive): a prescribed displacement
    /// whose static effect (moments and reactions of an indeterminate girder, the
    /// deflected shape) adds to the response.
    Settlement,
}

/// One change of a support's condition (`support_condition.N`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SupportConditionSpec {
    /// Position of the support (m from the girder's left end): one of the supports.
    #[schemars(range(min = 0))]
    pub position_m: f64,
    /// `bearing_degradation`, `scour` or `settlement`.
    pub kind: SupportChange,
    /// Bearing degradation and scour: fraction of the stiffness lost once fully grown,
    /// in (0, 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(transform = bounds::positive, transform = bounds::below(1.0))]
    pub reduction: Option<f64>,
    /// Settlement: the support's final downward displacement (m), non-zero and finite
    /// (negative: heave).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub settlement_m: Option<f64>,
    /// Simulation time when the change starts (s), >= 0.
    #[schemars(range(min = 0))]
    pub onset_s: f64,
    /// How it grows after the onset (default `step`).
    #[serde(default)]
    pub growth: Growth,
}

impl SupportConditionSpec {
    /// Checks the entry against `girder`; `path` is `support_condition.N`. Returns the
    /// index of its support.
    pub fn validate(&self, path: &str, girder: &Girder) -> Result<usize> {
        let support = support_at(girder, self.position_m, &format!("{path}.position_m"))?;
        let kind = girder.supports[support];
        let needs = |field: &str, present: bool| match present {
            true => Ok(()),
            false => Err(Error::invalid(
                format!("{path}.{field}"),
                "(missing)",
                format!("is needed by kind = {}", self.kind_name()),
            )),
        };
        let refuses = |field: &str, present: bool| match present {
            false => Ok(()),
            true => Err(Error::invalid(
                format!("{path}.{field}"),
                "(given)",
                format!("does not apply to kind = {}", self.kind_name()),
            )),
        };
        match self.kind {
            SupportChange::BearingDegradation | SupportChange::Scour => {
                needs("reduction", self.reduction.is_some())?;
                refuses("settlement_m", self.settlement_m.is_some())?;
                let r = self.reduction.unwrap_or(f64::NAN);
                if !(r.is_finite() && r > 0.0 && r < 1.0) {
                    return Err(Error::invalid(
                        format!("{path}.reduction"),
                        num(r),
                        "must be a fraction of the stiffness in (0, 1)",
                    ));
                }
                if kind.rigid_vertical() {
                    return Err(Error::invalid(
                        format!("{path}.kind"),
                        self.kind_name(),
                        format!(
                            "needs an elastic support, and the one at x = {} m is {} (give \
                             it as {{ elastic = {{ vertical_n_m = ..., rotational_n_m_rad = \
                             ... }} }} with the bearing's stiffness)",
                            num(self.position_m),
                            kind.name()
                        ),
                    ));
                }
            }
            SupportChange::Settlement => {
                needs("settlement_m", self.settlement_m.is_some())?;
                refuses("reduction", self.reduction.is_some())?;
                let s = self.settlement_m.unwrap_or(f64::NAN);
                if !(s.is_finite() && s != 0.0 && s.abs() <= 1.0) {
                    return Err(Error::invalid(
                        format!("{path}.settlement_m"),
                        num(s),
                        "must be a non-zero displacement of at most 1 m either way",
                    ));
                }
            }
        }
        require_non_negative(&format!("{path}.onset_s"), self.onset_s)?;
        self.growth.validate(&format!("{path}.growth"))?;
        Ok(support)
    }

    fn kind_name(&self) -> &'static str {
        match self.kind {
            SupportChange::BearingDegradation => "bearing_degradation",
            SupportChange::Scour => "scour",
            SupportChange::Settlement => "settlement",
        }
    }

    /// (vertical, rotational) stiffness factors at `t_s`.
    fn stiffness_factors(&self, t_s: f64) -> (f64, f64) {
        let lost = self.reduction.unwrap_or(0.0) * self.growth.progress(t_s - self.onset_s);
        match self.kind {
            SupportChange::BearingDegradation => (1.0 - lost, 1.0),
            SupportChange::Scour => (1.0 - lost, 1.0 - lost),
            SupportChange::Settlement => (1.0, 1.0),
        }
    }

    /// Downward displacement of the support at `t_s` (m).
    fn settlement_at(&self, t_s: f64) -> f64 {
        self.settlement_m.unwrap_or(0.0) * self.growth.progress(t_s - self.onset_s)
    }

    /// True for the changes that alter the stiffness (the model is rebuilt for them).
    pub fn changes_stiffness(&self) -> bool {
        self.kind != SupportChange::Settlement
    }
}

/// The index of the support of `girder` at `x_m` (to 1 mm); the error names `field` and
/// lists the supports (a free end or a point of a span is not one).
pub fn support_at(girder: &Girder, x_m: f64, field: &str) -> Result<usize> {
    let positions = girder.support_positions_m();
    positions
        .iter()
        .position(|&s| (s - x_m).abs() <= ON_SUPPORT_M)
        .ok_or_else(|| {
            let list: Vec<String> = positions.iter().map(|&s| num(s)).collect();
            Error::invalid(
                field,
                num(x_m),
                format!(
                    "is not a support (supports at [{}] m; a free end or a point of a span \
                     has none to change)",
                    list.join(", ")
                ),
            )
        })
}

/// Checks every `[[support_condition]]` entry; errors name `support_condition.N.field`.
pub fn validate_support_conditions(
    conditions: &[SupportConditionSpec],
    girder: &Girder,
) -> Result<()> {
    conditions.iter().enumerate().try_for_each(|(i, c)| {
        c.validate(&format!("support_condition.{i}"), girder)
            .map(|_| ())
    })
}

/// The supports' condition at one instant.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SupportState {
    /// Factor on each support's (vertical, rotational) springs, girder order (1: as built).
    pub stiffness_factor: Vec<(f64, f64)>,
    /// Downward displacement of each support (m).
    pub settlement_m: Vec<f64>,
}

impl SupportState {
    /// Every support as built.
    pub fn intact(supports: usize) -> Self {
        Self {
            stiffness_factor: vec![(1.0, 1.0); supports],
            settlement_m: vec![0.0; supports],
        }
    }

    /// The supports of `girder` with their springs scaled by the factors.
    pub fn apply(&self, girder: &mut Girder) {
        for (support, &(fv, fr)) in girder.supports.iter_mut().zip(&self.stiffness_factor) {
            if let Support::Elastic {
                vertical_n_m,
                rotational_n_m_rad,
            } = support
            {
                *vertical_n_m *= fv;
                *rotational_n_m_rad *= fr;
            }
        }
    }

    /// True when any settlement is non-zero.
    pub fn settles(&self) -> bool {
        self.settlement_m.iter().any(|&s| s != 0.0)
    }
}

/// The supports' conditions over a run.
#[derive(Debug, Clone)]
pub struct SupportConditions {
    entries: Vec<(usize, SupportConditionSpec)>,
    supports: usize,
}

impl SupportConditions {
    /// Validated entries on `girder`.
    pub fn new(conditions: &[SupportConditionSpec], girder: &Girder) -> Result<Self> {
        let entries = conditions
            .iter()
            .enumerate()
            .map(|(i, c)| {
                Ok((
                    c.validate(&format!("support_condition.{i}"), girder)?,
                    c.clone(),
                ))
            })
            .collect::<Result<_>>()?;
        Ok(Self {
            entries,
            supports: girder.supports.len(),
        })
    }

    /// The state at `t_s` into `state` (reusing its vectors); changes of one support
    /// compound (factors multiply, settlements add).
    pub fn update(&self, t_s: f64, state: &mut SupportState) {
        state.stiffness_factor.clear();
        state.stiffness_factor.resize(self.supports, (1.0, 1.0));
        state.settlement_m.clear();
        state.settlement_m.resize(self.supports, 0.0);
        for (support, c) in &self.entries {
            let (fv, fr) = c.stiffness_factors(t_s);
            let f = &mut state.stiffness_factor[*support];
            *f = (f.0 * fv, f.1 * fr);
            state.settlement_m[*support] += c.settlement_at(t_s);
        }
    }

    /// The onsets (and the ends of linear growth) for `/events`.
    pub fn events(&self) -> Vec<ConditionEvent> {
        self.entries
            .iter()
            .enumerate()
            .flat_map(|(i, (_, c))| {
                let what = match c.kind {
                    SupportChange::Settlement => {
                        format!("settles {} mm", num(1e3 * c.settlement_m.unwrap_or(0.0)))
                    }
                    _ => format!(
                        "loses {:.1} % of its stiffness",
                        100.0 * c.reduction.unwrap_or(0.0)
                    ),
                };
                let onset = ConditionEvent {
                    t_ns: seconds_to_ns(c.onset_s),
                    text: format!(
                        "support_condition.{i} begins: the support at x = {} m ({}) {what}, \
                         growth {}",
                        num(c.position_m),
                        c.kind_name(),
                        c.growth.label()
                    ),
                };
                let complete = match c.growth {
                    Growth::Linear { duration_s } => Some(ConditionEvent {
                        t_ns: seconds_to_ns(c.onset_s + duration_s),
                        text: format!("support_condition.{i} fully grown: {what}"),
                    }),
                    _ => None,
                };
                std::iter::once(onset).chain(complete)
            })
            .collect()
    }
}
