//! ISO 8608 random profile synthesis by inverse FFT.
//!
//! Harmonic superposition (docs/physics.md section 7, ISO 8608 Annex F)
//! `r(x) = sum_k A_k cos(2 pi n_k x + phi_k)` with uniform random phases `phi_k`, evaluated
//! for all samples at once by one inverse FFT. The lines sit on the FFT grid
//! `n_k = k dn`, `dn = 1 / (N_fft dx)`; each line carries exactly the spectrum's integral
//! over its bin (`A_k^2 / 2 = integral of G_d over the bin within [n1, n2]`, closed form),
//! so the mean square over one period of the FFT equals the band integral exactly, for
//! every realisation, not only on average. The FFT period is at least twice the generated
//! length, so the profile never repeats within it.

use rand::RngExt;
use rand_chacha::ChaCha8Rng;
use rustfft::num_complex::Complex;
use rustfft::FftPlanner;

use super::spec::N0_CYCLES_M;
use super::track::TrackClass;
use crate::error::{Error, Result};

/// Largest FFT accepted: 2^26 samples (1 GiB of complex buffer), 1 677 km at 0.05 m.
const MAX_FFT_LEN: usize = 1 << 26;

/// The band must be resolved by at least this many lines per `n1` (dn <= n1 / 8), so that
/// the lowest octave of the spectrum has several lines even on a short road.
const LINES_PER_N1: f64 = 8.0;

/// Parameters of one synthesis, validated by the spec.
#[derive(Debug, Clone, Copy)]
pub(crate) struct IsoBand {
    pub gd_n0_m3: f64,
    /// A track spectrum instead of ISO 8608's (then `gd_n0_m3` is unused).
    pub track: Option<TrackClass>,
    pub n1_cycles_m: f64,
    pub n2_cycles_m: f64,
    pub spacing_m: f64,
    pub tyre_patch_m: Option<f64>,
}

/// FFT length for `n_samples` output samples: a power of two, at least twice the output
/// (no periodicity within it) and fine enough in frequency for the band's lower edge.
pub(crate) fn fft_len(n_samples: usize, band: &IsoBand) -> Result<usize> {
    let min_for_band = (LINES_PER_N1 / (band.n1_cycles_m * band.spacing_m)).ceil();
    let needed = (2.0 * n_samples as f64).max(min_for_band).max(16.0);
    if needed.is_nan() || needed > MAX_FFT_LEN as f64 {
        return Err(Error::invalid(
            "road length / sample_spacing_m",
            needed,
            format!(
                "needs an FFT of more than {MAX_FFT_LEN} samples; shorten the road or \
                 increase sample_spacing_m / n1_cycles_m"
            ),
        ));
    }
    Ok((needed as usize).next_power_of_two())
}

/// Amplitudes `A_k` of the lines `k` (frequency `k dn`) carrying the band `[n1, n2]`.
///
/// Line k stands for the bin `[(k - 1/2) dn, (k + 1/2) dn]`, cut to the band; the first and
/// last lines take the band's ends. `A_k^2 / 2 = G_d(n0) n0^2 (1/a - 1/b)` over `[a, b]`
/// (or a track spectrum's closed-form integral), so the energies telescope to the exact
/// band variance.
pub(crate) fn line_amplitudes(band: &IsoBand, nfft: usize) -> Vec<(usize, f64)> {
    let dn = 1.0 / (nfft as f64 * band.spacing_m);
    let k_top = nfft / 2 - 1; // below Nyquist: a line there would lose its sine part
    let k_lo = ((band.n1_cycles_m / dn + 0.5).floor() as usize).max(1);
    let k_hi = ((band.n2_cycles_m / dn + 0.5).floor() as usize).min(k_top);
    let c = band.gd_n0_m3 * N0_CYCLES_M * N0_CYCLES_M;
    // Twice the bin's variance: A_k^2 (ISO 8608 in closed form, or the track spectrum's).
    let twice_variance = |a: f64, b: f64| match band.track {
        Some(track) => 2.0 * track.band_variance_m2(a, b),
        None => 2.0 * c * (1.0 / a - 1.0 / b),
    };
    (k_lo..=k_hi)
        .filter_map(|k| {
            let kf = k as f64;
            let a = if k == k_lo {
                band.n1_cycles_m
            } else {
                (kf - 0.5) * dn
            };
            let b = if k == k_hi {
                band.n2_cycles_m
            } else {
                (kf + 0.5) * dn
            };
            (b > a).then(|| (k, twice_variance(a, b).sqrt()))
        })
        .collect()
}

/// Transfer function of a moving average of length `a` m at `n` cycle/m: `sinc(pi n a)`.
fn moving_average_gain(n_cycles_m: f64, length_m: f64) -> f64 {
    let u = std::f64::consts::PI * n_cycles_m * length_m;
    if u.abs() < 1e-12 {
        1.0
    } else {
        u.sin() / u
    }
}

/// One full FFT period of elevation (m) and exact slope (dr/dx) samples at `k dx`.
///
/// Both come from one complex inverse FFT: the Hermitian spectra of elevation `R` and
/// slope `S = i 2 pi n R` are packed as `Y = R + i S`, so `y = r + i s`. The moving-average
/// tyre filter is applied exactly (continuous average) as its gain `sinc(pi n a)`.
#[cfg(test)]
pub(crate) fn synthesize_period(
    band: &IsoBand,
    nfft: usize,
    rng: &mut ChaCha8Rng,
) -> (Vec<f64>, Vec<f64>) {
    synthesize(band, nfft, nfft, rng)
}

/// The first `n_samples` samples of one FFT period of elevation (m) and exact slope
/// (dr/dx) at `k dx` (see `synthesize_period`).
pub(crate) fn synthesize(
    band: &IsoBand,
    nfft: usize,
    n_samples: usize,
    rng: &mut ChaCha8Rng,
) -> (Vec<f64>, Vec<f64>) {
    let dn = 1.0 / (nfft as f64 * band.spacing_m);
    let two_pi = 2.0 * std::f64::consts::PI;
    let mut spectrum = vec![Complex::new(0.0, 0.0); nfft];
    for (k, amplitude) in line_amplitudes(band, nfft) {
        let phase = two_pi * rng.random::<f64>();
        let n = k as f64 * dn;
        let gain = band.tyre_patch_m.map_or(1.0, |a| moving_average_gain(n, a));
        let c = Complex::from_polar(0.5 * amplitude * gain, phase);
        let w = two_pi * n;
        // Y[k] = R[k] + i S[k] = c (1 - w); Y[N-k] = conj(c) + i conj(i w c) = conj(c) (1 + w).
        spectrum[k] = c * (1.0 - w);
        spectrum[nfft - k] = c.conj() * (1.0 + w);
    }
    let fft = FftPlanner::<f64>::new().plan_fft_inverse(nfft);
    fft.process(&mut spectrum);
    spectrum[..n_samples.min(nfft)]
        .iter()
        .map(|y| (y.re, y.im))
        .unzip()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::road::spec::iso8608_band_rms_m;
    use rand::SeedableRng;

    fn band(tyre_patch_m: Option<f64>) -> IsoBand {
        IsoBand {
            gd_n0_m3: 64e-6,
            track: None,
            n1_cycles_m: 0.01,
            n2_cycles_m: 4.0,
            spacing_m: 0.05,
            tyre_patch_m,
        }
    }

    #[test]
    fn fft_period_is_at_least_twice_the_road_and_resolves_n1() {
        // Twice the road: the profile never repeats within it. dn <= n1 / 8: the lowest
        // octave [n1, 2 n1] holds at least 8 lines even on a 10 m road.
        let b = band(None);
        for n_samples in [2, 201, 16_000, 100_001] {
            let nfft = fft_len(n_samples, &b).unwrap();
            assert!(nfft >= 2 * n_samples && nfft.is_power_of_two());
            assert!(1.0 / (nfft as f64 * b.spacing_m) <= b.n1_cycles_m / 8.0);
        }
    }

    #[test]
    fn full_period_mean_square_is_exactly_the_band_integral() {
        // The line energies telescope to the closed-form band variance, and Parseval makes
        // the period mean square equal to sum A_k^2 / 2 for any phases. Only rounding is
        // left: 1e-9 relative is ~1e6 ulps of margin for a 2^15-point FFT.
        let b = band(None);
        let nfft = fft_len(4000, &b).unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let (r, _) = synthesize_period(&b, nfft, &mut rng);
        let ms = r.iter().map(|z| z * z).sum::<f64>() / nfft as f64;
        let target = iso8608_band_rms_m(b.gd_n0_m3, b.n1_cycles_m, b.n2_cycles_m).powi(2);
        assert!((ms / target - 1.0).abs() < 1e-9, "ms {ms} target {target}");
    }

    #[test]
    fn packed_fft_matches_direct_harmonic_sum() {
        // Independent check of the spectrum packing: sum the cosines directly at a few
        // points. Tolerance 1e-12 m: rounding of ~1000 terms of ~1e-4 m.
        let b = IsoBand {
            n1_cycles_m: 0.5,
            ..band(Some(0.24))
        };
        let nfft = fft_len(100, &b).unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let (r, s) = synthesize_period(&b, nfft, &mut rng);
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let lines: Vec<(usize, f64, f64)> = line_amplitudes(&b, nfft)
            .into_iter()
            .map(|(k, a)| (k, a, 2.0 * std::f64::consts::PI * rng.random::<f64>()))
            .collect();
        let dn = 1.0 / (nfft as f64 * b.spacing_m);
        for j in [0, 1, 17, nfft / 3, nfft - 1] {
            let x = j as f64 * b.spacing_m;
            let (mut rd, mut sd) = (0.0, 0.0);
            for &(k, a, phi) in &lines {
                let n = k as f64 * dn;
                let g = moving_average_gain(n, 0.24);
                let th = 2.0 * std::f64::consts::PI * n * x + phi;
                rd += a * g * th.cos();
                sd -= a * g * 2.0 * std::f64::consts::PI * n * th.sin();
            }
            assert!((r[j] - rd).abs() < 1e-12, "r[{j}] {} vs {rd}", r[j]);
            assert!((s[j] - sd).abs() < 1e-11, "s[{j}] {} vs {sd}", s[j]);
        }
    }

    #[test]
    fn tyre_filter_reduces_mean_square_to_the_filtered_integral() {
        // Filtered variance = integral of G_d(n) sinc^2(pi n a) over the band. The synthesis
        // applies the gain at the line centre, a midpoint rule with dn ~ 6e-4 cycle/m whose
        // relative error is ~ (dn / n1)^2 / 24 ~ 1.5e-4; 1e-3 bounds it.
        let b = band(Some(0.24));
        let nfft = fft_len(4000, &b).unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let (r, _) = synthesize_period(&b, nfft, &mut rng);
        let ms = r.iter().map(|z| z * z).sum::<f64>() / nfft as f64;
        let m = 200_000;
        let h = (b.n2_cycles_m.ln() - b.n1_cycles_m.ln()) / m as f64;
        let integral: f64 = (0..m)
            .map(|i| {
                let n = (b.n1_cycles_m.ln() + (i as f64 + 0.5) * h).exp();
                let g = moving_average_gain(n, 0.24);
                crate::physics::road::spec::iso8608_psd_m3(b.gd_n0_m3, n) * g * g * n * h
            })
            .sum();
        assert!((ms / integral - 1.0).abs() < 1e-3, "ms {ms} vs {integral}");
        let unfiltered = iso8608_band_rms_m(b.gd_n0_m3, 0.01, 4.0).powi(2);
        assert!(ms < unfiltered);
    }
}
