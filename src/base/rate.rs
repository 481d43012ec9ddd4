//! Sample rates held as exact fractions, so that sample instants are integer nanoseconds
//! computed from the sample index (`t_k_ns = round(k * 1e9 / rate_hz)`), never accumulated.

use crate::error::{require_positive, Error, Result};

/// Nanoseconds per second.
pub const NS_PER_S: u128 = 1_000_000_000;

/// Largest denominator of the fraction that stands for a rate. Every rate written with up
/// to six decimals (`51.2 = 256 / 5`) or as a simple fraction (`1000 / 3`) is exact; any
/// other `f64` is replaced by its best continued-fraction convergent, relative error below
/// `1 / (rate * 2^48)`.
const MAX_DENOMINATOR: u128 = 1 << 24;

/// Highest accepted rate: one sample per nanosecond.
const MAX_RATE_HZ: f64 = 1e9;

/// A sample rate `num / den` Hz, reduced, with `num, den > 0`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ExactRate {
    num: u128,
    den: u128,
}

impl ExactRate {
    /// The fraction standing for `rate_hz`; `field` names the value in errors.
    pub fn from_hz(field: &str, rate_hz: f64) -> Result<Self> {
        require_positive(field, rate_hz)?;
        if rate_hz > MAX_RATE_HZ {
            return Err(Error::invalid(
                field,
                rate_hz,
                format!("must be <= {MAX_RATE_HZ:e} Hz (one sample per ns)"),
            ));
        }
        let (num, den) = best_fraction(rate_hz);
        if num == 0 {
            return Err(Error::invalid(
                field,
                rate_hz,
                format!("is too low to represent (the smallest rate is 1/{MAX_DENOMINATOR} Hz)"),
            ));
        }
        Ok(Self { num, den })
    }

    /// The rate in Hz as a float.
    pub fn hz(&self) -> f64 {
        self.num as f64 / self.den as f64
    }

    /// `round(k * 1e9 / rate)` in integer arithmetic, halves rounded up. Saturates at
    /// `u64::MAX` (a run of 584 years).
    pub fn instant_ns(&self, k: u64) -> u64 {
        // k < 2^64, 1e9 < 2^30, den <= 2^24: the numerator stays below 2^120.
        let twice = 2 * u128::from(k) * NS_PER_S * self.den + self.num;
        u64::try_from(twice / (2 * self.num)).unwrap_or(u64::MAX)
    }

    /// The period in ns if it is a whole number of nanoseconds.
    pub fn whole_period_ns(&self) -> Option<u64> {
        let numerator = NS_PER_S * self.den;
        if numerator.is_multiple_of(self.num) {
            u64::try_from(numerator / self.num).ok()
        } else {
            None
        }
    }

    /// The period rounded to whole ns, halves up (what a block message carries as its
    /// nominal sample spacing).
    pub fn period_ns_rounded(&self) -> u64 {
        self.instant_ns(1)
    }

    /// `round(n * 1e9 / rate)`: the nominal time spanned by `n` sample periods, ns.
    pub fn span_ns(&self, n: u64) -> u64 {
        self.instant_ns(n)
    }

    /// How many instants `instant_ns(k)`, `k = 0, 1, ...`, fall at or before `end_ns`:
    /// the samples of a stream at this rate over `[0, end_ns]`.
    pub fn count_until_ns(&self, end_ns: u64) -> u64 {
        // k / rate <= end: k = floor(end * num / (1e9 den)), then the rounding of the
        // instants settles the last one (instants round halves up).
        let mut k = u64::try_from(u128::from(end_ns) * self.num / (NS_PER_S * self.den))
            .unwrap_or(u64::MAX - 1);
        while k < u64::MAX - 1 && self.instant_ns(k + 1) <= end_ns {
            k += 1;
        }
        while k > 0 && self.instant_ns(k) > end_ns {
            k -= 1;
        }
        k + 1
    }

    /// Ordering of two rates, exact.
    pub fn cmp_rate(&self, other: &Self) -> std::cmp::Ordering {
        (self.num * other.den).cmp(&(other.num * self.den))
    }
}

/// The last convergent of the continued fraction of `x > 0` whose denominator is at most
/// `MAX_DENOMINATOR`, stopping early once it equals `x` to within 4 ulp.
fn best_fraction(x: f64) -> (u128, u128) {
    // Convergents h_n / k_n: h_n = a_n h_{n-1} + h_{n-2}, seeded with h_{-2} = 0,
    // h_{-1} = 1, k_{-2} = 1, k_{-1} = 0.
    let (mut h2, mut h1) = (0u128, 1u128);
    let (mut k2, mut k1) = (1u128, 0u128);
    let mut best = (0u128, 1u128);
    let mut r = x;
    for _ in 0..80 {
        let a_f = r.floor();
        if !(0.0..1e30).contains(&a_f) {
            break;
        }
        let a = a_f as u128;
        let Some(h) = a.checked_mul(h1).and_then(|v| v.checked_add(h2)) else {
            break;
        };
        let Some(k) = a.checked_mul(k1).and_then(|v| v.checked_add(k2)) else {
            break;
        };
        if k > MAX_DENOMINATOR {
            break;
        }
        (h2, h1) = (h1, h);
        (k2, k1) = (k1, k);
        best = (h, k);
        if (h as f64 / k as f64 - x).abs() <= 4.0 * f64::EPSILON * x {
            break;
        }
        let frac = r - a_f;
        if frac <= 0.0 {
            break;
        }
        r = 1.0 / frac;
    }
    // Convergents are already in lowest terms.
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frac(x: f64) -> (u128, u128) {
        let r = ExactRate::from_hz("rate_hz", x).unwrap();
        (r.num, r.den)
    }

    #[test]
    fn decimal_and_fractional_rates_are_exact() {
        assert_eq!(frac(200.0), (200, 1));
        assert_eq!(frac(300.0), (300, 1));
        assert_eq!(frac(128.0), (128, 1));
        assert_eq!(frac(51.2), (256, 5));
        assert_eq!(frac(1652.0), (1652, 1));
        assert_eq!(frac(1000.0 / 3.0), (1000, 3));
        assert_eq!(frac(0.5), (1, 2));
        assert_eq!(frac(0.1), (1, 10));
        assert_eq!(frac(12.345678), (6172839, 500000));
    }

    #[test]
    fn instants_are_rounded_from_the_index_without_float_loss() {
        let r = ExactRate::from_hz("rate_hz", 300.0).unwrap();
        assert_eq!(r.instant_ns(0), 0);
        assert_eq!(r.instant_ns(1), 3_333_333);
        assert_eq!(r.instant_ns(2), 6_666_667);
        assert_eq!(r.instant_ns(3), 10_000_000);
        // k * 1e9 / 300 = 1e18 + 1e7 / 3 exactly; an f64 product would be off by ~100 ns.
        assert_eq!(r.instant_ns(300_000_000_001), 1_000_000_000_003_333_333);
        let r = ExactRate::from_hz("rate_hz", 51.2).unwrap();
        assert_eq!(r.instant_ns(1), 19_531_250);
        assert_eq!(r.instant_ns(3), 58_593_750);
    }

    #[test]
    fn counts_until_an_end_match_the_instants_one_by_one() {
        for hz in [200.0, 300.0, 51.2, 1000.0 / 3.0, 0.5] {
            let r = ExactRate::from_hz("rate_hz", hz).unwrap();
            for end_ns in [
                0,
                1,
                3_333_333,
                3_333_334,
                10_000_000,
                19_531_250,
                2_000_000_001,
            ] {
                let brute = (0..).take_while(|&k| r.instant_ns(k) <= end_ns).count() as u64;
                assert_eq!(r.count_until_ns(end_ns), brute, "{hz} Hz until {end_ns} ns");
            }
        }
    }

    #[test]
    fn whole_periods_and_ordering() {
        let a = ExactRate::from_hz("a", 1000.0).unwrap();
        let b = ExactRate::from_hz("b", 300.0).unwrap();
        assert_eq!(a.whole_period_ns(), Some(1_000_000));
        assert_eq!(b.whole_period_ns(), None);
        assert_eq!(a.cmp_rate(&b), std::cmp::Ordering::Greater);
        assert_eq!(a.cmp_rate(&a), std::cmp::Ordering::Equal);
    }

    #[test]
    fn bad_rates_name_the_field() {
        for bad in [0.0, -3.0, f64::NAN, f64::INFINITY, 2e9, 1e-12] {
            let e = ExactRate::from_hz("sensors.0.rate_hz", bad).unwrap_err();
            assert!(e.to_string().starts_with("sensors.0.rate_hz = "), "{e}");
        }
    }
}
