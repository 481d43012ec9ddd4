//! Packet loss as runs of lost samples: independent (Bernoulli) or bursty (Gilbert-Elliott).
//!
//! Gilbert-Elliott (Gilbert 1960, Elliott 1963), the simplified form where every sample of
//! the bad state B is lost and none of the good state G: a two-state Markov chain per
//! sample with transition probabilities `p_gb = P(G -> B)` and `p_bg = P(B -> G)`.
//! - A bad sojourn is geometric on `{1, 2, ...}` with mean `1 / p_bg`, so a mean burst of
//!   `B` samples gives `p_bg = 1 / B`.
//! - The stationary probability of B, the long-run loss rate, is
//!   `pi_B = p_gb / (p_gb + p_bg) = p`, so `p_gb = p p_bg / (1 - p) = p / (B (1 - p))`.
//! - `p_gb <= 1` requires `p <= B / (1 + B)`.
//!
//! The chain is simulated by its sojourns: alternate geometric good and bad spell lengths,
//! drawn at the start of each spell. This is the same process (sojourns of a Markov chain
//! are independent geometrics) and it knows each burst's length when the burst begins, so
//! the burst's label can be written before its first lost sample. The chain starts in its
//! stationary law (bad with probability `p`); memorylessness makes the first spell's
//! remaining length geometric too. Random loss is the same machinery with runs of one
//! sample and geometric gaps (failures before a success of probability `p`), so neither
//! model draws a number per kept sample.

use rand::RngExt;
use rand_chacha::ChaCha8Rng;

use super::draws::failures_before_success;
use super::fault_spec::LossSpec;

/// What happens to one sample.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum LossStep {
    /// Delivered.
    Kept,
    /// Lost, inside a run already announced.
    Lost,
    /// Lost, first sample of a run of `samples` lost samples.
    RunStarts { samples: u64 },
}

#[derive(Debug, Clone, Copy)]
enum Model {
    /// Runs of one sample, gaps of `failures_before_success(p)` samples.
    Random { probability: f64 },
    /// Good spells `Geo(p_good_to_bad)`, bad spells `Geo(p_bad_to_good)`, on `{1, 2, ...}`.
    Bursty {
        p_good_to_bad: f64,
        p_bad_to_good: f64,
    },
}

/// Transition probabilities `(p_gb, p_bg)` of the Gilbert-Elliott chain with long-run loss
/// `probability` and mean burst `mean_burst_samples` (module doc).
pub fn gilbert_elliott_transitions(probability: f64, mean_burst_samples: f64) -> (f64, f64) {
    let p_bad_to_good = 1.0 / mean_burst_samples;
    let p_good_to_bad = probability * p_bad_to_good / (1.0 - probability);
    (p_good_to_bad, p_bad_to_good)
}

/// The loss process of one channel, over sample indices `k = 0, 1, ...`.
#[derive(Debug, Clone)]
pub(crate) struct LossProcess {
    model: Model,
    rng: ChaCha8Rng,
    /// First sample of the current or next run.
    run_start: u64,
    /// One past its last sample.
    run_end: u64,
}

impl LossProcess {
    /// The process for a validated `spec`.
    pub(crate) fn new(spec: &LossSpec, mut rng: ChaCha8Rng) -> Self {
        let model = match *spec {
            LossSpec::Random { probability } => Model::Random { probability },
            LossSpec::Bursty {
                probability,
                mean_burst_samples,
            } => {
                let (p_good_to_bad, p_bad_to_good) =
                    gilbert_elliott_transitions(probability, mean_burst_samples);
                Model::Bursty {
                    p_good_to_bad,
                    p_bad_to_good,
                }
            }
        };
        let run_start = match model {
            Model::Random { probability } => failures_before_success(&mut rng, probability),
            Model::Bursty { p_good_to_bad, .. } => {
                let stationary_bad = spec.probability();
                if rng.random::<f64>() < stationary_bad {
                    0
                } else {
                    spell(&mut rng, p_good_to_bad)
                }
            }
        };
        let mut process = Self {
            model,
            rng,
            run_start,
            run_end: run_start,
        };
        process.run_end = run_start.saturating_add(process.run_length());
        process
    }

    /// Whether this is a burst model (labels of kind `loss_burst`).
    pub(crate) fn is_bursty(&self) -> bool {
        matches!(self.model, Model::Bursty { .. })
    }

    /// The fate of sample `k`; call for every `k` in increasing order.
    pub(crate) fn step(&mut self, k: u64) -> LossStep {
        while k >= self.run_end {
            self.schedule_next_run();
        }
        if k < self.run_start {
            LossStep::Kept
        } else if k == self.run_start {
            LossStep::RunStarts {
                samples: self.run_end - self.run_start,
            }
        } else {
            LossStep::Lost
        }
    }

    fn schedule_next_run(&mut self) {
        let gap = match self.model {
            Model::Random { probability } => failures_before_success(&mut self.rng, probability),
            Model::Bursty { p_good_to_bad, .. } => spell(&mut self.rng, p_good_to_bad),
        };
        self.run_start = self.run_end.saturating_add(gap);
        self.run_end = self.run_start.saturating_add(self.run_length());
    }

    fn run_length(&mut self) -> u64 {
        match self.model {
            Model::Random { .. } => 1,
            Model::Bursty { p_bad_to_good, .. } => spell(&mut self.rng, p_bad_to_good),
        }
    }
}

/// A sojourn of a Markov chain state left with probability `p_leave` per step: geometric
/// on `{1, 2, ...}`, mean `1 / p_leave`.
fn spell(rng: &mut ChaCha8Rng, p_leave: f64) -> u64 {
    failures_before_success(rng, p_leave).saturating_add(1)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    #[test]
    fn transitions_reproduce_the_stationary_loss_and_mean_burst() {
        // Closed forms of the two-state chain, evaluated independently of the derivation.
        let (p_gb, p_bg) = gilbert_elliott_transitions(0.02, 20.0);
        assert!((p_gb / (p_gb + p_bg) - 0.02).abs() < 1e-15);
        assert!((1.0 / p_bg - 20.0).abs() < 1e-12);
    }

    #[test]
    fn a_sample_by_sample_markov_chain_gives_the_same_statistics() {
        // Cross-check the sojourn simulation against the per-sample chain with the same
        // transitions. Loss fractions over 1e6 samples, p = 0.1, B = 5: lag-1 correlation
        // rho = 1 - p_gb - p_bg = 0.778, variance inflation (1 + rho) / (1 - rho) = 8,
        // SE = sqrt(0.09 * 8 / 1e6) = 8.5e-4 each; the two differ by < 5 SE of the
        // difference, 6e-3.
        let spec = LossSpec::Bursty {
            probability: 0.1,
            mean_burst_samples: 5.0,
        };
        let n = 1_000_000;
        let mut process = LossProcess::new(&spec, ChaCha8Rng::seed_from_u64(3));
        let lost_sojourn = (0..n)
            .filter(|&k| process.step(k) != LossStep::Kept)
            .count();
        let (p_gb, p_bg) = gilbert_elliott_transitions(0.1, 5.0);
        let mut rng = ChaCha8Rng::seed_from_u64(4);
        let mut bad = false;
        let mut lost_chain = 0;
        for _ in 0..n {
            let u: f64 = rng.random();
            bad = if bad { u >= p_bg } else { u < p_gb };
            lost_chain += usize::from(bad);
        }
        let (a, b) = (lost_sojourn as f64 / n as f64, lost_chain as f64 / n as f64);
        assert!((a - b).abs() < 6e-3, "sojourns {a}, chain {b}");
        assert!((a - 0.1).abs() < 4e-3, "{a}");
    }

    #[test]
    fn random_loss_with_probability_one_loses_every_sample_as_single_runs() {
        let spec = LossSpec::Random { probability: 1.0 };
        let mut process = LossProcess::new(&spec, ChaCha8Rng::seed_from_u64(5));
        for k in 0..100 {
            assert_eq!(process.step(k), LossStep::RunStarts { samples: 1 });
        }
    }
}
