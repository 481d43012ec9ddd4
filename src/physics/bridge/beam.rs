//! The physical beam: its girder (spans, overhangs, supports), flexural rigidity and mass
//! along it, independent of any discretization.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::girder::Girder;
use crate::base::schema as bounds;
use crate::error::{num, require_positive, Error, Result};

/// A straight Euler-Bernoulli girder: spans on supports, optional overhangs.
///
/// `sections` replace the reference EI and mass over parts of the girder (haunches, a
/// heavier span); `stiffness_regions` scale EI over parts of it (damage, stiffening). The
/// models built from it take both into account through the Hermite assembly, so a
/// non-uniform girder needs no other code path.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BeamProperties {
    /// Spans, overhangs and supports.
    pub girder: Girder,
    /// Flexural rigidity EI of the undamaged reference section (N m^2).
    pub flexural_rigidity_n_m2: f64,
    /// Mass per unit length of the reference section (kg/m).
    pub mass_per_length_kg_m: f64,
    /// Segments with their own section, linearly varying between their ends (default:
    /// none, the reference section everywhere).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub sections: Vec<Section>,
    /// Regions where EI is multiplied by a factor (default: none, uniform beam).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub stiffness_regions: Vec<StiffnessRegion>,
}

/// The stiffest spring support accepted, as a multiple of the girder's own stiffness
/// (see `BeamProperties::validate`).
pub const MAX_SPRING_TO_GIRDER: f64 = 1e10;

// Deserialized by hand rather than as an untagged enum, whose only message for a wrong
// shape is "did not match any variant": a list of three values is told a haunch has two.
/// A value constant over a segment, or varying linearly from its start to its end.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, JsonSchema)]
#[serde(untagged)]
pub enum Varying {
    /// The same value over the segment.
    Constant(#[schemars(transform = bounds::positive)] f64),
    /// [at start_m, at end_m], linear between (a haunch).
    Linear(#[schemars(transform = bounds::positive_items)] [f64; 2]),
}

impl<'de> Deserialize<'de> for Varying {
    fn deserialize<D: serde::Deserializer<'de>>(
        deserializer: D,
    ) -> std::result::Result<Self, D::Error> {
        deserializer.deserialize_any(VaryingVisitor)
    }
}

struct VaryingVisitor;

impl<'de> serde::de::Visitor<'de> for VaryingVisitor {
    type Value = Varying;

    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("one number, or [at start, at end] for a haunch")
    }

    fn visit_f64<E: serde::de::Error>(self, v: f64) -> std::result::Result<Varying, E> {
        Ok(Varying::Constant(v))
    }

    fn visit_i64<E: serde::de::Error>(self, v: i64) -> std::result::Result<Varying, E> {
        Ok(Varying::Constant(v as f64))
    }

    fn visit_u64<E: serde::de::Error>(self, v: u64) -> std::result::Result<Varying, E> {
        Ok(Varying::Constant(v as f64))
    }

    fn visit_seq<A: serde::de::SeqAccess<'de>>(
        self,
        mut seq: A,
    ) -> std::result::Result<Varying, A::Error> {
        let mut values = Vec::with_capacity(2);
        while let Some(v) = seq.next_element::<f64>()? {
            values.push(v);
        }
        match values.as_slice() {
            &[start, end] => Ok(Varying::Linear([start, end])),
            _ => Err(serde::de::Error::custom(format_args!(
                "a haunch is [at start, at end]: 2 values, not {}",
                values.len()
            ))),
        }
    }
}

impl Varying {
    /// The value a fraction `t` in [0, 1] along the segment.
    pub fn at(&self, t: f64) -> f64 {
        match *self {
            Varying::Constant(v) => v,
            Varying::Linear([a, b]) => a + (b - a) * t,
        }
    }

    fn ends(&self) -> [f64; 2] {
        match *self {
            Varying::Constant(v) => [v, v],
            Varying::Linear(ends) => ends,
        }
    }
}

/// A segment of the girder with its own section.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Section {
    /// Start of the segment (m from the girder's left end).
    #[schemars(range(min = 0))]
    pub start_m: f64,
    /// End of the segment (m), after `start_m`, on the girder.
    #[schemars(transform = bounds::positive)]
    pub end_m: f64,
    /// EI over the segment (N m^2): one value, or [start, end] for a haunch (default: the
    /// reference EI).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub flexural_rigidity_n_m2: Option<Varying>,
    /// Mass per length over the segment (kg/m): one value or [start, end] (default: the
    /// reference mass).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mass_per_length_kg_m: Option<Varying>,
}

/// Gauss-Legendre points and weights on [-1, 1], 4 points: exact for the piecewise
/// linear sections times piecewise-constant factors integrated between their edges.
pub(super) const GAUSS_4: [(f64, f64); 4] = [
    (-0.861_136_311_594_052_6, 0.347_854_845_137_453_85),
    (-0.339_981_043_584_856_3, 0.652_145_154_862_546_2),
    (0.339_981_043_584_856_3, 0.652_145_154_862_546_2),
    (0.861_136_311_594_052_6, 0.347_854_845_137_453_85),
];

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
        Self::simply_supported(30.0, 5.629e10, 12_000.0)
    }

    /// A uniform simply supported span.
    pub fn simply_supported(span_m: f64, ei_n_m2: f64, mass_per_length_kg_m: f64) -> Self {
        BeamProperties {
            girder: Girder::simply_supported(span_m),
            flexural_rigidity_n_m2: ei_n_m2,
            mass_per_length_kg_m,
            sections: Vec::new(),
            stiffness_regions: Vec::new(),
        }
    }

    /// Total length of the girder, overhangs included (m).
    pub fn length_m(&self) -> f64 {
        self.girder.length_m()
    }

    /// Checks every field; `path` prefixes the field names in errors (e.g. "bridge").
    pub fn validate(&self, path: &str) -> Result<()> {
        self.girder.validate(path)?;
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
            self.check_extent(&p, r.start_m, r.end_m)?;
            require_positive(&format!("{p}.ei_factor"), r.ei_factor)?;
        }
        self.validate_sections(path)?;
        self.check_springs_against_the_girder(path)
    }

    /// A spring many orders stiffer than the girder it holds leaves the girder's own
    /// stiffness below the round-off of the factorization: `1e300` passes every sign check
    /// and then fails (or silently loses the beam) in the solve. Beyond
    /// [`MAX_SPRING_TO_GIRDER`] times the shortest span's `EI / L^3` (vertical) or `EI / L`
    /// (rotational), fewer than 6 of f64's 16 digits are left for the beam; a support that
    /// stiff is rigid, and `"pinned"` or `"fixed"` says so exactly.
    fn check_springs_against_the_girder(&self, path: &str) -> Result<()> {
        let span_m = self
            .girder
            .spans_m
            .iter()
            .copied()
            .fold(f64::INFINITY, f64::min);
        let ei = self.flexural_rigidity_n_m2;
        let girder = [
            ("vertical_n_m", ei / span_m.powi(3), "EI / L^3", "N/m"),
            ("rotational_n_m_rad", ei / span_m, "EI / L", "N m/rad"),
        ];
        for (i, support) in self.girder.supports.iter().enumerate() {
            let (kv, kr) = support.springs();
            for ((name, k_girder, formula, unit), k) in girder.iter().zip([kv, kr]) {
                if k > MAX_SPRING_TO_GIRDER * k_girder {
                    return Err(Error::invalid(
                        format!("{path}.supports.{i}.{name}"),
                        num(k),
                        format!(
                            "is {:.1e} times the girder's {formula} = {k_girder:.3e} {unit} \
                             (at most {MAX_SPRING_TO_GIRDER:e}): the factorization would lose \
                             the girder; a rigid support is \"pinned\" or \"fixed\"",
                            k / k_girder
                        ),
                    ));
                }
            }
        }
        Ok(())
    }

    /// `start_m < end_m`, both on the girder.
    fn check_extent(&self, path: &str, start_m: f64, end_m: f64) -> Result<()> {
        let length = self.length_m();
        let inside = |x: f64| x.is_finite() && (0.0..=length).contains(&x);
        if !inside(start_m) {
            return Err(Error::invalid(
                format!("{path}.start_m"),
                start_m,
                format!("must lie on the girder [0, {length}] m"),
            ));
        }
        if !inside(end_m) || end_m <= start_m {
            return Err(Error::invalid(
                format!("{path}.end_m"),
                end_m,
                format!("must lie in ({start_m}, {length}] m"),
            ));
        }
        Ok(())
    }

    fn validate_sections(&self, path: &str) -> Result<()> {
        let mut sorted: Vec<(usize, &Section)> = self.sections.iter().enumerate().collect();
        sorted.sort_by(|a, b| a.1.start_m.total_cmp(&b.1.start_m));
        for (i, section) in &self.sections.iter().enumerate().collect::<Vec<_>>() {
            let p = format!("{path}.sections.{i}");
            self.check_extent(&p, section.start_m, section.end_m)?;
            for (name, value) in [
                ("flexural_rigidity_n_m2", section.flexural_rigidity_n_m2),
                ("mass_per_length_kg_m", section.mass_per_length_kg_m),
            ] {
                for v in value.iter().flat_map(|v| v.ends()) {
                    require_positive(&format!("{p}.{name}"), v)?;
                }
            }
        }
        for pair in sorted.windows(2) {
            if pair[1].1.start_m < pair[0].1.end_m {
                return Err(Error::invalid(
                    format!("{path}.sections.{}.start_m", pair[1].0),
                    pair[1].1.start_m,
                    format!(
                        "overlaps sections.{} (which ends at {} m)",
                        pair[0].0, pair[0].1.end_m
                    ),
                ));
            }
        }
        Ok(())
    }

    /// True when EI and mass are the same everywhere (the closed-form flexibility applies).
    pub fn is_uniform(&self) -> bool {
        self.sections.is_empty() && self.stiffness_regions.iter().all(|r| r.ei_factor == 1.0)
    }

    /// The section covering `x_m`, and the fraction along it.
    fn section_at(&self, x_m: f64) -> Option<(&Section, f64)> {
        self.sections
            .iter()
            .find(|s| (s.start_m..=s.end_m).contains(&x_m))
            .map(|s| (s, (x_m - s.start_m) / (s.end_m - s.start_m)))
    }

    /// EI of the undamaged section at `x_m` (N m^2), before the stiffness regions.
    fn section_ei_n_m2(&self, x_m: f64) -> f64 {
        match self.section_at(x_m) {
            Some((s, t)) => s
                .flexural_rigidity_n_m2
                .map_or(self.flexural_rigidity_n_m2, |v| v.at(t)),
            None => self.flexural_rigidity_n_m2,
        }
    }

    /// Mass per length at `x_m` (kg/m).
    pub fn mass_at_kg_m(&self, x_m: f64) -> f64 {
        match self.section_at(x_m) {
            Some((s, t)) => s
                .mass_per_length_kg_m
                .map_or(self.mass_per_length_kg_m, |v| v.at(t)),
            None => self.mass_per_length_kg_m,
        }
    }

    /// The integral of `f` over [a, b], by 4-point Gauss between the edges of every
    /// section and region (exact for the linear sections times constant factors).
    fn integrate(&self, a_m: f64, b_m: f64, f: impl Fn(f64) -> f64) -> f64 {
        let mut edges: Vec<f64> = self
            .sections
            .iter()
            .flat_map(|s| [s.start_m, s.end_m])
            .chain(
                self.stiffness_regions
                    .iter()
                    .flat_map(|r| [r.start_m, r.end_m]),
            )
            .filter(|&x| x > a_m && x < b_m)
            .chain([a_m, b_m])
            .collect();
        edges.sort_by(f64::total_cmp);
        edges
            .windows(2)
            .map(|w| {
                let (mid, half) = (0.5 * (w[0] + w[1]), 0.5 * (w[1] - w[0]));
                GAUSS_4
                    .iter()
                    .map(|(s, weight)| weight * half * f(mid + half * s))
                    .sum::<f64>()
            })
            .sum()
    }

    /// Mean mass per length over [a, b] (kg/m).
    pub fn mean_mass_kg_m(&self, a_m: f64, b_m: f64) -> f64 {
        if self.sections.is_empty() {
            return self.mass_per_length_kg_m;
        }
        self.integrate(a_m, b_m, |x| self.mass_at_kg_m(x)) / (b_m - a_m)
    }

    /// Mass over [a, b] (kg).
    pub fn mass_between_kg(&self, a_m: f64, b_m: f64) -> f64 {
        if b_m <= a_m {
            return 0.0;
        }
        self.mean_mass_kg_m(a_m, b_m) * (b_m - a_m)
    }

    /// Mean EI over [a, b] (exact for the piecewise-constant regions). Where regions
    /// overlap their factors multiply, as in [`Self::ei_at_n_m2`].
    pub fn mean_ei_n_m2(&self, a_m: f64, b_m: f64) -> f64 {
        if !self.sections.is_empty() {
            return self.integrate(a_m, b_m, |x| self.ei_at_n_m2(x)) / (b_m - a_m);
        }
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
        self.section_ei_n_m2(x_m) * factor
    }

    /// Total mass (kg).
    pub fn total_mass_kg(&self) -> f64 {
        self.mass_between_kg(0.0, self.length_m())
    }

    /// Closed-form f_n of the uniform simply supported beam with the longest span and the
    /// reference section (Hz), docs/physics.md section 1: exact for the paper's single
    /// span, the scale of the fundamental for any other girder (for example the lowest
    /// mode of equal continuous spans, whose pier is a node of it).
    pub fn closed_form_frequency_hz(&self, n: usize) -> f64 {
        let nf = n as f64;
        let span = self.girder.longest_span_m();
        nf * nf * std::f64::consts::PI / (2.0 * span * span)
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
        beam.girder.spans_m[0] = -1.0;
        let msg = beam.validate("bridge").unwrap_err().to_string();
        assert!(
            msg.contains("bridge.spans_m.0") && msg.contains("-1"),
            "{msg}"
        );
        beam.girder.spans_m[0] = 30.0;
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
