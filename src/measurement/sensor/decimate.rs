//! Decimation of a sampled stream by a whole factor, with the channel's anti-alias
//! filter: what a viewer preview of a high-rate channel shows.
//!
//! Input sample `k` (any uniformly sampled stream, e.g. a sensor's measured samples);
//! output `j` is the filtered value at input sample `j M`: the Kaiser-windowed sinc of
//! [`super::AntiAliasOptions`] designed for the output rate (pass band to 0.4 of it,
//! stop band from 0.5, 80 dB by default), symmetric, so zero phase: the output at `j M`
//! lines up with input `j M` without delay. It is handed over once input `j M + L` has
//! arrived (`L` the kernel's half-width). Ends as the channel's: inputs before the first
//! are taken equal to it; [`Decimator::flush`] completes the outputs up to the last
//! input by holding it.

use std::sync::Arc;

use super::kaiser::PolyphaseKernel;
use super::resample::AntiAliasOptions;
use crate::error::{Error, Result};

/// Streaming whole-factor decimator.
#[derive(Debug, Clone)]
pub struct Decimator {
    factor: u64,
    kernel: Arc<PolyphaseKernel>,
    /// The last `width` inputs, twice over (`buf[i]` and `buf[i + width]`), so that the
    /// window is always one contiguous slice.
    buf: Vec<f64>,
    width: usize,
    /// Inputs pushed so far.
    pushed: u64,
    /// Index (in outputs) of the next output to emit.
    next_output: u64,
}

impl Decimator {
    /// A decimator by `factor` (>= 2) with filter `options`; `field` names the factor in
    /// errors.
    pub fn new(factor: u64, options: &AntiAliasOptions, field: &str) -> Result<Self> {
        if factor < 2 {
            return Err(Error::invalid(
                field,
                factor,
                "gives a decimation factor below 2 (the preview would be the stream itself)",
            ));
        }
        let ratio = 1.0 / factor as f64;
        // Outputs fall on input samples: one phase.
        let design = options.kaiser_design(ratio, Some(1));
        let kernel = PolyphaseKernel::shared(&design);
        let width = kernel.taps();
        Ok(Decimator {
            factor,
            kernel,
            buf: vec![0.0; 2 * width],
            width,
            pushed: 0,
            next_output: 0,
        })
    }

    /// The decimation factor.
    pub fn factor(&self) -> u64 {
        self.factor
    }

    /// Inputs between an output's centre and its hand-over (the kernel's half-width).
    pub fn latency_samples(&self) -> u64 {
        self.kernel.half_width() as u64
    }

    fn store(&mut self, value: f64) {
        if self.pushed == 0 {
            // Inputs before the first hold its value.
            self.buf.iter_mut().for_each(|v| *v = value);
        }
        let i = (self.pushed % self.width as u64) as usize;
        self.buf[i] = value;
        self.buf[i + self.width] = value;
        self.pushed += 1;
    }

    /// The output whose window ends at the newest input.
    fn filtered(&self) -> f64 {
        // The window holds inputs pushed - width .. pushed - 1, oldest first.
        let start = (self.pushed % self.width as u64) as usize;
        self.kernel.apply(0.0, &self.buf[start..start + self.width])
    }

    /// Pushes input `k = pushed`; `emit(centre_index, value)` receives the output it
    /// completes, if any (centre index in inputs).
    pub fn push(&mut self, value: f64, mut emit: impl FnMut(u64, f64)) {
        self.store(value);
        let half = self.kernel.half_width() as u64;
        let centre = self.next_output * self.factor;
        if self.pushed == centre + half + 1 {
            emit(centre, self.filtered());
            self.next_output += 1;
        }
    }

    /// Emits the outputs centred at or before the last input, holding the last input
    /// where the kernel reaches beyond it. The decimator is spent afterwards.
    pub fn flush(&mut self, mut emit: impl FnMut(u64, f64)) {
        if self.pushed == 0 {
            return;
        }
        let last = self.pushed - 1;
        let hold = self.buf[(last % self.width as u64) as usize];
        let half = self.kernel.half_width() as u64;
        while self.next_output * self.factor <= last {
            let centre = self.next_output * self.factor;
            while self.pushed < centre + half + 1 {
                self.store(hold);
            }
            emit(centre, self.filtered());
            self.next_output += 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn decimate(input: &[f64], factor: u64) -> Vec<(u64, f64)> {
        let mut d = Decimator::new(factor, &AntiAliasOptions::default(), "rate").unwrap();
        let mut out = Vec::new();
        for &x in input {
            d.push(x, |k, y| out.push((k, y)));
        }
        d.flush(|k, y| out.push((k, y)));
        out
    }

    #[test]
    fn every_multiple_of_the_factor_is_an_output_centre() {
        let out = decimate(&vec![1.0; 1003], 8);
        let centres: Vec<u64> = out.iter().map(|o| o.0).collect();
        assert_eq!(centres, (0..=125).map(|j| 8 * j).collect::<Vec<_>>());
        // DC passes exactly (unit-sum kernel), ends included (hold).
        assert!(out.iter().all(|o| (o.1 - 1.0).abs() < 1e-12), "{out:?}");
    }

    #[test]
    fn the_pass_band_passes_without_delay_and_the_stop_band_is_removed() {
        // 200 Hz in, factor 8: 25 Hz out, pass band to 10 Hz, stop band from 12.5 Hz.
        let fs = 200.0;
        let n = 8000;
        let tone = |f: f64| -> Vec<f64> {
            (0..n)
                .map(|k| (2.0 * std::f64::consts::PI * f * k as f64 / fs).sin())
                .collect()
        };
        // A 3 Hz tone: the outputs equal the input at their centres (zero phase; pass-band
        // ripple of the 80 dB design ~1e-4), away from the ends.
        let x = tone(3.0);
        let out = decimate(&x, 8);
        let worst = out[100..out.len() - 100]
            .iter()
            .map(|&(k, y)| (y - x[k as usize]).abs())
            .fold(0.0, f64::max);
        assert!(worst < 3e-4, "pass band error {worst}");
        // A 40 Hz tone (it would alias to 10 Hz): attenuated by >= 80 dB less margin.
        let out = decimate(&tone(40.0), 8);
        let worst = out[100..out.len() - 100]
            .iter()
            .map(|o| o.1.abs())
            .fold(0.0, f64::max);
        assert!(worst < 2e-4, "stop band residue {worst}");
    }

    #[test]
    fn a_factor_below_two_names_the_field() {
        let e = Decimator::new(1, &AntiAliasOptions::default(), "decimation factor")
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("decimation factor = 1 gives"), "{e}");
    }
}
