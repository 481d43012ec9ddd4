//! Welch estimate of a one-sided power spectral density, for verifying road profiles
//! (and any uniformly sampled signal).
//!
//! Welch (1967): Hann-windowed segments with 50 % overlap, each segment's mean removed,
//! periodograms averaged. One-sided density scaling `G(n_k) = 2 dx |X_k|^2 / sum w^2`
//! (bins 1 .. len/2 - 1; DC and Nyquist are not reported), so that the integral of `G`
//! over frequency equals the mean square of a signal whose content lies between them.

use rustfft::num_complex::Complex;
use rustfft::FftPlanner;

use crate::error::{require_positive, Error, Result};

/// A one-sided PSD estimate.
#[derive(Debug, Clone, PartialEq)]
pub struct WelchPsd {
    /// Bin frequencies `k / (segment_len dx)`, k = 1 .. segment_len/2 - 1, cycle/m (or Hz).
    pub frequencies: Vec<f64>,
    /// Averaged one-sided density per bin, unit^2 per cycle/m (m^3 for elevation in m).
    pub density: Vec<f64>,
    /// Number of periodograms averaged.
    pub segments: usize,
}

impl WelchPsd {
    /// Averages `other` into `self` (same segment length and spacing), weighting each by
    /// its number of segments: the Welch estimate over several realisations.
    pub fn merge(&mut self, other: &WelchPsd) -> Result<()> {
        if self.frequencies != other.frequencies {
            return Err(Error::invalid(
                "welch segment",
                other.frequencies.len(),
                "differs between the estimates being merged",
            ));
        }
        let (a, b) = (self.segments as f64, other.segments as f64);
        for (d, o) in self.density.iter_mut().zip(&other.density) {
            *d = (*d * a + o * b) / (a + b);
        }
        self.segments += other.segments;
        Ok(())
    }
}

/// Welch PSD of `samples` at spacing `spacing` with segments of `segment_len` samples
/// (even, >= 8, at most `samples.len()`).
pub fn welch_psd(samples: &[f64], spacing: f64, segment_len: usize) -> Result<WelchPsd> {
    require_positive("spacing", spacing)?;
    if segment_len < 8 || !segment_len.is_multiple_of(2) || segment_len > samples.len() {
        return Err(Error::invalid(
            "segment_len",
            segment_len,
            format!(
                "must be even, >= 8 and <= the number of samples {}",
                samples.len()
            ),
        ));
    }
    let window: Vec<f64> = (0..segment_len)
        .map(|i| {
            let phase = 2.0 * std::f64::consts::PI * i as f64 / segment_len as f64;
            0.5 * (1.0 - phase.cos())
        })
        .collect();
    let window_power: f64 = window.iter().map(|w| w * w).sum();
    let fft = FftPlanner::<f64>::new().plan_fft_forward(segment_len);
    let half = segment_len / 2;
    let mut density = vec![0.0; half - 1];
    let mut buffer = vec![Complex::new(0.0, 0.0); segment_len];
    let hop = segment_len / 2;
    let mut segments = 0;
    let mut start = 0;
    while start + segment_len <= samples.len() {
        let seg = &samples[start..start + segment_len];
        let mean = seg.iter().sum::<f64>() / segment_len as f64;
        for ((b, &s), &w) in buffer.iter_mut().zip(seg).zip(&window) {
            *b = Complex::new((s - mean) * w, 0.0);
        }
        fft.process(&mut buffer);
        for (d, b) in density.iter_mut().zip(&buffer[1..half]) {
            *d += b.norm_sqr();
        }
        segments += 1;
        start += hop;
    }
    let scale = 2.0 * spacing / (window_power * segments as f64);
    density.iter_mut().for_each(|d| *d *= scale);
    let df = 1.0 / (segment_len as f64 * spacing);
    Ok(WelchPsd {
        frequencies: (1..half).map(|k| k as f64 * df).collect(),
        density,
        segments,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sinusoid_power_integrates_to_its_mean_square() {
        // A sinusoid on a bin centre: the Hann main lobe spreads its power over 3 bins and
        // the density integrates (sum * df) to A^2 / 2. Exact up to rounding, 1e-9.
        let (n, dx, a) = (4096, 0.05, 0.003);
        let f = 40.0 / (256.0 * dx);
        let x: Vec<f64> = (0..n)
            .map(|i| a * (2.0 * std::f64::consts::PI * f * i as f64 * dx + 0.3).cos())
            .collect();
        let psd = welch_psd(&x, dx, 256).unwrap();
        assert_eq!(psd.segments, 31);
        let df = psd.frequencies[0];
        let power: f64 = psd.density.iter().sum::<f64>() * df;
        assert!((power / (0.5 * a * a) - 1.0).abs() < 1e-9, "{power}");
    }

    #[test]
    fn rejects_bad_segment() {
        assert!(welch_psd(&[0.0; 10], 1.0, 12).is_err());
        assert!(welch_psd(&[0.0; 10], 1.0, 7).is_err());
        assert!(welch_psd(&[0.0; 10], 0.0, 8).is_err());
    }
}
