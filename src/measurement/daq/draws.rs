//! Random draws and unit conversions shared by the clock and fault models. Every draw takes
//! the caller's generator, so each component keeps its own stream.

use rand::RngExt;
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;

use crate::error::{num, Error, Result};

/// Nanoseconds per second, as a float for conversions.
pub(crate) const NS_PER_S: f64 = 1e9;

/// Seconds per hour, for `*_per_hour` rates.
pub(crate) const S_PER_HOUR: f64 = 3600.0;

/// Longest duration or instant accepted from a scenario: 100 years. Keeps every conversion
/// to `u64` nanoseconds far from overflow (`u64::MAX` ns is 584 years).
pub(crate) const MAX_SECONDS: f64 = 100.0 * 365.25 * 86_400.0;

/// `prefix.name`, or `name` alone for an empty prefix.
pub(crate) fn field(prefix: &str, name: &str) -> String {
    if prefix.is_empty() {
        name.to_string()
    } else {
        format!("{prefix}.{name}")
    }
}

/// `seconds` (finite, `0 <= seconds <= MAX_SECONDS`) as whole nanoseconds, rounded.
pub(crate) fn seconds_to_ns(field: &str, seconds: f64) -> Result<u64> {
    if seconds.is_finite() && (0.0..=MAX_SECONDS).contains(&seconds) {
        // In range by the check above, so the cast neither saturates nor wraps.
        Ok((seconds * NS_PER_S).round() as u64)
    } else {
        Err(Error::invalid(
            field,
            num(seconds),
            format!("must be a finite number in [0, {MAX_SECONDS:e}] s"),
        ))
    }
}

/// Checks `0 < seconds <= MAX_SECONDS`.
pub(crate) fn require_duration(field: &str, seconds: f64) -> Result<f64> {
    if seconds.is_finite() && seconds > 0.0 && seconds <= MAX_SECONDS {
        Ok(seconds)
    } else {
        Err(Error::invalid(
            field,
            num(seconds),
            format!("must be a duration in (0, {MAX_SECONDS:e}] s"),
        ))
    }
}

/// Checks `0 <= p <= 1`.
pub(crate) fn require_probability(field: &str, p: f64) -> Result<f64> {
    if (0.0..=1.0).contains(&p) {
        Ok(p)
    } else {
        Err(Error::invalid(
            field,
            num(p),
            "must be a probability in [0, 1]",
        ))
    }
}

/// A uniform draw in `(0, 1]`, safe to take the logarithm of.
fn open_unit(rng: &mut ChaCha8Rng) -> f64 {
    1.0 - rng.random::<f64>()
}

/// Exponential draw of mean `mean` (inversion: `-mean ln U`).
pub(crate) fn exponential(rng: &mut ChaCha8Rng, mean: f64) -> f64 {
    -mean * open_unit(rng).ln()
}

/// Number of failures before the first success of Bernoulli(`p`) trials, on `{0, 1, ...}`,
/// by inversion: `floor(ln U / ln(1 - p))` (Devroye 1986, ch. X.2). `p = 1` gives 0 and
/// `p = 0` saturates at `u64::MAX` (never).
pub(crate) fn failures_before_success(rng: &mut ChaCha8Rng, p: f64) -> u64 {
    if p >= 1.0 {
        return 0;
    }
    if p <= 0.0 {
        return u64::MAX;
    }
    // ln_1p keeps ln(1 - p) accurate for the small probabilities typical of packet loss.
    let failures = (open_unit(rng).ln() / (-p).ln_1p()).floor();
    // `as` saturates: a count beyond u64 is "never" for any run.
    failures as u64
}

/// Standard normal draw truncated to `[-limit, limit]` by rejection (exact truncated law).
pub(crate) fn truncated_standard_normal(rng: &mut ChaCha8Rng, limit: f64) -> f64 {
    loop {
        let z: f64 = rng.sample(StandardNormal);
        if z.abs() <= limit {
            return z;
        }
    }
}

/// Onsets of a Poisson process in time (rate per ns), drawn as exponential gaps on demand
/// and snapped by the caller to the first sample at or after each onset. Onsets are
/// integer nanoseconds summed from rounded gaps, so a long run accumulates no float error.
#[derive(Debug, Clone)]
pub(crate) struct PoissonOnsets {
    mean_gap_ns: f64,
    next_ns: u64,
}

impl PoissonOnsets {
    /// A process of `rate_per_hour` onsets per hour starting at time 0 (`rate = 0`: none).
    pub(crate) fn new(rate_per_hour: f64, rng: &mut ChaCha8Rng) -> Self {
        if rate_per_hour <= 0.0 {
            return Self {
                mean_gap_ns: f64::INFINITY,
                next_ns: u64::MAX,
            };
        }
        let mean_gap_ns = S_PER_HOUR * NS_PER_S / rate_per_hour;
        let mut onsets = Self {
            mean_gap_ns,
            next_ns: 0,
        };
        onsets.advance(rng);
        onsets
    }

    /// Whether an onset is due at or before `t_ns`; if so it is consumed and the next one
    /// drawn. Call in a loop: several onsets may fall within one sample period.
    pub(crate) fn take_due(&mut self, t_ns: u64, rng: &mut ChaCha8Rng) -> bool {
        if self.next_ns > t_ns {
            return false;
        }
        self.advance(rng);
        true
    }

    fn advance(&mut self, rng: &mut ChaCha8Rng) {
        let gap_ns = exponential(rng, self.mean_gap_ns).round() as u64;
        self.next_ns = self.next_ns.saturating_add(gap_ns);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    #[test]
    fn geometric_count_has_the_closed_form_mean() {
        // Mean of failures before success: (1 - p) / p = 9 for p = 0.1; variance
        // (1 - p) / p^2 = 90, so the standard error over 1e5 draws is 0.03: 5 SE = 0.15.
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        let n = 100_000;
        let sum: u64 = (0..n).map(|_| failures_before_success(&mut rng, 0.1)).sum();
        let mean = sum as f64 / n as f64;
        assert!((mean - 9.0).abs() < 0.15, "{mean}");
        assert_eq!(failures_before_success(&mut rng, 1.0), 0);
        assert_eq!(failures_before_success(&mut rng, 0.0), u64::MAX);
    }

    #[test]
    fn truncated_normal_stays_inside_and_has_the_truncated_variance() {
        // Variance of N(0,1) truncated at +/-1: 1 - 2 phi(1) / (2 Phi(1) - 1) = 0.29112.
        // The sample variance of 2e5 draws has SE ~ sqrt(Var(z^2) / n) < 0.001: 0.005 is 5 SE.
        let mut rng = ChaCha8Rng::seed_from_u64(2);
        let n = 200_000;
        let mut sum_sq = 0.0;
        for _ in 0..n {
            let z = truncated_standard_normal(&mut rng, 1.0);
            assert!(z.abs() <= 1.0);
            sum_sq += z * z;
        }
        let var = sum_sq / n as f64;
        assert!((var - 0.29112).abs() < 0.005, "{var}");
    }

    #[test]
    fn seconds_convert_and_out_of_range_values_name_the_field() {
        assert_eq!(seconds_to_ns("a", 1.5).unwrap(), 1_500_000_000);
        let e = seconds_to_ns("faults.dead.from_s", -1.0).unwrap_err();
        assert!(e.to_string().starts_with("faults.dead.from_s = -1 "), "{e}");
        let e = require_duration("x.duration_s", 0.0).unwrap_err();
        assert!(e.to_string().starts_with("x.duration_s = 0 "), "{e}");
    }
}
