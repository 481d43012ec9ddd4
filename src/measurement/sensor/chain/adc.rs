//! The analog-to-digital converter: mid-tread quantiser with clipping at the code limits.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;

use super::preset::AdcParameters;
use crate::measurement::sensor::SampleStage;

/// Number of samples an ADC clipped, shared between the stage (which the channel owns)
/// and whoever flags off-scale records after the run. Clones count together.
#[derive(Debug, Clone, Default)]
pub struct ClipCounter(Arc<AtomicU64>);

impl ClipCounter {
    /// Samples clipped so far.
    pub fn get(&self) -> u64 {
        self.0.load(Ordering::Relaxed)
    }

    fn increment(&self) {
        // Relaxed: a plain event count; readers only need the value after the run.
        self.0.fetch_add(1, Ordering::Relaxed);
    }
}

/// Mid-tread quantiser: `code = round(x / lsb)` (half away from zero), clamped to
/// `-2^(bits-1) ..= 2^(bits-1) - 1`; the output is `code * lsb` with
/// `lsb = 2 range / 2^bits`. A sample whose unclamped code is outside the limits is
/// clipped and counted. The converter is an ideal one: no differential non-linearity,
/// no dither beyond the sensor's own noise. Non-finite values pass unchanged and
/// uncounted (they are upstream bugs, not off-scale signals).
#[derive(Debug, Clone)]
pub struct Quantiser {
    lsb: f64,
    min_code: f64,
    max_code: f64,
    clipped: ClipCounter,
}

impl Quantiser {
    /// A quantiser for `adc`, counting into `clipped`. `adc` is validated by the caller
    /// (bits 1..=32, range > 0).
    pub fn new(adc: &AdcParameters, clipped: ClipCounter) -> Self {
        let half_codes = 2f64.powi(adc.bits as i32 - 1);
        Self {
            lsb: adc.lsb(),
            min_code: -half_codes,
            max_code: half_codes - 1.0,
            clipped,
        }
    }

    /// Quantisation step.
    pub fn lsb(&self) -> f64 {
        self.lsb
    }

    /// Largest and smallest output values, `max_code * lsb` and `min_code * lsb`.
    pub fn limits(&self) -> (f64, f64) {
        (self.min_code * self.lsb, self.max_code * self.lsb)
    }
}

impl SampleStage for Quantiser {
    fn apply(&mut self, _t_ns: u64, value: f64) -> f64 {
        if !value.is_finite() {
            return value;
        }
        let code = (value / self.lsb).round();
        if code > self.max_code || code < self.min_code {
            self.clipped.increment();
        }
        code.clamp(self.min_code, self.max_code) * self.lsb
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn quantiser(bits: u32, range: f64) -> (Quantiser, ClipCounter) {
        let counter = ClipCounter::default();
        let q = Quantiser::new(&AdcParameters { bits, range }, counter.clone());
        (q, counter)
    }

    #[test]
    fn three_bit_codes_by_hand() {
        // 3 bits over +/-4: lsb 1, codes -4..=3. Hand table, rounding half away from zero.
        let (mut q, clipped) = quantiser(3, 4.0);
        let cases = [
            (0.0, 0.0),
            (0.49, 0.0),
            (0.5, 1.0),
            (-0.5, -1.0),
            (2.6, 3.0),
            (3.49, 3.0),
            (3.5, 3.0),
            (-4.49, -4.0),
            (-4.5, -4.0),
            (100.0, 3.0),
        ];
        for (x, y) in cases {
            assert_eq!(q.apply(0, x), y, "{x}");
        }
        // Clipped: 3.5 (code 4), -4.5 (code -5), 100.
        assert_eq!(clipped.get(), 3);
        assert_eq!(q.limits(), (-4.0, 3.0));
    }

    #[test]
    fn nan_passes_uncounted() {
        let (mut q, clipped) = quantiser(16, 1.0);
        assert!(q.apply(0, f64::NAN).is_nan());
        assert_eq!(clipped.get(), 0);
    }
}
