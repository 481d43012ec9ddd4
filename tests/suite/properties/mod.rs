//! Property tests:
//!
//! 1. random valid scenarios: resolve never panics; a resolved scenario runs to the end
//!    (a `Divergence` fails the property: the scenarios are valid), every f64 of every
//!    record is finite, and a second run gives the same records;
//! 2. random byte strings, random TOML-like text and mutations of the default scenario:
//!    `Scenario::from_toml` and `resolve` return Ok or Err, never panic;
//! 3. matrix invariants of random beams for the three discretizations: symmetric,
//!    positive definite M and K, positive ascending frequencies, f1 within the known
//!    accuracy of the closed form; EI reduced over regions keeps all that and lowers f1.
//!
//! One file per family: `scenarios` (1), `text` (2), `matrices` (3); the strategies both
//! 1 and 3 draw from are here.

mod matrices;
mod scenarios;
mod text;

use std::f64::consts::PI;

use proptest::prelude::*;

use bridgetwin::physics::bridge::{LumpedStiffness, ModelSpec};

/// `default_cases` cases, unless `PROPTEST_CASES` asks for another count (a longer hunt:
/// `PROPTEST_CASES=2000 cargo test --test suite properties::`).
pub(super) fn config(default_cases: u32) -> ProptestConfig {
    let mut config = ProptestConfig::default();
    if std::env::var_os("PROPTEST_CASES").is_none() {
        config.cases = default_cases;
    }
    config
}

pub(super) fn model_strategy() -> impl Strategy<Value = ModelSpec> {
    prop_oneof![
        (5usize..=60).prop_map(|nodes| ModelSpec::LumpedMass {
            nodes,
            stiffness: LumpedStiffness::Auto,
        }),
        (4usize..=40).prop_map(|elements| ModelSpec::FiniteElement { elements }),
        (1usize..=20, proptest::option::of(0usize..=20)).prop_map(|(modes, extra)| {
            ModelSpec::Modal {
                modes,
                elements: extra.map(|e| 2 * modes + e),
            }
        }),
    ]
}

/// (span, mass per length, f1): f1 is drawn log-uniformly in a band that follows the
/// usual f1 ~ 100 / L (Hz, L in m) of road bridges, clipped to 1-20 Hz; EI follows.
pub(super) fn beam_strategy() -> impl Strategy<Value = (f64, f64, f64)> {
    (5.0f64..=80.0, 2_000.0f64..=30_000.0, 0.0f64..=1.0).prop_map(|(span, mass, u)| {
        let lo = (30.0 / span).max(1.0);
        let hi = (300.0 / span).min(20.0);
        let f1 = lo * (hi / lo).powf(u);
        (span, mass, f1)
    })
}

/// EI of a uniform beam with first frequency `f1_hz`: f1 = (pi / 2) sqrt(EI / m) / L^2.
pub(super) fn ei_for(span_m: f64, mass_kg_m: f64, f1_hz: f64) -> f64 {
    mass_kg_m * (2.0 * f1_hz * span_m * span_m / PI).powi(2)
}
