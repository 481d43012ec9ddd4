//! Butterworth band-pass filter for the ambient force: a Butterworth high-pass at the low
//! edge cascaded with a Butterworth low-pass at the high edge, each of order
//! [`EDGE_ORDER`], realised as second-order sections designed by the bilinear transform
//! with pre-warped edges (Oppenheim & Schafer, Discrete-Time Signal Processing, 3rd ed.,
//! section 7.2; second-order section formulas as in R. Bristow-Johnson's "Audio EQ
//! Cookbook").
//!
//! Pre-warping makes the digital response exactly
//! `|H(f)|^2 = 1 / (1 + (t_lo / t)^2n) * 1 / (1 + (t / t_hi)^2n)` with `t = tan(pi f dt)`,
//! `t_lo = tan(pi f_lo dt)`, `t_hi = tan(pi f_hi dt)`: half power at both edges, a zero at
//! DC and at Nyquist. [`BandPass::butterworth_gain_squared`] is that closed form; the
//! calibration integrates [`BandPass::gain_squared`], evaluated from the coefficients
//! actually used, and the tests pin the two to each other.
//!
//! A cascade of a high-pass and a low-pass is used instead of the low-pass-to-band-pass
//! transformation: for the wide bands of ambient excitation (a decade or more) the two are
//! indistinguishable, and the cascade keeps every section a plain Butterworth pair whose
//! poles stay well conditioned even when the low edge is 1e-4 of the sample rate.

use std::f64::consts::PI;

use nalgebra::Complex;

use crate::error::{num, Error, Result};

/// Order of the Butterworth high-pass and of the low-pass that bound the band (each): 24 dB
/// per octave outside the band. Even, so that both are whole second-order sections.
pub const EDGE_ORDER: usize = 4;

/// Second-order sections: `EDGE_ORDER / 2` high-pass followed by `EDGE_ORDER / 2` low-pass.
pub const SECTIONS: usize = EDGE_ORDER;

/// One second-order section `H(z) = (b0 + b1 z^-1 + b2 z^-2) / (1 + a1 z^-1 + a2 z^-2)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Biquad {
    /// Numerator `[b0, b1, b2]`.
    pub b: [f64; 3],
    /// Denominator `[a1, a2]` (a0 = 1).
    pub a: [f64; 2],
}

/// Which side of the band a section shapes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Edge {
    HighPass,
    LowPass,
}

impl Biquad {
    /// Bilinear transform of `w_c^2 / (s^2 + w_c s / q + w_c^2)` (low-pass) or
    /// `s^2 / (...)` (high-pass), with `k = tan(pi f_c dt)` the pre-warped edge.
    fn butterworth(edge: Edge, k: f64, q: f64) -> Self {
        let norm = 1.0 / (1.0 + k / q + k * k);
        let a = [2.0 * (k * k - 1.0) * norm, (1.0 - k / q + k * k) * norm];
        let b = match edge {
            Edge::LowPass => {
                let b0 = k * k * norm;
                [b0, 2.0 * b0, b0]
            }
            Edge::HighPass => [norm, -2.0 * norm, norm],
        };
        Biquad { b, a }
    }

    /// Complex response at the normalised angular frequency `theta = 2 pi f dt` (rad).
    pub fn response(&self, theta: f64) -> Complex<f64> {
        let z1 = Complex::from_polar(1.0, -theta);
        let z2 = z1 * z1;
        let num = self.b[0] + z1 * self.b[1] + z2 * self.b[2];
        let den = 1.0 + z1 * self.a[0] + z2 * self.a[1];
        num / den
    }

    /// Largest pole modulus (< 1 for a stable section): how slowly its transient decays.
    pub fn pole_radius(&self) -> f64 {
        let [a1, a2] = self.a;
        let disc = a1 * a1 - 4.0 * a2;
        if disc < 0.0 {
            // Complex pair: |p|^2 = p p* = a2.
            a2.sqrt()
        } else {
            let root = disc.sqrt();
            (0.5 * (-a1 + root)).abs().max((0.5 * (-a1 - root)).abs())
        }
    }
}

/// The designed band-pass: coefficients only, no state (see [`FilterBank`]).
#[derive(Debug, Clone, PartialEq)]
pub struct BandPass {
    sections: [Biquad; SECTIONS],
    low_hz: f64,
    high_hz: f64,
    dt_s: f64,
}

impl BandPass {
    /// Designs the filter for the band `band_hz = [low, high]` at step `dt_s`.
    /// Requires `0 < low < high < 1 / (2 dt)`; errors name `field` (the scenario path of
    /// the band, e.g. `ambient.band_hz`) or `dt_s`.
    pub fn new(band_hz: [f64; 2], dt_s: f64, field: &str) -> Result<Self> {
        validate_band(band_hz, dt_s, field)?;
        let [low_hz, high_hz] = band_hz;
        let k_low = (PI * low_hz * dt_s).tan();
        let k_high = (PI * high_hz * dt_s).tan();
        let mut sections = [Biquad {
            b: [0.0; 3],
            a: [0.0; 2],
        }; SECTIONS];
        let pairs = EDGE_ORDER / 2;
        for p in 0..pairs {
            let q = butterworth_q(p);
            sections[p] = Biquad::butterworth(Edge::HighPass, k_low, q);
            sections[pairs + p] = Biquad::butterworth(Edge::LowPass, k_high, q);
        }
        Ok(BandPass {
            sections,
            low_hz,
            high_hz,
            dt_s,
        })
    }

    /// The second-order sections, high-pass first.
    pub fn sections(&self) -> &[Biquad; SECTIONS] {
        &self.sections
    }

    /// Pass band `[low, high]` (Hz).
    pub fn band_hz(&self) -> [f64; 2] {
        [self.low_hz, self.high_hz]
    }

    /// Sample interval (s).
    pub fn dt_s(&self) -> f64 {
        self.dt_s
    }

    /// `|H(f)|^2` evaluated from the section coefficients.
    pub fn gain_squared(&self, f_hz: f64) -> f64 {
        let theta = 2.0 * PI * f_hz * self.dt_s;
        self.sections
            .iter()
            .map(|s| s.response(theta).norm_sqr())
            .product()
    }

    /// The closed form of `|H(f)|^2` for an ideal pre-warped Butterworth design (module doc).
    pub fn butterworth_gain_squared(&self, f_hz: f64) -> f64 {
        let t = (PI * f_hz * self.dt_s).tan().abs();
        if t == 0.0 {
            return 0.0;
        }
        let n2 = 2 * EDGE_ORDER as i32;
        let t_low = (PI * self.low_hz * self.dt_s).tan();
        let t_high = (PI * self.high_hz * self.dt_s).tan();
        1.0 / (1.0 + (t_low / t).powi(n2)) / (1.0 + (t / t_high).powi(n2))
    }

    /// Steps after which a transient of the filter has decayed by `factor` (e.g. 1e-3),
    /// from the slowest pole: `ln(factor) / ln(r_max)`.
    pub fn settling_steps(&self, factor: f64) -> usize {
        let r_max = self
            .sections
            .iter()
            .map(Biquad::pole_radius)
            .fold(0.0, f64::max);
        if r_max <= 0.0 {
            return 0;
        }
        (factor.ln() / r_max.ln()).ceil().max(0.0) as usize
    }
}

/// Q of the `p`-th pole pair of an order-`EDGE_ORDER` Butterworth filter:
/// `1 / (2 cos((2 p + 1) pi / (2 n)))`.
fn butterworth_q(p: usize) -> f64 {
    let theta = (2 * p + 1) as f64 * PI / (2 * EDGE_ORDER) as f64;
    1.0 / (2.0 * theta.cos())
}

fn validate_band(band_hz: [f64; 2], dt_s: f64, field: &str) -> Result<()> {
    crate::error::require_positive("dt_s", dt_s)?;
    let [low, high] = band_hz;
    let nyquist_hz = 0.5 / dt_s;
    let shown = format!("[{}, {}]", num(low), num(high));
    if !(low.is_finite() && high.is_finite()) {
        return Err(Error::invalid(field, shown, "must hold two finite numbers"));
    }
    if low <= 0.0 {
        return Err(Error::invalid(
            field,
            shown,
            "must have a low edge > 0 Hz (a force with a DC part drifts the bridge)",
        ));
    }
    if high <= low {
        return Err(Error::invalid(
            field,
            shown,
            "must be [low, high] with low < high",
        ));
    }
    if high >= nyquist_hz {
        return Err(Error::invalid(
            field,
            shown,
            format!(
                "must have a high edge below the solver Nyquist frequency {} Hz (dt_s = {})",
                num(nyquist_hz),
                num(dt_s)
            ),
        ));
    }
    Ok(())
}

/// Independent channels filtered by one [`BandPass`]: the state of every section of every
/// channel lives in one preallocated buffer, so [`FilterBank::process`] never allocates.
#[derive(Debug, Clone)]
pub struct FilterBank {
    band: BandPass,
    /// Transposed direct form II state `[s1, s2]` per section, channel-major.
    state: Vec<[f64; 2]>,
}

impl FilterBank {
    /// `channels` channels at rest.
    pub fn new(band: BandPass, channels: usize) -> Self {
        FilterBank {
            band,
            state: vec![[0.0; 2]; channels * SECTIONS],
        }
    }

    /// The filter.
    pub fn band(&self) -> &BandPass {
        &self.band
    }

    /// Number of channels.
    pub fn channels(&self) -> usize {
        self.state.len() / SECTIONS
    }

    /// Feeds `x` to channel `channel` and returns its output. Transposed direct form II
    /// (one multiply-add chain per section, the form with the best round-off for f64).
    pub fn process(&mut self, channel: usize, x: f64) -> f64 {
        let states = &mut self.state[channel * SECTIONS..(channel + 1) * SECTIONS];
        let mut y = x;
        for (s, section) in states.iter_mut().zip(&self.band.sections) {
            let input = y;
            y = section.b[0] * input + s[0];
            s[0] = section.b[1] * input - section.a[0] * y + s[1];
            s[1] = section.b[2] * input - section.a[1] * y;
        }
        y
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn band(low: f64, high: f64, dt: f64) -> BandPass {
        BandPass::new([low, high], dt, "ambient.band_hz").unwrap()
    }

    #[test]
    fn sections_match_the_closed_form_butterworth() {
        // Both are the same rational function; only round-off separates them. The worst
        // case is the high-pass near DC, where numerator and denominator cancel down to
        // ~(f dt)^2 ~ 1e-9: relative round-off ~1e-16 / 1e-9 = 1e-7 would already be
        // visible, 1e-6 leaves a margin. Far in the stop band (gain < 1e-12 of the pass
        // band) the cancellation is total and only the absolute error is meaningful.
        for (low, high, dt) in [(0.5, 30.0, 0.002), (0.05, 80.0, 0.001), (2.0, 6.0, 0.01)] {
            let bp = band(low, high, dt);
            let nyquist = 0.5 / dt;
            for i in 1..2000 {
                let f = nyquist * (i as f64 / 2000.0).powi(3);
                let (got, want) = (bp.gain_squared(f), bp.butterworth_gain_squared(f));
                assert!(
                    (got - want).abs() <= 1e-6 * want + 1e-12,
                    "f = {f}: {got} vs {want}"
                );
            }
            // Half power at each edge, up to the other edge's small skirt.
            let lo_edge = bp.butterworth_gain_squared(low);
            assert!((lo_edge - 0.5).abs() < 0.5 * 0.01, "{lo_edge}");
        }
    }

    #[test]
    fn impulse_response_energy_is_the_integral_of_the_gain() {
        // Parseval: sum h_k^2 = 2 dt * integral_0^{fs/2} |H|^2 df. The integral is done
        // here by a plain fine midpoint rule (independent of the calibration's grid); a
        // 1e-4 relative error bounds both the rule's error and the impulse truncation
        // (the response has decayed by 1e-12 in energy).
        let dt = 0.004;
        let bp = band(0.5, 30.0, dt);
        let mut bank = FilterBank::new(bp.clone(), 1);
        let steps = bp.settling_steps(1e-6) * 2;
        let energy: f64 = (0..steps)
            .map(|k| bank.process(0, if k == 0 { 1.0 } else { 0.0 }).powi(2))
            .sum();
        let n = 400_000;
        let df = 0.5 / dt / n as f64;
        let integral: f64 = (0..n)
            .map(|i| bp.gain_squared((i as f64 + 0.5) * df) * df)
            .sum();
        let expected = 2.0 * dt * integral;
        assert!(
            (energy / expected - 1.0).abs() < 1e-4,
            "{energy} vs {expected}"
        );
    }

    #[test]
    fn stop_bands_fall_at_24_db_per_octave() {
        // Closed form with n = 4: an octave outside an edge, |H|^2 ~ 1 / (1 + 2^8) = -24 dB
        // (the pre-warp moves it slightly at the high edge).
        let bp = band(0.5, 30.0, 0.002);
        let db = |f: f64| 10.0 * bp.gain_squared(f).log10();
        assert!((db(0.25) + 24.1).abs() < 0.2, "{}", db(0.25));
        assert!((db(60.0) + 24.1).abs() < 1.5, "{}", db(60.0));
        assert_eq!(bp.gain_squared(0.0), 0.0);
        assert!(bp.gain_squared(250.0) < 1e-20);
        assert!((db(4.0)).abs() < 0.01);
    }

    #[test]
    fn bad_bands_name_the_field_and_the_value() {
        let cases = [
            (
                [0.0, 30.0],
                0.002,
                "ambient.band_hz = [0, 30] must have a low edge > 0",
            ),
            (
                [5.0, 5.0],
                0.002,
                "ambient.band_hz = [5, 5] must be [low, high]",
            ),
            (
                [0.5, 250.0],
                0.002,
                "ambient.band_hz = [0.5, 250] must have a high edge",
            ),
            (
                [f64::NAN, 3.0],
                0.002,
                "ambient.band_hz = [NaN, 3] must hold",
            ),
            ([0.5, 30.0], -1.0, "dt_s = -1"),
        ];
        for (b, dt, start) in cases {
            let e = BandPass::new(b, dt, "ambient.band_hz")
                .unwrap_err()
                .to_string();
            assert!(e.starts_with(start), "{e}");
        }
    }
}
