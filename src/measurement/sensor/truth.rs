//! The noise-free truth at a sensor's output instants: cubic Hermite interpolation of the
//! solver samples, no filter.
//!
//! On the interval `[n0, n0 + 1]` (unit step, `t = frac`):
//! `p(t) = h00(t) x0 + h10(t) m0 + h01(t) x1 + h11(t) m1`, with the cubic Hermite basis
//! `h00 = 2t^3 - 3t^2 + 1`, `h10 = t^3 - 2t^2 + t`, `h01 = -2t^3 + 3t^2`, `h11 = t^3 - t^2`,
//! and slopes from the fourth-order central difference
//! `m_i = (x_{i-2} - 8 x_{i-1} + 8 x_{i+1} - x_{i+2}) / 12`. The slopes are exact for
//! quartics and the basis for cubics, so cubics are reproduced exactly and the error is
//! O(dt^4); the interpolant is C1 (each node's slope is shared by both intervals). Needs
//! solver samples `n0 - 2 ..= n0 + 3`: 3 steps of latency.

use super::resample::Rates;
use super::schedule::OutputSchedule;
use crate::base::rate::ExactRate;
use crate::error::Result;

/// Samples needed before the output interval.
pub const HERMITE_LOOKBACK: usize = 2;
/// Samples needed after the start of the output interval.
pub const HERMITE_LOOKAHEAD: usize = 3;

/// Hermite value at `frac` after `window[centre]`; `window` holds at least samples
/// `centre - 2 ..= centre + 3` unless `frac == 0`, when it returns `window[centre]`.
pub fn hermite(frac: f64, window: &[f64], centre: usize) -> f64 {
    if frac == 0.0 {
        return window[centre];
    }
    let x = &window[centre - HERMITE_LOOKBACK..=centre + HERMITE_LOOKAHEAD];
    let (xm2, xm1, x0, x1, x2, x3) = (x[0], x[1], x[2], x[3], x[4], x[5]);
    let m0 = (xm2 - 8.0 * xm1 + 8.0 * x1 - x2) / 12.0;
    let m1 = (xm1 - 8.0 * x0 + 8.0 * x2 - x3) / 12.0;
    let t = frac;
    let t2 = t * t;
    let t3 = t2 * t;
    let h00 = 2.0 * t3 - 3.0 * t2 + 1.0;
    let h10 = t3 - 2.0 * t2 + t;
    let h01 = -2.0 * t3 + 3.0 * t2;
    let h11 = t3 - t2;
    h00 * x0 + h10 * m0 + h01 * x1 + h11 * m1
}

/// Streaming truth interpolator: the noise-free value at the output instants
/// `t_k = round(k * 1e9 / fs_out)` ns. Same schedule, start hold and [`flush`] hold as
/// [`super::Resampler`]; latency 3 solver steps (0 when `fs_out == fs_in`, where the solver
/// samples are the truth).
///
/// [`flush`]: TruthInterpolator::flush
#[derive(Debug)]
pub struct TruthInterpolator {
    schedule: OutputSchedule,
}

impl TruthInterpolator {
    /// From the solver rate `fs_in_hz` to `fs_out_hz` (field `<field_prefix>.rate_hz`).
    pub fn new(fs_in_hz: f64, fs_out_hz: f64, field_prefix: &str) -> Result<Self> {
        let rates = Rates::new(fs_in_hz, fs_out_hz, field_prefix)?;
        let (back, ahead) = if rates.same {
            (0, 0)
        } else {
            (HERMITE_LOOKBACK, HERMITE_LOOKAHEAD)
        };
        Ok(Self {
            schedule: OutputSchedule::new(rates.out, rates.dt_ns, back, ahead),
        })
    }

    /// Pushes the next solver sample; `emit(t_ns, truth)` for each completed output.
    pub fn push(&mut self, value: f64, mut emit: impl FnMut(u64, f64)) -> usize {
        let centre = self.schedule.centre();
        self.schedule
            .push(value, |d| emit(d.t_ns, hermite(d.frac, d.window, centre)))
    }

    /// Emits the outputs up to the last solver instant (holding the last value).
    pub fn flush(&mut self, mut emit: impl FnMut(u64, f64)) -> usize {
        let centre = self.schedule.centre();
        self.schedule
            .flush(|d| emit(d.t_ns, hermite(d.frac, d.window, centre)))
    }

    /// Largest delay between an output instant and the push that emits it.
    pub fn latency_ns(&self) -> u64 {
        self.schedule.lookahead() as u64 * self.schedule.dt_ns()
    }

    /// Output rate in Hz.
    pub fn rate_hz(&self) -> f64 {
        let rate: ExactRate = self.schedule.rate();
        rate.hz()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cubics_are_reproduced_exactly() {
        let p = |x: f64| 0.3 - 1.1 * x + 0.25 * x * x - 0.04 * x * x * x;
        let window: Vec<f64> = (-2..=3).map(|i| p(i as f64)).collect();
        for frac in [0.0, 0.1, 0.5, 0.77, 0.999] {
            let got = hermite(frac, &window, 2);
            assert!(
                (got - p(frac)).abs() < 1e-14,
                "{frac}: {got} vs {}",
                p(frac)
            );
        }
    }

    #[test]
    fn error_is_fourth_order() {
        // sin sampled at step h, evaluated at frac = 0.37: halving h must divide the
        // error by ~16 (between 14 and 18 allows for the next-order term).
        let err = |h: f64| {
            let w: Vec<f64> = (-2..=3).map(|i| (1.0 + i as f64 * h).sin()).collect();
            (hermite(0.37, &w, 2) - (1.0 + 0.37 * h).sin()).abs()
        };
        let (e1, e2) = (err(0.2), err(0.1));
        let ratio = e1 / e2;
        assert!((14.0..18.0).contains(&ratio), "{e1:e} {e2:e} ratio {ratio}");
    }

    #[test]
    fn streaming_truth_hits_the_solver_samples_at_common_instants() {
        // 250 Hz out of 1 kHz: every output instant is a solver instant.
        let mut t = TruthInterpolator::new(1000.0, 250.0, "s").unwrap();
        let mut out = Vec::new();
        for i in 0..40 {
            t.push((i as f64 * 0.1).sin(), |t_ns, v| out.push((t_ns, v)));
        }
        t.flush(|t_ns, v| out.push((t_ns, v)));
        assert_eq!(out.len(), 10);
        for (k, (t_ns, v)) in out.iter().enumerate() {
            assert_eq!(*t_ns, 4_000_000 * k as u64);
            assert_eq!(*v, (4.0 * k as f64 * 0.1).sin());
        }
    }
}
