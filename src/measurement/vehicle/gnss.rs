//! A GNSS receiver's error: position along the road and speed over ground, each with its
//! noise. The position error is a first-order Gauss-Markov process (the slowly wandering
//! error of multipath and atmosphere; white with `correlation_s = 0`), the speed error
//! white: a Doppler speed is far less correlated than a position.

use rand::RngExt;
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;

/// The noise of one receiver.
#[derive(Debug, Clone, PartialEq)]
pub struct GnssNoise {
    /// Standard deviation of the position error (m).
    pub position_sigma_m: f64,
    /// Correlation time of the position error (s); 0: white.
    pub correlation_s: f64,
    /// Standard deviation of the speed error (m/s).
    pub speed_sigma_m_s: f64,
}

/// The running error of one receiver sampling every `period_s`.
#[derive(Debug, Clone)]
pub struct GnssError {
    noise: GnssNoise,
    /// exp(-T / tau): the share of the last position error kept each fix.
    keep: f64,
    position_error_m: Option<f64>,
    rng: ChaCha8Rng,
}

impl GnssError {
    pub fn new(noise: GnssNoise, period_s: f64, rng: ChaCha8Rng) -> Self {
        let keep = match noise.correlation_s > 0.0 {
            true => (-period_s / noise.correlation_s).exp(),
            false => 0.0,
        };
        Self {
            noise,
            keep,
            position_error_m: None,
            rng,
        }
    }

    /// The (position, speed) errors of the next fix. The first position error is drawn
    /// from the stationary distribution; then `e' = k e + sigma sqrt(1 - k^2) w` keeps the
    /// variance at sigma^2 with the autocorrelation `k^n` at lag n (Gelb 1974, Applied
    /// Optimal Estimation, 3.8).
    pub fn draw(&mut self) -> (f64, f64) {
        let w: f64 = self.rng.sample(StandardNormal);
        let sigma = self.noise.position_sigma_m;
        let e = match self.position_error_m {
            None => sigma * w,
            Some(e) => self.keep * e + sigma * (1.0 - self.keep * self.keep).sqrt() * w,
        };
        self.position_error_m = Some(e);
        let v: f64 = self.rng.sample(StandardNormal);
        (e, self.noise.speed_sigma_m_s * v)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::base::random::child_rng;

    fn errors(correlation_s: f64, n: usize) -> Vec<f64> {
        let noise = GnssNoise {
            position_sigma_m: 2.0,
            correlation_s,
            speed_sigma_m_s: 0.1,
        };
        let mut e = GnssError::new(noise, 0.1, child_rng(1, "gnss"));
        (0..n).map(|_| e.draw().0).collect()
    }

    fn lag_correlation(x: &[f64], lag: usize) -> f64 {
        let n = x.len() - lag;
        let var = x.iter().map(|v| v * v).sum::<f64>() / x.len() as f64;
        (0..n).map(|i| x[i] * x[i + lag]).sum::<f64>() / n as f64 / var
    }

    #[test]
    fn the_position_error_has_its_sigma_and_correlation_time() {
        // 200 000 fixes at 10 Hz with tau = 5 s: 4000 correlation times, so the variance
        // is known to ~sqrt(2 / 4000) = 2.2 % and the lag-50 correlation (e^-1) to ~0.03.
        let x = errors(5.0, 200_000);
        let rms = (x.iter().map(|v| v * v).sum::<f64>() / x.len() as f64).sqrt();
        assert!((rms / 2.0 - 1.0).abs() < 0.07, "rms {rms}");
        let r = lag_correlation(&x, 50);
        assert!((r - (-1.0f64).exp()).abs() < 0.06, "lag-50 correlation {r}");
        // White without a correlation time.
        let w = errors(0.0, 20_000);
        assert!(lag_correlation(&w, 1).abs() < 0.03);
    }
}
