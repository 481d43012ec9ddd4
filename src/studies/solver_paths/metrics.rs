//! Error metrics between two crossing histories, on the coarser of their time grids:
//! the midspan deflection (max-norm relative to the peak), the midspan acceleration
//! low-passed to 50 Hz (max-norm and RMS, relative), the tyre forces while on the span
//! (max error over the static load), and the quick peak-only metrics the bench reports.

use rustfft::num_complex::Complex;
use rustfft::FftPlanner;
use serde::Serialize;

use super::history::History;

/// Pass band edge of the acceleration filter (Hz): unity gain below.
pub const PASS_HZ: f64 = 45.0;
/// Stop band edge (Hz): zero gain above; the gain is 1/2 at 50 Hz.
pub const STOP_HZ: f64 = 55.0;

/// The errors of one history against a reference.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct PathErrors {
    /// max |u - u_ref| / max |u_ref| at midspan.
    pub deflection: f64,
    /// max |a - a_ref| / max |a_ref|, both low-passed to 50 Hz.
    pub acceleration_max: f64,
    /// RMS(a - a_ref) / RMS(a_ref), both low-passed to 50 Hz.
    pub acceleration_rms: f64,
    /// max over both axles, while on the span, of |F - F_ref| / F_static.
    pub force: f64,
    /// max |M - M_ref| / max |M_ref|, midspan bending moment (the strain gauge).
    pub moment: f64,
    /// |max(-u) - max(-u_ref)| / max(-u_ref): the peak downward midspan deflection.
    pub peak_deflection: f64,
    /// max over axles of |max F - max F_ref| / max F_ref, while on the span.
    pub peak_force: f64,
}

impl PathErrors {
    /// The largest of the history metrics (deflection, acceleration RMS, force).
    pub fn worst(&self) -> f64 {
        self.deflection.max(self.acceleration_rms).max(self.force)
    }
}

/// Zero-phase low-pass of `x` sampled every `dt_s`: unity below `PASS_HZ`, a raised-cosine
/// transition to zero at `STOP_HZ`. Done by FFT with the signal zero-padded to twice its
/// length, so the short impulse response of the smooth transition cannot wrap around.
pub fn low_pass(x: &[f64], dt_s: f64) -> Vec<f64> {
    let n = (2 * x.len()).next_power_of_two().max(2);
    let mut planner = FftPlanner::<f64>::new();
    let mut buf: Vec<Complex<f64>> = x.iter().map(|&v| Complex::new(v, 0.0)).collect();
    buf.resize(n, Complex::new(0.0, 0.0));
    planner.plan_fft_forward(n).process(&mut buf);
    let df_hz = 1.0 / (n as f64 * dt_s);
    for (k, c) in buf.iter_mut().enumerate() {
        let f_hz = k.min(n - k) as f64 * df_hz;
        *c *= gain(f_hz) / n as f64;
    }
    planner.plan_fft_inverse(n).process(&mut buf);
    buf.iter().take(x.len()).map(|c| c.re).collect()
}

fn gain(f_hz: f64) -> f64 {
    if f_hz <= PASS_HZ {
        1.0
    } else if f_hz >= STOP_HZ {
        0.0
    } else {
        let s = (f_hz - PASS_HZ) / (STOP_HZ - PASS_HZ);
        0.5 * (1.0 + (std::f64::consts::PI * s).cos())
    }
}

/// Every `stride`-th sample, the first `len` of them.
fn decimate<T: Copy>(x: &[T], stride: usize, len: usize) -> Vec<T> {
    x.iter().step_by(stride).take(len).copied().collect()
}

/// Samples of `history` per sample of the grid `dt_s` (a whole number, checked).
fn stride(history: &History, dt_s: f64) -> usize {
    let ratio = dt_s / history.dt_s;
    let stride = ratio.round().max(1.0) as usize;
    assert!(
        (ratio - stride as f64).abs() < 1e-6,
        "time steps {} and {dt_s} s are not commensurate",
        history.dt_s
    );
    stride
}

/// The quantities of one history on the grid `dt_s` (acceleration low-passed first).
struct OnGrid {
    u: Vec<f64>,
    m: Vec<f64>,
    a: Vec<f64>,
    f: [Vec<f64>; 2],
    on: [Vec<bool>; 2],
}

fn on_grid(h: &History, dt_s: f64, len: usize) -> OnGrid {
    let s = stride(h, dt_s);
    OnGrid {
        u: decimate(&h.deflection_m, s, len),
        m: decimate(&h.moment_n_m, s, len),
        a: decimate(&low_pass(&h.acceleration_m_s2, h.dt_s), s, len),
        f: [
            decimate(&h.force_n[0], s, len),
            decimate(&h.force_n[1], s, len),
        ],
        on: [
            decimate(&h.on_span[0], s, len),
            decimate(&h.on_span[1], s, len),
        ],
    }
}

fn max_abs(x: impl Iterator<Item = f64>) -> f64 {
    x.fold(0.0, |m, v| m.max(v.abs()))
}

fn rms(x: impl Iterator<Item = f64>) -> f64 {
    let (sum, n) = x.fold((0.0, 0usize), |(s, n), v| (s + v * v, n + 1));
    (sum / n.max(1) as f64).sqrt()
}

/// Errors of `path` against `reference` on the coarser of their grids, over the samples
/// both cover.
pub fn compare(path: &History, reference: &History) -> PathErrors {
    let dt_s = path.dt_s.max(reference.dt_s);
    let len = (path.len() - 1) / stride(path, dt_s) + 1;
    let len = len.min((reference.len() - 1) / stride(reference, dt_s) + 1);
    let (p, r) = (on_grid(path, dt_s, len), on_grid(reference, dt_s, len));
    let diff = |a: &[f64], b: &[f64]| -> Vec<f64> { a.iter().zip(b).map(|(x, y)| x - y).collect() };
    let da = diff(&p.a, &r.a);
    let mut errors = PathErrors {
        deflection: max_abs(diff(&p.u, &r.u).into_iter()) / max_abs(r.u.iter().copied()),
        acceleration_max: max_abs(da.iter().copied()) / max_abs(r.a.iter().copied()),
        acceleration_rms: rms(da.into_iter()) / rms(r.a.iter().copied()),
        moment: max_abs(diff(&p.m, &r.m).into_iter()) / max_abs(r.m.iter().copied()),
        peak_deflection: relative(peak(&p.u, |u| -u), peak(&r.u, |u| -u)),
        ..PathErrors::default()
    };
    for k in 0..2 {
        let on_span = |g: &OnGrid| -> Vec<f64> {
            (0..len)
                .filter(|&i| r.on[k][i])
                .map(|i| g.f[k][i])
                .collect()
        };
        let (fp, fr) = (on_span(&p), on_span(&r));
        let df = max_abs(fp.iter().zip(&fr).map(|(a, b)| a - b));
        errors.force = errors.force.max(df / path.static_n[k]);
        let peak_error = relative(peak(&fp, |f| f), peak(&fr, |f| f));
        errors.peak_force = errors.peak_force.max(peak_error);
    }
    errors
}

fn peak(x: &[f64], sign: impl Fn(f64) -> f64) -> f64 {
    x.iter().map(|&v| sign(v)).fold(f64::MIN, f64::max)
}

fn relative(value: f64, reference: f64) -> f64 {
    (value - reference).abs() / reference.abs()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sine(f_hz: f64, dt_s: f64, n: usize) -> Vec<f64> {
        (0..n)
            .map(|i| (2.0 * std::f64::consts::PI * f_hz * i as f64 * dt_s).sin())
            .collect()
    }

    #[test]
    fn low_pass_keeps_the_pass_band_and_removes_the_stop_band() {
        // A 10 Hz tone passes, a 120 Hz tone goes; away from the ends (the zero padding
        // makes the signal start and stop abruptly there).
        let dt = 1e-3;
        let (keep, drop) = (sine(10.0, dt, 4000), sine(120.0, dt, 4000));
        let mixed: Vec<f64> = keep.iter().zip(&drop).map(|(a, b)| a + b).collect();
        let out = low_pass(&mixed, dt);
        let worst = (500..3500).fold(0.0f64, |m, i| m.max((out[i] - keep[i]).abs()));
        assert!(worst < 1e-3, "{worst}");
    }

    #[test]
    fn identical_histories_have_zero_error_and_a_scaled_one_its_scale() {
        let dt = 5e-4;
        let n = 2001;
        let u: Vec<f64> = sine(2.0, dt, n).iter().map(|v| -1e-3 * v.abs()).collect();
        let h = History {
            dt_s: dt,
            deflection_m: u.clone(),
            moment_n_m: u.iter().map(|v| -1e9 * v).collect(),
            acceleration_m_s2: sine(4.0, dt, n),
            force_n: [vec![1e5; n], vec![2e5; n]],
            on_span: [vec![true; n], vec![true; n]],
            static_n: [1e5, 2e5],
            loop_wall_s: 0.0,
        };
        assert_eq!(compare(&h, &h), PathErrors::default());
        // The coarse history at 1 ms, 1 % larger everywhere.
        let mut coarse = h.clone();
        coarse.dt_s = 1e-3;
        coarse.deflection_m = u.iter().step_by(2).map(|v| 1.01 * v).collect();
        coarse.moment_n_m = coarse.deflection_m.iter().map(|v| -1e9 * v).collect();
        coarse.acceleration_m_s2 = sine(4.0, 1e-3, 1001).iter().map(|v| 1.01 * v).collect();
        coarse.force_n = [vec![1.01e5; 1001], vec![2.02e5; 1001]];
        coarse.on_span = [vec![true; 1001], vec![true; 1001]];
        let e = compare(&coarse, &h);
        for v in [
            e.deflection,
            e.acceleration_rms,
            e.force,
            e.moment,
            e.peak_deflection,
        ] {
            assert!((v - 0.01).abs() < 1e-3, "{e:?}");
        }
    }
}
