//! What a continuous girder costs per coupled step: the three-span example against the
//! paper's single span, both with 150 Hermite elements (banded FE, the truck on the
//! girder), timed alternately in one run so that the machine's load falls on both.

use serde::Serialize;

use super::setup::{path_timer, truck, BenchPath};
use super::timing::{median, time_per_step, TimingPlan};
use crate::error::Result;
use crate::physics::bridge::{BeamProperties, BridgeModel, ModelSpec};
use crate::studies::continuous::example_beam;

/// Elements of both models.
pub const ELEMENTS: usize = 150;

/// The two per-step times and their ratio.
#[derive(Debug, Clone, Serialize)]
pub struct GirderCost {
    pub elements: usize,
    /// Medians over the rounds of each round's median (us).
    pub single_span_us: f64,
    pub three_span_us: f64,
    /// three_span_us / single_span_us (target <= 1.5).
    pub ratio: f64,
    pub rounds: usize,
}

/// Times both models `rounds` times, alternately, with `plan`.
pub fn measure(plan: &TimingPlan, rounds: usize) -> Result<GirderCost> {
    let vehicle = truck()?;
    let spec = ModelSpec::FiniteElement { elements: ELEMENTS };
    let single = BridgeModel::build(&BeamProperties::paper_default(), &spec, 0.02)?;
    let three = BridgeModel::build(&example_beam()?, &spec, 0.02)?;
    let (mut a, mut b) = (Vec::new(), Vec::new());
    for _ in 0..rounds.max(1) {
        a.push(
            time_per_step(plan, path_timer(BenchPath::FeBanded, &single, &vehicle)).median_step_s,
        );
        b.push(
            time_per_step(plan, path_timer(BenchPath::FeBanded, &three, &vehicle)).median_step_s,
        );
    }
    let (single_span_us, three_span_us) = (1e6 * median(&a), 1e6 * median(&b));
    Ok(GirderCost {
        elements: ELEMENTS,
        single_span_us,
        three_span_us,
        ratio: three_span_us / single_span_us,
        rounds: rounds.max(1),
    })
}
