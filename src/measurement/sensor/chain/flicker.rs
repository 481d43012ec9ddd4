//! 1/f ("flicker") noise from a bank of first-order autoregressive sections.
//!
//! A sum of independent relaxation processes whose corner frequencies are spread evenly on
//! a logarithmic axis has a 1/f spectrum between the lowest and highest corner: with
//! corners uniform in `ln f_k` and weights `1/f_k`,
//! `integral (1/f_k) / (1 + (f/f_k)^2) d(ln f_k) = (pi/2) / f` (van der Ziel, Physica 16,
//! 1950; Keshner, Proc. IEEE 70, 1982). Each section here is the exact discrete
//! counterpart, an AR(1) process `s[n] = a s[n-1] + sqrt(q) w[n]` with
//! `a = exp(-2 pi f_k / fs)`, whose one-sided PSD is
//!
//! ```text
//! S_k(f) = (2 q / fs) / ((1 - a)^2 + 4 a sin^2(pi f / fs))
//! ```
//!
//! The weights `q_k` start from the integral above and are then fitted once, at
//! construction, by non-negative least squares on a log grid so that the sum also follows
//! 1/f near the band edges, where the continuous result does not hold. Every AR(1) spectrum
//! is flat at fs/2, so no positive sum of them follows 1/f right up to Nyquist: the fit
//! covers `[lowest, 0.4 fs]` (the anti-alias pass band) with at most [`DESIGN_RIPPLE_DB`],
//! and the last fifth of the band ends up to [`NYQUIST_EXCESS_DB`] high (both checked
//! against the closed form in the tests). There the white part dominates by far unless the
//! corner is near fs/2. Below the lowest frequency the spectrum flattens, as a real
//! sensor's drift does once bounded.
//!
//! Cost: [`SECTIONS_PER_DECADE`] normal draws and multiply-adds per decade per sample
//! (about 19 sections for 1 mHz..1 kHz), no allocation after construction.

use nalgebra::{DMatrix, DVector};
use rand::RngExt;
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;

/// Corner frequencies per decade. Three keep the fitted ripple under
/// [`DESIGN_RIPPLE_DB`]; some of the sections above the band get weight 0 in the fit.
pub const SECTIONS_PER_DECADE: f64 = 3.0;

/// Largest deviation of the fitted bank's PSD from the 1/f target over
/// `[lowest, FIT_TOP_FRACTION * fs]`, in dB (measured 0.16 dB for 1 to 8 decades).
pub const DESIGN_RIPPLE_DB: f64 = 0.2;

/// Largest excess of the bank's PSD over 1/f between `FIT_TOP_FRACTION * fs` and fs/2,
/// in dB (measured 0.81 dB).
pub const NYQUIST_EXCESS_DB: f64 = 1.0;

/// Upper end of the fitted band, fraction of the sample rate (the anti-alias pass-band
/// edge of the channel).
pub const FIT_TOP_FRACTION: f64 = 0.4;

/// Log-grid points per decade on which the fit compares the bank with 1/f.
const GRID_PER_DECADE: f64 = 12.0;

/// One AR(1) section: pole `a` and innovation variance `q`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ArSection {
    /// Pole, `exp(-2 pi f_k / fs)`, in (0, 1).
    pub pole: f64,
    /// `1 - pole`, kept separately because it is tiny (3e-6 for 1 mHz at 2 kHz) and
    /// would lose half its digits if computed from the pole.
    pub one_minus_pole: f64,
    /// Innovation variance `q` (unit^2).
    pub innovation_variance: f64,
}

impl ArSection {
    fn with_corner(corner_hz: f64, rate_hz: f64) -> Self {
        let x = 2.0 * std::f64::consts::PI * corner_hz / rate_hz;
        Self {
            pole: (-x).exp(),
            one_minus_pole: -(-x).exp_m1(),
            innovation_variance: 0.0,
        }
    }

    /// One-sided PSD of the section at `f_hz` (unit^2/Hz), closed form of the module doc.
    pub fn psd(&self, f_hz: f64, rate_hz: f64) -> f64 {
        let s = (std::f64::consts::PI * f_hz / rate_hz).sin();
        let denominator = self.one_minus_pole.powi(2) + 4.0 * self.pole * s * s;
        2.0 * self.innovation_variance / rate_hz / denominator
    }

    /// Stationary variance `q / (1 - a^2)`.
    pub fn stationary_variance(&self) -> f64 {
        self.innovation_variance / (self.one_minus_pole * (1.0 + self.pole))
    }
}

/// Sections whose summed one-sided PSD approximates `level / f` (unit^2/Hz) on
/// `[lowest_hz, rate_hz / 2]`. The caller checks `0 < lowest_hz < 0.4 rate_hz` and
/// `level >= 0`.
pub fn design_bank(level: f64, lowest_hz: f64, rate_hz: f64) -> Vec<ArSection> {
    let nyquist_hz = 0.5 * rate_hz;
    let step = 10f64.powf(1.0 / SECTIONS_PER_DECADE);
    // One corner below the band and corners up to the first at or above Nyquist, so both
    // band edges are covered from outside.
    let mut sections = Vec::new();
    let mut corner_hz = lowest_hz / step;
    loop {
        let mut section = ArSection::with_corner(corner_hz, rate_hz);
        // Continuous limit: a Lorentzian of low-frequency level (2/pi) ln(step) / f_k,
        // and S_k(0) = 2 q / (fs (1 - a)^2).
        let lorentz_level = (2.0 / std::f64::consts::PI) * step.ln() / corner_hz;
        section.innovation_variance =
            0.5 * lorentz_level * rate_hz * section.one_minus_pole.powi(2);
        sections.push(section);
        if corner_hz >= nyquist_hz {
            break;
        }
        corner_hz *= step;
    }
    refine(&mut sections, lowest_hz, rate_hz);
    for s in &mut sections {
        s.innovation_variance *= level;
    }
    sections
}

/// Least-squares fit of the weights: minimises the relative error
/// `sum_j (S(f_j) f_j - 1)^2` on a log grid over `[lowest, 0.4 fs]` subject to every
/// innovation variance being >= 0 (the problem is linear in them; non-negative least
/// squares, once per sensor on an ~80 x 20 system). Unconstrained least squares would
/// give the barely constrained sections above the band weights of alternating sign.
fn refine(sections: &mut [ArSection], lowest_hz: f64, rate_hz: f64) {
    let grid_hz = fit_grid(lowest_hz, FIT_TOP_FRACTION * rate_hz, sections.len() + 1);
    // Column k: section k's relative PSD at its current (continuous-limit) weight; solving
    // for scale factors keeps every column O(1).
    let a = DMatrix::from_fn(grid_hz.len(), sections.len(), |j, k| {
        sections[k].psd(grid_hz[j], rate_hz) * grid_hz[j]
    });
    let b = DVector::from_element(grid_hz.len(), 1.0);
    let scale = nnls(&a, &b);
    for (s, x) in sections.iter_mut().zip(scale.iter()) {
        s.innovation_variance *= x;
    }
}

/// Non-negative least squares, `min |A x - b|` with `x >= 0`: the active-set algorithm of
/// Lawson & Hanson (Solving Least Squares Problems, 1974, ch. 23, algorithm NNLS).
fn nnls(a: &DMatrix<f64>, b: &DVector<f64>) -> DVector<f64> {
    let n = a.ncols();
    let tolerance = 1e-12 * a.norm() * b.norm();
    let mut x = DVector::zeros(n);
    let mut passive = vec![false; n];
    for _ in 0..3 * n {
        let gradient = a.transpose() * (b - a * &x);
        let candidate = (0..n)
            .filter(|&j| !passive[j])
            .max_by(|&i, &j| gradient[i].total_cmp(&gradient[j]));
        match candidate {
            Some(j) if gradient[j] > tolerance => passive[j] = true,
            _ => break,
        }
        loop {
            let z = passive_solve(a, b, &passive);
            let blocking = (0..n)
                .filter(|&j| passive[j] && z[j] <= 0.0)
                .map(|j| x[j] / (x[j] - z[j]))
                .fold(f64::INFINITY, f64::min);
            if blocking.is_infinite() {
                x = z;
                break;
            }
            x += (z - &x) * blocking;
            for j in 0..n {
                if passive[j] && x[j] <= tolerance {
                    passive[j] = false;
                    x[j] = 0.0;
                }
            }
        }
    }
    x
}

/// Unconstrained least squares on the passive columns; zero elsewhere.
fn passive_solve(a: &DMatrix<f64>, b: &DVector<f64>, passive: &[bool]) -> DVector<f64> {
    let columns: Vec<usize> = (0..a.ncols()).filter(|&j| passive[j]).collect();
    let sub = DMatrix::from_fn(a.nrows(), columns.len(), |i, k| a[(i, columns[k])]);
    let mut z = DVector::zeros(a.ncols());
    if let Ok(solution) = sub.svd(true, true).solve(b, 1e-14) {
        for (k, &j) in columns.iter().enumerate() {
            z[j] = solution[k];
        }
    }
    z
}

/// Log-spaced frequencies from `low_hz` to `high_hz`, [`GRID_PER_DECADE`] per decade and
/// at least `min_points`.
fn fit_grid(low_hz: f64, high_hz: f64, min_points: usize) -> Vec<f64> {
    let decades = (high_hz / low_hz).log10();
    let points = ((decades * GRID_PER_DECADE).ceil() as usize + 1).max(min_points);
    (0..points)
        .map(|i| low_hz * (high_hz / low_hz).powf(i as f64 / (points - 1) as f64))
        .collect()
}

/// Summed one-sided PSD of a bank at `f_hz` (unit^2/Hz).
pub fn bank_psd(sections: &[ArSection], f_hz: f64, rate_hz: f64) -> f64 {
    sections.iter().map(|s| s.psd(f_hz, rate_hz)).sum()
}

/// Generator of 1/f noise with one-sided PSD `level / f`, from its own random stream.
#[derive(Debug, Clone)]
pub struct FlickerNoise {
    poles: Vec<f64>,
    innovation_sigmas: Vec<f64>,
    states: Vec<f64>,
    rng: ChaCha8Rng,
}

impl FlickerNoise {
    /// Noise of one-sided PSD `level / f` on `[lowest_hz, rate_hz/2]` sampled at
    /// `rate_hz` (`level` in unit^2, e.g. `ND^2 fc`). Each section starts in its
    /// stationary distribution, so the record has no start-up transient (the sensor was
    /// powered long before the run); those starting states are the first draws of `rng`.
    pub fn new(level: f64, lowest_hz: f64, rate_hz: f64, mut rng: ChaCha8Rng) -> Self {
        let sections = design_bank(level, lowest_hz, rate_hz);
        let states = sections
            .iter()
            .map(|s| s.stationary_variance().sqrt() * rng.sample::<f64, _>(StandardNormal))
            .collect();
        Self {
            poles: sections.iter().map(|s| s.pole).collect(),
            innovation_sigmas: sections
                .iter()
                .map(|s| s.innovation_variance.sqrt())
                .collect(),
            states,
            rng,
        }
    }

    /// Number of AR sections.
    pub fn sections(&self) -> usize {
        self.poles.len()
    }

    /// The next sample: every section advances by one step; the output is their sum.
    pub fn sample(&mut self) -> f64 {
        let mut sum = 0.0;
        for ((state, &pole), &sigma) in self
            .states
            .iter_mut()
            .zip(&self.poles)
            .zip(&self.innovation_sigmas)
        {
            let w: f64 = self.rng.sample(StandardNormal);
            *state = pole * *state + sigma * w;
            sum += *state;
        }
        sum
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    /// Worst deviation in dB of the designed bank from `level / f` on a fine log grid
    /// over `[low, high]`, from the closed-form PSD (not the fit's own grid).
    fn deviation_db(level: f64, lowest_hz: f64, rate_hz: f64, low: f64, high: f64) -> f64 {
        let bank = design_bank(level, lowest_hz, rate_hz);
        let n = 3000;
        (0..=n)
            .map(|i| low * (high / low).powf(i as f64 / n as f64))
            .map(|f| (10.0 * (bank_psd(&bank, f, rate_hz) * f / level).log10()).abs())
            .fold(0.0, f64::max)
    }

    #[test]
    fn designed_bank_follows_one_over_f_within_the_stated_ripple() {
        let cases = [
            (1e-3, 100.0),
            (1e-3, 200.0),
            (1e-3, 10_000.0),
            (1e-4, 20_000.0),
            (0.1, 100.0),
            (1.0, 10.0),
        ];
        for &(lowest_hz, rate_hz) in &cases {
            let fit_top = FIT_TOP_FRACTION * rate_hz;
            let ripple = deviation_db(3.7, lowest_hz, rate_hz, lowest_hz, fit_top);
            let top = deviation_db(3.7, lowest_hz, rate_hz, fit_top, 0.5 * rate_hz);
            println!(
                "flicker bank from {lowest_hz} Hz at {rate_hz} Hz: \
                 ripple {ripple:.4} dB, top {top:.3} dB"
            );
            assert!(
                ripple <= DESIGN_RIPPLE_DB,
                "{lowest_hz} {rate_hz}: {ripple} dB"
            );
            assert!(top <= NYQUIST_EXCESS_DB, "{lowest_hz} {rate_hz}: {top} dB");
        }
    }

    #[test]
    fn section_psd_integrates_to_its_stationary_variance() {
        // Parseval: the one-sided PSD integrated over [0, fs/2] is the variance. Midpoint
        // rule with 2e5 cells on a smooth integrand: error far below 1e-6.
        let mut s = ArSection::with_corner(3.0, 200.0);
        s.innovation_variance = 0.7;
        let n = 200_000;
        let df = 100.0 / n as f64;
        let integral: f64 = (0..n)
            .map(|i| s.psd((i as f64 + 0.5) * df, 200.0) * df)
            .sum();
        let expected = s.stationary_variance();
        assert!(
            (integral / expected - 1.0).abs() < 1e-6,
            "{integral} vs {expected}"
        );
    }

    #[test]
    fn generator_variance_matches_the_bank() {
        // Lowest frequency 1 Hz at 200 Hz: the slowest section's correlation time is
        // ~0.2 s (~40 samples), so 4e5 samples give ~1e4 independent stretches and the
        // sample variance has a relative standard error of ~2 %; 8 % is 4 sigma.
        let (level, lowest_hz, rate_hz) = (2.0, 1.0, 200.0);
        let bank = design_bank(level, lowest_hz, rate_hz);
        let expected: f64 = bank.iter().map(ArSection::stationary_variance).sum();
        let mut g = FlickerNoise::new(level, lowest_hz, rate_hz, ChaCha8Rng::seed_from_u64(5));
        let n = 400_000;
        let var = (0..n).map(|_| g.sample().powi(2)).sum::<f64>() / n as f64;
        println!("flicker variance {var:.4} vs {expected:.4}");
        assert!((var / expected - 1.0).abs() < 0.08, "{var} vs {expected}");
    }
}
