//! The physical beam: span, flexural rigidity and mass, independent of any discretization.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::base::schema as bounds;
use crate::error::{require_positive, Error, Result};

/// A simply supported Euler-Bernoulli beam.
///
/// `stiffness_regions` scale EI over parts of the span (damage, stiffening); the models
/// built from it take them into account through the Hermite assembly, so a non-uniform
/// beam needs no other code path.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BeamProperties {
    /// Span between the supports (m).
    pub span_m: f64,
    /// Flexural rigidity EI of the undamaged section (N m^2).
    pub flexural_rigidity_n_m2: f64,
    /// Mass per unit length (kg/m).
    pub mass_per_length_kg_m: f64,
    /// Regions where EI is multiplied by a factor (default: none, uniform beam).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub stiffness_regions: Vec<StiffnessRegion>,
}

/// EI multiplied by `ei_factor` for `start_m <= x <= end_m`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct StiffnessRegion {
    /// Start of the region (m from the left support), on the span.
    #[schemars(range(min = 0))]
    pub start_m: f64,
    /// End of the region (m), after `start_m`, on the span.
    #[schemars(transform = bounds::positive)]
    pub end_m: f64,
    /// Factor on EI in the region, > 0; in (0, 1] for damage.
    #[schemars(transform = bounds::positive)]
    pub ei_factor: f64,
}

impl BeamProperties {
    /// The paper's 30 m bridge: f1 = 3.78 Hz (docs/physics.md section 1).
    pub fn paper_default() -> Self {
        BeamProperties {
            span_m: 30.0,
            flexural_rigidity_n_m2: 5.629e10,
            mass_per_length_kg_m: 12_000.0,
            stiffness_regions: Vec::new(),
        }
    }

    /// Checks every field; `path` prefixes the field names in errors (e.g. "bridge").
    pub fn validate(&self, path: &str) -> Result<()> {
        require_positive(&format!("{path}.span_m"), self.span_m)?;
        require_positive(
            &format!("{path}.flexural_rigidity_n_m2"),
            self.flexural_rigidity_n_m2,
        )?;
        require_positive(
            &format!("{path}.mass_per_length_kg_m"),
            self.mass_per_length_kg_m,
        )?;
        for (i, r) in self.stiffness_regions.iter().enumerate() {
            let p = format!("{path}.stiffness_regions.{i}");
            let inside = |x: f64| x.is_finite() && (0.0..=self.span_m).contains(&x);
            if !inside(r.start_m) {
                return Err(Error::invalid(
                    format!("{p}.start_m"),
                    r.start_m,
                    format!("must lie on the span [0, {}] m", self.span_m),
                ));
            }
            if !inside(r.end_m) || r.end_m <= r.start_m {
                return Err(Error::invalid(
                    format!("{p}.end_m"),
                    r.end_m,
                    format!("must lie in ({}, {}] m", r.start_m, self.span_m),
                ));
            }
            require_positive(&format!("{p}.ei_factor"), r.ei_factor)?;
        }
        Ok(())
    }

    /// True when EI is the same everywhere (closed-form flexibility applies).
    pub fn is_uniform(&self) -> bool {
        self.stiffness_regions.iter().all(|r| r.ei_factor == 1.0)
    }

    /// Mean EI over [a, b] (exact for the piecewise-constant regions). Where regions
    /// overlap their factors multiply, as in [`Self::ei_at_n_m2`].
    pub fn mean_ei_n_m2(&self, a_m: f64, b_m: f64) -> f64 {
        let length = b_m - a_m;
        // The factor is constant between consecutive region edges: integrate it there.
        let mut edges: Vec<f64> = self
            .stiffness_regions
            .iter()
            .flat_map(|r| [r.start_m, r.end_m])
            .filter(|&x| x > a_m && x < b_m)
            .chain([a_m, b_m])
            .collect();
        edges.sort_by(f64::total_cmp);
        let factor_integral: f64 = edges
            .windows(2)
            .map(|w| {
                let mid = 0.5 * (w[0] + w[1]);
                let factor: f64 = self
                    .stiffness_regions
                    .iter()
                    .filter(|r| (r.start_m..=r.end_m).contains(&mid))
                    .map(|r| r.ei_factor)
                    .product();
                (w[1] - w[0]) * factor
            })
            .sum();
        self.flexural_rigidity_n_m2 * factor_integral / length
    }

    /// EI at a point (N m^2).
    pub fn ei_at_n_m2(&self, x_m: f64) -> f64 {
        let factor: f64 = self
            .stiffness_regions
            .iter()
            .filter(|r| (r.start_m..=r.end_m).contains(&x_m))
            .map(|r| r.ei_factor)
            .product();
        self.flexural_rigidity_n_m2 * factor
    }

    /// Total mass (kg).
    pub fn total_mass_kg(&self) -> f64 {
        self.mass_per_length_kg_m * self.span_m
    }

    /// Closed-form f_n of the uniform simply supported beam (Hz), docs/physics.md section 1.
    pub fn closed_form_frequency_hz(&self, n: usize) -> f64 {
        let nf = n as f64;
        nf * nf * std::f64::consts::PI / (2.0 * self.span_m * self.span_m)
            * (self.flexural_rigidity_n_m2 / self.mass_per_length_kg_m).sqrt()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paper_beam_has_f1_3_78_hz() {
        let beam = BeamProperties::paper_default();
        // docs/physics.md: f1 3.780, f2 15.12, f3 34.02 Hz (4 significant digits).
        assert!((beam.closed_form_frequency_hz(1) - 3.780).abs() < 5e-4);
        assert!((beam.closed_form_frequency_hz(2) - 15.12).abs() < 5e-3);
        assert!((beam.closed_form_frequency_hz(3) - 34.02).abs() < 5e-3);
    }

    #[test]
    fn validation_names_the_field() {
        let mut beam = BeamProperties::paper_default();
        beam.span_m = -1.0;
        let msg = beam.validate("bridge").unwrap_err().to_string();
        assert!(msg.contains("bridge.span_m") && msg.contains("-1"), "{msg}");
        beam.span_m = 30.0;
        beam.mass_per_length_kg_m = f64::NAN;
        let msg = beam.validate("bridge").unwrap_err().to_string();
        assert!(msg.contains("bridge.mass_per_length_kg_m"), "{msg}");
    }

    #[test]
    fn mean_ei_over_partial_region() {
        let mut beam = BeamProperties::paper_default();
        beam.stiffness_regions.push(StiffnessRegion {
            start_m: 10.0,
            end_m: 12.0,
            ei_factor: 0.5,
        });
        let ei = beam.flexural_rigidity_n_m2;
        assert!((beam.mean_ei_n_m2(11.0, 13.0) - 0.75 * ei).abs() < 1e-3 * ei);
        assert_eq!(beam.ei_at_n_m2(11.0), 0.5 * ei);
        assert!(!beam.is_uniform());
    }

    #[test]
    fn mean_ei_multiplies_overlapping_factors() {
        // Two regions with factor 0.3 over [10, 12] and [11, 14]: 0.09 on [11, 12].
        let mut beam = BeamProperties::paper_default();
        for (start_m, end_m) in [(10.0, 12.0), (11.0, 14.0)] {
            beam.stiffness_regions.push(StiffnessRegion {
                start_m,
                end_m,
                ei_factor: 0.3,
            });
        }
        let ei = beam.flexural_rigidity_n_m2;
        assert!((beam.ei_at_n_m2(11.5) - 0.09 * ei).abs() < 1e-9 * ei);
        // [9, 15]: 1 + 0.3 + 0.09 + 0.3 * 2 + 1 = 2.99 over 6 m.
        assert!((beam.mean_ei_n_m2(9.0, 15.0) - 2.99 / 6.0 * ei).abs() < 1e-12 * ei);
        assert!((beam.mean_ei_n_m2(11.25, 11.75) - 0.09 * ei).abs() < 1e-12 * ei);
        assert_eq!(beam.mean_ei_n_m2(20.0, 21.0), ei);
    }
}
