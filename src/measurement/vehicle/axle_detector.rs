//! A road axle detector (a tape switch or pneumatic tube across the lane): it reports the
//! instant each axle crosses it, late or early by a timing jitter (the switch's closure,
//! the logger's sampling), and now and then misses an axle (a light axle, a worn tape).

use rand::RngExt;
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;

/// What a detector reports of one axle crossing at `true_ns`: `None` when it misses it,
/// else the time it stamps (ns, may precede `true_ns` by the jitter).
#[derive(Debug, Clone)]
pub struct DetectorTiming {
    /// Standard deviation of the timing error (s).
    pub jitter_s: f64,
    /// Probability of missing an axle, in [0, 1).
    pub miss_probability: f64,
    rng: ChaCha8Rng,
}

impl DetectorTiming {
    pub fn new(jitter_s: f64, miss_probability: f64, rng: ChaCha8Rng) -> Self {
        Self {
            jitter_s,
            miss_probability,
            rng,
        }
    }

    /// The stamp of a crossing at `true_ns` (run time), or `None` when missed. Both draws
    /// happen for every crossing, so a miss never shifts the jitter of the next one.
    pub fn observe(&mut self, true_ns: u64) -> Option<i64> {
        let u: f64 = self.rng.random();
        let z: f64 = self.rng.sample(StandardNormal);
        let stamp = true_ns as i64 + (self.jitter_s * z * 1e9).round() as i64;
        (u >= self.miss_probability).then_some(stamp)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::base::random::child_rng;

    #[test]
    fn jitter_and_misses_have_their_rates() {
        // 40 000 crossings: the miss share 0.05 is known to sqrt(0.05 * 0.95 / 40000) =
        // 0.0011, the jitter's sigma to 0.35 %.
        let mut d = DetectorTiming::new(1e-3, 0.05, child_rng(3, "axle"));
        let n = 40_000;
        let mut errors = Vec::new();
        for k in 0..n {
            let t = k * 1_000_000_000;
            if let Some(s) = d.observe(t) {
                errors.push((s - t as i64) as f64 * 1e-9);
            }
        }
        let missed = 1.0 - errors.len() as f64 / n as f64;
        assert!((missed - 0.05).abs() < 0.005, "missed {missed}");
        let sigma = (errors.iter().map(|e| e * e).sum::<f64>() / errors.len() as f64).sqrt();
        assert!((sigma / 1e-3 - 1.0).abs() < 0.02, "jitter {sigma}");
        let mut exact = DetectorTiming::new(0.0, 0.0, child_rng(3, "axle"));
        assert_eq!(exact.observe(123_456), Some(123_456));
    }
}
