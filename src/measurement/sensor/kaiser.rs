//! Continuous Kaiser-windowed-sinc low-pass kernel and its polyphase table.
//!
//! Kernel, with `x` in solver samples and `f_c` the cutoff in cycles per solver sample
//! (Kaiser and Schafer 1980; Oppenheim and Schafer, *Discrete-Time Signal Processing*,
//! 3rd ed., section 7.6):
//! `h(x) = 2 f_c sinc(2 f_c x) w(x / L)` for `|x| <= L`, Kaiser window
//! `w(r) = (I0(beta sqrt(1 - r^2)) - 1) / (I0(beta) - 1)`,
//! with `beta = 0.1102 (A - 8.7)` for `A > 50` dB, `0.5842 (A - 21)^0.4 + 0.07886 (A - 21)`
//! for `21 <= A <= 50` (here `A >= 30`), and length `N = (A - 7.95) / (2.285 dw) + 1` taps for a transition
//! band `dw` (rad/sample); `L = ceil((N - 1) / 2)`.
//!
//! The window is shifted by its edge value (`- 1`) so that it reaches zero at `|x| = L`:
//! the standard Kaiser window stops at `1 / I0(beta)` (0.3 % at 80 dB), a jump that a
//! continuous kernel read at arbitrary offsets would carry into every output as a
//! phase-dependent error (5.8e-6 for 200 Hz out of 1 kHz, the whole error of the phase
//! interpolation at 512 phases). The shift changes the window by < 1 / I0(beta) and
//! keeps the design's attenuation (checked in `tests/suite/sensor_chain.rs`).
//!
//! The table holds `h` at `P + 1` equally spaced fractional offsets (phases) for the
//! `2L + 1` samples around an output instant; between phases the weights are interpolated
//! linearly. Every phase is normalised to unit sum, so DC passes exactly, and the
//! interpolated weights (a convex combination of two rows) keep unit sum.

use crate::base::dot::dot;
use std::f64::consts::PI;
use std::sync::{Arc, Mutex, OnceLock};

/// Design of one kernel, all frequencies in cycles per solver sample.
#[derive(Debug, Clone, Copy)]
pub(crate) struct KaiserDesign {
    /// Cutoff (middle of the transition band).
    pub cutoff: f64,
    /// Transition band width.
    pub transition: f64,
    /// Stop-band attenuation in dB (>= 30).
    pub attenuation_db: f64,
    /// Number of phases; `None`: the smallest power of two that keeps the linear
    /// interpolation error 40 dB below the stop-band ripple (see `auto_phases`).
    pub phases: Option<usize>,
}

/// Kernel half-width and shape.
#[derive(Debug, Clone, Copy)]
struct Kaiser {
    cutoff: f64,
    half_width: usize,
    beta: f64,
    i0_beta: f64,
}

impl Kaiser {
    fn new(design: &KaiserDesign) -> Self {
        let a = design.attenuation_db;
        // Callers validate A >= 30 dB, so beta > 2 and I0(beta) - 1 > 0.
        let beta = if a > 50.0 {
            0.1102 * (a - 8.7)
        } else {
            0.5842 * (a - 21.0).max(0.0).powf(0.4) + 0.07886 * (a - 21.0).max(0.0)
        };
        let dw = 2.0 * PI * design.transition;
        let taps = (a - 7.95) / (2.285 * dw) + 1.0;
        let half_width = ((taps - 1.0) / 2.0).ceil().max(1.0) as usize;
        Self {
            cutoff: design.cutoff,
            half_width,
            beta,
            i0_beta: bessel_i0(beta),
        }
    }

    /// `h(x)`, zero outside `|x| <= L`; even in `x` bit for bit.
    fn eval(&self, x: f64) -> f64 {
        let x = x.abs();
        let l = self.half_width as f64;
        if x > l {
            return 0.0;
        }
        let r = x / l;
        let window =
            (bessel_i0(self.beta * (1.0 - r * r).max(0.0).sqrt()) - 1.0) / (self.i0_beta - 1.0);
        2.0 * self.cutoff * sinc(2.0 * self.cutoff * x) * window
    }
}

/// `sin(pi u) / (pi u)`.
fn sinc(u: f64) -> f64 {
    if u == 0.0 {
        1.0
    } else {
        let p = PI * u;
        p.sin() / p
    }
}

/// Modified Bessel function of the first kind, order 0, by its power series
/// `sum ((x/2)^k / k!)^2` (Abramowitz and Stegun 9.6.12); all terms are positive, so the
/// sum is accurate to rounding for the `x <= 30` used here.
pub(crate) fn bessel_i0(x: f64) -> f64 {
    let q = 0.25 * x * x;
    let mut term = 1.0;
    let mut sum = 1.0;
    let mut k = 1.0;
    while term > 1e-17 * sum {
        term *= q / (k * k);
        sum += term;
        k += 1.0;
    }
    sum
}

/// Phases for linear interpolation error `(2 pi f_c)^2 / (2 P^2)` (second derivative of
/// the sinc main lobe, summed over the taps) below 1 % of the stop-band ripple
/// `10^(-A/20)`. The table size `(P + 1)(2L + 1)` is then about the same for every rate
/// ratio (P grows with `f_c`, L with `1 / f_c`): ~0.1 M entries at 80 dB.
fn auto_phases(cutoff: f64, attenuation_db: f64) -> usize {
    let ripple = 10f64.powf(-attenuation_db / 20.0);
    let p = 2.0 * PI * cutoff * (50.0 / ripple).sqrt();
    (p.ceil().clamp(1.0, 65_536.0) as usize).next_power_of_two()
}

/// The polyphase table; see the module doc.
#[derive(Debug, Clone)]
pub(crate) struct PolyphaseKernel {
    kaiser: Kaiser,
    half_width: usize,
    phases: usize,
    /// `phases + 1` rows of `2 half_width + 1` weights, each built on first use. Row `p`
    /// is the offset `frac = p / phases`; weight `j` multiplies solver sample
    /// `n0 - half_width + j`, at distance `x = frac + half_width - j` from the output
    /// instant. A channel whose output instants fall on solver samples reads one row (a
    /// 200 Hz channel of a 1 kHz run with no clock error); building all ~500 rows up front
    /// took longer than the loop of a short run.
    table: Vec<OnceLock<Box<[f64]>>>,
}

impl PolyphaseKernel {
    /// Half-width `L` and phase count `P` the design leads to, before building anything.
    pub(crate) fn planned_size(design: &KaiserDesign) -> (usize, usize) {
        let phases = design
            .phases
            .unwrap_or_else(|| auto_phases(design.cutoff, design.attenuation_db))
            .max(1);
        (Kaiser::new(design).half_width, phases)
    }

    /// The kernel of `design`, built once per process and shared: sensors with the same
    /// rate (and every run of a sweep) use one table, and a row built for one is built
    /// for all. Each row costs taps Bessel and sine evaluations.
    pub(crate) fn shared(design: &KaiserDesign) -> Arc<Self> {
        /// Distinct designs kept; the oldest is dropped beyond this (runs use a handful).
        const CAPACITY: usize = 16;
        type Cache = Mutex<Vec<([u64; 4], Arc<PolyphaseKernel>)>>;
        static CACHE: OnceLock<Cache> = OnceLock::new();
        let key = [
            design.cutoff.to_bits(),
            design.transition.to_bits(),
            design.attenuation_db.to_bits(),
            design.phases.map_or(u64::MAX, |p| p as u64),
        ];
        let cache = CACHE.get_or_init(|| Mutex::new(Vec::new()));
        // A poisoned lock only means another thread panicked mid-insert: the data is a
        // plain list of finished kernels, still valid.
        let mut kernels = cache.lock().unwrap_or_else(|e| e.into_inner());
        if let Some((_, kernel)) = kernels.iter().find(|(k, _)| *k == key) {
            return Arc::clone(kernel);
        }
        let kernel = Arc::new(Self::new(design));
        if kernels.len() == CAPACITY {
            kernels.remove(0);
        }
        kernels.push((key, Arc::clone(&kernel)));
        kernel
    }

    pub(crate) fn new(design: &KaiserDesign) -> Self {
        let kaiser = Kaiser::new(design);
        let (half_width, phases) = Self::planned_size(design);
        Self {
            kaiser,
            half_width,
            phases,
            table: (0..=phases).map(|_| OnceLock::new()).collect(),
        }
    }

    /// Row `p` of the table (built on first use), normalised to unit sum. Every weight sits
    /// at `x = frac + L - j = i / P` for an integer `i`, evaluated at `|i| / P`: with `P` a
    /// power of two that is exact, so the weights are the same bits as `h(x)` at each
    /// entry, and `h` is even bit for bit.
    fn row(&self, p: usize) -> &[f64] {
        self.table[p].get_or_init(|| {
            let (half_width, phases) = (self.half_width as i64, self.phases as i64);
            let mut row: Box<[f64]> = (0..self.taps() as i64)
                .map(|j| {
                    let i = p as i64 + (half_width - j) * phases;
                    self.kaiser.eval(i.unsigned_abs() as f64 / phases as f64)
                })
                .collect();
            let sum: f64 = row.iter().sum();
            row.iter_mut().for_each(|w| *w /= sum);
            row
        })
    }

    /// `L`: samples needed on each side of the output instant.
    pub(crate) fn half_width(&self) -> usize {
        self.half_width
    }

    /// Number of taps, `2 L + 1` (the first is zero unless `frac == 0`).
    pub(crate) fn taps(&self) -> usize {
        2 * self.half_width + 1
    }

    /// Number of table phases.
    pub(crate) fn phases(&self) -> usize {
        self.phases
    }

    /// Weight `j` at offset `frac`, interpolated between phases.
    #[cfg(test)]
    pub(crate) fn weight(&self, frac: f64, j: usize) -> f64 {
        let (p, mu) = self.phase(frac);
        (1.0 - mu) * self.row(p)[j] + mu * self.row(p + 1)[j]
    }

    fn phase(&self, frac: f64) -> (usize, f64) {
        let s = frac * self.phases as f64;
        let p = (s.floor() as usize).min(self.phases - 1);
        (p, s - p as f64)
    }

    /// Filtered value at `frac` after the centre sample of `samples`, which holds the
    /// `2 L + 1` solver samples `n0 - L ..= n0 + L`. O(taps), no allocation.
    pub(crate) fn apply(&self, frac: f64, samples: &[f64]) -> f64 {
        let (p, mu) = self.phase(frac);
        let y_lo = dot(self.row(p), samples);
        if mu == 0.0 {
            return y_lo;
        }
        (1.0 - mu) * y_lo + mu * dot(self.row(p + 1), samples)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn design_200_of_1000() -> KaiserDesign {
        KaiserDesign {
            cutoff: 0.45 * 200.0 / 1000.0,
            transition: 0.1 * 200.0 / 1000.0,
            attenuation_db: 80.0,
            phases: None,
        }
    }

    #[test]
    fn bessel_i0_matches_tables() {
        // Abramowitz and Stegun table 9.8: I0(1) = 1.266065878, e^-5 I0(5) = 0.1835408126.
        assert!((bessel_i0(0.0) - 1.0).abs() < 1e-15);
        assert!((bessel_i0(1.0) - 1.266_065_878).abs() < 1e-9);
        assert!((bessel_i0(5.0) * (-5f64).exp() - 0.183_540_812_6).abs() < 1e-10);
    }

    #[test]
    fn kaiser_length_follows_the_formula() {
        // N = (80 - 7.95) / (2.285 * 2 pi * 0.02) + 1 = 251.9; L = ceil(125.45) = 126.
        let k = PolyphaseKernel::new(&design_200_of_1000());
        assert_eq!(k.half_width(), 126);
        assert_eq!(k.taps(), 253);
        assert_eq!(k.phases(), 512);
    }

    #[test]
    fn rows_are_symmetric_and_sum_to_one() {
        let k = PolyphaseKernel::new(&design_200_of_1000());
        let w = k.taps();
        let row0: Vec<f64> = (0..w).map(|j| k.weight(0.0, j)).collect();
        for j in 0..w {
            assert_eq!(row0[j], row0[w - 1 - j]);
        }
        // frac = 0.5: weights j and (w - 2 - j) are at x = +-(L + 0.5 - j).
        let half: Vec<f64> = (0..w).map(|j| k.weight(0.5, j)).collect();
        for j in 1..w - 1 {
            assert!((half[j] - half[w - j]).abs() < 1e-16, "{j}");
        }
        for frac in [0.0, 0.123, 0.5, 0.999] {
            let s: f64 = (0..w).map(|j| k.weight(frac, j)).sum();
            assert!((s - 1.0).abs() < 1e-14, "{frac}: {s}");
        }
    }

    #[test]
    fn phase_interpolation_error_is_far_below_the_stop_band() {
        // Against the kernel evaluated directly (normalised the same way): the summed
        // absolute weight error bounds the output error for a unit-amplitude input and must
        // stay under 1 % of the 80 dB ripple (1e-6), the design rule of `auto_phases`.
        let design = design_200_of_1000();
        let k = PolyphaseKernel::new(&design);
        let kaiser = Kaiser::new(&design);
        let w = k.taps();
        let l = k.half_width() as f64;
        let mut worst: f64 = 0.0;
        for i in 0..997 {
            let frac = (i as f64 + 0.37) / 997.0;
            let exact: Vec<f64> = (0..w).map(|j| kaiser.eval(frac + l - j as f64)).collect();
            let sum: f64 = exact.iter().sum();
            let err: f64 = (0..w)
                .map(|j| (k.weight(frac, j) - exact[j] / sum).abs())
                .sum();
            worst = worst.max(err);
        }
        assert!(worst < 1e-6, "worst summed weight error {worst:e}");
    }

    #[test]
    fn dot_matches_naive() {
        let a: Vec<f64> = (0..11).map(|i| i as f64 * 0.5).collect();
        let b: Vec<f64> = (0..11).map(|i| 1.0 - i as f64).collect();
        let naive: f64 = a.iter().zip(&b).map(|(x, y)| x * y).sum();
        assert!((dot(&a, &b) - naive).abs() < 1e-12);
    }
}
