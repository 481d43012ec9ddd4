//! Vehicle classes and their random models: gross weight, axle spacings, axle load shares
//! and body overhangs.
//!
//! Defaults follow the Auxerre traffic behind the Eurocode LM1 calibration (Grave-type
//! model as in Caprani's BTLS; docs/sensors.md section 4) where that reference gives a value;
//! every other value is an engineering estimate and is marked "estimated" below.

use rand::RngExt;
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::base::schema as bounds;
use crate::base::units::GRAVITY_M_S2;
use crate::error::{num, require_non_negative, require_positive, Error, Result};

/// Normal draws are truncated to `mean +/- TRUNCATION_SD * sd` (spacings, speeds, load
/// share and parameter variation): the tails beyond 3 sd are where a normal model of a
/// physical length or speed stops being physical (negative spacings, 0 speed).
pub const TRUNCATION_SD: f64 = 3.0;

/// Smallest share of a weight mixture's mass that may lie inside its truncation range. A
/// smaller share almost always means a unit mistake (kg for t) and would make the
/// rejection sampler slow.
const MIN_WEIGHT_MASS_IN_RANGE: f64 = 0.5;

/// Draws after which the rejection samplers give up and clamp. With at least half the mass
/// in range (validated) the chance of reaching it is below 2^-1000: a guard, not a path.
const MAX_REJECTION_DRAWS: usize = 1000;

/// Largest relative sd of a per-vehicle perturbation (load shares, suspension
/// parameters): with 3-sd truncation the factor stays above 1 - 3 * 0.3 = 0.1 > 0.
pub const MAX_RELATIVE_SD: f64 = 0.3;

/// The vehicle classes of the generator, in the order of their default shares.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum VehicleClass {
    /// Passenger car (2 axles).
    Car,
    /// Rigid two-axle truck.
    Truck2Axle,
    /// Rigid three-axle truck (single front axle, rear tandem).
    Truck3Axle,
    /// Four-axle rigid truck: twin steer axles and a rear tandem (estimated layout).
    Truck4Axle,
    /// Five-axle articulated truck: two-axle tractor with a tridem semi-trailer.
    Artic5Axle,
}

impl VehicleClass {
    /// All classes, in share order.
    pub const ALL: [VehicleClass; 5] = [
        VehicleClass::Car,
        VehicleClass::Truck2Axle,
        VehicleClass::Truck3Axle,
        VehicleClass::Truck4Axle,
        VehicleClass::Artic5Axle,
    ];

    /// The name used in scenarios (`classes = { car = 0.8, ... }`) and records.
    pub fn name(self) -> &'static str {
        match self {
            VehicleClass::Car => "car",
            VehicleClass::Truck2Axle => "truck_2axle",
            VehicleClass::Truck3Axle => "truck_3axle",
            VehicleClass::Truck4Axle => "truck_4axle",
            VehicleClass::Artic5Axle => "artic_5axle",
        }
    }

    /// The class called `name`, if any.
    pub fn from_name(name: &str) -> Option<VehicleClass> {
        Self::ALL.into_iter().find(|c| c.name() == name)
    }

    /// Position in [`VehicleClass::ALL`].
    pub fn index(self) -> usize {
        self as usize
    }

    /// Number of axles.
    pub fn axle_count(self) -> usize {
        match self {
            VehicleClass::Car | VehicleClass::Truck2Axle => 2,
            VehicleClass::Truck3Axle => 3,
            VehicleClass::Truck4Axle => 4,
            VehicleClass::Artic5Axle => 5,
        }
    }

    /// All class names, comma separated, for error messages.
    pub(crate) fn names() -> String {
        Self::ALL.map(VehicleClass::name).join(", ")
    }

    /// Default model of the class; see the module docs for the sources.
    pub fn default_model(self) -> ClassModel {
        match self {
            VehicleClass::Car => car(),
            VehicleClass::Truck2Axle => truck_2axle(),
            VehicleClass::Truck3Axle => truck_3axle(),
            VehicleClass::Truck4Axle => truck_4axle(),
            VehicleClass::Artic5Axle => artic_5axle(),
        }
    }
}

/// One normal component of a gross-weight mixture.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct WeightComponent {
    /// Mixture weight, >= 0; the weights of a class are divided by their sum.
    #[schemars(range(min = 0))]
    pub share: f64,
    /// Mean gross weight, t.
    #[schemars(transform = bounds::positive)]
    pub mean_t: f64,
    /// Standard deviation, t, >= 0.
    #[schemars(range(min = 0))]
    pub sd_t: f64,
}

/// The random model of one class (`[traffic.models.<class>]` replaces a default whole).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ClassModel {
    /// Gross weight: a mixture of normals (unloaded / loaded populations), t; at least
    /// one component.
    #[schemars(length(min = 1))]
    pub weight: Vec<WeightComponent>,
    /// Lower end of the truncation range of the gross weight, t, >= 0.
    #[schemars(range(min = 0))]
    pub weight_min_t: f64,
    /// Upper end of the truncation range of the gross weight, t, above `weight_min_t`.
    #[schemars(transform = bounds::positive)]
    pub weight_max_t: f64,
    /// Mean of each axle spacing, front to rear, m, each > 0 (one fewer than the axles).
    #[schemars(transform = bounds::positive_items)]
    pub spacing_mean_m: Vec<f64>,
    /// Standard deviation of each spacing, m, each >= 0 and below a third of its mean;
    /// draws are truncated at 3 sd.
    #[schemars(inner(range(min = 0)))]
    pub spacing_sd_m: Vec<f64>,
    /// Mean share of the gross weight on each axle, front to rear, each > 0; sums to 1.
    #[schemars(transform = bounds::positive_items)]
    pub load_share: Vec<f64>,
    /// Relative sd of each axle's share per vehicle, in [0, 0.3] (the shares are then
    /// renormalised).
    #[schemars(range(min = 0, max = MAX_RELATIVE_SD))]
    pub load_share_sd_rel: f64,
    /// Body length ahead of the front axle, m, >= 0.
    #[schemars(range(min = 0))]
    pub front_overhang_m: f64,
    /// Body length behind the last axle, m, >= 0.
    #[schemars(range(min = 0))]
    pub rear_overhang_m: f64,
}

/// One vehicle's class-dependent draws.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Body {
    pub gross_weight_n: f64,
    pub axle_spacing_m: Vec<f64>,
    pub axle_load_n: Vec<f64>,
    pub front_overhang_m: f64,
    pub rear_overhang_m: f64,
}

impl ClassModel {
    /// Checks the model of `class`; errors name `<field_prefix>.<field>`.
    pub fn validate(&self, class: VehicleClass, field_prefix: &str) -> Result<()> {
        let field = |name: &str| format!("{field_prefix}.{name}");
        self.validate_weight(field_prefix)?;
        let spacings = class.axle_count() - 1;
        require_len(
            &field("spacing_mean_m"),
            self.spacing_mean_m.len(),
            spacings,
        )?;
        require_len(&field("spacing_sd_m"), self.spacing_sd_m.len(), spacings)?;
        for (i, (&mean_m, &sd_m)) in self
            .spacing_mean_m
            .iter()
            .zip(&self.spacing_sd_m)
            .enumerate()
        {
            require_positive(&format!("{field_prefix}.spacing_mean_m.{i}"), mean_m)?;
            let sd_field = format!("{field_prefix}.spacing_sd_m.{i}");
            require_non_negative(&sd_field, sd_m)?;
            if mean_m - TRUNCATION_SD * sd_m <= 0.0 {
                return Err(Error::invalid(
                    sd_field,
                    num(sd_m),
                    format!("must be below mean / 3 = {} m", num(mean_m / 3.0)),
                ));
            }
        }
        self.validate_load_share(class, field_prefix)?;
        require_non_negative(&field("front_overhang_m"), self.front_overhang_m)?;
        require_non_negative(&field("rear_overhang_m"), self.rear_overhang_m)?;
        Ok(())
    }

    fn validate_weight(&self, field_prefix: &str) -> Result<()> {
        if self.weight.is_empty() {
            return Err(Error::invalid(
                format!("{field_prefix}.weight"),
                "[]",
                "must list at least one normal component",
            ));
        }
        for (i, c) in self.weight.iter().enumerate() {
            let prefix = format!("{field_prefix}.weight.{i}");
            require_non_negative(&format!("{prefix}.share"), c.share)?;
            require_positive(&format!("{prefix}.mean_t"), c.mean_t)?;
            require_non_negative(&format!("{prefix}.sd_t"), c.sd_t)?;
        }
        let total: f64 = self.weight.iter().map(|c| c.share).sum();
        if total <= 0.0 {
            return Err(Error::invalid(
                format!("{field_prefix}.weight"),
                num(total),
                "(sum of shares) must be > 0",
            ));
        }
        let min_field = format!("{field_prefix}.weight_min_t");
        require_non_negative(&min_field, self.weight_min_t)?;
        let max_field = format!("{field_prefix}.weight_max_t");
        require_positive(&max_field, self.weight_max_t)?;
        if self.weight_max_t <= self.weight_min_t {
            return Err(Error::invalid(
                max_field,
                num(self.weight_max_t),
                format!("must exceed weight_min_t = {}", num(self.weight_min_t)),
            ));
        }
        let mass = self.weight_mass_in_range();
        if mass < MIN_WEIGHT_MASS_IN_RANGE {
            return Err(Error::invalid(
                format!("{field_prefix}.weight"),
                format!("{} of the mixture", num(mass)),
                format!(
                    "lies in [weight_min_t, weight_max_t]; at least {MIN_WEIGHT_MASS_IN_RANGE} \
                     must (weights are in tonnes)"
                ),
            ));
        }
        Ok(())
    }

    fn validate_load_share(&self, class: VehicleClass, field_prefix: &str) -> Result<()> {
        let field = format!("{field_prefix}.load_share");
        require_len(&field, self.load_share.len(), class.axle_count())?;
        for (i, &share) in self.load_share.iter().enumerate() {
            require_positive(&format!("{field}.{i}"), share)?;
        }
        let total: f64 = self.load_share.iter().sum();
        if (total - 1.0).abs() > SHARE_SUM_TOLERANCE {
            return Err(Error::invalid(
                field,
                format!("{:?}", self.load_share),
                format!("must sum to 1 (sum {})", num(total)),
            ));
        }
        require_relative_sd(
            &format!("{field_prefix}.load_share_sd_rel"),
            self.load_share_sd_rel,
        )?;
        Ok(())
    }

    /// Mixture mass inside the truncation range, from the normal CDF.
    fn weight_mass_in_range(&self) -> f64 {
        let total: f64 = self.weight.iter().map(|c| c.share).sum();
        self.weight
            .iter()
            .map(|c| {
                let (lo, hi) = (self.weight_min_t, self.weight_max_t);
                let inside = if c.sd_t > 0.0 {
                    normal_cdf((hi - c.mean_t) / c.sd_t) - normal_cdf((lo - c.mean_t) / c.sd_t)
                } else if (lo..=hi).contains(&c.mean_t) {
                    1.0
                } else {
                    0.0
                };
                c.share / total * inside
            })
            .sum()
    }

    /// Draws one vehicle of this (validated) model from `rng`, in a fixed order: weight,
    /// spacings, load shares.
    pub(crate) fn draw(&self, rng: &mut ChaCha8Rng) -> Body {
        let gross_weight_n = self.draw_weight_t(rng) * 1000.0 * GRAVITY_M_S2;
        let axle_spacing_m = self
            .spacing_mean_m
            .iter()
            .zip(&self.spacing_sd_m)
            .map(|(&mean, &sd)| mean + sd * truncated_standard_normal(rng))
            .collect();
        let axle_load_n = self
            .draw_load_shares(rng)
            .into_iter()
            .map(|share| share * gross_weight_n)
            .collect();
        Body {
            gross_weight_n,
            axle_spacing_m,
            axle_load_n,
            front_overhang_m: self.front_overhang_m,
            rear_overhang_m: self.rear_overhang_m,
        }
    }

    /// Gross weight from the mixture truncated to `[weight_min_t, weight_max_t]`, by
    /// rejection: pick a component by its share, draw, keep if in range. Exact for the
    /// truncated mixture (rejection conditions the whole mixture on the range).
    fn draw_weight_t(&self, rng: &mut ChaCha8Rng) -> f64 {
        let total: f64 = self.weight.iter().map(|c| c.share).sum();
        let mut weight_t = self.weight[0].mean_t;
        for _ in 0..MAX_REJECTION_DRAWS {
            let pick = rng.random::<f64>() * total;
            let component = pick_component(&self.weight, pick);
            let z: f64 = rng.sample(StandardNormal);
            weight_t = component.mean_t + component.sd_t * z;
            if (self.weight_min_t..=self.weight_max_t).contains(&weight_t) {
                return weight_t;
            }
        }
        weight_t.clamp(self.weight_min_t, self.weight_max_t)
    }

    /// Mean shares times `1 + sd_rel * z` (z truncated at 3 sd), renormalised to sum 1: the
    /// front/rear split varies with the payload's position, the gross weight does not.
    fn draw_load_shares(&self, rng: &mut ChaCha8Rng) -> Vec<f64> {
        let shares: Vec<f64> = self
            .load_share
            .iter()
            .map(|&s| s * (1.0 + self.load_share_sd_rel * truncated_standard_normal(rng)))
            .collect();
        let total: f64 = shares.iter().sum();
        shares.into_iter().map(|s| s / total).collect()
    }
}

fn pick_component(components: &[WeightComponent], mut pick: f64) -> &WeightComponent {
    for c in components {
        if pick < c.share {
            return c;
        }
        pick -= c.share;
    }
    // Rounding left `pick` just above the last share: it belongs to the last component.
    &components[components.len() - 1]
}

/// Shares (class mix, load shares) must sum to 1 within this: room for decimal input such
/// as 0.046 + 0.0056 + ... without accepting a forgotten class.
pub(crate) const SHARE_SUM_TOLERANCE: f64 = 1e-6;

fn require_len(field: &str, len: usize, expected: usize) -> Result<()> {
    if len == expected {
        Ok(())
    } else {
        Err(Error::invalid(
            field,
            format!("{len} values"),
            format!("must have {expected} (one per axle or axle spacing)"),
        ))
    }
}

/// Checks a relative standard deviation of a truncated perturbation.
pub(crate) fn require_relative_sd(field: &str, sd_rel: f64) -> Result<f64> {
    require_non_negative(field, sd_rel)?;
    if sd_rel > MAX_RELATIVE_SD {
        return Err(Error::invalid(
            field,
            num(sd_rel),
            format!("must be <= {MAX_RELATIVE_SD} (factors must stay positive)"),
        ));
    }
    Ok(sd_rel)
}

/// A standard normal draw truncated to `[-3, 3]` by rejection (acceptance 99.7 %).
pub(crate) fn truncated_standard_normal(rng: &mut ChaCha8Rng) -> f64 {
    for _ in 0..MAX_REJECTION_DRAWS {
        let z: f64 = rng.sample(StandardNormal);
        if z.abs() <= TRUNCATION_SD {
            return z;
        }
    }
    0.0
}

/// Standard normal CDF, `Phi(z) = erfc(-z / sqrt 2) / 2` (Abramowitz & Stegun 26.2.29);
/// `libm::erfc` is a port of FreeBSD's msun (error below 1 ulp), and the erfc form keeps
/// the far lower tail accurate where `1 + erf` would cancel.
fn normal_cdf(z: f64) -> f64 {
    0.5 * libm::erfc(-z / std::f64::consts::SQRT_2)
}

fn components(list: &[(f64, f64, f64)]) -> Vec<WeightComponent> {
    list.iter()
        .map(|&(share, mean_t, sd_t)| WeightComponent {
            share,
            mean_t,
            sd_t,
        })
        .collect()
}

/// Car: 1.45 +/- 0.22 t in [1.0, 2.0] t, wheelbase 2.6 +/- 0.15 m, 55 : 45 front/rear,
/// 4.4 m long. All estimated (European passenger cars).
fn car() -> ClassModel {
    ClassModel {
        weight: components(&[(1.0, 1.45, 0.22)]),
        weight_min_t: 1.0,
        weight_max_t: 2.0,
        spacing_mean_m: vec![2.6],
        spacing_sd_m: vec![0.15],
        load_share: vec![0.55, 0.45],
        load_share_sd_rel: 0.05,
        front_overhang_m: 0.85,
        rear_overhang_m: 0.95,
    }
}

/// Two-axle rigid truck: spacing 5.53 +/- 0.51 m and shares 1/3 : 2/3 (docs/sensors.md 4);
/// weight 0.6 x N(8.5, 2.0) + 0.4 x N(14, 2.5) t in [3.5, 22] t (empty to the 18 t limit
/// plus overloads) and overhangs 1.4 / 2.6 m are estimated.
fn truck_2axle() -> ClassModel {
    ClassModel {
        weight: components(&[(0.6, 8.5, 2.0), (0.4, 14.0, 2.5)]),
        weight_min_t: 3.5,
        weight_max_t: 22.0,
        spacing_mean_m: vec![5.53],
        spacing_sd_m: vec![0.51],
        load_share: vec![1.0 / 3.0, 2.0 / 3.0],
        load_share_sd_rel: 0.08,
        front_overhang_m: 1.4,
        rear_overhang_m: 2.6,
    }
}

/// Three-axle rigid truck (steer + tandem), all estimated: 0.5 x N(14, 3) +
/// 0.5 x N(24, 3) t in [7, 32] t (26 t limit plus overloads), spacings 4.5 +/- 0.4 and
/// 1.35 +/- 0.05 m (the `vehicle::classes` preset's), shares 0.28 / 0.36 / 0.36, 10.1 m
/// long.
fn truck_3axle() -> ClassModel {
    ClassModel {
        weight: components(&[(0.5, 14.0, 3.0), (0.5, 24.0, 3.0)]),
        weight_min_t: 7.0,
        weight_max_t: 32.0,
        spacing_mean_m: vec![4.5, 1.35],
        spacing_sd_m: vec![0.4, 0.05],
        load_share: vec![0.28, 0.36, 0.36],
        load_share_sd_rel: 0.08,
        front_overhang_m: 1.4,
        rear_overhang_m: 2.8,
    }
}

/// Four-axle rigid truck (twin steer + tandem, the `vehicle::classes` preset's layout),
/// all estimated: 0.4 x N(17, 3.5) + 0.6 x N(29, 3.5) t in [9, 40] t (32 t limit plus
/// overloads), spacings 1.9 +/- 0.1, 3.3 +/- 0.4, 1.35 +/- 0.05 m, shares
/// 0.2 / 0.2 / 0.3 / 0.3, 10.75 m long.
fn truck_4axle() -> ClassModel {
    ClassModel {
        weight: components(&[(0.4, 17.0, 3.5), (0.6, 29.0, 3.5)]),
        weight_min_t: 9.0,
        weight_max_t: 40.0,
        spacing_mean_m: vec![1.9, 3.3, 1.35],
        spacing_sd_m: vec![0.1, 0.4, 0.05],
        load_share: vec![0.2, 0.2, 0.3, 0.3],
        load_share_sd_rel: 0.08,
        front_overhang_m: 1.4,
        rear_overhang_m: 2.8,
    }
}

/// Five-axle articulated truck: weight 0.16 x N(29.6, 5.5) + 0.834 x N(41.2, 5.5) t (the
/// shares renormalised to sum 1) and spacing means 3.24, 5.43, 1.20, 1.21 m (docs/sensors.md 4);
/// truncation [12, 60] t (empty tractor-trailer to 40 t plus heavy overloads), spacing sds
/// 0.2 / 0.6 / 0.05 / 0.05 m, shares 0.16 / 0.27 / 0.19 x 3 and overhangs 1.4 / 4.0 m
/// (16.5 m, the EU limit) are estimated.
fn artic_5axle() -> ClassModel {
    ClassModel {
        weight: components(&[(0.16, 29.6, 5.5), (0.834, 41.2, 5.5)]),
        weight_min_t: 12.0,
        weight_max_t: 60.0,
        spacing_mean_m: vec![3.24, 5.43, 1.20, 1.21],
        spacing_sd_m: vec![0.2, 0.6, 0.05, 0.05],
        load_share: vec![0.16, 0.27, 0.19, 0.19, 0.19],
        load_share_sd_rel: 0.08,
        front_overhang_m: 1.4,
        rear_overhang_m: 4.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_models_are_valid() {
        for class in VehicleClass::ALL {
            class
                .default_model()
                .validate(class, &format!("traffic.models.{}", class.name()))
                .unwrap();
            assert_eq!(VehicleClass::from_name(class.name()), Some(class));
        }
    }

    #[test]
    fn normal_cdf_matches_tabulated_values() {
        // Phi(1) = 0.841344746, Phi(-1.96) = 0.024997895 (Abramowitz & Stegun 26.2,
        // 9 digits): the tolerances are the table's rounding (5e-10), not the erfc's.
        assert!((normal_cdf(1.0) - 0.841_344_746).abs() < 1e-9);
        assert!((normal_cdf(-1.96) - 0.024_997_895).abs() < 1e-9);
        // erfc(0) = 1 exactly in libm, so Phi(0) is exactly 0.5.
        assert_eq!(normal_cdf(0.0), 0.5);
        // The far tail keeps its relative accuracy: Phi(-8) = 6.22096057e-16 (A&S 26.2.2
        // asymptotics; 1 + erf(-8/sqrt 2) would be 0 or one ulp of 1).
        assert!((normal_cdf(-8.0) / 6.220_960_574e-16 - 1.0).abs() < 1e-9);
    }

    #[test]
    fn a_range_in_kilograms_is_rejected() {
        let mut m = truck_2axle();
        m.weight_min_t = 3_500.0;
        m.weight_max_t = 22_000.0;
        let e = m
            .validate(VehicleClass::Truck2Axle, "traffic.models.truck_2axle")
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("traffic.models.truck_2axle.weight = 0 of"),
            "{e}"
        );
    }
}
