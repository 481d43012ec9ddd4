//! What the scenario tables of the pitch-plane vehicles (`half_car`, `rigid_truck`,
//! `articulated`) share: the per-axle arrays, the preset-override rule and the checks
//! whose errors name the field.
//!
//! Serde cannot combine `#[serde(flatten)]` with `deny_unknown_fields`, so the shared
//! fields cannot live in a flattened struct without giving up strict keys. Instead
//! [`pitch_plane_spec!`] writes them once and expands them into each spec: every spec is
//! a plain `deny_unknown_fields` struct whose unknown keys are rejected by name.

use super::models::AxleParams;
use crate::error::{num, require_non_negative, require_positive, Error, Result};

/// Declares the scenario table of a pitch-plane vehicle: the fields given (each an
/// `Option`, so that a preset can fill it), then the per-axle arrays every such vehicle
/// has (front first, one entry per axle, of type `$axles`). Also generates
///
/// - `overriding(&self, base)`: each field given here, else `base`'s (a preset's);
/// - `axle_arrays(&self)`: the arrays by field name, for [`validated_axles`];
/// - `with_axle_arrays(self, arrays)`: the arrays set, for the presets.
macro_rules! pitch_plane_spec {
    (
        $(#[$meta:meta])*
        pub struct $name:ident, axle arrays of $axles:ty {
            $( $(#[$field_doc:meta])* pub $field:ident: Option<$ty:ty>, )+
        }
    ) => {
        $(#[$meta])*
        #[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
        #[serde(deny_unknown_fields)]
        pub struct $name {
            $(
                $(#[$field_doc])*
                #[serde(default, skip_serializing_if = "Option::is_none")]
                pub $field: Option<$ty>,
            )+
            // The bounds mirror AXLE_ARRAY_CHECKS.
            /// Unsprung mass per axle (kg), each > 0.
            #[serde(default, skip_serializing_if = "Option::is_none")]
            #[schemars(transform = $crate::base::schema::positive_items)]
            pub axle_mass_kg: Option<$axles>,
            /// Suspension stiffness per axle (N/m), each > 0.
            #[serde(default, skip_serializing_if = "Option::is_none")]
            #[schemars(transform = $crate::base::schema::positive_items)]
            pub suspension_stiffness_n_m: Option<$axles>,
            /// Suspension damping per axle (N s/m), each >= 0.
            #[serde(default, skip_serializing_if = "Option::is_none")]
            #[schemars(transform = $crate::base::schema::non_negative_items)]
            pub suspension_damping_n_s_m: Option<$axles>,
            /// Tyre stiffness per axle, all its tyres together (N/m), each > 0.
            #[serde(default, skip_serializing_if = "Option::is_none")]
            #[schemars(transform = $crate::base::schema::positive_items)]
            pub tyre_stiffness_n_m: Option<$axles>,
            /// Tyre damping per axle, all its tyres together (N s/m), each >= 0.
            #[serde(default, skip_serializing_if = "Option::is_none")]
            #[schemars(transform = $crate::base::schema::non_negative_items)]
            pub tyre_damping_n_s_m: Option<$axles>,
        }

        impl $name {
            /// Each field given here, else `base`'s (fields next to a preset override it).
            fn overriding(&self, base: $name) -> $name {
                $name {
                    $( $field: self.$field.clone().or(base.$field), )+
                    axle_mass_kg: self.axle_mass_kg.clone().or(base.axle_mass_kg),
                    suspension_stiffness_n_m: self
                        .suspension_stiffness_n_m
                        .clone()
                        .or(base.suspension_stiffness_n_m),
                    suspension_damping_n_s_m: self
                        .suspension_damping_n_s_m
                        .clone()
                        .or(base.suspension_damping_n_s_m),
                    tyre_stiffness_n_m: self.tyre_stiffness_n_m.clone().or(base.tyre_stiffness_n_m),
                    tyre_damping_n_s_m: self.tyre_damping_n_s_m.clone().or(base.tyre_damping_n_s_m),
                }
            }

            /// The per-axle arrays by field name, in the order [`validated_axles`] checks.
            fn axle_arrays(&self) -> $crate::physics::vehicle::pitch_plane_spec::AxleArrays<'_> {
                [
                    ("axle_mass_kg", self.axle_mass_kg.as_ref().map(|a| &a[..])),
                    (
                        "suspension_stiffness_n_m",
                        self.suspension_stiffness_n_m.as_ref().map(|a| &a[..]),
                    ),
                    (
                        "suspension_damping_n_s_m",
                        self.suspension_damping_n_s_m.as_ref().map(|a| &a[..]),
                    ),
                    ("tyre_stiffness_n_m", self.tyre_stiffness_n_m.as_ref().map(|a| &a[..])),
                    ("tyre_damping_n_s_m", self.tyre_damping_n_s_m.as_ref().map(|a| &a[..])),
                ]
            }

            /// This spec with the per-axle arrays `[mass, suspension stiffness, suspension
            /// damping, tyre stiffness, tyre damping]`.
            fn with_axle_arrays(self, [m, ks, cs, kt, ct]: [$axles; 5]) -> Self {
                Self {
                    axle_mass_kg: Some(m),
                    suspension_stiffness_n_m: Some(ks),
                    suspension_damping_n_s_m: Some(cs),
                    tyre_stiffness_n_m: Some(kt),
                    tyre_damping_n_s_m: Some(ct),
                    ..self
                }
            }
        }
    };
}
pub(crate) use pitch_plane_spec;

/// The per-axle arrays of a spec by field name, each `None` when neither the spec nor its
/// preset gives it.
pub(crate) type AxleArrays<'a> = [(&'static str, Option<&'a [f64]>); 5];

/// The check of each array of [`AxleArrays`]: masses and stiffnesses > 0, dampings >= 0.
const AXLE_ARRAY_CHECKS: [fn(&str, f64) -> Result<f64>; 5] = [
    require_positive,
    require_positive,
    require_non_negative,
    require_positive,
    require_non_negative,
];

/// The `n` axles of `arrays`, every array checked for presence, length and sign; errors
/// name `{path}.{field}` or `{path}.{field}.{i}`.
pub(crate) fn validated_axles(path: &str, n: usize, arrays: AxleArrays) -> Result<Vec<AxleParams>> {
    let mut checked: Vec<&[f64]> = Vec::with_capacity(arrays.len());
    for ((name, values), check) in arrays.into_iter().zip(AXLE_ARRAY_CHECKS) {
        checked.push(per_axle(values, &format!("{path}.{name}"), n, check)?);
    }
    Ok((0..n)
        .map(|j| AxleParams {
            mass_kg: checked[0][j],
            suspension_stiffness_n_m: checked[1][j],
            suspension_damping_n_s_m: checked[2][j],
            tyre_stiffness_n_m: checked[3][j],
            tyre_damping_n_s_m: checked[4][j],
        })
        .collect())
}

/// A per-axle array of `n` entries, each passing `check`.
fn per_axle<'a>(
    values: Option<&'a [f64]>,
    field: &str,
    n: usize,
    check: fn(&str, f64) -> Result<f64>,
) -> Result<&'a [f64]> {
    let values = required(values, field)?;
    if values.len() != n {
        return Err(Error::invalid(
            field,
            format!("{values:?}"),
            format!("must have {n} entries, one per axle (axle_spacing_m gives {n} axles)"),
        ));
    }
    for (i, &v) in values.iter().enumerate() {
        check(&format!("{field}.{i}"), v)?;
    }
    Ok(values)
}

/// Model name for the truth records: `kind/preset`, or `kind` without a preset.
pub(crate) fn named(kind: &str, preset: &Option<String>) -> String {
    match preset {
        Some(p) => format!("{kind}/{p}"),
        None => kind.to_string(),
    }
}

/// The preset `name` of a kind whose presets are `known`, through `lookup`; `None` without
/// a name.
pub(crate) fn preset_or_default<T: Default>(
    path: &str,
    name: &Option<String>,
    known: &[&str],
    lookup: impl Fn(&str) -> Option<T>,
) -> Result<T> {
    match name {
        Some(name) => lookup(name).ok_or_else(|| {
            Error::invalid(
                format!("{path}.preset"),
                format!("\"{name}\""),
                format!("is not a preset; known: {}", known.join(", ")),
            )
        }),
        None => Ok(T::default()),
    }
}

/// `value`, or an error naming `field` when neither the spec nor its preset gives it.
pub(crate) fn required<T>(value: Option<T>, field: &str) -> Result<T> {
    value.ok_or_else(|| Error::invalid(field, "(missing)", "is required when no preset gives it"))
}

/// A required value > 0.
pub(crate) fn positive(value: Option<f64>, field: &str) -> Result<f64> {
    require_positive(field, required(value, field)?)
}

/// `value` in `[lo, hi]` m; the error says it must lie between `between`.
pub(crate) fn require_within(
    field: &str,
    value: f64,
    lo: f64,
    hi: f64,
    between: &str,
) -> Result<f64> {
    if value.is_finite() && (lo..=hi).contains(&value) {
        Ok(value)
    } else {
        Err(Error::invalid(
            field,
            num(value),
            format!("must lie between {between}, in [{lo}, {hi}] m"),
        ))
    }
}
