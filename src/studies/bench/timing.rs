//! Wall-clock timing with `std::time::Instant`: warm up, size the repetitions from the
//! warm-up, take the median (robust to the odd preempted repetition on a shared machine).

use std::time::{Duration, Instant};

/// How long and how often to measure.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TimingPlan {
    /// Repetitions whose median is reported.
    pub repetitions: usize,
    /// Aimed wall time of one repetition (s).
    pub target_rep_s: f64,
    /// Steps timed per repetition at least ("a few steps" for the slow direct method).
    pub min_steps: u64,
    /// Steps per repetition at most.
    pub max_steps: u64,
    /// When one step takes longer than this (s), only `slow_repetitions` are done.
    pub slow_step_s: f64,
    pub slow_repetitions: usize,
}

impl TimingPlan {
    /// The plan of `bridgetwin bench` (`quick`: fewer and shorter repetitions).
    pub fn for_bench(quick: bool) -> Self {
        TimingPlan {
            repetitions: if quick { 5 } else { 9 },
            target_rep_s: if quick { 0.01 } else { 0.05 },
            min_steps: 2,
            max_steps: 20_000,
            slow_step_s: 0.02,
            slow_repetitions: 3,
        }
    }
}

/// The per-step time of one measurement.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepTiming {
    /// Median over the repetitions of (repetition time / steps) (s).
    pub median_step_s: f64,
    /// Smallest and largest per-step time over the repetitions (s).
    pub min_step_s: f64,
    pub max_step_s: f64,
    pub steps_per_rep: u64,
    pub repetitions: usize,
}

/// Median of `values` (the mean of the middle two for an even count).
pub fn median(values: &[f64]) -> f64 {
    let mut v = values.to_vec();
    v.sort_by(f64::total_cmp);
    let n = v.len();
    match n {
        0 => f64::NAN,
        _ if n % 2 == 1 => v[n / 2],
        _ => 0.5 * (v[n / 2 - 1] + v[n / 2]),
    }
}

/// Times `time(steps)` (which runs and times `steps` steps): one warm-up call of
/// `min_steps` steps (first-touch allocations, caches), a second warm-up sized to a
/// tenth of a repetition, then the repetitions.
pub fn time_per_step(plan: &TimingPlan, mut time: impl FnMut(u64) -> Duration) -> StepTiming {
    let first = time(plan.min_steps).as_secs_f64() / plan.min_steps as f64;
    let probe_steps = steps_for(plan, 0.1 * plan.target_rep_s, first);
    let estimate = time(probe_steps).as_secs_f64() / probe_steps as f64;
    let steps = steps_for(plan, plan.target_rep_s, estimate);
    let repetitions = if estimate > plan.slow_step_s {
        plan.slow_repetitions
    } else {
        plan.repetitions
    };
    let per_step: Vec<f64> = (0..repetitions.max(1))
        .map(|_| time(steps).as_secs_f64() / steps as f64)
        .collect();
    StepTiming {
        median_step_s: median(&per_step),
        min_step_s: per_step.iter().copied().fold(f64::INFINITY, f64::min),
        max_step_s: per_step.iter().copied().fold(0.0, f64::max),
        steps_per_rep: steps,
        repetitions: per_step.len(),
    }
}

fn steps_for(plan: &TimingPlan, wall_s: f64, step_s: f64) -> u64 {
    let steps = (wall_s / step_s.max(1e-9)).round() as u64;
    steps.clamp(plan.min_steps, plan.max_steps)
}

/// Median wall time of `repetitions` calls of `run`, after one warm-up call (s).
pub fn median_wall_s(repetitions: usize, mut run: impl FnMut()) -> f64 {
    run();
    let times: Vec<f64> = (0..repetitions.max(1))
        .map(|_| {
            let start = Instant::now();
            run();
            start.elapsed().as_secs_f64()
        })
        .collect();
    median(&times)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_of_odd_and_even_counts() {
        assert_eq!(median(&[3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(&[4.0, 1.0, 3.0, 2.0]), 2.5);
        assert!(median(&[]).is_nan());
    }

    #[test]
    fn slow_steps_get_few_short_repetitions() {
        // A fake step of 50 ms: the plan falls back to the minimum of steps and the few
        // repetitions of the slow case, and the median is the fake step time.
        let plan = TimingPlan::for_bench(true);
        let mut calls = Vec::new();
        let t = time_per_step(&plan, |steps| {
            calls.push(steps);
            Duration::from_millis(50 * steps)
        });
        assert_eq!(t.steps_per_rep, plan.min_steps);
        assert_eq!(t.repetitions, plan.slow_repetitions);
        assert_eq!(calls.len(), 2 + plan.slow_repetitions);
        assert!((t.median_step_s - 0.05).abs() < 1e-12);
    }

    #[test]
    fn fast_steps_fill_the_target_time() {
        let plan = TimingPlan::for_bench(false);
        let t = time_per_step(&plan, |steps| Duration::from_micros(5 * steps));
        assert_eq!(t.steps_per_rep, 10_000);
        assert_eq!(t.repetitions, plan.repetitions);
    }
}
